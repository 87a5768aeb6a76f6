//! Many nodes at once over one link: each node's procedure runs on its own thread against a
//! [`NodeBus`] that hands every bus service to the caller's thread. That thread acts once
//! every running node waits on one: NMT commands first (a frame each), else the SDO
//! transfers together ([`Bus::sdo_many`]: one per node, all in flight at once), else the
//! waits (a pause, a boot-up or heartbeat wait) folded into one, until the earliest
//! deadline, each frame heard handed to every node listening. So long device operations
//! overlap, and the bus's time (virtual on the simulator) moves as it does for one node.
//!
//! Network apply and check ask for SDO only ([`Serve::sdo_only`]): NMT, waits and frames
//! are refused to their nodes, and nothing of them is done on the bus. A firmware download
//! asks for all of it ([`Serve::all`]), with its program data taking turns.

use crate::bus::{Bus, LssAnswer, LssExchange, Observed, SdoJob};
use crate::canopen::nmt;
use crate::error::{Error, Result};
use crate::frame::Frame;
use std::sync::mpsc::{channel, Sender};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// What the coordinator serves the nodes' procedures beyond SDO transfers.
pub(crate) struct Serve {
    /// NMT commands, pauses and frames heard; without, a node's procedure that asks for
    /// one is told `refused`, and the bus's boot-ups and block-transfer support stay the
    /// caller's.
    all: bool,
    refused: &'static str,
    /// Downloads to this object take turns, one node at a time: CAN arbitration gives the
    /// bus to the lowest id, so a block download to node 5 (0x605) would hold off node 7's
    /// (0x607) past any timeout; the bus is full with one anyway.
    one_at_a_time: Option<u16>,
    /// A stop during a shared transfer or wait is said to each node as such; without, as
    /// the link lost (what network apply and check have always said).
    keeps_interruption: bool,
}

impl Serve {
    /// SDO transfers only; `refused` says why anything else is not served.
    pub(crate) fn sdo_only(refused: &'static str) -> Self {
        Serve { all: false, refused, one_at_a_time: None, keeps_interruption: false }
    }

    /// Every service but raw frames, LSS and remote requests (those are `refused`);
    /// downloads to `one_at_a_time` take turns.
    pub(crate) fn all(refused: &'static str, one_at_a_time: u16) -> Self {
        Serve { all: true, refused, one_at_a_time: Some(one_at_a_time), keeps_interruption: true }
    }
}

/// What the caller hears of the run, on the coordinating thread.
pub(crate) trait Watch<T> {
    /// The procedure for `slot` begins.
    fn begun(&mut self, _slot: usize) {}
    /// A node's procedure asked for `job`.
    fn transfer(&mut self, _job: &SdoJob) {}
    /// The procedure for `slot` ended with `result`; `lost` once a shared transfer found
    /// the link failed. Whether to begin further nodes (once no, never again).
    fn ended(&mut self, slot: usize, result: &T, lost: bool) -> bool;
}

/// When the last service a node asked for began on the bus: with several nodes, a
/// transfer may wait its turn, and its rate counts from then.
#[derive(Default)]
pub(crate) struct Served(Mutex<Option<Instant>>);

impl Served {
    /// When the last service began; unset, it began when asked.
    pub(crate) fn since(&self) -> Option<Instant> {
        *self.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn set(&self, t: Instant) {
        *self.0.lock().unwrap_or_else(|e| e.into_inner()) = Some(t);
    }
}

/// A bus service one node's procedure waits on.
enum Ask {
    Sdo(SdoJob),
    Nmt(nmt::Command, u8),
    /// Wake at this time.
    Sleep(Instant),
    /// The next frame on the bus, or none at this time.
    Listen(Instant),
}

impl Ask {
    fn deadline(&self) -> Option<Instant> {
        match self {
            Ask::Sleep(t) | Ask::Listen(t) => Some(*t),
            _ => None,
        }
    }
}

enum Got {
    Bytes(Vec<u8>),
    Done,
    Frame(Option<(Frame, Instant)>),
}

/// The coordinator's answer, with what the node's procedure reads of the bus between
/// services: the time, whether its boot-up came, whether block transfer holds for it.
struct Answer {
    got: Result<Got>,
    /// When the service began (an SDO transfer's turn came).
    began: Instant,
    now: Instant,
    booted: bool,
    block: bool,
}

enum Msg<T> {
    Ask(usize, Ask, Sender<Answer>),
    Done(usize, T),
}

/// The bus as one node's procedure sees it: each service asked of the coordinator.
pub(crate) struct NodeBus<T> {
    slot: usize,
    node: u8,
    describe: String,
    sees_traffic: bool,
    /// NMT and waits go to the coordinator; else they are refused here.
    all: bool,
    refused: &'static str,
    to_coordinator: Sender<Msg<T>>,
    now: Instant,
    block: bool,
    served: Arc<Served>,
    /// Its own boot-ups, handed over by the coordinator: a procedure forgets them before
    /// the steps that cause one.
    observed: Observed,
}

impl<T> NodeBus<T> {
    /// When this node's last service began on the bus.
    pub(crate) fn served(&self) -> Arc<Served> {
        Arc::clone(&self.served)
    }

