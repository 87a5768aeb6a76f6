//! A node's configuration as a DCF (CiA 306): read into one ([`dump`]), compared with one
//! ([`diff`]), and made to match one ([`apply`]) — writing only what differs, in a safe
//! order, with what happened to each object in the report.

use super::{as_text, le_u32, sized, Progress};
use crate::bus::{Bus, SdoOptions};
use crate::cancel::Cancel;
use crate::canopen::{abort, DataType, ObjAddr};
use crate::error::{Error, Result};
use crate::od::eds::{self, Eds, Header};
use crate::od::xdd;
use crate::od::{builtin, names, Dictionary, Entry, Init};
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::time::Duration;

/// A DCF: the values a device is to hold (its `ParameterValue`s), with their dictionary.
#[derive(Debug, Clone)]
pub struct Dcf {
    pub eds: Eds,
}

impl Dcf {
    /// The vendor-ID and product code the file is for: `[DeviceInfo]`, else its 0x1018
    /// values; 0 where it does not say.
    pub fn identity(&self) -> (u32, u32) {
        let part = |key: &str, sub: u8| {
            let from_info = self.eds.info.get(key).and_then(|v| eds::parse_int(v)).and_then(|v| u32::try_from(v).ok());
            let from_value = || match self.eds.values.get(&ObjAddr::new(0x1018, sub)) {
                Some(crate::od::Init::Bytes(b)) => Some(super::le_u32(b)),
                _ => None,
            };
            from_info.filter(|v| *v != 0).or_else(from_value).unwrap_or(0)
        };
        (part("vendornumber", 1), part("productnumber", 2))
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
            return Err(Error::Usage(format!(
                "{first}; {} has {} error(s) against CiA 306, so its values are not all read: nothing is compared \
                 or written (canctl config check {} lists them)",
                self.path(),
                errors.len(),
                self.path()
            )));
        }
        let mut out = Vec::new();
        for (addr, init) in &self.eds.values {
            let Some(entry) = self.eds.dict.get(*addr) else { continue };
            let value = Entry { default: init.clone(), ..entry.clone() }.default_for(node);
            out.push((entry.clone(), value));
        }
        if out.is_empty() {
            return Err(Error::Usage(format!(
                "{} has no ParameterValue: it is an EDS, not a DCF (canctl config dump makes one)",
                self.path()
            )));
        }
        Ok(out)
    }

    fn name_of(&self, addr: ObjAddr) -> String {
        self.eds.dict.display_name(addr).unwrap_or_default()
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
    SdoOptions { max_upload: super::upload_limit(Some(dtype)), ..sized(timeout, dtype.size()) }
}

fn read_one(bus: &mut dyn Bus, node: u8, e: &Entry, timeout: Duration) -> Result<Vec<u8>> {
    bus.sdo_upload(node, e.addr, &opts(timeout, e.dtype)).map(|b| fit(e, b))
}

