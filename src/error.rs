//! The library's error type: one variant per kind of failure, with what it is about (node,
//! object, abort code, how long was waited) as fields. Every variant belongs to one
//! [`ErrorClass`], and the class alone decides the exit code ([`Error::exit_code`]), so the
//! CLI never has to guess how a failure should end the process, and nothing ever reads an
//! error's text to decide anything.
//!
//! The display texts are the messages canctl prints; tests and the README quote them.
//! To ask what kind of failure an error is, use [`Error::class`] or [`Error::is_timeout`]
//! (which see through [`Error::Hinted`]), not a match on one variant of the class.

use crate::canopen::lss::{FastscanError, Identity};
use crate::canopen::{abort, ObjAddr};
use std::fmt;
use std::path::PathBuf;
use std::time::Duration;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    // ---- usage (exit 2) ----
    /// The user asked for something malformed or impossible, said in free form.
    #[error("{0}")]
    Usage(String),
    /// A file or stream given as input could not be used.
    #[error("{0}")]
    Input(crate::input::InputError),
    /// An EDS, DCF, XDD or XDC that cannot be read (the reason names the file) or does not
    /// parse (`FILE:LINE: why`): said once, without a prefix that repeats it.
    #[error(transparent)]
    Eds(#[from] crate::od::ReadError),
    /// A bus address that does not parse.
    #[error("bus '{}': {reason}", clipped(uri))]
    BadBusAddr { uri: String, reason: String },
    /// A node-id outside what this bus can address.
    #[error("{}", node_id_text(*node, *range))]
    NodeIdOutOfRange { node: u8, range: NodeIdRange },
    /// A value too large for an SDO download (CiA 301 sizes are 32-bit).
    #[error("{len} bytes cannot be written by SDO: CiA 301 sizes are 32-bit (at most {} bytes)", u32::MAX)]
    TooLargeForSdo { len: usize },
    /// A CAN bit rate the slcan adapter protocol has no code for.
    #[error("{port}: slcan has no {kbit} kbit/s; use one of {}", supported.join(" "))]
    SlcanBitRate { port: String, kbit: u32, supported: Vec<String> },
    /// Something this kind of bus cannot do (`{bus}: {why}`).
    #[error("{bus}: {why}")]
    NotOnThisBus { bus: String, why: &'static str },
    /// LSS was asked to give a node-id that something on the bus already answers to
    /// (`by`: "an SDO answer", "its heartbeat", ...); nothing was sent.
    #[error("node-id {node} is in use: {by} came from node {node}{}; a second device on it would make both unreachable. Nothing was sent; choose a free id (canctl scan lists those in use), or --force gives it anyway", identity.map(|i| format!(" (identity {i})")).unwrap_or_default())]
    NodeIdInUse { node: u8, identity: Option<Identity>, by: &'static str },
    /// A drive command for a node whose device type (0x1000) names another profile.
    #[error("node {node} is not a CiA 402 drive: its device type (0x1000) is 0x{device_type:08X}, {}; drive commands are for profile 402", profile_text(*device_type))]
    NotADrive { node: u8, device_type: u32 },

    // ---- no response (exit 3) ----
    /// A node did not answer at all (`node` 0: all nodes, as NMT addresses them).
    #[error("{}", no_answer_text(*node, what, *waited))]
    NoAnswer { node: u8, what: Service, waited: Duration },
    /// A write that is an action (`what`: store, program control, ...) got no answer to the
    /// request that completes it: the device may have done it. It is not repeated
    /// (`canopen::sdo::retry`); a read-back, where one can tell, did not confirm it.
    #[error("node {node}: outcome unknown: {obj} ({what}) is an action, sent once, and its answer did not come within {} ms: the device may have done it or not. Not repeated behind your back: check the device, then send it again if it was not done", waited.as_millis())]
    SdoOutcomeUnknown { node: u8, obj: ObjAddr, what: &'static str, waited: Duration },
    /// A node answered an SDO transfer, then it did not finish.
    #[error("{}", SdoUnfinishedText { node: *node, obj: *obj, moved: *moved, why })]
    SdoUnfinished { node: u8, obj: ObjAddr, moved: Moved, why: Unfinished },
    /// No answer to a remote (RTR) frame.
    #[error("no answer to the remote request for 0x{cob:03X} within {} ms", waited.as_millis())]
    NoRemoteAnswer { cob: u16, waited: Duration },
    /// No LSS device answered a confirmed LSS service; with the identity when one device
    /// was selected (the selective switch).
    #[error("{}", match identity {
        Some(id) => format!("no LSS device with identity {id} answered {request} within {} ms", waited.as_millis()),
        None => format!("no LSS device answered {request} within {} ms", waited.as_millis()),
    })]
    NoLssAnswer { request: String, identity: Option<Identity>, waited: Duration },
    /// `lss assign` gave a device a node-id and heard no answer, however often asked: the
    /// request may have reached it and only the answers been lost, so it may hold it.
    #[error(
        "no answer from {identity} to set-id {node} within {} ms, asked {tries} times: unknown whether it \
         holds node {node} now (canctl lss inquire --identity {identity} shows its node-id)",
        waited.as_millis()
    )]
    LssSetIdUnknown { identity: Identity, node: u8, tries: u32, waited: Duration },
    /// An EPOS2 gateway reports that the node behind it did not answer on the CAN bus.
    #[error("{}: no answer on the CAN bus (the EPOS2 reports SDO timeout 0x05040000)", Epos2Place { node: *node, command, obj: *obj })]
    Epos2NoCanAnswer { node: u8, command: &'static str, obj: Option<ObjAddr> },
    /// A serial CAN adapter did not answer one of its commands.
    #[error("{port}: the adapter did not answer {command:?} within {} ms", waited.as_millis())]
    AdapterNoAnswer { port: String, command: String, waited: Duration },
    /// LSS fastscan did not find a device (exit 3), or found one it could not confirm (exit 5).
    #[error("{}", fastscan_text(error, *step))]
    Fastscan { error: FastscanError, step: Duration },

    // ---- refused by the device (exit 4) ----
    /// The device refused an SDO transfer.
    #[error("node {node}: SDO abort 0x{code:08X} on {obj}: {}", abort::meaning(*code))]
    SdoAbort { node: u8, obj: ObjAddr, code: u32 },
    /// An LSS device answered a configuration service with an error.
    #[error("LSS {service}: error {error}: {}{}", crate::canopen::lss::error_meaning(*cs, *error),
        if *error == 255 { format!(" (specific code {specific})") } else { String::new() })]
    LssRefused { service: String, cs: u8, error: u8, specific: u8 },
    /// An EPOS2 answered a command with an error code (a maxon code or, where no object is
    /// involved, any code).
    #[error("{}: {}error 0x{code:08X}: {}", Epos2Place { node: *node, command, obj: *obj },
        if crate::epos2::command::is_maxon_code(*code) { "EPOS2 " } else { "" },
        crate::epos2::command::error_meaning(*code))]
    Epos2Refused { node: u8, command: &'static str, obj: Option<ObjAddr>, code: u32 },
    /// LSS assignment found no free node-id for a device.
    #[error("no free node-id left from {start} to 127 for {identity}: give a lower --start")]
    NoFreeNodeId { start: u8, identity: Identity },
    /// A node keeps no error history (it has no object 0x1003), so there is none to clear.
    #[error("node {node} keeps no error history (it has no object 0x1003): there is nothing to clear")]
    NoErrorHistory { node: u8 },
    /// A node keeps no description of itself (CiA 301 object 0x1021).
    #[error(
        "node {node}: the device does not store its EDS (0x1021); get the EDS from its vendor and give it with --eds"
    )]
    NoStoredEds { node: u8 },
    /// A node cannot store or restore (`verb`) parameters on command.
    #[error("{}", store_refused_text(*node, verb, why))]
    StoreRefused { node: u8, verb: &'static str, why: StoreRefusal },
    /// A drive command (`goal`: enable, disable …) stopped short of its goal, in `state`.
    /// Stopped for want of an answer it is a timeout (exit 3), else a refusal (exit 4).
    #[error("node {node}: {goal} stopped in {state}: {why}")]
    DriveStopped { node: u8, goal: &'static str, state: String, why: DriveStop },

    // ---- link failure (exit 5) ----
    /// The link to the bus failed, or the device answered with something unintelligible.
    #[error("{0}")]
    Link(LinkError),
    /// The EDS a node stores (0x1021) does not unpack in the format it names (0x1022).
    #[error("node {node}: its stored EDS (0x1021) cannot be used: {why}; nothing was saved")]
    StoredEds { node: u8, why: crate::od::stored::StoredError },

    // ---- verification failed (exit 6) ----
    /// An object read back other than what was written.
    #[error("node {node}: {obj} reads back {read} after writing {wrote}")]
    ReadBack { node: u8, obj: ObjAddr, wrote: String, read: String },
    /// Objects read back other than what was written.
    #[error("node {node}: {} read back other values than written", join(objects))]
    ReadBackMany { node: u8, objects: Vec<ObjAddr> },
    /// A node's objects differ from a configuration file.
    #[error("node {node} differs from {file} in {count} object(s)")]
    Differs { node: u8, file: String, count: usize },
    /// A device description file deviates from CiA 306 so that something it describes is
    /// not used (`config check`).
    #[error("{file}: {errors} error(s) and {warnings} warning(s) against CiA 306 (listed above); correct the file, or ask its vendor for one that follows CiA 306")]
    FileDeviates { file: String, errors: usize, warnings: usize },
    /// A configuration file names another device (vendor-ID, product code) than the node
    /// is; each difference said as `"vendor-ID 0x... on node N, 0x... in the file"`.
    #[error("{file} is for another device: {}. Nothing was written; --force applies it anyway", differences.join(", "))]
    OtherDevice { file: String, differences: Vec<String> },
    /// A bus is not as its network project says; `differences` in words ("2 node check(s)
    /// failed", ...).
    #[error("{bus} is not as {project} says: {}", differences.join(", "))]
    NetworkDiffers { bus: String, project: String, differences: Vec<String> },
    /// Nodes that answered before a network-wide bit-rate switch do not answer at the new
    /// rate.
    #[error("node(s) {} did not follow the switch to {rate}: they do not answer at the new rate", join_ids(nodes))]
    NotFollowed { rate: String, nodes: Vec<u8> },

    /// Nodes on a bus are not healthy; `nodes` in words ("node 1: error register 0x81").
    #[error("{bus}: {} of {total} node(s) not healthy: {}", nodes.len(), nodes.join("; "))]
    Unhealthy { bus: String, total: usize, nodes: Vec<String> },

    // ---- output (exit 7) ----
    /// A result could not be written (disk full, no permission, a closed terminal); the
    /// device side is unaffected.
    #[error("cannot write {path}: {why}")]
    Output { path: String, why: String },

    // ---- interrupted (exit 130) ----
    /// The user pressed Ctrl-C.
    #[error("interrupted")]
    Interrupted,
    /// The user asked to stop while an SDO transfer was under way: it was ended part-way,
    /// with an abort sent to the device (`aborted`, its code) where the link allows one.
    #[error("interrupted: the {} of {obj} {} node {node} stopped after {moved}{}",
        if *upload { "read" } else { "write" }, if *upload { "from" } else { "to" },
        match aborted { Some(code) => format!("; the transfer was aborted (SDO abort 0x{code:08X})"), None => String::new() })]
    SdoInterrupted { node: u8, obj: ObjAddr, upload: bool, moved: Moved, aborted: Option<u32> },

    /// An error with advice appended (e.g. which nodes the last scan saw); it ends the
    /// process as the error itself would.
    #[error("{error}{hint}")]
    Hinted { error: Box<Error>, hint: String },
}

