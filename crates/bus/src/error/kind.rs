//! The library's error type, [`Error`]: its variants, what they say, and what they wrap.

use super::detail::*;
use super::link::LinkError;
use crate::canopen::lss::{FastscanError, Identity};
use crate::canopen::{abort, DataType, ObjAddr};
use std::time::Duration;

/// Everything that can go wrong in the library, each with its exit code ([`Error::class`]).
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    // ---- usage (exit 2) ----
    /// The user asked for something malformed or impossible, said in free form.
    #[error("{0}")]
    Usage(String),
    /// A DCF breaks CiA 306 so that its values are not all read: nothing is compared or
    /// written from it.
    #[error(
        "{first}; {file} has {errors} error(s) against CiA 306, so its values are not all read: nothing is \
         compared or written"
    )]
    DcfNotReadWhole {
        /// The first error in it.
        first: Box<crate::od::lint::Warning>,
        /// The file, as named.
        file: String,
        /// How many errors it has.
        errors: usize,
    },
    /// A file given as a DCF holds no values (no ParameterValue): it is an EDS.
    #[error("{file} has no ParameterValue: it is an EDS, not a DCF")]
    NotADcf {
        /// The file, as named.
        file: String,
    },
    /// A project's file leads outside the project's folder through a symbolic link.
    #[error(transparent)]
    OutsideProject(#[from] OutsideProject),
    /// A path given for the sim network's state is not canctl's to write.
    #[error(transparent)]
    SimState(#[from] StateRefused),
    /// A file or stream given as input could not be used: the user's to fix (exit 2).
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    /// What a node holds does not decode as the data type asked for (or the dictionary's).
    #[error("node {node}: {obj} holds {} byte(s) ({}), which is not {}", bytes.len(), crate::canopen::types::hex(bytes),
        match dtype { DataType::Unicode => "UTF-16 text (us)".to_string(),
            t => format!("a {t} ({} bytes)", t.size().unwrap_or(0)) })]
    NotOfType {
        /// The node-id of the node it is about.
        node: u8,
        /// The object read.
        obj: ObjAddr,
        /// What the node sent, as it sent it.
        bytes: Vec<u8>,
        /// The data type the bytes were to decode as.
        dtype: DataType,
    },
    /// A TPDO asked for that the node does not have (no communication object `comm`).
    #[error("node {node} has no TPDO{pdo} (no object 0x{comm:04X})")]
    NoSuchTpdo {
        /// The node-id of the node it is about.
        node: u8,
        /// The TPDO's number (1 for TPDO1).
        pdo: u16,
        /// Its communication parameter object (0x1800 + number - 1).
        comm: u16,
    },
    /// None of the TPDOs looked at is valid: there is nothing to stream.
    #[error("node {node} has no valid TPDO to stream")]
    NoValidTpdo {
        /// The node-id of the node it is about.
        node: u8,
    },
    /// A global LSS inquiry, meant for one device, was answered by `count`.
    #[error("{count} devices answered the global inquiry")]
    InquiryAnsweredByMany {
        /// How many devices answered.
        count: usize,
    },
    /// An EDS, DCF, XDD or XDC that cannot be read (the reason names the file) or does not
    /// parse (`FILE:LINE: why`): said once, without a prefix that repeats it.
    #[error(transparent)]
    Eds(#[from] crate::od::ReadError),
    /// A bus address that does not parse.
    #[error("bus '{}': {reason}", clipped(uri))]
    BadBusAddr {
        /// The address as given.
        uri: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A node-id outside what this bus can address.
    #[error("{}", node_id_text(*node, *range))]
    NodeIdOutOfRange {
        /// The node-id given.
        node: u8,
        /// The node-ids this bus can address.
        range: NodeIdRange,
    },
    /// A value too large for an SDO download (CiA 301 sizes are 32-bit).
    #[error("{len} bytes cannot be written by SDO: CiA 301 sizes are 32-bit (at most {} bytes)", u32::MAX)]
    TooLargeForSdo {
        /// The value's size, in bytes.
        len: usize,
    },
    /// A CAN bit rate the slcan adapter protocol has no code for.
    #[error("{port}: slcan has no {kbit} kbit/s; use one of {}", supported.join(" "))]
    SlcanBitRate {
        /// The adapter's serial port.
        port: String,
        /// The bit rate asked for, in kbit/s.
        kbit: u32,
        /// The bit rates the protocol has codes for (`500k`, ...).
        supported: Vec<String>,
    },
    /// Something this kind of bus cannot do (`{bus}: {why}`).
    #[error("{bus}: {why}")]
    NotOnThisBus {
        /// The bus, as its address reads.
        bus: String,
        /// What it cannot do, and what to do instead.
        why: &'static str,
    },
    /// A remote (RTR) frame asked of a link that cannot carry one (`backend` names it).
    #[error("{bus}: {backend} carries no remote (RTR) frames: node guarding and RTR polling cannot go through it; a node's heartbeat (0x1017) shows its state instead")]
    NoRemoteFrames {
        /// The bus, as its address reads.
        bus: String,
        /// The kind of link ("socketcand").
        backend: &'static str,
    },
    /// LSS was asked to give a node-id that something on the bus already answers to
    /// (`by`: "an SDO answer", "its heartbeat", ...); nothing was sent.
    #[error("node-id {node} is in use: {by} came from node {node}{}; a second device on it would make both unreachable. Nothing was sent", identity.map(|i| format!(" (identity {i})")).unwrap_or_default())]
    NodeIdInUse {
        /// The node-id asked for.
        node: u8,
        /// The LSS identity of the device that answers to it, when it was read.
        identity: Option<Identity>,
        /// What showed the node-id in use.
        by: &'static str,
    },
    /// A drive command for a node whose device type (0x1000) names another profile.
    #[error("node {node} is not a CiA 402 drive: its device type (0x1000) is 0x{device_type:08X}, {}; drive commands are for profile 402", profile_text(*device_type))]
    NotADrive {
        /// The node-id of the node it is about.
        node: u8,
        /// Its device type (0x1000); the profile number is the low 16 bits.
        device_type: u32,
    },

    // ---- no response (exit 3) ----
    /// A node did not answer at all (`node` 0: all nodes, as NMT addresses them).
    #[error("{}", no_answer_text(*node, what, *waited))]
    NoAnswer {
        /// The node-id asked (0: all nodes).
        node: u8,
        /// What it was asked.
        what: Service,
        /// How long an answer was waited for (for each request, where there were several).
        waited: Duration,
    },
    /// A write that is an action (`what`: store, program control, ...) got no answer to the
    /// request that completes it: the device may have done it. It is not repeated
    /// (`canopen::sdo::retry`); a read-back, where one can tell, did not confirm it.
    #[error("node {node}: outcome unknown: {obj} ({what}) is an action, sent once, and its answer did not come within {} ms: the device may have done it or not. Not repeated behind your back: check the device, then send it again if it was not done", waited.as_millis())]
    SdoOutcomeUnknown {
        /// The node-id of the node it is about.
        node: u8,
        /// The object written.
        obj: ObjAddr,
        /// The action the write asks for, in words ("store parameters", ...).
        what: &'static str,
        /// How long the answer was waited for.
        waited: Duration,
    },
    /// A node answered an SDO transfer, then it did not finish.
    #[error("{}", sdo_unfinished_text(*node, *obj, *moved, why))]
    SdoUnfinished {
        /// The node-id of the node it is about.
        node: u8,
        /// The object transferred.
        obj: ObjAddr,
        /// How much had moved when it stopped.
        moved: Moved,
        /// Why it did not finish.
        why: Unfinished,
    },
    /// No answer to a remote (RTR) frame.
    #[error("no answer to the remote request for 0x{cob:03X} within {} ms", waited.as_millis())]
    NoRemoteAnswer {
        /// The COB-ID requested.
        cob: u16,
        /// How long the answer was waited for.
        waited: Duration,
    },
    /// No LSS device answered a confirmed LSS service; with the identity when one device
    /// was selected (the selective switch).
    #[error("{}", match identity {
        Some(id) => format!("no LSS device with identity {id} answered {request} within {} ms", waited.as_millis()),
        None => format!("no LSS device answered {request} within {} ms", waited.as_millis()),
    })]
    NoLssAnswer {
        /// The LSS service, in words.
        request: String,
        /// The identity of the device selected, if one was.
        identity: Option<Identity>,
        /// How long an answer was waited for.
        waited: Duration,
    },
    /// `lss assign` gave a device a node-id and heard no answer, however often asked: the
    /// request may have reached it and only the answers been lost, so it may hold it.
    #[error(
        "no answer from {identity} to set-id {node} within {} ms, asked {tries} times: unknown whether it \
         holds node {node} now",
        waited.as_millis()
    )]
    LssSetIdUnknown {
        /// The device's LSS identity.
        identity: Identity,
        /// The node-id it was given.
        node: u8,
        /// How many times it was asked.
        tries: u32,
        /// How long each answer was waited for.
        waited: Duration,
    },
    /// An EPOS2 gateway reports that the node behind it did not answer on the CAN bus.
    #[error("{}: no answer on the CAN bus (the EPOS2 reports SDO timeout 0x05040000)", epos2_place(*node, command, *obj))]
    Epos2NoCanAnswer {
        /// The node-id behind the gateway.
        node: u8,
        /// The EPOS2 command sent ("ReadObject", ...).
        command: &'static str,
        /// The object it was for; none for a command about no object.
        obj: Option<ObjAddr>,
    },
    /// A serial CAN adapter did not answer one of its commands.
    #[error("{port}: the adapter did not answer {command:?} within {} ms", waited.as_millis())]
    AdapterNoAnswer {
        /// The adapter's serial port.
        port: String,
        /// The adapter command sent, as sent.
        command: String,
        /// How long the answer was waited for.
        waited: Duration,
    },
    /// LSS fastscan did not find a device (exit 3), or found one it could not confirm (exit 5).
    #[error("{}", fastscan_text(error, *step))]
    Fastscan {
        /// What the fastscan found, or did not.
        error: FastscanError,
        /// The longest wait for answers a step used.
        step: Duration,
    },

    // ---- refused by the device (exit 4) ----
    /// The device refused an SDO transfer.
    #[error("node {node}: SDO abort 0x{code:08X} on {obj}: {}", abort::meaning(*code))]
    SdoAbort {
        /// The node-id of the node it is about.
        node: u8,
        /// The object transferred.
        obj: ObjAddr,
        /// The SDO abort code (CiA 301), as the device sent it.
        code: u32,
    },
    /// An LSS device answered a configuration service with an error.
    #[error("LSS {service}: error {error}: {}{}", crate::canopen::lss::error_meaning(*cs, *error),
        if *error == 255 { format!(" (specific code {specific})") } else { String::new() })]
    LssRefused {
        /// The LSS service, in words.
        service: String,
        /// The service's command specifier (CiA 305).
        cs: u8,
        /// The error code the device answered (255: device-specific, see `specific`).
        error: u8,
        /// The device-specific error code (meaningful when `error` is 255).
        specific: u8,
    },
    /// An EPOS2 answered a command with an error code (a maxon code or, where no object is
    /// involved, any code).
    #[error("{}: {}error 0x{code:08X}: {}", epos2_place(*node, command, *obj),
        if crate::epos2::command::is_maxon_code(*code) { "EPOS2 " } else { "" },
        crate::epos2::command::error_meaning(*code))]
    Epos2Refused {
        /// The node-id addressed (0: the EPOS2 itself).
        node: u8,
        /// The EPOS2 command sent ("ReadObject", ...).
        command: &'static str,
        /// The object it was for; none for a command about no object.
        obj: Option<ObjAddr>,
        /// The error code the EPOS2 answered.
        code: u32,
    },
    /// LSS assignment found no free node-id for a device.
    #[error("no free node-id left from {start} to 127 for {identity}")]
    NoFreeNodeId {
        /// The first node-id that could be given.
        start: u8,
        /// The LSS identity of the device left without one.
        identity: Identity,
    },
    /// A node keeps no error history (it has no object 0x1003), so there is none to clear.
    #[error("node {node} keeps no error history (it has no object 0x1003): there is nothing to clear")]
    NoErrorHistory {
        /// The node-id of the node it is about.
        node: u8,
    },
    /// A node without CiA 302-3's program-download objects: no bootloader to ask.
    #[error("node {node} has no program-download objects 0x1F50/0x1F51/0x1F56/0x1F57: no CiA 302-3 bootloader there")]
    NoBootloader {
        /// The node-id of the node it is about.
        node: u8,
    },
    /// A node keeps no description of itself (CiA 301 object 0x1021).
    #[error("node {node}: the device does not store its EDS (0x1021)")]
    NoStoredEds {
        /// The node-id of the node it is about.
        node: u8,
    },
    /// A node cannot store or restore parameters on command.
    #[error("{}", store_refused_text(*node, *command, why))]
    StoreRefused {
        /// The node-id of the node it is about.
        node: u8,
        /// Which it was asked to do.
        command: ParameterCommand,
        /// Why the node cannot.
        why: StoreRefusal,
    },
    /// A drive command (`goal`: enable, disable …) stopped short of its goal, in `state`.
    /// Stopped for want of an answer it is a timeout (exit 3), else a refusal (exit 4).
    #[error("node {node}: {goal} stopped in {state}: {why}")]
    DriveStopped {
        /// The node-id of the node it is about.
        node: u8,
        /// The command's goal, in words.
        goal: &'static str,
        /// The CiA 402 state the drive stopped in, in words.
        state: String,
        /// Why it stopped.
        why: DriveStop,
    },

    // ---- link failure (exit 5) ----
    /// The link to the bus failed, or the device answered with something unintelligible.
    #[error("{0}")]
    Link(LinkError),
    /// The EDS a node stores (0x1021) does not unpack in the format it names (0x1022).
    #[error("node {node}: its stored EDS (0x1021) cannot be used: {why}; nothing was saved")]
    StoredEds {
        /// The node-id of the node it is about.
        node: u8,
        /// Why the stored file cannot be used.
        why: crate::od::stored::StoredError,
    },

    // ---- verification failed (exit 6) ----
    /// An object read back other than what was written.
    #[error("node {node}: {obj} reads back {read} after writing {wrote}")]
    ReadBack {
        /// The node-id of the node it is about.
        node: u8,
        /// The object written.
        obj: ObjAddr,
        /// The value written, formatted.
        wrote: String,
        /// The value read back, formatted.
        read: String,
    },
    /// Objects read back other than what was written.
    #[error("node {node}: {} read back other values than written", join(objects))]
    ReadBackMany {
        /// The node-id of the node it is about.
        node: u8,
        /// The objects that read back other values.
        objects: Vec<ObjAddr>,
    },
    /// A device description file deviates from CiA 306 so that something it describes is
    /// not used (`config check`).
    #[error("{file}: {errors} error(s) and {warnings} warning(s) against CiA 306 (listed above); correct the file, or ask its vendor for one that follows CiA 306")]
    FileDeviates {
        /// The file, as named.
        file: String,
        /// How many findings are errors.
        errors: usize,
        /// How many findings are warnings.
        warnings: usize,
    },
    /// A configuration file names another device (vendor-ID, product code) than the node
    /// is; each difference said as `"vendor-ID 0x... on node N, 0x... in the file"`.
    #[error("{file} is for another device: {}. Nothing was written", differences.join(", "))]
    OtherDevice {
        /// The configuration file, as named.
        file: String,
        /// Each identity entry that differs, in words.
        differences: Vec<String>,
    },
    // ---- output (exit 7) ----
    /// A result could not be written (disk full, no permission, a closed terminal); the
    /// device side is unaffected.
    #[error("cannot write {path}: {why}")]
    Output {
        /// Where the result was to go (a path, or the stream it was written to).
        path: String,
        /// Why it could not be written.
        why: String,
    },

    // ---- interrupted (exit 130) ----
    /// The user pressed Ctrl-C.
    #[error("interrupted")]
    Interrupted,
    /// The user asked to stop while an SDO transfer was under way: it was ended part-way,
    /// with an abort sent to the device (`aborted`, its code) where the link allows one.
    #[error("interrupted: the {} of {obj} {} node {node} stopped after {moved}{}",
        if *upload { "read" } else { "write" }, if *upload { "from" } else { "to" },
        match aborted { Some(code) => format!("; the transfer was aborted (SDO abort 0x{code:08X})"), None => String::new() })]
    SdoInterrupted {
        /// The node-id of the node it is about.
        node: u8,
        /// The object transferred.
        obj: ObjAddr,
        /// A read (upload from the node); else a write.
        upload: bool,
        /// How much had moved when it stopped.
        moved: Moved,
        /// The abort code sent to the device; none where the link could not send one.
        aborted: Option<u32>,
    },

    /// The user asked to stop while the cause of `error` (a node that did not answer) was
    /// looked for: `error` stands, its cause was not found.
    #[error("{error}; stopped while its cause was looked for")]
    DiagnosisInterrupted {
        /// What failed before the stop.
        error: Box<Error>,
    },

    /// A file a settings file names could not be used: where it is named (`canctl.toml:4`),
    /// then why. It ends the process as the error itself would.
    #[error("{file}:{line}: {error}")]
    InSettingsFile {
        /// The settings file.
        file: String,
        /// The line that names the file.
        line: usize,
        /// Why it could not be used.
        error: Box<Error>,
    },
    /// An error with what the library knows to add about it ([`Advice`]); it ends the
    /// process as the error itself would.
    #[error("{error}{advice}")]
    Advised {
        /// The error itself.
        error: Box<Error>,
        /// What is known to add, which follows the error's message.
        advice: Advice,
    },

    // Errors whose remedy names a flag: the message says what happened, the remedy is a
    // the front end chooses and words (`output/remedies.rs`, issue 28).
    /// This OS has no SocketCAN (`bus`: the address given) (exit 2).
    #[error(
        "{bus}: SocketCAN is Linux's; on this OS reach the bus through a serial-line adapter (slcan:PORT, e.g. \
         slcan:COM5 or slcan:/dev/tty.usbmodem1101) or an EPOS2 (epos2-usb:PORT)"
    )]
    NoSocketCan {
        /// The bus address given.
        bus: String,
    },
    /// A session's TPDO mapping could not be put back as it was before the session: the
    /// write that failed (`error`, which decides the exit code).
    #[error("{error}{}", tpdo_left(*node, *tpdo))]
    TpdoNotPutBack {
        /// The node-id.
        node: u8,
        /// The TPDO (1-based).
        tpdo: u16,
        /// Why it could not be put back.
        error: Box<Error>,
    },
    /// The size of an object to map into a PDO, which the dictionary does not give, could not
    /// be learnt by reading it (`obj`): the read's error, which decides the exit code.
    #[error("{error}")]
    MapSizeUnread {
        /// The object to map.
        obj: ObjAddr,
        /// Why it could not be read.
        error: Box<Error>,
    },
    /// A network project, or a file it names, that cannot be used as it is (exit 2).
    #[error("{0}")]
    ProjectUnusable(Box<ProjectProblem>),
    /// A file canctl makes (a DCF, an XDC, a project) cannot hold a value as it is (exit 2).
    #[error("{0}")]
    NotWritable(NotWritable),
    /// A value outside the limits a dictionary gives its object (`dictionary`: which
    /// one), refused before anything is written (exit 2).
    #[error("{value} is outside the range of {object}: use {low} to {high} ({dictionary}); nothing was written")]
    OutOfRange {
        /// The object.
        object: ObjAddr,
        /// The value, as given or as the file writes it.
        value: String,
        /// The lowest value allowed.
        low: i128,
        /// The highest value allowed.
        high: i128,
        /// The dictionary the limits come from, in words.
        dictionary: String,
    },
    /// No data type to encode a value with: none was asked for and the dictionary has no
    /// entry for the object (exit 2).
    #[error(
        "no data type to encode '{value}' for {object} (no dictionary entry): one of b u8 u16 u24 u32 u40 u48 u56 \
         u64 i8 i16 i24 i32 i40 i48 i56 i64 r32 r64 t td vs us os d"
    )]
    TypeNeeded {
        /// The value to encode, as given.
        value: String,
        /// The object it is for.
        object: ObjAddr,
    },
    /// An LSS service (`verb`) asked of an EPOS2 reached directly, which has no LSS (exit 2).
    #[error("an EPOS2 reached directly (node 0) has no LSS, so `lss {verb}` cannot be done on it")]
    NoLssOnDirectEpos2 {
        /// The LSS command asked for (`inquire`, `fastscan`, `assign`).
        verb: String,
    },
    /// `lss activate` asked of an EPOS2 reached directly: it takes a new bit rate only when
    /// it is stored and reset (exit 2).
    #[error("an EPOS2 reached directly takes its new bit rate when it is stored and reset")]
    Epos2RateOnStore,
    /// Nothing answered a wait, and the link says why: its failure (`error`), which decides
    /// the exit code; an adapter's bus errors then have a remedy (its bit rate).
    #[error("{error}")]
    NothingAnswered {
        /// The link's failure.
        error: Box<Error>,
    },
    /// `lss assign` gave a device a node-id, and it still answered in LSS configuration state
    /// however often it was sent back to waiting: it holds `node` but has not taken it up
    /// (it boots with it when it leaves configuration state, or at its next power cycle).
    #[error(
        "{identity}, given node {node}, still answers in LSS configuration state after being sent back to \
         waiting {tries} times; it takes node {node} up when it leaves (power-cycle it if it stays there)"
    )]
    LssStillConfiguring {
        /// The device's LSS identity.
        identity: Identity,
        /// The node-id it was given.
        node: u8,
        /// How many times it was sent back.
        tries: u32,
    },
    /// `lss assign` found a device (or `network apply` selected one), and another one
    /// answered as being in LSS configuration state too, however often every device was sent
    /// back to waiting: a node-id given now would be taken by both, so none was.
    #[error(
        "{identity} was selected {times} time(s) with another device in LSS configuration state too (one \
         that misses the switch back to waiting); no node-id given, as both would take it"
    )]
    LssCrowded {
        /// The device found.
        identity: Identity,
        /// How many searches found it so.
        times: u32,
    },
    /// A device still answered in LSS configuration state however often every device was
    /// sent back to waiting.
    #[error(
        "a device still answers in LSS configuration state after every device was sent back to waiting \
         {tries} times (it misses the switch)"
    )]
    LssLeftInConfiguration {
        /// How many times every device was sent back.
        tries: u32,
    },
}

