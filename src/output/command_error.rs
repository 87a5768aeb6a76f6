//! Why a command ended without its result, and the one place that says how: its exit code
//! (one [`CommandError::class`]), its words with their remedy ([`CommandError::text`]) and its
//! JSON form ([`CommandError::json`]). Every command returns it; `main` prints it and exits.
//! Each kind of failure is a variant, matched where it is worded: no downcasts, no message
//! spliced onto another.

use super::hints::{library_error_text, Explained};
use super::usage::UsageError;
use crate::error::ErrorClass;
use crate::ops::firmware::FirmwareError;
use crate::ops::unmet::{Shortfall, Unmet};

/// What ended a command short of its result.
#[derive(Debug, thiserror::Error)]
pub enum CommandError {
    /// The library's error (a device's, the link's, a file's, a usage's).
    #[error(transparent)]
    Library(#[from] crate::Error),
    /// A firmware download's own failure (flash status, identification, no boot-up); the
    /// bus's or device's failure during a download is a [`CommandError::Library`] error.
    #[error(transparent)]
    Firmware(FirmwareError),
    /// A library error with what the front end learnt about it (a silent node's likely cause,
    /// the nodes the last scan saw).
    #[error(transparent)]
    Explained(Box<Explained>),
    /// The work was done, and what it found is not as asked (a node unhealthy): the
    /// report said what; this says it in a line.
    #[error(transparent)]
    Unmet(#[from] Unmet),
    /// A command run on several buses, some of which fell short: the worst (of `class`, on
    /// `bus`) decides the exit code; the report shows every bus's, so its words are not
    /// said again here.
    #[error("{failed} of {total} buses failed, each as said for its bus; the worst was on {bus}")]
    OnBuses {
        /// The bus of the worst, as its URI.
        bus: String,
        /// The worst's class.
        class: ErrorClass,
        /// How many buses fell short.
        failed: usize,
        /// How many buses were worked.
        total: usize,
    },
    /// The command line's refusal of its arguments.
    #[error(transparent)]
    Usage(#[from] UsageError),
    /// The `--log-frames` file could not be made.
    #[error("--log-frames: {0}")]
    FrameLog(crate::Error),
    /// The result could not be written (standard output closed or full).
    #[error(transparent)]
    Output(#[from] std::io::Error),
}

/// What a command returns.
pub type CommandResult<T = ()> = Result<T, CommandError>;

impl From<FirmwareError> for CommandError {
    /// A download's step the bus or the device failed is that failure, as any command's: so
    /// it is explained (a silent node's likely cause) as any command's.
    fn from(e: FirmwareError) -> CommandError {
        match e {
            FirmwareError::Bus(e) => CommandError::Library(e),
            e => CommandError::Firmware(e),
        }
    }
}

impl From<crate::sim::serve::ServeError> for CommandError {
    /// `canctl sim`'s failure is the library's; what it cannot serve, a usage error.
    fn from(e: crate::sim::serve::ServeError) -> CommandError {
        match e {
            crate::sim::serve::ServeError::Failed(e) => CommandError::Library(e),
            refused => CommandError::Usage(UsageError::CannotServe(refused)),
        }
    }
}

impl From<Shortfall> for CommandError {
    fn from(s: Shortfall) -> CommandError {
        match s {
            Shortfall::Failed(e) => CommandError::Library(e),
            Shortfall::Unmet(u) => CommandError::Unmet(u),
            Shortfall::OnBuses { bus, worst, failed, total } => {
                CommandError::OnBuses { bus, class: worst.class(), failed, total }
            }
        }
    }
}

impl From<Explained> for CommandError {
    fn from(x: Explained) -> CommandError {
        CommandError::Explained(Box::new(x))
    }
}

impl CommandError {
    /// How the process ends for it (DESIGN.md's exit codes).
    pub fn class(&self) -> ErrorClass {
        match self {
            CommandError::Firmware(e) => e.class(),
            CommandError::Unmet(u) => u.class(),
            CommandError::OnBuses { class, .. } => *class,
            CommandError::Usage(_) => ErrorClass::Usage,
            CommandError::Output(_) => ErrorClass::Output,
            CommandError::Library(e) | CommandError::FrameLog(e) => e.class(),
            CommandError::Explained(x) => x.error.class(),
        }
    }

    /// The process exit code, and whether to say why: a reader that went away (`canctl scan |
    /// head -1`) ends it quietly, with 0.
    pub fn exit_code(&self) -> (i32, bool) {
        match self {
            CommandError::Output(io) if io.kind() == std::io::ErrorKind::BrokenPipe => (0, false),
            e => (e.class().exit_code(), true),
        }
    }

    /// The library's error it is or carries.
    pub fn library(&self) -> Option<&crate::Error> {
        match self {
            CommandError::Library(e) | CommandError::FrameLog(e) => Some(e),
            CommandError::Explained(x) => Some(&x.error),
            CommandError::Firmware(_)
            | CommandError::Unmet(_)
            | CommandError::OnBuses { .. }
            | CommandError::Usage(_)
            | CommandError::Output(_) => None,
        }
    }

    /// As canctl prints it: the message, then its remedy in canctl's terms, then what was
    /// learnt about it.
    pub fn text(&self) -> String {
        match self {
            CommandError::Library(e) => library_error_text(e),
            CommandError::Firmware(e) => super::firmware::firmware_error_text(e),
            CommandError::Explained(x) => format!("{}{}", library_error_text(&x.error), x.advice),
            CommandError::FrameLog(e) => format!("--log-frames: {}", library_error_text(e)),
            CommandError::Unmet(_)
            | CommandError::OnBuses { .. }
            | CommandError::Usage(_)
            | CommandError::Output(_) => self.to_string(),
        }
    }

    /// As `--format json` gives it, for a node that did not answer (exit 3) and a link's
    /// failure (exit 5): `{"error", "exit_code", "diagnosis"}`, the diagnosis the likely cause
    /// (a finding as `canctl doctor` gives it; null when there is none, or with
    /// --no-diagnose). `None` for every other error: its message alone.
    pub fn json(&self) -> Option<serde_json::Value> {
        let code = self.class().exit_code();
        let finding = match self {
            CommandError::Explained(x) => x.finding.as_ref(),
            _ => None,
        };
        let diagnosis = match (finding, self.library().map(crate::Error::root)) {
            (Some(finding), _) => Some(super::doctor::finding_json(finding)),
            (None, Some(crate::Error::Link(link))) => {
                Some(super::doctor::finding_json(&crate::ops::doctor::link_finding(link)))
            }
            // Nothing answered: no finding to give (the worst of several buses included).
            (None, Some(_)) if code == ErrorClass::Timeout.exit_code() => None,
            (None, None) if matches!(self, CommandError::OnBuses { class: ErrorClass::Timeout, .. }) => None,
            _ => return None,
        };
        Some(serde_json::json!({ "error": self.text(), "exit_code": code, "diagnosis": diagnosis }))
    }
}

/// `error` with what [`crate::ops::explain::explain`] learned said in its hint: the link's
/// failure instead of it, the likely cause of a node's silence (which rides along for
/// `--format json`'s `diagnosis`) and the nodes the last scan saw, or the objects near a
/// missing one.
pub(crate) fn explained(
    error: crate::Error,
    explanation: crate::ops::explain::Explanation,
    dicts: &crate::ops::dictionaries::Dictionaries,
) -> CommandError {
    use crate::ops::explain::Explanation;
    match explanation {
        Explanation::Link(link) => link.into(),
        Explanation::Interrupted => crate::Error::DiagnosisInterrupted { error: Box::new(error) }.into(),
        Explanation::Silent { bus, finding, last_scan } => {
            let cause = finding.as_ref().map(super::doctor::likely_cause_text).unwrap_or_default();
            Explained { error, advice: cause + &super::hints::last_scan_hint(&bus, &last_scan), finding }.into()
        }
        Explanation::Near { node, near } => {
            let near = near.into_iter().map(|a| dicts.label(node, a)).collect();
            error.advised(crate::error::Advice::Near(near)).into()
        }
    }
}
