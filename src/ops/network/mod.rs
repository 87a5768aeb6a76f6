//! A whole network from one CiA 306-3 project (`nodelist.cpj` plus one DCF per node):
//! [`dump`] a live bus into one, [`check`] a bus against one, [`apply`] one to a bus.

use super::config::{self, Dcf};
pub use super::lss::LssTally;
use super::Progress;
use crate::bus::lss::LssMaster;
use crate::bus::{Bus, LssWait, SdoOptions};
use crate::cancel::Cancel;
use crate::canopen::lss::{Identity, Request};
use crate::canopen::ObjAddr;
use crate::error::{Error, Result, Service};
use crate::od::cpj::{self, Commissioning, Project};
use crate::od::eds;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The project file canctl writes and looks for in a folder.
pub const PROJECT_FILE: &str = "nodelist.cpj";

const DEVICE_TYPE: ObjAddr = ObjAddr::new(0x1000, 0);
const NAME: ObjAddr = ObjAddr::new(0x1008, 0);

/// A project with each listed node's DCF read.
#[derive(Debug)]
pub struct Loaded {
    pub file: PathBuf,
    pub project: Project,
    pub nodes: Vec<Listed>,
    /// What the files say that deserves a look, with file:line.
    pub warnings: Vec<String>,
}

/// A node the project lists as present.
#[derive(Debug)]
pub struct Listed {
    pub node: u8,
    /// `NodeXName`, else the DCF's product name, else empty.
    pub name: String,
    pub dcf: Option<Dcf>,
    pub commissioning: Commissioning,
}

impl Listed {
    /// The identity an LSS device with this configuration answers to: the DCF's vendor-ID,
    /// product code and revision, and the commissioning's LSS serial number.
    pub fn lss_identity(&self) -> Option<Identity> {
        let dcf = self.dcf.as_ref()?;
        let (vendor, product) = dcf.identity();
        let serial = self.commissioning.lss_serial.filter(|s| *s != 0)?;
        let revision = info_number(dcf, "revisionnumber").unwrap_or(0);
        (vendor != 0 && product != 0).then_some(Identity { vendor, product, revision, serial })
    }
}

fn info_number(dcf: &Dcf, key: &str) -> Option<u32> {
    dcf.eds.info.get(key).and_then(|v| eds::parse_int(v)).and_then(|v| u32::try_from(v).ok())
}

/// Read a project and the DCF of every node it lists; any file that cannot be used is a
/// usage error naming it (file:line where a line is to blame).
pub fn load(file: &Path) -> Result<Loaded> {
    let read = cpj::read_file(file).map_err(|e| Error::Usage(format!("cannot use {e}")))?;
    let mut warnings = read.warnings;
    let project = read.project;
    let mut nodes = Vec::new();
    for (node, entry) in project.present() {
        let (dcf, commissioning) = match project.dcf_path(file, node) {
            None => (None, Commissioning::default()),
            Some(path) => {
                let name = path.display().to_string();
                let bytes = crate::input::read_regular_file(&path, crate::input::EDS)
                    .map_err(|e| Error::Usage(format!("cannot use {name} (node {node} in {}): {e}", file.display())))?;
                let dcf = Dcf::parse(&bytes, &name)?;
                let xml = crate::od::xdd::is_xml(&bytes);
                let c = match xml {
                    true => crate::od::xdd::read_commissioning(&bytes, &name).map_err(|e| e.to_string()),
                    false => cpj::read_commissioning(&bytes, &name).map_err(|e| e.to_string()),
                }
                .map_err(|e| Error::Usage(format!("cannot use {e}")))?;
                if let Some(id) = c.node_id.filter(|id| *id != node) {
                    return Err(Error::Usage(format!(
                        "{name} is for node-id {id} ({}), but {} lists it for node {node}",
                        if xml { "DeviceCommissioning nodeID" } else { "[DeviceComissioning] NodeID" },
                        file.display()
                    )));
                }
                warnings.extend(dcf.warnings().iter().map(|w| w.to_string()));
                (Some(dcf), c)
            }
        };
        let name = entry.name.clone().or_else(|| dcf.as_ref().and_then(|d| d.eds.info.get("productname").cloned()));
        nodes.push(Listed { node, name: name.unwrap_or_default(), dcf, commissioning });
    }
    Ok(Loaded { file: file.to_path_buf(), project, nodes, warnings })
}

/// Whether an error means nobody answered (exit 3), whichever variant says it.
fn no_answer(e: &Error) -> bool {
    e.exit_code() == 3
}

/// Every node that answers (`ops::scan::probe`), with its device type where it gave one.
fn probe(bus: &mut dyn Bus, window: Duration, progress: &mut dyn Progress) -> Result<BTreeMap<u8, Option<u32>>> {
    Ok(super::scan::probe(bus, window, progress)?.into_iter().collect())
}

// ---------------------------------------------------------------------------------------
// dump

/// What `dump` read: the files of a project, to be written into one folder.
#[derive(Debug, Serialize)]
pub struct Dumped {
    pub bus: String,
    pub nodes: Vec<DumpedNode>,
    /// Devices that answered LSS without a node-id (not in the project: they have no
    /// objects to read).
    pub unconfigured: usize,
    /// File name and content: `nodelist.cpj` first, then one DCF per node.
    #[serde(skip)]
    pub files: Vec<(String, Vec<u8>)>,
}

#[derive(Debug, Serialize)]
pub struct DumpedNode {
    pub node: u8,
    pub name: String,
    pub file: String,
    pub objects: usize,
}

/// How to dump a network.
#[derive(Clone, Debug)]
pub struct DumpOptions {
    pub timeout: Duration,
    /// How long the probes wait for answers.
    pub window: Duration,
    /// `NetName` of the project.
    pub net_name: String,
    /// The bus's bit rate in kbit/s, for each DCF's `Baudrate` (left out when unknown).
    pub baudrate_kbit: Option<u32>,
}