/// What a failure means for the user, and so how the process ends. The README's
/// "Exit codes" table lists these (a test checks that it does).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ErrorClass {
    Usage,
    Timeout,
    Refused,
    Link,
    Verify,
    Output,
    Interrupted,
}

impl ErrorClass {
    pub const ALL: [ErrorClass; 7] = [
        ErrorClass::Usage,
        ErrorClass::Timeout,
        ErrorClass::Refused,
        ErrorClass::Link,
        ErrorClass::Verify,
        ErrorClass::Output,
        ErrorClass::Interrupted,
    ];

    /// The process exit code: the only place where exit codes are chosen.
    pub fn exit_code(self) -> i32 {
        match self {
            ErrorClass::Usage => 2,
            ErrorClass::Timeout => 3,
            ErrorClass::Refused => 4,
            ErrorClass::Link => 5,
            ErrorClass::Verify => 6,
            ErrorClass::Output => 7,
            ErrorClass::Interrupted => 130,
        }
    }
}

impl From<crate::od::eds::EdsError> for Error {
    fn from(e: crate::od::eds::EdsError) -> Error {
        Error::Eds(e.into())
    }
}

impl Error {
    pub fn class(&self) -> ErrorClass {
        use ErrorClass as C;
        match self {
            Error::Usage(_)
            | Error::Input(_)
            | Error::Eds(_)
            | Error::BadBusAddr { .. }
            | Error::NodeIdOutOfRange { .. }
            | Error::TooLargeForSdo { .. }
            | Error::SlcanBitRate { .. }
            | Error::NotOnThisBus { .. }
            | Error::NotADrive { .. }
            | Error::NodeIdInUse { .. }
            // The range the user gave is full: no device refused anything.
            | Error::NoFreeNodeId { .. } => C::Usage,
            Error::NoAnswer { .. }
            | Error::SdoOutcomeUnknown { .. }
            | Error::SdoUnfinished { .. }
            | Error::NoRemoteAnswer { .. }
            | Error::NoLssAnswer { .. }
            | Error::LssSetIdUnknown { .. }
            | Error::Epos2NoCanAnswer { .. }
            | Error::AdapterNoAnswer { .. } => C::Timeout,
            Error::Fastscan { error: FastscanError::Unconfirmed(_), .. } => C::Link,
            Error::Fastscan { .. } => C::Timeout,
            Error::SdoAbort { .. }
            | Error::LssRefused { .. }
            | Error::Epos2Refused { .. }
            | Error::StoreRefused { .. }
            | Error::NoErrorHistory { .. }
            | Error::NoStoredEds { .. } => C::Refused,
            Error::DriveStopped { why: DriveStop::NoAnswer, .. } => C::Timeout,
            Error::DriveStopped { .. } => C::Refused,
            Error::Link(_) | Error::StoredEds { .. } => C::Link,
            Error::ReadBack { .. }
            | Error::ReadBackMany { .. }
            | Error::Differs { .. }
            | Error::FileDeviates { .. }
            | Error::OtherDevice { .. }
            | Error::NetworkDiffers { .. }
            | Error::NotFollowed { .. }
            | Error::Unhealthy { .. } => C::Verify,
            Error::Output { .. } => C::Output,
            Error::Interrupted | Error::SdoInterrupted { .. } => C::Interrupted,
            Error::Hinted { error, .. } => error.class(),
        }
    }

