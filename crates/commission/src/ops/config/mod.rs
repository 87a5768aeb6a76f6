//! A node's configuration as a DCF (CiA 306): read into one ([`dump`]), compared with one
//! ([`diff`]), and made to match one ([`apply`]) — writing only what differs, in a safe
//! order, with what happened to each object in the report.

use super::progress::Progress;
use super::sdo_options::sized;
use super::values::le_u32;
use crate::bus::{Bus, SdoOptions};
use crate::cancel::Cancel;
use crate::canopen::{abort, DataType, ObjAddr};
use crate::error::{Error, Result};
use crate::od::eds::{self, Eds, Header};
use crate::od::xdd;
use crate::od::{builtin, names, Dictionary, Entry, Init};
use crate::ops::event::Notice;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::time::Duration;

/// A DCF: the values a device is to hold (its `ParameterValue`s), with their dictionary.
#[derive(Debug, Clone)]
pub struct Dcf {
    /// The device description: its objects, each with the value the DCF gives (`ParameterValue`).
    pub(crate) eds: Eds,
}

impl Dcf {
    /// The vendor-ID and product code the file is for: `[DeviceInfo]`, else its 0x1018
    /// values; 0 where it does not say.
    pub fn identity(&self) -> (u32, u32) {
        let part = |key: &str, addr: ObjAddr| {
            let from_value = || match self.eds.values.get(&addr) {
                Some(crate::od::Init::Bytes(b)) => Some(super::values::le_u32(b)),
                _ => None,
            };
            self.info_number(key).filter(|v| *v != 0).or_else(from_value).unwrap_or(0)
        };
        (part("vendornumber", ObjAddr::VENDOR_ID), part("productnumber", ObjAddr::PRODUCT_CODE))
    }

    /// A number of its `[DeviceInfo]` (`key` in lower case).
    pub(crate) fn info_number(&self, key: &str) -> Option<u32> {
        self.eds.info.get(key).and_then(|v| eds::parse_int(v)).and_then(|v| u32::try_from(v).ok())
    }

    /// Read a DCF file; an unreadable one is a usage error citing file:line.
    pub fn read(path: &Path) -> Result<Dcf> {
        let eds = crate::od::read_description(path)?;
        Ok(Dcf { eds })
    }

    /// A DCF's text; `name` stands for its file in messages.
    pub fn parse(bytes: &[u8], name: &str) -> Result<Dcf> {
        let eds = crate::od::parse_description(bytes, name)?;
        Ok(Dcf { eds })
    }

    /// The file's name as given.
    pub fn path(&self) -> &str {
        &self.eds.path
    }

    /// Objects the file describes in a way canctl passes over, with file:line.
    pub fn warnings(&self) -> &[crate::od::lint::Warning] {
        &self.eds.warnings
    }

    /// The values for `node`, with their dictionary entries; `$NODEID` means that node.
    fn values(&self, node: u8) -> Result<Vec<Wanted>> {
        // An EDS with an object left out still names the rest; a DCF so read would be
        // applied (or compared) without what it left out: refused, with the first reason.
        let errors: Vec<&crate::od::lint::Warning> =
            self.eds.warnings.iter().filter(|w| w.severity == crate::od::lint::Severity::Error).collect();
        if let Some(first) = errors.first() {
            let (first, file) = (Box::new((*first).clone()), self.path().to_string());
            return Err(Error::DcfNotReadWhole { first, file, errors: errors.len() });
        }
        let (dict, values) = (&self.eds.dict, self.eds.values.iter());
        let out: Vec<Wanted> =
            values.filter_map(|(addr, init)| dict.get(*addr).map(|e| (e.clone(), e.value_for(init, node)))).collect();
        if out.is_empty() {
            return Err(Error::NotADcf { file: self.path().to_string() });
        }
        Ok(out)
    }
}

/// A DCF value for a node, with its dictionary entry.
type Wanted = (Entry, Vec<u8>);

/// Bytes as the entry holds them: an EPOS2's ReadObject answers four bytes for any short
/// object, the rest meaningless; and a device may keep an integer in fewer bytes than the
/// dictionary says (the MH sensor's 0x1002 is UNSIGNED8), which is the same number.
fn fit(entry: &Entry, mut bytes: Vec<u8>) -> Vec<u8> {
    if let Some(size) = entry.dtype.size() {
        if let (Some((lo, _)), Some(&last)) = (entry.dtype.int_range(), bytes.last()) {
            let fill = if lo < 0 && last & 0x80 != 0 { 0xFF } else { 0 };
            bytes.resize(bytes.len().max(size), fill);
        }
        bytes.truncate(size);
    }
    bytes
}

fn show(entry: &Entry, bytes: &[u8]) -> String {
    eds::format_value(&Init::Bytes(bytes.to_vec()), entry.dtype)
}

fn opts(timeout: Duration, dtype: DataType) -> SdoOptions {
    SdoOptions { max_upload: super::sdo_options::upload_limit(Some(dtype)), ..sized(timeout, dtype.size()) }
}

fn read_one(bus: &mut dyn Bus, node: u8, e: &Entry, timeout: Duration) -> Result<Vec<u8>> {
    bus.sdo_upload(node, e.addr, &opts(timeout, e.dtype)).map(|b| fit(e, b))
}

