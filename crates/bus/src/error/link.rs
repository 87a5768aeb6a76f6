//! Link failures: the port, interface, pseudo-terminal or server, and what went wrong with it.

use super::detail::clipped;
use crate::canopen::ObjAddr;
use std::fmt;
use std::path::PathBuf;
use std::time::Duration;

/// A link failure: the port, interface or pseudo-terminal, and what went wrong with it.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum LinkError {
    /// A port or interface that cannot be opened.
    #[error("cannot open {}: {error}", clipped(port))]
    Open {
        /// The port or interface, as named.
        port: String,
        /// The OS's error.
        error: std::sync::Arc<std::io::Error>,
    },
    /// A path given as a serial port that is none (`/dev/null`, a file): the OS's word for
    /// it, "Not a typewriter", says nothing to most.
    #[error(
        "{} is not a serial port; serial ports here: {}",
        clipped(port),
        if available.is_empty() { "none found".to_string() } else { available.join(", ") }
    )]
    NotSerialPort {
        /// The path, as given.
        port: String,
        /// The serial ports this machine has.
        available: Vec<String>,
    },
    /// An operation on an open port or interface failed (`{port}: {op}: {source}`; no `op`:
    /// `{port}: {source}`).
    #[error("{port}: {}{error}", if op.is_empty() { String::new() } else { format!("{op}: ") })]
    Io {
        /// The port or interface, as named.
        port: String,
        /// The operation that failed (may be empty).
        op: &'static str,
        /// The OS's error.
        error: std::sync::Arc<std::io::Error>,
    },
    /// No network interface of this name; `available` lists the CAN interfaces there are
    /// (the remedy, the front end's, names them and the nearest one).
    #[error("there is no network interface '{iface}'")]
    NoInterface {
        /// The interface asked for.
        iface: String,
        /// The CAN interfaces this machine has.
        available: Vec<String>,
    },
    /// A network interface that is not a CAN interface.
    #[error("'{iface}' is not a CAN interface")]
    NotCan {
        /// The interface, as named.
        iface: String,
    },
    /// A CAN interface that is down.
    #[error("{iface} is down: bring it up first (e.g. sudo ip link set {iface} up type can bitrate 500000)")]
    Down {
        /// The interface, as named.
        iface: String,
    },
    /// The CAN controller went bus-off.
    #[error("{iface}: the controller went bus-off ({detail})")]
    BusOff {
        /// The interface, as named.
        iface: String,
        /// What the controller reported.
        detail: String,
    },
    /// Frames could not be queued for this long.
    #[error(
        "{iface}: the transmit queue stayed full for {} s (no other node acknowledging? bus-off?)",
        waited.as_secs()
    )]
    TxQueueFull {
        /// The interface, as named.
        iface: String,
        /// How long frames could not be queued.
        waited: Duration,
    },
    /// A serial CAN adapter refused a command.
    #[error(
        "{port}: the adapter refused to {what}; is it an slcan (Lawicel) adapter, and not in use by another program?"
    )]
    AdapterRefused {
        /// The adapter's serial port.
        port: String,
        /// What it was asked to do, in words.
        what: &'static str,
    },
    /// A serial CAN adapter reports bus errors (its status flags, by name).
    #[error("{port}: the adapter reports {}: check the wiring, the termination and the bit rate", flags.join(", "))]
    AdapterBusError {
        /// The adapter's serial port.
        port: String,
        /// Its status flags that are set, by name.
        flags: Vec<&'static str>,
    },
    /// A serial CAN adapter refused to send a frame (with its status flags, when it gave them),
    /// or, with no `cob`, refused a frame while receiving.
    #[error("{}", match cob {
        Some(cob) if flags.is_empty() => format!("{port}: the adapter refused to send {cob:03X}"),
        Some(cob) => format!("{port}: the adapter refused to send {cob:03X} ({})", flags.join(", ")),
        None => format!("{port}: the adapter refused a frame"),
    })]
    AdapterRefusedFrame {
        /// The adapter's serial port.
        port: String,
        /// The COB-ID of the frame it refused to send; none when it refused one while receiving.
        cob: Option<u16>,
        /// Its status flags that are set, by name (empty when it gave none).
        flags: Vec<&'static str>,
    },
    /// An SDO transfer broke off on a protocol error; `aborted` is the abort code sent.
    #[error("node {node}: SDO transfer of {obj} failed: {reason}{}",
        aborted.map(|c| format!(" (aborted with 0x{c:08X})")).unwrap_or_default())]
    SdoProtocol {
        /// The node-id of the node it is about.
        node: u8,
        /// The object transferred.
        obj: ObjAddr,
        /// What was wrong with the answer, in words.
        reason: String,
        /// The abort code sent to the device; none when none was sent.
        aborted: Option<u32>,
    },
    /// An upload did not end within the limit of bytes asked for, and was stopped (the
    /// answers never said the size, as an EPOS2's do not, so only what arrived was counted).
    #[error(
        "node {node}: SDO transfer of {obj} failed: the upload did not end within the limit of {limit} bytes: \
             stopped after {received}"
    )]
    UploadOverLimit {
        /// The node-id of the node it is about.
        node: u8,
        /// The object read.
        obj: ObjAddr,
        /// The limit, in bytes.
        limit: usize,
        /// The bytes that had arrived when it was stopped.
        received: usize,
    },
    /// The EPOS2 serial line or an EPOS2's answer failed.
    #[error(transparent)]
    Epos2(#[from] crate::epos2::Epos2Error),
    /// A socketcand server could not be reached, refused, or went away.
    #[error(transparent)]
    Socketcand(#[from] crate::socketcand::SocketcandError),
    /// The simulator's state file could not be used.
    #[error("sim state file {}: {what}: {detail}", path.display())]
    StateFile {
        /// The state file.
        path: PathBuf,
        /// What could not be done with it.
        what: &'static str,
        /// Why, as the OS or the parser said.
        detail: String,
        /// The file is there but cannot be taken as it is: starting a fresh network is the
        /// remedy.
        afresh: bool,
    },
    /// Another process holds the simulator's network (its state file's lock); `holder`
    /// names it (pid and command line) as far as it said.
    #[error("the sim network is in use by {holder} (waited {}): it serves one command at a time; stop that one",
        if *waited < Duration::from_secs(1) { format!("{} ms", waited.as_millis()) } else { format!("{} s", waited.as_secs_f64()) })]
    SimInUse {
        /// The process that holds it (pid and command line), or "another process".
        holder: String,
        /// How long the lock was waited for.
        waited: Duration,
        /// The `--bus` that reaches the devices where that process serves them, if it does.
        serving: Option<String>,
    },
    /// A pseudo-terminal (the simulator's serial devices) failed.
    #[error("{op}: {detail}")]
    Pty {
        /// What failed.
        op: PtyOp,
        /// Why, as the OS said.
        detail: String,
    },
}

/// What failed on a pseudo-terminal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum PtyOp {
    /// Creating one.
    Create,
    /// Setting its terminal attributes (raw mode).
    Termios,
    /// Finding its path.
    Name,
    /// Waiting for it to be readable.
    Poll,
    /// Reading from it.
    Read,
    /// Writing to it.
    Write,
    /// Telling the user its path.
    PrintPath,
}

impl LinkError {
    /// The port or interface this error's message begins with, when it begins with one.
    pub(crate) fn names_port(&self) -> Option<&str> {
        match self {
            LinkError::Io { port, .. }
            | LinkError::AdapterRefused { port, .. }
            | LinkError::AdapterBusError { port, .. }
            | LinkError::AdapterRefusedFrame { port, .. } => Some(port),
            LinkError::BusOff { iface, .. } | LinkError::TxQueueFull { iface, .. } => Some(iface),
            _ => None,
        }
    }
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