    pub fn exit_code(&self) -> i32 {
        self.class().exit_code()
    }

    /// Nobody answered in time (exit 3): what a scan or a poll treats as "not there".
    pub fn is_timeout(&self) -> bool {
        self.class() == ErrorClass::Timeout
    }

    /// The user asked to stop (exit 130): a procedure ends with a report of what it did.
    pub fn is_interrupted(&self) -> bool {
        self.class() == ErrorClass::Interrupted
    }

    /// The error under any hint.
    pub fn root(&self) -> &Error {
        match self {
            Error::Hinted { error, .. } => error.root(),
            e => e,
        }
    }

    /// This error with advice appended to its message.
    pub fn with_hint(self, hint: impl Into<String>) -> Error {
        Error::Hinted { error: Box::new(self), hint: hint.into() }
    }
}

/// Why a drive command stopped before its goal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DriveStop {
    /// The drive is in fault (or went into fault on the way); fault-reset leaves it once
    /// the cause is gone.
    FaultPresent,
    /// A fault reset left the drive in fault: the cause is still there.
    FaultRemains,
    /// The drive did not switch on and its statusword shows no voltage (bit 4).
    VoltageMissing,
    /// The drive answered but did not take the transition within the wait.
    TransitionRefused,
    /// The drive stopped answering SDO.
    NoAnswer,
    /// The statusword shows no CiA 402 state.
    NoState,
}

impl fmt::Display for DriveStop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            DriveStop::FaultPresent => "fault present (canctl drive fault-reset NODE clears it once its cause is gone)",
            DriveStop::FaultRemains => {
                "the fault remains after the reset: its cause is still there (canctl drive status NODE shows the errors)"
            }
            DriveStop::VoltageMissing => "voltage missing (statusword bit 4 clear: check the power supply)",
            DriveStop::TransitionRefused => "transition refused (the statusword did not follow the controlword)",
            DriveStop::NoAnswer => "no answer",
            DriveStop::NoState => "the statusword shows no CiA 402 state",
        })
    }
}

/// The device profile a device type (0x1000) names, in words.
fn profile_text(device_type: u32) -> String {
    let profile = device_type & 0xFFFF;
    let name = match profile {
        0 => return "no standard device profile".into(),
        401 => "generic I/O modules",
        402 => "drives and motion control",
        404 => "measuring devices and closed-loop controllers",
        406 => "encoders",
        _ => return format!("profile {profile}"),
    };
    format!("profile {profile} (CiA {profile}, {name})")
}

impl From<LinkError> for Error {
    fn from(e: LinkError) -> Error {
        Error::Link(e)
    }
}

/// Text the user gave, echoed in a message: a value of 100 KB (a variable expanded by
/// mistake) shown whole would bury the message, so a long one is cut, its length said.
pub fn clipped(text: &str) -> std::borrow::Cow<'_, str> {
    const SHOWN: usize = 60;
    let count = text.chars().count();
    if count <= SHOWN + 20 {
        return text.into();
    }
    format!("{}… ({count} characters)", text.chars().take(SHOWN).collect::<String>()).into()
}

/// `; did you mean --bus sim?` for an interface name one or two letters from `sim` or from
/// an interface that exists (`sims`, `cna0`), else nothing.
fn did_you_mean(iface: &str, available: &[String]) -> String {
    let near = std::iter::once("sim")
        .chain(available.iter().map(String::as_str))
        .map(|c| (crate::od::names::distance(iface, c), c))
        .filter(|(d, c)| *d <= 2 && *d < c.len())
        .min();
    near.map_or_else(String::new, |(_, c)| format!("; did you mean --bus {c}?"))
}