/// Where the device's vendor-ID and product code are not the ones the file names, in words.
fn identity_differences(bus: &mut dyn Bus, node: u8, dcf: &Dcf, timeout: Duration) -> Result<Vec<String>> {
    let (vendor, product) = dcf.identity();
    let parts = super::node::Node::new(bus, node, timeout).compare_identity(vendor, product)?;
    Ok(parts
        .iter()
        .filter(|p| !p.matches())
        .map(|p| format!("{} {} on node {node}, 0x{:08X} in the file", p.what, p.device_text(), p.file))
        .collect())
}

/// A value the target's dictionary does not allow, refused before anything is written.
fn out_of_range(entry: &Entry, value: &[u8], limits: crate::od::OutsideLimits, source: &str) -> Error {
    let crate::od::OutsideLimits { low, high, .. } = limits;
    Error::OutOfRange { object: entry.addr, value: show(entry, value), low, high, dictionary: source.to_string() }
}

/// The dictionary a node is judged by, with the name of its source: the one given (an EDS
/// bound to the node), else the built-in one for the node's profile (0x1000), which decides
/// what 0x6000 and the like mean (DS401/402/406).
fn node_dictionary(
    bus: &mut dyn Bus,
    node: u8,
    given: Option<(&Dictionary, &str)>,
    timeout: Duration,
) -> Result<(Dictionary, String)> {
    if let Some((d, source)) = given {
        return Ok((d.clone(), source.to_string()));
    }
    let device_type = builtin::dictionary(None).get(ObjAddr::DEVICE_TYPE).expect("0x1000");
    let profile = le_u32(&read_one(bus, node, device_type, timeout)?) as u16;
    Ok((builtin::dictionary(Some(profile)).clone(), format!("the built-in dictionary (profile {profile})")))
}

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

/// One write of the plan.
pub(crate) struct Step {
    pub addr: ObjAddr,
    pub value: Vec<u8>,
    /// An intermediate write of the PDO sequence, not a value of the file.
    pub interim: &'static str,
    /// The PDO (communication and mapping index) whose change this write is part of: the
    /// device holds a usable PDO only before the first and after the last of them.
    pub pdo: Option<(u16, u16)>,
}

impl Step {
    fn new(addr: ObjAddr, value: Vec<u8>, interim: &'static str) -> Step {
        Step { addr, value, interim, pdo: None }
    }
}

/// The communication and mapping parameter indexes of the PDO an index belongs to.
fn pdo_indices(index: u16) -> Option<(u16, u16)> {
    match index {
        0x1400..=0x15FF | 0x1800..=0x19FF => Some((index, index + 0x200)),
        0x1600..=0x17FF | 0x1A00..=0x1BFF => Some((index - 0x200, index)),
        _ => None,
    }
}

/// Writes in a safe order: plain objects first; then per PDO whose COB-ID or mapping
/// changes: COB-ID invalid, mapping count 0, entries, count, other parameters, COB-ID.
pub(crate) fn plan(changes: &BTreeMap<ObjAddr, Vec<u8>>, current: &dyn Fn(ObjAddr) -> Option<Vec<u8>>) -> Vec<Step> {
    let mut steps: Vec<Step> = Vec::new();
    let mut pdos: BTreeSet<(u16, u16)> = BTreeSet::new();
    for (addr, value) in changes {
        match pdo_indices(addr.index) {
            Some((comm, map)) if addr.index == map || addr.sub == 1 => {
                pdos.insert((comm, map));
            }
            _ => steps.push(Step::new(*addr, value.clone(), "")),
        }
    }
    // Plain objects of a PDO comm record (transmission type, timers) already went above.
    for (comm, map) in pdos {
        let first = steps.len();
        let cob = ObjAddr::new(comm, 1);
        let cob_now = current(cob).map(|v| le_u32(&v));
        if let Some(c) = cob_now.filter(|c| c & 0x8000_0000 == 0) {
            steps.push(Step::new(cob, (c | 0x8000_0000).to_le_bytes().to_vec(), "PDO made invalid"));
        }
        let map_changes: Vec<(&ObjAddr, &Vec<u8>)> = changes.iter().filter(|(a, _)| a.index == map).collect();
        if !map_changes.is_empty() {
            let count = ObjAddr::new(map, 0);
            steps.push(Step::new(count, vec![0], "mapping count 0"));
            for (a, v) in map_changes.iter().filter(|(a, _)| a.sub > 0) {
                steps.push(Step::new(**a, (*v).clone(), ""));
            }
            let final_count = changes.get(&count).cloned().or_else(|| current(count)).unwrap_or(vec![0]);
            let interim = if changes.contains_key(&count) { "" } else { "mapping count back" };
            steps.push(Step::new(count, final_count, interim));
        }
        let final_cob = changes.get(&cob).cloned().or_else(|| cob_now.map(|c| c.to_le_bytes().to_vec()));
        if let Some(v) = final_cob {
            steps.push(Step::new(cob, v, if changes.contains_key(&cob) { "" } else { "PDO valid again" }));
        }
        for step in &mut steps[first..] {
            step.pdo = Some((comm, map));
        }
    }
    steps
}

mod apply;
pub(crate) mod report;
pub use apply::*;
pub use report::{Action, Change, CutWrites, Difference, Fix, Incomplete, LeftIn, Outcome, ReadBack};

#[cfg(test)]
mod tests {
    use super::*;

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
