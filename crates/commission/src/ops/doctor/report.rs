//! What doctor reports: the findings, each a [`Cause`] with its [`Evidence`] and
//! [`Remedy`], and what was found fine. Typed, for any front end to word.

use crate::bus::controller::{CanState, ErrorFrameCounts, RateHeard};
use crate::bus::Bus;
use crate::canopen::nmt;
use crate::canopen::ObjAddr;
use crate::error::Result;
use crate::ops::clash;
use crate::ops::node::Identity;
use serde::Serialize;
use std::time::Duration;

/// The diagnosis: findings ranked most likely cause first, and what was found fine.
#[derive(Debug, Default, Serialize)]
pub struct Diagnosis {
    /// The bus examined.
    pub bus: String,
    /// The node examined, if one was given.
    pub node: Option<u8>,
    /// How long the bus was listened to (0: a link that shows no traffic, or none done).
    pub listened_ms: u64,
    /// What is wrong, most likely cause first; empty when nothing is.
    pub findings: Vec<Finding>,
    /// What was checked and found fine, each with what showed it.
    pub fine: Vec<Evidence>,
    /// Whether nothing is wrong.
    pub ok: bool,
}

/// One cause found, with what shows it and what to do.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Finding {
    /// What is wrong.
    #[serde(flatten)]
    pub cause: Cause,
    /// The frames, answers and errors that show it.
    pub evidence: Vec<Evidence>,
    /// What to do about it.
    pub remedy: Remedy,
}

/// A cause of silence, most specific first in `Cause::rank`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(tag = "cause", rename_all = "snake_case")]
pub enum Cause {
    /// The host cannot use its link to the bus.
    Host {
        /// What the link reported.
        problem: HostProblem,
    },
    /// The CAN controller or adapter reports the bus unusable: frames nobody acknowledges,
    /// bus errors, bus-off (no other device powered, no termination, another bit rate).
    Controller {
        /// What the controller reported.
        state: ControllerState,
    },
    /// Nothing on the bus: no frame heard in the listen, no node answered the probe.
    BusSilent,
    /// Frames are heard but no node answered the probe on any id, and no node's heartbeat
    /// explains it: the devices serve no SDO there, or on other COB-IDs.
    NoAnswers,
    /// One COB-ID fills the bus (a babbling device: a high-priority id sent without pause
    /// wins every arbitration) and no node answered the probe.
    Flood {
        /// The COB-ID.
        cob_id: u16,
    },
    /// Two devices answer to one node-id.
    NodeIdClash {
        /// The node-id.
        node: u8,
    },
    /// The node is alive but Stopped: it serves no SDO there (CiA 301).
    Stopped {
        /// The node.
        node: u8,
    },
    /// The node is alive (heartbeat or guarding) but its SDO server does not answer on the
    /// default COB-IDs (0x600 + node, 0x580 + node): its 0x1200 was changed, or the server
    /// is off.
    SdoSilent {
        /// The node.
        node: u8,
    },
    /// The device the last scan saw on `node` answers on another node-id now.
    Moved {
        /// Where the last scan saw it.
        node: u8,
        /// Where it answers now.
        now: u8,
    },
    /// Nothing from the node while other nodes are heard: not powered, not connected, or
    /// on another node-id.
    NodeSilent {
        /// The node.
        node: u8,
    },
    /// Nothing from the node while other nodes are heard, on a link that cannot ask node
    /// guarding: stopped (a Stopped node without heartbeat shows nothing else), or silent.
    SilentOrStopped {
        /// The node.
        node: u8,
    },
    /// Devices wait in LSS configuration without a node-id: they serve no SDO and send no
    /// heartbeat until one is given (CiA 305).
    LssUnconfigured {
        /// How many answered "identify non-configured remote slave".
        count: usize,
    },
    /// The EPOS2 gateway's error register has its communication bit set: its CAN side sees
    /// errors (overrun, error passive, bus-off; its error history 0x1003 names which).
    Epos2CanErrors {
        /// Its error register 0x1001.
        register: u8,
    },
    /// The controller's error frames show only frames nobody acknowledged: no other
    /// device is powered, or the bus is not terminated.
    NothingAcknowledges,
    /// The controller's error frames show bit, stuff or form errors: frames are destroyed
    /// on the bus (a device at another bit rate, or the wiring).
    SignalErrors,
    /// The bus's traffic decodes cleanly at another bit rate than the link's (a sweep).
    OtherBitRate {
        /// The rate it decodes at, in kbit/s.
        kbit: u32,
    },
}

