//! `network apply`: every listed node brought to its DCF, node-ids over LSS first.

use crate::bus::lss::LssMaster;
use crate::bus::Bus;
use crate::cancel::Cancel;
use crate::canopen::lss::{Identity, Request};
use crate::error::{Error, Result, Service};
use crate::ops::back;
use crate::ops::config;
use crate::ops::progress::{ItemEnd, Progress};
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Duration;

use super::check::{matches, unlisted, Unlisted};
use super::parallel::{self, node_label, End};
use super::project::{probe, Listed, Loaded};
use super::report::{NodeApplied, NodeCheck, NodeResult, Outcome};
use crate::ops::unmet::{NetworkDifference, Shortfall, Unmet};

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
#[non_exhaustive]
pub struct Applied {
    /// The project file, as named.
    pub project: String,
    /// The bus, as it describes itself.
    pub bus: String,
    /// Nothing was written: `nodes` says what would be.
    pub dry_run: bool,
    /// Each node the project lists, by node-id.
    pub nodes: Vec<NodeApplied>,
    /// Objects written on the whole network.
    pub written: usize,
    /// Nodes that answered but the project does not list: apply cannot make them match.
    pub unlisted: Vec<Unlisted>,
    /// Whether the network now matches the project ([`matches`]): every node brought to
    /// its DCF, none unlisted.
    pub ok: bool,
    /// The first failure, or the verdict (its exit code is the command's).
    #[serde(skip)]
    pub failure: Option<Shortfall>,
}

impl Applied {
    /// The command's outcome: Ok when the network matches the project, else the first failure, or a verification error (exit 6).
    pub fn outcome(self) -> Result<(), Shortfall> {
        self.failure.map_or(Ok(()), Err)
    }
}

/// Give `node` to the LSS device with `identity`, store it, and wait until the node answers
/// SDO with it.
fn assign(bus: &mut dyn Bus, identity: &Identity, node: u8, o: &ApplyOptions) -> Result<()> {
    let mut m = LssMaster::new(bus, o.config.timeout);
    let result = m
        .enter(Some(identity))
        .and_then(|_| match m.others_configuring()? {
            true => Err(Error::LssCrowded { identity: *identity, times: 1 }),
            false => Ok(()),
        })
        .and_then(|_| m.configure(Request::ConfigureNodeId(node), "set-id", false))
        .and_then(|_| m.configure(Request::StoreConfiguration, "store", false));
    // Back in waiting state the device takes its new node-id and boots; left in
    // configuration state (the switch lost), it would take the next device's node-id too.
    let left = match result {
        Ok(_) => m.back_to_waiting(*identity, node),
        Err(_) => m.leave(),
    };
    result?;
    left?;
    // Back in the sense that matters here: it answers at the node-id it was given (a
    // boot-up would prove a reset, not that).
    let deadline = bus.now() + o.boot_wait;
    if back::until_answering(bus, node, deadline, o.window, None)? {
        return Ok(());
    }
    let what = Service::AfterLssAssign { identity: *identity };
    Err(Error::NoAnswer { node, what, waited: o.boot_wait })
}

/// A node's row, and the error that failed it.
type NodeOutcome = (NodeApplied, Option<Error>);

fn empty_row(listed: &Listed) -> NodeApplied {
    NodeApplied { node: listed.node, name: listed.name.clone(), file: listed.file(), ..NodeApplied::default() }
}

/// One node that answers: `config apply` (only what differs, in its safe order, verified
/// when asked), then store when anything was written.
fn configure_node(bus: &mut dyn Bus, listed: &Listed, o: &ApplyOptions) -> NodeOutcome {
    let mut row = empty_row(listed);
    let Some(dcf) = &listed.dcf else {
        return (NodeApplied { ok: true, outcome: Outcome::Done, result: NodeResult::NoDcf, ..row }, None);
    };
    let mut co = o.config.clone();
    co.store = false;
    let mut applied = match config::apply(bus, listed.node, dcf, &co) {
        Ok(a) => a,
        Err(e) => return failed(row, e),
    };
    row.written = applied.written.len();
    row.objects = std::mem::take(&mut applied.objects);
    let would = row.objects.iter().filter(|c| c.result.action == config::Action::WouldWrite).count();
    if applied.interrupted {
        // Stopped between two transfers, a PDO change under way put back: what was done,
        // what was not, and the state the node is left in, as `config apply` says it.
        // (Its objects are the row's by now, so what was planned and not written is told by
        // them, not again here.)
        let incomplete = applied.incomplete().unwrap_or_default();
        let not_stored = o.config.store && !o.config.dry_run && row.written > 0;
        row.result = NodeResult::Interrupted { incomplete, not_stored };
        let changed = row.written > 0 || !applied.rolled_back.is_empty() || !applied.to_fix.is_empty();
        row.outcome = if changed { Outcome::StoppedPartWay } else { Outcome::StoppedUnchanged };
        return (row, Some(Error::Interrupted));
    }
    if let Err(e) = applied.outcome() {
        return failed(row, e);
    }
    if o.config.store && row.written > 0 {
        if o.config.interrupted.is_cancelled() {
            row.result = NodeResult::StoppedBeforeStore { written: row.written, verified: o.config.verify };
            row.outcome = Outcome::StoppedPartWay;
            return (row, Some(Error::Interrupted));
        }
        let t = crate::ops::store::Timeouts { answer: o.config.timeout, write: o.config.store_timeout };
        match crate::ops::store::store(bus, listed.node, crate::ops::store::Class::All, t) {
            Ok(_) => row.stored = true,
            Err(e) => return failed(row, e),
        }
    }
    row.ok = true;
    row.outcome = Outcome::Done;
    row.result = if o.config.dry_run {
        NodeResult::WouldWrite { count: would }
    } else {
        NodeResult::Written { count: row.written, verified: o.config.verify, stored: row.stored }
    };
    (row, None)
}

