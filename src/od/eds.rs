//! EDS and DCF files (CiA 306): INI sections per object and sub-object, read into a
//! `Dictionary` (plus a DCF's `ParameterValue`s) and written from one.
//!
//! Real files are Latin-1, use CRLF, vary the case of keys and section names and leave out
//! optional keys; the reader takes all that. What it cannot read it names with file:line.

use super::{Access, Dictionary, Entry, Init, ObjectKind};
use crate::canopen::{DataType, ObjAddr};
use std::collections::BTreeMap;

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
    /// What was read but deserves a look (objects passed over, repeated keys, over-long
    /// lines), each with file:line. The library never prints: the caller shows them.
    pub warnings: Vec<String>,
}

/// CiA 306 keeps a line to 255 characters; longer ones are read, with a warning.
pub const MAX_LINE_CHARS: usize = 255;

/// The warnings kept: a file with thousands of repeated keys gives a list, not a flood.
pub const MAX_WARNINGS: usize = 100;

fn warn(warnings: &mut Vec<String>, msg: String) {
    match warnings.len() {
        n if n < MAX_WARNINGS => warnings.push(msg),
        MAX_WARNINGS => warnings.push(format!("further warnings left out (the first {MAX_WARNINGS} are listed)")),
        _ => {}
    }
}

struct Section {
    name: String,
    line: usize,
    /// Lower-cased key → value and line; a repeated key keeps its last value.
    keys: std::collections::HashMap<String, (String, usize)>,
}

impl Section {
    fn get(&self, key: &str) -> Option<(&str, usize)> {
        self.keys.get(key).map(|(v, l)| (v.as_str(), *l))
    }
}

/// The blanks an INI line may have around keys and values: ASCII space and tab only, so
/// that Latin-1 bytes such as 0xA0 stay part of the value.
fn trim_blanks(s: &str) -> &str {
    s.trim_matches([' ', '\t'])
}