/// A DCF made for one kind of device is not written into another: the vendor-ID and
/// product code the file names must be the device's (exit 6 otherwise, before anything is
/// written). A file that names neither is applied anywhere.
fn check_identity(bus: &mut dyn Bus, node: u8, dcf: &Dcf, timeout: Duration) -> Result<()> {
    let differ = identity_differences(bus, node, dcf, timeout)?;
    if differ.is_empty() {
        return Ok(());
    }
    Err(Error::OtherDevice { file: dcf.path().to_string(), differences: differ })
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
fn out_of_range(entry: &Entry, value: &[u8], source: &str) -> Error {
    let shown = show(entry, value);
    let (lo, hi) = entry.range.expect("only a ranged entry refuses");
    Error::Usage(format!(
        "{shown} is outside the range of {}: use {lo} to {hi} ({source}); nothing was written",
        entry.addr
    ))
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
    let device_type = builtin::dictionary(None).get(ObjAddr::new(0x1000, 0)).expect("0x1000");
    let profile = le_u32(&read_one(bus, node, device_type, timeout)?) as u16;
    Ok((builtin::dictionary(Some(profile)).clone(), format!("the built-in dictionary (profile {profile})")))
}

/// A node's objects, read into a DCF.
#[derive(Debug, Serialize)]
pub struct Dump {
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
    /// The DCF, Latin-1 as CiA 306 has it (or the XDC, UTF-8 XML, from [`dump_as`]).
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
    Dcf,
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
            Err(Error::SdoAbort { code, .. }) => progress.note(&format!("note: {}: {}", e.addr, abort::meaning(code))),
            Err(err) => return Err(err),
        }
        let (name, kind) = dict.object_info(e.addr.index).expect("declared object");
        present.object(e.addr.index, name, kind);
        present.insert((*e).clone());
    }
    progress.finish();
    let identity = |sub| values.get(&ObjAddr::new(0x1018, sub)).map_or(0, |v: &Vec<u8>| le_u32(v));
    let name = values
        .get(&ObjAddr::new(0x1008, 0))
        .map(|v| String::from_utf8_lossy(v).trim_end_matches('\0').to_string())
        .unwrap_or_default();
    let header = Header {
        file_name: file_name.to_string(),
        description: format!("node {node} on {}, read by canctl; objects from {source}", bus.describe()),
        vendor_name: String::new(),
        vendor_number: identity(1),
        product_name: name,
        product_number: identity(2),
        revision: identity(3),
        node_id: Some(node),
    };
    // A value no DCF can hold (a newline in a string, say) is left out, and said so.
    let (text, file) = match form {
        FileForm::Dcf => (eds::parameter_text as fn(&Entry, &[u8], Option<u8>) -> _, "DCF"),
        FileForm::Xdc => (xdd::actual_value_text as fn(&Entry, &[u8], Option<u8>) -> _, "XDC"),
    };
    values.retain(|addr, v| match present.get(*addr).map(|e| text(e, v, Some(node))) {
        Some(Err(why)) => {
            progress.note(&format!("note: {addr} left out of the {file}: {why}"));
            false
        }
        _ => true,
    });
    let dcf = match form {
        FileForm::Dcf => eds::write_bytes(&present, Some(&values), &header),
        FileForm::Xdc => xdd::write_bytes(&present, Some(&values), &header),
    }
    .map_err(|e| Error::Usage(e.to_string()))?;
    Ok(Dump { node, objects: values.len(), interrupted: false, wanted: wanted.len(), source, dcf })
}

/// Where a node differs from a DCF.
#[derive(Debug, Serialize)]
pub struct Diff {
    pub node: u8,
    pub file: String,
    /// Objects that match.
    pub same: usize,
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

#[derive(Debug, Serialize)]
pub struct Difference {
    #[serde(serialize_with = "as_text")]
    pub object: ObjAddr,
    pub name: String,
    /// The device's value, or why it has none.
    pub device: String,
    pub file: String,
}

impl Diff {
    /// A verification error when anything differs; interrupted, the interruption.
    pub fn check(&self) -> Result<()> {
        if self.interrupted {
            return Err(Error::Interrupted);
        }
        if self.differences.is_empty() {
            return Ok(());
        }
        Err(Error::Differs { node: self.node, file: self.file.clone(), count: self.differences.len() })
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
        differences.push(Difference {
            object: entry.addr,
            name: dcf.name_of(entry.addr),
            device,
            file: show(entry, want),
        });
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
            _ => steps.push(Step { addr: *addr, value: value.clone(), interim: "", pdo: None }),
        }
    }
    // Plain objects of a PDO comm record (transmission type, timers) already went above.
    for (comm, map) in pdos {
        let first = steps.len();
        let cob = ObjAddr::new(comm, 1);
        let cob_now = current(cob).map(|v| le_u32(&v));
        if let Some(c) = cob_now.filter(|c| c & 0x8000_0000 == 0) {
            steps.push(Step {
                addr: cob,
                value: (c | 0x8000_0000).to_le_bytes().to_vec(),
                interim: "PDO made invalid",
                pdo: None,
            });
        }
        let map_changes: Vec<(&ObjAddr, &Vec<u8>)> = changes.iter().filter(|(a, _)| a.index == map).collect();
        if !map_changes.is_empty() {
            let count = ObjAddr::new(map, 0);
            steps.push(Step { addr: count, value: vec![0], interim: "mapping count 0", pdo: None });
            for (a, v) in map_changes.iter().filter(|(a, _)| a.sub > 0) {
                steps.push(Step { addr: **a, value: (*v).clone(), interim: "", pdo: None });
            }
            let final_count = changes.get(&count).cloned().or_else(|| current(count)).unwrap_or(vec![0]);
            steps.push(Step {
                addr: count,
                value: final_count,
                interim: if changes.contains_key(&count) { "" } else { "mapping count back" },
                pdo: None,
            });
        }
        let final_cob = changes.get(&cob).cloned().or_else(|| cob_now.map(|c| c.to_le_bytes().to_vec()));
        if let Some(v) = final_cob {
            steps.push(Step {
                addr: cob,
                value: v,
                interim: if changes.contains_key(&cob) { "" } else { "PDO valid again" },
                pdo: None,
            });
        }
        for step in &mut steps[first..] {
            step.pdo = Some((comm, map));
        }
    }
    steps
}