/// Scan the bus and read every node into a DCF (`nodeN.dcf`, with its
/// `[DeviceComissioning]`: node-id, name, bit rate, LSS serial number), listed in a
/// `nodelist.cpj`.
pub fn dump(bus: &mut dyn Bus, o: &DumpOptions, progress: &mut dyn Progress) -> Result<Dumped> {
    let found = probe(bus, o.window, progress)?;
    let unconfigured = crate::bus::lss::count_unconfigured(bus, o.window)?;
    let mut project = Project { net_name: Some(o.net_name.clone()), ..Project::default() };
    let mut nodes = Vec::new();
    let mut files = Vec::new();
    for node in found.keys().copied() {
        let file = format!("node{node}.dcf");
        let dumped = config::dump(bus, node, None, &file, o.timeout, progress)?;
        let parsed = Dcf::parse(&dumped.dcf, &file)?;
        let serial = parsed.eds.values.get(&ObjAddr::new(0x1018, 4)).and_then(|v| match v {
            crate::od::Init::Bytes(b) => Some(super::le_u32(b)),
            _ => None,
        });
        let name = match parsed.eds.values.get(&NAME) {
            Some(crate::od::Init::Bytes(b)) => String::from_utf8_lossy(b).trim_end_matches('\0').to_string(),
            _ => String::new(),
        };
        let commissioning = Commissioning {
            node_id: Some(node),
            node_name: (!name.is_empty()).then(|| name.clone()),
            baudrate_kbit: o.baudrate_kbit,
            lss_serial: serial,
            ..Commissioning::default()
        };
        let bytes = cpj::with_commissioning(&dumped.dcf, &commissioning).map_err(|e| Error::Usage(e.to_string()))?;
        project.nodes.insert(
            node,
            cpj::Node {
                present: true,
                name: (!name.is_empty()).then(|| name.clone()),
                refd: None,
                dcf: Some(file.clone()),
            },
        );
        nodes.push(DumpedNode { node, name, file: file.clone(), objects: dumped.objects });
        files.push((file, bytes));
    }
    let cpj = cpj::write(&project).map_err(|e| Error::Usage(e.to_string()))?;
    files.insert(0, (PROJECT_FILE.to_string(), cpj));
    Ok(Dumped { bus: bus.describe(), nodes, unconfigured, files })
}

// ---------------------------------------------------------------------------------------
// check

/// How to check a network.
#[derive(Clone, Debug)]
pub struct CheckOptions {
    pub timeout: Duration,
    pub window: Duration,
    /// How many nodes are checked at once (1: one after the other).
    pub jobs: usize,
    /// The NMT state every listed node must be in, when the caller expects one (CiA 306-3
    /// projects do not say).
    pub state: Option<crate::canopen::nmt::State>,
}

/// Is the network as the project says?
#[derive(Debug, Serialize)]
pub struct Checked {
    pub project: String,
    pub net_name: Option<String>,
    pub bus: String,
    pub nodes: Vec<NodeCheck>,
    /// Nodes that answered but the project does not list, with their device type.
    pub unlisted: Vec<Unlisted>,
    /// Devices that answered LSS "identify non-configured remote slave": said, but no
    /// difference (see [`matches`]).
    pub unconfigured: usize,
    /// Whether the network matches the project ([`matches`]).
    pub ok: bool,
}

/// What "the network matches the project" means, for `check` and `apply` alike: every
/// listed node is as the project says (`nodes_ok`), and no node the project does not list
/// answers. Devices waiting for a node-id are no difference: without one they have no
/// place in a project, and a listed device that lost its id fails its own `present` check.
fn matches(nodes_ok: bool, unlisted: &[Unlisted]) -> bool {
    nodes_ok && unlisted.is_empty()
}

/// The nodes that answered a probe but the project does not list.
fn unlisted(found: &BTreeMap<u8, Option<u32>>, loaded: &Loaded) -> Vec<Unlisted> {
    found
        .iter()
        .filter(|(n, _)| !loaded.nodes.iter().any(|l| l.node == **n))
        .map(|(n, t)| Unlisted { node: *n, device_type: *t })
        .collect()
}

#[derive(Debug, Serialize)]
pub struct NodeCheck {
    pub node: u8,
    pub name: String,
    pub file: Option<String>,
    pub checks: Vec<Verdict>,
}

/// One check of one node: `present`, `identity`, `objects`, `state`.
#[derive(Debug, Serialize)]
pub struct Verdict {
    pub check: &'static str,
    pub ok: bool,
    /// What was found, in a sentence.
    pub detail: String,
    /// For `objects`: each writable object that differs.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub differences: Vec<config::Difference>,
}

#[derive(Debug, Serialize)]
pub struct Unlisted {
    pub node: u8,
    pub device_type: Option<u32>,
}

impl Checked {
    /// A verification error (exit 6) when anything differs.
    pub fn outcome(&self) -> Result<()> {
        if self.ok {
            return Ok(());
        }
        let failed: usize = self.nodes.iter().map(|n| n.checks.iter().filter(|c| !c.ok).count()).sum();
        let mut parts = Vec::new();
        if failed > 0 {
            parts.push(format!("{failed} node check(s) failed"));
        }
        if !self.unlisted.is_empty() {
            parts.push(format!("{} node(s) not in the project", self.unlisted.len()));
        }
        Err(Error::NetworkDiffers { bus: self.bus.clone(), project: self.project.clone(), differences: parts })
    }
}

fn hex(v: u32) -> String {
    format!("0x{v:08X}")
}

/// The vendor-ID and product code of `node` against the DCF's (parts the DCF leaves at 0
/// are not compared).
fn check_identity(bus: &mut dyn Bus, node: u8, dcf: &Dcf, timeout: Duration) -> Result<Verdict> {
    let (vendor, product) = dcf.identity();
    let mut differ = Vec::new();
    let mut seen = Vec::new();
    for p in super::node::Node::new(bus, node, timeout).compare_identity(vendor, product)? {
        if p.matches() {
            seen.push(format!("{} {}", p.what, p.device_text()));
        } else {
            differ.push(format!("{} {}, {} in {}", p.what, p.device_text(), hex(p.file), dcf.path()));
        }
    }
    let (ok, detail) = match (differ.is_empty(), seen.is_empty()) {
        (false, _) => (false, format!("another device: {}", differ.join(", "))),
        (true, true) => (true, format!("{} names no vendor-ID or product code: not compared", dcf.path())),
        (true, false) => (true, seen.join(", ")),
    };
    Ok(Verdict { check: "identity", ok, detail, differences: Vec::new() })
}

/// Every writable object of the DCF against the node (read-only values such as serial
/// numbers or measurements are the device's, not its configuration).
fn check_objects(bus: &mut dyn Bus, node: u8, dcf: &Dcf, timeout: Duration) -> Result<Verdict> {
    let diff = config::diff(bus, node, dcf, timeout)?;
    let writable = |addr: ObjAddr| dcf.eds.dict.get(addr).is_some_and(|e| e.access.writable());
    let differences: Vec<config::Difference> = diff.differences.into_iter().filter(|d| writable(d.object)).collect();
    let detail = match differences.len() {
        0 => format!("every writable object as in {}", dcf.path()),
        n => {
            let list: Vec<String> = differences
                .iter()
                .map(|d| format!("{} {}: {} on the node, {} in the file", d.object, d.name, d.device, d.file))
                .collect();
            format!("{n} object(s) differ from {}: {}", dcf.path(), list.join("; "))
        }
    };
    Ok(Verdict { check: "objects", ok: differences.is_empty(), detail, differences })
}

/// The node's NMT state against `want`: from its heartbeat, when one was seen in this
/// session, else by node guarding (through an EPOS2: by remote request).
fn check_state(bus: &mut dyn Bus, node: u8, want: crate::canopen::nmt::State, window: Duration) -> Result<Verdict> {
    let wait = (2 * window).max(Duration::from_millis(200));
    let seen = super::node::Node::new(bus, node, wait).nmt_state(wait)?;
    let (ok, detail) = match seen {
        Some((state, from)) => (state == want, format!("{state} (from its {from}), {want} expected")),
        None => (false, format!("no heartbeat seen and no answer to node guarding; {want} expected")),
    };
    Ok(Verdict { check: "state", ok, detail, differences: Vec::new() })
}

