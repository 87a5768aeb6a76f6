//! EDS and DCF files (CiA 306): INI sections per object and sub-object, read into a
//! `Dictionary` (plus a DCF's `ParameterValue`s) and written from one.
//!
//! Real files are Latin-1, use CRLF, vary the case of keys and section names and leave out
//! optional keys; the reader takes all that. What it cannot read it names with file:line.

/// Re-exported for readers beside this one.
pub use super::lint::MAX_WARNINGS;
use super::lint::{self, Kind, Warning, Warnings};
use super::{Access, Dictionary, Entry, Init, ObjectKind};
use crate::canopen::{DataType, ObjAddr};
use std::collections::{BTreeMap, BTreeSet};

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct EdsError {
    pub path: String,
    /// 0 when the file could not be read at all.
    pub line: usize,
    pub msg: String,
}

impl std::fmt::Display for EdsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            0 => f.write_str(&self.msg),
            line => write!(f, "{}:{line}: {}", self.path, self.msg),
        }
    }
}

/// A parsed EDS or DCF.
#[derive(Debug, Clone, Default)]
pub struct Eds {
    pub path: String,
    pub dict: Dictionary,
    /// `ParameterValue`s of a DCF: what the device is to hold.
    pub values: BTreeMap<ObjAddr, Init>,
    /// `[DeviceComissioning] NodeID` of a DCF.
    pub node_id: Option<u8>,
    /// `[DeviceInfo]` keys, lower-cased, as written.
    pub info: BTreeMap<String, String>,
    /// Data types `[DummyUsage]` allows as gaps in a PDO mapping (`Dummy0005=1`: 0x0005).
    pub dummy_usage: BTreeSet<u16>,
    /// Where the file deviates from CiA 306 (objects left out, repeated keys, over-long
    /// lines, ...), each with file:line and what the reader did. The library never prints:
    /// the caller shows them.
    pub warnings: Warnings,
}

/// CiA 306 keeps a line to 255 characters; longer ones are read, with a warning.
pub const MAX_LINE_CHARS: usize = 255;

struct Section {
    name: String,
    line: usize,
    /// Lower-cased key → value and line; a repeated key keeps its last value.
    keys: std::collections::HashMap<String, (String, usize)>,
    /// Lower-cased key → the key as the file spells it, for messages.
    spelled: std::collections::HashMap<String, String>,
}

impl Section {
    fn get(&self, key: &str) -> Option<(&str, usize)> {
        self.keys.get(key).map(|(v, l)| (v.as_str(), *l))
    }

    /// The section's name as CiA 306 spells it, for messages.
    fn spelled_name(&self) -> &'static str {
        match self.name.as_str() {
            "mandatoryobjects" => "MandatoryObjects",
            "optionalobjects" => "OptionalObjects",
            _ => "ManufacturerObjects",
        }
    }
}

/// The blanks an INI line may have around keys and values: ASCII space and tab only, so
/// that Latin-1 bytes such as 0xA0 stay part of the value.
fn trim_blanks(s: &str) -> &str {
    s.trim_matches([' ', '\t'])
}

/// Sections with their lines; keys lower-cased. Each byte becomes the Latin-1 character
/// of the same number, so a value's text gives back its exact bytes (`to_latin1`).
fn parse_ini(bytes: &[u8], path: &str, warnings: &mut Vec<Warning>) -> Result<Vec<Section>, EdsError> {
    let text: String = bytes.iter().map(|b| *b as char).collect();
    let err = |line: usize, msg: String| EdsError { path: path.to_string(), line, msg };
    let mut sections: Vec<Section> = Vec::new();
    let mut seen_sections: BTreeMap<String, usize> = BTreeMap::new();
    for (i, raw) in text.split('\n').enumerate() {
        let no = i + 1;
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        if raw.chars().count() > MAX_LINE_CHARS {
            let msg = format!(
                "line of {} characters, more than the {MAX_LINE_CHARS} CiA 306 allows (read in full)",
                raw.chars().count()
            );
            lint::push(warnings, Warning::new(path, no, Kind::LongLine, msg));
        }
        let line = trim_blanks(raw);
        if line.is_empty() || line.starts_with(';') || line.starts_with('#') {
            continue;
        }
        if let Some(rest) = line.strip_prefix('[') {
            let name =
                rest.strip_suffix(']').ok_or_else(|| err(no, format!("section header '{line}' has no closing ]")))?;
            let name = trim_blanks(name).to_ascii_lowercase();
            if let Some(first) = seen_sections.insert(name.clone(), no) {
                let msg = format!("section {line} again (before at line {first}): this one replaces it");
                lint::push(warnings, Warning::new(path, no, Kind::RepeatedSection, msg));
            }
            sections.push(Section { name, line: no, keys: Default::default(), spelled: Default::default() });
            continue;
        }
        let (key, value) =
            line.split_once('=').ok_or_else(|| err(no, format!("expected KEY=VALUE or [SECTION], found '{line}'")))?;
        let section = sections.last_mut().ok_or_else(|| err(no, format!("'{line}' comes before any [SECTION]")))?;
        let key_lower = trim_blanks(key).to_ascii_lowercase();
        section.spelled.insert(key_lower.clone(), trim_blanks(key).to_string());
        let value = (trim_blanks(value).to_string(), no);
        if let Some((_, first)) = section.keys.insert(key_lower, value) {
            let msg = format!(
                "{} repeated in [{}] (before at line {first}): the value of line {no} is used",
                trim_blanks(key),
                section.name
            );
            lint::push(warnings, Warning::new(path, no, Kind::RepeatedKey, msg));
        }
    }
    Ok(sections)
}

