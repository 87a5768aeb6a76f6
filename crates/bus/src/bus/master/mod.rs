//! CANopen client logic over a raw frame link: drives the SDO state machines, sends NMT,
//! and notes the heartbeats that pass by.

use super::api::{Bus, FrameLink, LssAnswer, LssExchange, LssWait, SdoJob, SdoOptions, TransferHook, ALL_NODES};
use super::frame_log::FrameLog;
use super::observer::Observed;
use crate::cancel::Cancel;
use crate::canopen::lss;
use crate::canopen::nmt::Command;
use crate::canopen::sdo::retry::{self, OnTimeout};
use crate::canopen::sdo::{self, SdoClient, SdoError};
use crate::canopen::{abort, ObjAddr};
use crate::error::{Error, LinkError, Moved, NodeIdRange, Result, Service, Unfinished};
use crate::frame::Frame;
use crate::trace::{self, Dir};
use std::collections::{BTreeMap, BTreeSet, VecDeque};

use std::time::{Duration, Instant};

/// How often transfers that may be stopped look at the request to stop while they wait.
const STOP_POLL: Duration = Duration::from_millis(50);
/// The most a batch waits once the user asked to stop (for a written value's answer, for
/// what an aborted transfer still sends): a signal ends any command within half a second,
/// whatever a device does.
const STOP_GRACE: Duration = Duration::from_millis(250);

/// What a batch of transfers heeds besides the bus: a request to stop, and who to tell
/// when a transfer moves on ([`SdoOptions::stop`], [`SdoOptions::on_progress`]).
#[derive(Default)]
struct Watch {
    stop: Option<Cancel>,
    on_progress: Option<TransferHook>,
}

impl Watch {
    fn of<'a>(opts: impl IntoIterator<Item = &'a SdoOptions>) -> Watch {
        let mut w = Watch::default();
        for o in opts {
            w.stop = w.stop.or_else(|| o.stop.clone());
            w.on_progress = w.on_progress.or_else(|| o.on_progress.clone());
        }
        w
    }

    fn stopped(&self) -> bool {
        self.stop.as_ref().is_some_and(Cancel::is_cancelled)
    }
}

/// The CANopen client (SDO, NMT, LSS, frames) over a raw [`FrameLink`]: the [`Bus`] of
/// SocketCAN, slcan and the simulator.
pub struct Master<L: FrameLink> {
    link: L,
    describe: String,
    /// Where every frame sent and received is also written (`--log-frames`).
    frame_log: Option<FrameLog>,
    /// Everything the received frames showed.
    observed: Observed,
    /// The error-control id a remote request waits on: its answer is node guarding.
    guarding: Option<u16>,
    /// Nodes that refused block transfer in this session: not asked again.
    no_block: BTreeSet<u8>,
    in_lss_exchange: bool,
    /// Each node's last SDO answer, which may come a second time into its next transfer.
    last_sdo_answer: BTreeMap<u8, Vec<u8>>,
    /// When the frames sent so far will have left the bus, where the link knows how long a
    /// frame takes: a request asked again early is timed from there, not from when it was
    /// queued behind a hundred others.
    bus_free_at: Instant,
}

/// How long the others' answers may hold back the first answer of a node: eight answer
/// times (`SdoOptions::timeout`), and at least 4 s, which 127 requests and their answers
/// queued on a 10 kbit/s bus take.
fn held_back_most(timeout: Duration) -> Duration {
    (timeout * 8).max(Duration::from_secs(4))
}

/// The transfers of a batch not begun yet, by node, in order: each with its slot in the
/// results.
type Queues = BTreeMap<u8, VecDeque<(usize, SdoClient, AskAgain)>>;

