//! The EPOS2 backend's errors: the serial line failed, or an answer made no sense. The
//! library's [`crate::Error`] wraps them (as a link failure, exit 5).

use super::frame::FrameError;
use crate::canopen::ObjAddr;
use std::io;

/// An EPOS2 serial command or its answer failed.
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum Epos2Error {
    /// An EPOS2 serial command failed on the line (after a resync and a retry, when the
    /// first failure allowed one).
    #[error("{bus}: {command} failed: {failure}; {}{}",
        retry.as_ref().map(|second| format!("after a resync and retry: {second}; ")).unwrap_or_default(),
        retry.as_ref().unwrap_or(failure).advice())]
    Serial {
        /// The bus, as its address reads (`epos2-rs232:/dev/ttyS0`).
        bus: String,
        /// The command's name.
        command: &'static str,
        /// What went wrong.
        failure: Failure,
        /// What went wrong again after a resync, when the first failure allowed a retry.
        retry: Option<Failure>,
    },
    /// An EPOS2 answer that does not make sense.
    #[error("{}{problem}", if problem.names_bus() { format!("{bus}: ") } else { String::new() })]
    Answer {
        /// The bus, as its address reads.
        bus: String,
        /// What was wrong with the answer.
        problem: Epos2Problem,
    },
}

/// What was wrong with an EPOS2's answer.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum Epos2Problem {
    /// The answer to this command is shorter than its error code.
    #[error("the answer to {command} is too short")]
    TooShort {
        /// The command's name.
        command: &'static str,
    },
    /// A SegmentRead answer without its control byte.
    #[error("empty SegmentRead answer")]
    EmptySegment,
    /// A segmented read whose toggle bit did not alternate.
    #[error("node {node}: segmented read of {obj}: toggle bit not alternated")]
    ToggleNotAlternated {
        /// The node read from.
        node: u8,
        /// The object read.
        obj: ObjAddr,
    },
    /// A segment that claims more bytes than it carries.
    #[error("node {node}: segment claims {claimed} bytes but carries fewer")]
    ShortSegment {
        /// The node read from.
        node: u8,
        /// The bytes the segment claims.
        claimed: usize,
    },
    /// Segments in a row that carried no data and said more follow.
    #[error(
        "node {node}: segmented read of {obj}: {count} segments in a row without data that say more follow; \
         stopped. The device's SDO server is stuck"
    )]
    EmptySegments {
        /// The node read from.
        node: u8,
        /// The object read.
        obj: ObjAddr,
        /// How many in a row.
        count: usize,
    },
    /// A read that went on past the limit for reads through an EPOS2.
    #[error(
        "node {node}: segmented read of {obj}: {bytes} bytes and the device still says more follow; stopped at \
         the limit of {limit_kib} KiB for reads through an EPOS2. A value this large is read over SocketCAN (block \
         transfer); otherwise the device is faulty: reset it"
    )]
    TooLong {
        /// The node read from.
        node: u8,
        /// The object read.
        obj: ObjAddr,
        /// The bytes read when it was given up.
        bytes: usize,
        /// The limit, in KiB.
        limit_kib: usize,
    },
    /// A segmented write the EPOS2 confirmed one segment too many of.
    #[error("node {node}: segmented write of {obj}: the EPOS2 confirmed another segment")]
    ExtraSegment {
        /// The node written to.
        node: u8,
        /// The object written.
        obj: ObjAddr,
    },
}

impl Epos2Problem {
    /// Whether its message is about the bus, not a node: it then follows the bus's name.
    fn names_bus(&self) -> bool {
        matches!(self, Epos2Problem::TooShort { .. } | Epos2Problem::EmptySegment)
    }
}

/// Why one attempt failed.
#[derive(Debug, Clone, thiserror::Error)]
pub enum Failure {
    /// The EPOS2 refused the frame (RS232 'F'), during this step.
    #[error("the EPOS2 refused the frame: answered {0}")]
    Nack(&'static str),
    /// Nothing came in time, during this step.
    #[error("no answer {0}")]
    Timeout(&'static str),
    /// What came was not a valid frame.
    #[error("bad answer frame: {0}")]
    Frame(FrameError),
    /// An unexpected byte instead of an acknowledgement, during this step.
    #[error("unexpected byte 0x{0:02X} {1}")]
    Unexpected(u8, &'static str),
    /// Only answers that belong to no command of ours came.
    #[error("{0} answers in a row that do not answer this command (discarded)")]
    Misfit(usize),
    /// The line never fell quiet: bytes, milliseconds.
    #[error("the line does not fall quiet: {0} bytes in {1} ms without a pause")]
    Babble(usize, u128),
    /// The serial port failed.
    #[error("the port failed: {0}")]
    Io(std::sync::Arc<io::Error>),
}

impl Failure {
    pub(crate) fn retryable(&self) -> bool {
        !matches!(self, Failure::Io(_) | Failure::Babble(..))
    }

    /// What the user can do about it.
    pub(crate) fn advice(&self) -> &'static str {
        match self {
            Failure::Io(_) => "check that the device is connected and powered, then run the command again",
            Failure::Babble(..) => {
                "check the bit rate (?baud=), that no other program uses the port, and the cable; \
                 then run the command again"
            }
            // A slow device is the other cause: a remedy the front end words.
            _ => "check the cable, the bit rate (?baud=) and that no other program uses the port",
        }
    }

    /// Whether a slow device, given more time, could have answered: not when the port
    /// failed or the line never fell quiet.
    pub fn may_be_slow(&self) -> bool {
        self.retryable()
    }
}