/// `1018` → (0x1018, None); `1018sub2` → (0x1018, Some(2)); anything else → None.
fn object_section(name: &str) -> Option<(u16, Option<u8>)> {
    let (index, sub) = match name.split_once("sub") {
        Some((i, s)) => (i, Some(s)),
        None => (name, None),
    };
    if index.len() != 4 || !index.chars().all(|c| c.is_ascii_hexdigit()) {
        return None;
    }
    let index = u16::from_str_radix(index, 16).ok()?;
    match sub {
        None => Some((index, None)),
        Some(s) if !s.is_empty() && s.len() <= 2 => Some((index, Some(u8::from_str_radix(s, 16).ok()?))),
        Some(_) => None,
    }
}

/// CiA 306 integers: `0x` hex, a leading `0` octal, otherwise decimal; a sign allowed.
pub fn parse_int(text: &str) -> Option<i128> {
    let t = trim_blanks(text);
    let (neg, body) = match t.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, t.strip_prefix('+').unwrap_or(t)),
    };
    // Beyond 32 digits no CiA 301 integer is meant, and i128 would overflow.
    if body.is_empty() || body.len() > 32 || body.starts_with(['+', '-']) {
        return None;
    }
    let v = if let Some(h) = body.strip_prefix("0x").or_else(|| body.strip_prefix("0X")) {
        i128::from_str_radix(h, 16).ok()?
    } else if body.len() > 1 && body.starts_with('0') {
        i128::from_str_radix(&body[1..], 8).ok()?
    } else {
        body.parse().ok()?
    };
    Some(if neg { -v } else { v })
}

/// The node-ids a `$NODEID` value may be used for (CiA 301).
const NODE_IDS: std::ops::RangeInclusive<i128> = 1..=127;