/// How to apply a DCF.
#[derive(Clone, Debug)]
pub struct ApplyOptions {
    /// How long to wait for each answer.
    pub timeout: Duration,
    /// Plan and report, write nothing.
    pub dry_run: bool,
    /// Read every written object back.
    pub verify: bool,
    /// Store the parameters (0x1010:1) when everything is written (and verified).
    pub store: bool,
    /// How long the device may take to store.
    pub store_timeout: Duration,
    /// Apply even when the device's vendor-ID or product code is not the file's.
    pub force: bool,
    /// The target's dictionary, with the name of its source (an EDS bound to the node); by
    /// default the built-in one for the node's profile. Writes are judged by it: ranges
    /// before anything is written, and in a dry run what the device will refuse.
    pub dictionary: Option<(Dictionary, String)>,
    /// Set when the user asks to stop (SIGINT, SIGTERM, Ctrl-C): looked at between SDO
    /// transfers, never in the middle of one. A PDO change under way is then rolled back.
    pub interrupted: Cancel,
}

impl ApplyOptions {
    pub fn new(timeout: Duration) -> ApplyOptions {
        ApplyOptions {
            timeout,
            dry_run: false,
            verify: false,
            store: false,
            store_timeout: Duration::from_secs(5),
            force: false,
            dictionary: None,
            interrupted: Cancel::new(),
        }
    }
}

/// What applying a DCF did, object by object. A failure part-way still gives the report:
/// [`Applied::outcome`] turns it into the error.
#[derive(Debug, Serialize)]
pub struct Applied {
    pub node: u8,
    pub file: String,
    pub dry_run: bool,
    pub objects: Vec<Change>,
    /// Whether the parameters were stored (0x1010:1).
    pub stored: bool,
    /// The write that failed; nothing after it was written.
    #[serde(skip)]
    pub failure: Option<Error>,
    /// When the failure is an object the device lacks: the objects of the device's
    /// dictionary nearest to it.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub did_you_mean: Vec<String>,
    /// What was written, in order.
    #[serde(skip)]
    pub written: Vec<ObjAddr>,
    /// Objects that read back other values than written.
    #[serde(skip)]
    pub mismatch: Vec<ObjAddr>,
    /// The run was stopped on request (SIGINT, SIGTERM) at a point between transfers.
    pub interrupted: bool,
    /// PDOs whose change was under way when the run stopped, put back as they were
    /// (their previous mapping and COB-ID): `TPDO1 (0x1800, 0x1A00)`.
    pub rolled_back: Vec<String>,
    /// When putting a PDO back failed: the writes that would, in this order.
    pub to_fix: Vec<Fix>,
    /// What the device holds now, when the run did not finish: a sentence for people.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub state: Option<String>,
}

/// A write that would bring an object back to its value before the run.
#[derive(Debug, Serialize)]
pub struct Fix {
    #[serde(serialize_with = "as_text")]
    pub object: ObjAddr,
    /// The value it had before the run, as a DCF writes it; `None` when unknown.
    pub value: Option<String>,
}

