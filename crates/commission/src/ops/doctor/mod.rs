//! Why a node, or the whole bus, is silent: a bounded look at the bus (a listen, the link's
//! own report, a probe of every node-id) and, given a node, at that node (an SDO read, its
//! heartbeat or node-guarding answer, the device the last scan saw there, a second device
//! on its id). The result is a ranked list of findings, each with the frames or errors that
//! show it and the remedy; and what was checked and found fine.
//!
//! Doctor never writes to a device and sends no broadcast: only SDO reads (uploads), node
//! guarding remote requests, and listening. Every wait is bounded by the listen window or
//! the per-request timeout ([`DoctorOptions`]).

mod controller;
mod epos2;
mod lss;
mod report;
pub mod sweep;

use report::{ms, timed};
pub use report::{Cause, ControllerState, Diagnosis, Evidence, Finding, FrameCount, HostProblem, Remedy};

use crate::bus::{Bus, SdoOptions};
use crate::canopen::nmt::{self, ErrorControl};
use crate::canopen::sdo::SdoClient;
use crate::canopen::ObjAddr;
use crate::error::{Error, LinkError, Result};
use crate::frame::Frame;
use crate::ops::clash::{self, Clash};
use crate::ops::progress::Silent;
use crate::ops::scan;
use crate::ops::scan_cache::SeenNode;
use crate::ops::values::le_u32;
use std::collections::{BTreeMap, BTreeSet};
use std::time::Duration;

/// How many requests the node's SDO read gets: a lost frame is not taken for a silent node.
const SDO_REQUESTS: u32 = 2;
/// A COB-ID heard this many times in the listen, nine frames in ten, fills the bus.
const FLOOD_FRAMES: usize = 100;
/// At most this many nodes that were not on the last scan are asked whether they are the
/// one that moved.
const MAX_CANDIDATES: usize = 8;

/// What doctor looks at, and how long it may wait.
#[derive(Clone, Debug)]
pub struct DoctorOptions {
    /// The node to examine; `None`: the bus only.
    pub node: Option<u8>,
    /// How long to listen to the bus's own traffic first (heartbeats, boot-ups, anything).
    pub listen: Duration,
    /// How long each request waits for its answer (SDO read, node guarding, the probe).
    pub timeout: Duration,
    /// What the last scan of this bus saw (`scan_cache::load`): a node that moved is
    /// recognised by it.
    pub last_scan: Vec<SeenNode>,
    /// Whether to ask for devices without a node-id (LSS "identify non-configured remote
    /// slave", CiA 305, one wait of `timeout`): a broadcast, so only when the user asks.
    pub lss: bool,
}

/// What the listen heard.
#[derive(Default)]
struct Heard {
    frames: BTreeMap<u16, usize>,
    /// Per node: heartbeats and boot-ups counted, the states said (in order, each once),
    /// the last state.
    beats: BTreeMap<u8, (usize, Vec<nmt::State>, nmt::State)>,
}

impl Heard {
    fn take(&mut self, f: &Frame) {
        if f.is_remote() {
            return;
        }
        *self.frames.entry(f.id()).or_default() += 1;
        if let Some((node, state)) = ErrorControl::parse(f).and_then(|(node, ec)| Some((node, ec.state()?))) {
            let e = self.beats.entry(node).or_insert((0, Vec::new(), state));
            e.0 += 1;
            if !e.1.contains(&state) {
                e.1.push(state);
            }
            e.2 = state;
        }
    }

    /// The COB-ID that fills the bus, if one does: at least [`FLOOD_FRAMES`] frames and
    /// nine in ten of all heard.
    fn flood(&self) -> Option<u16> {
        let total: usize = self.frames.values().sum();
        let (cob, n) = self.frames.iter().max_by_key(|(_, n)| **n)?;
        (*n >= FLOOD_FRAMES && *n * 10 >= total * 9).then_some(*cob)
    }