/// A link failure: the port, interface or pseudo-terminal, and what went wrong with it.
#[derive(Debug, thiserror::Error)]
pub enum LinkError {
    /// A port or interface that cannot be opened.
    #[error("cannot open {}: {error}", clipped(port))]
    Open { port: String, error: std::io::Error },
    /// A path given as a serial port that is none (`/dev/null`, a file): the OS's word for
    /// it, "Not a typewriter", says nothing to most.
    #[error(
        "{} is not a serial port; serial ports here: {}",
        clipped(port),
        if available.is_empty() { "none found".to_string() } else { available.join(", ") }
    )]
    NotSerialPort { port: String, available: Vec<String> },
    /// An operation on an open port or interface failed (`{port}: {op}: {source}`; no `op`:
    /// `{port}: {source}`).
    #[error("{port}: {}{error}", if op.is_empty() { String::new() } else { format!("{op}: ") })]
    Io { port: String, op: &'static str, error: std::io::Error },
    /// No network interface of this name; `available` lists the CAN interfaces there are.
    #[error(
        "there is no network interface '{iface}'{} (CAN interfaces here: {}).\n  \
         A CAN adapter: plug it in, then sudo ip link set {iface} up type can bitrate 500000\n  \
         A virtual bus: sudo ip link add dev {iface} type vcan && sudo ip link set up {iface}\n  \
         No hardware: try the demo network, --bus sim",
        did_you_mean(iface, available),
        if available.is_empty() { "none".to_string() } else { available.join(", ") }
    )]
    NoInterface { iface: String, available: Vec<String> },
    /// A network interface that is not a CAN interface.
    #[error("'{iface}' is not a CAN interface")]
    NotCan { iface: String },
    /// A CAN interface that is down.
    #[error("{iface} is down: bring it up first (e.g. sudo ip link set {iface} up type can bitrate 500000)")]
    Down { iface: String },
    /// The CAN controller went bus-off.
    #[error("{iface}: the controller went bus-off ({detail})")]
    BusOff { iface: String, detail: String },
    /// Frames could not be queued for this long.
    #[error(
        "{iface}: the transmit queue stayed full for {} s (no other node acknowledging? bus-off?)",
        waited.as_secs()
    )]
    TxQueueFull { iface: String, waited: Duration },
    /// A serial CAN adapter refused a command.
    #[error(
        "{port}: the adapter refused to {what}; is it an slcan (Lawicel) adapter, and not in use by another program?"
    )]
    AdapterRefused { port: String, what: &'static str },
    /// A serial CAN adapter reports bus errors (its status flags, by name).
    #[error("{port}: the adapter reports {}: check the wiring, the termination and the bit rate", flags.join(", "))]
    AdapterBusError { port: String, flags: Vec<&'static str> },
    /// A serial CAN adapter refused to send a frame (with its status flags, when it gave them),
    /// or, with no `cob`, refused a frame while receiving.
    #[error("{}", match cob {
        Some(cob) if flags.is_empty() => format!("{port}: the adapter refused to send {cob:03X}"),
        Some(cob) => format!("{port}: the adapter refused to send {cob:03X} ({})", flags.join(", ")),
        None => format!("{port}: the adapter refused a frame"),
    })]
    AdapterRefusedFrame { port: String, cob: Option<u16>, flags: Vec<&'static str> },
    /// An SDO transfer broke off on a protocol error; `aborted` is the abort code sent.
    #[error("node {node}: SDO transfer of {obj} failed: {reason}{}",
        aborted.map(|c| format!(" (aborted with 0x{c:08X})")).unwrap_or_default())]
    SdoProtocol { node: u8, obj: ObjAddr, reason: String, aborted: Option<u32> },
    /// An EPOS2 serial command failed on the line (after a resync and a retry, when the
    /// first failure allowed one).
    #[error("{}", epos2_serial_text(bus, command, failure, retry.as_ref()))]
    Epos2Serial {
        bus: String,
        command: &'static str,
        failure: crate::epos2::transport::Failure,
        retry: Option<crate::epos2::transport::Failure>,
    },
    /// An EPOS2 answer that does not make sense.
    #[error("{}", epos2_answer_text(bus, problem))]
    Epos2Answer { bus: String, problem: Epos2Problem },
    /// The simulator's state file could not be used.
    #[error("sim state file {}: {what}: {detail}", path.display())]
    StateFile { path: PathBuf, what: &'static str, detail: String },
    /// Another process holds the simulator's network (its state file's lock); `holder`
    /// names it (pid and command line) as far as it said.
    #[error("the sim network is in use by {holder} (waited {}): it serves one command at a time; stop that one, \
             or serve the network where several commands share it as on a real bus (`canctl sim --socketcan vcan0`, \
             then --bus vcan0); --bus sim:OTHER.state would be another network, not this one",
        if *waited < Duration::from_secs(1) { format!("{} ms", waited.as_millis()) } else { format!("{} s", waited.as_secs_f64()) })]
    SimInUse { holder: String, waited: Duration },
    /// A pseudo-terminal (the simulator's serial devices) failed.
    #[error("{op}: {detail}")]
    Pty { op: PtyOp, detail: String },
}

/// What a node was asked and did not answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Service {
    /// An SDO transfer of this object.
    Sdo(ObjAddr),
    /// An SDO transfer of this object, started `requests` times (the retries of
    /// `canopen::sdo::retry`), each waited for the time given.
    SdoRetried { obj: ObjAddr, requests: u8 },
    /// Its NMT state: node guarding, after listening for a heartbeat for `heartbeat` (none
    /// where the bus shows no traffic).
    NmtState { heartbeat: Option<Duration> },
    /// Remote requests after an NMT reset: the reset is not confirmed.
    AfterReset,
    /// The boot-up message after an NMT reset.
    BootUp,
    /// Anything, after the device with this LSS identity was given the node-id over LSS.
    AfterLssAssign { identity: Identity },
    /// The probe of a node a network project lists; `lss` is the identity its DCF names, by
    /// which `--assign` could find it.
    ProjectNode { lss: Option<Identity> },
}

fn no_answer_text(node: u8, what: &Service, waited: Duration) -> String {
    let ms = waited.as_millis();
    match what {
        Service::Sdo(obj) => format!("node {node}: did not answer the SDO transfer of {obj} (waited {ms} ms)"),
        Service::SdoRetried { obj, requests } => format!(
            "node {node}: did not answer the SDO transfer of {obj}: no answer to {requests} requests, {} in all \
             ({ms} ms each)",
            match waited * u32::from(*requests) {
                all if all < Duration::from_secs(1) => format!("{} ms", all.as_millis()),
                all => format!("{:.1} s", all.as_secs_f64()),
            }
        ),
        Service::NmtState { heartbeat } => format!(
            "node {node}: {}no answer to node guarding within {ms} ms",
            heartbeat.map(|l| format!("no heartbeat within {} ms and ", l.as_millis())).unwrap_or_default()
        ),
        Service::AfterReset => format!(
            "node {node}: NMT reset sent, but no answer to remote requests within {ms} ms after it; \
             not confirmed. Check the node with `canctl scan`, or wait longer (--wait)"
        ),
        Service::BootUp if node == 0 => format!("all nodes: no boot-up within {ms} ms"),
        Service::BootUp => format!("node {node}: no boot-up within {ms} ms"),
        Service::AfterLssAssign { identity } => {
            format!("{identity} took node-id {node} over LSS but did not answer with it within {ms} ms")
        }
        Service::ProjectNode { lss: Some(id) } => {
            format!("node {node} did not answer; --assign gives it its node-id over LSS ({id})")
        }
        Service::ProjectNode { lss: None } => {
            format!("node {node} did not answer (its DCF names no LSS serial number, so --assign cannot find it)")
        }
    }
}

