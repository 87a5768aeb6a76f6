//! The details errors carry: what was asked of a node, why a store or a transfer stopped,
//! why a drive stopped; with the words their messages are made of.

use crate::canopen::lss::{FastscanError, Identity};
use crate::canopen::ObjAddr;
use std::fmt;
use std::path::PathBuf;
use std::time::Duration;

/// Why a drive command stopped before its goal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, thiserror::Error)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum DriveStop {
    /// The drive is in fault (or went into fault on the way); fault-reset leaves it once
    /// the cause is gone.
    #[error("fault present")]
    FaultPresent,
    /// A fault reset left the drive in fault: the cause is still there.
    #[error("the fault remains after the reset: its cause is still there")]
    FaultRemains,
    /// The drive did not switch on and its statusword shows no voltage (bit 4).
    #[error("voltage missing (statusword bit 4 clear: check the power supply)")]
    VoltageMissing,
    /// The drive answered but did not take the transition within the wait.
    #[error("transition refused (the statusword did not follow the controlword)")]
    TransitionRefused,
    /// The drive stopped answering SDO.
    #[error("no answer")]
    NoAnswer,
    /// The statusword shows no CiA 402 state.
    #[error("the statusword shows no CiA 402 state")]
    NoState,
}

/// The device profile a device type (0x1000) names, in words.
pub(super) fn profile_text(device_type: u32) -> String {
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

/// What a node was asked and did not answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Service {
    /// An SDO transfer of this object.
    Sdo(ObjAddr),
    /// An SDO transfer of this object, started `requests` times (the retries of
    /// `canopen::sdo::retry`), each waited for the time given.
    SdoRetried {
        /// The object transferred.
        obj: ObjAddr,
        /// How many times the transfer was started.
        requests: u8,
    },
    /// Its NMT state: node guarding, after listening for a heartbeat for `heartbeat` (none
    /// where the bus shows no traffic).
    NmtState {
        /// How long a heartbeat was listened for; none where the bus showed no traffic.
        heartbeat: Option<Duration>,
    },
    /// Remote requests after an NMT reset: the reset is not confirmed.
    AfterReset,
    /// The boot-up message after an NMT reset.
    BootUp,
    /// Anything, after the device with this LSS identity was given the node-id over LSS.
    AfterLssAssign {
        /// The device's LSS identity.
        identity: Identity,
    },
    /// The probe of a node a network project lists; `lss` is the identity its DCF names, by
    /// which an LSS assignment could find it.
    ProjectNode {
        /// The LSS identity its DCF names; none when it names no serial number.
        lss: Option<Identity>,
    },
}

pub(super) fn no_answer_text(node: u8, what: &Service, waited: Duration) -> String {
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
             not confirmed"
        ),
        Service::BootUp if node == 0 => format!("all nodes: no boot-up within {ms} ms"),
        Service::BootUp => format!("node {node}: no boot-up within {ms} ms"),
        Service::AfterLssAssign { identity } => {
            format!("{identity} took node-id {node} over LSS but did not answer with it within {ms} ms")
        }
        // What to do about it (the LSS identity it names) is a `Hint`, worded by the front end.
        Service::ProjectNode { .. } => format!("node {node} did not answer"),
    }
}

/// Why a node cannot store or restore parameters on command (CiA 301 0x1010/0x1011).
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum StoreRefusal {
    /// It has no such object (0x1010 or 0x1011).
    NoObject {
        /// 0x1010 (store) or 0x1011 (restore).
        index: u16,
    },
    /// Its highest sub-index (`highest`) does not reach this class of parameters; `offered`
    /// names the classes it has.
    NotOffered {
        /// The class of parameters asked for (`all`, `comm`, `app`, `mfr`).
        class: &'static str,
        /// 0x1010 (store) or 0x1011 (restore).
        index: u16,
        /// The object's highest sub-index (its sub-index 0).
        highest: u8,
        /// The classes it has, by name.
        offered: Vec<&'static str>,
    },
    /// The sub-index says it does not do this on command (`caps`, its value); for a store,
    /// `saves_itself` when it says it saves on its own.
    NotOnCommand {
        /// The class of parameters asked for (`all`, `comm`, `app`, `mfr`).
        class: &'static str,
        /// The sub-index of that class.
        obj: ObjAddr,
        /// Its value: what the node says it does (CiA 301 bit 0: on command; bit 1: by itself).
        caps: u32,
        /// For a store: the node says it saves by itself.
        saves_itself: bool,
    },
}

