//! EDS and DCF files (CiA 306): INI sections per object and sub-object, read into a
//! `Dictionary` (plus a DCF's `ParameterValue`s) and written from one.
//!
//! Real files are Latin-1, use CRLF, vary the case of keys and section names and leave out
//! optional keys; the reader takes all that. What it cannot read it names with file:line.

use super::{Access, Dictionary, Entry, Init, ObjectKind};
use crate::canopen::{DataType, ObjAddr};
use std::collections::BTreeMap;

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{path}:{line}: {msg}")]
pub struct EdsError {
    pub path: String,
    pub line: usize,
    pub msg: String,
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
    /// Objects passed over (unsupported data types), with file:line.
    pub warnings: Vec<String>,
}

struct Section {
    name: String,
    line: usize,
    keys: Vec<(String, String, usize)>,
}

impl Section {
    fn get(&self, key: &str) -> Option<(&str, usize)> {
        self.keys.iter().rev().find(|(k, _, _)| k == key).map(|(_, v, l)| (v.as_str(), *l))
    }
}

/// Sections with their lines; keys lower-cased. Latin-1 bytes become the same characters.
fn parse_ini(bytes: &[u8], path: &str) -> Result<Vec<Section>, EdsError> {
    let text: String = bytes.iter().map(|b| *b as char).collect();
    let err = |line: usize, msg: String| EdsError { path: path.to_string(), line, msg };
    let mut sections: Vec<Section> = Vec::new();
    for (i, raw) in text.split('\n').enumerate() {
        let line = raw.trim_end_matches('\r').trim();
        let no = i + 1;
        if line.is_empty() || line.starts_with(';') || line.starts_with('#') {
            continue;
        }
        if let Some(rest) = line.strip_prefix('[') {
            let name =
                rest.strip_suffix(']').ok_or_else(|| err(no, format!("section header '{line}' has no closing ]")))?;
            sections.push(Section { name: name.trim().to_ascii_lowercase(), line: no, keys: Vec::new() });
            continue;
        }
        let (key, value) =
            line.split_once('=').ok_or_else(|| err(no, format!("expected KEY=VALUE or [SECTION], found '{line}'")))?;
        let section = sections.last_mut().ok_or_else(|| err(no, format!("'{line}' comes before any [SECTION]")))?;
        section.keys.push((key.trim().to_ascii_lowercase(), value.trim().to_string(), no));
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
fn parse_int(text: &str) -> Option<i128> {
    let t = text.trim();
    let (neg, body) = match t.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, t.strip_prefix('+').unwrap_or(t)),
    };
    let v = if let Some(h) = body.strip_prefix("0x").or_else(|| body.strip_prefix("0X")) {
        i128::from_str_radix(h, 16).ok()?
    } else if body.len() > 1 && body.starts_with('0') {
        i128::from_str_radix(&body[1..], 8).ok()?
    } else {
        body.parse().ok()?
    };
    Some(if neg { -v } else { v })
}