/// Check the bus against the project: each listed node present, with the identity its DCF
/// names and every writable object as the DCF has it; no node the project does not list;
/// no device waiting for a node-id.
pub fn check(bus: &mut dyn Bus, loaded: &Loaded, o: &CheckOptions, progress: &mut dyn Progress) -> Result<Checked> {
    let found = probe(bus, o.window, progress)?;
    let unconfigured = crate::bus::lss::count_unconfigured(bus, o.window)?;
    let check_node = |bus: &mut dyn Bus, i: usize| -> Result<NodeCheck> {
        let listed = &loaded.nodes[i];
        let present = found.contains_key(&listed.node);
        let mut checks = vec![Verdict {
            check: "present",
            ok: present,
            detail: if present {
                format!("node {} answered", listed.node)
            } else {
                format!("node {} did not answer within {} ms", listed.node, o.window.as_millis())
            },
            differences: Vec::new(),
        }];
        if let (true, Some(dcf)) = (present, &listed.dcf) {
            checks.push(check_identity(bus, listed.node, dcf, o.timeout)?);
            if checks.last().is_some_and(|c| c.ok) {
                checks.push(check_objects(bus, listed.node, dcf, o.timeout)?);
            }
        }
        Ok(NodeCheck {
            node: listed.node,
            name: listed.name.clone(),
            file: listed.dcf.as_ref().map(|d| d.path().to_string()),
            checks,
        })
    };
    let all: Vec<usize> = (0..loaded.nodes.len()).collect();
    progress.start("checking", all.len() as u64);
    let results: Vec<Result<NodeCheck>> = if o.jobs <= 1 {
        all.iter()
            .map(|i| {
                progress.advance(*i as u64);
                check_node(bus, *i)
            })
            .collect()
    } else {
        let stopped = |_: usize, e: Error| Err(e);
        let items: Vec<(usize, u8)> = all.iter().map(|i| (*i, loaded.nodes[*i].node)).collect();
        parallel::each(bus, &items, o.jobs, &Cancel::new(), &check_node, &stopped, progress)
            .into_iter()
            .map(|(_, r)| r)
            .collect()
    };
    let mut nodes = results.into_iter().collect::<Result<Vec<NodeCheck>>>()?;
    if let Some(want) = o.state {
        // Node guarding and heartbeats are the link's, not a node's SDO: asked here.
        for n in nodes.iter_mut().filter(|n| n.checks[0].ok) {
            n.checks.push(check_state(bus, n.node, want, o.window)?);
        }
    }
    progress.finish();
    let unlisted = unlisted(&found, loaded);
    let ok = matches(nodes.iter().all(|n| n.checks.iter().all(|c| c.ok)), &unlisted);
    Ok(Checked {
        project: loaded.file.display().to_string(),
        net_name: loaded.project.net_name.clone(),
        bus: bus.describe(),
        nodes,
        unlisted,
        unconfigured,
        ok,
    })
}

// ---------------------------------------------------------------------------------------
// apply

/// How to apply a project.
#[derive(Clone, Debug)]
pub struct ApplyOptions {
    /// Timeouts, dry run, verify, force; `store` is done here, only for nodes written to.
    pub config: config::ApplyOptions,
    /// Give node-ids over LSS to listed nodes that do not answer, matched by the LSS
    /// identity their DCF names.
    pub assign: bool,
    /// How long probes wait for answers.
    pub window: Duration,
    /// How long a device given a node-id may take to answer with it.
    pub boot_wait: Duration,
    /// How many nodes are configured at once (1: one after the other).
    pub jobs: usize,
    /// Reset the nodes written to (NMT reset node) and wait, up to `boot_wait`, until each
    /// is back (its boot-up, or an SDO answer where the link shows no traffic).
    pub reset: bool,
    /// Set when the user asks to stop (SIGINT, SIGTERM, Ctrl-C): no node is begun after
    /// that, and the report says which were not. The nodes under way stop at their next
    /// safe point when `config.interrupted` is the same flag (between two SDO transfers, a
    /// PDO change under way rolled back, as `config apply` does), else they finish.
    pub interrupted: Cancel,
}

/// What applying a project did, node by node.
#[derive(Debug, Serialize)]
pub struct Applied {
    pub project: String,
    pub bus: String,
    pub dry_run: bool,
    pub nodes: Vec<NodeApplied>,
    /// Objects written on the whole network.
    pub written: usize,
    /// Nodes that answered but the project does not list: apply cannot make them match.
    pub unlisted: Vec<Unlisted>,
    /// Whether the network now matches the project ([`matches`]): every node brought to
    /// its DCF, none unlisted.
    pub ok: bool,
    /// The first failure (its exit code is the command's).
    #[serde(skip)]
    pub failure: Option<Error>,
}

#[derive(Debug, Serialize)]
pub struct NodeApplied {
    pub node: u8,
    pub name: String,
    pub file: Option<String>,
    /// `assigned over LSS to IDENTITY` when `--assign` gave the node its id.
    pub assigned: Option<String>,
    /// Objects written (PDO sequence steps included).
    pub written: usize,
    pub stored: bool,
    /// What happened, in a sentence.
    pub result: String,
    /// What happened, in one word: the summary counts these, as the table shows them.
    pub outcome: Outcome,
    pub ok: bool,
    /// Each object written or not, as `config apply` reports it.
    pub objects: Vec<config::Change>,
}

/// Where a node's apply ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Outcome {
    /// Brought to its DCF (or, in a dry run, found what would be written).
    Done,
    /// Failed; the result says why.
    Failed,
    /// Stopped by the user after something was written (or a PDO change rolled back).
    StoppedPartWay,
    /// Stopped by the user before anything was written: the node is as it was.
    StoppedUnchanged,
    /// Not begun: the user stopped the run first (its node-id may have been given).
    NotBegun,
}