    /// What the bus as a whole shows when no node answered the probe (`probe`): nothing at
    /// all, or one id filling it; `None` when neither.
    fn bus_finding(&self, answered: bool, probe: &Evidence, listened_ms: u64) -> Option<Finding> {
        if answered {
            return None;
        }
        if self.frames.is_empty() {
            let evidence = vec![Evidence::NothingHeard { listened_ms }, probe.clone()];
            return Some(Finding { cause: Cause::BusSilent, evidence, remedy: Remedy::CheckBus });
        }
        let cob_id = self.flood()?;
        let evidence = vec![self.traffic(), probe.clone()];
        Some(Finding { cause: Cause::Flood { cob_id }, evidence, remedy: Remedy::FindFlooder { cob_id } })
    }

    fn traffic(&self) -> Evidence {
        Evidence::Traffic { frames: self.frames.iter().map(|(c, n)| FrameCount { cob_id: *c, count: *n }).collect() }
    }

    fn heartbeats(&self, node: u8) -> Option<Evidence> {
        let (count, _, state) = self.beats.get(&node)?;
        Some(Evidence::Heartbeats { node, count: *count, state: *state })
    }
}

impl Diagnosis {
    /// The verdict (exit 6) when a problem was found.
    pub fn outcome(&self) -> Result<(), crate::ops::unmet::Unmet> {
        match self.findings.len() {
            0 => Ok(()),
            count => Err(crate::ops::unmet::Unmet::Diagnosed { bus: self.bus.clone(), count }),
        }
    }
}

/// [`doctor`], then, given a `sweep` window, the bit-rate sweep ([`sweep::sweep`]) of an
/// adapter that listens at each rate in turn; `uri` is the bus's address, whose rate an
/// slcan adapter's names (`slcan:PORT@RATE`).
pub fn doctor_swept(
    bus: &mut dyn Bus,
    o: &DoctorOptions,
    uri: Option<&str>,
    sweep: Option<Duration>,
) -> Result<Diagnosis> {
    let mut d = doctor(bus, o)?;
    let own_kbit = match uri.map(str::parse::<crate::connect::BusAddr>) {
        Some(Ok(crate::connect::BusAddr::Slcan { kbit, .. })) => Some(kbit),
        _ => None,
    };
    match (sweep, own_kbit) {
        (Some(window), _) => sweep::sweep(bus, &mut d, own_kbit, window)?,
        (None, Some(kbit)) => sweep::offer(&mut d, kbit),
        (None, None) => {}
    }
    Ok(d)
}

/// Examine the bus and, given one, the node; link failures become findings (the host,
/// the controller), other errors end it (an interruption).
pub fn doctor(bus: &mut dyn Bus, o: &DoctorOptions) -> Result<Diagnosis> {
    let mut d = Diagnosis { bus: bus.describe(), node: o.node, ..Diagnosis::default() };
    let examined = examine(bus, o, &mut d).and_then(|()| match o.lss {
        true => lss::ask(bus, o.timeout, &mut d),
        false => {
            lss::point_at_it(&mut d);
            Ok(())
        }
    });
    if let Err(e) = examined {
        let Error::Link(link) = e.root() else { return Err(e) };
        d.findings.push(link_finding(link));
    }
    controller::examine(bus, &mut d);
    d.findings.sort_by_key(|f| f.cause.rank());
    d.ok = d.findings.is_empty();
    Ok(d)
}

