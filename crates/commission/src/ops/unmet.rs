//! Verdicts: a command did its work and found the bus or a device not as asked (a node
//! unhealthy, a network not as its project says). Not errors: nothing failed, the report
//! says what was found. [`Unmet`] says it in a line and ends the run with exit 6 (DESIGN.md),
//! and [`Shortfall`] is how a run that may also fail ends: a failure, a verdict, or the worst
//! of several buses'.

use crate::error::{Error, ErrorClass};
use std::fmt;

/// What a command found not as asked, in a line; its report holds the whole of it.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
// Exhaustive on purpose: canctl words every variant.
pub enum Unmet {
    /// A node's objects differ from a configuration file.
    #[error("node {node} differs from {file} in {count} object(s)")]
    Differs {
        /// The node-id.
        node: u8,
        /// The configuration file, as named.
        file: String,
        /// How many objects differ.
        count: usize,
    },
    /// A bus is not as its network project says.
    #[error("{bus} is not as {project} says: {}", join(differences, ", "))]
    NetworkDiffers {
        /// The bus, as its address reads.
        bus: String,
        /// The network project file, as named.
        project: String,
        /// What differs.
        differences: Vec<NetworkDifference>,
    },
    /// Nodes that answered before a network-wide bit-rate switch do not answer at the new
    /// rate.
    #[error("node(s) {} did not follow the switch to {rate}: they do not answer at the new rate", join(nodes, ", "))]
    NotFollowed {
        /// The new bit rate, by name (`250k`, ...).
        rate: String,
        /// The node-ids that do not answer at it.
        nodes: Vec<u8>,
    },
    /// Nodes on a bus are not healthy: each with the checks it failed.
    #[error("{bus}: {} of {total} node(s) not healthy: {}", nodes.len(), join(nodes, "; "))]
    Unhealthy {
        /// The bus, as its address reads.
        bus: String,
        /// How many nodes were checked.
        total: usize,
        /// Each node not healthy.
        nodes: Vec<NotHealthy>,
    },
    /// `doctor` found problems on a bus (its report lists them, most likely cause first).
    #[error("{bus}: {count} problem(s) found, most likely cause first in the report")]
    Diagnosed {
        /// The bus examined.
        bus: String,
        /// How many problems it found.
        count: usize,
    },
}

impl Unmet {
    /// How the process ends for it: a verification failure (exit 6).
    pub fn class(&self) -> ErrorClass {
        ErrorClass::Verify
    }

    /// The bus the message begins with, if it names one.
    pub fn names_bus(&self) -> Option<&str> {
        match self {
            Unmet::NetworkDiffers { bus, .. } | Unmet::Unhealthy { bus, .. } | Unmet::Diagnosed { bus, .. } => {
                Some(bus)
            }
            Unmet::Differs { .. } | Unmet::NotFollowed { .. } => None,
        }
    }
}

/// One way a bus differs from its network project.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NetworkDifference {
    /// Checks of the project's nodes failed (`network check`): how many.
    ChecksFailed(usize),
    /// Nodes on the bus that the project does not list: how many.
    NotInProject(usize),
    /// The nodes that answer but are not in the project (`network apply`).
    AnswerNotInProject(Vec<u8>),
}

impl fmt::Display for NetworkDifference {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NetworkDifference::ChecksFailed(n) => write!(f, "{n} node check(s) failed"),
            NetworkDifference::NotInProject(n) => write!(f, "{n} node(s) not in the project"),
            NetworkDifference::AnswerNotInProject(nodes) => {
                write!(f, "node(s) {} answer but are not in the project", join(nodes, ", "))
            }
        }
    }
}

/// A node a health check found not healthy: which, and the checks it failed (by their
/// names, as the report's columns read: `nmt`, `error register`, ...).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NotHealthy {
    /// The node-id.
    pub node: u8,
    /// The checks it failed.
    pub failed: Vec<&'static str>,
}

impl fmt::Display for NotHealthy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "node {}: {}", self.node, self.failed.join(", "))
    }
}

/// How a run ended short of "done, as asked".
#[derive(Debug)]
pub enum Shortfall {
    /// Something failed (the library's error).
    Failed(Error),
    /// The work was done, and what it found is not as asked.
    Unmet(Unmet),
    /// Several buses were worked and some fell short: the worst of them, on `bus`, decides
    /// the class; the report shows every bus's.
    OnBuses {
        /// The bus of the worst, as its URI.
        bus: String,
        /// The worst shortfall.
        worst: Box<Shortfall>,
        /// How many buses fell short.
        failed: usize,
        /// How many buses were worked.
        total: usize,
    },
}

impl Shortfall {
    /// How the process ends for it.
    pub fn class(&self) -> ErrorClass {
        match self {
            Shortfall::Failed(e) => e.class(),
            Shortfall::Unmet(u) => u.class(),
            Shortfall::OnBuses { worst, .. } => worst.class(),
        }
    }

    /// The process exit code for it.
    pub fn exit_code(&self) -> i32 {
        self.class().exit_code()
    }

    /// The user asked to stop (exit 130).
    pub fn is_interrupted(&self) -> bool {
        self.class() == ErrorClass::Interrupted
    }
}

impl From<Error> for Shortfall {
    fn from(e: Error) -> Shortfall {
        Shortfall::Failed(e)
    }
}

impl From<Unmet> for Shortfall {
    fn from(u: Unmet) -> Shortfall {
        Shortfall::Unmet(u)
    }
}

fn join<T: fmt::Display>(items: &[T], separator: &str) -> String {
    items.iter().map(ToString::to_string).collect::<Vec<_>>().join(separator)
}
