//! Values in EDS and DCF text (CiA 306): integers, reals, `$NODEID` offsets, access and
//! data type codes read; values written back so that they read as the same bytes.

use super::ini::{to_latin1, trim_blanks};
use crate::{Access, Init, ObjectKind};
use canctl_canopen::DataType;
/// CiA 306 integers: `0x` hex, a leading `0` octal, otherwise decimal; a sign allowed
/// ([`canctl_canopen::number::parse_cia306`], the one number reading with CiA 306's octal).
pub fn parse_int(text: &str) -> Option<i128> {
    canctl_canopen::number::parse_cia306(trim_blanks(text))
}

/// The node-ids a `$NODEID` value may be used for (CiA 301).
pub(super) const NODE_IDS: std::ops::RangeInclusive<i128> = 1..=127;

/// `$NODEID`, `$NODEID+n` or `n+$NODEID` (any case, blanks allowed): the offset `n`.
pub(super) fn node_id_offset(text: &str) -> Option<Result<i128, String>> {
    let lower = text.to_ascii_lowercase();
    let at = lower.find("$nodeid")?;
    let (before, after) = (trim_blanks(&lower[..at]), trim_blanks(&lower[at + "$nodeid".len()..]));
    let offset = match (before, after) {
        ("", "") => Some(0),
        ("", rest) => rest.strip_prefix('+').and_then(parse_unsigned),
        (rest, "") => rest.strip_suffix('+').and_then(parse_unsigned),
        _ => None,
    };
    Some(offset.ok_or_else(|| format!("'{text}' is not $NODEID, $NODEID+n or n+$NODEID with a number n ≥ 0")))
}

pub(super) fn parse_unsigned(text: &str) -> Option<i128> {
    Some(trim_blanks(text)).filter(|t| !t.starts_with(['+', '-'])).and_then(parse_int)
}

/// A real as CiA 306 files write it (`1.5`, `-2e3`, `inf`, `nan`), or the exact bits as
/// `0x` and 8 or 16 hex digits (how canctl writes a NaN with a payload).
pub(super) fn parse_real(t: &str, dtype: DataType) -> Result<Vec<u8>, String> {
    let width = dtype.size().expect("fixed-size real") * 2;
    if let Some(h) = t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        if h.len() == width && h.chars().all(|c| c.is_ascii_hexdigit()) {
            let bits = u64::from_str_radix(h, 16).map_err(|e| e.to_string())?;
            return Ok(bits.to_le_bytes()[..width / 2].to_vec());
        }
        return Err(format!("'{t}' is not a {dtype}: hex gives its bits as 0x and {width} digits"));
    }
    dtype.parse(if t.is_empty() { "0" } else { t }).map_err(|e| e.0)
}

/// Signed values written in hex are two's complement (`0xFFFF` is -1 for an INTEGER16).
pub(super) fn signed_from_hex(v: i128, text: &str, dtype: DataType) -> i128 {
    match dtype.int_range() {
        Some((lo, hi)) if dtype.is_signed() && v > hi && text.to_ascii_lowercase().contains("0x") => v - (hi - lo + 1),
        _ => v,
    }
}