/// One object: its value before, the value wanted, and what happened.
#[derive(Debug, Serialize)]
pub struct Change {
    #[serde(serialize_with = "as_text")]
    pub object: ObjAddr,
    pub name: String,
    pub old: String,
    pub new: String,
    /// What happened to it; serialised as its sentence (`written, verified`).
    #[serde(serialize_with = "as_text")]
    pub result: Outcome,
}

/// What a run did, or would do, with one object.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Action {
    /// Written.
    Written,
    /// The write failed with this error.
    Failed(String),
    /// Not written: an earlier write failed.
    NotWritten,
    /// Not written: the user stopped the run first.
    NotWrittenInterrupted,
    /// A dry run would write it.
    WouldWrite,
    /// A dry run would not get this far: an earlier write would fail.
    WouldNotBeWritten,
    /// A dry run: the device would refuse it with this abort code.
    WouldBeRefused(u32),
    /// A dry run: the object is read-only in the dictionary named.
    WouldBeRefusedReadOnly(String),
    /// The device does not have the object (abort code), and it is not writable anyway.
    NotOnDevice(u32),
    /// The file's value differs from the device's, but the device's object cannot be
    /// written (its access type, such as `ro`).
    ReadOnlyOnDevice(&'static str),
}

/// The read-back of a written value.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ReadBack {
    /// It reads back as written.
    Verified,
    /// It reads back as this other value.
    Differs(String),
}

/// What happened to one object of a run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Outcome {
    /// The write.
    pub action: Action,
    /// Why this write is a step on the way (a PDO's COB-ID made invalid first); `None` for
    /// the write of the value the file holds.
    pub interim: Option<&'static str>,
    /// A write that puts a PDO back after a change of it failed half-way.
    pub rollback: bool,
    /// The read-back, when one was made.
    pub read_back: Option<ReadBack>,
}

impl Outcome {
    fn new(action: Action) -> Outcome {
        Outcome { action, interim: None, rollback: false, read_back: None }
    }

    /// The write of the file's own value (not a step on the way, not a rollback), which is
    /// what a verification reads back.
    fn is_final(&self) -> bool {
        !self.rollback
            && self.interim.is_none()
            && !matches!(self.action, Action::NotOnDevice(_) | Action::NotWrittenInterrupted)
    }
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.action {
            Action::Written => write!(f, "written")?,
            Action::Failed(e) => write!(f, "failed: {e}")?,
            Action::NotWritten => write!(f, "not written")?,
            Action::NotWrittenInterrupted => write!(f, "not written (interrupted)")?,
            Action::WouldWrite => write!(f, "would write")?,
            Action::WouldNotBeWritten => write!(f, "would not be written")?,
            Action::WouldBeRefused(code) => write!(f, "would be refused: {}", abort::meaning(*code))?,
            Action::WouldBeRefusedReadOnly(source) => write!(f, "would be refused: read only in {source}")?,
            Action::NotOnDevice(code) => write!(f, "not on the device ({})", abort::meaning(*code))?,
            Action::ReadOnlyOnDevice(access) => write!(f, "{access} on the device: not written")?,
        }
        if self.rollback {
            write!(f, " (rollback)")?;
        }
        if let Some(interim) = &self.interim {
            write!(f, " ({interim})")?;
        }
        match &self.read_back {
            Some(ReadBack::Verified) => write!(f, ", verified"),
            Some(ReadBack::Differs(got)) => write!(f, ", reads back {got}"),
            None => Ok(()),
        }
    }
}

impl Change {
    fn new(dcf: &Dcf, addr: ObjAddr, old: Option<&[u8]>, new: &[u8], result: Outcome) -> Change {
        let entry = dcf.eds.dict.get(addr).or_else(|| builtin::dictionary(None).get(addr));
        let fmt = |b: &[u8]| entry.map_or_else(|| crate::canopen::types::hex(b), |e| show(e, b));
        let name = dcf
            .eds
            .dict
            .display_name(addr)
            .or_else(|| builtin::dictionary(None).display_name(addr))
            .unwrap_or_default();
        Change { object: addr, name, old: old.map_or("-".to_string(), fmt), new: fmt(new), result }
    }
}

