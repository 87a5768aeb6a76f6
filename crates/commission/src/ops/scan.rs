//! Find every node on a bus: an SDO read of 0x1000 to all 127 node-ids at once, then each
//! answering node's identity (0x1018:1..4), name (0x1008) and NMT state; last, the devices
//! without a node-id (LSS "identify non-configured remote slave") and those left in LSS
//! configuration state (they answer the LSS inquiries, and without a node-id no SDO).

mod identify;
pub(crate) mod probe;
mod report;
mod window;

use probe::probe_until_stopped;
pub use probe::{probe, Repeat};
pub(crate) use probe::{probe_once, probe_rounds};
pub use report::{Configuring, Gone, Node, Phase, Scan};
pub use window::{check_window, FULL_WINDOW};

pub use super::nmt::StateFrom;
use super::progress::Progress;
use crate::bus::observer::SeenBy;
use crate::bus::{Bus, LssWait};
use crate::canopen::lss::{Identity, Inquiry, Request, Response, UNCONFIGURED};
use crate::canopen::ObjAddr;
use crate::error::{Error, Result};
use std::collections::BTreeSet;
use std::time::Duration;

/// How long to wait.
#[derive(Clone, Copy, Debug)]
pub struct ScanOptions {
    /// How long the bus must stay quiet after the last answer to the probes (slow devices
    /// answer up to 80 ms late).
    pub window: Duration,
    /// How long to wait for each answer to the identity reads.
    pub timeout: Duration,
}

impl ScanOptions {
    /// Refuses a window no device can answer within, before anything is sent.
    pub fn check(&self) -> Result<()> {
        check_window(self.window)
    }

    /// Whether slow devices may have been missed: the window is shorter than they answer in.
    pub fn may_miss_slow_devices(&self) -> bool {
        self.window < FULL_WINDOW
    }
}

/// The longest scan waits for heartbeats: a node that beats more slowly is asked by node
/// guarding instead.
const MAX_HEARTBEAT_WAIT: Duration = Duration::from_secs(3);

/// The LSS questions scan asks: "any device without a node-id?", then the inquiries only
/// devices in configuration state answer.
const LSS_QUESTIONS: [Request; 6] = [
    Request::IdentifyNonConfigured,
    Request::Inquire(Inquiry::Vendor),
    Request::Inquire(Inquiry::Product),
    Request::Inquire(Inquiry::Revision),
    Request::Inquire(Inquiry::Serial),
    Request::Inquire(Inquiry::NodeId),
];

/// Scan the bus. Stopped by the user (over a [`Stoppable`](crate::bus::stoppable::Stoppable)
/// bus), it reports what it found so far, `interrupted`.
pub fn scan(bus: &mut dyn Bus, o: &ScanOptions, progress: &mut dyn Progress) -> Result<Scan> {
    scan_against(bus, o, &[], progress)
}

/// [`scan`], knowing the nodes the last scan of this bus saw (`last_seen`): one that shows
/// nothing now (no answer to the probe, no heartbeat) is asked by node guarding. A Stopped
/// node serves no SDO and may beat no heartbeat: it answers, and is listed with its state;
/// one that does not answer that either is [`Scan::gone`], never silently left out.
pub fn scan_against(bus: &mut dyn Bus, o: &ScanOptions, last_seen: &[u8], progress: &mut dyn Progress) -> Result<Scan> {
    o.check()?;
    let mut report = Scan { bus: bus.describe(), ..Scan::default() };
    let mut phase = 0;
    match scan_into(bus, o, last_seen, progress, &mut report, &mut phase) {
        Err(e) if e.is_interrupted() => {
            progress.finish();
            (report.interrupted, report.not_done) = (true, Phase::ALL[phase..].to_vec());
            Ok(report)
        }
        other => other.map(|_| report),
    }
}