/// The quick part of the checks, for a node that just did not answer a request: its state
/// from a heartbeat the bus already showed, else one node-guarding request (waiting up to
/// `wait`); when neither says it, the other nodes the bus showed during the command, else a
/// read of 0x1000 of every node-id at once (one `wait`): the node alone is silent, or the
/// whole bus. Where the link shows no traffic (an EPOS2 reads the ids one by one), a read of
/// one node of `last_scan` instead: does the bus answer but this node not? At most two
/// waits of `wait`. Reads only.
pub fn quick(bus: &mut dyn Bus, node: u8, last_scan: &[u8], wait: Duration) -> Result<Option<Finding>> {
    let beat = bus.observed().states.get(&node).copied();
    let (state, seen) = match beat {
        Some(state) => (Some(state), Evidence::Heartbeats { node, count: 1, state }),
        None => guarded(bus, node, wait)?,
    };
    let finding = |cause, remedy, evidence| Some(Finding { cause, evidence, remedy });
    Ok(match state {
        Some(state) => Some(shown_but_silent(node, state, vec![seen])),
        // Through an EPOS2 the read of every id is one after the other: far from quick.
        None if !bus.sees_traffic() => another_answers(bus, node, last_scan, wait)?
            .and_then(|other| finding(Cause::NodeSilent { node }, Remedy::CheckNode { node }, vec![seen, other])),
        // Other nodes showed themselves during the command: the bus is not silent, and no
        // probe of every node-id need say so.
        None if bus.observed().nodes.keys().any(|&n| n != node) => {
            let nodes = bus.observed().nodes.keys().copied().filter(|&n| n != node).collect();
            let heard = Evidence::NodesHeard { nodes };
            finding(Cause::NodeSilent { node }, Remedy::CheckNodeOrLss { node }, vec![seen, heard])
        }
        None => {
            let (found, waited_ms) = timed(bus, |bus| scan::probe_once(bus, wait))?;
            if found.iter().any(|(n, _)| *n == node) {
                // It answers now: a late answer, not a cause to name.
                return Ok(None);
            }
            let probe = Evidence::ProbeAnswers { nodes: found.iter().map(|(n, _)| *n).collect(), waited_ms };
            // These checks ask no LSS: where nothing answers, the fix says how to.
            let frames = bus.observed().frames;
            match (found.is_empty() && bus.observed().nodes.is_empty(), frames) {
                (true, 0) => finding(Cause::BusSilent, Remedy::CheckBusOrLss, vec![seen, probe]),
                (true, count) => {
                    finding(Cause::NoAnswers, Remedy::WatchBus, vec![seen, probe, Evidence::FramesReceived { count }])
                }
                (false, _) => finding(Cause::NodeSilent { node }, Remedy::CheckNodeOrLss { node }, vec![seen, probe]),
            }
        }
    })
}

/// A read of 0x1000 of the first node of `last_scan` other than `node`, waiting up to
/// `wait`: the evidence that it answered (any answer, an abort included), or `None` when
/// it did not either (a link that shows no traffic cannot tell a silent bus from more).
fn another_answers(bus: &mut dyn Bus, node: u8, last_scan: &[u8], wait: Duration) -> Result<Option<Evidence>> {
    // The gateway's own node answers from its own dictionary, not over the bus.
    let own = bus.own_node();
    let Some(&other) = last_scan.iter().find(|&&n| n != node && Some(n) != own) else { return Ok(None) };
    let opts =
        SdoOptions { retries: 0, ..crate::ops::sdo_options::capped(wait, crate::ops::sdo_options::NUMBER_LIMIT) };
    let (read, waited_ms) = timed(bus, |bus| Ok(bus.sdo_upload(other, ObjAddr::DEVICE_TYPE, &opts)))?;
    match read {
        Ok(_) | Err(Error::SdoAbort { .. }) => Ok(Some(Evidence::LastScanNodeAnswers { node: other, waited_ms })),
        Err(e) if e.is_interrupted() => Err(e),
        Err(_) => Ok(None),
    }
}

/// What node guarding of `node` shows, waiting up to `wait`: its state and the evidence.
/// A link that carries no remote frames (socketcand) cannot ask: that is said, never taken
/// for a failure of the node.
fn guarded(bus: &mut dyn Bus, node: u8, wait: Duration) -> Result<(Option<nmt::State>, Evidence)> {
    Ok(match timed(bus, |bus| crate::ops::node::Node::new(bus, node, wait).guard(wait)) {
        Ok((Some(g), _)) => match g.state() {
            Some(state) => (Some(state), Evidence::Guarding { node, state }),
            None => (None, Evidence::GuardingNotAState { node }),
        },
        Ok((None, waited_ms)) => (None, Evidence::NoGuardingAnswer { node, waited_ms }),
        Err(e) if matches!(e.root(), Error::NoRemoteFrames { .. }) => (None, Evidence::GuardingUnavailable { node }),
        Err(e) => return Err(e),
    })
}

