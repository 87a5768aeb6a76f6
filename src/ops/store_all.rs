//! `store` and `restore` over several nodes, one after the other, and a restore chained
//! with the reset that makes the defaults apply (and the wait for the node's boot-up).
//! Stopped part-way, the run says what was done on the node under way and the state it is
//! left in; the caller words the nodes not begun.

use super::nmt::{self, ResetOptions};
use super::store::{self, Class, Restored, Stored, Timeouts};
use super::Stopped;
use crate::bus::Bus;
use crate::canopen::nmt::Command;
use crate::error::Error;
use crate::hint::Hint;
use std::time::Duration;

/// How a node's turn ended, when not with its report.
#[derive(Debug)]
#[non_exhaustive]
pub enum Ended {
    /// The user stopped it: what was done on this node, what was not.
    Stopped(Stopped),
    /// It failed: the first failure ends the run.
    Failed(Error),
}

impl From<Error> for Ended {
    fn from(e: Error) -> Ended {
        Ended::Failed(e)
    }
}

/// What became of a run over several nodes: the reports of the nodes done, in the order
/// asked; when the run ended early, how, on the node after them (`nodes[done.len()]`).
#[derive(Debug)]
pub(crate) struct EachNode<R> {
    /// The reports of the nodes done.
    pub done: Vec<R>,
    /// How the run ended on the next node, when it did not get through them all.
    pub ended: Option<Ended>,
}

fn each_node<R>(nodes: &[u8], mut one: impl FnMut(u8) -> Result<R, Ended>) -> EachNode<R> {
    let mut done = Vec::new();
    for &node in nodes {
        match one(node) {
            Ok(report) => done.push(report),
            Err(ended) => return EachNode { done, ended: Some(ended) },
        }
    }
    EachNode { done, ended: None }
}

/// Store `class` on each of `nodes` in turn (0x1010).
pub(crate) fn store_nodes(bus: &mut dyn Bus, nodes: &[u8], class: Class, t: Timeouts) -> EachNode<Stored> {
    each_node(nodes, |node| match store::store(bus, node, class, t) {
        Ok(report) => Ok(report),
        Err(e) if e.is_interrupted() => {
            let not_done = vec![format!("'save' to 0x1010:{} of node {node}", class as u8 + 1)];
            let state = format!("nothing was stored on node {node}: its non-volatile memory is as it was");
            Err(Ended::Stopped(Stopped::new("store", Vec::new(), not_done, state)))
        }
        Err(e) => Err(e.into()),
    })
}

/// Restore `class` on each of `nodes` in turn (0x1011); with `reset`, reset each node then
/// and wait (at least 2 s, or the write timeout) for it to boot with the defaults.
pub(crate) fn restore_nodes(
    bus: &mut dyn Bus,
    nodes: &[u8],
    class: Class,
    t: Timeouts,
    reset: bool,
) -> EachNode<Restored> {
    each_node(nodes, |node| restore_one(bus, node, class, t, reset))
}

fn restore_one(bus: &mut dyn Bus, node: u8, class: Class, t: Timeouts, reset: bool) -> Result<Restored, Ended> {
    let stopped =
        |done: Vec<String>, not_done: Vec<String>, state: String| Stopped::new("restore", done, not_done, state);
    let mut report = match store::restore(bus, node, class, t) {
        Ok(report) => report,
        Err(e) if e.is_interrupted() => {
            let not_done = vec![format!("'load' to 0x1011:{} of node {node}", class as u8 + 1)];
            let state = format!("nothing was changed: node {node} keeps its parameters");
            return Err(Ended::Stopped(stopped(Vec::new(), not_done, state)));
        }
        Err(e) => return Err(e.into()),
    };
    if !reset {
        return Ok(report);
    }
    report.reset = true;
    let o = ResetOptions { wait: t.write.max(Duration::from_secs(2)), timeout: t.answer };
    let done = vec![format!("node {node}: 'load' written to {}", report.object)];
    match nmt::reset(bus, Command::ResetNode, node, &o) {
        Ok(r) if r.interrupted => {
            let not_done = vec![format!("confirming that node {node} booted")];
            let state = format!(
                "node {node}: the defaults are loaded and the reset went out; whether it booted with them is not \
                 known"
            );
            let report = stopped([done, vec![format!("NMT reset of node {node}")]].concat(), not_done, state);
            Err(Ended::Stopped(report.with_remedy(Hint::ReadNmtState { node })))
        }
        Ok(r) if !r.confirmed => {
            report.reset_unconfirmed = r.why;
            Ok(report)
        }
        Ok(_) => Ok(report),
        Err(e) if e.is_interrupted() => {
            let not_done = vec![format!("NMT reset of node {node}")];
            let state = format!("node {node}: the defaults are loaded and apply from its next reset");
            Err(Ended::Stopped(stopped(done, not_done, state).with_remedy(Hint::ResetNode { node })))
        }
        Err(e) => Err(e.into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::connect::{BusAddr, OpenOptions};

    fn demo(timeout: Duration) -> Box<dyn Bus> {
        let mut opts = OpenOptions::new(timeout);
        opts.ephemeral = true;
        crate::connect::open(&"sim".parse::<BusAddr>().unwrap(), &opts).unwrap()
    }

    /// Each node in the order asked; a restore with reset waits for the boot-up.
    #[test]
    fn every_node_is_done_in_turn_and_a_reset_is_confirmed() {
        let t = Timeouts { answer: Duration::from_millis(500), write: Duration::from_secs(5) };
        let mut bus = demo(t.answer);
        let stored = store_nodes(bus.as_mut(), &[5, 10], Class::All, t);
        assert!(stored.ended.is_none(), "{:?}", stored.ended);
        assert_eq!(stored.done.iter().map(|s| s.node).collect::<Vec<_>>(), [5, 10]);
        let restored = restore_nodes(bus.as_mut(), &[5], Class::All, t, true);
        assert!(restored.ended.is_none(), "{:?}", restored.ended);
        let r = &restored.done[0];
        assert!(r.reset && r.reset_unconfirmed.is_none(), "{r:?}");
    }

    /// The first node that fails ends the run: the nodes before it are reported, the ones
    /// after it not begun.
    #[test]
    fn the_first_failure_ends_the_run_after_the_nodes_done() {
        let t = Timeouts { answer: Duration::from_millis(100), write: Duration::from_millis(500) };
        let mut bus = demo(t.answer);
        let run = store_nodes(bus.as_mut(), &[5, 99, 10], Class::All, t);
        assert_eq!(run.done.iter().map(|s| s.node).collect::<Vec<_>>(), [5]);
        assert!(matches!(run.ended, Some(Ended::Failed(Error::NoAnswer { .. }))), "{:?}", run.ended);
    }
}