/// Why a node cannot store or restore parameters on command (CiA 301 0x1010/0x1011).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum StoreRefusal {
    /// It has no such object (0x1010 or 0x1011).
    NoObject { index: u16 },
    /// Its highest sub-index (`highest`) does not reach this class of parameters; `offered`
    /// names the classes it has.
    NotOffered { class: &'static str, index: u16, highest: u8, offered: Vec<&'static str> },
    /// The sub-index says it does not do this on command (`caps`, its value); for a store,
    /// `saves_itself` when it says it saves on its own.
    NotOnCommand { class: &'static str, obj: ObjAddr, caps: u32, saves_itself: bool },
}

fn store_refused_text(node: u8, verb: &str, why: &StoreRefusal) -> String {
    match why {
        StoreRefusal::NoObject { index } => {
            format!("node {node} has no object 0x{index:04X}: it cannot {verb} parameters")
        }
        StoreRefusal::NotOffered { class, index, highest, offered } => format!(
            "node {node} cannot {verb} {class} (0x{index:04X}:0 = {highest}; it offers: {})",
            if offered.is_empty() { "nothing".to_string() } else { offered.join(", ") }
        ),
        StoreRefusal::NotOnCommand { class, obj, caps, saves_itself } => format!(
            "node {node} does not {verb} {class} on command ({obj} = 0x{caps:08X}){}",
            if *saves_itself { ": it saves them by itself" } else { "" }
        ),
    }
}

fn join(objects: &[ObjAddr]) -> String {
    objects.iter().map(|o| o.to_string()).collect::<Vec<_>>().join(", ")
}

fn join_ids(nodes: &[u8]) -> String {
    nodes.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(", ")
}

/// Which node-ids a bus can address.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeIdRange {
    /// 1 to 127 (a CAN bus).
    CanOpen,
    /// 0 (the EPOS2 itself) or 1 to 127 (the nodes behind it).
    Epos2,
}

fn node_id_text(node: u8, range: NodeIdRange) -> String {
    match (range, node) {
        (NodeIdRange::CanOpen, 0) => {
            "node-id 0 is only for an EPOS2 on an epos2-rs232/epos2-usb bus; here use 1 to 127".into()
        }
        (NodeIdRange::CanOpen, _) => format!("node-id {node} is out of range: use 1 to 127"),
        (NodeIdRange::Epos2, _) => format!("node-id {node} is out of range: use 0 (the EPOS2 itself) or 1 to 127"),
    }
}

/// How much of an SDO transfer had moved: bytes, of the total when the size is known.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Moved {
    pub bytes: usize,
    pub total: Option<usize>,
}

impl fmt::Display for Moved {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.total {
            Some(total) => write!(f, "{} of {total} bytes", self.bytes),
            None => write!(f, "{} bytes", self.bytes),
        }
    }
}

/// Why an SDO transfer the node had answered did not finish.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Unfinished {
    /// Its total deadline (`budget`, from the size and `timeout`) passed.
    Deadline { budget: Duration, timeout: Duration },
    /// Nothing moved it on for `waited`, though the device sent `ignored` frames (`last`
    /// the last of them, in hex).
    NoProgress { waited: Duration, ignored: usize, last: String },
    /// The node fell silent for `waited`.
    Silent { waited: Duration },
}

struct SdoUnfinishedText<'a> {
    node: u8,
    obj: ObjAddr,
    moved: Moved,
    why: &'a Unfinished,
}

impl fmt::Display for SdoUnfinishedText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let SdoUnfinishedText { node, obj, moved, why } = self;
        match why {
            Unfinished::Deadline { budget, timeout } => write!(
                f,
                "node {node}: the SDO transfer of {obj} did not finish within its deadline of {:.1} s \
                 ({moved} moved; the deadline follows from the size and --timeout {} ms)",
                budget.as_secs_f64(),
                timeout.as_millis()
            ),
            Unfinished::NoProgress { waited, ignored, last } => write!(
                f,
                "node {node}: the SDO transfer of {obj} made no progress for {} ms ({moved} moved): \
                 the device sent {ignored} frame(s) that did not advance it (the last: {last})",
                waited.as_millis()
            ),
            Unfinished::Silent { waited } => write!(
                f,
                "node {node}: stopped answering during the SDO transfer of {obj} (waited {} ms, {moved} moved)",
                waited.as_millis()
            ),
        }
    }
}

/// `node N: COMMAND[ of OBJECT]`: where an EPOS2 command failed.
struct Epos2Place<'a> {
    node: u8,
    command: &'a str,
    obj: Option<ObjAddr>,
}

impl fmt::Display for Epos2Place<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.obj {
            Some(obj) => write!(f, "node {}: {} of {obj}", self.node, self.command),
            None => write!(f, "node {}: {}", self.node, self.command),
        }
    }
}

fn fastscan_text(error: &FastscanError, step: Duration) -> String {
    let step = step.as_millis();
    match error {
        FastscanError::NoDevice => "no device without a node-id answered the fastscan".into(),
        FastscanError::Unconfirmed(part) => format!(
            "fastscan: identity part {part} was found but not confirmed, even with a {step} ms step (a device \
             changed state, or frames were lost); try again, or a longer --step"
        ),
        FastscanError::NoMatch { part, value } => format!(
            "no device without a node-id has {} 0x{value:08X} (waited up to {step} ms a step)",
            ["vendor-id", "product code", "revision", "serial"].get(*part as usize).unwrap_or(&"identity part")
        ),
        FastscanError::Lost => {
            format!("fastscan: a device without a node-id answered, then stopped answering, even with a {step} ms step")
        }
    }
}

fn epos2_serial_text(
    bus: &str,
    command: &str,
    failure: &crate::epos2::transport::Failure,
    retry: Option<&crate::epos2::transport::Failure>,
) -> String {
    match retry {
        Some(second) => {
            format!("{bus}: {command} failed: {failure}; after a resync and retry: {second}; {}", second.advice())
        }
        None => format!("{bus}: {command} failed: {failure}; {}", failure.advice()),
    }
}

/// What was wrong with an EPOS2's answer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Epos2Problem {
    /// The answer to this command is shorter than its error code.
    TooShort { command: &'static str },
    /// A SegmentRead answer without its control byte.
    EmptySegment,
    /// A segmented read whose toggle bit did not alternate.
    ToggleNotAlternated { node: u8, obj: ObjAddr },
    /// A segment that claims more bytes than it carries.
    ShortSegment { node: u8, claimed: usize },
    /// Segments in a row that carried no data and said more follow.
    EmptySegments { node: u8, obj: ObjAddr, count: usize },
    /// A read that went on past the limit for reads through an EPOS2.
    TooLong { node: u8, obj: ObjAddr, bytes: usize, limit_kib: usize },
    /// A segmented write the EPOS2 confirmed one segment too many of.
    ExtraSegment { node: u8, obj: ObjAddr },
}

