//! Many nodes at once over one link: each node's procedure runs on its own thread against a
//! [`NodeBus`], which hands its SDO transfers to the caller's thread; that thread waits until
//! every running node has one transfer waiting (or is done), then runs them together
//! ([`Bus::sdo_many`]: one per node, all in flight at once) and hands back the answers.

use super::*;
use crate::bus::{LssAnswer, LssExchange, Observed, SdoJob};
use crate::frame::Frame;
use crate::ops::counted::transfers;
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
    /// One transfer after another: the coordinator runs one per node at a time.
    fn sdo_batch(&mut self, jobs: &[SdoJob], progress: &mut dyn FnMut(usize)) -> Result<Vec<Result<Vec<u8>>>> {
        crate::bus::one_by_one(jobs, progress, |job| self.ask(job.clone()))
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
    fn recv_frame_stamped(&mut self, _: Instant) -> Result<Option<(Frame, Instant)>> {
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
    fn lss(&mut self, _: &LssExchange) -> Result<Vec<LssAnswer>> {
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
                        let why =
                            Error::Usage("canctl's procedure for this node stopped (a bug: please report it)".into());
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