    fn ask(&mut self, ask: Ask) -> Result<Got> {
        let gone = || Error::NotOnThisBus { bus: self.describe.clone(), why: "the coordinating thread is gone" };
        let (tx, rx) = channel();
        self.to_coordinator.send(Msg::Ask(self.slot, ask, tx)).map_err(|_| gone())?;
        let a = rx.recv().map_err(|_| gone())?;
        (self.now, self.block) = (a.now, a.block);
        self.served.set(a.began);
        if a.booted {
            self.observed.boot_ups.insert(self.node);
        }
        a.got
    }

    fn not_here(&self) -> Error {
        Error::NotOnThisBus { bus: self.describe.clone(), why: self.refused }
    }

    /// `ask` of the coordinator, where it serves NMT and waits; else refused here.
    fn ask_served(&mut self, ask: Ask) -> Result<Got> {
        if !self.all {
            return Err(self.not_here());
        }
        self.ask(ask)
    }
}

fn unexpected() -> Error {
    Error::Usage("canctl's coordinator answered a request with the wrong kind (a bug: please report it)".into())
}

impl<T> Bus for NodeBus<T> {
    fn describe(&self) -> String {
        self.describe.clone()
    }
    /// One transfer after another: the coordinator runs one per node at a time.
    fn sdo_batch(&mut self, jobs: &[SdoJob], progress: &mut dyn FnMut(usize)) -> Result<Vec<Result<Vec<u8>>>> {
        crate::bus::one_by_one(jobs, progress, |job| match self.ask(Ask::Sdo(job.clone()))? {
            Got::Bytes(b) => Ok(b),
            _ => Err(unexpected()),
        })
    }
    fn nmt(&mut self, cmd: nmt::Command, node: u8) -> Result<()> {
        self.ask_served(Ask::Nmt(cmd, node)).map(|_| ())
    }
    fn send_frame(&mut self, _: &Frame) -> Result<()> {
        Err(self.not_here())
    }
    fn sees_traffic(&self) -> bool {
        self.sees_traffic
    }
    fn block_transfer_to(&self, _: u8) -> bool {
        self.block
    }
    fn recv_frame_stamped(&mut self, deadline: Instant) -> Result<Option<(Frame, Instant)>> {
        match self.ask_served(Ask::Listen(deadline))? {
            Got::Frame(f) => Ok(f),
            _ => Err(unexpected()),
        }
    }
    /// The bus's time as of this node's last service.
    fn now(&self) -> Instant {
        self.now
    }
    fn sleep_until(&mut self, t: Instant) -> Result<()> {
        self.ask_served(Ask::Sleep(t)).map(|_| ())
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

/// A node waiting on a service.
struct Waiting {
    slot: usize,
    ask: Ask,
    reply: Sender<Answer>,
}

/// Serves the waiting nodes: NMT first, else the SDO transfers together, else one wait.
struct Coordinator<'a> {
    bus: &'a mut dyn Bus,
    nodes: &'a [u8],
    serve: &'a Serve,
    /// When the service being answered began.
    began: Instant,
    /// The link failure a shared transfer found.
    lost: bool,
}

impl Coordinator<'_> {
    /// The same error for each node a shared wait or batch ended for.
    fn for_each_node(&self, e: &Error) -> Error {
        if self.serve.keeps_interruption && e.is_interrupted() {
            return Error::Interrupted;
        }
        let error = std::io::Error::other(e.to_string());
        Error::Link(crate::error::LinkError::Io { port: self.bus.describe(), op: "", error: error.into() })
    }