impl<L: FrameLink> Master<L> {
    /// A client over `link`; `describe` is the bus as messages name it (`socketcan:can0`).
    pub fn new(link: L, describe: String) -> Master<L> {
        let bus_free_at = link.now();
        Master {
            link,
            describe,
            frame_log: None,
            observed: Observed::default(),
            guarding: None,
            no_block: BTreeSet::new(),
            in_lss_exchange: false,
            last_sdo_answer: BTreeMap::new(),
            bus_free_at,
        }
    }

    /// Also write every frame sent and received to `log`.
    pub fn with_frame_log(mut self, log: Option<FrameLog>) -> Master<L> {
        self.frame_log = log;
        self
    }

    /// The link under the client (tests drive the simulator through it).
    pub fn link_mut(&mut self) -> &mut L {
        &mut self.link
    }

    /// A frame went by: to the trace and the frame log.
    fn seen(&self, dir: Dir, frame: &Frame) {
        if self.frame_log.is_none() && !trace::frames_enabled() {
            return;
        }
        let iface = self.link.name();
        trace::frame(&iface, dir, frame);
        if let Some(log) = &self.frame_log {
            log.record(&iface, frame);
        }
    }

    fn send(&mut self, frame: &Frame) -> Result<()> {
        self.seen(Dir::Tx, frame);
        self.link.send(frame)?;
        self.on_the_bus(1);
        Ok(())
    }

    /// `frames` more were sent: when they will have left the bus.
    fn on_the_bus(&mut self, frames: u32) {
        if let Some(each) = self.link.frame_time() {
            self.bus_free_at = self.bus_free_at.max(self.link.now()) + each * frames;
        }
    }