pub(super) fn store_refused_text(node: u8, verb: ParameterCommand, why: &StoreRefusal) -> String {
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

pub(super) fn join(objects: &[ObjAddr]) -> String {
    objects.iter().map(|o| o.to_string()).collect::<Vec<_>>().join(", ")
}

/// Which node-ids a bus can address.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum NodeIdRange {
    /// 1 to 127 (a CAN bus).
    CanOpen,
    /// 0 (the EPOS2 itself) or 1 to 127 (the nodes behind it).
    Epos2,
}

pub(super) fn node_id_text(node: u8, range: NodeIdRange) -> String {
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
    /// Bytes moved.
    pub bytes: usize,
    /// The transfer's size, when known.
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
#[non_exhaustive]
pub enum Unfinished {
    /// Its total deadline (`budget`, from the size and `timeout`) passed.
    Deadline {
        /// The whole transfer's deadline.
        budget: Duration,
        /// The timeout for one answer it follows from.
        timeout: Duration,
    },
    /// Nothing moved it on for `waited`, though the device sent `ignored` frames (`last`
    /// the last of them, in hex).
    NoProgress {
        /// How long nothing moved it on.
        waited: Duration,
        /// How many frames the device sent meanwhile.
        ignored: usize,
        /// The last of them, in hex.
        last: String,
    },
    /// The node fell silent for `waited`.
    Silent {
        /// How long the node was silent.
        waited: Duration,
    },
}

pub(super) fn sdo_unfinished_text(node: u8, obj: ObjAddr, moved: Moved, why: &Unfinished) -> String {
    match why {
        // The timeout it follows from is the front end's remedy to word.
        Unfinished::Deadline { budget, .. } => format!(
            "node {node}: the SDO transfer of {obj} did not finish within its deadline of {:.1} s ({moved} moved)",
            budget.as_secs_f64(),
        ),
        Unfinished::NoProgress { waited, ignored, last } => format!(
            "node {node}: the SDO transfer of {obj} made no progress for {} ms ({moved} moved): \
             the device sent {ignored} frame(s) that did not advance it (the last: {last})",
            waited.as_millis()
        ),
        Unfinished::Silent { waited } => format!(
            "node {node}: stopped answering during the SDO transfer of {obj} (waited {} ms, {moved} moved)",
            waited.as_millis()
        ),
    }
}

/// `node N: COMMAND[ of OBJECT]`: where an EPOS2 command failed.
pub(super) fn epos2_place(node: u8, command: &str, obj: Option<ObjAddr>) -> String {
    match obj {
        Some(obj) => format!("node {node}: {command} of {obj}"),
        None => format!("node {node}: {command}"),
    }
}

pub(super) fn fastscan_text(error: &FastscanError, step: Duration) -> String {
    let step = step.as_millis();
    match error {
        FastscanError::NoDevice => "no device without a node-id answered the fastscan".into(),
        FastscanError::Unconfirmed(part) => format!(
            "fastscan: identity part {part} was found but not confirmed, even with a {step} ms step (a device \
             changed state, or frames were lost)"
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

/// A file of a project that, symbolic links followed, is outside the project's folder: a
/// project from someone else must not make canctl read or rewrite a file elsewhere.
#[derive(Debug, Clone, thiserror::Error)]
#[error(
    "{} is a link to {}, outside the project's folder {}: a project reads and writes only files in its own \
     folder",
    .link.display(), .points_to.display(), .folder.display()
)]
// Exhaustive on purpose: canctl words every case, and the compiler says when one is new.
pub struct OutsideProject {
    /// The file, as the project names it.
    pub link: std::path::PathBuf,
    /// Where it leads, links followed.
    pub points_to: std::path::PathBuf,
    /// The project's folder, links followed.
    pub folder: std::path::PathBuf,
}

/// Why a path given for the sim network's state is not used: it is not canctl's to write,
/// nor to write beside.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum StateRefused {
    /// The path is a folder.
    #[error("sim state file {}: is a folder; the sim network's state is a file (nothing was written)", .0.display())]
    Folder(PathBuf),
    /// The file there holds something else than a sim network's state.
    #[error("{} is not a sim network's state: it is left as it is, and nothing is written beside it", .0.display())]
    NotAState(PathBuf),
    /// The folder it would be in is missing: only the default state file's is made.
    #[error("there is no folder {} for the sim state file {}: a folder is made only for the default one", .folder.display(), .path.display())]
    NoFolder {
        /// The missing folder.
        folder: PathBuf,
        /// The state file.
        path: PathBuf,
    },
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

/// What the library knows to add to an error where it happened (an [`Error::Advised`](super::Error::Advised)),
/// said after the error's message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Advice {
    /// Objects whose names or addresses are near the one asked for, as the user would write
    /// them.
    Near(Vec<String>),
    /// A store or restore was sent once and its answer did not come: the node may have
    /// done it.
    SentOnce {
        /// The node asked.
        node: u8,
        /// Which was sent.
        command: ParameterCommand,
    },
    /// The TCP port asked for to serve on is taken.
    PortTaken,
}

impl fmt::Display for Advice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Advice::Near(near) => write!(f, "; did you mean {}?", near.join(", ")),
            Advice::SentOnce { node, command } => write!(
                f,
                "; the {command} was sent once and may have been done: unknown whether node {node} {}",
                match command {
                    ParameterCommand::Store => "stored its parameters",
                    ParameterCommand::Restore => "restored its defaults",
                }
            ),
            Advice::PortTaken => f.write_str("; serve on another port, or on port 0 for any free one"),
        }
    }
}

