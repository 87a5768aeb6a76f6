//! `canctl config dump|diff|apply`: a node's configuration as a DCF (CiA 306), compared
//! with a file, and made to match one — writing only what differs, in a safe order.

use super::{parse_node, Ctx};
use crate::bus::{Bus, SdoOptions};
use crate::canopen::{abort, DataType, ObjAddr};
use crate::error::Error;
use crate::od::eds::{self, Eds, Header};
use crate::od::{builtin, Dictionary, Entry, Init};
use crate::output::Format;
use clap::{Args, Subcommand};
use clap_complete::engine::ArgValueCandidates;
use serde_json::json;
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::time::Duration;

#[derive(Subcommand, Debug)]
pub enum ConfigCommand {
    Dump(DumpArgs),
    Diff(DiffArgs),
    Apply(ApplyArgs),
}

/// Read every readable object of a node into a DCF
///
/// The objects come from the node's EDS (--eds), else from the built-in dictionary for its
/// profile (0x1000), probed: what the node does not have is left out. DOMAINs are not read.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim config dump 10 > io.dcf
  canctl --bus can0 --eds 5=mh.eds config dump 5 --out sensor.dcf")]
pub struct DumpArgs {
    /// Node-id, 1..127
    #[arg(value_parser = parse_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: u8,
    /// Write the DCF here instead of standard output
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Show where a node differs from a DCF's ParameterValues
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim config diff 10 io.dcf
  canctl --bus can0 config diff 10 io.dcf --check --format json   # exit 6 when they differ")]
pub struct DiffArgs {
    /// Node-id, 1..127
    #[arg(value_parser = parse_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: u8,
    /// The DCF
    pub file: PathBuf,
    /// Exit 6 when anything differs
    #[arg(long)]
    pub check: bool,
}

/// Make a node match a DCF: write only what differs, safely, and prove it
///
/// Values are checked against the file's ranges before anything is written. PDOs are
/// changed the CiA 301 way: COB-ID made invalid, mapping count 0, entries, count, COB-ID
/// back. Each object is reported with its old and new value and what happened; a failure
/// part-way says what was written and what was not.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim config apply 10 io.dcf --dry-run
  canctl --bus can0 config apply 10 io.dcf --verify --store --format json")]
pub struct ApplyArgs {
    /// Node-id, 1..127
    #[arg(value_parser = parse_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: u8,
    /// The DCF
    pub file: PathBuf,
    /// Show what would be written, write nothing
    #[arg(long)]
    pub dry_run: bool,
    /// Store the parameters (0x1010:1) when everything is written
    #[arg(long)]
    pub store: bool,
    /// Read every written object back (exit 6 when one differs)
    #[arg(long)]
    pub verify: bool,
    /// How long the device may take to store
    #[arg(long, value_name = "DUR", default_value = "5s", value_parser = super::parse_duration)]
    pub store_timeout: Duration,
}

pub fn run(ctx: &Ctx, bus: &mut dyn Bus, cmd: &ConfigCommand) -> anyhow::Result<()> {
    match cmd {
        ConfigCommand::Dump(a) => dump(ctx, bus, a),
        ConfigCommand::Diff(a) => diff(ctx, bus, a),
        ConfigCommand::Apply(a) => apply(ctx, bus, a),
    }
}

fn opts(ctx: &Ctx, dtype: DataType) -> SdoOptions {
    let mut o = SdoOptions::new(ctx.timeout);
    o.size_hint = dtype.size();
    o
}

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

fn read_one(ctx: &Ctx, bus: &mut dyn Bus, node: u8, e: &Entry) -> crate::Result<Vec<u8>> {
    bus.sdo_upload(node, e.addr, &opts(ctx, e.dtype)).map(|b| fit(e, b))
}

fn dump(ctx: &Ctx, bus: &mut dyn Bus, a: &DumpArgs) -> anyhow::Result<()> {
    let node = a.node;
    let (dict, source) = match ctx.dicts.eds_for(node) {
        Some(e) => (e.dict.clone(), e.path.clone()),
        None => {
            // The profile (DS401/402/406) decides what 0x6000 and the like mean.
            let t = read_one(ctx, bus, node, builtin::dictionary(None).get(ObjAddr::new(0x1000, 0)).expect("0x1000"))?;
            let profile = u32::from_le_bytes(t.get(..4).and_then(|b| b.try_into().ok()).unwrap_or([0; 4])) as u16;
            (builtin::dictionary(Some(profile)).clone(), format!("the built-in dictionary (profile {profile})"))
        }
    };
    let wanted: Vec<&Entry> = dict.entries().filter(|e| e.access.readable() && e.dtype != DataType::D).collect();
    let bar = ctx.out.bar(wanted.len() as u64, "reading");
    let mut present = Dictionary::default();
    let mut values = BTreeMap::new();
    for (i, e) in wanted.iter().enumerate() {
        bar.set_position(i as u64);
        match read_one(ctx, bus, node, e) {
            Ok(v) => {
                values.insert(e.addr, v);
            }
            // Not on this device: left out of the file.
            Err(Error::SdoAbort { code: abort::NO_OBJECT | abort::NO_SUBINDEX, .. }) => continue,
            Err(Error::SdoAbort { code, .. }) => ctx.out.note(&format!("note: {}: {}", e.addr, abort::meaning(code))),
            Err(err) => return Err(err.into()),
        }
        let (name, kind) = dict.object_info(e.addr.index).expect("declared object");
        present.object(e.addr.index, name, kind);
        present.insert((*e).clone());
    }
    bar.finish_and_clear();
    let u32_of = |addr| {
        values
            .get(&ObjAddr::new(0x1018, addr))
            .and_then(|v: &Vec<u8>| v.get(..4))
            .map_or(0, |b| u32::from_le_bytes(b.try_into().unwrap()))
    };
    let name = values
        .get(&ObjAddr::new(0x1008, 0))
        .map(|v| String::from_utf8_lossy(v).trim_end_matches('\0').to_string())
        .unwrap_or_default();
    let header = Header {
        file_name: a
            .out
            .as_ref()
            .map_or(format!("node{node}.dcf"), |p| p.file_name().unwrap_or_default().to_string_lossy().into_owned()),
        description: format!("node {node} on {}, read by canctl; objects from {source}", bus.describe()),
        vendor_name: String::new(),
        vendor_number: u32_of(1),
        product_name: name,
        product_number: u32_of(2),
        revision: u32_of(3),
        node_id: Some(node),
    };
    // A value no DCF can carry exactly is left out, and said so: never written changed.
    values.retain(|addr, v| match present.get(*addr).map(|e| eds::parameter_text(e, v, Some(node))) {
        Some(Err(why)) => {
            ctx.out.note(&format!("note: {addr} left out of the DCF: {why}"));
            false
        }
        _ => true,
    });
    let text = eds::write_bytes(&present, Some(&values), &header).map_err(|e| Error::Usage(e.to_string()))?;
    match &a.out {
        Some(path) => {
            std::fs::write(path, text).map_err(|e| Error::Usage(format!("cannot write {}: {e}", path.display())))?;
            ctx.out.note(&format!("{} objects of node {node} written to {}", values.len(), path.display()));
        }
        None => ctx.out.write_bytes(&text)?,
    }
    Ok(())
}

/// A DCF value for a node, with its dictionary entry.
type Wanted = (Entry, Vec<u8>);

/// The DCF's ParameterValues for `node`, with their dictionary entries.
fn file_values(path: &std::path::Path, node: u8) -> crate::Result<(Eds, Vec<Wanted>)> {
    let eds = eds::read_file(path).map_err(|e| Error::Usage(format!("cannot use {e}")))?;
    for w in &eds.warnings {
        eprintln!("canctl: warning: {w}");
    }
    let mut out = Vec::new();
    for (addr, init) in &eds.values {
        let Some(entry) = eds.dict.get(*addr) else { continue };
        // $NODEID means the node the file is applied to.
        let value = Entry { default: init.clone(), ..entry.clone() }.default_for(node);
        out.push((entry.clone(), value));
    }
    if out.is_empty() {
        return Err(Error::Usage(format!(
            "{} has no ParameterValue: it is an EDS, not a DCF (canctl config dump makes one)",
            path.display()
        )));
    }
    Ok((eds, out))
}

fn name_of(eds: &Eds, addr: ObjAddr) -> String {
    eds.dict.display_name(addr).unwrap_or_default()
}

fn diff(ctx: &Ctx, bus: &mut dyn Bus, a: &DiffArgs) -> anyhow::Result<()> {
    let (eds, values) = file_values(&a.file, a.node)?;
    let mut rows = Vec::new();
    let mut same = 0;
    for (entry, want) in values.iter().filter(|(e, _)| e.access.readable()) {
        let device = match read_one(ctx, bus, a.node, entry) {
            Ok(v) if v == *want => {
                same += 1;
                continue;
            }
            Ok(v) => show(entry, &v),
            Err(Error::SdoAbort { code, .. }) => format!("({})", abort::meaning(code)),
            Err(e) => return Err(e.into()),
        };
        rows.push((entry.addr, name_of(&eds, entry.addr), device, show(entry, want)));
    }
    match ctx.out.format {
        Format::Json => ctx.out.json(&json!({
            "node": a.node,
            "file": a.file.display().to_string(),
            "same": same,
            "differences": rows.iter().map(|(o, n, d, f)| json!({ "object": o.to_string(), "name": n, "device": d, "file": f })).collect::<Vec<_>>(),
        }))?,
        _ => {
            let table: Vec<Vec<String>> = rows.iter().map(|(o, n, d, f)| vec![o.to_string(), n.clone(), d.clone(), f.clone()]).collect();
            if ctx.out.format == Format::Csv || !table.is_empty() {
                ctx.out.table(&["object", "name", "device", "file"], &table)?;
            }
            ctx.out.note(&format!("node {}: {} object(s) differ from {}, {same} match", a.node, rows.len(), a.file.display()));
        }
    }
    if a.check && !rows.is_empty() {
        return Err(Error::Verify(format!(
            "node {} differs from {} in {} object(s)",
            a.node,
            a.file.display(),
            rows.len()
        ))
        .into());
    }
    Ok(())
}

/// One write of the plan.
pub(super) struct Step {
    pub(super) addr: ObjAddr,
    pub(super) value: Vec<u8>,
    /// An intermediate write of the PDO sequence, not a value of the file.
    pub(super) interim: &'static str,
}

fn pdo_indices(index: u16) -> Option<(u16, u16)> {
    match index {
        0x1400..=0x15FF | 0x1800..=0x19FF => Some((index, index + 0x200)),
        0x1600..=0x17FF | 0x1A00..=0x1BFF => Some((index - 0x200, index)),
        _ => None,
    }
}

/// Writes in a safe order: plain objects first; then per PDO whose COB-ID or mapping
/// changes: COB-ID invalid, mapping count 0, entries, count, other parameters, COB-ID.
pub(super) fn plan(changes: &BTreeMap<ObjAddr, Vec<u8>>, current: &dyn Fn(ObjAddr) -> Option<Vec<u8>>) -> Vec<Step> {
    let mut steps: Vec<Step> = Vec::new();
    let mut pdos: BTreeSet<(u16, u16)> = BTreeSet::new();
    for (addr, value) in changes {
        match pdo_indices(addr.index) {
            Some((comm, map)) if addr.index == map || addr.sub == 1 => {
                pdos.insert((comm, map));
            }
            _ => steps.push(Step { addr: *addr, value: value.clone(), interim: "" }),
        }
    }
    // Plain objects of a PDO comm record (transmission type, timers) already went above.
    for (comm, map) in pdos {
        let cob = ObjAddr::new(comm, 1);
        let cob_now =
            current(cob).map(|v| u32::from_le_bytes(v.get(..4).and_then(|b| b.try_into().ok()).unwrap_or([0; 4])));
        if let Some(c) = cob_now.filter(|c| c & 0x8000_0000 == 0) {
            steps.push(Step {
                addr: cob,
                value: (c | 0x8000_0000).to_le_bytes().to_vec(),
                interim: "PDO made invalid",
            });
        }
        let map_changes: Vec<(&ObjAddr, &Vec<u8>)> = changes.iter().filter(|(a, _)| a.index == map).collect();
        if !map_changes.is_empty() {
            let count = ObjAddr::new(map, 0);
            steps.push(Step { addr: count, value: vec![0], interim: "mapping count 0" });
            for (a, v) in map_changes.iter().filter(|(a, _)| a.sub > 0) {
                steps.push(Step { addr: **a, value: (*v).clone(), interim: "" });
            }
            let final_count = changes.get(&count).cloned().or_else(|| current(count)).unwrap_or(vec![0]);
            steps.push(Step {
                addr: count,
                value: final_count,
                interim: if changes.contains_key(&count) { "" } else { "mapping count back" },
            });
        }
        let final_cob = changes.get(&cob).cloned().or_else(|| cob_now.map(|c| c.to_le_bytes().to_vec()));
        if let Some(v) = final_cob {
            steps.push(Step {
                addr: cob,
                value: v,
                interim: if changes.contains_key(&cob) { "" } else { "PDO valid again" },
            });
        }
    }
    steps
}

fn apply(ctx: &Ctx, bus: &mut dyn Bus, a: &ApplyArgs) -> anyhow::Result<()> {
    let node = a.node;
    let (eds, values) = file_values(&a.file, node)?;
    // Everything is checked before anything is written.
    for (entry, value) in &values {
        super::sdo::check_range(entry, value)?;
    }
    let mut current: BTreeMap<ObjAddr, Vec<u8>> = BTreeMap::new();
    let mut changes: BTreeMap<ObjAddr, Vec<u8>> = BTreeMap::new();
    let mut rows: Vec<Row> = Vec::new();
    for (entry, want) in &values {
        let now = if entry.access.readable() {
            match read_one(ctx, bus, node, entry) {
                Ok(v) => Some(v),
                Err(Error::SdoAbort { code, .. }) if !entry.access.writable() => {
                    rows.push(Row::new(
                        &eds,
                        entry.addr,
                        None,
                        want,
                        format!("not on the device ({})", abort::meaning(code)),
                    ));
                    continue;
                }
                Err(Error::SdoAbort { .. }) => None,
                Err(e) => return Err(e.into()),
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
            rows.push(Row::new(
                &eds,
                entry.addr,
                now.as_deref(),
                want,
                format!("{} on the device: not written", entry.access.name()),
            ));
            continue;
        }
        changes.insert(entry.addr, want.clone());
    }
    // The PDO sequence needs the COB-IDs and mapping counts of the PDOs it touches.
    for (comm, map) in changes.keys().filter_map(|a| pdo_indices(a.index)).collect::<BTreeSet<_>>() {
        for addr in [ObjAddr::new(comm, 1), ObjAddr::new(map, 0)] {
            if let std::collections::btree_map::Entry::Vacant(slot) = current.entry(addr) {
                if let Ok(v) = bus.sdo_upload(node, addr, &SdoOptions::new(ctx.timeout)) {
                    slot.insert(v);
                }
            }
        }
    }
    let steps = plan(&changes, &|addr| current.get(&addr).cloned());
    let entry_of = |addr: ObjAddr| eds.dict.get(addr).or_else(|| builtin::dictionary(None).get(addr));
    let mut failure: Option<Error> = None;
    let mut written: Vec<ObjAddr> = Vec::new();
    for step in &steps {
        let dtype = entry_of(step.addr).map_or(DataType::U32, |e| e.dtype);
        let result = if a.dry_run {
            "would write".to_string()
        } else if failure.is_some() {
            "not written".to_string()
        } else {
            match bus.sdo_download(node, step.addr, &step.value, &opts(ctx, dtype)) {
                Ok(()) => {
                    written.push(step.addr);
                    "written".to_string()
                }
                Err(e) => {
                    let text = format!("failed: {e}");
                    failure = Some(e);
                    text
                }
            }
        };
        let result = if step.interim.is_empty() { result } else { format!("{result} ({})", step.interim) };
        rows.push(Row::new(&eds, step.addr, current.get(&step.addr).map(|v| v.as_slice()), &step.value, result));
    }
    let mut mismatch = Vec::new();
    if a.verify && failure.is_none() && !a.dry_run {
        for (addr, want) in &changes {
            let Some(entry) = entry_of(*addr) else { continue };
            if !entry.access.readable() {
                continue;
            }
            let got = read_one(ctx, bus, node, entry)?;
            let row =
                rows.iter_mut().rev().find(|r| r.addr == *addr && !r.result.contains('(')).expect("row of a change");
            if got == *want {
                row.result.push_str(", verified");
            } else {
                row.result.push_str(&format!(", reads back {}", show(entry, &got)));
                mismatch.push(*addr);
            }
        }
    }
    let stored = if a.store && failure.is_none() && mismatch.is_empty() && !a.dry_run {
        super::store::signature(ctx, bus, node, false, super::store::Class::All, a.store_timeout)?;
        true
    } else {
        false
    };
    report(ctx, a, &rows, stored)?;
    if let Some(e) = failure {
        let done: Vec<String> = written.iter().map(|w| w.to_string()).collect();
        ctx.out.note(&format!(
            "written before the failure: {}",
            if done.is_empty() { "nothing".into() } else { done.join(", ") }
        ));
        return Err(e.into());
    }
    if !mismatch.is_empty() {
        let list: Vec<String> = mismatch.iter().map(|m| m.to_string()).collect();
        return Err(
            Error::Verify(format!("node {node}: {} read back other values than written", list.join(", "))).into()
        );
    }
    Ok(())
}

struct Row {
    addr: ObjAddr,
    name: String,
    old: String,
    new: String,
    result: String,
}

impl Row {
    fn new(eds: &Eds, addr: ObjAddr, old: Option<&[u8]>, new: &[u8], result: String) -> Row {
        let entry = eds.dict.get(addr).or_else(|| builtin::dictionary(None).get(addr));
        let fmt = |b: &[u8]| entry.map_or_else(|| crate::canopen::types::hex(b), |e| show(e, b));
        let name =
            eds.dict.display_name(addr).or_else(|| builtin::dictionary(None).display_name(addr)).unwrap_or_default();
        Row { addr, name, old: old.map_or("-".to_string(), fmt), new: fmt(new), result }
    }
}

fn report(ctx: &Ctx, a: &ApplyArgs, rows: &[Row], stored: bool) -> anyhow::Result<()> {
    match ctx.out.format {
        Format::Json => ctx.out.json(&json!({
            "node": a.node,
            "file": a.file.display().to_string(),
            "dry_run": a.dry_run,
            "objects": rows.iter().map(|r| json!({ "object": r.addr.to_string(), "name": r.name, "old": r.old, "new": r.new, "result": r.result })).collect::<Vec<_>>(),
            "stored": stored,
        }))?,
        _ => {
            let table: Vec<Vec<String>> =
                rows.iter().map(|r| vec![r.addr.to_string(), r.name.clone(), r.old.clone(), r.new.clone(), r.result.clone()]).collect();
            ctx.out.table(&["object", "name", "old", "new", "result"], &table)?;
            if rows.is_empty() {
                ctx.out.note(&format!("node {} already matches {}", a.node, a.file.display()));
            }
            if stored {
                ctx.out.note(&format!("node {}: parameters stored (0x1010:1)", a.node));
            }
        }
    }
    Ok(())
}