/// The finding for a node that did not answer SDO, from the state it showed (`shown`: the
/// state and what showed it) and a read of every node-id (`probe`): stopped (it serves no
/// SDO there), alive with its SDO server elsewhere or off, or silent.
pub(crate) fn silent_node(node: u8, shown: Option<(nmt::State, Evidence)>, probe: Evidence) -> Finding {
    match shown {
        Some((state, seen)) => shown_but_silent(node, state, vec![seen, probe]),
        None => {
            Finding { cause: Cause::NodeSilent { node }, evidence: vec![probe], remedy: Remedy::CheckNode { node } }
        }
    }
}

/// The finding for a node that serves no SDO though it shows its NMT state (`state`, as
/// `evidence` shows it): stopped (a stopped node serves no SDO: CiA 301 §7.3.2.2), else its
/// SDO server is elsewhere or off. The one reading of it for doctor, the quick checks after a
/// command's silent node, and health.
fn shown_but_silent(node: u8, state: nmt::State, evidence: Vec<Evidence>) -> Finding {
    let (cause, remedy) = match state {
        nmt::State::Stopped => (Cause::Stopped { node }, Remedy::PreOperational { node }),
        _ => (Cause::SdoSilent { node }, Remedy::ResetCommunication { node }),
    };
    Finding { cause, evidence, remedy }
}

/// The diagnosis of a link that could not even be opened.
pub fn unopened(bus: &str, node: Option<u8>, error: &LinkError) -> Diagnosis {
    Diagnosis { bus: bus.to_string(), node, findings: vec![link_finding(error)], ..Diagnosis::default() }
}

/// The finding a link failure shows: the host's side, or the controller's report of the bus.
pub fn link_finding(error: &LinkError) -> Finding {
    let (cause, remedy) = match error {
        LinkError::BusOff { .. } => (Cause::Controller { state: ControllerState::BusOff }, Remedy::CheckBus),
        LinkError::AdapterBusError { .. } | LinkError::AdapterRefusedFrame { cob: Some(_), .. } => {
            (Cause::Controller { state: ControllerState::BusErrors }, Remedy::CheckBus)
        }
        _ => (Cause::Host { problem: host_problem(error) }, Remedy::FixHost { problem: host_problem(error) }),
    };
    Finding { cause, evidence: vec![Evidence::LinkReported { message: error.to_string() }], remedy }
}

fn host_problem(error: &LinkError) -> HostProblem {
    let io_problem = |e: &std::io::Error| match (e.kind(), e.raw_os_error()) {
        (std::io::ErrorKind::PermissionDenied, _) => HostProblem::NoPermission,
        (_, Some(ENOBUFS)) => HostProblem::TransmitQueueFull,
        _ => HostProblem::LinkFailed,
    };
    match error {
        LinkError::Down { .. } => HostProblem::InterfaceDown,
        LinkError::NoInterface { .. } | LinkError::NotCan { .. } | LinkError::NotSerialPort { .. } => {
            HostProblem::NoInterface
        }
        LinkError::Open { error, .. } => match io_problem(error) {
            HostProblem::LinkFailed => HostProblem::CannotOpen,
            p => p,
        },
        LinkError::Io { error, .. } => io_problem(error),
        LinkError::TxQueueFull { .. } => HostProblem::TransmitQueueFull,
        LinkError::AdapterRefused { .. } | LinkError::AdapterRefusedFrame { .. } | LinkError::Epos2(_) => {
            HostProblem::AdapterNotAnswering
        }
        _ => HostProblem::LinkFailed,
    }
}

/// ENOBUFS, the errno of a full transmit queue (Linux 105; the BSDs and macOS 55).
const ENOBUFS: i32 =
    if cfg!(any(target_os = "macos", target_os = "freebsd", target_os = "netbsd", target_os = "openbsd")) {
        55
    } else {
        105
    };

/// Every check, then the link's own report of the bus after them (an adapter's bus errors
/// show only once it has sent something).
fn examine(bus: &mut dyn Bus, o: &DoctorOptions, d: &mut Diagnosis) -> Result<()> {
    examine_all(bus, o, d)?;
    // The one link that shows no traffic is an EPOS2 gateway: it tells of its CAN side.
    if !bus.sees_traffic() {
        epos2::look(bus, o.timeout, d)?;
    }
    bus.check_link()?;
    d.fine.push(Evidence::LinkQuiet);
    Ok(())
}