fn epos2_answer_text(bus: &str, problem: &Epos2Problem) -> String {
    match problem {
        Epos2Problem::TooShort { command } => format!("{bus}: the answer to {command} is too short"),
        Epos2Problem::EmptySegment => format!("{bus}: empty SegmentRead answer"),
        Epos2Problem::ToggleNotAlternated { node, obj } => {
            format!("node {node}: segmented read of {obj}: toggle bit not alternated")
        }
        Epos2Problem::ShortSegment { node, claimed } => {
            format!("node {node}: segment claims {claimed} bytes but carries fewer")
        }
        Epos2Problem::EmptySegments { node, obj, count } => format!(
            "node {node}: segmented read of {obj}: {count} segments in a row without data \
             that say more follow; stopped. The device's SDO server is stuck: reset the node \
             (`canctl nmt reset {node}`) and read again"
        ),
        Epos2Problem::TooLong { node, obj, bytes, limit_kib } => format!(
            "node {node}: segmented read of {obj}: {bytes} bytes and the device still says more follow; \
             stopped at the limit of {limit_kib} KiB for reads through an EPOS2. A value this large is \
             read over SocketCAN (block transfer); otherwise the device is faulty: reset it"
        ),
        Epos2Problem::ExtraSegment { node, obj } => {
            format!("node {node}: segmented write of {obj}: the EPOS2 confirmed another segment")
        }
    }
}

/// What failed on a pseudo-terminal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PtyOp {
    Create,
    Termios,
    Name,
    Poll,
    Read,
    Write,
    /// Telling the user its path.
    PrintPath,
}