impl Applied {
    /// The error that ended the run, else a verification error when a value did not read
    /// back as written.
    pub fn outcome(self) -> Result<()> {
        if let Some(e) = self.failure {
            if self.did_you_mean.is_empty() {
                return Err(e);
            }
            return Err(e.with_hint(format!("; did you mean {}?", self.did_you_mean.join(", "))));
        }
        if !self.mismatch.is_empty() {
            return Err(Error::ReadBackMany { node: self.node, objects: self.mismatch });
        }
        Ok(())
    }

    /// For a run that did not finish: what was written, what was not, what was put back,
    /// and the state the device is left in, as sentences for people.
    pub fn summary(&self) -> Vec<String> {
        if !self.interrupted && self.rolled_back.is_empty() && self.to_fix.is_empty() {
            return Vec::new();
        }
        let list = |v: Vec<String>| if v.is_empty() { "nothing".to_string() } else { v.join(", ") };
        let mut out = Vec::new();
        // Interrupted while reading, the state says it all.
        let not_written = |r: &Change| matches!(r.result.action, Action::NotWritten | Action::NotWrittenInterrupted);
        let planned = self.objects.iter().any(|r| r.result.action == Action::Written || not_written(r));
        if self.interrupted && planned {
            let done: Vec<String> = self.written.iter().map(|w| w.to_string()).collect();
            let not: Vec<String> =
                self.objects.iter().filter(|r| not_written(r)).map(|r| r.object.to_string()).collect();
            out.push(format!(
                "interrupted after {} write(s): written {}; not written {}",
                done.len(),
                list(done),
                list(not)
            ));
        }
        for pdo in &self.rolled_back {
            out.push(format!("{pdo}: its change was under way; rolled back to its previous mapping and COB-ID"));
        }
        if !self.to_fix.is_empty() {
            let fixes: Vec<String> = self
                .to_fix
                .iter()
                .map(|f| format!("{} = {}", f.object, f.value.as_deref().unwrap_or("(previous value unknown)")))
                .collect();
            out.push(format!(
                "the rollback did not finish: to put the PDO back, write in this order {} (or run config apply again to finish the change)",
                fixes.join(", ")
            ));
        }
        if let Some(state) = &self.state {
            out.push(state.clone());
        }
        out
    }
}

/// A PDO's name from its communication index: `TPDO1 (0x1800, 0x1A00)`.
fn pdo_name((comm, map): (u16, u16)) -> String {
    let (kind, n) = if comm >= 0x1800 { ("TPDO", comm - 0x1800 + 1) } else { ("RPDO", comm - 0x1400 + 1) };
    format!("{kind}{n} (0x{comm:04X}, 0x{map:04X})")
}

/// The writes of a PDO change under way, and the values its objects had before them.
struct Underway {
    pdo: (u16, u16),
    /// Each object written (or possibly written) so far, with its value before the run.
    before: BTreeMap<ObjAddr, Option<Vec<u8>>>,
}