/// The scan, into `report`; `phase` says which of [`Phase::ALL`] it is in.
fn scan_into(
    bus: &mut dyn Bus,
    o: &ScanOptions,
    last_seen: &[u8],
    progress: &mut dyn Progress,
    report: &mut Scan,
    phase: &mut usize,
) -> Result<()> {
    // Where the bus's traffic is seen, "any device without a node-id?" goes out with the
    // probes and its answers come in during the same window. Round after round, the
    // inquiries wait until the probes are answered (a device in configuration state with a
    // node-id would otherwise queue its SDO answer behind its LSS answers, which lose
    // arbitration to the probes, past the first round's window), and their answers come in
    // while the identities are read. Where the probe asks again within its window, it
    // lasts a whole window past its last request, long enough for such a device's answers
    // however late they come: the inquiries go out with the probes.
    let lss_alongside = bus.sees_traffic();
    let lss_first = lss_alongside && bus.frame_time().is_some();
    // Two states at once in this scan's time are two devices on one node-id (`clash`).
    bus.observed().states_heard.clear();
    let mut inquired_by = bus.now() + o.window;
    if lss_alongside {
        bus.observed().take_lss_answers();
        let asked_first = if lss_first { &LSS_QUESTIONS[..] } else { &LSS_QUESTIONS[..1] };
        for q in asked_first {
            bus.lss_exchange(&q.encode(), 0, Duration::ZERO, LssWait::Nothing)?;
        }
    }
    let rounds = probe_rounds(bus);
    let probed = probe_until_stopped(bus, o.window, rounds, Some(ObjAddr::SERIAL_NUMBER), progress)?;
    report.nodes = probed.found.into_iter().map(|(node, device_type)| Node::probed(node, device_type)).collect();
    let serials_heard = probed.also;
    (report.probe_rounds, report.answered_on_repeat) = (probed.rounds, probed.repeats);
    if probed.stopped {
        return Err(Error::Interrupted);
    }
    if lss_alongside && !lss_first {
        inquired_by = bus.now() + o.window;
        for q in &LSS_QUESTIONS[1..] {
            bus.lss_exchange(&q.encode(), 0, Duration::ZERO, LssWait::Nothing)?;
        }
    }
    // Before the identities are read: a node listed only for another node's answer.
    let found: Vec<u8> = report.nodes.iter().map(|n| n.node).collect();
    let seen = &bus.observed().nodes;
    let shows_itself =
        seen.iter().filter(|(_, how)| how.iter().any(|h| matches!(h, SeenBy::Heartbeat | SeenBy::BootUp)));
    let suspects: BTreeSet<u8> =
        shows_itself.map(|(n, _)| *n).chain(last_seen.iter().copied()).filter(|n| !found.contains(n)).collect();
    let suspects = Vec::from_iter(suspects);
    let shown = super::answers_elsewhere::look(bus, &suspects, &found, o.window)?;
    report.nodes.retain(|n| !shown.phantoms.contains(&n.node));
    report.answers_elsewhere = shown.elsewhere.clone();
    *phase = 1;
    let silent = identify::identify(bus, &mut report.nodes, o.timeout, progress)?;
    identify::confirm_silent(bus, report, silent, o.window, progress)?;
    let serials: Vec<(u8, Option<u32>)> = report.nodes.iter().map(|n| (n.node, n.serial)).collect();
    report.clashes = super::clash::find_after(bus, &serials, o.window, o.timeout, serials_heard)?;
    *phase = 2;
    nmt_states(bus, &mut report.nodes, o)?;
    add_seen_otherwise(bus, &mut report.nodes);
    // Its answers on that COB-ID showed it to the bus's observer too: it is still not there.
    report.nodes.retain(|n| !shown.phantoms.contains(&n.node) && !report.not_there.contains(&n.node));
    let is_new = |n: &&u8| !report.nodes.iter().any(|f| f.node == **n);
    let mut unseen: Vec<Node> = last_seen.iter().filter(is_new).map(|&node| Node { node, ..Node::default() }).collect();
    guard_states(bus, &mut unseen, o)?;
    for n in unseen {
        match n.state_from {
            StateFrom::Silent { .. } | StateFrom::NoRemoteFrames => {
                report.gone.push(Gone { node: n.node, from: n.state_from })
            }
            _ => report.nodes.push(n),
        }
    }
    report.nodes.sort_by_key(|n| n.node);
    *phase = 3;
    let answers = if lss_alongside {
        // What is left of the inquiries' window (the reads above mostly took it).
        while bus.recv_frame(inquired_by)?.is_some() {}
        bus.observed().take_lss_answers()
    } else {
        let mut answers = Vec::new();
        for q in LSS_QUESTIONS {
            let expect = q.expected_answer().expect("answered");
            answers.extend(bus.lss_exchange(&q.encode(), expect, o.window, LssWait::All)?.iter().map(|a| a.data));
        }
        answers
    };
    report.lss_unconfigured = crate::bus::lss::count_non_configured(&answers);
    report.lss_configuration = configuring(&answers);
    Ok(())
}

