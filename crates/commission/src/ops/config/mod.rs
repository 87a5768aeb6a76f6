//! A node's configuration as a DCF (CiA 306): read into one ([`dump`]), compared with one
//! ([`diff`]), and made to match one ([`apply`]) — writing only what differs, in a safe
//! order, with what happened to each object in the report.

use super::progress::Progress;
use super::values::le_u32;
use crate::bus::Bus;
use crate::canopen::{abort, DataType, ObjAddr};
use crate::error::{Error, Result};
use crate::od::eds::{self, Header};
use crate::od::xdd;
use crate::od::{Dictionary, Entry};
use crate::ops::event::Notice;
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Duration;

/// A node's objects, read into a DCF.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Dump {
    /// The node-id read.
    pub node: u8,
    /// How many objects the node answered.
    pub objects: usize,
    /// The user stopped the reading part-way (SIGINT, SIGTERM, over a
    /// [`Stoppable`](crate::bus::stoppable::Stoppable) bus): `objects` of `wanted` were
    /// read, and there is no DCF.
    pub interrupted: bool,
    /// How many objects the dictionary lists to be read.
    pub wanted: usize,
    /// Where the list of objects came from: an EDS, or the built-in dictionary.
    pub source: String,
    /// The DCF, Latin-1 as CiA 306 has it (or the XDC, UTF-8 XML, from `dump_as`).
    #[serde(skip)]
    pub dcf: Vec<u8>,
}

/// Read every readable object of `node` into a DCF named `file_name`. The objects come from
/// `dictionary` (with the name of its source), else from the built-in dictionary for the
/// node's profile (0x1000), probed: what the node does not have is left out. DOMAINs are
/// not read.
pub fn dump(
    bus: &mut dyn Bus,
    node: u8,
    dictionary: Option<(&Dictionary, &str)>,
    file_name: &str,
    timeout: Duration,
    progress: &mut dyn Progress,
) -> Result<Dump> {
    dump_as(bus, node, dictionary, file_name, timeout, progress, FileForm::Dcf)
}

/// The form of a node's configuration file: CiA 306's INI or CiA 311's XML.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileForm {
    /// A DCF (CiA 306, INI).
    Dcf,
    /// An XDC (CiA 311, XML).
    Xdc,
}

/// [`dump`], into a DCF or an XDC.
pub fn dump_as(
    bus: &mut dyn Bus,
    node: u8,
    dictionary: Option<(&Dictionary, &str)>,
    file_name: &str,
    timeout: Duration,
    progress: &mut dyn Progress,
    form: FileForm,
) -> Result<Dump> {
    let (dict, source) = node_dictionary(bus, node, dictionary, timeout)?;
    let wanted: Vec<&Entry> = dict.entries().filter(|e| e.access.readable() && e.dtype != DataType::D).collect();
    progress.start("reading", wanted.len() as u64);
    let mut present = Dictionary::default();
    let mut values = BTreeMap::new();
    for (i, e) in wanted.iter().enumerate() {
        progress.advance(i as u64);
        match read_one(bus, node, e, timeout) {
            Ok(v) => {
                values.insert(e.addr, v);
            }
            Err(err) if err.is_interrupted() => {
                progress.finish();
                let (objects, wanted) = (values.len(), wanted.len());
                return Ok(Dump { node, objects, interrupted: true, wanted, source, dcf: Vec::new() });
            }
            // Not on this device: left out of the file.
            Err(err) if super::node::is_missing(&err) => continue,
            Err(Error::SdoAbort { code, .. }) => progress.event(Notice::Refused { addr: e.addr, code }.into()),
            Err(err) => return Err(err),
        }
        let (name, kind) = dict.object_info(e.addr.index).expect("declared object");
        present.object(e.addr.index, name, kind);
        present.insert((*e).clone());
    }
    progress.finish();
    let identity = |addr| values.get(&addr).map_or(0, |v: &Vec<u8>| le_u32(v));
    let name = values
        .get(&ObjAddr::DEVICE_NAME)
        .map(|v| String::from_utf8_lossy(v).trim_end_matches('\0').to_string())
        .unwrap_or_default();
    let header = Header {
        file_name: file_name.to_string(),
        description: format!("node {node} on {}, read by canctl; objects from {source}", bus.describe()),
        vendor_name: String::new(),
        vendor_number: identity(ObjAddr::VENDOR_ID),
        product_name: name,
        product_number: identity(ObjAddr::PRODUCT_CODE),
        revision: identity(ObjAddr::REVISION_NUMBER),
        node_id: Some(node),
    };
    // A value no DCF can hold (a newline in a string, say) is left out, and said so.
    type Text = fn(&Entry, &[u8], Option<u8>) -> Result<String, String>;
    type Write = fn(&Dictionary, Option<&BTreeMap<ObjAddr, Vec<u8>>>, &Header) -> Result<Vec<u8>, eds::WriteError>;
    let (text, write, file): (Text, Write, _) = match form {
        FileForm::Dcf => (eds::parameter_text, eds::write_bytes, "DCF"),
        FileForm::Xdc => (xdd::actual_value_text, xdd::write_bytes, "XDC"),
    };
    values.retain(|addr, v| match present.get(*addr).map(|e| text(e, v, Some(node))) {
        Some(Err(why)) => {
            progress.event(Notice::LeftOut { addr: *addr, file, why }.into());
            false
        }
        _ => true,
    });
    let dcf = write(&present, Some(&values), &header).map_err(|e| Error::NotWritable(e.into()))?;
    Ok(Dump { node, objects: values.len(), interrupted: false, wanted: wanted.len(), source, dcf })
}