impl Cause {
    /// How likely this cause is to explain the rest (lower first): a host that cannot
    /// send explains a silent bus, a silent bus explains a silent node.
    pub(crate) fn rank(&self) -> u8 {
        match self {
            // A bit rate named names more than the controller's errors, which only say that it
            // is wrong (a host problem would have kept the sweep from running at all).
            Cause::Host { .. } | Cause::OtherBitRate { .. } => 0,
            Cause::Controller { .. } | Cause::Epos2CanErrors { .. } => 1,
            Cause::NothingAcknowledges | Cause::SignalErrors => 1,
            // A device without a node-id comes before a silent node or bus, which it explains.
            Cause::BusSilent | Cause::Flood { .. } | Cause::NoAnswers | Cause::LssUnconfigured { .. } => 2,
            Cause::NodeIdClash { .. } => 3,
            Cause::Stopped { .. } => 4,
            Cause::Moved { .. } => 5,
            Cause::SdoSilent { .. } => 6,
            Cause::NodeSilent { .. } | Cause::SilentOrStopped { .. } => 7,
        }
    }
}

/// What the host's link reported.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum HostProblem {
    /// The CAN interface is down.
    InterfaceDown,
    /// There is no interface of that name.
    NoInterface,
    /// The port or interface may not be opened by this user.
    NoPermission,
    /// The port or interface cannot be opened for another reason.
    CannotOpen,
    /// Frames could not be queued (ENOBUFS: the transmit queue is full).
    TransmitQueueFull,
    /// The serial adapter or gateway stopped answering or refused a command.
    AdapterNotAnswering,
    /// Another failure of the link (its message says which).
    LinkFailed,
}

/// What the controller or adapter reported about the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ControllerState {
    /// Bus-off: it stopped taking part after too many errors.
    BusOff,
    /// Bus errors or error-passive: frames nobody acknowledged, or a bus at another bit rate.
    BusErrors,
}