    /// Frames ready at once (a block's segments): the link may write them in one go. They
    /// go to the log once written: a write that failed part-way does not say which left.
    fn send_all(&mut self, frames: &[Frame]) -> Result<()> {
        self.link.send_all(frames)?;
        frames.iter().for_each(|f| self.seen(Dir::Tx, f));
        self.on_the_bus(frames.len() as u32);
        Ok(())
    }

    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        Ok(self.link.recv(deadline)?.inspect(|f| self.received(f)))
    }

    fn recv_stamped(&mut self, deadline: Instant) -> Result<Option<(Frame, Instant)>> {
        Ok(self.link.recv_stamped(deadline)?.inspect(|(f, _)| self.received(f)))
    }

    fn received(&mut self, f: &Frame) {
        self.seen(Dir::Rx, f);
        self.observed.on_frame(f, self.guarding, self.in_lss_exchange);
    }

    /// Run SDO transfers: one per node at a time, all nodes at once. Each ends with its
    /// answer or an error: after `timeout` without progress, at its total deadline, at a
    /// protocol error, or at the device's abort.
    fn run(
        &mut self,
        jobs: Vec<(u8, SdoClient, AskAgain)>,
        timeout: Duration,
        retries: u8,
        ask_again: Option<Duration>,
        progress: &mut dyn FnMut(usize),
        watch: &Watch,
    ) -> Result<Vec<Result<Vec<u8>>>> {
        let mut results: Vec<Option<Result<Vec<u8>>>> = (0..jobs.len()).map(|_| None).collect();
        // Which transfer each result is, for the trace.
        let jobs_of: Vec<(u8, ObjAddr)> = jobs.iter().map(|(node, client, _)| (*node, client.addr())).collect();
        let mut queues: Queues = BTreeMap::new();
        for (slot, (node, client, again)) in jobs.into_iter().enumerate() {
            queues.entry(node).or_default().push_back((slot, client, again));
        }
        self.link.set_filters(&sdo_filters(queues.keys().copied()))?;
        let mut active: BTreeMap<u8, Active> = BTreeMap::new();
        // Actions whose outcome is unknown, and the read that can tell: (slot, node, (object, value if done)).
        let mut read_backs: Vec<(usize, u8, (ObjAddr, Vec<u8>))> = Vec::new();
        let mut finished = 0;
        let nodes: Vec<u8> = queues.keys().copied().collect();
        for node in nodes.into_iter().filter(|_| !watch.stopped()) {
            self.start_next(node, &mut queues, &mut active, timeout, retries, ask_again)?;
        }
        // A node that has not answered at all is given up only once every node has been
        // quiet for `timeout`: while others still answer, the bus (or the requests queued on
        // it) may be what holds its answer back. This is what lets a scan's window count
        // from the last answer, not from when 127 probes were queued. But never past
        // `held_back_most` from its request: a device that answers without end must not
        // keep a silent node's wait going with it.
        let mut quiet_from = self.link.now();
        let mut echoes = Echoes::new();
        let deadline_of = |a: &Active, quiet_from: Instant| {
            let held_back = (quiet_from + timeout).min(a.started + held_back_most(timeout));
            match (a.heard, a.stop_by) {
                (true, _) => a.deadline(),
                (false, Some(by)) => a.deadline().max(held_back).min(by),
                (false, None) => a.deadline().max(held_back),
            }
        };
        loop {
            if watch.stopped() {
                self.stop(&mut active, &mut queues, &mut results, timeout)?;
            }
            let now = self.link.now();
            // The answers still to come to a read asked more than once.
            let awaited: Option<Instant> = echoes.values().filter(|a| awaited(a, now)).map(|a| a.counted_until).min();
            if active.is_empty() && (awaited.is_none() || watch.stopped()) {
                break;
            }
            self.ask_again_the_silent(&mut active, timeout, ask_again)?;
            // A transfer is given up at its deadline in bus time: the frame at hand is
            // judged by when it was on the bus, so answers that came in time but waited to
            // be read (this program was not running) still count. Checked on every frame,
            // not only when the link is quiet: on a busy bus frames keep coming and a
            // transfer must still end on time.
            let asking_again = active.values().filter_map(Active::asks_again_at);
            let Some(deadline) =
                active.values().map(|a| deadline_of(a, quiet_from)).chain(asking_again).chain(awaited).min()
            else {
                continue;
            };
            let wake = match deadline {
                d if d <= now => now,
                d if watch.stop.is_some() => d.min(now + STOP_POLL),
                d => d,
            };
            let received = self.recv_stamped(wake)?;
            let at = received.as_ref().map_or_else(|| self.link.now(), |(_, at)| *at);
            let expired: Vec<u8> =
                active.iter().filter(|(_, a)| deadline_of(a, quiet_from) <= at).map(|(n, _)| *n).collect();
            for node in expired {
                let mut a = active.remove(&node).expect("active");
                let addr = a.client.addr();
                // Once the user asked to stop, nothing is started again.
                let stopping = a.stop_by.is_some();
                let next = retry::on_timeout(&a.client, if stopping { 0 } else { a.retries_left });
                // Aborted so that the server forgets it, also when it never answered: its
                // answer may be what was lost, and it may be waiting for the next segment.
                if a.heard || next == OnTimeout::Again {
                    self.send(&Frame::new(sdo::request_cob(node), &sdo::abort_frame(addr, abort::TIMED_OUT)))?;
                }
                if next == OnTimeout::Again {
                    if a.heard && a.answered_attempt.is_none() {
                        a.answered_attempt = Some(expiry_error(node, &a, at, timeout));
                    }
                    a.retries_left -= 1;
                    a.requests += 1;
                    tracing::debug!(
                        target: "canctl::sdo",
                        "node {node}: SDO transfer of {addr}: nothing for {} ms, aborted and started again \
                         ({} more time(s) at most)",
                        timeout.as_millis(),
                        a.retries_left
                    );
                    let first = a.client.restart();
                    self.send(&Frame::new(sdo::request_cob(node), &first))?;
                    let now = self.link.now();
                    a.started = now;
                    a.idle_deadline = now + timeout;
                    a.total_deadline = now + a.client.time_budget(timeout);
                    a.heard = false;
                    // A transfer started again after its timeout is asked again no more.
                    a.ask_again_at = None;
                    active.insert(node, a);
                    continue;
                }
                results[a.slot] = Some(Err(match (next, retry::action(addr)) {
                    (OnTimeout::Unknown, Some(what)) => {
                        Error::SdoOutcomeUnknown { node, obj: addr, what, waited: timeout }
                    }
                    _ if !a.heard && a.answered_attempt.is_some() => {
                        a.answered_attempt.take().expect("an answered attempt")
                    }
                    // A read cut short by the stop, before its window ran out or before it
                    // was asked again: its silence says nothing of the node.
                    _ if stopping
                        && !a.heard
                        && a.client.is_upload()
                        && (a.ask_again_at.is_some() || at < a.idle_deadline.min(a.total_deadline)) =>
                    {
                        Error::Interrupted
                    }
                    _ => expiry_error(node, &a, at, timeout),
                }));
                if next == OnTimeout::Unknown && !stopping {
                    if let Some(check) = a.client.written().and_then(|w| retry::read_back(addr, w)) {
                        read_backs.push((a.slot, node, check));
                    }
                }
                finished += 1;
                // A node that answered none of its requests is not asked the rest of its
                // reads where the batch counts answers (a probe): each would be one more
                // window of silence.
                if ask_again.is_some() && !a.heard && !stopping {
                    for (slot, client, _) in queues.remove(&node).unwrap_or_default() {
                        let what = Service::Sdo(client.addr());
                        results[slot] = Some(Err(Error::NoAnswer { node, what, waited: timeout }));
                        finished += 1;
                    }
                }
                progress(finished);
                self.start_next(node, &mut queues, &mut active, timeout, retries, ask_again)?;
            }
            let Some((f, _)) = received else { continue };
            let node = f.id().wrapping_sub(0x580);
            if f.is_remote() || !(1..=127).contains(&node) {
                continue;
            }
            let node = node as u8;
            // An answer to a read already answered (not one under way of the same object).
            let reading = active.get(&node).map(|a| a.client.addr());
            let counted = echoes
                .range_mut((node, ObjAddr::new(0, 0))..=(node, ObjAddr::new(u16::MAX, u8::MAX)))
                .filter(|((_, addr), _)| reading != Some(*addr))
                .find_map(|((_, addr), asked)| Some((asked, upload_answer(f.data(), *addr)?.carried())));
            if let Some((asked, value)) = counted {
                asked.answers.push(value);
                continue;
            }
            let Some(a) = active.get_mut(&node) else {
                continue;
            };
            // Whether the transfer ends on its first answer: only then do the answers to
            // its other requests (a read asked again) show whether a frame was lost.
            let counts_answers = ask_again.is_some() && !a.heard;
            a.heard = true;
            let outcome = a.client.on_response(f.data());
            let addr = a.client.addr();
            self.last_sdo_answer.insert(node, f.data().to_vec());
            let done = match outcome {
                Ok(step) => {
                    if step.progress {
                        quiet_from = at;
                        a.idle_deadline = at + timeout;
                        // The size may have become known: the budget follows it.
                        a.total_deadline = a.started + a.client.time_budget(timeout);
                    }
                    let frames: Vec<Frame> = step.send.iter().map(|p| Frame::new(sdo::request_cob(node), p)).collect();
                    self.send_all(&frames)?;
                    // The server's answer to a request counts from when it left the bus (the
                    // link knows when: behind the other requests queued), however long ago
                    // the answer that led to it was on the bus.
                    if step.progress && !step.send.is_empty() {
                        a.idle_deadline = a.idle_deadline.max(self.bus_free_at.max(self.link.now()) + timeout);
                    }
                    if let (true, None, Some(hook)) = (step.progress, &step.done, &watch.on_progress) {
                        hook(a.client.progress().0);
                    }
                    let Some(data) = step.done else { continue };
                    Ok(data)
                }
                Err(e) => Err(e),
            };
            let a = active.remove(&node).expect("active");
            if counts_answers {
                echo(&mut echoes, node, &a, f.data(), timeout);
            }
            if done.is_ok() && a.client.fell_back() {
                self.no_block.insert(node);
            }
            results[a.slot] = Some(match done {
                Ok(data) => Ok(data),
                Err(e) => Err(self.sdo_error(node, addr, e)?),
            });
            finished += 1;
            progress(finished);
            self.start_next(node, &mut queues, &mut active, timeout, retries, ask_again)?;
        }
        if ask_again.is_some() {
            // A count the user's stop cut short (its window still open) shows no loss: the
            // answers still to come were not waited for.
            if watch.stopped() {
                let now = self.link.now();
                echoes.retain(|_, asked| !awaited(asked, now));
            }
            self.observed.answers_counted = echoes;
        }
        self.read_back(read_backs, &mut results, timeout, retries, watch)?;
        let results: Vec<Result<Vec<u8>>> = results.into_iter().map(|r| r.expect("every job ends")).collect();
        for ((node, addr), r) in jobs_of.iter().zip(&results) {
            let outcome = || r.as_ref().map_or_else(ToString::to_string, |data| format!("{} bytes", data.len()));
            tracing::trace!(target: "canctl::sdo", "node {node}: SDO transfer of {addr}: {}", outcome());
        }
        Ok(results)
    }

    /// The user asked to stop: none of the transfers not begun is, and every transfer the
    /// device has answered and that goes on (segments, blocks) ends with an abort sent to
    /// the device (CiA 301), so that it is not left waiting for the rest. A transfer whose
    /// first answer is still awaited is let finish: its one request may already have done
    /// its work (an expedited write), and an answer that goes on is aborted at the next turn.
    /// What an aborted server still sends (the rest of its sub-block) is let arrive first.
    fn stop(
        &mut self,
        active: &mut BTreeMap<u8, Active>,
        queues: &mut Queues,
        results: &mut [Option<Result<Vec<u8>>>],
        timeout: Duration,
    ) -> Result<()> {
        for (slot, _, _) in std::mem::take(queues).into_values().flatten() {
            results[slot] = Some(Err(Error::Interrupted));
        }
        let by = self.link.now() + STOP_GRACE;
        // A transfer still waiting for its first answer is let finish until `by`, not
        // started again: a write's request may have done its work, a read's answer may be
        // on its way (a scan's partial report lists the node).
        for a in active.values_mut().filter(|a| !a.heard && a.stop_by.is_none()) {
            a.stop_by = Some(by);
        }
        let heard: Vec<u8> = active.iter().filter(|(_, a)| a.heard).map(|(n, _)| *n).collect();
        for node in heard {
            let a = active.remove(&node).expect("active");
            let obj = a.client.addr();
            self.send(&Frame::new(sdo::request_cob(node), &sdo::abort_frame(obj, abort::GENERAL_ERROR)))?;
            self.let_answers_land(node, a.client.answers_in_flight(), timeout.min(STOP_GRACE), by)?;
            let (bytes, total) = a.client.progress();
            let (upload, moved) = (a.client.is_upload(), Moved { bytes, total });
            results[a.slot] =
                Some(Err(Error::SdoInterrupted { node, obj, upload, moved, aborted: Some(abort::GENERAL_ERROR) }));
        }
        Ok(())
    }

    /// Wait for what `node` still sends for a transfer just aborted, so that the next
    /// transfer (in this program or the next) does not take it for its answer. A server
    /// that stopped at the abort sends nothing: the wait ends after `timeout` of silence,
    /// and at `by` however much the server still sends.
    fn let_answers_land(&mut self, node: u8, mut expected: usize, timeout: Duration, by: Instant) -> Result<()> {
        let cob = 0x580 + u16::from(node);
        // The silence is this node's: other nodes' frames (heartbeats, their transfers)
        // do not make the wait longer, else a busy bus would hold it forever.
        let mut until = (self.link.now() + timeout).min(by);
        while expected > 0 && self.link.now() < until {
            let Some(f) = self.recv(until)? else { break };
            if f.id() != cob || f.is_remote() {
                continue;
            }
            // The server's own abort ends what it sends.
            if f.data().first() == Some(&0x80) && f.len() == 8 {
                break;
            }
            expected -= 1;
            until = (self.link.now() + timeout).min(by);
        }
        Ok(())
    }

    fn start_next(
        &mut self,
        node: u8,
        queues: &mut Queues,
        active: &mut BTreeMap<u8, Active>,
        timeout: Duration,
        retries: u8,
        ask_again: Option<Duration>,
    ) -> Result<()> {
        let Some((slot, mut client, again)) = queues.get_mut(&node).and_then(|q| q.pop_front()) else {
            return Ok(());
        };
        if let Some(previous) = self.last_sdo_answer.get(&node) {
            client.set_previous_answer(previous);
        }
        let first = client.start();
        tracing::trace!(target: "canctl::sdo", "node {node}: SDO transfer of {} starts", client.addr());
        self.send(&Frame::new(sdo::request_cob(node), &first))?;
        let now = self.link.now();
        let total_deadline = now + client.time_budget(timeout);
        // Only a plain read's request can go again while it stands: it asks nothing twice.
        let ask_again_at = ask_again
            .filter(|_| again == AskAgain::Yes && retries > 0 && is_initiate_upload(&first))
            .map(|after| self.bus_free_at.max(now) + after);
        active.insert(
            node,
            Active {
                slot,
                client,
                started: now,
                idle_deadline: now + timeout,
                total_deadline,
                heard: false,
                retries_left: retries,
                requests: 1,
                answered_attempt: None,
                stop_by: None,
                ask_again_at,
                last_left: self.bus_free_at.max(now),
            },
        );
        Ok(())
    }

    /// Actions whose answer was lost, where reading an object tells whether they were done
    /// (`retry::read_back`): the ones it confirms are done; the others stay unknown.
    fn read_back(
        &mut self,
        checks: Vec<(usize, u8, (ObjAddr, Vec<u8>))>,
        results: &mut [Option<Result<Vec<u8>>>],
        timeout: Duration,
        retries: u8,
        watch: &Watch,
    ) -> Result<()> {
        if checks.is_empty() || watch.stopped() {
            return Ok(());
        }
        let reads =
            checks.iter().map(|(_, node, (addr, _))| (*node, SdoClient::upload(*addr, false), AskAgain::No)).collect();
        let got = self.run(reads, timeout, retries, None, &mut |_| {}, watch)?;
        for ((slot, node, (addr, done)), read) in checks.into_iter().zip(got) {
            let confirmed = read.as_ref().is_ok_and(|v| *v == done);
            tracing::debug!(target: "canctl::sdo", "node {node}: read back {addr} after a lost answer: {read:?}");
            if confirmed {
                results[slot] = Some(Ok(Vec::new()));
            }
        }
        Ok(())
    }

    fn sdo_error(&mut self, node: u8, addr: ObjAddr, e: SdoError) -> Result<Error> {
        Ok(match e {
            SdoError::ServerAbort(code) => Error::SdoAbort { node, obj: addr, code },
            SdoError::ClientAbort { code, reason } => {
                self.send(&Frame::new(sdo::request_cob(node), &sdo::abort_frame(addr, code)))?;
                LinkError::SdoProtocol { node, obj: addr, reason, aborted: Some(code) }.into()
            }
            SdoError::Inconsistent(reason) => LinkError::SdoProtocol { node, obj: addr, reason, aborted: None }.into(),
            SdoError::OverLimit { limit, received } => {
                self.send(&Frame::new(sdo::request_cob(node), &sdo::abort_frame(addr, abort::OUT_OF_MEMORY)))?;
                LinkError::UploadOverLimit { node, obj: addr, limit, received }.into()
            }
        })
    }

    fn block_allowed(&self, node: u8, wanted: bool) -> bool {
        wanted && !self.no_block.contains(&node)
    }

    fn upload_client(&self, node: u8, addr: ObjAddr, opts: &SdoOptions) -> SdoClient {
        SdoClient::upload(addr, self.block_allowed(node, opts.block_upload))
            .with_max_upload(opts.max_upload)
            .with_size_hint(opts.size_hint)
    }
}

