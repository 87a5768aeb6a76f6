//! How a failure ends the process: the exit-code table, and each error's place in it.

use super::detail::DriveStop;
use super::kind::Error;
use crate::canopen::lss::FastscanError;

/// What a failure means for the user, and so how the process ends. The README's
/// "Exit codes" table lists these (a test checks that it does).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
// Exhaustive on purpose: the exit-code table lists every class, and a new one must be placed.
pub enum ErrorClass {
    /// The user asked for something malformed or impossible (exit 2).
    Usage,
    /// Nobody answered in time (exit 3).
    Timeout,
    /// The device refused (exit 4).
    Refused,
    /// The link to the bus failed, or an answer was unintelligible (exit 5).
    Link,
    /// A check found differences, or a read-back did not confirm a write (exit 6).
    Verify,
    /// A result could not be written (exit 7).
    Output,
    /// The user asked to stop (exit 130).
    Interrupted,
}

impl ErrorClass {
    /// Every class, in the order of the exit-code table.
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

/// Each error's class: the one mapping from errors to exit codes.
impl Error {
    /// Which kind of failure this is: the one mapping from errors to exit codes.
    pub fn class(&self) -> ErrorClass {
        use ErrorClass as C;
        match self {
            Error::Usage(_)
            | Error::DcfNotReadWhole { .. }
            | Error::NotADcf { .. }
            | Error::NotOfType { .. }
            | Error::NoSuchTpdo { .. }
            | Error::NoValidTpdo { .. }
            | Error::InquiryAnsweredByMany { .. }
            | Error::Input(_)
            | Error::OutsideProject(_)
            | Error::SimState(_)
            | Error::Eds(_)
            | Error::BadBusAddr { .. }
            | Error::NodeIdOutOfRange { .. }
            | Error::TooLargeForSdo { .. }
            | Error::SlcanBitRate { .. }
            | Error::NotOnThisBus { .. }
            | Error::NoRemoteFrames { .. }
            | Error::NotADrive { .. }
            | Error::NodeIdInUse { .. }
            | Error::NoSocketCan { .. }
            | Error::TypeNeeded { .. }
            | Error::OutOfRange { .. }
            | Error::ProjectUnusable(_)
            | Error::NotWritable(_)
            | Error::NoLssOnDirectEpos2 { .. }
            | Error::Epos2RateOnStore
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
            Error::Fastscan { error: FastscanError::Unconfirmed(_), .. }
            | Error::LssStillConfiguring { .. }
            | Error::LssCrowded { .. }
            | Error::LssLeftInConfiguration { .. } => C::Link,
            Error::Fastscan { .. } => C::Timeout,
            Error::SdoAbort { .. }
            | Error::LssRefused { .. }
            | Error::Epos2Refused { .. }
            | Error::StoreRefused { .. }
            | Error::NoErrorHistory { .. }
            | Error::NoBootloader { .. }
            | Error::NoStoredEds { .. } => C::Refused,
            Error::DriveStopped { why: DriveStop::NoAnswer, .. } => C::Timeout,
            Error::DriveStopped { .. } => C::Refused,
            Error::Link(_) | Error::StoredEds { .. } => C::Link,
            Error::ReadBack { .. }
            | Error::ReadBackMany { .. }
            | Error::FileDeviates { .. }
            | Error::OtherDevice { .. } => C::Verify,
            Error::Output { .. } => C::Output,
            Error::Interrupted | Error::SdoInterrupted { .. } | Error::DiagnosisInterrupted { .. } => C::Interrupted,
            Error::Advised { error, .. }
            | Error::InSettingsFile { error, .. }
            | Error::MapSizeUnread { error, .. }
            | Error::TpdoNotPutBack { error, .. }
            | Error::NothingAnswered { error } => error.class(),
        }
    }

    /// The process exit code for this error.
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
}
