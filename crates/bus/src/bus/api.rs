//! The service-level API itself: the [`Bus`] trait, the [`FrameLink`] under a
//! [`Master`](super::Master), what a transfer is asked with, and the helpers every bus shares.

use super::observer::Observed;
use super::{clock, controller};
use crate::cancel::Cancel;
use crate::canopen::nmt::Command;
use crate::canopen::ObjAddr;
use crate::error::Result;
use crate::frame::Frame;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A raw frame link: what SocketCAN and the simulator provide.
pub trait FrameLink {
    /// Sends one frame; an error when the link cannot (bus-off, adapter gone).
    fn send(&mut self, frame: &Frame) -> Result<()>;
    /// Sends `frames` in order, all of them now: what a sender has ready at once (the
    /// segments of an SDO block, the answers of a device's block). Links that carry
    /// frames in a stream (socketcand over TCP) write them in one go rather than one
    /// system call and one TCP segment a frame; the others send each as [`send`](Self::send).
    /// Nothing is held back for later: when it returns, every frame is on its way.
    fn send_all(&mut self, frames: &[Frame]) -> Result<()> {
        frames.iter().try_for_each(|f| self.send(f))
    }
    /// The next frame, or `None` once `deadline` passes without one.
    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>>;
    /// The next frame with the moment it was on the bus, on the clock of `now`. Judging a
    /// device's timing from it does not depend on when canctl got round to reading (a
    /// loaded host delivers frames in bursts). Links that know no better stamp receipt.
    fn recv_stamped(&mut self, deadline: Instant) -> Result<Option<(Frame, Instant)>> {
        Ok(self.recv(deadline)?.map(|f| (f, self.now())))
    }
    /// Interface name for traces (`can0`, `sim`).
    fn name(&self) -> String;
    /// The clock `recv` deadlines are measured on. Real links keep the default (monotonic);
    /// the simulator on virtual time, and test links that play a device with virtual delays,
    /// return their own time.
    fn now(&self) -> Instant {
        clock::monotonic_now()
    }
    /// Let time pass until `t` on this link's clock. Frames that arrive meanwhile wait for
    /// the next `recv`. A virtual clock just moves on (running its devices up to `t`).
    fn sleep_until(&mut self, t: Instant) -> Result<()> {
        clock::sleep_until(t);
        Ok(())
    }
    /// Receive only frames whose id matches one of these (id, mask) pairs; `[(0, 0)]`
    /// is everything. Links without hardware filtering ignore it.
    fn set_filters(&mut self, _filters: &[(u16, u16)]) -> Result<()> {
        Ok(())
    }
    /// Finish cleanly (the simulator saves its state here).
    fn close(&mut self) -> Result<()> {
        Ok(())
    }
    /// After a silence (a scan no node answered): an error when the link itself reports
    /// the bus unusable (an slcan adapter's status flags after frames nobody acknowledged:
    /// a wrong bit rate, no termination), so that it is not taken for an empty bus.
    fn check(&mut self) -> Result<()> {
        Ok(())
    }
    /// Whether this link switches its own bit rate when the devices do (CiA 305 "activate
    /// bit timing"): the simulated bus does; a CAN interface must be switched by its owner.
    fn follows_bit_rate_switch(&self) -> bool {
        false
    }
    /// The longest an 8-byte data frame occupies the bus at the link's bit rate (see
    /// [`Bus::frame_time`]); `None` where the link does not know its rate.
    fn frame_time(&self) -> Option<Duration> {
        None
    }
    /// What the link knows about the bus beyond its frames (the controller's state, the
    /// error frames it reported); `None` for links that know nothing of the kind.
    fn report(&mut self) -> Option<controller::LinkReport> {
        None
    }
    /// Listen, listen-only (sending and acknowledging nothing), at `kbit` for `window`, then
    /// go back to the link's own rate; `None` for links that cannot change their rate.
    fn listen_at(&mut self, _kbit: u32, _window: Duration) -> Result<Option<controller::RateHeard>> {
        Ok(None)
    }
}