/// Storing a node's parameters (0x1010, 'save') or restoring its defaults (0x1011, 'load').
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParameterCommand {
    /// Store the parameters in non-volatile memory.
    Store,
    /// Restore the defaults (from the next reset on).
    Restore,
}

/// The command as a verb: `store` or `restore`.
impl fmt::Display for ParameterCommand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ParameterCommand::Store => "store",
            ParameterCommand::Restore => "restore",
        })
    }
}

/// What makes a network project, or a file it names, unusable.
#[derive(Debug, Clone, thiserror::Error)]
pub enum ProjectProblem {
    /// The project file (CiA 306-3 `nodelist.cpj`) itself.
    #[error("cannot use {0}")]
    Project(crate::od::cpj::CpjError),
    /// The commissioning (`[DeviceComissioning]`) of a DCF it names.
    #[error("cannot use {0}")]
    Commissioning(crate::od::cpj::CpjError),
    /// The commissioning (`DeviceCommissioning`) of an XDC it names.
    #[error("cannot use {0}")]
    XdcCommissioning(crate::od::xdd::XmlError),
    /// A DCF it names that cannot be read (`node` and `project`: whose, where listed).
    #[error("cannot use {dcf}{}: {error}", node.map(|n| format!(" (node {n} in {project})")).unwrap_or_default())]
    Dcf {
        /// The DCF, as the project names it.
        dcf: String,
        /// The node the project lists it for, when said.
        node: Option<u8>,
        /// The project file.
        project: String,
        /// Why it cannot be read.
        error: crate::input::InputError,
    },
    /// A DCF that gives another node-id than the one the project lists it for.
    #[error("{dcf} is for node-id {id} ({}), but {project} lists it for node {node}",
        if *xml { "DeviceCommissioning nodeID" } else { "[DeviceComissioning] NodeID" })]
    OtherNodeId {
        /// The DCF (or XDC).
        dcf: String,
        /// The node-id it gives.
        id: u8,
        /// The node the project lists it for.
        node: u8,
        /// The project file.
        project: String,
        /// Whether it is an XDC (its key named as CiA 311 names it).
        xml: bool,
    },
}

/// A value a file canctl makes cannot hold as it is.
#[derive(Debug, Clone, thiserror::Error)]
pub enum NotWritable {
    /// An EDS, DCF or XDC.
    #[error(transparent)]
    Description(#[from] crate::od::eds::WriteError),
    /// A project file, or the commissioning section of a DCF.
    #[error(transparent)]
    Project(#[from] crate::od::cpj::WriteError),
}
