//! Writing an EDS or DCF from a dictionary (and a DCF's values): the sections, keys and
//! `ParameterValue`s, each value checked to read back as the same bytes.

use super::ini::{to_latin1, BOM};
use super::values::{unwritable_bytes, value_text};
use crate::{Dictionary, Entry, Init, ObjectKind, Values};
use canctl_canopen::{DataType, ObjAddr};
/// What an EDS says about the file and the device.
#[derive(Clone, Debug, Default)]
pub struct Header {
    /// The file's own name (`FileName`).
    pub file_name: String,
    /// What the file describes, in words (`Description`).
    pub description: String,
    /// The vendor's name (`VendorName`).
    pub vendor_name: String,
    /// The CiA vendor-id (`VendorNumber`, 0x1018:1).
    pub vendor_number: u32,
    /// The product's name (`ProductName`).
    pub product_name: String,
    /// The vendor's product code (`ProductNumber`, 0x1018:2).
    pub product_number: u32,
    /// The revision number (`RevisionNumber`, 0x1018:3).
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
    /// Why it cannot be written exactly.
    pub why: String,
}

/// An EDS (no values) or a DCF (with `ParameterValue`s) for `dict`, as the bytes of the
/// file. Every value reads back to the same bytes (`parse`), or nothing is written and the
/// error names the object and why. Names are Latin-1 as CiA 306 files traditionally are,
/// UTF-8 when one is beyond Latin-1.
pub fn write_bytes(dict: &Dictionary, values: Option<&Values>, h: &Header) -> Result<Vec<u8>, WriteError> {
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
pub fn write(dict: &Dictionary, values: Option<&Values>, h: &Header) -> String {
    write_bytes(dict, values, h).unwrap_or_else(|e| panic!("{e}")).iter().map(|b| *b as char).collect()
}

pub(super) enum Line {
    /// Keys, names and descriptions: text in the file's encoding.
    Text(String),
    /// `Key=` then a value's own bytes.
    Value(String, Vec<u8>),
}

pub(super) struct Writer {
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
pub(super) fn predefined_cob_id_base(addr: ObjAddr) -> Option<u32> {
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
pub(super) fn parameter_value(e: &Entry, bytes: &[u8], node: Option<u8>) -> Init {
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

pub(super) fn entry_keys(
    w: &mut Writer,
    dict: &Dictionary,
    e: &Entry,
    values: Option<&Values>,
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