impl fmt::Display for PtyOp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            PtyOp::Create => "cannot create a pseudo-terminal",
            PtyOp::Termios => "pty termios",
            PtyOp::Name => "pty name",
            PtyOp::Poll => "pty poll",
            PtyOp::Read => "pty read",
            PtyOp::Write => "pty write",
            PtyOp::PrintPath => "cannot print the pty path",
        })
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;

    const OBJ: ObjAddr = ObjAddr { index: 0x1018, sub: 1 };

    fn ms(n: u64) -> Duration {
        Duration::from_millis(n)
    }

    /// Every class is in `ALL` (a class added without it fails to compile here).
    #[test]
    fn all_lists_every_class() {
        for class in ErrorClass::ALL {
            let position = match class {
                ErrorClass::Usage => 0,
                ErrorClass::Timeout => 1,
                ErrorClass::Refused => 2,
                ErrorClass::Link => 3,
                ErrorClass::Verify => 4,
                ErrorClass::Output => 5,
                ErrorClass::Interrupted => 6,
            };
            assert_eq!(ErrorClass::ALL[position], class);
        }
    }

    /// The texts are the ones canctl printed when these errors were strings.
    #[test]
    fn messages_say_what_they_always_said() {
        let cases: Vec<(Error, &str)> = vec![
            (
                Error::NoAnswer { node: 7, what: Service::Sdo(OBJ), waited: ms(500) },
                "node 7: did not answer the SDO transfer of 0x1018:1 (waited 500 ms)",
            ),
            (
                Error::SdoUnfinished {
                    node: 7,
                    obj: OBJ,
                    moved: Moved { bytes: 10, total: Some(100) },
                    why: Unfinished::Deadline { budget: ms(2500), timeout: ms(500) },
                },
                "node 7: the SDO transfer of 0x1018:1 did not finish within its deadline of 2.5 s (10 of 100 bytes \
                 moved; the deadline follows from the size and --timeout 500 ms)",
            ),
            (
                Error::SdoUnfinished {
                    node: 7,
                    obj: OBJ,
                    moved: Moved { bytes: 10, total: None },
                    why: Unfinished::NoProgress { waited: ms(500), ignored: 3, last: "60 00 00".into() },
                },
                "node 7: the SDO transfer of 0x1018:1 made no progress for 500 ms (10 bytes moved): the device \
                 sent 3 frame(s) that did not advance it (the last: 60 00 00)",
            ),
            (
                Error::SdoUnfinished {
                    node: 7,
                    obj: OBJ,
                    moved: Moved { bytes: 0, total: None },
                    why: Unfinished::Silent { waited: ms(500) },
                },
                "node 7: stopped answering during the SDO transfer of 0x1018:1 (waited 500 ms, 0 bytes moved)",
            ),
            (
                Error::NoAnswer { node: 4, what: Service::NmtState { heartbeat: Some(ms(1500)) }, waited: ms(500) },
                "node 4: no heartbeat within 1500 ms and no answer to node guarding within 500 ms",
            ),
            (
                Error::NoAnswer { node: 4, what: Service::NmtState { heartbeat: None }, waited: ms(500) },
                "node 4: no answer to node guarding within 500 ms",
            ),
            (
                Error::NoAnswer { node: 4, what: Service::AfterReset, waited: ms(3000) },
                "node 4: NMT reset sent, but no answer to remote requests within 3000 ms after it; not confirmed. \
                 Check the node with `canctl scan`, or wait longer (--wait)",
            ),
            (Error::NoAnswer { node: 4, what: Service::BootUp, waited: ms(3000) }, "node 4: no boot-up within 3000 ms"),
            (
                Error::NoAnswer { node: 0, what: Service::BootUp, waited: ms(3000) },
                "all nodes: no boot-up within 3000 ms",
            ),
            (
                Error::StoreRefused { node: 5, verb: "restore", why: StoreRefusal::NoObject { index: 0x1011 } },
                "node 5 has no object 0x1011: it cannot restore parameters",
            ),
            (
                Error::StoreRefused {
                    node: 5,
                    verb: "store",
                    why: StoreRefusal::NotOffered {
                        class: "manufacturer parameters",
                        index: 0x1010,
                        highest: 1,
                        offered: vec!["all parameters"],
                    },
                },
                "node 5 cannot store manufacturer parameters (0x1010:0 = 1; it offers: all parameters)",
            ),
            (
                Error::StoreRefused {
                    node: 5,
                    verb: "store",
                    why: StoreRefusal::NotOnCommand {
                        class: "all parameters",
                        obj: ObjAddr { index: 0x1010, sub: 1 },
                        caps: 2,
                        saves_itself: true,
                    },
                },
                "node 5 does not store all parameters on command (0x1010:1 = 0x00000002): it saves them by itself",
            ),
            (
                Error::ReadBackMany { node: 5, objects: vec![OBJ, ObjAddr { index: 0x2000, sub: 0 }] },
                "node 5: 0x1018:1, 0x2000:0 read back other values than written",
            ),
            (
                Error::OtherDevice {
                    file: "a.dcf".into(),
                    differences: vec!["vendor-ID 0x00000001 on node 5, 0x00000002 in the file".into()],
                },
                "a.dcf is for another device: vendor-ID 0x00000001 on node 5, 0x00000002 in the file. Nothing was \
                 written; --force applies it anyway",
            ),
            (
                Error::NoRemoteAnswer { cob: 0x705, waited: ms(300) },
                "no answer to the remote request for 0x705 within 300 ms",
            ),
            (
                Error::NoLssAnswer { request: "set-id".into(), identity: None, waited: ms(100) },
                "no LSS device answered set-id within 100 ms",
            ),
            (
                Error::NoLssAnswer {
                    request: "the selective switch".into(),
                    identity: Some(Identity { vendor: 1, product: 2, revision: 3, serial: 4 }),
                    waited: ms(100),
                },
                "no LSS device with identity 0x00000001:0x00000002:0x00000003:0x00000004 answered the selective \
                 switch within 100 ms",
            ),
            (
                Error::LssSetIdUnknown {
                    identity: Identity { vendor: 0x40, product: 2, revision: 3, serial: 4 },
                    node: 20,
                    tries: 3,
                    waited: ms(200),
                },
                "no answer from 0x00000040:0x00000002:0x00000003:0x00000004 to set-id 20 within 200 ms, asked 3 \
                 times: unknown whether it holds node 20 now (canctl lss inquire --identity \
                 0x00000040:0x00000002:0x00000003:0x00000004 shows its node-id)",
            ),
            (
                Error::LssRefused { service: "store".into(), cs: 0x17, error: 1, specific: 0 },
                "LSS store: error 1: store configuration not supported",
            ),
            (
                Error::LssRefused { service: "set-id".into(), cs: 0x11, error: 255, specific: 9 },
                "LSS set-id: error 255: implementation-specific error (see the specific code) (specific code 9)",
            ),
            (
                Error::Epos2NoCanAnswer { node: 3, command: "ReadObject", obj: Some(OBJ) },
                "node 3: ReadObject of 0x1018:1: no answer on the CAN bus (the EPOS2 reports SDO timeout 0x05040000)",
            ),
            (
                Error::Epos2Refused { node: 0, command: "SendNMTService", obj: None, code: 0x0602_0000 },
                "node 0: SendNMTService: error 0x06020000: Object does not exist in the object dictionary",
            ),
            (
                Error::Epos2Refused {
                    node: 2,
                    command: "WriteObject",
                    obj: Some(OBJ),
                    code: crate::epos2::command::WRONG_NMT_STATE,
                },
                "node 2: WriteObject of 0x1018:1: EPOS2 error 0x0F00FFC0: Device is in wrong NMT state",
            ),
            (
                Error::NodeIdOutOfRange { node: 0, range: NodeIdRange::CanOpen },
                "node-id 0 is only for an EPOS2 on an epos2-rs232/epos2-usb bus; here use 1 to 127",
            ),
            (
                Error::NodeIdOutOfRange { node: 200, range: NodeIdRange::CanOpen },
                "node-id 200 is out of range: use 1 to 127",
            ),
            (
                Error::NodeIdOutOfRange { node: 200, range: NodeIdRange::Epos2 },
                "node-id 200 is out of range: use 0 (the EPOS2 itself) or 1 to 127",
            ),
            (
                Error::SlcanBitRate { port: "slcan:x".into(), kbit: 83, supported: vec!["10k".into(), "20k".into()] },
                "slcan:x: slcan has no 83 kbit/s; use one of 10k 20k",
            ),
            (
                Error::AdapterNoAnswer { port: "slcan:x".into(), command: "S6".into(), waited: ms(200) },
                "slcan:x: the adapter did not answer \"S6\" within 200 ms",
            ),
            (
                Error::Fastscan { error: FastscanError::NoDevice, step: ms(10) },
                "no device without a node-id answered the fastscan",
            ),
            (
                Error::Fastscan { error: FastscanError::NoMatch { part: 1, value: 0x1234 }, step: ms(10) },
                "no device without a node-id has product code 0x00001234 (waited up to 10 ms a step)",
            ),
            (
                Error::NoFreeNodeId {
                    start: 120,
                    identity: Identity { vendor: 1, product: 2, revision: 3, serial: 4 },
                },
                "no free node-id left from 120 to 127 for 0x00000001:0x00000002:0x00000003:0x00000004: give a lower --start",
            ),
            (
                Error::ReadBack { node: 5, obj: OBJ, wrote: "7".into(), read: "8".into() },
                "node 5: 0x1018:1 reads back 8 after writing 7",
            ),
            (
                LinkError::SdoProtocol {
                    node: 5,
                    obj: OBJ,
                    reason: "toggle bit not alternated".into(),
                    aborted: Some(0x0503_0000),
                }
                .into(),
                "node 5: SDO transfer of 0x1018:1 failed: toggle bit not alternated (aborted with 0x05030000)",
            ),
            (LinkError::Io { port: "can0".into(), op: "", error: std::io::Error::other("gone") }.into(), "can0: gone"),
            (
                LinkError::Io { port: "can0".into(), op: "send failed", error: std::io::Error::other("gone") }.into(),
                "can0: send failed: gone",
            ),
            (
                LinkError::AdapterRefusedFrame { port: "slcan:x".into(), cob: Some(0), flags: vec!["bus error"] }
                    .into(),
                "slcan:x: the adapter refused to send 000 (bus error)",
            ),
            (
                LinkError::AdapterRefusedFrame { port: "slcan:x".into(), cob: None, flags: vec![] }.into(),
                "slcan:x: the adapter refused a frame",
            ),
            (
                LinkError::Epos2Answer {
                    bus: "epos2-usb:/dev/x".into(),
                    problem: Epos2Problem::TooShort { command: "ReadObject" },
                }
                .into(),
                "epos2-usb:/dev/x: the answer to ReadObject is too short",
            ),
            (LinkError::Pty { op: PtyOp::Poll, detail: "EINTR".into() }.into(), "pty poll: EINTR"),
            (
                LinkError::StateFile { path: "/tmp/s.json".into(), what: "cannot read", detail: "denied".into() }
                    .into(),
                "sim state file /tmp/s.json: cannot read: denied",
            ),
        ];
        for (error, text) in cases {
            assert_eq!(error.to_string(), text);
        }
    }

    /// The link failures, likewise.
    #[test]
    fn link_messages_say_what_they_always_said() {
        use crate::epos2::transport::Failure;
        let cases: Vec<(LinkError, &str)> = vec![
            (
                LinkError::NoInterface { iface: "can9".into(), available: vec![] },
                "there is no network interface 'can9' (CAN interfaces here: none).\n  \
                 A CAN adapter: plug it in, then sudo ip link set can9 up type can bitrate 500000\n  \
                 A virtual bus: sudo ip link add dev can9 type vcan && sudo ip link set up can9\n  \
                 No hardware: try the demo network, --bus sim",
            ),
            (LinkError::NotCan { iface: "eth0".into() }, "'eth0' is not a CAN interface"),
            (
                LinkError::Down { iface: "can0".into() },
                "can0 is down: bring it up first (e.g. sudo ip link set can0 up type can bitrate 500000)",
            ),
            (
                LinkError::BusOff { iface: "can0".into(), detail: "bus off".into() },
                "can0: the controller went bus-off (bus off)",
            ),
            (
                LinkError::TxQueueFull { iface: "can0".into(), waited: Duration::from_secs(2) },
                "can0: the transmit queue stayed full for 2 s (no other node acknowledging? bus-off?)",
            ),
            (
                LinkError::AdapterRefused { port: "slcan:x".into(), what: "open the channel" },
                "slcan:x: the adapter refused to open the channel; is it an slcan (Lawicel) adapter, and not in use \
                 by another program?",
            ),
            (
                LinkError::AdapterBusError { port: "slcan:x".into(), flags: vec!["bus error", "error passive"] },
                "slcan:x: the adapter reports bus error, error passive: check the wiring, the termination and the \
                 bit rate",
            ),
            (
                LinkError::AdapterRefusedFrame { port: "slcan:x".into(), cob: Some(0x601), flags: vec![] },
                "slcan:x: the adapter refused to send 601",
            ),
            (
                LinkError::Epos2Serial {
                    bus: "epos2-rs232:/dev/x".into(),
                    command: "ReadObject",
                    failure: Failure::Timeout("to the OpCode"),
                    retry: None,
                },
                "epos2-rs232:/dev/x: ReadObject failed: no answer to the OpCode; check the cable, the bit rate \
                 (?baud=) and that no other program uses the port; a slow device may need a \
                 longer --timeout",
            ),
            (
                LinkError::Epos2Serial {
                    bus: "epos2-rs232:/dev/x".into(),
                    command: "ReadObject",
                    failure: Failure::Misfit(3),
                    retry: Some(Failure::Io(std::io::Error::other("gone"))),
                },
                "epos2-rs232:/dev/x: ReadObject failed: 3 answers in a row that do not answer this command \
                 (discarded); after a resync and retry: the port failed: gone; check that the device is connected \
                 and powered, then run the command again",
            ),
            (
                LinkError::Epos2Answer { bus: "b".into(), problem: Epos2Problem::EmptySegment },
                "b: empty SegmentRead answer",
            ),
            (
                LinkError::Epos2Answer {
                    bus: "b".into(),
                    problem: Epos2Problem::ToggleNotAlternated { node: 2, obj: OBJ },
                },
                "node 2: segmented read of 0x1018:1: toggle bit not alternated",
            ),
            (
                LinkError::Epos2Answer { bus: "b".into(), problem: Epos2Problem::ShortSegment { node: 2, claimed: 7 } },
                "node 2: segment claims 7 bytes but carries fewer",
            ),
            (
                LinkError::Epos2Answer {
                    bus: "b".into(),
                    problem: Epos2Problem::EmptySegments { node: 2, obj: OBJ, count: 8 },
                },
                "node 2: segmented read of 0x1018:1: 8 segments in a row without data that say more follow; \
                 stopped. The device's SDO server is stuck: reset the node (`canctl nmt reset 2`) and read again",
            ),
            (
                LinkError::Epos2Answer {
                    bus: "b".into(),
                    problem: Epos2Problem::TooLong { node: 2, obj: OBJ, bytes: 1048576, limit_kib: 1024 },
                },
                "node 2: segmented read of 0x1018:1: 1048576 bytes and the device still says more follow; stopped \
                 at the limit of 1024 KiB for reads through an EPOS2. A value this large is read over SocketCAN \
                 (block transfer); otherwise the device is faulty: reset it",
            ),
            (
                LinkError::Epos2Answer { bus: "b".into(), problem: Epos2Problem::ExtraSegment { node: 2, obj: OBJ } },
                "node 2: segmented write of 0x1018:1: the EPOS2 confirmed another segment",
            ),
            (LinkError::Pty { op: PtyOp::Create, detail: "ENOSPC".into() }, "cannot create a pseudo-terminal: ENOSPC"),
        ];
        for (error, text) in cases {
            assert_eq!(Error::from(error).to_string(), text);
        }
        let usage = [
            (
                Error::TooLargeForSdo { len: 5_000_000_000 },
                "5000000000 bytes cannot be written by SDO: CiA 301 sizes are 32-bit (at most 4294967295 bytes)",
            ),
            (
                Error::BadBusAddr { uri: "sim:".into(), reason: "sim: needs a state file path".into() },
                "bus 'sim:': sim: needs a state file path",
            ),
            (
                Error::NotOnThisBus {
                    bus: "epos2-usb:/dev/x".into(),
                    why: "remote frames go through RequestCANFrame; use a request",
                },
                "epos2-usb:/dev/x: remote frames go through RequestCANFrame; use a request",
            ),
        ];
        for (error, text) in usage {
            assert_eq!(error.exit_code(), 2);
            assert_eq!(error.to_string(), text);
        }
    }

    #[test]
    fn a_hint_is_appended_and_keeps_the_exit_code() {
        let e = Error::NoAnswer { node: 7, what: Service::Sdo(OBJ), waited: ms(500) }.with_hint("; try scan");
        assert_eq!(e.to_string(), "node 7: did not answer the SDO transfer of 0x1018:1 (waited 500 ms); try scan");
        assert_eq!(e.exit_code(), 3);
        assert!(matches!(e.root(), Error::NoAnswer { node: 7, .. }));
    }

    #[test]
    fn a_fastscan_that_could_not_confirm_is_a_link_failure_the_others_are_timeouts() {
        let step = ms(10);
        assert_eq!(Error::Fastscan { error: FastscanError::Unconfirmed(2), step }.exit_code(), 5);
        assert_eq!(Error::Fastscan { error: FastscanError::Lost, step }.exit_code(), 3);
        assert_eq!(Error::Fastscan { error: FastscanError::NoDevice, step }.exit_code(), 3);
    }

    /// A link failure prints once: its cause is in its text, not repeated as a source.
    #[test]
    fn a_link_error_has_no_source_to_print_twice() {
        use std::error::Error as _;
        let e: Error = LinkError::Open { port: "/dev/x".into(), error: std::io::Error::other("gone") }.into();
        assert!(e.source().is_none());
        assert_eq!(e.to_string(), "cannot open /dev/x: gone");
    }
}
