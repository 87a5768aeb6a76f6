//! Is every node on the bus healthy? A scan, then for each node its error register
//! (0x1001), logged errors (0x1003:0) and, for CiA 402 drives, the statusword (0x6041);
//! then a short watch of the bus: each heartbeat producer's beats must come on time, and
//! no node may send an EMCY with an error.

use super::doctor::{self, Evidence};
use super::node::HISTORY_COUNT;
use super::progress::Progress;
use super::scan::{self, ScanOptions};
use super::values::le_u32;
use super::verdict::Remedy;
use crate::bus::Bus;
use crate::canopen::emcy::{self, Emergency, Origin};
use crate::canopen::nmt::{self, ErrorControl};
use crate::canopen::{cia402, ObjAddr};
use crate::error::Result;
use crate::frame::Frame;
use crate::ops::unmet::{NotHealthy, Unmet};
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

/// A heartbeat is late when no beat came for 1.5 periods plus this: what a consumer
/// usually allows, and room for the master's own scheduling.
const HEARTBEAT_SLACK: Duration = Duration::from_millis(50);
/// How long the end of a watch waits for frames from before the end that canctl has not
/// read yet.
const LATE_FRAMES: Duration = Duration::from_millis(20);
/// The shortest and longest automatic watch.
const MIN_WATCH: Duration = Duration::from_millis(300);
const MAX_WATCH: Duration = Duration::from_secs(10);

/// How to check the health of every node.
#[derive(Clone, Debug)]
pub struct HealthOptions {
    /// The scan's quiet window after the probes.
    pub window: Duration,
    /// How long to wait for each answer.
    pub timeout: Duration,
    /// How long to watch heartbeats and EMCYs; `None`: long enough for two beats of the
    /// slowest producer (0.3 s to 10 s).
    pub watch: Option<Duration>,
    /// The NMT state every node must be in, when the caller expects one.
    pub state: Option<nmt::State>,
    /// The nodes the last scan of this bus saw: one that shows nothing now is a finding
    /// (asked by node guarding first: a Stopped node answers that), never a pass.
    pub last_seen: Vec<u8>,
}

/// The health of every node found.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Health {
    /// The bus, as it describes itself.
    pub bus: String,
    /// How long the bus was watched for heartbeats and EMCYs (0: a link that shows no
    /// traffic).
    pub watched_ms: u64,
    /// Each node found, by node-id.
    pub nodes: Vec<NodeHealth>,
    /// Devices without a node-id that answered LSS (not nodes yet; not judged).
    pub lss_unconfigured: usize,
    /// The nodes that answered the scan's probe only when asked again: the bus is losing
    /// frames (not judged: each node's checks say how it is).
    pub answered_on_repeat: Vec<scan::Repeat>,
    /// Node-ids the scan found answered for by another device ([`scan::Scan::not_there`]):
    /// not nodes, not judged; said.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub not_there: Vec<u8>,
    /// Whether every node is healthy.
    pub ok: bool,
}

/// One node's health: what it showed, and each check's verdict.
#[derive(Debug, Default, Serialize)]
#[non_exhaustive]
pub struct NodeHealth {
    /// The node-id.
    pub node: u8,
    /// Its name (0x1008); none when it has none.
    pub name: Option<String>,
    /// Its device type (0x1000); none when it did not say.
    pub device_type: Option<u32>,
    /// The NMT state the node showed (heartbeat, else node guarding).
    pub nmt: Option<nmt::State>,
    /// How the NMT state was learned (`heartbeat`, `node guarding`, ...), or why it was not.
    pub nmt_from: scan::StateFrom,
    /// The producer heartbeat time 0x1017 (ms); `None`: the node has none.
    pub heartbeat_ms: Option<u16>,
    /// Heartbeats seen during the watch, and the longest time without one (ms).
    pub heartbeats: usize,
    /// The longest time without a heartbeat during the watch (from its start to the first, between two, from the last to its end), in ms; none when the node has no heartbeat time or nothing was watched.
    pub longest_gap_ms: Option<u64>,
    /// 0x1001.
    pub error_register: Option<u8>,
    /// 0x1003:0; `None`: the node keeps no history (or would not say).
    pub errors_logged: Option<u8>,
    /// EMCYs seen during the watch.
    pub emcy: Vec<SeenEmcy>,
    /// For CiA 402 drives: 0x6041 and the state it codes.
    pub statusword: Option<u16>,
    /// The CiA 402 state the statusword codes; none when it codes none, or the node is no drive.
    pub drive_state: Option<cia402::State>,
    /// Each check: `nmt`, `heartbeat`, `error register`, `emcy`, `drive`.
    pub checks: Vec<Check>,
    /// Every check passed.
    pub ok: bool,
    /// For a node silent to SDO, the likely cause as `canctl doctor` names it, from what
    /// the scan and the watch already saw (no request of its own); `None` for the others.
    pub diagnosis: Option<doctor::Finding>,
}

