//! An error kept in a report row (a write that failed, a node that did not answer): the
//! typed error itself, for the front end to word with its remedy as it words any error.

use crate::error::Error;

/// An error a report row tells of.
#[derive(Debug, Clone)]
pub struct Failure {
    /// The error.
    pub error: Error,
}

impl From<&Error> for Failure {
    fn from(error: &Error) -> Failure {
        Failure { error: error.clone() }
    }
}

/// The error's own message (as it displays), without a remedy.
impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.error.fmt(f)
    }
}

/// Rows are compared by what they say: the error's message.
impl PartialEq for Failure {
    fn eq(&self, other: &Failure) -> bool {
        self.error.to_string() == other.error.to_string()
    }
}

impl Eq for Failure {}
