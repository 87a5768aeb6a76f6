//! What `network apply` and `network check` tell of each node: the rows a progress display
//! is given as each node ends, and the reports hold.

use crate::ops::config::report::{Change, Incomplete};
use crate::ops::verdict::Verdict;
use serde::Serialize;

/// What applying its DCF did to one node.
#[derive(Debug, Default, Serialize)]
pub struct NodeApplied {
    /// The node-id.
    pub node: u8,
    /// Its name (`NodeXName`, else the DCF's product name, else empty).
    pub name: String,
    /// Its DCF, as the project names it; none when it names none.
    pub file: Option<String>,
    /// The LSS identity the node was given its node-id by (or, in a dry run, would be
    /// looked for by), when it was asked for.
    pub assigned: Option<String>,
    /// Objects written (PDO sequence steps included).
    pub written: usize,
    /// Its parameters were stored (0x1010:1).
    pub stored: bool,
    /// What happened, for the front end to word (the JSON of canctl carries its sentence
    /// here, with the node-id given over LSS and the reset).
    pub result: NodeResult,
    /// After it was written to, the node was reset: whether it was back (booted) within
    /// the boot wait; `None` when it was not reset.
    #[serde(skip)]
    pub reset: Option<bool>,
    /// The failure the result tells, typed: its message and remedy for the front end to word.
    #[serde(skip)]
    pub failure: Option<crate::ops::failure::Failure>,
    /// What happened, in one word: the summary counts these, as the table shows them.
    pub outcome: Outcome,
    /// The node now matches its DCF.
    pub ok: bool,
    /// Each object written or not, as `config apply` reports it.
    pub objects: Vec<Change>,
}

/// What happened to one node: its DCF applied or not, and how far. Whether its node-id was
/// given over LSS first is [`NodeApplied::assigned`]; a reset after, [`NodeApplied::reset`].
#[derive(Debug, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum NodeResult {
    /// It answers, but the project names no DCF for it: nothing to apply.
    NoDcf,
    /// A dry run: `count` objects would be written (0: it is up to date).
    WouldWrite {
        /// Objects that would be written.
        count: usize,
    },
    /// Brought to its DCF: `count` objects written (0: it was up to date already).
    Written {
        /// Objects written (PDO sequence steps included).
        count: usize,
        /// Each was read back as written.
        verified: bool,
        /// Its parameters were stored (0x1010:1).
        stored: bool,
    },
    /// Failed: [`NodeApplied::failure`] says how.
    #[default]
    Failed,
    /// The user stopped it at a point between two transfers.
    Interrupted {
        /// What was written, what not, what was put back, and the state it is left in.
        #[serde(skip)]
        incomplete: Incomplete,
        /// Objects were written and storing was asked for, but they were not stored.
        not_stored: bool,
    },
    /// The user stopped the run after its objects were written, before they were stored.
    StoppedBeforeStore {
        /// Objects written.
        written: usize,
        /// Each was read back as written.
        verified: bool,
    },
    /// A dry run: it does not answer, and would be looked for over LSS by the identity in
    /// [`NodeApplied::assigned`] and given its node-id.
    WouldAssign,
    /// Given its node-id over LSS, then not configured: the run ended before this node was
    /// begun.
    NotConfigured {
        /// The user stopped the run; else the link was lost.
        interrupted: bool,
    },
    /// Not begun: the user stopped the run first.
    NotBegun,
}

/// Where a node's apply ended.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Outcome {
    /// Brought to its DCF (or, in a dry run, found what would be written).
    Done,
    /// Failed; the result says why.
    #[default]
    Failed,
    /// Stopped by the user after something was written (or a PDO change rolled back).
    StoppedPartWay,
    /// Stopped by the user before anything was written: the node is as it was.
    StoppedUnchanged,
    /// Not begun: the user stopped the run first (its node-id may have been given).
    NotBegun,
}

/// One listed node and its checks.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct NodeCheck {
    /// The node-id.
    pub node: u8,
    /// Its name (`NodeXName`, else the DCF's product name, else empty).
    pub name: String,
    /// Its DCF, as the project names it; none when it names none.
    pub file: Option<String>,
    /// Each check and its verdict.
    pub checks: Vec<Verdict>,
}