/// One EMCY the node sent during the watch.
pub use super::verdict::SeenEmcy;

/// One check of one node: the verdict `network check` gives too.
pub use super::verdict::Verdict as Check;
/// What a check found.
pub use super::verdict::{Finding, Logged};

impl Health {
    /// The report without the nodes' diagnoses (the user asked for none).
    pub fn without_diagnoses(mut self) -> Health {
        self.nodes.iter_mut().for_each(|n| n.diagnosis = None);
        self
    }

    /// The verdict (exit 6) when any node is not healthy.
    pub fn outcome(&self) -> Result<(), Unmet> {
        if self.ok {
            return Ok(());
        }
        let failed = |n: &NodeHealth| n.checks.iter().filter(|c| !c.ok).map(|c| c.check).collect();
        let nodes =
            self.nodes.iter().filter(|n| !n.ok).map(|n| NotHealthy { node: n.node, failed: failed(n) }).collect();
        Err(Unmet::Unhealthy { bus: self.bus.clone(), total: self.nodes.len(), nodes })
    }
}

/// How a producer's heartbeats came during a watch: `arrivals` are their times from the
/// start of the watch, which lasted `watched`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Beats {
    pub count: usize,
    /// The longest time without a beat: from the start to the first, between two, from
    /// the last to the end.
    pub longest_gap: Duration,
    pub on_time: bool,
}

/// The longest a producer of this period may go without a beat.
pub(crate) fn allowed_gap(period: Duration) -> Duration {
    period * 3 / 2 + HEARTBEAT_SLACK
}

/// Judge a producer's beats: on time when no gap was longer than [`allowed_gap`].
pub(crate) fn judge_beats(period: Duration, arrivals: &[Duration], watched: Duration) -> Beats {
    let mut edges = vec![Duration::ZERO];
    edges.extend(arrivals.iter().copied().filter(|t| *t <= watched));
    edges.push(watched);
    let longest_gap = edges.windows(2).map(|w| w[1].saturating_sub(w[0])).max().unwrap_or_default();
    Beats { count: arrivals.len(), longest_gap, on_time: longest_gap <= allowed_gap(period) }
}

/// The watch that lets every producer of these periods miss a beat visibly: two periods of
/// the slowest and the slack, 0.3 s to 10 s.
pub(crate) fn watch_for(periods: impl Iterator<Item = Duration>) -> Duration {
    let slowest = periods.max().unwrap_or_default();
    (slowest * 2 + HEARTBEAT_SLACK).clamp(MIN_WATCH, MAX_WATCH)
}

/// The node's heartbeat period (0x1017), when it produces one.
fn period(n: &scan::Node) -> Option<Duration> {
    n.heartbeat_ms.filter(|ms| *ms > 0).map(|ms| Duration::from_millis(ms.into()))
}

/// What the watch saw of one node.
#[derive(Default)]
struct Watched {
    arrivals: Vec<Duration>,
    state: Option<nmt::State>,
    emcy: Vec<Emergency>,
}