fn examine_all(bus: &mut dyn Bus, o: &DoctorOptions, d: &mut Diagnosis) -> Result<()> {
    let mut heard = Heard::default();
    if bus.sees_traffic() {
        let end = bus.now() + o.listen;
        // Until the end even on a bus that never falls quiet (a babbling device).
        while let Some(f) = bus.recv_frame(end)?.filter(|_| bus.now() <= end) {
            heard.take(&f);
        }
        d.listened_ms = ms(o.listen);
    }
    bus.check_link()?;
    let Some(node) = o.node else { return examine_bus(bus, o, &heard, d) };
    let ((answers, elsewhere), sdo_waited_ms) = timed(bus, |bus| sdo_probe(bus, node, o.timeout, &mut heard))?;
    if let Some(first) = answers.first() {
        d.fine.push(match first.value() {
            Some(value) => Evidence::SdoAnswer { node, obj: ObjAddr::SERIAL_NUMBER, value },
            None => Evidence::SdoAnswerUnread { node, obj: ObjAddr::SERIAL_NUMBER },
        });
        d.fine.extend(heard.heartbeats(node));
        let values = answers.iter().filter_map(|r| r.value()).collect();
        return look_for_clash(bus, o, node, values, &heard, d);
    }
    let no_answer =
        Evidence::NoSdoAnswer { node, obj: ObjAddr::SERIAL_NUMBER, requests: SDO_REQUESTS, waited_ms: sdo_waited_ms };
    let mut evidence: Vec<Evidence> = heard.heartbeats(node).into_iter().collect();
    let state = match heard.beats.get(&node) {
        Some((_, _, state)) => Some(*state),
        None => {
            let (state, seen) = guarded(bus, node, o.timeout)?;
            evidence.push(seen);
            state
        }
    };
    evidence.push(no_answer.clone());
    evidence.extend(elsewhere.iter().map(|cob_id| Evidence::SdoAnswerOn { node, cob_id: *cob_id }));
    let Some(state) = state else { return node_absent(bus, o, (node, no_answer, evidence), &heard, d) };
    d.findings.push(shown_but_silent(node, state, evidence));
    Ok(())
}

/// Nothing at all from the node, silent to SDO and guarding (`absent`: the node, its SDO
/// reads unanswered and all that was seen of it): has its device moved to another id, is
/// the whole bus silent, or is only this node missing?
fn node_absent(
    bus: &mut dyn Bus,
    o: &DoctorOptions,
    (node, no_answer, mut evidence): (u8, Evidence, Vec<Evidence>),
    heard: &Heard,
    d: &mut Diagnosis,
) -> Result<()> {
    let (found, waited_ms) = timed(bus, |bus| scan::probe(bus, o.timeout, &mut Silent))?;
    let ids: Vec<u8> = found.iter().map(|(n, _)| *n).collect();
    let probe = Evidence::ProbeAnswers { nodes: ids.clone(), waited_ms };
    if let Some(mut bus_wide) = heard.bus_finding(!ids.is_empty(), &probe, d.listened_ms) {
        evidence.append(&mut bus_wide.evidence);
        bus_wide.evidence = evidence;
        d.findings.push(bus_wide);
        return Ok(());
    }
    if let Some(moved) = find_moved(bus, o, node, &ids, no_answer)? {
        d.findings.push(moved);
        return Ok(());
    }
    if !heard.frames.is_empty() {
        evidence.push(heard.traffic());
    }
    // Where node guarding could not be asked, a Stopped node looks the same.
    let unguarded = evidence.iter().any(|e| matches!(e, Evidence::GuardingUnavailable { .. }));
    evidence.push(probe);
    d.findings.push(match unguarded {
        true => Finding { cause: Cause::SilentOrStopped { node }, evidence, remedy: Remedy::PreOperational { node } },
        false => Finding { cause: Cause::NodeSilent { node }, evidence, remedy: Remedy::CheckNode { node } },
    });
    Ok(())
}