/// Where a node differs from a DCF.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Diff {
    /// The node-id compared.
    pub node: u8,
    /// The DCF compared with, as named.
    pub file: String,
    /// Objects that match.
    pub same: usize,
    /// Each object whose value differs, in the file's order.
    pub differences: Vec<Difference>,
    /// The user stopped the comparison part-way (SIGINT, SIGTERM, over a
    /// [`Stoppable`](crate::bus::stoppable::Stoppable) bus): the objects counted are those
    /// compared so far.
    pub interrupted: bool,
    /// Objects of the file not compared, when interrupted.
    #[serde(skip_serializing_if = "is_zero")]
    pub not_compared: usize,
    /// The file is for another kind of device: where the device's identity (vendor-ID,
    /// product code) is not the file's, as `config apply` would refuse it.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub other_device: Vec<String>,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl Diff {
    /// The verdict (exit 6) when anything differs; interrupted, the interruption.
    pub fn check(&self) -> Result<(), crate::ops::unmet::Shortfall> {
        if self.interrupted {
            return Err(Error::Interrupted.into());
        }
        if self.differences.is_empty() {
            return Ok(());
        }
        let (node, file, count) = (self.node, self.file.clone(), self.differences.len());
        Err(crate::ops::unmet::Unmet::Differs { node, file, count }.into())
    }
}

/// Compare the node's readable objects with the DCF's values.
pub fn diff(bus: &mut dyn Bus, node: u8, dcf: &Dcf, timeout: Duration) -> Result<Diff> {
    let values = dcf.values(node)?;
    let mut differences = Vec::new();
    let mut same = 0;
    let readable: Vec<&Wanted> = values.iter().filter(|(e, _)| e.access.readable()).collect();
    for (i, (entry, want)) in readable.iter().enumerate() {
        let device = match read_one(bus, node, entry, timeout) {
            Ok(v) if v == *want => {
                same += 1;
                continue;
            }
            Ok(v) => show(entry, &v),
            Err(Error::SdoAbort { code, .. }) => format!("({})", abort::meaning(code)),
            Err(e) if e.is_interrupted() => {
                let (file, not_compared) = (dcf.path().to_string(), readable.len() - i);
                let other_device = Vec::new();
                return Ok(Diff { node, file, same, differences, interrupted: true, not_compared, other_device });
            }
            Err(e) => return Err(e),
        };
        let (name, file) = (dcf.eds.dict.display_name(entry.addr).unwrap_or_default(), show(entry, want));
        differences.push(Difference { object: entry.addr, name, device, file });
    }
    // Last, so that a comparison stopped part-way has compared all it could: whether the
    // file is for this kind of device at all (config apply refuses one that is not).
    let (file, not_compared) = (dcf.path().to_string(), 0);
    let (interrupted, other_device) = match identity_differences(bus, node, dcf, timeout) {
        Err(e) if e.is_interrupted() => (true, Vec::new()),
        other => (false, other?),
    };
    Ok(Diff { node, file, same, differences, interrupted, not_compared, other_device })
}

mod apply;
mod dcf;
mod order;
pub(crate) mod report;
pub use apply::*;
pub use dcf::Dcf;
use dcf::{identity_differences, node_dictionary, read_one, show, Wanted};
pub(crate) use order::plan;
pub use report::{Action, Change, CutWrites, Difference, Fix, Incomplete, LeftIn, Outcome, ReadBack};

#[cfg(test)]
mod tests {
    use super::dcf::fit;
    use super::*;
    use crate::od::builtin;

    #[test]
    fn a_pdo_mapping_is_changed_the_cia_301_way() {
        let (cob, count, entry1, event) =
            (ObjAddr::new(0x1800, 1), ObjAddr::new(0x1A00, 0), ObjAddr::new(0x1A00, 1), ObjAddr::new(0x1800, 5));
        let mut changes = BTreeMap::new();
        changes.insert(entry1, 0x6064_0020u32.to_le_bytes().to_vec());
        changes.insert(event, 20u16.to_le_bytes().to_vec());
        let current = |a: ObjAddr| match (a.index, a.sub) {
            (0x1800, 1) => Some(0x185u32.to_le_bytes().to_vec()),
            (0x1A00, 0) => Some(vec![2]),
            _ => None,
        };
        let steps: Vec<(ObjAddr, Vec<u8>, &str)> =
            plan(&changes, &current).into_iter().map(|s| (s.addr, s.value, s.interim)).collect();
        assert_eq!(
            steps,
            [
                (event, vec![20, 0], ""),
                (cob, 0x8000_0185u32.to_le_bytes().to_vec(), "PDO made invalid"),
                (count, vec![0], "mapping count 0"),
                (entry1, 0x6064_0020u32.to_le_bytes().to_vec(), ""),
                (count, vec![2], "mapping count back"),
                (cob, 0x185u32.to_le_bytes().to_vec(), "PDO valid again"),
            ]
        );
    }

    #[test]
    fn answers_are_fitted_to_the_entrys_type() {
        let entry = |dtype| Entry { dtype, ..builtin::dictionary(None).get(ObjAddr::new(0x1017, 0)).unwrap().clone() };
        // An EPOS2's ReadObject: four bytes for a UNSIGNED16.
        assert_eq!(fit(&entry(DataType::U16), vec![0x64, 0, 0xAA, 0xBB]), [0x64, 0]);
        // A device keeping an INTEGER32 in one byte: the same number, sign-extended.
        assert_eq!(fit(&entry(DataType::I32), vec![0xFE]), [0xFE, 0xFF, 0xFF, 0xFF]);
        assert_eq!(fit(&entry(DataType::U32), vec![0x05]), [5, 0, 0, 0]);
    }
}