/// How one SDO transfer is made: its timeout, transfer kinds, limits, stop and progress.
#[derive(Clone)]
pub struct SdoOptions {
    /// How long to wait for each answer: a transfer that makes no progress for this long
    /// ends (frames that do not advance it do not count). The whole transfer has a deadline
    /// that follows from it and the size (`SdoClient::time_budget`).
    pub timeout: Duration,
    /// Ask for block upload (worth it for strings and domains).
    pub block_upload: bool,
    /// Allow block download for large values.
    pub block_download: bool,
    /// The size the caller expects, when it knows the type: links whose short read
    /// returns a fixed four bytes (EPOS2 ReadObject) cut the answer to it.
    pub size_hint: Option<usize>,
    /// Uploads stop (and announced sizes are refused) beyond this many bytes.
    pub max_upload: usize,
    /// Set when the user asks to stop (SIGINT, SIGTERM, Ctrl-C): looked at between the
    /// frames of a transfer. A transfer the device has answered and that goes on then ends
    /// with a CiA 301 abort (0x08000000) sent to the device, so that it is not left waiting
    /// for the rest until its own timeout, and with
    /// [`Error::SdoInterrupted`](crate::Error::SdoInterrupted). One still waiting for its
    /// first answer is let finish, for at most 250 ms and without a retry (a write's request
    /// may have done its work already): a read that gets no answer then ends with
    /// [`Error::Interrupted`](crate::Error::Interrupted), as its wait was cut short, and so
    /// do those not begun.
    pub stop: Option<Cancel>,
    /// Called with the bytes moved so far each time an answer moves a transfer on (a
    /// segment, a sub-block): for progress, and for tests that act at an exact point of a
    /// transfer.
    pub on_progress: Option<TransferHook>,
    /// How many times a transfer that got no answer in time is aborted and started again
    /// (a lost frame is retried, not waited out). Writes that are actions are never
    /// repeated once sent whole (`canopen::sdo::retry`).
    pub retries: u8,
    /// A read that has heard nothing this long after its request left the bus is asked
    /// again (`retries` times at most) while the earlier request still stands: an answer
    /// to any of them counts, and the wait is `timeout` from the last one. A lost frame
    /// then costs a typical answer time, not a whole timeout. Only where the link knows how
    /// long a frame takes ([`Bus::frame_time`]); elsewhere a retry comes after the
    /// timeout, as for other transfers. How many of the requests each node answered is
    /// kept in [`Observed::answers_counted`], with every answer to every
    /// read of the batch; a node that answered none of a read's requests is not asked
    /// the rest of its reads in the batch.
    pub ask_again_after: Option<Duration>,
}

/// What [`SdoOptions::on_progress`] calls.
pub type TransferHook = Arc<dyn Fn(usize) + Send + Sync>;

impl std::fmt::Debug for SdoOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SdoOptions")
            .field("timeout", &self.timeout)
            .field("block_upload", &self.block_upload)
            .field("block_download", &self.block_download)
            .field("size_hint", &self.size_hint)
            .field("max_upload", &self.max_upload)
            .field("stop", &self.stop)
            .field("on_progress", &self.on_progress.as_ref().map(|_| "(hook)"))
            .field("retries", &self.retries)
            .field("ask_again_after", &self.ask_again_after)
            .finish()
    }
}

impl SdoOptions {
    /// The defaults with this timeout: block download allowed, no block upload, the
    /// default upload limit and retries, no stop, no progress.
    pub fn new(timeout: Duration) -> SdoOptions {
        SdoOptions {
            timeout,
            block_upload: false,
            block_download: true,
            size_hint: None,
            max_upload: crate::canopen::sdo::client::DEFAULT_MAX_UPLOAD,
            stop: None,
            on_progress: None,
            retries: crate::canopen::sdo::retry::DEFAULT_RETRIES,
            ask_again_after: None,
        }
    }
}

