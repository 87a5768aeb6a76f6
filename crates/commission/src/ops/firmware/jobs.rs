//! `firmware download 5,6,7 IMAGE --jobs N`: up to N nodes at once on one bus.
//!
//! Each node's procedure is [`super::download`] itself, run by the shared coordinator
//! ([`crate::ops::in_parallel`]) with every service it needs: NMT, the waits (a poll's
//! pause, a boot-up or heartbeat wait) folded into one, and the SDO transfers together,
//! the program data one node at a time. So the erases of seconds overlap, and the bus's
//! time (virtual on the simulator) moves as it does for one node.

use super::download::{download_timed, ended, DownloadOptions, DownloadReport, Failed, FirmwareError, Outcome};
use super::each::{download_each, Batch};
use crate::bus::Bus;
use crate::cancel::Cancel;
use crate::canopen::program::{self, PROGRAM_DATA};
use crate::error::Error;
use crate::ops::in_parallel::{self, Serve, Watch};
use crate::ops::progress::{ItemEnd, Progress};

/// Each node's line, and when to begin no more.
struct Lines<'a> {
    nodes: &'a [u8],
    cancel: Option<&'a Cancel>,
    progress: &'a mut dyn Progress,
}

impl Watch<Outcome> for Lines<'_> {
    fn begun(&mut self, slot: usize) {
        self.progress.item(&format!("node {}", self.nodes[slot]), crate::ops::progress::ItemStatus::Begun);
    }

    fn ended(&mut self, slot: usize, outcome: &Outcome, _lost: bool) -> bool {
        self.progress.item_ended(&format!("node {}", self.nodes[slot]), ItemEnd::Downloaded(ended(outcome)));
        let interrupted = matches!(outcome, Err(f) if f.report.interrupted);
        !interrupted && !self.cancel.is_some_and(Cancel::is_cancelled)
    }
}

/// Download `image` into `nodes`, up to `jobs` of them at once (1: [`download_each`],
/// one after the other). Each node gets the report it would get alone; one that fails
/// does not stop the others; an interruption ends those under way (each says where its
/// device is) and begins no more (listed as not begun). Alone or one after the other, a
/// node's transfer is a phase of `progress` counting its bytes; several at once, each
/// node's start and end are told instead.
pub fn download_jobs(
    bus: &mut dyn Bus,
    nodes: &[u8],
    image: &[u8],
    o: &DownloadOptions,
    jobs: usize,
    progress: &mut dyn Progress,
) -> Batch {
    if jobs <= 1 || nodes.len() <= 1 {
        return download_each(bus, nodes, image, o, progress);
    }
    let serve = Serve::all("a firmware download in parallel sends no raw frames", PROGRAM_DATA);
    let stopped = |slot: usize, why: Error| {
        let id = o.expect_id.unwrap_or_else(|| program::image_id(image));
        let report = Box::new(DownloadReport::begun(nodes[slot], o.program, image.len(), id));
        Err(Box::new(Failed { error: FirmwareError::Bus(why), report }))
    };
    let work = |node_bus: &mut in_parallel::NodeBus<Outcome>, slot: usize| {
        let served = node_bus.served();
        download_timed(node_bus, nodes[slot], image, o, &mut crate::ops::progress::Silent, &served)
    };
    let mut lines = Lines { nodes, cancel: o.cancel.as_ref(), progress };
    let outcomes = in_parallel::run(bus, nodes, jobs, &serve, &work, &stopped, &mut lines);
    let mut batch = Batch { nodes: Vec::new(), interrupted: false };
    for (&node, outcome) in nodes.iter().zip(outcomes) {
        batch.push(node, outcome);
    }
    batch
}