/// A value as the file writes it, for an entry of type `dtype`.
pub(crate) fn parse_value(text: &str, dtype: DataType) -> Result<Init, String> {
    let t = trim_blanks(text);
    // A VISIBLE_STRING is its text, `$NODEID` included: it is arithmetic on numbers only.
    if dtype == DataType::Vs {
        return Ok(Init::Bytes(to_latin1(t)));
    }
    if let Some(offset) = node_id_offset(t) {
        let offset = offset?;
        let Some((_, hi)) = dtype.int_range().filter(|_| dtype != DataType::Bool) else {
            return Err(format!("'{t}' is node-id arithmetic, which needs an integer type, not {dtype}"));
        };
        let highest = offset + NODE_IDS.end();
        if highest > hi {
            return Err(format!(
                "'{t}' exceeds {dtype} (at most {hi}): node-id 127 would give {highest}; \
                 only offsets up to {} fit every node-id",
                hi - NODE_IDS.end()
            ));
        }
        return Ok(Init::NodeIdPlus(offset as u64));
    }
    let bytes = match dtype {
        DataType::Vs => unreachable!("handled above"),
        // The caller decodes the file's text first (`Reader::try_entry`).
        DataType::Unicode => t.encode_utf16().flat_map(u16::to_le_bytes).collect(),
        // A number is the 48 bits as they travel (python-canopen's files write 0).
        DataType::TimeOfDay | DataType::TimeDifference => match parse_int(t) {
            Some(v) if (0..1 << 48).contains(&v) => v.to_le_bytes()[..6].to_vec(),
            _ if t.is_empty() => vec![0; 6],
            _ => dtype.parse(t).map_err(|e| e.0)?,
        },
        DataType::Os | DataType::D => canctl_canopen::types::parse_hex(t)?,
        DataType::R32 | DataType::R64 => parse_real(t, dtype)?,
        _ => {
            let v = if t.is_empty() { 0 } else { parse_int(t).ok_or_else(|| format!("'{t}' is not an integer"))? };
            let (lo, hi) = dtype.int_range().expect("integer type");
            let v = signed_from_hex(v, t, dtype);
            if v < lo || v > hi {
                return Err(format!("{t} is out of range for {dtype}: use {lo} to {hi}"));
            }
            v.to_le_bytes()[..dtype.size().unwrap()].to_vec()
        }
    };
    Ok(Init::Bytes(bytes))
}

/// `parse_value`, and where that fails, what a value written as C writes an integer
/// (`0x1234ULL`, `100U`) or as words write a BOOLEAN (`false`) plainly means: the value,
/// and the text it was read as when it needed that (the reader warns).
pub fn parse_value_as_meant(text: &str, dtype: DataType) -> Result<(Init, Option<String>), String> {
    match parse_value(text, dtype) {
        Ok(value) => Ok((value, None)),
        Err(why) => {
            let Some(meant) = plain_meaning(trim_blanks(text), dtype) else { return Err(why) };
            let value = parse_value(&meant, dtype).map_err(|_| why)?;
            Ok((value, Some(meant)))
        }
    }
}

/// `false`/`true` for a BOOLEAN, an integer without its C suffix (`U`, `L`, `UL`, `LL`,
/// `ULL`, any case): the text CiA 306 would write; `None` when there is no plain meaning.
fn plain_meaning(text: &str, dtype: DataType) -> Option<String> {
    let lower = text.to_ascii_lowercase();
    match (dtype, lower.as_str()) {
        (DataType::Bool, "false") => return Some("0".into()),
        (DataType::Bool, "true") => return Some("1".into()),
        _ => {}
    }
    dtype.int_range()?;
    // Longest first; no hex digit is a U or an L, so a suffix is never part of the number.
    let suffix = ["ull", "llu", "ul", "lu", "ll", "u", "l"].into_iter().find(|s| lower.ends_with(s))?;
    let number = &text[..text.len() - suffix.len()];
    parse_int(number).map(|_| number.to_string())
}

/// What a reader says of a value it read as meant ([`parse_value_as_meant`]).
pub fn read_as_meant(key: &str, text: &str, who: &str, meant: &str) -> String {
    format!("{key} {text} of {who} read as {meant}")
}

pub(super) fn parse_access(text: &str) -> Option<Access> {
    Some(match text.trim().to_ascii_lowercase().as_str() {
        "ro" => Access::Ro,
        "wo" => Access::Wo,
        "rw" | "rwr" | "rww" => Access::Rw,
        "const" => Access::Const,
        _ => return None,
    })
}

/// CiA 301 data types: 0x0001..0x001F static, 0x0020..0x003F complex, 0x0040..0x005F
/// manufacturer-specific, 0x0060..0x025F device-profile-specific.
pub(super) const DATA_TYPE_CODES: std::ops::RangeInclusive<i128> = 0x0001..=0x025F;