impl Node {
    /// A node that answered the probe, before anything else is asked.
    fn probed(node: u8, device_type: Option<u32>) -> Node {
        Node { node, device_type, answers_sdo: true, ..Node::default() }
    }
}

/// The nodes the bus showed during the scan (heartbeat, boot-up, an SDO answer that came
/// after its window) that answered none of the probes, into `nodes`: they are there. A
/// Stopped node is one (it answers no SDO and keeps beating).
fn add_seen_otherwise(bus: &mut dyn Bus, nodes: &mut Vec<Node>) {
    let seen = bus.observed();
    for (node, how) in &seen.nodes {
        let shown = how.iter().any(|h| matches!(h, SeenBy::Heartbeat | SeenBy::BootUp | SeenBy::Sdo));
        if !shown || nodes.iter().any(|n| n.node == *node) {
            continue;
        }
        let state = seen.states.get(node).copied();
        let state_from = match (state, how.contains(&SeenBy::Heartbeat)) {
            (None, _) => StateFrom::LateWithoutHeartbeat,
            (Some(_), true) => StateFrom::Heartbeat,
            (Some(_), false) => StateFrom::BootUp,
        };
        nodes.push(Node { node: *node, state, state_from, ..Node::default() });
    }
    nodes.sort_by_key(|n| n.node);
}

/// Each node's NMT state as the node really shows it, never a guess that changes from run to
/// run: a node that produces heartbeats is listened to for as long as its period (read from
/// 0x1017) needs; the others are asked by node guarding; what neither answers is unknown.
fn nmt_states(bus: &mut dyn Bus, found: &mut [Node], o: &ScanOptions) -> Result<()> {
    let beating = |f: &Node| f.heartbeat_ms.is_some_and(|ms| ms > 0);
    if bus.sees_traffic() {
        let longest = found.iter().filter_map(|f| f.heartbeat_ms).max().unwrap_or(0);
        // Twice the period: one beat may have gone just before the listening began.
        let end = bus.now() + (Duration::from_millis(2 * longest as u64) + o.window).min(MAX_HEARTBEAT_WAIT);
        let missing = |bus: &mut dyn Bus, found: &[Node]| {
            found.iter().any(|f| beating(f) && !bus.observed().states.contains_key(&f.node))
        };
        while missing(bus, found) && bus.recv_frame(end)?.is_some() {}
        let states = bus.observed().states.clone();
        for f in found.iter_mut() {
            if let Some(s) = states.get(&f.node) {
                (f.state, f.state_from) = (Some(*s), StateFrom::Heartbeat);
            }
        }
    }
    guard_states(bus, found, o)
}

