//! The EPOS2 backend's errors: the serial line failed, or an answer made no sense. The
//! library's [`crate::Error`] wraps them (as a link failure, exit 5).

use super::transport::Failure;
use crate::canopen::ObjAddr;

/// An EPOS2 serial command or its answer failed.
#[derive(Debug, thiserror::Error)]
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