/// The kind of object an ObjectType codes; `None` for one that holds no values (DEFTYPE,
/// DEFSTRUCT, NULL); `Err` for another, naming the codes canctl reads.
pub fn object_kind(code: i128) -> Result<Option<ObjectKind>, String> {
    Ok(Some(match code {
        // A DOMAIN object (0x2) is a single value, as a VAR is.
        7 | 2 => ObjectKind::Var,
        8 => ObjectKind::Array,
        9 => ObjectKind::Record,
        0 | 5 | 6 => return Ok(None),
        other => return Err(format!("{other} is not DOMAIN (2), VAR (7), ARRAY (8) or RECORD (9)")),
    }))
}

/// The type of a `DataType` code: `Ok(None)` for a CiA 301 type canctl does not handle,
/// an error for a number that is no data type at all.
pub fn data_type_from_code(code: i128) -> Result<Option<DataType>, String> {
    if !DATA_TYPE_CODES.contains(&code) {
        return Err(format!("DataType 0x{code:X} is not a CiA 301 data type (0x0001..0x025F; 0x0007 is UNSIGNED32)"));
    }
    Ok(canctl_canopen::types::ALL_TYPES.iter().copied().find(|t| i128::from(t.code()) == code))
}

/// What a reader does with a CiA 301 data type it does not handle (`data_type_from_code`
/// gave `Ok(None)`), in words.
pub fn type_as_bytes(who: &str, code: i128) -> String {
    format!("{who} has data type 0x{code:04X}, not a CiA 301 basic type: read as DOMAIN (d), its bytes as they are, no default")
}

/// A LowLimit or HighLimit: an integer, two's complement when a signed type's is hex; one
/// with a C suffix read as it plainly means, with the text it was read as (the reader warns).
pub fn parse_limit(text: &str, dtype: DataType) -> Option<(i128, Option<String>)> {
    if let Some(n) = parse_int(text) {
        return Some((signed_from_hex(n, text, dtype), None));
    }
    let meant = plain_meaning(trim_blanks(text), dtype)?;
    let n = parse_int(&meant)?;
    Some((signed_from_hex(n, &meant, dtype), Some(meant)))
}

/// Why a file needs object `index` (one of `od::MANDATORY`), in words.
pub fn mandatory(index: u16) -> String {
    format!("CiA 301 makes 0x{index:04X} mandatory for every device")
}

/// The text form of a value, for people (tables, messages). Files use `value_text`.
pub fn format_value(init: &Init, dtype: DataType) -> String {
    match value_text(init, dtype) {
        Ok(text) if dtype != DataType::Vs => text,
        _ => match init {
            Init::Bytes(b) => dtype.decode(b).map_or_else(|| canctl_canopen::types::hex(b), |v| v.to_string()),
            Init::NodeIdPlus(base) => format!("$NODEID+0x{base:X}"),
        },
    }
}

/// Why a value cannot be written to an EDS or DCF.
pub(super) fn unwritable_bytes(bytes: &[u8]) -> Option<String> {
    let describe = |b: u8| match b {
        0 => "a NUL byte (0x00)".to_string(),
        b'\n' => "a line feed (0x0A)".to_string(),
        b'\r' => "a carriage return (0x0D)".to_string(),
        b'\t' => "a tab (0x09)".to_string(),
        other => format!("the control character 0x{other:02X}"),
    };
    if let Some(&b) = bytes.iter().find(|b| **b < 0x20 || **b == 0x7F) {
        return Some(format!(
            "it holds {}, and a VISIBLE_STRING in an EDS/DCF is one line of visible characters (CiA 306)",
            describe(b)
        ));
    }
    if bytes.first().is_some_and(|b| *b == b' ') || bytes.last().is_some_and(|b| *b == b' ') {
        return Some("it begins or ends with a space, which every EDS/DCF reader trims (CiA 306)".into());
    }
    None
}