/// Heartbeats and EMCYs (on each node's COB-ID, `emcy_cobs`) of these nodes until `watch`
/// has passed. Each beat counts at the moment the link says it was on the bus, not when
/// canctl read it: on a loaded host frames wait and come in a burst, and a healthy
/// producer must not look late for it.
fn watch_bus(
    bus: &mut dyn Bus,
    nodes: &[scan::Node],
    emcy_cobs: &BTreeMap<u16, u8>,
    watch: Duration,
) -> Result<BTreeMap<u8, Watched>> {
    let mut seen: BTreeMap<u8, Watched> = nodes.iter().map(|n| (n.node, Watched::default())).collect();
    let start = bus.now();
    let end = start + watch;
    let mut take = |f: Frame, at: Instant| {
        let at = at.saturating_duration_since(start);
        if let Some((node, ErrorControl::State { state, .. })) = ErrorControl::parse(&f) {
            if let Some(w) = seen.get_mut(&node) {
                w.arrivals.push(at);
                w.state = Some(state);
            }
        } else if let (Some(node), false) = (emcy_cobs.get(&f.id()), f.is_remote()) {
            if let (Some(w), Some(e)) = (seen.get_mut(node), Emergency::decode(f.data())) {
                w.emcy.push(e);
            }
        }
    };
    while let Some((f, at)) = bus.recv_frame_stamped(end)? {
        if at > end {
            return Ok(seen);
        }
        take(f, at);
    }
    // Frames that were on the bus before the end may still wait to be read (canctl itself
    // was held up): taken until one from after the end, or the link falls quiet.
    while let Some((f, at)) = bus.recv_frame_stamped(bus.now() + LATE_FRAMES)?.filter(|(_, at)| *at <= end) {
        take(f, at);
    }
    Ok(seen)
}

/// Per node: 0x1001, 0x1003:0, 0x1014 and, for drives, 0x6041, all nodes at once.
struct Read {
    register: Result<Vec<u8>>,
    history: Result<Vec<u8>>,
    emcy_cob: Result<Vec<u8>>,
    statusword: Option<Result<Vec<u8>>>,
}

/// The COB-ID the node sends its EMCYs on (0x1014 as read, else the default 0x80 + node);
/// `None` when it says it sends none (bit 31).
fn emcy_cob(read: Option<&Read>, node: u8) -> Option<u16> {
    match read.and_then(|r| r.emcy_cob.as_ref().ok()).filter(|b| b.len() >= 4).map(|b| le_u32(b)) {
        Some(cob) if cob & 0x8000_0000 != 0 => None,
        Some(cob) => Some((cob & 0x7FF) as u16),
        None => Some(emcy::cob(node)),
    }
}

/// What each node holds, read from every node at once; `None` for a node that answers no
/// SDO (its sdo check says so): reading it would only wait.
fn read_objects(bus: &mut dyn Bus, found: &[scan::Node], timeout: Duration) -> Result<Vec<Option<Read>>> {
    let is_drive = |n: &scan::Node| n.device_type.is_some_and(cia402::is_drive);
    let objects = |n: &scan::Node| {
        let read = [ObjAddr::ERROR_REGISTER, HISTORY_COUNT, ObjAddr::EMCY_COB_ID].into_iter();
        let node = n.node;
        read.chain(is_drive(n).then_some(cia402::STATUSWORD)).map(move |addr| (node, addr))
    };
    let requests: Vec<(u8, ObjAddr)> = found.iter().filter(|n| n.answers_sdo).flat_map(objects).collect();
    let mut answers = bus
        .sdo_upload_many(
            &requests,
            &super::sdo_options::capped(timeout, super::sdo_options::NUMBER_LIMIT),
            &mut |_| {},
        )?
        .into_iter();
    let mut next = || answers.next().expect("one answer per request");
    let mut read = |n: &scan::Node| {
        let (register, history, emcy_cob) = (next(), next(), next());
        Read { register, history, emcy_cob, statusword: is_drive(n).then(&mut next) }
    };
    Ok(found.iter().map(|n| n.answers_sdo.then(|| read(n))).collect())
}

