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
    #[error("{}", serial_text(bus, command, failure, retry.as_ref()))]
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
    #[error("{}", answer_text(bus, problem))]
    Answer {
        /// The bus, as its address reads.
        bus: String,
        /// What was wrong with the answer.
        problem: Epos2Problem,
    },
}

fn serial_text(bus: &str, command: &str, failure: &Failure, retry: Option<&Failure>) -> String {
    match retry {
        Some(second) => {
            format!("{bus}: {command} failed: {failure}; after a resync and retry: {second}; {}", second.advice())
        }
        None => format!("{bus}: {command} failed: {failure}; {}", failure.advice()),
    }
}

/// What was wrong with an EPOS2's answer.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Epos2Problem {
    /// The answer to this command is shorter than its error code.
    TooShort {
        /// The command's name.
        command: &'static str,
    },
    /// A SegmentRead answer without its control byte.
    EmptySegment,
    /// A segmented read whose toggle bit did not alternate.
    ToggleNotAlternated {
        /// The node read from.
        node: u8,
        /// The object read.
        obj: ObjAddr,
    },
    /// A segment that claims more bytes than it carries.
    ShortSegment {
        /// The node read from.
        node: u8,
        /// The bytes the segment claims.
        claimed: usize,
    },
    /// Segments in a row that carried no data and said more follow.
    EmptySegments {
        /// The node read from.
        node: u8,
        /// The object read.
        obj: ObjAddr,
        /// How many in a row.
        count: usize,
    },
    /// A read that went on past the limit for reads through an EPOS2.
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
    ExtraSegment {
        /// The node written to.
        node: u8,
        /// The object written.
        obj: ObjAddr,
    },
}

fn answer_text(bus: &str, problem: &Epos2Problem) -> String {
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
             that say more follow; stopped. The device's SDO server is stuck"
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

/// Why one attempt failed.
#[derive(Debug, Clone)]
pub enum Failure {
    /// The EPOS2 refused the frame (RS232 'F'), during this step.
    Nack(&'static str),
    /// Nothing came in time, during this step.
    Timeout(&'static str),
    /// What came was not a valid frame.
    Frame(FrameError),
    /// An unexpected byte instead of an acknowledgement, during this step.
    Unexpected(u8, &'static str),
    /// Only answers that belong to no command of ours came.
    Misfit(usize),
    /// The line never fell quiet: bytes, milliseconds.
    Babble(usize, u128),
    /// The serial port failed.
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

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Nack(stage) => write!(f, "the EPOS2 refused the frame: answered {stage}"),
            Failure::Timeout(stage) => write!(f, "no answer {stage}"),
            Failure::Frame(e) => write!(f, "bad answer frame: {e}"),
            Failure::Unexpected(b, stage) => write!(f, "unexpected byte 0x{b:02X} {stage}"),
            Failure::Misfit(n) => write!(f, "{n} answers in a row that do not answer this command (discarded)"),
            Failure::Babble(bytes, ms) => {
                write!(f, "the line does not fall quiet: {bytes} bytes in {ms} ms without a pause")
            }
            Failure::Io(e) => write!(f, "the port failed: {e}"),
        }
    }
}
