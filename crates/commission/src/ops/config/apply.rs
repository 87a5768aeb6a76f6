//! `config apply`: a node made to match a DCF, writing only what differs, PDOs in the
//! CiA 301 order, rolled back when a change of one stops half-way.

use crate::bus::{Bus, SdoOptions};
use crate::cancel::Cancel;
use crate::canopen::{abort, DataType, ObjAddr};
use crate::error::{Error, Result};
use crate::od::{builtin, names, Dictionary, Entry};
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};
use std::time::Duration;

use super::dcf::{identity_differences, node_dictionary, opts, out_of_range, read_one, show, Dcf};
use super::order::{pdo_indices, plan, Step};
use super::report::{Action, Change, CutWrites, Fix, Incomplete, LeftIn, Outcome, ReadBack};
use crate::error::Advice;
use crate::ops::failure::Failure;

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
    /// Options that write and check nothing more than asked: no store, no read-back, no force; `timeout` for each SDO answer.
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
#[derive(Debug, Default, Serialize)]
#[non_exhaustive]
pub struct Applied {
    /// The node-id written to.
    pub node: u8,
    /// The DCF applied, as named.
    pub file: String,
    /// Nothing was written: `objects` says what would be.
    pub dry_run: bool,
    /// Each object of the file, with what happened to it, in the order written.
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
    /// What the device holds now, when the run did not finish (canctl's JSON words it as
    /// `state`).
    #[serde(skip)]
    pub state: Option<LeftIn>,
}

/// The entry of an object in the DCF's dictionary, else in the built-in one.
fn entry_of(dcf: &Dcf, addr: ObjAddr) -> Option<&Entry> {
    dcf.eds.dict.get(addr).or_else(|| builtin::dictionary(None).get(addr))
}

/// A value of an object as its entry shows it, in hex without one.
fn shown(dcf: &Dcf, addr: ObjAddr, bytes: &[u8]) -> String {
    entry_of(dcf, addr).map_or_else(|| crate::canopen::types::hex(bytes), |e| show(e, bytes))
}