/// Check every node the scan finds.
pub fn health(bus: &mut dyn Bus, o: &HealthOptions, progress: &mut dyn Progress) -> Result<Health> {
    let found = scan::scan_against(bus, &ScanOptions { window: o.window, timeout: o.timeout }, &o.last_seen, progress)?;
    let reads = read_objects(bus, &found.nodes, o.timeout)?;
    let watch = if bus.sees_traffic() {
        o.watch.unwrap_or_else(|| watch_for(found.nodes.iter().filter_map(period)))
    } else {
        Duration::ZERO
    };
    let emcy_cobs: BTreeMap<u16, u8> =
        found.nodes.iter().zip(&reads).filter_map(|(n, r)| Some((emcy_cob(r.as_ref(), n.node)?, n.node))).collect();
    progress.start("watching heartbeats and EMCYs", 1);
    let mut seen =
        if watch > Duration::ZERO { watch_bus(bus, &found.nodes, &emcy_cobs, watch)? } else { BTreeMap::new() };
    progress.finish();
    let judge = |(n, read): (&scan::Node, _)| judge_node(n, read, seen.remove(&n.node), watch, o.state);
    let mut nodes: Vec<NodeHealth> = found.nodes.iter().zip(reads).map(judge).collect();
    let answered = found.nodes.iter().filter(|n| n.answers_sdo).map(|n| n.node).collect();
    let probe = Evidence::ProbeAnswers { nodes: answered, waited_ms: o.timeout.as_millis() as u64 };
    for (h, n) in nodes.iter_mut().zip(&found.nodes) {
        h.diagnosis = diagnose(n, h, &probe);
    }
    nodes.extend(found.gone.iter().map(|g| gone(g, &probe)));
    nodes.sort_by_key(|n| n.node);
    // Two devices on one node-id: whatever else that node's answers say, they are not one
    // device's.
    for c in &found.clashes {
        if let Some(n) = nodes.iter_mut().find(|n| n.node == c.node) {
            n.checks.push(check("node-id", false, Finding::NodeIdClash { clash: c.clone() }));
            n.ok = false;
        }
    }
    let ok = nodes.iter().all(|n| n.ok);
    Ok(Health {
        bus: found.bus,
        watched_ms: watch.as_millis() as u64,
        nodes,
        lss_unconfigured: found.lss_unconfigured,
        answered_on_repeat: found.answered_on_repeat,
        not_there: found.not_there,
        ok,
    })
}

/// Why a node the scan saw is silent to SDO, from what the scan and the watch showed (the
/// one listen all nodes share; nothing asked of the bus): its state (stopped: it serves no
/// SDO; another: its SDO server is elsewhere or off), else only that it is silent.
fn diagnose(n: &scan::Node, h: &NodeHealth, probe: &Evidence) -> Option<doctor::Finding> {
    if n.answers_sdo {
        return None;
    }
    let node = n.node;
    let shown = match (h.heartbeats, h.nmt) {
        (count @ 1.., Some(state)) => Some((state, Evidence::Heartbeats { node, count, state })),
        (_, Some(state)) => Some((state, Evidence::ScanState { node, state, from: n.state_from })),
        (_, None) => None,
    };
    Some(doctor::silent_node(node, shown, probe.clone()))
}

/// A node the last scan saw that shows nothing now: not healthy, silent as far as the bus
/// can tell.
fn gone(g: &scan::Gone, probe: &Evidence) -> NodeHealth {
    NodeHealth {
        node: g.node,
        nmt_from: g.from,
        checks: vec![check("sdo", false, Finding::Gone { from: g.from })],
        diagnosis: Some(doctor::silent_node(g.node, None, probe.clone())),
        ..NodeHealth::default()
    }
}

fn check(check: &'static str, ok: bool, detail: Finding) -> Check {
    Check::new(check, ok, detail)
}

