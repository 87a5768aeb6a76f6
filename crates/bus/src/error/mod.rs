//! The library's error type: one variant per kind of failure, with what it is about (node,
//! object, abort code, how long was waited) as fields. Every variant belongs to one
//! [`ErrorClass`], and the class alone decides the exit code ([`Error::exit_code`]), so the
//! CLI never has to guess how a failure should end the process, and nothing ever reads an
//! error's text to decide anything.
//!
//! The display texts are the messages canctl prints; tests and the README quote them.
//! To ask what kind of failure an error is, use [`Error::class`] (which sees through
//! [`Error::Advised`]; in the crate, `is_timeout` and `is_interrupted` ask it), not a match on
//! one variant of the class.

mod class;
mod detail;
mod kind;
mod link;
pub use class::ErrorClass;
pub use detail::clipped;
pub use detail::{
    Advice, DriveStop, Moved, NodeIdRange, NotWritable, OutsideProject, ParameterCommand, ProjectProblem, Service,
    StateRefused, StoreRefusal, Unfinished,
};
pub use kind::{tpdo_left, Error, Result};
pub use link::{LinkError, PtyOp};