/// A value as the file writes it, for an entry of type `dtype`.
fn parse_value(text: &str, dtype: DataType) -> Result<Init, String> {
    let t = text.trim();
    let lower = t.to_ascii_lowercase();
    if lower.contains("$nodeid") {
        // `$NODEID+0x180`, `0x180+$NODEID`, `$NODEID`
        let rest: String = lower.replace("$nodeid", "").replace('+', "").trim().to_string();
        let base = if rest.is_empty() {
            0
        } else {
            parse_int(&rest).ok_or_else(|| format!("'{t}' is not $NODEID plus a number"))?
        };
        if dtype.int_range().is_none() || !(0..=u32::MAX as i128).contains(&base) {
            return Err(format!("'{t}' needs an unsigned integer type, not {dtype}"));
        }
        return Ok(Init::NodeIdPlus(base as u32));
    }
    let bytes = match dtype {
        DataType::Vs => t.as_bytes().to_vec(),
        DataType::Os | DataType::D => crate::canopen::types::parse_hex(t)?,
        DataType::R32 | DataType::R64 => dtype.parse(if t.is_empty() { "0" } else { t }).map_err(|e| e.0)?,
        _ => {
            let v = if t.is_empty() { 0 } else { parse_int(t).ok_or_else(|| format!("'{t}' is not an integer"))? };
            let (lo, hi) = dtype.int_range().expect("integer type");
            // Unsigned values written as negative numbers, or signed ones in hex, are common.
            let v = if v > hi && dtype.is_signed() { v - (hi - lo + 1) } else { v };
            if v < lo || v > hi {
                return Err(format!("{t} is out of range for {dtype} ({lo}..={hi})"));
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

fn data_type_from_code(code: u16) -> Option<DataType> {
    crate::canopen::types::ALL_TYPES.iter().copied().find(|t| t.code() == code)
}

/// Parse an EDS or DCF. `path` is only for messages.
pub fn parse(bytes: &[u8], path: &str) -> Result<Eds, EdsError> {
    let sections = parse_ini(bytes, path)?;
    let err = |line: usize, msg: String| EdsError { path: path.to_string(), line, msg };
    let mut eds = Eds { path: path.to_string(), ..Eds::default() };
    let by_name: BTreeMap<(u16, Option<u8>), &Section> =
        sections.iter().filter_map(|s| object_section(&s.name).map(|k| (k, s))).collect();
    for s in &sections {
        match s.name.as_str() {
            "deviceinfo" => eds.info = s.keys.iter().map(|(k, v, _)| (k.clone(), v.clone())).collect(),
            "devicecomissioning" | "devicecommissioning" => {
                if let Some((v, line)) = s.get("nodeid") {
                    let id = parse_int(v)
                        .filter(|n| (1..=127).contains(n))
                        .ok_or_else(|| err(line, format!("NodeID {v} is not 1..127")))?;
                    eds.node_id = Some(id as u8);
                }
            }
            _ => {}
        }
    }
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
        let name = s.get("parametername").map_or_else(|| format!("Object {index:04X}"), |(v, _)| v.to_string());
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
            let member =
                ss.get("parametername").map_or_else(|| format!("Sub-index {}", sub.unwrap()), |(v, _)| v.to_string());
            read_entry(&mut eds, ss, ObjAddr::new(*index, sub.unwrap()), &member, path)?;
        }
    }
    Ok(eds)
}

fn read_entry(eds: &mut Eds, s: &Section, addr: ObjAddr, name: &str, path: &str) -> Result<(), EdsError> {
    let err = |line: usize, msg: String| EdsError { path: path.to_string(), line, msg };
    let (dt, dt_line) = s.get("datatype").ok_or_else(|| err(s.line, format!("{addr} ({name}) has no DataType")))?;
    let code = parse_int(dt).ok_or_else(|| err(dt_line, format!("DataType '{dt}' is not a number")))?;
    let Some(dtype) = data_type_from_code(code as u16) else {
        eds.warnings.push(format!(
            "{path}:{dt_line}: {addr} ({name}) has data type 0x{code:04X}, which canctl does not handle; passed over"
        ));
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
                parse_int(v).map(Some).ok_or_else(|| err(line, format!("{key} '{v}' of {addr} is not an integer")))
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

/// Read a file from disk.
pub fn read_file(path: &std::path::Path) -> Result<Eds, EdsError> {
    let bytes =
        std::fs::read(path).map_err(|e| EdsError { path: path.display().to_string(), line: 0, msg: e.to_string() })?;
    parse(&bytes, &path.display().to_string())
}

/// The text form of a value in an EDS/DCF.
pub fn format_value(init: &Init, dtype: DataType) -> String {
    match init {
        Init::NodeIdPlus(0) => "$NODEID".into(),
        Init::NodeIdPlus(base) => format!("$NODEID+0x{base:X}"),
        Init::Bytes(b) => match dtype.decode(b) {
            Some(crate::canopen::types::Value::Uint(u)) => format!("0x{u:X}"),
            Some(crate::canopen::types::Value::Bool(v)) => (v as u8).to_string(),
            Some(v) => v.to_string(),
            None => crate::canopen::types::hex(b),
        },
    }
}

/// EDS files are Latin-1: text as its bytes (a character beyond Latin-1 becomes '?').
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

/// An EDS (no values) or a DCF (with `ParameterValue`s) for `dict`.
pub fn write(dict: &Dictionary, values: Option<&BTreeMap<ObjAddr, Vec<u8>>>, h: &Header) -> String {
    let mut out = String::new();
    let mut line = |s: String| {
        out.push_str(&s);
        out.push('\n');
    };
    line("[FileInfo]".into());
    line(format!("FileName={}", h.file_name));
    line("FileVersion=1".into());
    line("FileRevision=0".into());
    line("EDSVersion=4.0".into());
    line(format!("Description={}", h.description));
    line("CreatedBy=canctl".into());
    line(String::new());
    line("[DeviceInfo]".into());
    line(format!("VendorName={}", h.vendor_name));
    line(format!("VendorNumber=0x{:08X}", h.vendor_number));
    line(format!("ProductName={}", h.product_name));
    line(format!("ProductNumber=0x{:08X}", h.product_number));
    line(format!("RevisionNumber=0x{:08X}", h.revision));
    line("SimpleBootUpSlave=1".into());
    line("Granularity=8".into());
    line("LSS_Supported=1".into());
    line(String::new());
    if let Some(id) = h.node_id.filter(|_| values.is_some()) {
        line("[DeviceComissioning]".into());
        line(format!("NodeID={id}"));
        line(String::new());
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
        line(format!("[{section}]"));
        line(format!("SupportedObjects={}", objects.len()));
        for (n, i) in objects.iter().enumerate() {
            line(format!("{}=0x{i:04X}", n + 1));
        }
        line(String::new());
    }
    for (index, name, kind) in dict.objects() {
        let entries: Vec<&Entry> = dict.object_entries(index).collect();
        if entries.is_empty() {
            continue;
        }
        line(format!("[{index:04X}]"));
        line(format!("ParameterName={name}"));
        line(format!("ObjectType=0x{}", kind.code()));
        if kind == ObjectKind::Var {
            entry_keys(&mut line, entries[0], values, h.node_id);
            line(String::new());
            continue;
        }
        line(format!("SubNumber={}", entries.len()));
        line(String::new());
        for e in entries {
            line(format!("[{index:04X}sub{:X}]", e.addr.sub));
            line(format!("ParameterName={}", e.name));
            line("ObjectType=0x7".into());
            entry_keys(&mut line, e, values, h.node_id);
            line(String::new());
        }
    }
    out
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
fn parameter_value(e: &Entry, bytes: &[u8], node: Option<u8>) -> String {
    if let (Some(node), Some(base), Ok(raw)) = (node, predefined_cob_id_base(e.addr), <[u8; 4]>::try_from(bytes)) {
        let value = u32::from_le_bytes(raw);
        if value & 0x7FF == base + u32::from(node) {
            return format_value(&Init::NodeIdPlus(value - u32::from(node)), e.dtype);
        }
    }
    format_value(&Init::Bytes(bytes.to_vec()), e.dtype)
}

fn entry_keys(line: &mut impl FnMut(String), e: &Entry, values: Option<&BTreeMap<ObjAddr, Vec<u8>>>, node: Option<u8>) {
    line(format!("DataType=0x{:04X}", e.dtype.code()));
    line(format!("AccessType={}", e.access.name()));
    // A DOMAIN's default is its content: it has no place in a text file.
    if e.dtype != DataType::D {
        line(format!("DefaultValue={}", format_value(&e.default, e.dtype)));
    }
    if let Some((lo, hi)) = e.range {
        line(format!("LowLimit={lo}"));
        line(format!("HighLimit={hi}"));
    }
    line("PDOMapping=0".into());
    if let Some(v) = values.and_then(|v| v.get(&e.addr)) {
        line(format!("ParameterValue={}", parameter_value(e, v, node)));
    }
}

#[cfg(test)]
mod tests;
