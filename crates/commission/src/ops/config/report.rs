//! What a run of `config apply` did to each object and left on the device, and where a
//! node differs from a DCF: the report types, for the front end to word.

use crate::canopen::{abort, ObjAddr};
use crate::ops::failure::Failure;
use crate::ops::values::as_text;
use serde::Serialize;

/// What a run that did not finish left the device holding.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LeftIn {
    /// Interrupted while reading the device: nothing was written.
    Unread {
        /// The node.
        node: u8,
    },
    /// Stopped, or failed, among the writes.
    Written {
        /// The node.
        node: u8,
        /// The objects that hold the file's values now, in order.
        new: Vec<ObjAddr>,
        /// How many objects the file changes.
        of: usize,
        /// A value neither the old nor the file's is left behind (a COB-ID made invalid,
        /// a mapping count of 0).
        interim: bool,
        /// The PDO whose change was under way was put back.
        rolled_back: bool,
        /// Putting that PDO back failed ([`super::Applied::to_fix`] says how to finish it).
        rollback_failed: bool,
        /// Storing was asked for, and so nothing was stored: a reset brings back the stored
        /// parameters.
        store_asked: bool,
    },
}

/// A write that would bring an object back to its value before the run.
#[derive(Debug, Clone, Serialize)]
#[non_exhaustive]
pub struct Fix {
    /// The object to write.
    #[serde(serialize_with = "as_text")]
    pub object: ObjAddr,
    /// The value it had before the run, as a DCF writes it; `None` when unknown.
    pub value: Option<String>,
}

/// One object: its value before, the value wanted, and what happened.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Change {
    /// The object.
    #[serde(serialize_with = "as_text")]
    pub object: ObjAddr,
    /// Its name in the file.
    pub name: String,
    /// The device's value before, formatted (or why it has none).
    pub old: String,
    /// The file's value, formatted.
    pub new: String,
    /// What happened to it; serialised as its sentence (`written, verified`).
    #[serde(serialize_with = "as_text")]
    pub result: Outcome,
}

/// What a run did, or would do, with one object.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Action {
    /// Written.
    Written,
    /// The write failed with this error (its remedy typed, for the front end to word).
    Failed(Failure),
    /// Not written: an earlier write failed.
    NotWritten,
    /// Not written: the user stopped the run first.
    NotWrittenInterrupted,
    /// A dry run would write it.
    WouldWrite,
    /// A dry run would not get this far: an earlier write would fail.
    WouldNotBeWritten,
    /// A dry run: the device would refuse it with this abort code.
    WouldBeRefused(u32),
    /// A dry run: the object is read-only in the dictionary named.
    WouldBeRefusedReadOnly(String),
    /// The device does not have the object (abort code), and it is not writable anyway.
    NotOnDevice(u32),
    /// The file's value differs from the device's, but the device's object cannot be
    /// written (its access type, such as `ro`).
    ReadOnlyOnDevice(&'static str),
}

/// The read-back of a written value.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum ReadBack {
    /// It reads back as written.
    Verified,
    /// It reads back as this other value.
    Differs(String),
}

/// What happened to one object of a run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Outcome {
    /// The write.
    pub action: Action,
    /// Why this write is a step on the way (a PDO's COB-ID made invalid first); `None` for
    /// the write of the value the file holds.
    pub interim: Option<&'static str>,
    /// A write that puts a PDO back after a change of it failed half-way.
    pub rollback: bool,
    /// The read-back, when one was made.
    pub read_back: Option<ReadBack>,
}

impl Outcome {
    pub(super) fn new(action: Action) -> Outcome {
        Outcome { action, interim: None, rollback: false, read_back: None }
    }

    /// The write of the file's own value (not a step on the way, not a rollback), which is
    /// what a verification reads back.
    pub(super) fn is_final(&self) -> bool {
        !self.rollback
            && self.interim.is_none()
            && !matches!(self.action, Action::NotOnDevice(_) | Action::NotWrittenInterrupted)
    }

    /// The outcome in words, a failed write's error worded by `failure` (a front end adds
    /// its remedy).
    pub fn text(&self, failure: impl Fn(&Failure) -> String) -> String {
        let mut text = match &self.action {
            Action::Written => "written".to_string(),
            Action::Failed(e) => format!("failed: {}", failure(e)),
            Action::NotWritten => "not written".to_string(),
            Action::NotWrittenInterrupted => "not written (interrupted)".to_string(),
            Action::WouldWrite => "would write".to_string(),
            Action::WouldNotBeWritten => "would not be written".to_string(),
            Action::WouldBeRefused(code) => format!("would be refused: {}", abort::meaning(*code)),
            Action::WouldBeRefusedReadOnly(source) => format!("would be refused: read only in {source}"),
            Action::NotOnDevice(code) => format!("not on the device ({})", abort::meaning(*code)),
            Action::ReadOnlyOnDevice(access) => format!("{access} on the device: not written"),
        };
        if self.rollback {
            text.push_str(" (rollback)");
        }
        if let Some(interim) = &self.interim {
            text.push_str(&format!(" ({interim})"));
        }
        match &self.read_back {
            Some(ReadBack::Verified) => text.push_str(", verified"),
            Some(ReadBack::Differs(got)) => text.push_str(&format!(", reads back {got}")),
            None => {}
        }
        text
    }
}

/// The outcome in words, a failed write's error by its message.
impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text(|e| e.to_string()))
    }
}

/// What a run that did not finish left ([`super::Applied::incomplete`]), for the front end to word.
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub struct Incomplete {
    /// Stopped between two writes of those planned: what was written and what not.
    pub cut: Option<CutWrites>,
    /// PDOs whose change was under way, put back to their previous mapping and COB-ID
    /// (as [`super::Applied::rolled_back`] names them).
    pub rolled_back: Vec<String>,
    /// When putting a PDO back failed: the writes that would, in this order.
    pub to_fix: Vec<Fix>,
    /// What the device holds now ([`super::Applied::state`]).
    pub state: Option<LeftIn>,
}

/// The writes of a run stopped between two of them.
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub struct CutWrites {
    /// What was written, in order.
    pub written: Vec<ObjAddr>,
    /// What was planned and not written, in order.
    pub not_written: Vec<ObjAddr>,
}

/// One object whose value on the device is not the file's.
#[derive(Debug, Serialize)]
pub struct Difference {
    /// The object.
    #[serde(serialize_with = "as_text")]
    pub object: ObjAddr,
    /// Its name in the file.
    pub name: String,
    /// The device's value, or why it has none.
    pub device: String,
    /// The file's value, as the file writes it.
    pub file: String,
}