fn judge_node(
    n: &scan::Node,
    read: Option<Read>,
    watched: Option<Watched>,
    watch: Duration,
    want: Option<nmt::State>,
) -> NodeHealth {
    let watched = watched.unwrap_or_default();
    let origin =
        Origin { device_type: n.device_type, vendor: n.vendor_id, product: n.product_code, name: n.name.clone() };
    let mut h = NodeHealth {
        node: n.node,
        name: n.name.clone(),
        device_type: n.device_type,
        heartbeat_ms: n.heartbeat_ms,
        heartbeats: watched.arrivals.len(),
        ..NodeHealth::default()
    };

    // Seen on the bus but silent to SDO: nothing below can be read from it.
    if !n.answers_sdo {
        let detail = Finding::SilentToSdo { from: n.state_from };
        // A Stopped node serves no SDO; one that shows another state has its SDO server
        // elsewhere or off (its diagnosis says so), and pre-operational is no remedy.
        let stopped = matches!(n.state, None | Some(nmt::State::Stopped));
        let remedy = stopped.then_some(Remedy::PreOperational { node: n.node });
        h.checks.push(check("sdo", false, detail).with_remedy(remedy));
    }

    // NMT: the latest state the node showed.
    let (state, from) = match (watched.state, n.state) {
        (Some(s), _) => (Some(s), scan::StateFrom::Heartbeat),
        (None, s) => (s, n.state_from),
    };
    (h.nmt, h.nmt_from) = (state, from);
    h.checks.push(match (state, want) {
        // A link that carries no remote frames cannot ask by node guarding: the node is
        // not at fault for that (where it beats, the heartbeat said its state).
        (None, _) if from == scan::StateFrom::NoRemoteFrames => check("nmt", true, Finding::StateNotCheckable { from }),
        (None, _) => check("nmt", false, Finding::StateUnknown { from }),
        (Some(state), Some(want)) if state != want => check("nmt", false, Finding::WrongState { state, from, want }),
        (Some(state), _) => check("nmt", true, Finding::State { state, from }),
    });

    // Heartbeat: on time over the watch, when the node produces one.
    let period = period(n);
    let beats = period.filter(|_| watch > Duration::ZERO).map(|p| judge_beats(p, &watched.arrivals, watch));
    h.longest_gap_ms = beats.map(|b| b.longest_gap.as_millis() as u64);
    let watched_ms = watch.as_millis() as u64;
    let (ok, detail) = match (n.heartbeat_ms, period, beats) {
        (None, _, _) => (true, Finding::NoHeartbeatObject),
        (Some(_), None, _) => (true, Finding::HeartbeatOff),
        (Some(period_ms), Some(_), None) => (true, Finding::HeartbeatUnwatched { period_ms }),
        (Some(period_ms), Some(_), Some(b)) if b.count == 0 => {
            (false, Finding::HeartbeatMissing { period_ms, watched_ms })
        }
        (Some(period_ms), Some(_), Some(b)) if !b.on_time => {
            let longest_gap_ms = b.longest_gap.as_millis() as u64;
            (false, Finding::HeartbeatLate { period_ms, longest_gap_ms, beats: b.count, watched_ms })
        }
        (Some(period_ms), Some(_), Some(b)) => {
            (true, Finding::HeartbeatOnTime { period_ms, beats: b.count, watched_ms })
        }
    };
    h.checks.push(check("heartbeat", ok, detail));

    // Error register, with the history's count alongside; not read from a node that
    // answers no SDO (its sdo check says so).
    if let Some(read) = &read {
        judge_register(read, &mut h);
    }

    // EMCY during the watch: any error (an "error reset" says things got better).
    let seen = |e: &Emergency| {
        let entry = emcy::HistoryEntry { raw: e.history_entry() };
        let meaning = emcy::meaning(entry.code(), entry.manufacturer(), &origin).text;
        SeenEmcy { code: e.code, register: e.register, meaning }
    };
    h.emcy = watched.emcy.iter().map(seen).collect();
    let errors = watched.emcy.iter().any(|e| e.code != 0);
    h.checks.push(if watch == Duration::ZERO {
        check("emcy", true, Finding::EmcyUnwatched)
    } else if h.emcy.is_empty() {
        check("emcy", true, Finding::NoEmcy { watched_ms })
    } else {
        check("emcy", !errors, Finding::Emcys { seen: h.emcy.clone() })
    });

    // A CiA 402 drive: not in Fault.
    if let Some(r) = read.as_ref().and_then(|r| r.statusword.as_ref()) {
        judge_drive(r, &mut h);
    }
    h.ok = h.checks.iter().all(|c| c.ok);
    h
}