/// Why a transfer ran out of time, in the words a user can act on.
fn expiry_error(node: u8, a: &Active, now: Instant, timeout: Duration) -> Error {
    let obj = a.client.addr();
    if !a.heard {
        let what = match a.requests {
            1 => Service::Sdo(obj),
            requests => Service::SdoRetried { obj, requests },
        };
        return Error::NoAnswer { node, what, waited: timeout };
    }
    let (bytes, total) = a.client.progress();
    let moved = Moved { bytes, total };
    let why = if a.idle_deadline > now {
        Unfinished::Deadline { budget: a.total_deadline.saturating_duration_since(a.started), timeout }
    } else {
        match a.client.ignored() {
            Some((ignored, last)) => Unfinished::NoProgress { waited: timeout, ignored, last: last.to_string() },
            None => Unfinished::Silent { waited: timeout },
        }
    };
    Error::SdoUnfinished { node, obj, moved, why }
}

/// Receive filters for SDO transfers with these nodes: their answers, heartbeats (which
/// report NMT states on the way) and LSS answers (to a request sent along with a scan).
/// Many nodes: the whole SDO answer range.
fn sdo_filters(nodes: impl ExactSizeIterator<Item = u8>) -> Vec<(u16, u16)> {
    const HEARTBEATS: (u16, u16) = (0x700, 0x780);
    const LSS_ANSWERS: (u16, u16) = (lss::SLAVE_COB, 0x7FF);
    if nodes.len() > 8 {
        return vec![(0x580, 0x780), HEARTBEATS, LSS_ANSWERS];
    }
    nodes.map(|n| (sdo::response_cob(n), 0x7FF)).chain([HEARTBEATS, LSS_ANSWERS]).collect()
}