/// Put a PDO whose change stopped part-way back as it was, in the safe order (it is
/// invalid already: entries, count, COB-ID last). Returns the rows of the writes, and the
/// writes still needed when one failed.
fn roll_back(
    bus: &mut dyn Bus,
    node: u8,
    dcf: &Dcf,
    underway: &Underway,
    device: &mut BTreeMap<ObjAddr, Vec<u8>>,
    timeout: Duration,
) -> (Vec<Change>, Vec<Fix>) {
    let mut back = BTreeMap::new();
    let mut unknown = Vec::new();
    for (addr, before) in &underway.before {
        match before {
            Some(v) if device.get(addr) != Some(v) => {
                back.insert(*addr, v.clone());
            }
            Some(_) => {}
            None => unknown.push(*addr),
        }
    }
    let snapshot = device.clone();
    let steps: Vec<Step> = plan(&back, &|a| snapshot.get(&a).cloned())
        .into_iter()
        .filter(|s| s.interim.is_empty() || snapshot.get(&s.addr) != Some(&s.value))
        .collect();
    let entry_of = |addr: ObjAddr| dcf.eds.dict.get(addr).or_else(|| builtin::dictionary(None).get(addr));
    let shown = |addr: ObjAddr, v: &[u8]| entry_of(addr).map_or_else(|| crate::canopen::types::hex(v), |e| show(e, v));
    let mut rows = Vec::new();
    let mut to_fix: Vec<Fix> = Vec::new();
    for step in &steps {
        if !to_fix.is_empty() {
            to_fix.push(Fix { object: step.addr, value: Some(shown(step.addr, &step.value)) });
            continue;
        }
        let dtype = entry_of(step.addr).map_or(DataType::U32, |e| e.dtype);
        let old = device.get(&step.addr).cloned();
        let action = match bus.sdo_download(node, step.addr, &step.value, &opts(timeout, dtype)) {
            Ok(()) => {
                device.insert(step.addr, step.value.clone());
                Action::Written
            }
            Err(e) => {
                to_fix.push(Fix { object: step.addr, value: Some(shown(step.addr, &step.value)) });
                Action::Failed(e.to_string())
            }
        };
        let result = Outcome { rollback: true, ..Outcome::new(action) };
        rows.push(Change::new(dcf, step.addr, old.as_deref(), &step.value, result));
    }
    to_fix.extend(unknown.into_iter().map(|object| Fix { object, value: None }));
    (rows, to_fix)
}

