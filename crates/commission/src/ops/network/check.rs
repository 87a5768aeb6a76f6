//! `network check`: the bus against the project, node by node.

use crate::bus::Bus;
use crate::cancel::Cancel;
use crate::canopen::ObjAddr;
use crate::error::{Error, Result};
use crate::ops::config::{self, Dcf};
use crate::ops::progress::Progress;
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Duration;

use super::parallel;
use super::project::{probe, Loaded};
use super::report::NodeCheck;
use crate::ops::unmet::{NetworkDifference, Unmet};
use crate::ops::verdict::Remedy;

/// How to check a network.
#[derive(Clone, Debug)]
pub struct CheckOptions {
    /// How long to wait for each SDO answer.
    pub timeout: Duration,
    /// How long the probes wait for answers.
    pub window: Duration,
    /// How many nodes are checked at once (1: one after the other).
    pub jobs: usize,
    /// The NMT state every listed node must be in, when the caller expects one (CiA 306-3
    /// projects do not say).
    pub state: Option<crate::canopen::nmt::State>,
}

/// Is the network as the project says?
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Checked {
    /// The project file, as named.
    pub project: String,
    /// The project's `NetName`; none when it gives none.
    pub net_name: Option<String>,
    /// The bus, as it describes itself.
    pub bus: String,
    /// Each node the project lists, by node-id.
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
pub(super) fn matches(nodes_ok: bool, unlisted: &[Unlisted]) -> bool {
    nodes_ok && unlisted.is_empty()
}

/// The nodes that answered a probe but the project does not list.
pub(super) fn unlisted(found: &BTreeMap<u8, Option<u32>>, loaded: &Loaded) -> Vec<Unlisted> {
    found
        .iter()
        .filter(|(n, _)| !loaded.nodes.iter().any(|l| l.node == **n))
        .map(|(n, t)| Unlisted { node: *n, device_type: *t })
        .collect()
}

pub use crate::ops::verdict::{Finding, Verdict};

/// A node that answered but the project does not list.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Unlisted {
    /// The node-id.
    pub node: u8,
    /// Its device type (0x1000); none when it did not say.
    pub device_type: Option<u32>,
}

impl Checked {
    /// The verdict (exit 6) when anything differs.
    pub fn outcome(&self) -> Result<(), Unmet> {
        if self.ok {
            return Ok(());
        }
        let failed: usize = self.nodes.iter().map(|n| n.checks.iter().filter(|c| !c.ok).count()).sum();
        let mut parts = Vec::new();
        if failed > 0 {
            parts.push(NetworkDifference::ChecksFailed(failed));
        }
        if !self.unlisted.is_empty() {
            parts.push(NetworkDifference::NotInProject(self.unlisted.len()));
        }
        Err(Unmet::NetworkDiffers { bus: self.bus.clone(), project: self.project.clone(), differences: parts })
    }
}

/// The vendor-ID and product code of `node` against the DCF's (parts the DCF leaves at 0
/// are not compared).
fn check_identity(bus: &mut dyn Bus, node: u8, dcf: &Dcf, timeout: Duration) -> Result<Verdict> {
    let (vendor, product) = dcf.identity();
    let parts = crate::ops::node::Node::new(bus, node, timeout).compare_identity(vendor, product)?;
    let (seen, differ): (Vec<_>, Vec<_>) = parts.into_iter().partition(|p| p.matches());
    let file = dcf.path().to_string();
    let (ok, detail) = match (differ.is_empty(), seen.is_empty()) {
        (false, _) => (false, Finding::IdentityDiffers { differ, file }),
        (true, true) => (true, Finding::IdentityUnnamed { file }),
        (true, false) => (true, Finding::IdentityMatches { parts: seen }),
    };
    Ok(Verdict::new("identity", ok, detail))
}

/// Every writable object of the DCF against the node (read-only values such as serial
/// numbers or measurements are the device's, not its configuration).
fn check_objects(bus: &mut dyn Bus, node: u8, dcf: &Dcf, timeout: Duration) -> Result<Verdict> {
    let diff = config::diff(bus, node, dcf, timeout)?;
    let writable = |addr: ObjAddr| dcf.eds.dict.get(addr).is_some_and(|e| e.access.writable());
    let differences: Vec<config::Difference> = diff.differences.into_iter().filter(|d| writable(d.object)).collect();
    let file = dcf.path().to_string();
    let ok = differences.is_empty();
    let detail = if ok { Finding::ObjectsMatch { file } } else { Finding::ObjectsDiffer { file } };
    Ok(Verdict { differences, ..Verdict::new("objects", ok, detail) })
}

/// The node's NMT state against `want`: from its heartbeat, when one was seen in this
/// session, else by node guarding (through an EPOS2: by remote request).
fn check_state(bus: &mut dyn Bus, node: u8, want: crate::canopen::nmt::State, window: Duration) -> Result<Verdict> {
    let wait = (2 * window).max(Duration::from_millis(200));
    let seen = crate::ops::node::Node::new(bus, node, wait).nmt_state(wait)?;
    let (ok, detail) = match seen {
        Some((state, from)) => (state == want, Finding::NetworkState { state, from, want }),
        None => (false, Finding::NoNetworkState { want }),
    };
    Ok(Verdict::new("state", ok, detail))
}

/// Check the bus against the project: each listed node present, with the identity its DCF
/// names and every writable object as the DCF has it; no node the project does not list;
/// no device waiting for a node-id.
pub fn check(bus: &mut dyn Bus, loaded: &Loaded, o: &CheckOptions, progress: &mut dyn Progress) -> Result<Checked> {
    let found = probe(bus, o.window, progress)?;
    let unconfigured = crate::bus::lss::count_unconfigured(bus, o.window)?;
    // A node that answers no SDO may still show its state (a Stopped one beats on).
    let states = bus.observed().states.clone();
    let rounds = crate::ops::scan::probe_rounds(bus);
    let check_node = |bus: &mut dyn Bus, i: usize| -> Result<NodeCheck> {
        let listed = &loaded.nodes[i];
        let present = found.contains_key(&listed.node);
        let (node, window_ms) = (listed.node, o.window.as_millis() as u64);
        let (detail, remedy) = match (present, states.get(&node)) {
            (true, _) => (Finding::Answered { node }, None),
            (false, Some(state)) => (
                Finding::SilentListed { node, state: *state, rounds, window_ms },
                Some(Remedy::PreOperational { node }),
            ),
            (false, None) => (Finding::Absent { node, rounds, window_ms }, None),
        };
        let mut checks = vec![Verdict::new("present", present, detail).with_remedy(remedy)];
        if let (true, Some(dcf)) = (present, &listed.dcf) {
            checks.push(check_identity(bus, node, dcf, o.timeout)?);
            if checks.last().is_some_and(|c| c.ok) {
                checks.push(check_objects(bus, node, dcf, o.timeout)?);
            }
        }
        Ok(NodeCheck { node, name: listed.name.clone(), file: listed.file(), checks })
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
    // A node that answered no probe but beats (a Stopped one) is on the bus all the same.
    let mut on_bus = found;
    for node in states.keys() {
        on_bus.entry(*node).or_insert(None);
    }
    let unlisted = unlisted(&on_bus, loaded);
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