const EVERYTHING: [(u16, u16); 1] = [(0, 0)];

/// The longest time spent dropping frames left over before an LSS request.
const DRAIN_LIMIT: Duration = Duration::from_millis(20);

impl<L: FrameLink> Master<L> {
    /// Each read that has heard nothing and whose time to ask again has come
    /// ([`SdoOptions::ask_again_after`]) is sent again; its wait counts from the new request.
    fn ask_again_the_silent(
        &mut self,
        active: &mut BTreeMap<u8, Active>,
        timeout: Duration,
        ask_again: Option<Duration>,
    ) -> Result<()> {
        let (Some(after), now) = (ask_again, self.link.now()) else { return Ok(()) };
        for (node, a) in active.iter_mut() {
            if a.asks_again_at().is_none_or(|at| at > now) {
                continue;
            }
            let request = a.client.start();
            self.send(&Frame::new(sdo::request_cob(*node), &request))?;
            a.requests += 1;
            a.retries_left -= 1;
            a.last_left = self.bus_free_at.max(now);
            a.idle_deadline = a.idle_deadline.max(a.last_left + timeout);
            a.total_deadline = a.total_deadline.max(a.last_left + a.client.time_budget(timeout));
            a.ask_again_at = (a.retries_left > 0).then_some(a.last_left + after);
        }
        Ok(())
    }
}

fn check_node(node: u8) -> Result<()> {
    (1..=127).contains(&node).then_some(()).ok_or(Error::NodeIdOutOfRange { node, range: NodeIdRange::CanOpen })
}

mod active;
mod ask_again;
mod service;

use crate::bus::reply::upload_answer;
use active::Active;
use ask_again::{awaited, echo, is_initiate_upload, AskAgain, Echoes};

#[cfg(test)]
mod tests;