/// The device the last scan saw on `node`, found on another of the ids that answered
/// (`answering`) that the last scan did not see: the same vendor-ID and name.
fn find_moved(
    bus: &mut dyn Bus,
    o: &DoctorOptions,
    node: u8,
    answering: &[u8],
    no_answer: Evidence,
) -> Result<Option<Finding>> {
    let Some(was) = o.last_scan.iter().find(|s| s.node == node && s.scanned) else { return Ok(None) };
    let Some(vendor) = was.vendor_id else { return Ok(None) };
    let known: BTreeSet<u8> = o.last_scan.iter().filter(|s| s.scanned).map(|s| s.node).collect();
    let candidates: Vec<u8> = answering.iter().copied().filter(|n| !known.contains(n)).take(MAX_CANDIDATES).collect();
    let opts =
        SdoOptions { retries: 1, ..crate::ops::sdo_options::capped(o.timeout, crate::ops::sdo_options::NAME_LIMIT) };
    for now in candidates {
        let identity = match crate::ops::node::Node::new(bus, now, o.timeout).identity() {
            Ok(Some(identity)) if identity.vendor == vendor => identity,
            Ok(_) => continue,
            Err(e) if matches!(e.root(), Error::Link(_)) => return Err(e),
            Err(_) => continue,
        };
        let name =
            bus.sdo_upload(now, ObjAddr::DEVICE_NAME, &opts).ok().map(|b| String::from_utf8_lossy(&b).into_owned());
        if was.name.is_none() || was.name == name {
            let last = Evidence::LastScan { node, vendor_id: was.vendor_id, name: was.name.clone() };
            let evidence = vec![last, Evidence::Identity { node: now, identity, name }, no_answer];
            let (cause, remedy) = (Cause::Moved { node, now }, Remedy::UseNewId { node, now, identity });
            return Ok(Some(Finding { cause, evidence, remedy }));
        }
    }
    Ok(None)
}

/// The node answered: is it one device? Two answers to the read, heartbeats in two states,
/// a serial number that changes between reads.
fn look_for_clash(
    bus: &mut dyn Bus,
    o: &DoctorOptions,
    node: u8,
    answers: Vec<Option<u32>>,
    heard: &Heard,
    d: &mut Diagnosis,
) -> Result<()> {
    let two_answers = (answers.len() > 1).then(|| clash::Evidence::SdoAnswers { values: answers.clone() });
    let mut shown: Vec<clash::Evidence> = two_answers.into_iter().collect();
    let states = heard.beats.get(&node).filter(|(_, s, _)| s.len() > 1);
    shown.extend(states.map(|(_, states, _)| clash::Evidence::HeartbeatStates { states: states.clone() }));
    if shown.is_empty() {
        // The serial just read, against a second read: two devices whose answers merge on
        // the bus show as a serial that changes.
        let serial = answers.first().copied().flatten();
        let found: Vec<Clash> = clash::find(bus, &[(node, serial)], o.timeout, o.timeout)?;
        shown.extend(found.into_iter().map(|c| c.evidence));
    }
    if shown.is_empty() {
        d.fine.push(Evidence::OneDevice { node });
        return Ok(());
    }
    let evidence = shown.into_iter().map(|shown_by| Evidence::Clash { shown_by }).collect();
    d.findings.push(Finding { cause: Cause::NodeIdClash { node }, evidence, remedy: Remedy::SeparateIds { node } });
    Ok(())
}