/// What was seen (or not) that shows a finding, or that something is fine.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Evidence {
    /// Frames heard in the listen, by COB-ID, with how many of each.
    Traffic {
        /// Each COB-ID heard and how many times, by COB-ID.
        frames: Vec<FrameCount>,
    },
    /// Nothing was heard in the listen.
    NothingHeard {
        /// How long it listened.
        listened_ms: u64,
    },
    /// The node's heartbeats (or boot-ups) in the listen, and the last state they said.
    Heartbeats {
        /// The node.
        node: u8,
        /// How many.
        count: usize,
        /// The last state they said.
        state: nmt::State,
    },
    /// The node's answer to a node-guarding request.
    Guarding {
        /// The node.
        node: u8,
        /// The state it said.
        state: nmt::State,
    },
    /// No answer to a node-guarding request.
    NoGuardingAnswer {
        /// The node.
        node: u8,
        /// How long it waited, on the bus's clock.
        waited_ms: u64,
    },
    /// The node answered an SDO read.
    SdoAnswer {
        /// The node.
        node: u8,
        /// The object read.
        #[serde(serialize_with = "crate::ops::values::as_text")]
        obj: ObjAddr,
        /// Its value (a u32, little-endian), or `None` for an abort.
        value: Option<u32>,
    },
    /// The node answered an SDO read with the start of a segmented upload: it is there; the
    /// value, which follows in segments, was not read.
    SdoAnswerUnread {
        /// The node.
        node: u8,
        /// The object read.
        #[serde(serialize_with = "crate::ops::values::as_text")]
        obj: ObjAddr,
    },
    /// The node answered node guarding with something that is no NMT state.
    GuardingNotAState {
        /// The node.
        node: u8,
    },
    /// Node guarding could not be asked: the link carries no remote frames (socketcand).
    GuardingUnavailable {
        /// The node.
        node: u8,
    },
    /// No answer on 0x580 + node to an SDO read sent on 0x600 + node.
    NoSdoAnswer {
        /// The node.
        node: u8,
        /// The object read.
        #[serde(serialize_with = "crate::ops::values::as_text")]
        obj: ObjAddr,
        /// How many requests were sent.
        requests: u32,
        /// How long they took together, on the bus's clock.
        waited_ms: u64,
    },
    /// An answer to the node's SDO read came on another COB-ID than 0x580 + node.
    SdoAnswerOn {
        /// The node asked.
        node: u8,
        /// The COB-ID the answer came on.
        cob_id: u16,
    },
    /// Answers to a probe of every node-id (an SDO read of 0x1000 each).
    ProbeAnswers {
        /// The node-ids that answered.
        nodes: Vec<u8>,
        /// How long the probe took, on the bus's clock.
        waited_ms: u64,
    },
    /// A node the last scan saw answered a read of 0x1000 (through a link that shows no
    /// traffic, the quick sign that the bus itself answers).
    LastScanNodeAnswers {
        /// The node-id.
        node: u8,
        /// How long the read took, on the bus's clock.
        waited_ms: u64,
    },
    /// Other nodes the bus showed in use during the command (heartbeats, answers, boot-ups).
    NodesHeard {
        /// Their node-ids.
        nodes: Vec<u8>,
    },
    /// What the last scan saw on a node-id.
    LastScan {
        /// The node-id.
        node: u8,
        /// Its vendor-ID then.
        vendor_id: Option<u32>,
        /// Its name then.
        name: Option<String>,
    },
    /// What a node answers now.
    Identity {
        /// The node-id.
        node: u8,
        /// Its identity object 0x1018.
        identity: Identity,
        /// Its name.
        name: Option<String>,
    },
    /// Two devices showed on one node-id (see `clash::Evidence`).
    Clash {
        /// What showed it.
        shown_by: clash::Evidence,
    },
    /// The link reported an error (its message).
    LinkReported {
        /// The link's message.
        message: String,
    },
    /// One device answers to the node-id: one answer to a read, its heartbeats in one
    /// state, its serial number the same in two reads.
    OneDevice {
        /// The node-id.
        node: u8,
    },
    /// The link reported no error after the requests.
    LinkQuiet,
    /// The state the scan saw the node in, and how it learnt it (node guarding, a boot-up).
    ScanState {
        /// The node.
        node: u8,
        /// The state.
        state: nmt::State,
        /// How the scan learnt it.
        from: crate::ops::scan::StateFrom,
    },
    /// What an EPOS2 gateway said of itself: its error register 0x1001 and its CAN bit
    /// rate 0x2001 (its own code: 0 = 1 Mbit/s ... 6 = 20 kbit/s, 9 = detected); each
    /// `None` when it did not answer.
    Epos2Gateway {
        /// 0x1001.
        error_register: Option<u8>,
        /// 0x2001.
        bit_rate_code: Option<u16>,
    },
    /// Frames of any kind the link received while the command ran (none answering it).
    FramesReceived {
        /// How many.
        count: usize,
    },
    /// Answers to LSS "identify non-configured remote slave" (devices without a node-id).
    LssAnswers {
        /// How many answered.
        count: usize,
        /// How long it waited, on the bus's clock.
        waited_ms: u64,
    },
    /// The CAN controller's own report (netlink): its state and counters.
    ControllerReport {
        /// The interface.
        iface: String,
        /// Its state, if it said.
        state: Option<CanState>,
        /// The transmit error counter.
        tx_errors: Option<u16>,
        /// The receive error counter.
        rx_errors: Option<u16>,
        /// The automatic restart after bus-off in ms (0: none), if it said.
        restart_ms: Option<u32>,
        /// Its bit rate, if it said.
        bitrate: Option<u32>,
    },
    /// The interface is virtual (vcan): there is no controller to report a state.
    NoController {
        /// The interface.
        iface: String,
    },
    /// The error frames the controller reported, counted by what they said.
    ErrorFrames {
        /// The interface.
        iface: String,
        /// The counts.
        counts: ErrorFrameCounts,
    },
    /// A listen-only sweep: what each bit rate heard.
    Sweep {
        /// Each rate tried, fastest first.
        trials: Vec<RateHeard>,
    },
    /// The link cannot change its bit rate for a sweep (a CAN interface, a gateway).
    NoSweep {
        /// The bus.
        bus: String,
    },
    /// Frames found the interface's transmit queue full (ENOBUFS) and waited for room.
    QueueFull {
        /// The interface.
        iface: String,
        /// How many frames waited.
        frames: u32,
    },
}

