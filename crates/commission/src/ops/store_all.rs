//! `store` and `restore` over several nodes, one after the other, and a restore chained
//! with the reset that makes the defaults apply (and the wait for the node's boot-up).
//! Stopped part-way, the run says where the node under way was stopped ([`StoppedBefore`]); the
//! caller words it, and the nodes not begun.

use super::nmt::{self, ResetOptions};
use super::store::{self, Class, Restored, Stored, Timeouts};
use crate::bus::Bus;
use crate::canopen::nmt::Command;
use crate::canopen::ObjAddr;
use crate::error::Error;
use std::time::Duration;

/// How a node's turn ended, when not with its report.
#[derive(Debug)]
pub enum Ended {
    /// The user stopped it, at this point.
    Stopped(StoppedBefore),
    /// It failed: the first failure ends the run.
    Failed(Error),
}

/// What the user stopped a node's store or restore before, and so what the node holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StoppedBefore {
    /// Before 'save' was written: nothing was stored, its non-volatile memory is as it was.
    Save {
        /// The node-id.
        node: u8,
        /// Which parameters were to be stored.
        class: Class,
    },
    /// Before 'load' was written: nothing was changed, it keeps its parameters.
    Load {
        /// The node-id.
        node: u8,
        /// Which parameters were to be restored.
        class: Class,
    },
    /// 'load' was written to `object`, and the reset was not sent: the defaults apply from
    /// the node's next reset.
    Reset {
        /// The node-id.
        node: u8,
        /// Where 'load' was written (0x1011:N).
        object: ObjAddr,
    },
    /// 'load' was written to `object` and the reset went out; stopped while waiting for the
    /// boot-up: whether the node booted with the defaults is not known.
    BootUp {
        /// The node-id.
        node: u8,
        /// Where 'load' was written (0x1011:N).
        object: ObjAddr,
    },
}

/// What became of a run over several nodes: the reports of the nodes done, in the order
/// asked; when the run ended early, how, on the node after them (`nodes[done.len()]`).
#[derive(Debug)]
pub struct EachNode<R> {
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
pub fn store_nodes(bus: &mut dyn Bus, nodes: &[u8], class: Class, t: Timeouts) -> EachNode<Stored> {
    each_node(nodes, |node| {
        store::store(bus, node, class, t).map_err(|e| ended(e, StoppedBefore::Save { node, class }))
    })
}

/// Restore `class` on each of `nodes` in turn (0x1011); with `reset`, reset each node then
/// and wait (at least 2 s, or the write timeout) for it to boot with the defaults.
pub fn restore_nodes(bus: &mut dyn Bus, nodes: &[u8], class: Class, t: Timeouts, reset: bool) -> EachNode<Restored> {
    each_node(nodes, |node| restore_one(bus, node, class, t, reset))
}

fn restore_one(bus: &mut dyn Bus, node: u8, class: Class, t: Timeouts, reset: bool) -> Result<Restored, Ended> {
    let mut report = store::restore(bus, node, class, t).map_err(|e| ended(e, StoppedBefore::Load { node, class }))?;
    if !reset {
        return Ok(report);
    }
    report.reset = true;
    let o = ResetOptions { wait: t.write.max(Duration::from_secs(2)), timeout: t.answer };
    let object = report.object;
    match nmt::reset(bus, Command::ResetNode, node, &o) {
        Ok(r) if r.interrupted => Err(Ended::Stopped(StoppedBefore::BootUp { node, object })),
        Ok(r) if !r.confirmed => {
            report.reset_unconfirmed = r.why;
            Ok(report)
        }
        Ok(_) => Ok(report),
        Err(e) => Err(ended(e, StoppedBefore::Reset { node, object })),
    }
}

/// How an error ends the run: stopped where `at` says when it is the user's interruption.
fn ended(e: Error, at: StoppedBefore) -> Ended {
    match e.is_interrupted() {
        true => Ended::Stopped(at),
        false => Ended::Failed(e),
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
