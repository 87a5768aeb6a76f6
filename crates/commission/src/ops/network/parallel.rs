//! Network apply and check of many nodes at once over one link: the shared coordinator
//! ([`crate::ops::in_parallel`]) serving SDO only, each node's transfers on its progress bar.

use crate::bus::Bus;
use crate::cancel::Cancel;
use crate::error::Error;
use crate::ops::progress::{ItemEnd, Progress};
use std::collections::BTreeMap;

use crate::bus::SdoJob;
use crate::ops::in_parallel::{self, Serve, Watch};
use crate::ops::progress::ItemStatus;

/// The progress of each node, and when to begin no more.
struct Bars<'a> {
    items: &'a [(usize, u8)],
    stop: &'a Cancel,
    progress: &'a mut dyn Progress,
    /// Each node's (uploads, downloads) so far.
    counts: BTreeMap<u8, (u32, u32)>,
    done: u64,
}

impl<T: End> Watch<T> for Bars<'_> {
    fn transfer(&mut self, job: &SdoJob) {
        let (node, write) = match job {
            SdoJob::Upload { node, .. } => (*node, false),
            SdoJob::Download { node, .. } => (*node, true),
        };
        let count = self.counts.entry(node).or_default();
        *if write { &mut count.1 } else { &mut count.0 } += 1;
        self.progress.item(&node_label(node), ItemStatus::Transfers { reads: count.0, writes: count.1 });
    }

    fn ended(&mut self, slot: usize, result: &T, lost: bool) -> bool {
        self.progress.item_ended(&node_label(self.items[slot].1), result.end());
        self.done += 1;
        self.progress.advance(self.done);
        // After a link failure every further node would fail the same way.
        !lost && !self.stop.is_cancelled()
    }
}

/// A failure, said to the node whose procedure it ended.
fn link_lost(bus: &str, e: &Error) -> Error {
    let error = std::io::Error::other(e.to_string());
    Error::Link(crate::error::LinkError::Io { port: bus.to_string(), op: "", error: error.into() })
}

/// `work` for each of `items` (node indexes), up to `jobs` at once; `stopped` stands
/// for a node whose procedure ended without its result (a bug), so that the run still
/// ends. Results in the order of `items`; after a link failure or once `stop` is set,
/// no further node is begun, and those are left out.
pub(super) fn each<T: Send + End>(
    bus: &mut dyn Bus,
    items: &[(usize, u8)],
    jobs: usize,
    stop: &Cancel,
    work: &(dyn Fn(&mut dyn Bus, usize) -> T + Sync),
    stopped: &(dyn Fn(usize, Error) -> T + Sync),
    progress: &mut dyn Progress,
) -> Vec<(usize, T)> {
    let describe = bus.describe();
    let nodes: Vec<u8> = items.iter().map(|(_, node)| *node).collect();
    let serve =
        Serve::sdo_only("a node configured in parallel has SDO only (NMT, LSS and raw frames are the caller's)");
    let mut bars = Bars { items, stop, progress, counts: BTreeMap::new(), done: 0 };
    let work = |node_bus: &mut in_parallel::NodeBus<T>, slot: usize| work(node_bus, items[slot].0);
    let stopped = |slot: usize, why: Error| stopped(items[slot].0, link_lost(&describe, &why));
    let results = in_parallel::run(bus, &nodes, jobs, &serve, &work, &stopped, &mut bars);
    items.iter().zip(results).filter_map(|((i, _), r)| r.map(|r| (*i, r))).collect()
}

/// How a node's procedure ended, for its progress bar.
pub(super) trait End {
    fn end(&self) -> ItemEnd<'_>;
}

pub(super) fn node_label(node: u8) -> String {
    format!("node {node}")
}