/// The error register's check, with the history's count alongside, into `h`.
fn judge_register(read: &Read, h: &mut NodeHealth) {
    let register = read.register.as_ref().ok().and_then(|b| b.first().copied());
    let logged = read.history.as_ref().ok().and_then(|b| b.first().copied());
    (h.error_register, h.errors_logged) = (register, logged);
    // The history's part ends the detail: errors logged have their remedy after it.
    let (history, read_them) = match &read.history {
        Ok(_) => match logged {
            Some(0) => (Logged::Nothing, None),
            Some(k) => (Logged::Count(k), Some(Remedy::ReadErrorHistory { node: h.node })),
            None => (Logged::Unsaid, None),
        },
        Err(e) if super::node::is_missing(e) => (Logged::NoHistory, None),
        Err(e) => (Logged::Unread(e.into()), None),
    };
    h.checks.push(match (&read.register, register) {
        (Err(e), _) => check("error register", false, Finding::RegisterUnread { error: e.into() }),
        (Ok(_), None) => check("error register", false, Finding::RegisterEmpty),
        (Ok(_), Some(r)) => {
            check("error register", r == 0, Finding::Register { register: r, logged: history }).with_remedy(read_them)
        }
    });
}

/// A CiA 402 drive's check from its statusword read (not in Fault), into `h`.
fn judge_drive(r: &Result<Vec<u8>>, h: &mut NodeHealth) {
    let statusword = r.as_ref().ok().filter(|b| b.len() >= 2).map(|b| u16::from_le_bytes([b[0], b[1]]));
    let drive_state = statusword.and_then(cia402::State::from_statusword);
    (h.statusword, h.drive_state) = (statusword, drive_state);
    h.checks.push(match (r, statusword, drive_state) {
        (Err(e), _, _) => check("drive", false, Finding::StatuswordUnread { error: e.into() }),
        (Ok(_), None, _) => check("drive", false, Finding::StatuswordShort),
        (Ok(_), Some(statusword), None) => check("drive", false, Finding::NoDriveState { statusword }),
        (Ok(_), Some(statusword), Some(state)) => {
            let faulted = matches!(state, cia402::State::Fault | cia402::State::FaultReactionActive);
            let warning = statusword & cia402::sw::WARNING != 0;
            check("drive", !faulted, Finding::Drive { state, statusword, warning })
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canopen::abort;
    use crate::error::Error;

    const MS: Duration = Duration::from_millis(1);

    #[test]
    fn beats_every_period_are_on_time() {
        let arrivals: Vec<Duration> = (0..8).map(|k| (10 + 40 * k) * MS).collect();
        let b = judge_beats(40 * MS, &arrivals, 300 * MS);
        assert_eq!(b, Beats { count: 8, longest_gap: 40 * MS, on_time: true });
    }

    #[test]
    fn one_lost_beat_is_within_the_allowance_two_are_not() {
        // 100 ms producer: allowed 200 ms without a beat.
        assert_eq!(allowed_gap(100 * MS), 200 * MS);
        let one_lost = [50 * MS, 250 * MS, 350 * MS];
        assert!(judge_beats(100 * MS, &one_lost, 400 * MS).on_time);
        let two_lost = [50 * MS, 350 * MS];
        let b = judge_beats(100 * MS, &two_lost, 400 * MS);
        assert_eq!((b.on_time, b.longest_gap), (false, 300 * MS));
    }

    #[test]
    fn silence_at_the_start_or_the_end_counts() {
        // Stopped beating: nothing after the first beat.
        let b = judge_beats(100 * MS, &[20 * MS], 400 * MS);
        assert_eq!((b.on_time, b.longest_gap), (false, 380 * MS));
        // Started late.
        assert!(!judge_beats(100 * MS, &[260 * MS, 360 * MS], 400 * MS).on_time);
        // Never: the whole watch.
        assert_eq!(judge_beats(100 * MS, &[], 400 * MS).longest_gap, 400 * MS);
    }

    #[test]
    fn the_watch_lets_the_slowest_producer_miss_a_beat() {
        assert_eq!(watch_for([40 * MS, 100 * MS].into_iter()), MIN_WATCH);
        assert_eq!(watch_for([500 * MS].into_iter()), 1050 * MS);
        assert!(watch_for([500 * MS].into_iter()) > allowed_gap(500 * MS));
        assert_eq!(watch_for(std::iter::empty()), MIN_WATCH);
        assert_eq!(watch_for([Duration::from_secs(60)].into_iter()), MAX_WATCH);
    }

    fn sensor() -> scan::Node {
        scan::Node {
            node: 5,
            device_type: Some(0x000A_0196),
            vendor_id: Some(0x40),
            product_code: Some(0x4378_7800),
            revision: None,
            serial: None,
            name: Some("C01".into()),
            state: Some(nmt::State::Operational),
            state_from: scan::StateFrom::Heartbeat,
            heartbeat_ms: Some(40),
            answers_sdo: true,
        }
    }

    fn clean() -> Read {
        Read { register: Ok(vec![0]), history: Ok(vec![0]), emcy_cob: Ok(vec![0x85, 0, 0, 0]), statusword: None }
    }

    fn beating() -> Watched {
        Watched {
            arrivals: (0..7).map(|k| (5 + 40 * k) * MS).collect(),
            state: Some(nmt::State::Operational),
            emcy: vec![],
        }
    }

    fn failed(h: &NodeHealth) -> Vec<&str> {
        h.checks.iter().filter(|c| !c.ok).map(|c| c.check).collect()
    }

    #[test]
    fn an_emcy_with_an_error_during_the_watch_fails_the_node_an_error_reset_does_not() {
        let h = judge_node(&sensor(), Some(clean()), Some(beating()), 300 * MS, None);
        assert!(h.ok, "{:?}", h.checks);
        let mut w = beating();
        w.emcy.push(Emergency { code: 0x5000, register: 0x81, vendor: [0; 5] });
        let h = judge_node(&sensor(), Some(clean()), Some(w), 300 * MS, None);
        assert_eq!(failed(&h), ["emcy"]);
        // The sensor's manual names its code (seed 001).
        let named = |c: &Check| match &c.detail {
            Finding::Emcys { seen } => {
                seen.iter().any(|e| e.code == 0x5000 && e.meaning.starts_with("Device hardware: no stop pulses"))
            }
            _ => false,
        };
        assert!(h.checks.iter().any(named), "{:?}", h.checks);
        let mut w = beating();
        w.emcy.push(Emergency { code: 0x0000, register: 0, vendor: [0; 5] });
        assert!(judge_node(&sensor(), Some(clean()), Some(w), 300 * MS, None).ok);
    }

    #[test]
    fn a_faulted_drive_and_a_wrong_state_fail_their_checks() {
        let drive = scan::Node { device_type: Some(0x0002_0192), heartbeat_ms: Some(0), ..sensor() };
        let read = Read { statusword: Some(Ok(vec![0x08, 0x05])), ..clean() };
        let h = judge_node(&drive, Some(read), Some(Watched::default()), 300 * MS, Some(nmt::State::PreOperational));
        assert_eq!(failed(&h), ["nmt", "drive"]);
        assert_eq!(h.drive_state, Some(cia402::State::Fault));
        let read = Read { statusword: Some(Ok(vec![0x40, 0x05])), ..clean() };
        assert!(judge_node(&drive, Some(read), None, 300 * MS, None).ok);
        // A node without 0x1003 is fine; one whose 0x1001 does not answer is not.
        let read =
            Read { history: Err(Error::SdoAbort { node: 5, obj: HISTORY_COUNT, code: abort::NO_OBJECT }), ..clean() };
        assert!(judge_node(&sensor(), Some(read), Some(beating()), 300 * MS, None).ok);
        let read = Read {
            register: Err(Error::SdoAbort { node: 5, obj: ObjAddr::ERROR_REGISTER, code: abort::GENERAL_ERROR }),
            ..clean()
        };
        assert_eq!(failed(&judge_node(&sensor(), Some(read), Some(beating()), 300 * MS, None)), ["error register"]);
    }

    #[test]
    fn emcys_are_listened_for_where_0x1014_puts_them() {
        let with = |cob: Result<Vec<u8>>| emcy_cob(Some(&Read { emcy_cob: cob, ..clean() }), 5);
        assert_eq!(with(Ok(0x0000_0085u32.to_le_bytes().to_vec())), Some(0x85));
        assert_eq!(with(Ok(0x0000_0123u32.to_le_bytes().to_vec())), Some(0x123));
        assert_eq!(with(Ok(0x8000_0085u32.to_le_bytes().to_vec())), None);
        let no_object = Error::SdoAbort { node: 5, obj: ObjAddr::EMCY_COB_ID, code: abort::NO_OBJECT };
        assert_eq!(with(Err(no_object)), Some(0x85));
        assert_eq!(emcy_cob(None, 5), Some(0x85), "nothing read: the default");
    }
}