impl Applied {
    pub fn outcome(self) -> Result<()> {
        match self.failure {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

/// Give `node` to the LSS device with `identity`, store it, and wait until the node answers
/// SDO with it.
fn assign(bus: &mut dyn Bus, identity: &Identity, node: u8, o: &ApplyOptions) -> Result<()> {
    let mut m = LssMaster::new(bus, o.config.timeout);
    let result = m
        .enter(Some(identity))
        .and_then(|_| m.configure(Request::ConfigureNodeId(node), "set-id", false))
        .and_then(|_| m.configure(Request::StoreConfiguration, "store", false));
    // Back in waiting state the device takes its new node-id and boots.
    let left = m.leave();
    result?;
    left?;
    let deadline = bus.now() + o.boot_wait;
    loop {
        match bus.sdo_upload(node, DEVICE_TYPE, &SdoOptions::new(o.window)) {
            Ok(_) | Err(Error::SdoAbort { .. }) => return Ok(()),
            Err(e) if no_answer(&e) && bus.now() < deadline => continue,
            Err(e) if no_answer(&e) => {
                let what = Service::AfterLssAssign { identity: *identity };
                return Err(Error::NoAnswer { node, what, waited: o.boot_wait });
            }
            Err(e) => return Err(e),
        }
    }
}

/// A node's row, and the error that failed it.
type NodeOutcome = (NodeApplied, Option<Error>);

fn empty_row(listed: &Listed) -> NodeApplied {
    NodeApplied {
        node: listed.node,
        name: listed.name.clone(),
        file: listed.dcf.as_ref().map(|d| d.path().to_string()),
        assigned: None,
        written: 0,
        stored: false,
        result: String::new(),
        outcome: Outcome::Failed,
        ok: false,
        objects: Vec::new(),
    }
}

/// One node that answers: `config apply` (only what differs, in its safe order, verified
/// when asked), then store when anything was written.
fn configure_node(bus: &mut dyn Bus, listed: &Listed, o: &ApplyOptions) -> NodeOutcome {
    let mut row = empty_row(listed);
    let fail = |mut row: NodeApplied, e: Error| {
        row.result = format!("failed: {e}");
        (row, Some(e))
    };
    let Some(dcf) = &listed.dcf else {
        row.ok = true;
        row.outcome = Outcome::Done;
        row.result = "present; the project names no DCF for it".to_string();
        return (row, None);
    };
    let mut co = o.config.clone();
    co.store = false;
    let mut applied = match config::apply(bus, listed.node, dcf, &co) {
        Ok(a) => a,
        Err(e) => return fail(row, e),
    };
    row.written = applied.written.len();
    row.objects = std::mem::take(&mut applied.objects);
    let would = row.objects.iter().filter(|c| c.result.action == config::Action::WouldWrite).count();
    if applied.interrupted {
        // Stopped between two transfers, a PDO change under way put back: what was done,
        // what was not, and the state the node is left in, as `config apply` says it.
        row.result = format!("interrupted: {}", applied.summary().join("; "));
        let changed = row.written > 0 || !applied.rolled_back.is_empty() || !applied.to_fix.is_empty();
        row.outcome = if changed { Outcome::StoppedPartWay } else { Outcome::StoppedUnchanged };
        if o.config.store && !o.config.dry_run && row.written > 0 {
            row.result.push_str(&format!("; not stored (canctl store {} keeps what was written)", listed.node));
        }
        return (row, Some(Error::Interrupted));
    }
    if let Err(e) = applied.outcome() {
        return fail(row, e);
    }
    let stop = o.config.interrupted.is_cancelled();
    if o.config.store && row.written > 0 && stop {
        row.result = format!(
            "interrupted: {} object(s) written{}, not stored (canctl store {} keeps them)",
            row.written,
            if o.config.verify { ", verified" } else { "" },
            listed.node
        );
        row.outcome = Outcome::StoppedPartWay;
        return (row, Some(Error::Interrupted));
    }
    if o.config.store && row.written > 0 {
        let t = super::store::Timeouts { answer: o.config.timeout, write: o.config.store_timeout };
        match super::store::store(bus, listed.node, super::store::Class::All, t) {
            Ok(_) => row.stored = true,
            Err(e) => return fail(row, e),
        }
    }
    row.ok = true;
    row.outcome = Outcome::Done;
    row.result = match (o.config.dry_run, row.written) {
        (true, _) if would == 0 => "up to date: nothing would be written".to_string(),
        (true, _) => format!("{would} object(s) would be written"),
        (false, 0) => "up to date: nothing written".to_string(),
        (false, n) => format!(
            "{n} object(s) written{}{}",
            if o.config.verify { ", verified" } else { "" },
            if row.stored { ", stored" } else { "" }
        ),
    };
    (row, None)
}

/// Bring every listed node to its DCF: first the node-ids over LSS (one device at a time,
/// as LSS works), then up to `jobs` nodes at once, their SDO transfers in flight together on
/// the one link. A node that fails is reported and the others still done; the first
/// failure decides the exit code.
pub fn apply(bus: &mut dyn Bus, loaded: &Loaded, o: &ApplyOptions, progress: &mut dyn Progress) -> Result<Applied> {
    let found = probe(bus, o.window, progress)?;
    let mut rows: Vec<Option<NodeOutcome>> = Vec::new();
    // Nodes that must answer before they can be configured: given their id, or failed.
    let stop = || o.interrupted.is_cancelled();
    for listed in &loaded.nodes {
        let present = found.contains_key(&listed.node);
        rows.push((!present && !stop()).then(|| absent_node(bus, listed, o)));
    }
    let ready: Vec<usize> = (0..loaded.nodes.len())
        .filter(|i| match &rows[*i] {
            None => found.contains_key(&loaded.nodes[*i].node),
            Some((row, None)) => row.assigned.is_some() && !o.config.dry_run,
            Some(_) => false,
        })
        .collect();
    let assigned: Vec<Option<String>> =
        rows.iter().map(|r| r.as_ref().and_then(|(row, _)| row.assigned.clone())).collect();
    progress.start("applying", ready.len() as u64);
    let done = if o.jobs <= 1 {
        let mut done = Vec::new();
        for (k, i) in ready.iter().enumerate() {
            if stop() {
                break;
            }
            progress.advance(k as u64);
            let label = node_label(loaded.nodes[*i].node);
            let (mut reads, mut writes) = (0, 0);
            let result = {
                let mut counted = crate::bus::tap::AfterSdo::new(&mut *bus, |t, n| {
                    match t {
                        crate::bus::tap::Transfer::Upload => reads = n,
                        crate::bus::tap::Transfer::Download => writes = n,
                        crate::bus::tap::Transfer::Nmt => {}
                    }
                    progress.item(&label, &transfers(reads, writes), false);
                });
                configure_node(&mut counted, &loaded.nodes[*i], o)
            };
            progress.item(&label, &result.summary(), true);
            let link = matches!(result.1, Some(Error::Link(_)));
            done.push((*i, result));
            // A lost link ends the run: every further node would fail the same way.
            if link {
                break;
            }
        }
        done
    } else {
        let work = |bus: &mut dyn Bus, i: usize| configure_node(bus, &loaded.nodes[i], o);
        let stopped = |i: usize, e: Error| {
            let mut row = empty_row(&loaded.nodes[i]);
            row.result = format!("failed: {e}");
            (row, Some(e))
        };
        let items: Vec<(usize, u8)> = ready.iter().map(|i| (*i, loaded.nodes[*i].node)).collect();
        parallel::each(bus, &items, o.jobs, &o.interrupted, &work, &stopped, progress)
    };
    progress.finish();
    let configured: Vec<usize> = done.iter().map(|(i, _)| *i).collect();
    for (i, (mut row, error)) in done {
        if let Some(id) = &assigned[i] {
            row.assigned = Some(id.clone());
            row.result = format!("node-id given over LSS; {}", row.result);
        }
        rows[i] = Some((row, error));
    }
    if o.reset && !o.config.dry_run && !stop() {
        let written: Vec<u8> = rows
            .iter()
            .flatten()
            .filter(|(row, error)| error.is_none() && row.written > 0)
            .map(|(row, _)| row.node)
            .collect();
        let back = reset_and_wait(bus, &written, o)?;
        for (row, error) in rows.iter_mut().flatten() {
            match back.get(&row.node) {
                Some(true) => row.result.push_str(", reset, booted"),
                Some(false) => {
                    row.result.push_str(", reset, but not back");
                    row.ok = false;
                    error.get_or_insert(Error::NoAnswer { node: row.node, what: Service::BootUp, waited: o.boot_wait });
                }
                None => {}
            }
        }
    }
    let interrupted = stop();
    let mut nodes = Vec::new();
    let mut failure = interrupted.then_some(Error::Interrupted);
    for (i, outcome) in rows.into_iter().enumerate() {
        match outcome {
            // Given its node-id over LSS, then not configured: stopped by the user, or the
            // link was lost, before this node was begun.
            Some((mut row, None)) if ready.contains(&i) && !configured.contains(&i) => {
                let (why, outcome) = if interrupted {
                    ("interrupted before this node was begun", Outcome::NotBegun)
                } else {
                    ("the run ended (link lost) before this node was begun", Outcome::Failed)
                };
                row.result = format!("node-id given over LSS; not configured: {why}");
                row.outcome = outcome;
                row.ok = false;
                nodes.push(row);
            }
            Some((row, error)) => {
                if let Some(e) = error {
                    failure.get_or_insert(e);
                }
                nodes.push(row);
            }
            // Not begun: interrupted first, or the link was lost.
            None if interrupted => {
                let mut row = empty_row(&loaded.nodes[i]);
                row.result = "not done: interrupted before this node was begun".into();
                row.outcome = Outcome::NotBegun;
                nodes.push(row);
            }
            None => {}
        }
    }
    let written = nodes.iter().map(|n| n.written).sum();
    let unlisted = unlisted(&found, loaded);
    if !unlisted.is_empty() {
        let list: Vec<String> = unlisted.iter().map(|u| u.node.to_string()).collect();
        failure.get_or_insert(Error::NetworkDiffers {
            bus: bus.describe(),
            project: loaded.file.display().to_string(),
            differences: vec![format!("node(s) {} answer but are not in the project", list.join(", "))],
        });
    }
    Ok(Applied {
        project: loaded.file.display().to_string(),
        bus: bus.describe(),
        dry_run: o.config.dry_run,
        ok: matches(failure.is_none() && nodes.len() == loaded.nodes.len(), &unlisted),
        nodes,
        written,
        unlisted,
        failure,
    })
}

/// A node's result in a few words, for its progress bar.
trait Summary {
    fn summary(&self) -> String;
}

impl Summary for NodeOutcome {
    fn summary(&self) -> String {
        self.0.result.clone()
    }
}

impl Summary for Result<NodeCheck> {
    fn summary(&self) -> String {
        match self {
            Ok(n) => match n.checks.iter().filter(|c| !c.ok).count() {
                0 => "as the project says".to_string(),
                k => format!("{k} check(s) differ"),
            },
            Err(e) => format!("failed: {e}"),
        }
    }
}

fn node_label(node: u8) -> String {
    format!("node {node}")
}

fn transfers(reads: u32, writes: u32) -> String {
    format!("{reads} read(s), {writes} write(s)")
}

/// Many nodes at once over one link: each node's procedure runs on its own thread against a
/// [`NodeBus`], which hands its SDO transfers to the caller's thread; that thread waits until
/// every running node has one transfer waiting (or is done), then runs them together
/// ([`Bus::sdo_many`]: one per node, all in flight at once) and hands back the answers.
mod parallel {
    use super::*;
    use crate::bus::{LssAnswer, LssWait, Observed, SdoJob};
    use crate::frame::Frame;
    use std::sync::mpsc::{channel, Receiver, Sender};
    use std::sync::{Arc, Mutex};

    enum Msg<T> {
        Sdo(SdoJob, Sender<Result<Vec<u8>>>),
        Done(usize, T),
    }

    /// The bus as one node's procedure sees it: SDO only, through the coordinating thread.
    struct NodeBus<T> {
        describe: String,
        to_coordinator: Sender<Msg<T>>,
        /// The bus's time as of the last batch (set before its answers are handed back).
        clock: Arc<Mutex<Instant>>,
        observed: Observed,
    }

    impl<T> NodeBus<T> {
        fn ask(&mut self, job: SdoJob) -> Result<Vec<u8>> {
            let (tx, rx) = channel();
            let gone = || Error::NotOnThisBus { bus: self.describe.clone(), why: "the coordinating thread is gone" };
            self.to_coordinator.send(Msg::Sdo(job, tx)).map_err(|_| gone())?;
            rx.recv().map_err(|_| gone())?
        }

        fn not_here(&self) -> Error {
            Error::NotOnThisBus {
                bus: self.describe.clone(),
                why: "a node configured in parallel has SDO only (NMT, LSS and raw frames are the caller's)",
            }
        }
    }

    impl<T> Bus for NodeBus<T> {
        fn describe(&self) -> String {
            self.describe.clone()
        }
        fn sdo_upload(&mut self, node: u8, addr: ObjAddr, opts: &SdoOptions) -> Result<Vec<u8>> {
            self.ask(SdoJob::Upload { node, addr, opts: opts.clone() })
        }
        fn sdo_download(&mut self, node: u8, addr: ObjAddr, data: &[u8], opts: &SdoOptions) -> Result<()> {
            self.ask(SdoJob::Download { node, addr, data: data.to_vec(), opts: opts.clone() }).map(|_| ())
        }
        fn nmt(&mut self, _: crate::canopen::nmt::Command, _: u8) -> Result<()> {
            Err(self.not_here())
        }
        fn send_frame(&mut self, _: &Frame) -> Result<()> {
            Err(self.not_here())
        }
        fn sees_traffic(&self) -> bool {
            false
        }
        fn recv_frame(&mut self, _: Instant) -> Result<Option<Frame>> {
            Err(self.not_here())
        }
        /// The coordinator's bus's clock: it moves only while the coordinator runs a batch.
        fn now(&self) -> Instant {
            *self.clock.lock().unwrap_or_else(|e| e.into_inner())
        }
        fn sleep_until(&mut self, _: Instant) -> Result<()> {
            Err(self.not_here())
        }
        fn request_frame(&mut self, _: u16, _: u8, _: Duration) -> Result<Frame> {
            Err(self.not_here())
        }
        fn lss_exchange(&mut self, _: &[u8; 8], _: u8, _: Duration, _: LssWait) -> Result<Vec<LssAnswer>> {
            Err(self.not_here())
        }
        fn observed(&mut self) -> &mut Observed {
            &mut self.observed
        }
        fn close(&mut self) -> Result<()> {
            Ok(())
        }
    }

    /// A link failure, said to every node whose transfer it ended.
    fn link_lost(bus: &str, e: &Error) -> Error {
        let error = std::io::Error::other(e.to_string());
        Error::Link(crate::error::LinkError::Io { port: bus.to_string(), op: "", error })
    }

    /// `work` for each of `items` (node indexes), up to `jobs` at once; `stopped` stands
    /// for a node whose procedure ended without its result (a bug), so that the run still
    /// ends. Results in the order of `items`; after a link failure or once `stop` is set,
    /// no further node is begun, and those are left out.
    pub(super) fn each<T: Send + Summary>(
        bus: &mut dyn Bus,
        items: &[(usize, u8)],
        jobs: usize,
        stop: &Cancel,
        work: &(dyn Fn(&mut dyn Bus, usize) -> T + Sync),
        stopped: &(dyn Fn(usize, Error) -> T + Sync),
        progress: &mut dyn Progress,
    ) -> Vec<(usize, T)> {
        let describe = bus.describe();
        let (tx, rx): (Sender<Msg<T>>, Receiver<Msg<T>>) = channel();
        let mut done = Vec::new();
        let mut lost: Option<Error> = None;
        // Each node's transfers so far, for its progress bar.
        let mut counts: BTreeMap<u8, (u32, u32)> = BTreeMap::new();
        let clock = Arc::new(Mutex::new(bus.now()));
        std::thread::scope(|scope| {
            let mut queue = items.iter().map(|(i, _)| *i);
            let mut running = 0;
            let start = |i: usize| {
                let node_bus = NodeBus {
                    describe: describe.clone(),
                    to_coordinator: tx.clone(),
                    clock: Arc::clone(&clock),
                    observed: Observed::default(),
                };
                scope.spawn(move || {
                    let mut node_bus = node_bus;
                    // Whatever happens, the coordinator hears that this node is done: it
                    // waits for every running node.
                    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work(&mut node_bus, i)))
                        .unwrap_or_else(|_| {
                            let why = Error::Usage(
                                "canctl's procedure for this node stopped (a bug: please report it)".into(),
                            );
                            stopped(i, link_lost(&node_bus.describe, &why))
                        });
                    let _ = node_bus.to_coordinator.send(Msg::Done(i, result));
                });
            };
            for i in queue.by_ref().take(jobs) {
                start(i);
                running += 1;
            }
            let mut waiting: Vec<(SdoJob, Sender<Result<Vec<u8>>>)> = Vec::new();
            while running > 0 {
                // Every running node either waits for a transfer or has finished.
                while waiting.len() < running {
                    match rx.recv().expect("a running node sends before it ends") {
                        Msg::Sdo(job, reply) => {
                            let (node, write) = match &job {
                                SdoJob::Upload { node, .. } => (*node, false),
                                SdoJob::Download { node, .. } => (*node, true),
                            };
                            let count = counts.entry(node).or_default();
                            if write {
                                count.1 += 1;
                            } else {
                                count.0 += 1;
                            }
                            progress.item(&node_label(node), &transfers(count.0, count.1), false);
                            waiting.push((job, reply));
                        }
                        Msg::Done(i, result) => {
                            if let Some((_, node)) = items.iter().find(|(x, _)| *x == i) {
                                progress.item(&node_label(*node), &result.summary(), true);
                            }
                            done.push((i, result));
                            progress.advance(done.len() as u64);
                            running -= 1;
                            let stopping = stop.is_cancelled();
                            if let Some(next) = queue.next().filter(|_| lost.is_none() && !stopping) {
                                start(next);
                                running += 1;
                            }
                        }
                    }
                }
                if waiting.is_empty() {
                    continue;
                }
                let jobs: Vec<SdoJob> = waiting.iter().map(|(job, _)| job.clone()).collect();
                let results = bus.sdo_many(&jobs);
                *clock.lock().unwrap_or_else(|e| e.into_inner()) = bus.now();
                match results {
                    Ok(results) => {
                        for ((_, reply), result) in waiting.drain(..).zip(results) {
                            let _ = reply.send(result);
                        }
                    }
                    Err(e) => {
                        for (_, reply) in waiting.drain(..) {
                            let _ = reply.send(Err(link_lost(&describe, &e)));
                        }
                        lost.get_or_insert(e);
                    }
                }
            }
        });
        let order = |i: &usize| items.iter().position(|(x, _)| x == i);
        done.sort_by_key(|(i, _)| order(i));
        done
    }
}

/// NMT reset `nodes`, then wait until each is back: its boot-up message where the link shows
/// the bus's traffic, else an SDO answer. Whether each came back within `boot_wait`.
fn reset_and_wait(bus: &mut dyn Bus, nodes: &[u8], o: &ApplyOptions) -> Result<BTreeMap<u8, bool>> {
    let mut back: BTreeMap<u8, bool> = nodes.iter().map(|n| (*n, false)).collect();
    for n in nodes {
        bus.observed().boot_ups.remove(n);
        bus.nmt(crate::canopen::nmt::Command::ResetNode, *n)?;
    }
    let deadline = bus.now() + o.boot_wait;
    if bus.sees_traffic() {
        while back.values().any(|b| !b) {
            let frame = bus.recv_frame(deadline)?;
            for (n, b) in back.iter_mut() {
                *b |= bus.observed().boot_ups.contains(n);
            }
            if frame.is_none() {
                break;
            }
        }
    } else {
        for n in nodes {
            while bus.now() < deadline {
                match bus.sdo_upload(*n, DEVICE_TYPE, &SdoOptions::new(o.window)) {
                    Ok(_) | Err(Error::SdoAbort { .. }) => {
                        back.insert(*n, true);
                        break;
                    }
                    Err(e) if no_answer(&e) => continue,
                    Err(e) => return Err(e),
                }
            }
        }
    }
    Ok(back)
}

/// A listed node that did not answer the probe: given its node-id over LSS when asked (and
/// its DCF names an LSS identity), else failed.
fn absent_node(bus: &mut dyn Bus, listed: &Listed, o: &ApplyOptions) -> NodeOutcome {
    let mut row = empty_row(listed);
    let fail = |mut row: NodeApplied, e: Error| {
        row.result = format!("failed: {e}");
        (row, Some(e))
    };
    match listed.lss_identity() {
        Some(id) if o.assign && o.config.dry_run => {
            row.assigned = Some(id.to_string());
            row.result = format!("would be looked for over LSS ({id}) and given node-id {}", listed.node);
            row.ok = true;
            row.outcome = Outcome::Done;
            (row, None)
        }
        Some(id) if o.assign => match assign(bus, &id, listed.node, o) {
            Ok(()) => {
                row.assigned = Some(id.to_string());
                row.ok = true;
                row.outcome = Outcome::Done;
                (row, None)
            }
            Err(e) => fail(row, e),
        },
        Some(id) => {
            let what = Service::ProjectNode { lss: Some(id) };
            let e = Error::NoAnswer { node: listed.node, what, waited: o.window };
            fail(row, e)
        }
        None => {
            let what = Service::ProjectNode { lss: None };
            let e = Error::NoAnswer { node: listed.node, what, waited: o.window };
            fail(row, e)
        }
    }
}

// ---------------------------------------------------------------------------------------
// set-baud

/// How to switch a network's bit rate.
#[derive(Clone, Debug)]
pub struct SetBaudOptions {
    /// How long to collect the devices' LSS answers.
    pub timeout: Duration,
    /// How long the probes before and after the switch wait for answers.
    pub window: Duration,
    /// The new bit rate: its index in the CiA 305 table.
    pub index: u8,
    /// CiA 305 switch delay: the devices wait this long, switch, and wait as long again
    /// before they transmit.
    pub delay_ms: u16,
    /// Make the devices keep the new rate across power cycles ("store configuration").
    pub store: bool,
    /// Activate even when some device refused the new rate (it is left behind).
    pub force: bool,
    /// Set when the user asks to stop: checked before each LSS step; nothing is switched
    /// once it is set before the activation.
    pub interrupted: Cancel,
}

/// One node expected to follow the switch.
#[derive(Debug, Serialize)]
pub struct NodeFollowed {
    pub node: u8,
    pub name: String,
    /// Whether it answered the probe before the switch.
    pub before: bool,
    /// Whether it answers at the new rate; `None` where the link could not look (it stays
    /// at the old rate).
    pub after: Option<bool>,
    /// What happened, in a sentence.
    pub result: String,
}

/// What a network-wide bit-rate switch did.
#[derive(Debug, Serialize)]
pub struct BaudSwitched {
    pub bus: String,
    /// The new rate (`250k`).
    pub rate: String,
    /// Where the expected nodes come from: the project file, or the probe before the switch.
    pub expected_from: String,
    /// "configure bit timing", sent to every device in configuration state.
    pub configured: LssTally,
    /// "store configuration", when asked.
    pub stored: Option<LssTally>,
    /// Whether "activate bit timing" was sent.
    pub activated: bool,
    /// Why it was not, in words.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_activated: Option<String>,
    pub delay_ms: u16,
    /// Whether the link switched with the devices (the simulated bus does; a CAN interface
    /// or an EPOS2 must be switched by its owner).
    pub bus_followed: bool,
    pub nodes: Vec<NodeFollowed>,
    /// Nodes answering at the new rate that were not expected.
    pub unexpected: Vec<u8>,
    /// Devices without a node-id that answered LSS before and after the switch.
    pub unconfigured_before: usize,
    pub unconfigured_after: Option<usize>,
    /// Whether every expected node is confirmed at the new rate.
    pub ok: bool,
    /// Why it is not (its exit code is the command's).
    #[serde(skip)]
    pub failure: Option<Error>,
}

impl BaudSwitched {
    pub fn outcome(self) -> Result<()> {
        match self.failure {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

/// Switch every device on the bus to a new bit rate (CiA 305, LSS global): all into
/// configuration state, "configure bit timing", "store configuration" when asked, then
/// "activate bit timing" with the switch delay; the devices go quiet, switch after the
/// delay and wait as long again, during which nothing is sent. Where the link switched with
/// them, the devices are sent back to waiting state and the bus is probed again: every
/// expected node (the project's, else those found before) that does not answer at the new
/// rate is reported. A device refusing the rate stops the switch before anything is
/// activated, unless `force`.
pub fn set_baud(
    bus: &mut dyn Bus,
    project: Option<&Loaded>,
    o: &SetBaudOptions,
    progress: &mut dyn Progress,
) -> Result<BaudSwitched> {
    let stop = || o.interrupted.is_cancelled();
    if stop() {
        return Err(Error::Interrupted);
    }
    let rate = crate::canopen::lss::bit_rate_name(o.index);
    let before = probe(bus, o.window, progress)?;
    let unconfigured_before = crate::bus::lss::count_unconfigured(bus, o.window)?;
    let (expected, expected_from): (Vec<(u8, String)>, String) = match project {
        Some(p) => (p.nodes.iter().map(|l| (l.node, l.name.clone())).collect(), p.file.display().to_string()),
        None => (before.keys().map(|n| (*n, String::new())).collect(), "the probe before the switch".into()),
    };
    let mut report = BaudSwitched {
        bus: bus.describe(),
        rate: rate.clone(),
        expected_from,
        configured: LssTally::default(),
        stored: None,
        activated: false,
        not_activated: None,
        delay_ms: o.delay_ms,
        bus_followed: false,
        nodes: expected
            .iter()
            .map(|(node, name)| NodeFollowed {
                node: *node,
                name: name.clone(),
                before: before.contains_key(node),
                after: None,
                result: String::new(),
            })
            .collect(),
        unexpected: Vec::new(),
        unconfigured_before,
        unconfigured_after: None,
        ok: false,
        failure: None,
    };
    let not_switched = |report: &mut BaudSwitched, e: Error, why: &str| {
        for n in &mut report.nodes {
            n.result = "not switched".to_string();
        }
        report.not_activated = Some(why.to_string());
        report.failure = Some(e);
    };

    let mut m = LssMaster::new(bus, o.timeout);
    m.enter(None)?;
    let answers = match m.ask(Request::ConfigureBitTiming { table: 0, index: o.index }, LssWait::All) {
        Ok(a) => a,
        Err(e) => {
            m.leave()?;
            return Err(e);
        }
    };
    report.configured = LssTally::of(&answers, "configure bit timing");
    let refused = report.configured.first_refusal.take();
    if report.configured.confirmed == 0 {
        m.leave()?;
        let e = match refused {
            Some(e) => e,
            None => Error::NoLssAnswer { request: "configure bit timing".into(), identity: None, waited: o.timeout },
        };
        not_switched(&mut report, e, "no device took the new rate");
        return Ok(report);
    }
    if let Some(e) = refused.filter(|_| !o.force) {
        m.leave()?;
        let why = format!(
            "{} device(s) refused {rate} (--force switches the others and leaves them behind)",
            report.configured.refused.len()
        );
        not_switched(&mut report, e, &why);
        return Ok(report);
    }
    if stop() {
        m.leave()?;
        not_switched(&mut report, Error::Interrupted, "interrupted before the activation");
        return Ok(report);
    }
    if o.store {
        let answers = match m.ask(Request::StoreConfiguration, LssWait::All) {
            Ok(a) => a,
            Err(e) => {
                m.leave()?;
                return Err(e);
            }
        };
        report.stored = Some(LssTally::of(&answers, "store configuration"));
        // Those that stored it boot at the new rate from now on: the running bus must
        // follow them, so an interruption here no longer stops the switch.
    }
    m.send(Request::ActivateBitTiming { delay_ms: o.delay_ms })?;
    report.activated = true;
    // CiA 305: each device switches after the delay and is silent until the delay has
    // passed a second time; the master sends nothing in between either.
    let link = m.bus();
    link.sleep_until(link.now() + Duration::from_millis(2 * u64::from(o.delay_ms)))?;
    report.bus_followed = m.bus().follows_bit_rate_switch();
    if !report.bus_followed {
        // Only a link at the new rate reaches the devices again; they stay in
        // configuration state until an LSS command does.
        for n in &mut report.nodes {
            n.result = format!("not checked: {} stays at the old rate", report.bus);
        }
        report.ok = false;
        return Ok(report);
    }
    m.leave()?;
    let after = probe(bus, o.window, progress)?;
    report.unconfigured_after = Some(crate::bus::lss::count_unconfigured(bus, o.window)?);
    let mut behind = Vec::new();
    for n in &mut report.nodes {
        let here = after.contains_key(&n.node);
        n.after = Some(here);
        n.result = match (n.before, here) {
            (_, true) => format!("answers at {rate}"),
            (true, false) => {
                behind.push(n.node);
                format!("did not follow: answered before the switch, not at {rate}")
            }
            (false, false) => {
                behind.push(n.node);
                "not found: did not answer before the switch nor after it".to_string()
            }
        };
    }
    report.unexpected = after.keys().filter(|n| !expected.iter().any(|(e, _)| e == *n)).copied().collect();
    report.ok = behind.is_empty();
    if !behind.is_empty() {
        report.failure = Some(Error::NotFollowed { rate, nodes: behind });
    } else if stop() {
        report.failure = Some(Error::Interrupted);
    }
    Ok(report)
}

/// The project's DCFs with `[DeviceComissioning] Baudrate` set to `kbit`: each file's new
/// bytes, all made before any is written (the caller writes each atomically).
pub fn with_bit_rate(loaded: &Loaded, kbit: u32) -> Result<Vec<(PathBuf, Vec<u8>)>> {
    let mut out = Vec::new();
    for listed in &loaded.nodes {
        let Some(path) = loaded.project.dcf_path(&loaded.file, listed.node) else { continue };
        let name = path.display().to_string();
        let bytes = crate::input::read_regular_file(&path, crate::input::EDS)
            .map_err(|e| Error::Usage(format!("cannot use {name}: {e}")))?;
        let mut c = cpj::read_commissioning(&bytes, &name).map_err(|e| Error::Usage(format!("cannot use {e}")))?;
        c.baudrate_kbit = Some(kbit);
        let new = cpj::with_commissioning(&bytes, &c).map_err(|e| Error::Usage(e.to_string()))?;
        out.push((path, new));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::{BusAddr, OpenOptions};

    fn demo() -> Box<dyn Bus> {
        let mut opts = OpenOptions::new(Duration::from_millis(500));
        opts.ephemeral = true;
        crate::bus::open(&"sim".parse::<BusAddr>().unwrap(), &opts).unwrap()
    }

    fn example() -> Loaded {
        load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/sim-machine/nodelist.cpj")).unwrap()
    }

    /// Sets the stop flag once `after` nodes are done (or begun, one after the other), in
    /// the applying phase (the probe before it has its own).
    struct StopAfter {
        flag: Cancel,
        after: u64,
        applying: bool,
    }

    impl Progress for StopAfter {
        fn start(&mut self, what: &str, _: u64) {
            self.applying = what == "applying";
        }
        fn advance(&mut self, done: u64) {
            if self.applying && done >= self.after {
                self.flag.cancel();
            }
        }
    }

    /// Sets the flag once the probe before the switch is over.
    struct StopAfterProbe(Cancel);

    impl Progress for StopAfterProbe {
        fn finish(&mut self) {
            self.0.cancel();
        }
    }

    fn set_baud_options(flag: &Cancel) -> SetBaudOptions {
        SetBaudOptions {
            timeout: Duration::from_millis(200),
            window: Duration::from_millis(100),
            index: 3,
            delay_ms: 5,
            store: false,
            force: true,
            interrupted: flag.clone(),
        }
    }

    /// Interrupted before the activation, nothing is switched: every device back in waiting
    /// state at the old rate, the run reported as interrupted.
    #[test]
    fn set_baud_interrupted_before_the_activation_switches_nothing() {
        let flag = Cancel::new();
        let mut bus = demo();
        let report = set_baud(bus.as_mut(), None, &set_baud_options(&flag), &mut StopAfterProbe(flag.clone())).unwrap();
        assert!(!report.activated);
        assert!(matches!(report.failure, Some(Error::Interrupted)));
        assert_eq!(report.configured.confirmed, 6, "the stepper refuses, the others confirm");
        let still: Vec<u8> =
            probe(bus.as_mut(), Duration::from_millis(100), &mut super::super::Silent).unwrap().into_keys().collect();
        assert_eq!(still, [1, 5, 10, 32]);
    }

    /// Forced past the stepper's refusal: the others switch, the bus with them, and the
    /// stepper is named as left behind.
    #[test]
    fn set_baud_names_the_node_left_behind() {
        let flag = Cancel::new();
        let mut bus = demo();
        let report = set_baud(bus.as_mut(), None, &set_baud_options(&flag), &mut super::super::Silent).unwrap();
        assert!(report.activated && report.bus_followed);
        assert!(matches!(&report.failure, Some(Error::NotFollowed { nodes, .. }) if nodes == &[32]));
        let after: Vec<(u8, Option<bool>)> = report.nodes.iter().map(|n| (n.node, n.after)).collect();
        assert_eq!(after, [(1, Some(true)), (5, Some(true)), (10, Some(true)), (32, Some(false))]);
    }

    /// An interruption stops between nodes, one after the other or several at once: the
    /// nodes under way finish, the others are reported as not begun, and the run ends as
    /// interrupted.
    #[test]
    fn an_interruption_stops_between_nodes_and_says_which_were_not_done() {
        for jobs in [1, 2] {
            let flag = Cancel::new();
            let loaded = example();
            let mut o = ApplyOptions {
                config: config::ApplyOptions::new(Duration::from_millis(500)),
                assign: false,
                window: Duration::from_millis(100),
                boot_wait: Duration::from_secs(1),
                jobs,
                reset: false,
                interrupted: flag.clone(),
            };
            o.config.verify = true;
            let mut bus = demo();
            let report = apply(bus.as_mut(), &loaded, &o, &mut StopAfter { flag, after: 1, applying: false }).unwrap();
            let done: Vec<u8> = report.nodes.iter().filter(|n| n.ok).map(|n| n.node).collect();
            let not_begun: Vec<u8> =
                report.nodes.iter().filter(|n| n.result.starts_with("not done: interrupted")).map(|n| n.node).collect();
            // The demo network has nodes 1, 5, 10 and 32; 20 to 24 wait for --assign.
            assert_eq!(done, [1, 5], "--jobs {jobs}: {:?}", report.nodes.iter().map(|n| &n.result).collect::<Vec<_>>());
            assert_eq!(not_begun, [10, 32], "--jobs {jobs}");
            assert!(matches!(report.failure, Some(Error::Interrupted)));
            assert!(!report.ok);
        }
    }
}