    /// The failure `e` of a shared transfer or wait, to each node of `ended`.
    fn fail(&mut self, ended: Vec<Waiting>, e: &Error) {
        for w in ended {
            let e = self.for_each_node(e);
            self.answer(w, Err(e));
        }
    }

    fn answer(&mut self, w: Waiting, got: Result<Got>) {
        let node = self.nodes[w.slot];
        let booted = self.serve.all && self.bus.observed().boot_ups.remove(&node);
        let block = self.serve.all && self.bus.block_transfer_to(node);
        let answer = Answer { got, began: self.began, now: self.bus.now(), booted, block };
        // A node whose thread is gone has nothing left to be told.
        let _ = w.reply.send(answer);
    }

    /// The waits whose time has come end: a pause, or a listen that heard nothing.
    fn wake(&mut self, waiting: &mut Vec<Waiting>) {
        let now = self.bus.now();
        let due: Vec<Waiting> = waiting.extract_if(.., |w| w.ask.deadline().is_some_and(|t| t <= now)).collect();
        for w in due {
            let got = if matches!(w.ask, Ask::Listen(_)) { Got::Frame(None) } else { Got::Done };
            self.answer(w, Ok(got));
        }
    }

    fn serve(&mut self, waiting: &mut Vec<Waiting>) {
        self.began = self.bus.now();
        let nmt: Vec<Waiting> = waiting.extract_if(.., |w| matches!(w.ask, Ask::Nmt(..))).collect();
        if !nmt.is_empty() {
            for w in nmt {
                let Ask::Nmt(cmd, node) = w.ask else { unreachable!("partitioned") };
                let sent = self.bus.nmt(cmd, node).map(|()| Got::Done);
                self.answer(w, sent);
            }
            return;
        }
        let mut turn_taken = false;
        let one_at_a_time = self.serve.one_at_a_time;
        let served = |w: &mut Waiting| match &w.ask {
            Ask::Sdo(SdoJob::Download { addr, .. }) if Some(addr.index) == one_at_a_time => {
                !std::mem::replace(&mut turn_taken, true)
            }
            Ask::Sdo(_) => true,
            _ => false,
        };
        let sdo: Vec<Waiting> = waiting.extract_if(.., served).collect();
        if !sdo.is_empty() {
            let job = |w: &Waiting| if let Ask::Sdo(j) = &w.ask { j.clone() } else { unreachable!("partitioned") };
            let jobs: Vec<SdoJob> = sdo.iter().map(job).collect();
            match self.bus.sdo_many(&jobs) {
                Ok(results) => {
                    for (w, r) in sdo.into_iter().zip(results) {
                        self.answer(w, r.map(Got::Bytes));
                    }
                }
                Err(e) => {
                    self.fail(sdo, &e);
                    self.lost = true;
                }
            }
            // The transfers took their time: the waits it covered are over.
            self.wake(waiting);
            return;
        }
        // Only waits: one, until the earliest deadline; a frame goes to every listener.
        let until = waiting.iter().filter_map(|w| w.ask.deadline()).min().expect("only waits are left");
        let listening = waiting.iter().any(|w| matches!(w.ask, Ask::Listen(_)));
        let heard = match listening {
            _ if self.bus.now() >= until => Ok(None),
            true => self.bus.recv_frame_stamped(until),
            false => self.bus.sleep_until(until).map(|()| None),
        };
        match heard {
            Ok(heard) => {
                if let Some(frame) = heard {
                    let listeners: Vec<Waiting> = waiting.extract_if(.., |w| matches!(w.ask, Ask::Listen(_))).collect();
                    for w in listeners {
                        self.answer(w, Ok(Got::Frame(Some(frame))));
                    }
                }
                self.wake(waiting);
            }
            Err(e) => self.fail(std::mem::take(waiting), &e),
        }
    }
}

/// `work` for the node in each slot of `nodes`, up to `jobs` at once, in slot order.
/// `stopped` stands for a procedure that ended without its result (a bug), so that the
/// run still ends. Once `watch` says to begin no more, the slots not begun stay `None`.
pub(crate) fn run<T: Send>(
    bus: &mut dyn Bus,
    nodes: &[u8],
    jobs: usize,
    serve: &Serve,
    work: &(dyn Fn(&mut NodeBus<T>, usize) -> T + Sync),
    stopped: &(dyn Fn(usize, Error) -> T + Sync),
    watch: &mut dyn Watch<T>,
) -> Vec<Option<T>> {
    let describe = bus.describe();
    let sees_traffic = serve.all && bus.sees_traffic();
    let (tx, rx) = channel::<Msg<T>>();
    let mut results: Vec<Option<T>> = nodes.iter().map(|_| None).collect();
    let began = bus.now();
    let mut coordinator = Coordinator { bus, nodes, serve, began, lost: false };
    std::thread::scope(|scope| {
        let begin = |slot: usize, c: &mut Coordinator, watch: &mut dyn Watch<T>| {
            watch.begun(slot);
            let mut node_bus = NodeBus {
                slot,
                node: nodes[slot],
                describe: describe.clone(),
                sees_traffic,
                all: serve.all,
                refused: serve.refused,
                to_coordinator: tx.clone(),
                now: c.bus.now(),
                block: serve.all && c.bus.block_transfer_to(nodes[slot]),
                served: Arc::new(Served::default()),
                observed: Observed::default(),
            };
            scope.spawn(move || {
                let bug = "canctl's procedure for this node stopped (a bug: please report it)";
                let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work(&mut node_bus, slot)));
                let result = ran.unwrap_or_else(|_| stopped(slot, Error::Usage(bug.into())));
                // The coordinator waits for every running node: it must hear of this one.
                let _ = node_bus.to_coordinator.send(Msg::Done(slot, result));
            });
        };
        let mut queue = 0..nodes.len();
        let mut running = 0;
        let mut more = true;
        for slot in queue.by_ref().take(jobs) {
            begin(slot, &mut coordinator, watch);
            running += 1;
        }
        let mut waiting: Vec<Waiting> = Vec::new();
        while running > 0 {
            // Every running node either waits on a service or has finished.
            while waiting.len() < running {
                match rx.recv().expect("the coordinator holds a sender") {
                    Msg::Ask(slot, ask, reply) => {
                        if let Ask::Sdo(job) = &ask {
                            watch.transfer(job);
                        }
                        waiting.push(Waiting { slot, ask, reply });
                    }
                    Msg::Done(slot, result) => {
                        more &= watch.ended(slot, &result, coordinator.lost);
                        results[slot] = Some(result);
                        running -= 1;
                        if let Some(next) = queue.next().filter(|_| more) {
                            begin(next, &mut coordinator, watch);
                            running += 1;
                        }
                    }
                }
            }
            if !waiting.is_empty() {
                coordinator.serve(&mut waiting);
            }
        }
    });
    results
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::SdoOptions;
    use crate::canopen::ObjAddr;

    /// Each node's error for an NMT command, then its device type read.
    type Tried = (Option<Error>, Result<Vec<u8>>);

    struct Ends(Vec<usize>);

    impl Watch<Tried> for Ends {
        fn ended(&mut self, slot: usize, _: &Tried, _: bool) -> bool {
            self.0.push(slot);
            true
        }
    }

    fn try_nmt_then_read(serve: &Serve) -> Vec<Option<Tried>> {
        let mut bus = crate::bus::Master::new(crate::sim::SimLink::ephemeral(), "sim".to_string());
        let nodes = [1, 5, 10];
        let work = |bus: &mut NodeBus<Tried>, slot: usize| {
            let nmt = bus.nmt(nmt::Command::PreOperational, nodes[slot]).err();
            let read =
                bus.sdo_upload(nodes[slot], ObjAddr::new(0x1000, 0), &SdoOptions::new(Duration::from_millis(500)));
            (nmt, read)
        };
        let stopped = |_: usize, e: Error| (Some(e), Err(Error::Interrupted));
        let mut ends = Ends(Vec::new());
        let results = run(&mut bus, &nodes, 2, serve, &work, &stopped, &mut ends);
        assert_eq!(ends.0.len(), 3, "every node ends");
        results
    }

    #[test]
    fn sdo_only_refuses_nmt_and_still_serves_the_transfers() {
        for r in try_nmt_then_read(&Serve::sdo_only("SDO only here")) {
            let (nmt, read) = r.expect("every node begun");
            assert!(matches!(nmt, Some(Error::NotOnThisBus { why: "SDO only here", .. })), "{nmt:?}");
            assert_eq!(read.unwrap().len(), 4);
        }
    }

    #[test]
    fn all_serves_nmt_too() {
        for r in try_nmt_then_read(&Serve::all("no raw frames", 0x1F50)) {
            let (nmt, read) = r.expect("every node begun");
            assert!(nmt.is_none(), "{nmt:?}");
            assert_eq!(read.unwrap().len(), 4);
        }
    }
}