/// One transfer of [`Bus::sdo_batch`].
#[derive(Clone, Debug)]
pub enum SdoJob {
    /// Read an object (SDO upload).
    Upload {
        /// The node to read from.
        node: u8,
        /// The object read.
        addr: ObjAddr,
        /// Its timeout and transfer kind.
        opts: SdoOptions,
    },
    /// Write an object (SDO download).
    Download {
        /// The node to write to.
        node: u8,
        /// The object written.
        addr: ObjAddr,
        /// The bytes written.
        data: Vec<u8>,
        /// Its timeout and transfer kind.
        opts: SdoOptions,
    },
}

impl SdoJob {
    /// How this transfer is made.
    pub fn opts(&self) -> &SdoOptions {
        match self {
            SdoJob::Upload { opts, .. } | SdoJob::Download { opts, .. } => opts,
        }
    }

    /// The same transfer, made with `change(opts)`.
    pub(crate) fn with_opts(&self, change: impl Fn(&SdoOptions) -> SdoOptions) -> SdoJob {
        match self {
            SdoJob::Upload { node, addr, opts } => SdoJob::Upload { node: *node, addr: *addr, opts: change(opts) },
            SdoJob::Download { node, addr, data, opts } => {
                SdoJob::Download { node: *node, addr: *addr, data: data.clone(), opts: change(opts) }
            }
        }
    }
}

/// How many LSS answers to wait for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LssWait {
    /// An unconfirmed service: send and go on.
    Nothing,
    /// Done at the first answer (or when the wait is over).
    First,
    /// Every answer within the wait.
    All,
    /// The first answer, then any others that come within this much more (never past the
    /// wait): several slaves may answer one request, and a straggler must not count for
    /// the next.
    Settle(Duration),
}

/// One LSS slave answer and when it came, timed from the request.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct LssAnswer {
    /// The answer frame's eight bytes.
    pub data: [u8; 8],
    /// How long after the request it came.
    pub after: Duration,
}

/// One LSS exchange: a request and the answers to wait for (see [`Bus::lss_exchange`]).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct LssExchange {
    /// The master's request, eight bytes on 0x7E5.
    pub request: [u8; 8],
    /// The command specifier of the answers that count.
    pub expect: u8,
    /// How long to wait for them.
    pub wait: Duration,
    /// How many to wait for.
    pub collect: LssWait,
}

/// Node 0 in an NMT command addresses every node.
pub const ALL_NODES: u8 = 0;

/// The services commands use; one implementation per kind of link.
///
/// The methods up to [`Bus::close`] are the core: what a kind of link does its own way (a
/// backend) or passes on (a decorator such as [`stoppable::Stoppable`](super::stoppable::Stoppable), which passes on
/// the ones it leaves alone with the crate's `pass_on_unchanged!`). The ones after it are
/// built on the core only and are never overridden, so that a decorator that forwards the
/// core passes on everything the bus under it does (a [`Master`](super::Master) runs a batch of transfers
/// in parallel; single transfers are batches of one).
pub trait Bus {
    /// What this bus is, for messages: `sim`, `socketcan:can0`.
    fn describe(&self) -> String;

    /// Run SDO uploads and downloads, at most one per node at a time; a backend that can
    /// keeps one per node in flight at once. A download's answer is empty. `progress` is
    /// called with the number finished so far, as each ends. The outer error is a link
    /// failure (or a request no transfer could begin with); the inner ones belong to each
    /// job, one per job, in the jobs' order.
    fn sdo_batch(&mut self, jobs: &[SdoJob], progress: &mut dyn FnMut(usize)) -> Result<Vec<Result<Vec<u8>>>>;

    /// Send an NMT command to one node, or to all with `ALL_NODES`.
    fn nmt(&mut self, cmd: Command, node: u8) -> Result<()>;

    /// Sends one raw frame (SYNC, a PDO, LSS): nothing waits for an answer.
    fn send_frame(&mut self, frame: &Frame) -> Result<()>;

    /// The next frame seen on the bus with the moment it was there (see
    /// [`FrameLink::recv_stamped`]), or `None` at the deadline. Backends that know no
    /// better stamp the moment of receipt.
    fn recv_frame_stamped(&mut self, deadline: Instant) -> Result<Option<(Frame, Instant)>>;