/// How many frames of one COB-ID were heard.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct FrameCount {
    /// The COB-ID.
    pub cob_id: u16,
    /// How many.
    pub count: usize,
}

/// What to do about a finding; the front end words it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(tag = "remedy", rename_all = "snake_case")]
pub enum Remedy {
    /// Do what the link's message says (bring the interface up, a permission, a queue).
    FixHost {
        /// What the link reported.
        problem: HostProblem,
    },
    /// Check that another device is powered, the wiring, the termination and the bit rate.
    CheckBus,
    /// Watch the bus to see who sends what (a stopped node, another master).
    WatchBus,
    /// Find the device that sends this COB-ID without pause and power it off or fix it.
    FindFlooder {
        /// The COB-ID.
        cob_id: u16,
    },
    /// Put the node in pre-operational (NMT), where it serves SDO.
    PreOperational {
        /// The node.
        node: u8,
    },
    /// The SDO server's COB-IDs (0x1200) were changed or it is off: a reset of the node's
    /// communication brings back the defaults unless they were stored.
    ResetCommunication {
        /// The node.
        node: u8,
    },
    /// Use the node-id the device has now, or give it back the old one over LSS.
    UseNewId {
        /// Where it was.
        node: u8,
        /// Where it is.
        now: u8,
        /// Its identity, by which LSS addresses it.
        identity: Identity,
    },
    /// Give one of the devices another node-id over LSS, by its identity.
    SeparateIds {
        /// The node-id.
        node: u8,
    },
    /// Check the node is powered, connected and has this node-id (a scan lists those in use).
    CheckNode {
        /// The node.
        node: u8,
    },
    /// Give the devices without a node-id one over LSS.
    LssAssign,
    /// As [`Remedy::CheckBus`]; and a device without a node-id would answer LSS, which
    /// doctor asks only when told (a broadcast).
    CheckBusOrLss,
    /// As [`Remedy::CheckNode`]; and a device without a node-id would answer LSS, which
    /// doctor asks only when told (a broadcast).
    CheckNodeOrLss {
        /// The node.
        node: u8,
    },
    /// The controller stays bus-off (restart-ms is 0): once the cause is fixed, let it
    /// restart by itself (`ip link set IFACE type can restart-ms 100`).
    AutoRestart {
        /// The interface.
        iface: String,
    },
    /// Nothing acknowledges: power another device, terminate the bus (120 Ω at each end).
    CheckTermination,
    /// Frames are destroyed: check every device's bit rate against the interface's, then
    /// the wiring.
    CheckBitRate {
        /// The interface's bit rate, if its controller said.
        bitrate: Option<u32>,
    },
    /// Open the link at the rate the bus's traffic decodes at.
    UseBitRate {
        /// The rate, in kbit/s.
        kbit: u32,
    },
    /// As [`Remedy::CheckBus`], on an adapter that can find the bus's rate itself: it runs
    /// at `kbit`, and a listen-only sweep (doctor's, when asked) finds the bus's.
    CheckBusOrSweep {
        /// The adapter's rate, in kbit/s.
        kbit: u32,
    },
}

pub(super) fn ms(d: Duration) -> u64 {
    d.as_millis() as u64
}

/// What `f` returned, and how long it took on the bus's clock (ms). Evidence states the
/// time a wait took, not the timeout it was allowed: an EPOS2 gateway says "no answer"
/// after a wait of its own, and reads the node-ids one after the other.
pub(super) fn timed<T>(bus: &mut dyn Bus, f: impl FnOnce(&mut dyn Bus) -> Result<T>) -> Result<(T, u64)> {
    let start = bus.now();
    let value = f(bus)?;
    Ok((value, ms(bus.now().saturating_duration_since(start))))
}