/// Make `node` match the DCF: every value is checked against the file's ranges before
/// anything is written; only what differs is written, PDOs the CiA 301 way (COB-ID made
/// invalid, mapping count 0, entries, count, COB-ID back); then optionally read back and
/// stored.
pub fn apply(bus: &mut dyn Bus, node: u8, dcf: &Dcf, o: &ApplyOptions) -> Result<Applied> {
    let values = dcf.values(node)?;
    for (entry, value) in &values {
        super::check_range(entry, value)?;
    }
    let stop = || o.interrupted.is_cancelled();
    let unchanged = |rows: Vec<Change>| Applied {
        node,
        file: dcf.path().to_string(),
        dry_run: o.dry_run,
        objects: rows,
        stored: false,
        failure: Some(Error::Interrupted),
        did_you_mean: Vec::new(),
        written: Vec::new(),
        mismatch: Vec::new(),
        interrupted: true,
        rolled_back: Vec::new(),
        to_fix: Vec::new(),
        state: Some(format!("node {node} is as it was: interrupted while reading it, nothing was written")),
    };
    if stop() {
        return Ok(unchanged(Vec::new()));
    }
    if !o.force {
        check_identity(bus, node, dcf, o.timeout)?;
    }
    let given = o.dictionary.as_ref().map(|(d, source)| (d, source.as_str()));
    let (target, target_source) = node_dictionary(bus, node, given, o.timeout)?;
    let mut current: BTreeMap<ObjAddr, Vec<u8>> = BTreeMap::new();
    let mut changes: BTreeMap<ObjAddr, Vec<u8>> = BTreeMap::new();
    let mut rows: Vec<Change> = Vec::new();
    // Objects the device says it does not have: a write there is refused, and a dry run
    // says so instead of promising it.
    let mut absent: BTreeMap<ObjAddr, u32> = BTreeMap::new();
    for (entry, want) in &values {
        if stop() {
            return Ok(unchanged(rows));
        }
        let now = if entry.access.readable() {
            match read_one(bus, node, entry, o.timeout) {
                Ok(v) => Some(v),
                Err(Error::SdoAbort { code, .. }) if !entry.access.writable() => {
                    rows.push(Change::new(dcf, entry.addr, None, want, Outcome::new(Action::NotOnDevice(code))));
                    continue;
                }
                Err(e @ Error::SdoAbort { code, .. }) => {
                    if super::node::is_missing(&e) {
                        absent.insert(entry.addr, code);
                    }
                    None
                }
                Err(e) => return Err(e),
            }
        } else {
            None
        };
        if let Some(v) = &now {
            current.insert(entry.addr, v.clone());
        }
        if now.as_ref() == Some(want) {
            continue;
        }
        if !entry.access.writable() {
            let result = Outcome::new(Action::ReadOnlyOnDevice(entry.access.name()));
            rows.push(Change::new(dcf, entry.addr, now.as_deref(), want, result));
            continue;
        }
        changes.insert(entry.addr, want.clone());
    }
    // The PDO sequence needs the COB-IDs and mapping counts of the PDOs it touches.
    for (comm, map) in changes.keys().filter_map(|a| pdo_indices(a.index)).collect::<BTreeSet<_>>() {
        if stop() {
            return Ok(unchanged(rows));
        }
        for addr in [ObjAddr::new(comm, 1), ObjAddr::new(map, 0)] {
            if let std::collections::btree_map::Entry::Vacant(slot) = current.entry(addr) {
                if let Ok(v) = bus.sdo_upload(node, addr, &SdoOptions::new(o.timeout)) {
                    slot.insert(v);
                }
            }
        }
    }
    // The device will refuse a value outside its range: say so before writing anything.
    for (addr, value) in &changes {
        if let Some(entry) = target.get(*addr).filter(|e| e.dtype.size() == Some(value.len())) {
            super::check_range(entry, value).map_err(|_| out_of_range(entry, value, &target_source))?;
        }
    }
    let steps = plan(&changes, &|addr| current.get(&addr).cloned());
    let entry_of = |addr: ObjAddr| dcf.eds.dict.get(addr).or_else(|| builtin::dictionary(None).get(addr));
    let mut failure: Option<Error> = None;
    let mut interrupted = false;
    let mut written: Vec<ObjAddr> = Vec::new();
    // What the device holds, as far as read and written.
    let mut device = current.clone();
    let mut underway: Option<Underway> = None;
    let mut rollback_rows = Vec::new();
    let mut rolled_back = Vec::new();
    let mut to_fix = Vec::new();
    for (i, step) in steps.iter().enumerate() {
        if !o.dry_run && failure.is_none() && stop() {
            interrupted = true;
            failure = Some(Error::Interrupted);
        }
        let dtype = entry_of(step.addr).map_or(DataType::U32, |e| e.dtype);
        let action = if o.dry_run && failure.is_some() {
            Action::WouldNotBeWritten
        } else if let (true, Some(&code)) = (o.dry_run, absent.get(&step.addr)) {
            failure = Some(Error::SdoAbort { node, obj: step.addr, code });
            Action::WouldBeRefused(code)
        } else if o.dry_run && target.get(step.addr).is_some_and(|e| !e.access.writable()) {
            failure = Some(Error::SdoAbort { node, obj: step.addr, code: abort::READ_ONLY });
            Action::WouldBeRefusedReadOnly(target_source.to_string())
        } else if o.dry_run {
            Action::WouldWrite
        } else if interrupted {
            Action::NotWrittenInterrupted
        } else if failure.is_some() {
            Action::NotWritten
        } else {
            // The PDO this write belongs to is unusable from now until its last write.
            if let Some(pdo) = step.pdo {
                let u = underway.get_or_insert_with(|| Underway { pdo, before: BTreeMap::new() });
                u.before.entry(step.addr).or_insert_with(|| current.get(&step.addr).cloned());
            }
            match bus.sdo_download(node, step.addr, &step.value, &opts(o.timeout, dtype)) {
                Ok(()) => {
                    written.push(step.addr);
                    device.insert(step.addr, step.value.clone());
                    if steps.get(i + 1).is_none_or(|next| next.pdo != step.pdo) {
                        underway = None;
                    }
                    Action::Written
                }
                Err(e) => {
                    // Refused or unanswered: whether the device took the value is not
                    // known, so a rollback writes the old one back in any case.
                    device.remove(&step.addr);
                    let failed = Action::Failed(e.to_string());
                    failure = Some(e);
                    failed
                }
            }
        };
        let interim = (!step.interim.is_empty()).then_some(step.interim);
        let result = Outcome { interim, ..Outcome::new(action) };
        rows.push(Change::new(dcf, step.addr, current.get(&step.addr).map(|v| v.as_slice()), &step.value, result));
        // Stopped inside a PDO change: put the PDO back before anything else.
        if failure.is_some() && !o.dry_run {
            if let Some(u) = underway.take() {
                let (r, fix) = roll_back(bus, node, dcf, &u, &mut device, o.timeout);
                rollback_rows = r;
                if fix.is_empty() {
                    rolled_back.push(pdo_name(u.pdo));
                }
                to_fix = fix;
            }
        }
    }
    // An object the device lacks: the nearest ones it may have meant, from its own
    // dictionary (not the file's, which may describe another kind of device).
    let did_you_mean = match &failure {
        Some(e @ Error::SdoAbort { obj, code, .. }) if super::node::is_missing(e) => {
            names::near(&target, *obj, *code == abort::NO_OBJECT)
        }
        _ => Vec::new(),
    };
    rows.extend(rollback_rows);
    let mut mismatch = Vec::new();
    if o.verify && failure.is_none() && !o.dry_run {
        for (addr, want) in &changes {
            let Some(entry) = entry_of(*addr) else { continue };
            if !entry.access.readable() {
                continue;
            }
            if stop() {
                interrupted = true;
                failure = Some(Error::Interrupted);
                break;
            }
            let got = read_one(bus, node, entry, o.timeout)?;
            let row =
                rows.iter_mut().rev().find(|r| r.object == *addr && r.result.is_final()).expect("row of a change");
            if got == *want {
                row.result.read_back = Some(ReadBack::Verified);
            } else {
                row.result.read_back = Some(ReadBack::Differs(show(entry, &got)));
                mismatch.push(*addr);
            }
        }
    }
    if o.store && failure.is_none() && mismatch.is_empty() && !o.dry_run && stop() {
        interrupted = true;
        failure = Some(Error::Interrupted);
    }
    let stored = if o.store && failure.is_none() && mismatch.is_empty() && !o.dry_run {
        let t = super::store::Timeouts { answer: o.timeout, write: o.store_timeout };
        super::store::store(bus, node, super::store::Class::All, t)?;
        true
    } else {
        false
    };
    let state = (!o.dry_run && failure.is_some())
        .then(|| left_in(node, &changes, &device, &current, !rolled_back.is_empty(), !to_fix.is_empty(), o.store));
    Ok(Applied {
        node,
        file: dcf.path().to_string(),
        dry_run: o.dry_run,
        objects: rows,
        stored,
        failure,
        did_you_mean,
        written,
        mismatch,
        interrupted,
        rolled_back,
        to_fix,
        state,
    })
}

