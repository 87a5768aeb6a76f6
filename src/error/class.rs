//! How a failure ends the process: the exit-code table.

/// What a failure means for the user, and so how the process ends. The README's
/// "Exit codes" table lists these (a test checks that it does).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
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