/// `$NODEID`, `$NODEID+n` or `n+$NODEID` (any case, blanks allowed): the offset `n`.
fn node_id_offset(text: &str) -> Option<Result<i128, String>> {
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

fn parse_unsigned(text: &str) -> Option<i128> {
    let t = trim_blanks(text);
    if t.starts_with(['+', '-']) {
        return None;
    }
    parse_int(t)
}

/// A real as CiA 306 files write it (`1.5`, `-2e3`, `inf`, `nan`), or the exact bits as
/// `0x` and 8 or 16 hex digits (how canctl writes a NaN with a payload).
fn parse_real(t: &str, dtype: DataType) -> Result<Vec<u8>, String> {
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
fn signed_from_hex(v: i128, text: &str, dtype: DataType) -> i128 {
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
        let (_, hi) = match dtype.int_range() {
            Some(range) if dtype != DataType::Bool => range,
            _ => return Err(format!("'{t}' is node-id arithmetic, which needs an integer type, not {dtype}")),
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
        DataType::Os | DataType::D => crate::canopen::types::parse_hex(t)?,
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

fn parse_access(text: &str) -> Option<Access> {
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
const DATA_TYPE_CODES: std::ops::RangeInclusive<i128> = 0x0001..=0x025F;

/// The type of a `DataType` code: `Ok(None)` for a CiA 301 type canctl does not handle,
/// an error for a number that is no data type at all.
fn data_type_from_code(code: i128) -> Result<Option<DataType>, String> {
    if !DATA_TYPE_CODES.contains(&code) {
        return Err(format!("DataType 0x{code:X} is not a CiA 301 data type (0x0001..0x025F; 0x0007 is UNSIGNED32)"));
    }
    Ok(crate::canopen::types::ALL_TYPES.iter().copied().find(|t| i128::from(t.code()) == code))
}

/// How names and descriptions are encoded: Latin-1 as CiA 306 files traditionally are, or
/// UTF-8 where the file says so with a byte order mark or is valid UTF-8 beyond ASCII.
#[derive(Clone, Copy)]
struct TextEncoding {
    utf8: bool,
}

impl TextEncoding {
    fn of(bytes: &[u8]) -> TextEncoding {
        TextEncoding { utf8: !bytes.is_ascii() && std::str::from_utf8(bytes).is_ok() }
    }

    /// Text read as Latin-1 (one character per byte), as the file meant it: UTF-8, or
    /// Windows-1252, whose quotes and dashes take Latin-1's unused control codes 0x80..0x9F.
    fn decode(self, latin1: &str) -> String {
        if self.utf8 {
            if let Ok(s) = String::from_utf8(to_latin1(latin1)) {
                return s;
            }
        }
        latin1.chars().map(cp1252).collect()
    }
}

/// Windows-1252's characters for 0x80..0x9F (C1 controls in Latin-1, never text in an EDS).
fn cp1252(c: char) -> char {
    const HIGH: [char; 32] = [
        '€', '\u{81}', '‚', 'ƒ', '„', '…', '†', '‡', 'ˆ', '‰', 'Š', '‹', 'Œ', '\u{8D}', 'Ž', '\u{8F}', '\u{90}', '‘',
        '’', '“', '”', '•', '–', '—', '˜', '™', 'š', '›', 'œ', '\u{9D}', 'ž', 'Ÿ',
    ];
    match c as u32 {
        n @ 0x80..=0x9F => HIGH[(n - 0x80) as usize],
        _ => c,
    }
}

const BOM: &[u8] = b"\xEF\xBB\xBF";

/// Parse an EDS or DCF. `path` is only for messages.
///
/// Only a file that is not an EDS at all (not INI, or no section an EDS has) is refused;
/// what a reader can safely interpret is read, and an object that cannot be understood is
/// left out; both are in [`Eds::warnings`] with file:line and the CiA 306 rule.
pub fn parse(bytes: &[u8], path: &str) -> Result<Eds, EdsError> {
    let (bytes, encoding) = match bytes.strip_prefix(BOM) {
        Some(rest) => (rest, TextEncoding { utf8: true }),
        None => (bytes, TextEncoding::of(bytes)),
    };
    let mut eds = Eds { path: path.to_string(), ..Eds::default() };
    let sections = parse_ini(bytes, path, &mut eds.warnings)?;
    let by_name: BTreeMap<(u16, Option<u8>), &Section> =
        sections.iter().filter_map(|s| object_section(&s.name).map(|k| (k, s))).collect();
    let known = |n: &str| matches!(n, "fileinfo" | "deviceinfo" | "devicecomissioning" | "devicecommissioning");
    if by_name.is_empty() && !sections.iter().any(|s| known(&s.name)) {
        return Err(EdsError {
            path: path.to_string(),
            line: sections.first().map_or(0, |s| s.line),
            msg: "not an EDS or DCF: it has no [FileInfo], [DeviceInfo] or object section such as [1000]".into(),
        });
    }
    let mut r = Reader { path, encoding, eds };
    for s in &sections {
        match s.name.as_str() {
            "deviceinfo" => r.eds.info = s.keys.iter().map(|(k, (v, _))| (k.clone(), encoding.decode(v))).collect(),
            "devicecomissioning" | "devicecommissioning" => r.commissioning(s),
            "dummyusage" => r.dummy_usage(s),
            _ => {}
        }
    }
    let compact: BTreeMap<String, &Section> = sections.iter().map(|s| (s.name.clone(), s)).collect();
    for ((index, sub), s) in &by_name {
        // Data type definitions (0x0001..0x025F) describe types, not objects.
        if sub.is_some() || *index < 0x1000 {
            continue;
        }
        let name = r.name_of(s, format!("Object {index:04X}"));
        let kind_code = match r.plain(s, "objecttype") {
            Some((v, line)) => match parse_int(v) {
                Some(code) => code,
                None => {
                    r.left_out(line, format!("{index:04X} ({name}) left out: ObjectType '{v}' is not a number"));
                    continue;
                }
            },
            None => 7,
        };
        let kind = match kind_code {
            // A DOMAIN object (0x2) is a single value, as a VAR is.
            7 | 2 => ObjectKind::Var,
            8 => ObjectKind::Array,
            9 => ObjectKind::Record,
            // DEFTYPE, DEFSTRUCT and NULL objects hold no values.
            0 | 5 | 6 => continue,
            other => {
                let line = s.get("objecttype").map_or(s.line, |(_, l)| l);
                r.left_out(
                    line,
                    format!(
                        "{index:04X} ({name}) left out: ObjectType {other} is not DOMAIN (2), VAR (7), ARRAY (8) or RECORD (9)"
                    ),
                );
                continue;
            }
        };
        if kind == ObjectKind::Var {
            let domain = kind_code == 2;
            if let Some(entry) = r.entry(s, ObjAddr::new(*index, 0), &name, domain) {
                r.eds.dict.insert(entry);
            }
            continue;
        }
        let compact_count = match r.plain(s, "compactsubobj") {
            Some((v, line)) => match parse_int(v) {
                Some(0) => None,
                Some(n @ 1..=254) if kind == ObjectKind::Array => Some(n as u8),
                // CiA 306 gives CompactSubObj to ARRAYs; Lely's dcfgen writes it for PDO
                // mapping RECORDs too, whose members share one type all the same.
                Some(n @ 1..=254) => {
                    r.warn(
                        line,
                        Kind::CompactRecord,
                        format!("{index:04X} ({name}) is a RECORD with CompactSubObj={v}: read as an ARRAY of {n} sub-objects of its DataType"),
                    );
                    Some(n as u8)
                }
                _ => {
                    r.left_out(
                        line,
                        format!("{index:04X} ({name}) left out: CompactSubObj={v} is not 1..254 for an ARRAY (0x8)"),
                    );
                    continue;
                }
            },
            None => None,
        };
        let entries = match compact_count {
            Some(n) => r.compact(s, *index, &name, n, &compact),
            None => {
                let subs: Vec<(u8, &Section)> = by_name
                    .range((*index, Some(0))..=(*index, Some(255)))
                    .map(|((_, sub), ss)| (sub.unwrap(), *ss))
                    .collect();
                if subs.is_empty() {
                    r.left_out(
                        s.line,
                        format!(
                            "{index:04X} ({name}) left out: an ARRAY or RECORD without any [{index:04X}subN] section or CompactSubObj"
                        ),
                    );
                    continue;
                }
                r.sub_number(s, *index, &name, subs.len());
                subs.into_iter()
                    .filter_map(|(sub, ss)| {
                        let member = r.name_of(ss, format!("Sub-index {sub}"));
                        r.entry(ss, ObjAddr::new(*index, sub), &member, false)
                    })
                    .collect()
            }
        };
        if entries.is_empty() {
            continue;
        }
        r.eds.dict.object(*index, &name, kind);
        for e in entries {
            r.eds.dict.insert(e);
        }
    }
    r.object_lists(&sections, &by_name);
    // In the order of the file; the note that more were cut stays last.
    r.eds.warnings.sort_by_key(|w| if w.kind == Kind::MoreLeftOut { usize::MAX } else { w.line });
    Ok(r.eds)
}

/// The file being read: where its deviations go.
struct Reader<'p> {
    path: &'p str,
    encoding: TextEncoding,
    eds: Eds,
}

/// `0x3ED ; prevent homing` → `0x3ED`: the text before a `;` that follows a blank.
fn strip_comment(v: &str) -> Option<&str> {
    let at = v.char_indices().find(|(i, c)| *c == ';' && *i > 0 && v[..*i].ends_with([' ', '\t']))?.0;
    Some(trim_blanks(&v[..at]))
}

impl Reader<'_> {
    fn warn(&mut self, line: usize, kind: Kind, message: String) {
        self.eds.warnings.push(Warning::new(self.path, line, kind, message));
    }

    fn left_out(&mut self, line: usize, message: String) {
        self.warn(line, Kind::ObjectLeftOut, message);
    }

    fn name_of(&self, s: &Section, fallback: String) -> String {
        s.get("parametername").map_or(fallback, |(v, _)| self.encoding.decode(v))
    }

    /// A key whose value is a number, a code or a value of a non-string type: an inline
    /// comment after it is read as python-canopen and Lely's dcfchk read it, and said so.
    fn plain<'s>(&mut self, s: &'s Section, key: &str) -> Option<(&'s str, usize)> {
        let (v, line) = s.get(key)?;
        match strip_comment(v) {
            Some(value) => {
                let key = s.spelled.get(key).map_or(key, String::as_str);
                self.warn(
                    line,
                    Kind::InlineComment,
                    format!("{key}={v}: the text from ';' on is read as a comment; the value is '{value}'"),
                );
                Some((value, line))
            }
            None => Some((v, line)),
        }
    }

    fn commissioning(&mut self, s: &Section) {
        if let Some((v, line)) = self.plain(s, "nodeid") {
            match parse_int(v) {
                Some(id) if NODE_IDS.contains(&id) => self.eds.node_id = Some(id as u8),
                Some(0) => self.warn(
                    line,
                    Kind::PlaceholderCommissioning,
                    "NodeID=0 is a placeholder, not a node-id: the node given on the command line is used".into(),
                ),
                _ => self.warn(line, Kind::ValueIgnored, format!("NodeID {v} is not 1 to 127: ignored")),
            }
        }
        if let Some((v, line)) = self.plain(s, "baudrate") {
            match parse_int(v) {
                Some(10 | 20 | 50 | 125 | 250 | 500 | 800 | 1000) => {}
                Some(0) => self.warn(
                    line,
                    Kind::PlaceholderCommissioning,
                    "BaudRate=0 is a placeholder, not a bit rate: the bus's own bit rate is used".into(),
                ),
                _ => self.warn(
                    line,
                    Kind::ValueIgnored,
                    format!("BaudRate {v} is not a CiA 301 bit rate in kbit/s (10 ... 1000): ignored"),
                ),
            }
        }
    }

    /// `Dummy0002=1`: the data type 0x0002 may be mapped into a PDO as a gap.
    fn dummy_usage(&mut self, s: &Section) {
        let mut keys: Vec<(&String, &(String, usize))> = s.keys.iter().collect();
        keys.sort_by_key(|(_, (_, line))| *line);
        for (key, (v, line)) in keys {
            let code = key.strip_prefix("dummy").filter(|c| c.len() == 4).and_then(|c| u16::from_str_radix(c, 16).ok());
            match (code, parse_int(v)) {
                (Some(code), Some(1)) => {
                    self.eds.dummy_usage.insert(code);
                }
                (Some(_), Some(0)) => {}
                _ => {
                    let key = s.spelled.get(key.as_str()).unwrap_or(key);
                    self.warn(
                        *line,
                        Kind::BadDummyUsage,
                        format!("[DummyUsage] {key}={v} is not DummyNNNN=0 or 1: ignored"),
                    )
                }
            }
        }
    }

    /// `[MandatoryObjects]`, `[OptionalObjects]`, `[ManufacturerObjects]` against the
    /// object sections there are. The reader goes by the sections; a list that says
    /// otherwise is said, as is a mandatory object (CiA 301: 0x1000, 0x1001, 0x1018) the
    /// file lacks. A file without any list (a snippet, a test file) is not held to them.
    fn object_lists(&mut self, sections: &[Section], by_name: &BTreeMap<(u16, Option<u8>), &Section>) {
        const LISTS: [&str; 3] = ["mandatoryobjects", "optionalobjects", "manufacturerobjects"];
        let lists: Vec<&Section> = sections.iter().filter(|s| LISTS.contains(&s.name.as_str())).collect();
        let Some(first) = lists.first() else { return };
        let mut listed = BTreeSet::new();
        for list in &lists {
            let title = list.spelled_name();
            let mut entries: Vec<(usize, &str, usize)> = Vec::new();
            for (key, (v, line)) in &list.keys {
                if key == "supportedobjects" {
                    continue;
                }
                match (parse_int(key), parse_int(v).and_then(|i| u16::try_from(i).ok())) {
                    (Some(n), Some(index)) if n >= 1 => {
                        entries.push((n as usize, v, *line));
                        if !by_name.contains_key(&(index, None)) {
                            self.warn(
                                *line,
                                Kind::ObjectList,
                                format!("[{title}] lists 0x{index:04X}, which has no [{index:04X}] section: nothing to read"),
                            );
                        }
                        listed.insert(index);
                    }
                    _ => self.warn(*line, Kind::ObjectList, format!("[{title}] {key}={v} is not N=index: ignored")),
                }
            }
            match list.get("supportedobjects") {
                Some((v, line)) if parse_int(v) != Some(entries.len() as i128) => self.warn(
                    line,
                    Kind::ObjectList,
                    format!("[{title}] SupportedObjects={v} but it lists {}: the sections are read", entries.len()),
                ),
                None => self.warn(
                    list.line,
                    Kind::ObjectList,
                    format!("[{title}] has no SupportedObjects: the {} it lists are read", entries.len()),
                ),
                _ => {}
            }
        }
        for ((index, _), s) in by_name.range((0x1000, None)..).filter(|((_, sub), _)| sub.is_none()) {
            if !listed.contains(index) {
                self.warn(
                    s.line,
                    Kind::ObjectList,
                    format!("[{index:04X}] is in no object list ([MandatoryObjects], [OptionalObjects], [ManufacturerObjects]): read all the same"),
                );
            }
        }
        for index in [0x1000u16, 0x1001, 0x1018] {
            if !by_name.contains_key(&(index, None)) {
                self.warn(
                    first.line,
                    Kind::ObjectList,
                    format!("no [{index:04X}] section: CiA 301 makes 0x{index:04X} mandatory for every device"),
                );
            }
        }
    }

    /// SubNumber, which the reader does not need (it reads the sections there are).
    fn sub_number(&mut self, s: &Section, index: u16, name: &str, found: usize) {
        match self.plain(s, "subnumber") {
            None => self.warn(
                s.line,
                Kind::MissingSubNumber,
                format!("{index:04X} ({name}) has no SubNumber: its {found} [{index:04X}subN] sections are read"),
            ),
            Some((v, line)) => match parse_int(v) {
                Some(n) if n == found as i128 => {}
                _ => self.warn(
                    line,
                    Kind::SubNumberMismatch,
                    format!(
                        "{index:04X} ({name}) has SubNumber={v} but {found} [{index:04X}subN] sections: those are read"
                    ),
                ),
            },
        }
    }

    /// A CompactSubObj array: sub 0 holds the count, subs 1..=n share the object's type,
    /// access and default; `[xxxxName]` names them and a DCF's `[xxxxValue]` gives values.
    fn compact(
        &mut self,
        s: &Section,
        index: u16,
        name: &str,
        n: u8,
        sections: &BTreeMap<String, &Section>,
    ) -> Vec<Entry> {
        let sub0 = Entry {
            addr: ObjAddr::new(index, 0),
            name: "NrOfObjects".into(),
            dtype: DataType::U8,
            access: Access::Ro,
            default: Init::Bytes(vec![n]),
            range: None,
        };
        let Some(template) = self.entry(s, ObjAddr::new(index, 1), name, false) else { return Vec::new() };
        // The object section's own ParameterValue is no member's.
        self.eds.values.remove(&ObjAddr::new(index, 1));
        let names = self.compact_list(sections.get(&format!("{index:04x}name")).copied(), index, n);
        let values = self.compact_list(sections.get(&format!("{index:04x}value")).copied(), index, n);
        let mut out = Vec::new();
        for sub in 1..=n {
            let addr = ObjAddr::new(index, sub);
            let member = names.get(&sub).map_or_else(|| format!("{name}{sub}"), |(v, _)| self.encoding.decode(v));
            if let Some((text, line)) = values.get(&sub) {
                match parse_value(text, template.dtype) {
                    Ok(v) => {
                        self.eds.values.insert(addr, v);
                    }
                    Err(m) => self.warn(*line, Kind::ValueIgnored, format!("[{index:04X}Value] {sub}: {m}; ignored")),
                }
            }
            out.push(Entry { addr, name: member, ..template.clone() });
        }
        if !values.is_empty() {
            // The count the device is to hold is the number of values given.
            self.eds.values.insert(sub0.addr, Init::Bytes(vec![values.keys().max().copied().unwrap_or(0)]));
        }
        out.insert(0, sub0);
        out
    }

    /// The `N=text` lines of a `[xxxxName]` or `[xxxxValue]` section, by subindex.
    fn compact_list(&mut self, s: Option<&Section>, index: u16, n: u8) -> BTreeMap<u8, (String, usize)> {
        let Some(s) = s else { return BTreeMap::new() };
        let mut out = BTreeMap::new();
        for (key, (v, line)) in &s.keys {
            if key == "nrofentries" {
                continue;
            }
            match parse_int(key).filter(|k| (1..=i128::from(n)).contains(k)) {
                Some(sub) => {
                    out.insert(sub as u8, (v.clone(), *line));
                }
                None => self.warn(
                    *line,
                    Kind::BadCompactSection,
                    format!(
                        "[{}] {key}={v}: {key} is not a sub-index 1..{n} of {index:04X}'s CompactSubObj; ignored",
                        s.name
                    ),
                ),
            }
        }
        out
    }

    /// One entry; `None` when it cannot be understood (said, with its line).
    fn entry(&mut self, s: &Section, addr: ObjAddr, name: &str, domain: bool) -> Option<Entry> {
        match self.try_entry(s, addr, name, domain) {
            Ok(e) => Some(e),
            Err((line, why)) => {
                self.left_out(line, format!("{addr} ({name}) left out: {why}"));
                None
            }
        }
    }

    fn try_entry(&mut self, s: &Section, addr: ObjAddr, name: &str, domain: bool) -> Result<Entry, (usize, String)> {
        // A complex, manufacturer or profile type: its bytes, as python-canopen reads it.
        let mut as_bytes = None;
        let dtype = match self.plain(s, "datatype") {
            Some((dt, line)) => {
                let code = parse_int(dt).ok_or((line, format!("DataType '{dt}' is not a number")))?;
                match data_type_from_code(code).map_err(|m| (line, m))? {
                    Some(t) => t,
                    None => {
                        as_bytes = Some((line, code));
                        DataType::D
                    }
                }
            }
            // A DOMAIN object needs no DataType: it is one.
            None if domain => DataType::D,
            None => return Err((s.line, "it has no DataType".into())),
        };
        let access = match self.plain(s, "accesstype") {
            Some((v, line)) => {
                parse_access(v).ok_or((line, format!("AccessType '{v}' is not ro, wo, rw, rwr, rww or const")))?
            }
            // DOMAINs are often described by type alone.
            None if dtype == DataType::D => Access::Rw,
            None => return Err((s.line, "it has no AccessType".into())),
        };
        let value_key = |r: &mut Self, key: &str| -> Option<(String, usize)> {
            if dtype == DataType::Unicode {
                s.get(key).map(|(v, l)| (r.encoding.decode(v), l))
            } else if dtype == DataType::Vs {
                s.get(key).map(|(v, l)| (v.to_string(), l))
            } else {
                r.plain(s, key).map(|(v, l)| (v.to_string(), l))
            }
        };
        if let Some((line, code)) = as_bytes {
            self.warn(
                line,
                Kind::TypeAsBytes,
                format!("{addr} ({name}) has data type 0x{code:04X}, not a CiA 301 basic type: read as DOMAIN (d), its bytes as they are, no default"),
            );
        }
        let default = match value_key(self, "defaultvalue").filter(|_| as_bytes.is_none()) {
            // What DOMAIN defaults often say for "nothing".
            Some((v, line))
                if dtype == DataType::D && ["0", "0x0", "null"].contains(&v.to_ascii_lowercase().as_str()) =>
            {
                self.warn(
                    line,
                    Kind::DomainDefault,
                    format!("DefaultValue={v} of DOMAIN {addr} ({name}) read as empty"),
                );
                Init::Bytes(Vec::new())
            }
            Some((v, line)) => match parse_value(&v, dtype) {
                Ok(init) => init,
                // A DOMAIN's default is often a file name or a note: not its content.
                Err(m) if dtype == DataType::D => {
                    self.warn(line, Kind::ValueIgnored, format!("DefaultValue of {addr} ({name}): {m}; read as empty"));
                    Init::Bytes(Vec::new())
                }
                Err(m) => return Err((line, format!("DefaultValue {m}"))),
            },
            None => Init::Bytes(if let Some(size) = dtype.size() { vec![0; size] } else { Vec::new() }),
        };
        let limit = |r: &mut Self, key: &str| -> Option<i128> {
            let (v, line) = value_key(r, key)?;
            if v.is_empty() || dtype.int_range().is_none() {
                return None;
            }
            match parse_int(&v) {
                Some(n) => Some(signed_from_hex(n, &v, dtype)),
                None => {
                    r.warn(
                        line,
                        Kind::ValueIgnored,
                        format!("{key} '{v}' of {addr} ({name}) is not an integer: no limit"),
                    );
                    None
                }
            }
        };
        let range = match (limit(self, "lowlimit"), limit(self, "highlimit")) {
            (None, None) => None,
            (lo, hi) => {
                let (tlo, thi) = dtype.int_range().expect("integer");
                Some((lo.unwrap_or(tlo), hi.unwrap_or(thi)))
            }
        };
        if let Some((v, line)) = value_key(self, "parametervalue") {
            match parse_value(&v, dtype) {
                Ok(value) => {
                    self.eds.values.insert(addr, value);
                }
                Err(m) => {
                    self.warn(line, Kind::ValueIgnored, format!("ParameterValue of {addr} ({name}): {m}; ignored"))
                }
            }
        }
        Ok(Entry { addr, name: name.to_string(), dtype, access, default, range })
    }
}

/// Read a file from disk: a regular file within `input::MAX_EDS_BYTES`.
pub fn read_file(path: &std::path::Path) -> Result<Eds, EdsError> {
    let bytes = crate::input::read_regular_file(path, crate::input::EDS).map_err(|e| EdsError {
        path: path.display().to_string(),
        line: 0,
        msg: e.to_string(),
    })?;
    parse(&bytes, &path.display().to_string())
}

/// The text form of a value, for people (tables, messages). Files use `value_text`.
pub fn format_value(init: &Init, dtype: DataType) -> String {
    match value_text(init, dtype) {
        Ok(text) if dtype != DataType::Vs => text,
        _ => match init {
            Init::Bytes(b) => dtype.decode(b).map_or_else(|| crate::canopen::types::hex(b), |v| v.to_string()),
            Init::NodeIdPlus(base) => format!("$NODEID+0x{base:X}"),
        },
    }
}

/// Why a value cannot be written to an EDS or DCF.
fn unwritable_bytes(bytes: &[u8]) -> Option<String> {
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
fn real_text(bytes: &[u8], dtype: DataType) -> String {
    fn shortest(plain: String, exp: String) -> String {
        if exp.len() < plain.len() {
            exp
        } else {
            plain
        }
    }
    match dtype {
        DataType::R32 => {
            let v = f32::from_le_bytes(bytes.try_into().expect("4 bytes"));
            if v.is_nan() {
                return if v.to_bits() == f32::NAN.to_bits() { "nan".into() } else { format!("0x{:08X}", v.to_bits()) };
            }
            shortest(format!("{v}"), format!("{v:e}"))
        }
        _ => {
            let v = f64::from_le_bytes(bytes.try_into().expect("8 bytes"));
            if v.is_nan() {
                return if v.to_bits() == f64::NAN.to_bits() {
                    "nan".into()
                } else {
                    format!("0x{:016X}", v.to_bits())
                };
            }
            shortest(format!("{v}"), format!("{v:e}"))
        }
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
    use crate::canopen::types::Value;
    Ok(match dtype {
        DataType::Vs => {
            if let Some(why) = unwritable_bytes(bytes) {
                return Err(why);
            }
            bytes.iter().map(|b| *b as char).collect()
        }
        DataType::Os | DataType::D => crate::canopen::types::hex(bytes),
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

/// EDS files are Latin-1: text as its bytes (a character beyond Latin-1 becomes '?').
/// For text from `write`, whose characters stand for bytes, this gives those bytes.
pub fn to_latin1(text: &str) -> Vec<u8> {
    text.chars().map(|c| u8::try_from(c as u32).unwrap_or(b'?')).collect()
}

/// What an EDS says about the file and the device.
#[derive(Clone, Debug, Default)]
pub struct Header {
    pub file_name: String,
    pub description: String,
    pub vendor_name: String,
    pub vendor_number: u32,
    pub product_name: String,
    pub product_number: u32,
    pub revision: u32,
    /// For a DCF: the node-id it was read from or is meant for.
    pub node_id: Option<u8>,
}

/// Something a file cannot carry exactly; nothing is written then.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("cannot write {what} to an EDS/DCF: {why}")]
pub struct WriteError {
    /// The object and key, e.g. `0x1008:0 (Manufacturer device name) ParameterValue`.
    pub what: String,
    pub why: String,
}

/// An EDS (no values) or a DCF (with `ParameterValue`s) for `dict`, as the bytes of the
/// file. Every value reads back to the same bytes (`parse`), or nothing is written and the
/// error names the object and why. Names are Latin-1 as CiA 306 files traditionally are,
/// UTF-8 when one is beyond Latin-1.
pub fn write_bytes(
    dict: &Dictionary,
    values: Option<&BTreeMap<ObjAddr, Vec<u8>>>,
    h: &Header,
) -> Result<Vec<u8>, WriteError> {
    let mut w = Writer { lines: Vec::new() };
    w.raw("[FileInfo]");
    // A DCF written to standard output has no name of its own to give.
    if !h.file_name.is_empty() {
        w.text("FileInfo", "FileName", &h.file_name)?;
    }
    w.raw("FileVersion=1");
    w.raw("FileRevision=0");
    w.raw("EDSVersion=4.0");
    w.text("FileInfo", "Description", &h.description)?;
    w.raw("CreatedBy=canctl");
    w.raw("");
    w.raw("[DeviceInfo]");
    w.text("DeviceInfo", "VendorName", &h.vendor_name)?;
    w.raw(&format!("VendorNumber=0x{:08X}", h.vendor_number));
    w.text("DeviceInfo", "ProductName", &h.product_name)?;
    w.raw(&format!("ProductNumber=0x{:08X}", h.product_number));
    w.raw(&format!("RevisionNumber=0x{:08X}", h.revision));
    w.raw("SimpleBootUpSlave=1");
    w.raw("Granularity=8");
    w.raw("LSS_Supported=1");
    w.raw("");
    if let Some(id) = h.node_id.filter(|_| values.is_some()) {
        w.raw("[DeviceComissioning]");
        w.raw(&format!("NodeID={id}"));
        w.raw("");
    }
    // CiA 306 lists the objects in three sections: mandatory, optional, manufacturer.
    let section_of = |i: u16| match i {
        0x1000 | 0x1001 | 0x1018 => "MandatoryObjects",
        0x2000..=0x5FFF => "ManufacturerObjects",
        _ => "OptionalObjects",
    };
    for section in ["MandatoryObjects", "OptionalObjects", "ManufacturerObjects"] {
        let objects: Vec<u16> = dict
            .objects()
            .map(|(i, _, _)| i)
            .filter(|i| section_of(*i) == section && dict.object_entries(*i).next().is_some())
            .collect();
        w.raw(&format!("[{section}]"));
        w.raw(&format!("SupportedObjects={}", objects.len()));
        for (n, i) in objects.iter().enumerate() {
            w.raw(&format!("{}=0x{i:04X}", n + 1));
        }
        w.raw("");
    }
    for (index, name, kind) in dict.objects() {
        let entries: Vec<&Entry> = dict.object_entries(index).collect();
        if entries.is_empty() {
            continue;
        }
        w.raw(&format!("[{index:04X}]"));
        w.text(&format!("{index:04X}"), "ParameterName", name)?;
        w.raw(&format!("ObjectType=0x{}", kind.code()));
        if kind == ObjectKind::Var {
            entry_keys(&mut w, dict, entries[0], values, h.node_id)?;
            w.raw("");
            continue;
        }
        w.raw(&format!("SubNumber={}", entries.len()));
        w.raw("");
        for e in entries {
            w.raw(&format!("[{index:04X}sub{:X}]", e.addr.sub));
            w.text(&format!("{index:04X}sub{:X}", e.addr.sub), "ParameterName", &e.name)?;
            w.raw("ObjectType=0x7");
            entry_keys(&mut w, dict, e, values, h.node_id)?;
            w.raw("");
        }
    }
    Ok(w.finish())
}

/// As `write_bytes`, the bytes as characters (`to_latin1` gives them back), for a
/// dictionary built in code, such as the simulator's models.
///
/// # Panics
/// When the dictionary holds a value no EDS can carry: files from devices go through
/// `write_bytes`, which says so.
pub fn write(dict: &Dictionary, values: Option<&BTreeMap<ObjAddr, Vec<u8>>>, h: &Header) -> String {
    match write_bytes(dict, values, h) {
        Ok(bytes) => bytes.iter().map(|b| *b as char).collect(),
        Err(e) => panic!("{e}"),
    }
}

enum Line {
    /// Keys, names and descriptions: text in the file's encoding.
    Text(String),
    /// `Key=` then a value's own bytes.
    Value(String, Vec<u8>),
}

struct Writer {
    lines: Vec<Line>,
}

impl Writer {
    fn raw(&mut self, line: &str) {
        self.lines.push(Line::Text(line.to_string()));
    }

    /// `key=text`, where the text must read back the same.
    fn text(&mut self, section: &str, key: &str, text: &str) -> Result<(), WriteError> {
        if let Some(why) = unwritable_bytes(text.as_bytes()) {
            return Err(WriteError { what: format!("[{section}] {key} '{}'", text.escape_debug()), why });
        }
        self.lines.push(Line::Text(format!("{key}={text}")));
        Ok(())
    }

    fn value(&mut self, key: &str, text: &str) {
        self.lines.push(Line::Value(format!("{key}="), to_latin1(text)));
    }

    /// Latin-1 when every name is; else UTF-8, with a byte order mark where a value's own
    /// bytes would make the file read as Latin-1.
    fn finish(self) -> Vec<u8> {
        let utf8 = self.lines.iter().any(|l| matches!(l, Line::Text(t) if t.chars().any(|c| c as u32 > 0xFF)));
        let mut out = Vec::new();
        for line in &self.lines {
            match line {
                Line::Text(t) if utf8 => out.extend_from_slice(t.as_bytes()),
                Line::Text(t) => out.extend(to_latin1(t)),
                Line::Value(key, bytes) => {
                    out.extend_from_slice(key.as_bytes());
                    out.extend_from_slice(bytes);
                }
            }
            out.push(b'\n');
        }
        if utf8 && std::str::from_utf8(&out).is_err() {
            out.splice(0..0, BOM.iter().copied());
        }
        out
    }
}

/// The node-id-relative COB-IDs of the predefined connection set (CiA 301): their base.
fn predefined_cob_id_base(addr: ObjAddr) -> Option<u32> {
    match (addr.index, addr.sub) {
        (0x1014, 0) => Some(0x80),
        (0x1200, 1) => Some(0x600),
        (0x1200, 2) => Some(0x580),
        (0x1400..=0x1403, 1) => Some(0x200 + 0x100 * u32::from(addr.index - 0x1400)),
        (0x1800..=0x1803, 1) => Some(0x180 + 0x100 * u32::from(addr.index - 0x1800)),
        _ => None,
    }
}

/// A DCF value as written: a COB-ID that follows the predefined connection set for the
/// node it was read from becomes `$NODEID+base`, so applying the file to another node gives
/// that node its own COB-IDs rather than copies of the first one's.
fn parameter_value(e: &Entry, bytes: &[u8], node: Option<u8>) -> Init {
    if let (Some(node), Some(base), Ok(raw), DataType::U32) =
        (node, predefined_cob_id_base(e.addr), <[u8; 4]>::try_from(bytes), e.dtype)
    {
        let value = u32::from_le_bytes(raw);
        if value & 0x7FF == base + u32::from(node) {
            return Init::NodeIdPlus(u64::from(value - u32::from(node)));
        }
    }
    Init::Bytes(bytes.to_vec())
}

fn entry_keys(
    w: &mut Writer,
    dict: &Dictionary,
    e: &Entry,
    values: Option<&BTreeMap<ObjAddr, Vec<u8>>>,
    node: Option<u8>,
) -> Result<(), WriteError> {
    let refuse = |key: &str, why: String| WriteError {
        what: format!("{} ({}) {key}", e.addr, dict.display_name(e.addr).unwrap_or_else(|| e.name.clone())),
        why,
    };
    w.raw(&format!("DataType=0x{:04X}", e.dtype.code()));
    w.raw(&format!("AccessType={}", e.access.name()));
    // A DOMAIN's default is its content: it has no place in a text file.
    if e.dtype != DataType::D {
        let text = value_text(&e.default, e.dtype).map_err(|why| refuse("DefaultValue", why))?;
        w.value("DefaultValue", &text);
    }
    if let Some((lo, hi)) = e.range {
        w.raw(&format!("LowLimit={lo}"));
        w.raw(&format!("HighLimit={hi}"));
    }
    w.raw("PDOMapping=0");
    if let Some(v) = values.and_then(|v| v.get(&e.addr)) {
        let text = parameter_text(e, v, node).map_err(|why| refuse("ParameterValue", why))?;
        w.value("ParameterValue", &text);
    }
    Ok(())
}

/// The `ParameterValue` text of `bytes` for entry `e` in a DCF for `node`, or why a DCF
/// cannot carry it exactly.
pub fn parameter_text(e: &Entry, bytes: &[u8], node: Option<u8>) -> Result<String, String> {
    value_text(&parameter_value(e, bytes, node), e.dtype)
}

#[cfg(test)]
mod tests;