impl From<crate::od::eds::EdsError> for Error {
    fn from(e: crate::od::eds::EdsError) -> Error {
        Error::Eds(e.into())
    }
}

impl Error {
    /// The bus (or port) this error's message begins with, when it names one: shown as one
    /// of several buses' failures, it needs no prefix naming that bus again.
    pub fn names_bus(&self) -> Option<&str> {
        match self {
            Error::NotOnThisBus { bus, .. } | Error::NoRemoteFrames { bus, .. } | Error::NoSocketCan { bus } => {
                Some(bus)
            }
            Error::Advised { error, .. } | Error::TpdoNotPutBack { error, .. } | Error::NothingAnswered { error } => {
                error.names_bus()
            }
            Error::Link(e) => e.names_port(),
            _ => None,
        }
    }

    /// The error under any hint.
    pub fn root(&self) -> &Error {
        match self {
            Error::Advised { error, .. }
            | Error::TpdoNotPutBack { error, .. }
            | Error::MapSizeUnread { error, .. }
            | Error::NothingAnswered { error } => error.root(),
            e => e,
        }
    }

    /// This error with `advice` after its message.
    pub fn advised(self, advice: Advice) -> Error {
        Error::Advised { error: Box::new(self), advice }
    }
}

/// What a TPDO not put back leaves, to follow the failed write's message.
pub fn tpdo_left(node: u8, tpdo: u16) -> String {
    let comm = 0x1800 + tpdo - 1;
    format!("; node {node}'s TPDO{tpdo} was not put back as it was (0x{comm:04X}:1 may leave it switched off)")
}

/// The library's result.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl From<crate::epos2::Epos2Error> for Error {
    fn from(e: crate::epos2::Epos2Error) -> Error {
        Error::Link(LinkError::Epos2(e))
    }
}

impl From<crate::socketcand::SocketcandError> for Error {
    fn from(e: crate::socketcand::SocketcandError) -> Error {
        Error::Link(LinkError::Socketcand(e))
    }
}

impl From<LinkError> for Error {
    fn from(e: LinkError) -> Error {
        Error::Link(e)
    }
}