impl Change {
    fn new(dcf: &Dcf, addr: ObjAddr, old: Option<&[u8]>, new: &[u8], result: Outcome) -> Change {
        let builtin_name = || builtin::dictionary(None).display_name(addr);
        let name = dcf.eds.dict.display_name(addr).or_else(builtin_name).unwrap_or_default();
        let old = old.map_or("-".to_string(), |b| shown(dcf, addr, b));
        Change { object: addr, name, old, new: shown(dcf, addr, new), result }
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
            return Err(e.advised(Advice::Near(self.did_you_mean)));
        }
        if !self.mismatch.is_empty() {
            return Err(Error::ReadBackMany { node: self.node, objects: self.mismatch });
        }
        Ok(())
    }

    /// For a run that did not finish (stopped, or a PDO change put back or left to fix):
    /// what was written, what was not, what was put back, and the state the device is left
    /// in; `None` for a run that finished.
    pub fn incomplete(&self) -> Option<Incomplete> {
        if !self.interrupted && self.rolled_back.is_empty() && self.to_fix.is_empty() {
            return None;
        }
        let not_written = |r: &Change| matches!(r.result.action, Action::NotWritten | Action::NotWrittenInterrupted);
        // Interrupted while reading, nothing was planned: the state says it all.
        let planned = self.objects.iter().any(|r| r.result.action == Action::Written || not_written(r));
        let cut = (self.interrupted && planned).then(|| CutWrites {
            written: self.written.clone(),
            not_written: self.objects.iter().filter(|r| not_written(r)).map(|r| r.object).collect(),
        });
        Some(Incomplete {
            cut,
            rolled_back: self.rolled_back.clone(),
            to_fix: self.to_fix.clone(),
            state: self.state.clone(),
        })
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

/// One write of the plan, sized by the object's entry.
fn write(bus: &mut dyn Bus, node: u8, dcf: &Dcf, step: &Step, timeout: Duration) -> Result<()> {
    let dtype = entry_of(dcf, step.addr).map_or(DataType::U32, |e| e.dtype);
    bus.sdo_download(node, step.addr, &step.value, &opts(timeout, dtype))
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
    let back: BTreeMap<ObjAddr, Vec<u8>> = underway
        .before
        .iter()
        .filter_map(|(addr, before)| Some((*addr, before.clone().filter(|v| device.get(addr) != Some(v))?)))
        .collect();
    let unknown = underway.before.iter().filter(|(_, before)| before.is_none());
    let snapshot = device.clone();
    let steps: Vec<Step> = plan(&back, &|a| snapshot.get(&a).cloned())
        .into_iter()
        .filter(|s| s.interim.is_empty() || snapshot.get(&s.addr) != Some(&s.value))
        .collect();
    let mut rows = Vec::new();
    let mut to_fix: Vec<Fix> = Vec::new();
    for step in &steps {
        let fix = Fix { object: step.addr, value: Some(shown(dcf, step.addr, &step.value)) };
        if !to_fix.is_empty() {
            to_fix.push(fix);
            continue;
        }
        let old = device.get(&step.addr).cloned();
        let action = match write(bus, node, dcf, step, timeout) {
            Ok(()) => {
                device.insert(step.addr, step.value.clone());
                Action::Written
            }
            Err(e) => {
                to_fix.push(fix);
                Action::Failed(Failure::from(&e))
            }
        };
        let result = Outcome { rollback: true, ..Outcome::new(action) };
        rows.push(Change::new(dcf, step.addr, old.as_deref(), &step.value, result));
    }
    to_fix.extend(unknown.map(|(object, _)| Fix { object: *object, value: None }));
    (rows, to_fix)
}

/// Make `node` match the DCF: every value is checked against the file's ranges before
/// anything is written; only what differs is written, PDOs the CiA 301 way (COB-ID made
/// invalid, mapping count 0, entries, count, COB-ID back); then optionally read back and
/// stored.
pub fn apply(bus: &mut dyn Bus, node: u8, dcf: &Dcf, o: &ApplyOptions) -> Result<Applied> {
    let values = dcf.values(node)?;
    for (entry, value) in &values {
        crate::ops::values::check_range(entry, value)?;
    }
    let stop = || o.interrupted.is_cancelled();
    let unchanged = |objects: Vec<Change>| Applied {
        node,
        file: dcf.path().to_string(),
        dry_run: o.dry_run,
        objects,
        failure: Some(Error::Interrupted),
        interrupted: true,
        state: Some(LeftIn::Unread { node }),
        ..Applied::default()
    };
    if stop() {
        return Ok(unchanged(Vec::new()));
    }
    // A DCF made for one kind of device is not written into another: the vendor-ID and
    // product code the file names must be the device's (exit 6 otherwise, before anything
    // is written). A file that names neither is applied anywhere.
    let differences = if o.force { Vec::new() } else { identity_differences(bus, node, dcf, o.timeout)? };
    if !differences.is_empty() {
        return Err(Error::OtherDevice { file: dcf.path().to_string(), differences });
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
        let now = match entry.access.readable().then(|| read_one(bus, node, entry, o.timeout)) {
            None => None,
            Some(Ok(v)) => Some(v),
            Some(Err(Error::SdoAbort { code, .. })) if !entry.access.writable() => {
                rows.push(Change::new(dcf, entry.addr, None, want, Outcome::new(Action::NotOnDevice(code))));
                continue;
            }
            Some(Err(e @ Error::SdoAbort { code, .. })) => {
                if crate::ops::node::is_missing(&e) {
                    absent.insert(entry.addr, code);
                }
                None
            }
            Some(Err(e)) => return Err(e),
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
        let entry = target.get(*addr).filter(|e| e.dtype.size() == Some(value.len()));
        if let Some((entry, outside)) = entry.and_then(|e| Some((e, e.outside_limits(value)?))) {
            return Err(out_of_range(entry, value, outside, &target_source));
        }
    }
    let steps = plan(&changes, &|addr| current.get(&addr).cloned());
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
            match write(bus, node, dcf, step, o.timeout) {
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
                    let failed = Action::Failed(Failure::from(&e));
                    failure = Some(e);
                    failed
                }
            }
        };
        let interim = (!step.interim.is_empty()).then_some(step.interim);
        let result = Outcome { interim, ..Outcome::new(action) };
        rows.push(Change::new(dcf, step.addr, current.get(&step.addr).map(|v| v.as_slice()), &step.value, result));
        // Stopped inside a PDO change: put the PDO back before anything else.
        if let Some(u) = underway.take_if(|_| failure.is_some() && !o.dry_run) {
            let (r, fix) = roll_back(bus, node, dcf, &u, &mut device, o.timeout);
            rollback_rows = r;
            if fix.is_empty() {
                rolled_back.push(pdo_name(u.pdo));
            }
            to_fix = fix;
        }
    }
    // An object the device lacks: the nearest ones it may have meant, from its own
    // dictionary (not the file's, which may describe another kind of device).
    let did_you_mean = match &failure {
        Some(e @ Error::SdoAbort { obj, code, .. }) if crate::ops::node::is_missing(e) => {
            names::near(&target, *obj, *code == abort::NO_OBJECT)
        }
        _ => Vec::new(),
    };
    rows.extend(rollback_rows);
    let mut mismatch = Vec::new();
    if o.verify && failure.is_none() && !o.dry_run {
        for (addr, want) in &changes {
            let Some(entry) = entry_of(dcf, *addr).filter(|e| e.access.readable()) else { continue };
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
    let mut stored = o.store && failure.is_none() && mismatch.is_empty() && !o.dry_run;
    if stored && stop() {
        (interrupted, stored) = (true, false);
        failure = Some(Error::Interrupted);
    }
    if stored {
        let t = crate::ops::store::Timeouts { answer: o.timeout, write: o.store_timeout };
        crate::ops::store::store(bus, node, crate::ops::store::Class::All, t)?;
    }
    // What a run that did not finish leaves the device holding.
    let state = (!o.dry_run && failure.is_some()).then(|| LeftIn::Written {
        node,
        new: changes.iter().filter(|(a, v)| device.get(a) == Some(v)).map(|(a, _)| *a).collect(),
        of: changes.len(),
        // An intermediate value left behind (a COB-ID made invalid, a count of 0).
        interim: device.iter().any(|(a, v)| current.get(a).is_some_and(|b| b != v) && changes.get(a) != Some(v)),
        rolled_back: !rolled_back.is_empty(),
        rollback_failed: !to_fix.is_empty(),
        store_asked: o.store,
    });
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