/// `row`, failed with `e`.
fn failed(mut row: NodeApplied, e: Error) -> NodeOutcome {
    row.result = NodeResult::Failed;
    row.failure = Some((&e).into());
    (row, Some(e))
}

/// Bring every listed node to its DCF: first the node-ids over LSS (one device at a time,
/// as LSS works), then up to `jobs` nodes at once, their SDO transfers in flight together on
/// the one link. A node that fails is reported and the others still done; the first
/// failure decides the exit code.
pub fn apply(bus: &mut dyn Bus, loaded: &Loaded, o: &ApplyOptions, progress: &mut dyn Progress) -> Result<Applied> {
    let found = probe(bus, o.window, progress)?;
    // Nodes that must answer before they can be configured: given their id, or failed.
    let stop = || o.interrupted.is_cancelled();
    let absent = |listed: &Listed| !found.contains_key(&listed.node) && !stop();
    let mut rows: Vec<Option<NodeOutcome>> =
        loaded.nodes.iter().map(|listed| absent(listed).then(|| absent_node(bus, listed, o))).collect();
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
            let result = {
                let mut counted = crate::ops::counted::counted(&mut *bus, &label, progress);
                configure_node(&mut counted, &loaded.nodes[*i], o)
            };
            progress.item_ended(&label, result.end());
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
        let stopped = |i: usize, e: Error| failed(empty_row(&loaded.nodes[i]), e);
        let items: Vec<(usize, u8)> = ready.iter().map(|i| (*i, loaded.nodes[*i].node)).collect();
        parallel::each(bus, &items, o.jobs, &o.interrupted, &work, &stopped, progress)
    };
    progress.finish();
    let configured: Vec<usize> = done.iter().map(|(i, _)| *i).collect();
    for (i, (mut row, error)) in done {
        row.assigned.clone_from(&assigned[i]);
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
            row.reset = back.get(&row.node).copied();
            if row.reset == Some(false) {
                row.ok = false;
                error.get_or_insert(Error::NoAnswer { node: row.node, what: Service::BootUp, waited: o.boot_wait });
            }
        }
    }
    let interrupted = stop();
    let mut nodes = Vec::new();
    let mut failure = interrupted.then_some(Shortfall::Failed(Error::Interrupted));
    for (i, outcome) in rows.into_iter().enumerate() {
        match outcome {
            // Given its node-id over LSS, then not configured: stopped by the user, or the
            // link was lost, before this node was begun.
            Some((row, None)) if ready.contains(&i) && !configured.contains(&i) => {
                let result = NodeResult::NotConfigured { interrupted };
                let outcome = if interrupted { Outcome::NotBegun } else { Outcome::Failed };
                nodes.push(NodeApplied { result, outcome, ok: false, ..row });
            }
            Some((row, error)) => {
                failure = failure.or_else(|| error.map(Shortfall::from));
                nodes.push(row);
            }
            // Not begun: interrupted first, or the link was lost.
            None if interrupted => {
                let (result, outcome) = (NodeResult::NotBegun, Outcome::NotBegun);
                nodes.push(NodeApplied { result, outcome, ..empty_row(&loaded.nodes[i]) });
            }
            None => {}
        }
    }
    let written = nodes.iter().map(|n| n.written).sum();
    let unlisted = unlisted(&found, loaded);
    if !unlisted.is_empty() {
        let answering = unlisted.iter().map(|u| u.node).collect();
        failure.get_or_insert(Shortfall::Unmet(Unmet::NetworkDiffers {
            bus: bus.describe(),
            project: loaded.file.display().to_string(),
            differences: vec![NetworkDifference::AnswerNotInProject(answering)],
        }));
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

impl End for NodeOutcome {
    fn end(&self) -> ItemEnd<'_> {
        ItemEnd::Applied(&self.0)
    }
}

impl End for Result<NodeCheck> {
    fn end(&self) -> ItemEnd<'_> {
        ItemEnd::Checked(self)
    }
}

/// NMT reset `nodes`, then wait until each is back (`ops::back`): whether each came back
/// within `boot_wait`.
fn reset_and_wait(bus: &mut dyn Bus, nodes: &[u8], o: &ApplyOptions) -> Result<BTreeMap<u8, bool>> {
    back::forget_boot_ups(bus, nodes);
    for n in nodes {
        bus.nmt(crate::canopen::nmt::Command::ResetNode, *n)?;
    }
    back::wait_back(bus, nodes, o.boot_wait, o.window, None)
}

/// A listed node that did not answer the probe: given its node-id over LSS when asked (and
/// its DCF names an LSS identity), else failed.
fn absent_node(bus: &mut dyn Bus, listed: &Listed, o: &ApplyOptions) -> NodeOutcome {
    let mut row = empty_row(listed);
    match listed.lss_identity() {
        Some(id) if o.assign => {
            if o.config.dry_run {
                row.result = NodeResult::WouldAssign;
            } else if let Err(e) = assign(bus, &id, listed.node, o) {
                return failed(row, e);
            }
            row.assigned = Some(id.to_string());
            row.ok = true;
            row.outcome = Outcome::Done;
            (row, None)
        }
        lss => {
            let what = Service::ProjectNode { lss };
            failed(row, Error::NoAnswer { node: listed.node, what, waited: o.window })
        }
    }
}
