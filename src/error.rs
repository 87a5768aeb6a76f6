//! The library's error type. Every variant maps to one of the documented exit codes, so the
//! CLI never has to guess how a failure should end the process.

use crate::canopen::{abort, ObjAddr};

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The user asked for something malformed or impossible (exit 2).
    #[error("{0}")]
    Usage(String),
    /// Nobody answered in time (exit 3).
    #[error("{0}")]
    Timeout(String),
    /// The device refused an SDO transfer (exit 4).
    #[error("node {node}: SDO abort 0x{code:08X} on {obj}: {}", abort::meaning(*code))]
    SdoAbort { node: u8, obj: ObjAddr, code: u32 },
    /// The device refused something else, e.g. an unsupported service (exit 4).
    #[error("{0}")]
    Refused(String),
    /// The link to the bus failed, or the device answered with something unintelligible (exit 5).
    #[error("{0}")]
    Link(String),
    /// A read-back did not match what was written (exit 6).
    #[error("{0}")]
    Verify(String),
    /// Output could not be written: disk full, no permission, a closed terminal (exit 7).
    #[error("{0}")]
    Output(String),
    /// The user pressed Ctrl-C (exit 130).
    #[error("interrupted")]
    Interrupted,
}

impl Error {
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Usage(_) => 2,
            Error::Timeout(_) => 3,
            Error::SdoAbort { .. } | Error::Refused(_) => 4,
            Error::Link(_) => 5,
            Error::Verify(_) => 6,
            Error::Output(_) => 7,
            Error::Interrupted => 130,
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