/// Sections with their lines; keys lower-cased. Each byte becomes the Latin-1 character
/// of the same number, so a value's text gives back its exact bytes (`to_latin1`).
fn parse_ini(bytes: &[u8], path: &str, warnings: &mut Vec<String>) -> Result<Vec<Section>, EdsError> {
    let text: String = bytes.iter().map(|b| *b as char).collect();
    let err = |line: usize, msg: String| EdsError { path: path.to_string(), line, msg };
    let mut sections: Vec<Section> = Vec::new();
    let mut seen_sections: BTreeMap<String, usize> = BTreeMap::new();
    for (i, raw) in text.split('\n').enumerate() {
        let no = i + 1;
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        if raw.chars().count() > MAX_LINE_CHARS {
            warn(
                warnings,
                format!(
                    "{path}:{no}: line of {} characters, more than the {MAX_LINE_CHARS} CiA 306 allows (read in full)",
                    raw.chars().count()
                ),
            );
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
                warn(
                    warnings,
                    format!("{path}:{no}: section {line} again (before at line {first}): this one replaces it"),
                );
            }
            sections.push(Section { name, line: no, keys: Default::default() });
            continue;
        }
        let (key, value) =
            line.split_once('=').ok_or_else(|| err(no, format!("expected KEY=VALUE or [SECTION], found '{line}'")))?;
        let section = sections.last_mut().ok_or_else(|| err(no, format!("'{line}' comes before any [SECTION]")))?;
        let key_lower = trim_blanks(key).to_ascii_lowercase();
        let value = (trim_blanks(value).to_string(), no);
        if let Some((_, first)) = section.keys.insert(key_lower, value) {
            warn(
                warnings,
                format!(
                    "{path}:{no}: {} repeated in [{}] (before at line {first}): the value of line {no} is used",
                    trim_blanks(key),
                    section.name
                ),
            );
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

    /// Text read as Latin-1 (one character per byte), as the file meant it.
    fn decode(self, latin1: &str) -> String {
        if self.utf8 {
            if let Ok(s) = String::from_utf8(to_latin1(latin1)) {
                return s;
            }
        }
        latin1.to_string()
    }
}

const BOM: &[u8] = b"\xEF\xBB\xBF";

/// Parse an EDS or DCF. `path` is only for messages.
pub fn parse(bytes: &[u8], path: &str) -> Result<Eds, EdsError> {
    let (bytes, encoding) = match bytes.strip_prefix(BOM) {
        Some(rest) => (rest, TextEncoding { utf8: true }),
        None => (bytes, TextEncoding::of(bytes)),
    };
    let mut eds = Eds { path: path.to_string(), ..Eds::default() };
    let sections = parse_ini(bytes, path, &mut eds.warnings)?;
    let err = |line: usize, msg: String| EdsError { path: path.to_string(), line, msg };
    let by_name: BTreeMap<(u16, Option<u8>), &Section> =
        sections.iter().filter_map(|s| object_section(&s.name).map(|k| (k, s))).collect();
    for s in &sections {
        match s.name.as_str() {
            "deviceinfo" => eds.info = s.keys.iter().map(|(k, (v, _))| (k.clone(), encoding.decode(v))).collect(),
            "devicecomissioning" | "devicecommissioning" => {
                if let Some((v, line)) = s.get("nodeid") {
                    let id = parse_int(v)
                        .filter(|n| NODE_IDS.contains(n))
                        .ok_or_else(|| err(line, format!("NodeID {v} is not 1 to 127")))?;
                    eds.node_id = Some(id as u8);
                }
            }
            _ => {}
        }
    }
    let name_of = |s: &Section, fallback: String| s.get("parametername").map_or(fallback, |(v, _)| encoding.decode(v));
    for ((index, sub), s) in &by_name {
        if sub.is_some() {
            continue;
        }
        // Data type definitions (0x0001..0x025F) describe types, not objects.
        if *index < 0x1000 {
            continue;
        }
        let kind_code = match s.get("objecttype") {
            Some((v, line)) => parse_int(v).ok_or_else(|| err(line, format!("ObjectType '{v}' is not a number")))?,
            None => 7,
        };
        let name = name_of(s, format!("Object {index:04X}"));
        let kind = match kind_code {
            7 => ObjectKind::Var,
            8 => ObjectKind::Array,
            9 => ObjectKind::Record,
            // DEFTYPE, DEFSTRUCT and NULL objects hold no values.
            0 | 5 | 6 => continue,
            other => {
                return Err(err(
                    s.get("objecttype").map_or(s.line, |(_, l)| l),
                    format!("ObjectType {other} is not VAR (7), ARRAY (8) or RECORD (9)"),
                ))
            }
        };
        if kind == ObjectKind::Var {
            // `insert` declares the object, unless its type was passed over.
            read_entry(&mut eds, s, ObjAddr::new(*index, 0), &name, path)?;
            continue;
        }
        eds.dict.object(*index, &name, kind);
        let subs: Vec<(&(u16, Option<u8>), &&Section)> =
            by_name.range((*index, Some(0))..=(*index, Some(255))).collect();
        if subs.is_empty() {
            return Err(err(
                s.line,
                format!("{name} ({index:04X}) is an array or record without any [{index:04X}subN] section"),
            ));
        }
        for ((_, sub), ss) in subs {
            let member = name_of(ss, format!("Sub-index {}", sub.unwrap()));
            read_entry(&mut eds, ss, ObjAddr::new(*index, sub.unwrap()), &member, path)?;
        }
    }
    Ok(eds)
}

fn read_entry(eds: &mut Eds, s: &Section, addr: ObjAddr, name: &str, path: &str) -> Result<(), EdsError> {
    let err = |line: usize, msg: String| EdsError { path: path.to_string(), line, msg };
    let (dt, dt_line) = s.get("datatype").ok_or_else(|| err(s.line, format!("{addr} ({name}) has no DataType")))?;
    let code = parse_int(dt).ok_or_else(|| err(dt_line, format!("DataType '{dt}' is not a number")))?;
    let Some(dtype) = data_type_from_code(code).map_err(|m| err(dt_line, format!("{addr} ({name}): {m}")))? else {
        warn(
            &mut eds.warnings,
            format!(
            "{path}:{dt_line}: {addr} ({name}) has data type 0x{code:04X}, which canctl does not handle; passed over"
        ),
        );
        return Ok(());
    };
    let access = match s.get("accesstype") {
        Some((v, line)) => parse_access(v)
            .ok_or_else(|| err(line, format!("AccessType '{v}' is not ro, wo, rw, rwr, rww or const")))?,
        None => return Err(err(s.line, format!("{addr} ({name}) has no AccessType"))),
    };
    let default = match s.get("defaultvalue") {
        Some((v, line)) if dtype != DataType::D => {
            parse_value(v, dtype).map_err(|m| err(line, format!("DefaultValue of {addr}: {m}")))?
        }
        _ => Init::Bytes(if let Some(size) = dtype.size() { vec![0; size] } else { Vec::new() }),
    };
    let limit = |key: &str| -> Result<Option<i128>, EdsError> {
        match s.get(key) {
            Some((v, line)) if !v.is_empty() && dtype.int_range().is_some() => {
                let n = parse_int(v).ok_or_else(|| err(line, format!("{key} '{v}' of {addr} is not an integer")))?;
                Ok(Some(signed_from_hex(n, v, dtype)))
            }
            _ => Ok(None),
        }
    };
    let range = match (limit("lowlimit")?, limit("highlimit")?) {
        (None, None) => None,
        (lo, hi) => {
            let (tlo, thi) = dtype.int_range().expect("integer");
            Some((lo.unwrap_or(tlo), hi.unwrap_or(thi)))
        }
    };
    if let Some((v, line)) = s.get("parametervalue") {
        let value = parse_value(v, dtype).map_err(|m| err(line, format!("ParameterValue of {addr}: {m}")))?;
        eds.values.insert(addr, value);
    }
    eds.dict.insert(Entry { addr, name: name.to_string(), dtype, access, default, range });
    Ok(())
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