/// The NMT state of each of `nodes` whose state is not known yet, by node guarding (one
/// request each), or why it stays unknown.
fn guard_states(bus: &mut dyn Bus, nodes: &mut [Node], o: &ScanOptions) -> Result<()> {
    // Guarding answers come at once; a node that has none is not waited for long.
    let floor = Duration::from_millis(200);
    let guard_wait = (2 * o.window).max(floor).min(o.timeout.max(floor));
    for f in nodes.iter_mut().filter(|f| f.state.is_none()) {
        (f.state, f.state_from) = match super::node::Node::new(bus, f.node, guard_wait).guard(guard_wait) {
            // A link without remote frames (socketcand): the heartbeat was all there was.
            Err(e) if matches!(e.root(), Error::NoRemoteFrames { .. }) => (None, StateFrom::NoRemoteFrames),
            Err(e) => return Err(e),
            Ok(Some(g)) => (g.state(), StateFrom::guarding(g, bus)),
            Ok(None) => (None, StateFrom::Silent { heartbeat: f.heartbeat_ms.is_some_and(|ms| ms > 0) }),
        };
    }
    Ok(())
}

fn configuring(answers: &[[u8; 8]]) -> Configuring {
    let said = |a: &[u8; 8]| match Response::decode(a) {
        Some(Response::InquiredValue { inquiry, value }) => Some((inquiry, value)),
        _ => None,
    };
    let values = |q: Inquiry| answers.iter().filter_map(said).filter_map(|(i, v)| (i == q).then_some(v)).collect();
    let all: [Vec<u32>; 5] =
        [Inquiry::Vendor, Inquiry::Product, Inquiry::Revision, Inquiry::Serial, Inquiry::NodeId].map(values);
    let count = all.iter().map(Vec::len).max().unwrap_or(0);
    let one = match all.each_ref().map(|v| v.as_slice()) {
        [[vendor], [product], [revision], [serial], [node]] => Some((
            Identity { vendor: *vendor, product: *product, revision: *revision, serial: *serial },
            (*node as u8 != UNCONFIGURED).then_some(*node as u8),
        )),
        _ => None,
    };
    Configuring { count, one }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inquired(q: Inquiry, value: u32) -> [u8; 8] {
        Response::InquiredValue { inquiry: q, value }.encode()
    }

    /// JSON's `state_from` keeps the words scripts match on.
    #[test]
    fn where_a_state_came_from_is_said_in_words_in_json() {
        let json = |f: StateFrom| serde_json::to_value(f).unwrap();
        assert_eq!(json(StateFrom::NodeGuarding), "node guarding");
        assert_eq!(json(StateFrom::Epos2Remote), "remote request through the EPOS2");
        assert_eq!(json(StateFrom::NotAsked), "");
        assert_eq!(
            json(StateFrom::Silent { heartbeat: false }),
            "no heartbeat configured, and no answer to node guarding"
        );
    }

    #[test]
    fn one_device_in_configuration_state_is_named() {
        let mut answers = vec![Response::IdentifyNonConfiguredSlave.encode(), [0x7F, 0, 0, 0, 0, 0, 0, 0]];
        for (q, v) in [(Inquiry::Vendor, 0x40), (Inquiry::Product, 2), (Inquiry::Revision, 3), (Inquiry::Serial, 4)] {
            answers.push(inquired(q, v));
        }
        answers.push(inquired(Inquiry::NodeId, 0xFF));
        let c = configuring(&answers);
        assert_eq!(c.count, 1);
        assert_eq!(c.one, Some((Identity { vendor: 0x40, product: 2, revision: 3, serial: 4 }, None)));
        let json = serde_json::to_value(&c).unwrap();
        assert_eq!(json["devices"][0]["lss"]["vendor_id"], 0x40);
        assert_eq!(json["devices"][0]["node"], serde_json::Value::Null);
        // Two at once: counted, not paired up.
        answers.push(inquired(Inquiry::Serial, 5));
        assert_eq!(configuring(&answers), Configuring { count: 2, one: None });
        assert_eq!(configuring(&[Response::IdentifyNonConfiguredSlave.encode()]), Configuring::default());
    }
}
