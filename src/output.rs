//! The one place that decides how results look: human tables, JSON, CSV, JSON lines.
//! Results go to stdout; progress and diagnostics go to stderr. A command hands its
//! operation's report to [`Output::report`]; streams write records with [`RecordWriter`].

mod bars;
pub(crate) mod buses;
mod check;
mod command_error;
pub(crate) mod completion;
pub(crate) mod config;
pub(crate) mod diagnostics;
pub(crate) mod docs;
pub(crate) mod doctor;
mod drive;
mod events;
mod firmware;
mod health;
mod hints;
mod junit;
mod lss;
pub(crate) mod many_buses;
pub(crate) mod network;
mod nodes;
pub(crate) mod records;
mod remedies;
mod report;
mod reports;
pub(crate) mod sim;
pub mod stderr;
pub(crate) mod stopped;
mod table;
mod text;
mod usage;
mod verdicts;
mod wrap;

pub use bars::Bars;
pub(crate) use bars::NodeBars;
pub(crate) use command_error::explained;
pub use command_error::{CommandError, CommandResult};
pub(crate) use drive::{last_seen_text, watching_text};
pub use events::{event_line, say_deviations};
pub use hints::{last_scan_hint, library_error_text, switch_hint, Explained};
pub use junit::{TestCase, TestSuite};
pub(crate) use nodes::short_window_note;
pub use records::RecordWriter;
pub use report::{fitted_to_stderr, Format, FormatArg, Human, Line, Output, Report};
pub use reports::{applied_failure_note, sentence, stored_eds_line, Each};
pub use text::{csv, terminal_safe_lines};
pub use usage::UsageError;

#[cfg(test)]
mod tests;
// The error messages as canctl prints them, remedy included (issue 28).
#[cfg(test)]
mod error_texts;
