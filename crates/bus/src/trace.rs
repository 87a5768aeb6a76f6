//! Diagnostics as `tracing` events: the library never prints. The command line renders them
//! on stderr (`-v`, `-q`); a program embedding the crate installs its own subscriber.
//!
//! | target | level | what |
//! |---|---|---|
//! | [`FRAMES`] | DEBUG | every CAN frame sent or received; the message is the frame in candump's notation (`  vcan0  605   [8]  40 00 10 00 00 00 00 00`), the fields `iface`, `dir` (`tx`/`rx`) and `frame` (`605#4000100000000000`) |
//! | [`BYTES`] | DEBUG | every EPOS2 serial frame, as bytes (`  epos2-rs232:/dev/ttyS0 > 10 01 ...`) |
//! | other `canctl::*` | WARN | what a user should know: error frames on the bus, waiting for the sim network |
//! | other `canctl::*` | TRACE | what a procedure does along the way: SDO transfers, lock waits, slcan lines |

use crate::frame::Frame;

/// The target of the frame trace events.
pub const FRAMES: &str = "canctl::frames";
/// The target of the EPOS2 serial byte trace events.
pub const BYTES: &str = "canctl::bytes";

/// Which way a frame went, seen from canctl.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dir {
    /// Sent by canctl.
    Tx,
    /// Received by canctl.
    Rx,
}

impl Dir {
    /// The `dir` field's value: `tx` or `rx`.
    pub fn as_str(self) -> &'static str {
        match self {
            Dir::Tx => "tx",
            Dir::Rx => "rx",
        }
    }
}

/// Whether anyone listens to the frame trace (building a line costs an allocation).
pub(crate) fn frames_enabled() -> bool {
    tracing::enabled!(target: FRAMES, tracing::Level::DEBUG)
}

/// One frame trace event. The candump line is only built when someone listens.
pub fn frame(iface: &str, dir: Dir, frame: &Frame) {
    tracing::debug!(
        target: FRAMES,
        iface,
        dir = dir.as_str(),
        frame = %frame,
        "{}",
        frame.candump_line(iface)
    );
}

/// One EPOS2 serial frame as bytes; `dir` is `>` for what came from the device, `<` for
/// what went to it.
pub fn bytes(name: &str, dir: &str, bytes: &[u8]) {
    let hex = || bytes.iter().map(|b| format!("{b:02X}")).collect::<Vec<_>>().join(" ");
    tracing::debug!(target: BYTES, port = name, dir, "  {name} {dir} {}", hex());
}