/// The bus without a node: heartbeats of one id in two states, and, when the listen heard
/// nothing, a probe of every node-id.
fn examine_bus(bus: &mut dyn Bus, o: &DoctorOptions, heard: &Heard, d: &mut Diagnosis) -> Result<()> {
    for (&node, (_, states, _)) in heard.beats.iter().filter(|(_, (_, s, _))| s.len() > 1) {
        let evidence = vec![Evidence::Clash { shown_by: clash::Evidence::HeartbeatStates { states: states.clone() } }];
        d.findings.push(Finding { cause: Cause::NodeIdClash { node }, evidence, remedy: Remedy::SeparateIds { node } });
    }
    let (found, waited_ms) = timed(bus, |bus| scan::probe(bus, o.timeout, &mut Silent))?;
    // Traffic is fine only where some node answers: else it is the evidence of a finding.
    if !heard.frames.is_empty() && heard.flood().is_none() && !found.is_empty() {
        d.fine.push(heard.traffic());
    }
    let probe = Evidence::ProbeAnswers { nodes: found.iter().map(|(n, _)| *n).collect(), waited_ms };
    // A node that beats but did not answer its read: stopped, or its SDO server elsewhere.
    let answered: BTreeSet<u8> = found.iter().map(|(n, _)| *n).collect();
    for (node, (_, _, state)) in heard.beats.iter().filter(|(n, _)| !answered.contains(n)) {
        let node = *node;
        let evidence = heard.heartbeats(node).into_iter().chain([probe.clone()]).collect();
        d.findings.push(shown_but_silent(node, *state, evidence));
    }
    // A node the last scan saw that shows nothing now (no answer to the probe, no
    // heartbeat) is a finding, never a pass: node guarding tells a Stopped one.
    let unseen =
        o.last_scan.iter().filter(|s| s.scanned && !answered.contains(&s.node) && !heard.beats.contains_key(&s.node));
    for seen in unseen {
        let node = seen.node;
        let (state, guarding) = guarded(bus, node, o.timeout)?;
        let mut finding = silent_node(node, state.map(|s| (s, guarding.clone())), probe.clone());
        let last = Evidence::LastScan { node, vendor_id: seen.vendor_id, name: seen.name.clone() };
        finding.evidence.splice(0..0, [last].into_iter().chain(state.is_none().then_some(guarding)));
        d.findings.push(finding);
    }
    match heard.bus_finding(!found.is_empty(), &probe, d.listened_ms) {
        Some(finding) => d.findings.push(finding),
        None if !found.is_empty() => d.fine.push(probe),
        // Nobody answered though the bus is busy, and no heartbeat said why.
        None if d.findings.is_empty() => {
            let evidence = vec![heard.traffic(), probe];
            d.findings.push(Finding { cause: Cause::NoAnswers, evidence, remedy: Remedy::WatchBus });
        }
        None => {}
    }
    Ok(())
}

/// One SDO read of the node's serial number sent raw, up to [`SDO_REQUESTS`] times while none
/// is answered, each answer waited for `timeout`: every answer on 0x580 + node (two mean
/// two devices), and the COB-IDs an answer to it came on instead. Where the link shows no
/// traffic (an EPOS2 gateway), one read through the bus's own SDO client.
fn sdo_probe(
    bus: &mut dyn Bus,
    node: u8,
    timeout: Duration,
    heard: &mut Heard,
) -> Result<(Vec<clash::Reply>, Vec<u16>)> {
    if !bus.sees_traffic() {
        let opts = SdoOptions {
            retries: (SDO_REQUESTS - 1) as u8,
            ..crate::ops::sdo_options::capped(timeout, crate::ops::sdo_options::NUMBER_LIMIT)
        };
        return match bus.sdo_upload(node, ObjAddr::SERIAL_NUMBER, &opts) {
            Ok(v) => Ok((vec![clash::Reply::Value(le_u32(&v))], vec![])),
            Err(Error::SdoAbort { .. }) => Ok((vec![clash::Reply::Aborted], vec![])),
            Err(e) if e.is_timeout() => Ok((vec![], vec![])),
            Err(e) => Err(e),
        };
    }
    let own = crate::canopen::sdo::response_cob(node);
    let mut answers = Vec::new();
    let mut elsewhere = BTreeSet::new();
    for _ in 0..SDO_REQUESTS {
        let request = SdoClient::upload(ObjAddr::SERIAL_NUMBER, false).start();
        bus.send_frame(&Frame::new(crate::canopen::sdo::request_cob(node), &request))?;
        let end = bus.now() + timeout;
        while let Some(f) = bus.recv_frame(end)?.filter(|_| bus.now() <= end) {
            match clash::upload_answer(f.data(), ObjAddr::SERIAL_NUMBER) {
                Some(value) if f.id() == own => answers.push(value),
                // Another node's answer to the same read would need a request of its own:
                // one on another id now is this node's, moved by its 0x1200.
                Some(_) if !f.is_remote() => {
                    elsewhere.insert(f.id());
                }
                _ => heard.take(&f),
            }
        }
        if !answers.is_empty() {
            break;
        }
    }
    Ok((answers, elsewhere.into_iter().collect()))
}

#[cfg(test)]
mod tests;
