//! Objects by name: `ProducerHeartbeatTime`, `producer heartbeat time`,
//! `Identity object: Vendor-ID` and `Vendor-ID` all find their entry.

use super::Dictionary;
use canctl_canopen::ObjAddr;

/// Letters and digits only, lower case: spelling differences in spaces, case and
/// punctuation do not matter.
pub fn normalize(s: &str) -> String {
    s.chars().filter(|c| c.is_alphanumeric()).flat_map(|c| c.to_lowercase()).collect()
}

/// A name as one shell word that `find` accepts: `Identity object: Vendor-ID` becomes
/// `IdentityObjectVendorID`.
pub fn identifier(name: &str) -> String {
    name.split(|c: char| !c.is_alphanumeric())
        .flat_map(|word| {
            let mut chars = word.chars();
            chars.next().into_iter().flat_map(|c| c.to_uppercase()).chain(chars)
        })
        .collect()
}

/// The entry a name stands for, or why there is none (with the closest names).
pub fn find(dict: &Dictionary, name: &str) -> Result<ObjAddr, String> {
    let want = normalize(name);
    let full: Vec<ObjAddr> = dict
        .entries()
        .filter(|e| dict.display_name(e.addr).is_some_and(|n| normalize(&n) == want))
        .map(|e| e.addr)
        .collect();
    if let [one] = full.as_slice() {
        return Ok(*one);
    }
    // Spellings alike once punctuation is dropped ("Position Actual Value" 0x6064 and
    // "Position Actual Value*" 0x6063): the name written exactly as given wins.
    let exact = |addrs: &[ObjAddr], of: &dyn Fn(ObjAddr) -> Option<String>| -> Option<ObjAddr> {
        match addrs
            .iter()
            .filter(|a| of(**a).is_some_and(|n| n.trim().eq_ignore_ascii_case(name.trim())))
            .collect::<Vec<_>>()[..]
        {
            [one] => Some(*one),
            _ => None,
        }
    };
    if let Some(one) = exact(&full, &|a| dict.display_name(a)) {
        return Ok(one);
    }
    let short: Vec<ObjAddr> = dict.entries().filter(|e| normalize(&e.name) == want).map(|e| e.addr).collect();
    if let Some(one) = exact(&short, &|a| dict.get(a).map(|e| e.name.clone())) {
        return Ok(one);
    }
    match (full.as_slice(), short.as_slice()) {
        ([], [one]) => Ok(*one),
        ([], []) => {
            let close = closest(dict, &want);
            let hint = if close.is_empty() { String::new() } else { format!("; did you mean {}?", close.join(", ")) };
            Err(format!("no object named '{name}'{hint}"))
        }
        _ => {
            let many = if full.is_empty() { &short } else { &full };
            let list: Vec<String> =
                many.iter().take(5).map(|a| format!("{a} ({})", dict.display_name(*a).unwrap_or_default())).collect();
            Err(format!("'{name}' names several objects: {}; give the address", list.join(", ")))
        }
    }
}

/// Up to three names nearest to `want` (normalized): the names it is a word of first
/// (`heartbeat` finds ProducerHeartbeatTime), shortest first, then by edit distance.
fn closest(dict: &Dictionary, want: &str) -> Vec<String> {
    let mut scored: Vec<(bool, usize, ObjAddr, String)> = dict
        .entries()
        .filter_map(|e| {
            let n = dict.display_name(e.addr)?;
            let norm = normalize(&n);
            // A part of a name: scored by how much of the name is left unsaid.
            let part = norm.contains(want) && want.len() >= 4;
            let score = if part { norm.len() - want.len() } else { distance(&norm, want) };
            (part || score <= want.len() / 3 + 1).then_some((!part, score, e.addr, n))
        })
        .collect();
    scored.sort();
    // Sub-indexes that share their object's name (0x1016:1, :2, ...): the first stands for all.
    scored.dedup_by(|b, a| a.3 == b.3);
    scored.into_iter().take(3).map(|(_, _, addr, n)| format!("'{n}' ({addr})")).collect()
}

/// Edit distance (Levenshtein) between two words.
pub fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + (ca != *cb) as usize).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

/// Objects of `dict` near one a device says it does not have, named, at most five: see
/// [`near_addrs`].
pub fn near(dict: &Dictionary, addr: ObjAddr, object_missing: bool) -> Vec<String> {
    near_addrs(dict, addr, object_missing).into_iter().map(|a| label(dict, a)).collect()
}