    /// Send a remote request for `id` and return the first data frame with that id.
    fn request_frame(&mut self, id: u16, len: u8, timeout: Duration) -> Result<Frame>;

    /// Make one LSS exchange (see [`Bus::lss_exchange`]).
    fn lss(&mut self, exchange: &LssExchange) -> Result<Vec<LssAnswer>>;

    /// The bus's clock: every deadline given to this bus and every stamp it returns is on
    /// it. Monotonic on hardware, virtual in the simulator, where waiting makes time pass.
    /// Procedures read time here, never from the wall clock.
    fn now(&self) -> Instant;

    /// Let time pass until `t` on the bus's clock, sending nothing; frames that arrive
    /// meanwhile wait for the next `recv_frame`.
    fn sleep_until(&mut self, t: Instant) -> Result<()>;

    /// Whether this link shows the bus's own traffic (heartbeats, boot-ups, PDOs). An EPOS2
    /// answers commands only, so frames must be asked for with `request_frame`.
    fn sees_traffic(&self) -> bool;

    /// The longest an 8-byte data frame occupies the bus (worst-case stuffing), when the
    /// link knows its bit rate: when requests sent now will have left the bus. A
    /// decorator passes it on (`pass_on_unchanged!`).
    fn frame_time(&self) -> Option<Duration> {
        None
    }

    /// Whether the link itself follows an LSS bit-rate switch (see `FrameLink`). A
    /// decorator passes it on (`pass_on_unchanged!`).
    fn follows_bit_rate_switch(&self) -> bool {
        false
    }

    /// Whether a download to `node` that asks for SDO block transfer gets it: false where
    /// the link has none (a gateway) or the device refused it once (then segmented). A
    /// decorator passes it on (`pass_on_unchanged!`).
    fn block_transfer_to(&self, _node: u8) -> bool {
        false
    }

    /// After a silence: an error when the link reports the bus unusable (see
    /// [`FrameLink::check`]); links that cannot tell say nothing. A decorator passes it on
    /// (`pass_on_unchanged!`).
    fn check_link(&mut self) -> Result<()> {
        Ok(())
    }

    /// What the link knows about the bus beyond its frames (see [`FrameLink::report`]). A
    /// decorator passes it on (`pass_on_unchanged!`).
    fn link_report(&mut self) -> Option<controller::LinkReport> {
        None
    }

    /// The node-id a gateway answers for itself, from its own dictionary rather than over
    /// the bus (an EPOS2's own node): an answer from it shows nothing of the bus. `None` for
    /// links that are not a node. A decorator passes it on (`pass_on_unchanged!`).
    fn own_node(&mut self) -> Option<u8> {
        None
    }

    /// A listen-only trial at another bit rate (see [`FrameLink::listen_at`]). A decorator
    /// passes it on (`pass_on_unchanged!`).
    fn listen_at(&mut self, _kbit: u32, _window: Duration) -> Result<Option<controller::RateHeard>> {
        Ok(None)
    }

    /// What the bus showed by itself so far in this session (node-ids in use, NMT states,
    /// boot-ups, stray LSS answers). A link that sees no traffic knows only its own
    /// answers.
    fn observed(&mut self) -> &mut Observed;

    /// Finish cleanly; dropping without it may lose state (the simulator's).
    fn close(&mut self) -> Result<()>;

    /// Read an object.
    fn sdo_upload(&mut self, node: u8, addr: ObjAddr, opts: &SdoOptions) -> Result<Vec<u8>> {
        only(self.sdo_batch(&[SdoJob::Upload { node, addr, opts: opts.clone() }], &mut |_| {}))
    }

    /// Write an object.
    fn sdo_download(&mut self, node: u8, addr: ObjAddr, data: &[u8], opts: &SdoOptions) -> Result<()> {
        let job = SdoJob::Download { node, addr, data: data.to_vec(), opts: opts.clone() };
        only(self.sdo_batch(&[job], &mut |_| {})).map(|_| ())
    }