/// The state a run that did not finish leaves the device in, in a sentence.
fn left_in(
    node: u8,
    changes: &BTreeMap<ObjAddr, Vec<u8>>,
    device: &BTreeMap<ObjAddr, Vec<u8>>,
    before: &BTreeMap<ObjAddr, Vec<u8>>,
    rolled_back: bool,
    broken: bool,
    store: bool,
) -> String {
    let new: Vec<String> =
        changes.iter().filter(|(a, v)| device.get(a) == Some(v)).map(|(a, _)| a.to_string()).collect();
    // An intermediate value left behind (a COB-ID made invalid, a count of 0).
    let interim = device.iter().any(|(a, v)| before.get(a).is_some_and(|b| b != v) && changes.get(a) != Some(v));
    let mut s = if new.is_empty() && !interim {
        format!("node {node} is as it was before the run")
    } else if new.is_empty() {
        format!("node {node} holds none of the file's values")
    } else {
        format!(
            "node {node} holds the file's values for {} of {} object(s) ({}), its previous values for the rest",
            new.len(),
            changes.len(),
            new.join(", ")
        )
    };
    if broken || interim {
        s.push_str("; a PDO is left unusable: see the writes above");
    } else if rolled_back {
        s.push_str(" (the PDO that was being changed rolled back)");
    }
    if store {
        s.push_str("; nothing stored: a reset brings back the stored parameters");
    }
    s.push_str(". config apply again finishes the change");
    s
}

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