/// A real in the shortest text that reads back to the same bits; a NaN other than the one
/// `nan` reads as keeps its bits as hex.
pub(super) fn real_text(bytes: &[u8], dtype: DataType) -> String {
    let mut wide = [0u8; 8];
    wide[..bytes.len()].copy_from_slice(bytes);
    let bits = u64::from_le_bytes(wide);
    let (plain, exp, nan) = match dtype {
        DataType::R32 => {
            let v = f32::from_bits(bits as u32);
            (v.to_string(), format!("{v:e}"), u64::from(f32::NAN.to_bits()))
        }
        _ => (f64::from_bits(bits).to_string(), format!("{:e}", f64::from_bits(bits)), f64::NAN.to_bits()),
    };
    match plain.as_str() {
        "NaN" if bits == nan => "nan".into(),
        "NaN" => format!("0x{bits:0width$X}", width = bytes.len() * 2),
        _ if exp.len() < plain.len() => exp,
        _ => plain,
    }
}

/// The text of a value in an EDS/DCF, each character standing for one byte of the file
/// (Latin-1): it reads back to exactly the same bytes, or is refused with the reason.
pub fn value_text(init: &Init, dtype: DataType) -> Result<String, String> {
    let bytes = match init {
        Init::NodeIdPlus(base) => {
            return match dtype.int_range() {
                Some((_, hi)) if dtype != DataType::Bool && i128::from(*base) + NODE_IDS.end() <= hi => {
                    Ok(if *base == 0 { "$NODEID".into() } else { format!("$NODEID+0x{base:X}") })
                }
                _ => Err(format!("$NODEID+0x{base:X} does not fit {dtype} for every node-id")),
            };
        }
        Init::Bytes(b) => b,
    };
    if let Some(size) = dtype.size() {
        if bytes.len() != size {
            return Err(format!("it holds {} bytes; a {dtype} is {size}", bytes.len()));
        }
    }
    use canctl_canopen::types::Value;
    Ok(match dtype {
        DataType::Vs => {
            if let Some(why) = unwritable_bytes(bytes) {
                return Err(why);
            }
            bytes.iter().map(|b| *b as char).collect()
        }
        DataType::Os | DataType::D => canctl_canopen::types::hex(bytes),
        DataType::R32 | DataType::R64 => real_text(bytes, dtype),
        // The UTF-8 bytes, each as the character of its number (`Writer::value` writes them);
        // every code unit, NULs included, so that it reads back the same or is refused.
        DataType::Unicode => {
            let units: Vec<u16> =
                bytes.chunks(2).map(|c| u16::from_le_bytes([c[0], *c.get(1).unwrap_or(&0)])).collect();
            let text = match String::from_utf16(&units) {
                Ok(t) if bytes.len() % 2 == 0 => t,
                _ => return Err("it is not UTF-16 text (CiA 301 UNICODE_STRING)".into()),
            };
            if let Some(why) = unwritable_bytes(text.as_bytes()) {
                return Err(why);
            }
            text.bytes().map(|b| b as char).collect()
        }
        // The date and time where it reads back the same; else (reserved bits set, a
        // time of day past midnight) the raw 48 bits, so the file says exactly what was read.
        DataType::TimeOfDay | DataType::TimeDifference => {
            let text = dtype.decode(bytes).expect("size checked").to_string();
            if dtype.parse(&text).ok().as_deref() == Some(bytes) {
                text
            } else {
                let mut wide = [0u8; 8];
                wide[..6].copy_from_slice(bytes);
                format!("0x{:012X}", u64::from_le_bytes(wide))
            }
        }
        DataType::Bool if bytes[0] > 1 => {
            return Err(format!("it holds 0x{:02X}, and a BOOLEAN is 0 or 1 (CiA 301)", bytes[0]))
        }
        _ => match dtype.decode(bytes).expect("size checked") {
            Value::Uint(u) => format!("0x{u:X}"),
            Value::Bool(v) => (v as u8).to_string(),
            other => other.to_string(),
        },
    })
}