    /// Read many objects, as [`Bus::sdo_batch`] runs them.
    fn sdo_upload_many(
        &mut self,
        requests: &[(u8, ObjAddr)],
        opts: &SdoOptions,
        progress: &mut dyn FnMut(usize),
    ) -> Result<Vec<Result<Vec<u8>>>> {
        let jobs: Vec<SdoJob> = requests
            .iter()
            .map(|(node, addr)| SdoJob::Upload { node: *node, addr: *addr, opts: opts.clone() })
            .collect();
        self.sdo_batch(&jobs, progress)
    }

    /// Run uploads and downloads, as [`Bus::sdo_batch`] runs them.
    fn sdo_many(&mut self, jobs: &[SdoJob]) -> Result<Vec<Result<Vec<u8>>>> {
        self.sdo_batch(jobs, &mut |_| {})
    }

    /// The next frame seen on the bus, or `None` at the deadline.
    fn recv_frame(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        Ok(self.recv_frame_stamped(deadline)?.map(|(f, _)| f))
    }

    /// Send one LSS master request (0x7E5) and collect the slaves' answers (0x7E4, 8 bytes,
    /// command specifier `expect`) that arrive within `wait`; other frames never count, and
    /// do not make the wait longer. Answers left over from earlier requests are dropped
    /// first.
    fn lss_exchange(
        &mut self,
        request: &[u8; 8],
        expect: u8,
        wait: Duration,
        collect: LssWait,
    ) -> Result<Vec<LssAnswer>> {
        self.lss(&LssExchange { request: *request, expect, wait, collect })
    }
}

/// Inside `impl Bus for` a decorator: the core methods it passes on unchanged to the bus
/// in its field `$inner` (what it is, its clock, its traits, what it observed, closing).
macro_rules! pass_on_unchanged {
    ($inner:ident) => {
        fn describe(&self) -> String {
            self.$inner.describe()
        }
        fn now(&self) -> std::time::Instant {
            self.$inner.now()
        }
        fn sees_traffic(&self) -> bool {
            self.$inner.sees_traffic()
        }
        fn frame_time(&self) -> Option<std::time::Duration> {
            self.$inner.frame_time()
        }
        fn follows_bit_rate_switch(&self) -> bool {
            self.$inner.follows_bit_rate_switch()
        }
        fn block_transfer_to(&self, node: u8) -> bool {
            self.$inner.block_transfer_to(node)
        }
        fn check_link(&mut self) -> $crate::error::Result<()> {
            self.$inner.check_link()
        }
        fn link_report(&mut self) -> Option<$crate::bus::controller::LinkReport> {
            self.$inner.link_report()
        }
        fn own_node(&mut self) -> Option<u8> {
            self.$inner.own_node()
        }
        fn listen_at(
            &mut self,
            kbit: u32,
            window: std::time::Duration,
        ) -> $crate::error::Result<Option<$crate::bus::controller::RateHeard>> {
            self.$inner.listen_at(kbit, window)
        }
        fn observed(&mut self) -> &mut $crate::bus::Observed {
            self.$inner.observed()
        }
        fn close(&mut self) -> $crate::error::Result<()> {
            self.$inner.close()
        }
    };
}
pub(crate) use pass_on_unchanged;

/// The answer of a batch of one.
fn only(answers: Result<Vec<Result<Vec<u8>>>>) -> Result<Vec<u8>> {
    answers?.pop().expect("a batch answers each of its jobs")
}

/// [`Bus::sdo_batch`] for links that make one transfer at a time: `run` makes each, in
/// order. A stop is heeded between them, and a link failure ends the batch.
pub fn one_by_one(
    jobs: &[SdoJob],
    progress: &mut dyn FnMut(usize),
    mut run: impl FnMut(&SdoJob) -> Result<Vec<u8>>,
) -> Result<Vec<Result<Vec<u8>>>> {
    let mut out = Vec::with_capacity(jobs.len());
    for job in jobs {
        let stopped = job.opts().stop.as_ref().is_some_and(Cancel::is_cancelled);
        let r = if stopped { Err(crate::Error::Interrupted) } else { run(job) };
        if let Err(e @ crate::Error::Link(_)) = r {
            return Err(e);
        }
        out.push(r);
        progress(out.len());
    }
    Ok(out)
}