/// `0x1017:0 (Producer heartbeat time)`, or the address alone for an object without a name.
pub fn label(dict: &Dictionary, a: ObjAddr) -> String {
    dict.display_name(a).map_or_else(|| a.to_string(), |n| format!("{a} ({n})"))
}

/// Objects of `dict` near one a device says it does not have: the other sub-indexes of that
/// object (unless the device lacks the whole object, `object_missing`: abort 0x06020000),
/// else objects whose index is one hex digit off or has two neighbouring digits swapped
/// (0x1081 for 0x1018). At most five.
pub fn near_addrs(dict: &Dictionary, addr: ObjAddr, object_missing: bool) -> Vec<ObjAddr> {
    let mut near: Vec<ObjAddr> =
        dict.entries().map(|e| e.addr).filter(|a| !object_missing && a.index == addr.index && *a != addr).collect();
    if near.is_empty() {
        let mut indexes: Vec<u16> = dict.entries().map(|e| e.addr.index).filter(|i| one_slip(*i, addr.index)).collect();
        indexes.dedup();
        near = indexes
            .into_iter()
            .map(|i| ObjAddr::new(i, if dict.get(ObjAddr::new(i, addr.sub)).is_some() { addr.sub } else { 0 }))
            .collect();
    }
    near.truncate(5);
    near
}

/// Whether two indexes differ by one hex digit, or by two neighbouring digits swapped.
fn one_slip(a: u16, b: u16) -> bool {
    let (x, y) = (format!("{a:04X}").into_bytes(), format!("{b:04X}").into_bytes());
    let differ: Vec<usize> = (0..4).filter(|&i| x[i] != y[i]).collect();
    match differ.as_slice() {
        [_] => true,
        [i, j] => *j == i + 1 && x[*i] == y[*j] && x[*j] == y[*i],
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::dictionary;

    #[test]
    fn slips_of_one_digit_or_a_swap() {
        assert!(one_slip(0x1081, 0x1018) && one_slip(0x1017, 0x1016) && !one_slip(0x1017, 0x1170));
    }

    #[test]
    fn identifiers_are_one_word_that_finds_the_entry() {
        assert_eq!(identifier("Identity object: Vendor-ID"), "IdentityObjectVendorID");
        let d = dictionary(None);
        let mut checked = 0;
        for e in d.entries() {
            let name = d.display_name(e.addr).unwrap();
            let unique =
                d.entries().filter(|o| d.display_name(o.addr).map(|n| normalize(&n)) == Some(normalize(&name))).count()
                    == 1;
            if unique {
                assert_eq!(find(d, &identifier(&name)), Ok(e.addr), "{name}");
                checked += 1;
            }
        }
        assert!(checked > 50, "{checked}");
    }

    #[test]
    fn an_exact_name_wins_over_one_that_differs_in_punctuation() {
        let eds = crate::eds::read_file(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/fixtures/eds/exact-names.eds"
        )))
        .unwrap();
        let d = &eds.dict;
        assert_eq!(find(d, "Position Actual Value"), Ok(ObjAddr::new(0x6064, 0)));
        assert_eq!(find(d, "position actual value*"), Ok(ObjAddr::new(0x6063, 0)));
        // A spelling that is neither stays ambiguous, naming both.
        let e = find(d, "PositionActualValue").unwrap_err();
        assert!(e.contains("0x6063:0") && e.contains("0x6064:0"), "{e}");
    }

    #[test]
    fn spellings_find_their_entry() {
        let d = dictionary(None);
        for n in ["ProducerHeartbeatTime", "producer heartbeat time", "PRODUCER_HEARTBEAT_TIME"] {
            assert_eq!(find(d, n), Ok(ObjAddr::new(0x1017, 0)), "{n}");
        }
        assert_eq!(find(d, "Identity object: Vendor-ID"), Ok(ObjAddr::new(0x1018, 1)));
        assert_eq!(find(d, "VendorID"), Ok(ObjAddr::new(0x1018, 1)));
        assert_eq!(find(d, "Controlword"), Ok(ObjAddr::new(0x6040, 0)));
        let e = find(d, "ProducerHeartbeatTim").unwrap_err();
        assert!(e.contains("did you mean 'Producer heartbeat time' (0x1017:0)"), "{e}");
        assert!(find(d, "COB-ID").unwrap_err().contains("several objects"));
        assert!(find(d, "zzzzzzzz").unwrap_err().starts_with("no object named"));
    }
}
