//! `firmware download 5,6,7 IMAGE --jobs N`: up to N nodes at once on one bus.
//!
//! Each node's procedure is [`super::download`] itself, run on its own thread against a
//! [`NodeBus`] that hands every bus service to the caller's thread. That thread acts once
//! every running node waits on one: NMT commands first (a frame each), else the SDO
//! transfers together ([`Bus::sdo_many`]; the program data one node at a time), else the
//! waits (a poll's pause, a boot-up or heartbeat wait) folded into one, until the earliest
//! deadline, each frame heard handed to every node listening. So the erases of seconds
//! overlap, and the bus's time (virtual on the simulator) moves as it does for one node.

use super::*;
use crate::bus::{LssAnswer, LssExchange, Observed, SdoJob};
use crate::error::Result;
use crate::frame::Frame;
use std::sync::mpsc::{channel, Sender};

/// When the last SDO transfer a node asked for began on the bus: with several nodes, the
/// program data waits its turn, and its rate counts from then.
#[derive(Default)]
pub(super) struct Served(std::sync::Mutex<Option<Instant>>);

impl Served {
    pub(super) fn since(&self) -> Option<Instant> {
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

type Outcome = std::result::Result<DownloadReport, Box<Failed>>;

enum Msg {
    Ask(usize, Ask, Sender<Answer>),
    Done(usize, Outcome),
}

/// The bus as one node's procedure sees it: each service asked of the coordinator.
struct NodeBus {
    slot: usize,
    node: u8,
    describe: String,
    sees_traffic: bool,
    to_coordinator: Sender<Msg>,
    now: Instant,
    block: bool,
    served: std::sync::Arc<Served>,
    /// Its own boot-ups, handed over by the coordinator: the procedure forgets them
    /// before the steps that cause one.
    observed: Observed,
}

impl NodeBus {
    fn ask(&mut self, ask: Ask) -> Result<Got> {
        let gone = || Error::NotOnThisBus { bus: self.describe.clone(), why: "the coordinating thread is gone" };
        let (tx, rx) = channel();
        self.to_coordinator.send(Msg::Ask(self.slot, ask, tx)).map_err(|_| gone())?;
        let a = rx.recv().map_err(|_| gone())?;
        self.now = a.now;
        self.block = a.block;
        self.served.set(a.began);
        if a.booted {
            self.observed.boot_ups.insert(self.node);
        }
        a.got
    }

    fn not_here(&self) -> Error {
        Error::NotOnThisBus { bus: self.describe.clone(), why: "a firmware download in parallel sends no raw frames" }
    }
}

fn unexpected() -> Error {
    Error::Usage(
        "canctl's parallel firmware download answered a request with the wrong kind (a bug: please report it)".into(),
    )
}

impl Bus for NodeBus {
    fn describe(&self) -> String {
        self.describe.clone()
    }
    fn sdo_batch(&mut self, jobs: &[SdoJob], progress: &mut dyn FnMut(usize)) -> Result<Vec<Result<Vec<u8>>>> {
        crate::bus::one_by_one(jobs, progress, |job| match self.ask(Ask::Sdo(job.clone()))? {
            Got::Bytes(b) => Ok(b),
            _ => Err(unexpected()),
        })
    }
    fn nmt(&mut self, cmd: nmt::Command, node: u8) -> Result<()> {
        self.ask(Ask::Nmt(cmd, node)).map(|_| ())
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
        match self.ask(Ask::Listen(deadline))? {
            Got::Frame(f) => Ok(f),
            _ => Err(unexpected()),
        }
    }
    fn now(&self) -> Instant {
        self.now
    }
    fn sleep_until(&mut self, t: Instant) -> Result<()> {
        self.ask(Ask::Sleep(t)).map(|_| ())
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

/// The same error for each node a shared wait or batch ended for.
fn for_each_node(describe: &str, e: &Error) -> Error {
    if e.is_interrupted() {
        return Error::Interrupted;
    }
    let error = std::io::Error::other(e.to_string());
    Error::Link(crate::error::LinkError::Io { port: describe.to_string(), op: "", error })
}

/// Serves the waiting nodes: NMT first, else the SDO transfers together, else one wait.
struct Coordinator<'a> {
    bus: &'a mut dyn Bus,
    nodes: &'a [u8],
    describe: String,
    /// When the service being answered began.
    began: Instant,
}

impl Coordinator<'_> {
    fn answer(&mut self, w: Waiting, got: Result<Got>) {
        let node = self.nodes[w.slot];
        let booted = self.bus.observed().boot_ups.remove(&node);
        let answer =
            Answer { got, began: self.began, now: self.bus.now(), booted, block: self.bus.block_transfer_to(node) };
        // A node whose thread is gone has nothing left to be told.
        let _ = w.reply.send(answer);
    }

    /// The waits whose time has come end: a pause, or a listen that heard nothing.
    fn wake(&mut self, waiting: &mut Vec<Waiting>) {
        let now = self.bus.now();
        let (due, rest): (Vec<Waiting>, Vec<Waiting>) =
            waiting.drain(..).partition(|w| w.ask.deadline().is_some_and(|t| t <= now));
        *waiting = rest;
        for w in due {
            let got = if matches!(w.ask, Ask::Listen(_)) { Got::Frame(None) } else { Got::Done };
            self.answer(w, Ok(got));
        }
    }

    fn serve(&mut self, waiting: &mut Vec<Waiting>) {
        self.began = self.bus.now();
        let (nmt, rest): (Vec<Waiting>, Vec<Waiting>) = waiting.drain(..).partition(|w| matches!(w.ask, Ask::Nmt(..)));
        *waiting = rest;
        if !nmt.is_empty() {
            for w in nmt {
                let Ask::Nmt(cmd, node) = w.ask else { unreachable!("partitioned") };
                let sent = self.bus.nmt(cmd, node).map(|()| Got::Done);
                self.answer(w, sent);
            }
            return;
        }
        // The program data goes one node at a time: CAN arbitration gives the bus to the
        // lowest id, so a block download to node 5 (0x605) would hold off node 7's (0x607)
        // past any timeout; the bus is full with one anyway. The others wait their turn.
        let mut data_sent = false;
        let (sdo, rest): (Vec<Waiting>, Vec<Waiting>) = waiting.drain(..).partition(|w| match &w.ask {
            Ask::Sdo(SdoJob::Download { addr, .. }) if addr.index == PROGRAM_DATA => {
                !std::mem::replace(&mut data_sent, true)
            }
            Ask::Sdo(_) => true,
            _ => false,
        });
        *waiting = rest;
        if !sdo.is_empty() {
            let jobs: Vec<SdoJob> = sdo
                .iter()
                .map(|w| if let Ask::Sdo(j) = &w.ask { j.clone() } else { unreachable!("partitioned") })
                .collect();
            match self.bus.sdo_many(&jobs) {
                Ok(results) => {
                    for (w, r) in sdo.into_iter().zip(results) {
                        self.answer(w, r.map(Got::Bytes));
                    }
                }
                Err(e) => {
                    for w in sdo {
                        let e = for_each_node(&self.describe, &e);
                        self.answer(w, Err(e));
                    }
                }
            }
            // The transfers took their time: the waits it covered are over.
            self.wake(waiting);
            return;
        }
        // Only waits: one, until the earliest deadline; a frame goes to every listener.
        let until = waiting.iter().filter_map(|w| w.ask.deadline()).min().expect("only waits are left");
        let listening = waiting.iter().any(|w| matches!(w.ask, Ask::Listen(_)));
        let heard = if self.bus.now() >= until {
            Ok(None)
        } else if listening {
            self.bus.recv_frame_stamped(until)
        } else {
            self.bus.sleep_until(until).map(|()| None)
        };
        match heard {
            Ok(Some(frame)) => {
                let (listeners, rest): (Vec<Waiting>, Vec<Waiting>) =
                    waiting.drain(..).partition(|w| matches!(w.ask, Ask::Listen(_)));
                *waiting = rest;
                for w in listeners {
                    self.answer(w, Ok(Got::Frame(Some(frame))));
                }
                self.wake(waiting);
            }
            Ok(None) => self.wake(waiting),
            Err(e) => {
                for w in std::mem::take(waiting) {
                    let e = for_each_node(&self.describe, &e);
                    self.answer(w, Err(e));
                }
            }
        }
    }
}

/// Download `image` into `nodes`, up to `jobs` of them at once (1: [`download_each`],
/// one after the other). Each node gets the report it would get alone; one that fails
/// does not stop the others; an interruption ends those under way (each says where its
/// device is) and begins no more (listed as not begun). `o.watch` is told the bytes of
/// whichever node's transfer moved (one bar per node is the caller's to make of it).
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
    let describe = bus.describe();
    let sees_traffic = bus.sees_traffic();
    let (tx, rx) = channel::<Msg>();
    let mut outcomes: Vec<Option<Outcome>> = nodes.iter().map(|_| None).collect();
    let began = bus.now();
    let mut coordinator = Coordinator { bus, nodes, describe: describe.clone(), began };
    std::thread::scope(|scope| {
        let start = |slot: usize, now: Instant, block: bool| {
            let node = nodes[slot];
            let mut node_bus = NodeBus {
                slot,
                node,
                describe: describe.clone(),
                sees_traffic,
                to_coordinator: tx.clone(),
                now,
                block,
                served: std::sync::Arc::new(Served::default()),
                observed: Observed::default(),
            };
            scope.spawn(move || {
                let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    let served = std::sync::Arc::clone(&node_bus.served);
                    download_timed(&mut node_bus, node, image, o, &mut crate::ops::Silent, &served)
                }));
                let outcome = run.unwrap_or_else(|_| {
                    let why = Error::Usage("canctl's download for this node stopped (a bug: please report it)".into());
                    let id = o.expect_id.unwrap_or_else(|| program::image_id(image));
                    let report = Box::new(DownloadReport::begun(node, o.program, image.len(), id));
                    Err(Box::new(Failed { error: FirmwareError::Bus(why), report }))
                });
                // The coordinator waits for every running node: it must hear of this one.
                let _ = node_bus.to_coordinator.send(Msg::Done(slot, outcome));
            });
        };
        let mut queue = 0..nodes.len();
        let mut running = 0;
        let mut stopping = false;
        for slot in queue.by_ref().take(jobs) {
            progress.item(&format!("node {}", nodes[slot]), "under way", false);
            let bus = &mut coordinator.bus;
            start(slot, bus.now(), bus.block_transfer_to(nodes[slot]));
            running += 1;
        }
        let mut waiting: Vec<Waiting> = Vec::new();
        while running > 0 {
            while waiting.len() < running {
                match rx.recv().expect("the coordinator holds a sender") {
                    Msg::Ask(slot, ask, reply) => waiting.push(Waiting { slot, ask, reply }),
                    Msg::Done(slot, outcome) => {
                        let node = format!("node {}", nodes[slot]);
                        progress.item(&node, end_word(&outcome), true);
                        stopping |= matches!(&outcome, Err(f) if f.report.interrupted)
                            || o.cancel.as_ref().is_some_and(Cancel::is_cancelled);
                        outcomes[slot] = Some(outcome);
                        running -= 1;
                        if let Some(next) = queue.next().filter(|_| !stopping) {
                            progress.item(&format!("node {}", nodes[next]), "under way", false);
                            let bus = &mut coordinator.bus;
                            start(next, bus.now(), bus.block_transfer_to(nodes[next]));
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
    let mut batch = Batch { nodes: Vec::new(), interrupted: false };
    for (&node, outcome) in nodes.iter().zip(outcomes) {
        batch.nodes.push(match outcome {
            None => NodeDownload { node, report: None, error: Some(Unfinished::NotBegun) },
            Some(Ok(report)) => NodeDownload { node, report: Some(report), error: None },
            Some(Err(failed)) => {
                let Failed { error, report } = *failed;
                batch.interrupted |= report.interrupted;
                NodeDownload { node, report: Some(*report), error: Some(Unfinished::Failed(error)) }
            }
        });
    }
    batch
}

/// How a node's download ended, in a word (as [`download_each`] tells it).
pub(super) fn end_word(outcome: &Outcome) -> &'static str {
    match outcome {
        Ok(r) if r.skipped => "skipped",
        Ok(_) => "done",
        Err(f) if f.report.interrupted => "interrupted",
        Err(_) => "failed",
    }
}
