//! What a command's failure is explained with before it is shown: a node that did not
//! answer gets the link's own failure, the likely cause of its silence and the nodes the last
//! scan saw; an object the node does not have, the dictionary's objects near it that it has.

use super::dictionaries::Dictionaries;
use super::doctor::{self, Finding};
use super::scan_cache::{self, SeenNode};
use crate::bus::Bus;
use crate::canopen::abort::{NO_OBJECT, NO_SUBINDEX};
use crate::canopen::ObjAddr;
use crate::error::{Error, Service};
use std::time::Duration;

/// The longest each wait of the quick checks after a silent node may be: with the read of
/// every node-id, a second or so in all.
const QUICK_WAIT: Duration = Duration::from_millis(500);

/// What was learned about a failure, to be said with it.
pub enum Explanation {
    /// The link failed: its error replaces the node's silence (an adapter at another bit
    /// rate, say), so that every command ends as `sdo read` does.
    Link(Error),
    /// A node did not answer: the likely cause the quick checks found (when asked for and
    /// found), and the nodes the last scan of the bus saw.
    Silent {
        /// The bus's URI, as the scan cache knows it.
        bus: String,
        /// What the quick checks found ([`doctor::quick`]).
        finding: Option<Finding>,
        /// The nodes the last scan of the bus saw.
        last_scan: Vec<SeenNode>,
    },
    /// An object the node does not have: the dictionary's objects nearest to it that the node
    /// has (`near::present_near`); never empty.
    Near {
        /// The node asked.
        node: u8,
        /// The objects it has.
        near: Vec<ObjAddr>,
    },
    /// The user asked to stop while the quick checks looked for the cause.
    Interrupted,
}

/// How [`explain`] may look: the bus in force, the dictionaries, whether a silent node is
/// diagnosed (two waits of at most half a second), the answer timeout.
pub struct ExplainOptions<'a> {
    /// The bus's URI, for the scan cache; without it a silent node is not explained.
    pub bus: Option<&'a str>,
    /// The dictionaries the objects near a missing one come from.
    pub dicts: &'a Dictionaries,
    /// Whether a silent node is diagnosed (not `--no-diagnose`).
    pub diagnose: bool,
    /// The answer timeout in force (each quick check waits at most half a second of it).
    pub timeout: Duration,
}

/// What to add to `error`, learned on `bus`; `None` when nothing is to be said.
pub fn explain(bus: &mut dyn Bus, error: &Error, o: &ExplainOptions) -> Option<Explanation> {
    match (error, o.bus) {
        // Every request of a node's own that went unanswered: an SDO transfer, its state
        // (node guarding), its boot-up after a reset.
        (
            Error::NoAnswer {
                node,
                what:
                    Service::Sdo(_)
                    | Service::SdoRetried { .. }
                    | Service::NmtState { .. }
                    | Service::AfterReset
                    | Service::BootUp,
                ..
            },
            Some(uri),
        )
        | (Error::Epos2NoCanAnswer { node, .. }, Some(uri)) => {
            if let Err(link) = super::unheard::check(bus) {
                return Some(Explanation::Link(link));
            }
            let last_scan = scan_cache::load(uri);
            let seen: Vec<u8> = last_scan.iter().map(|n| n.node).collect();
            let quick = o.diagnose.then(|| doctor::quick(bus, *node, &seen, o.timeout.min(QUICK_WAIT)));
            let finding = match quick {
                Some(Err(e)) if e.is_interrupted() => return Some(Explanation::Interrupted),
                found => found.and_then(|found| found.ok().flatten()),
            };
            Some(Explanation::Silent { bus: uri.to_string(), finding, last_scan })
        }
        (Error::SdoAbort { node, obj, code: code @ (NO_OBJECT | NO_SUBINDEX) }, _) => {
            let near = super::near::present_near(bus, o.dicts, *node, *obj, *code == NO_OBJECT, o.timeout);
            (!near.is_empty()).then_some(Explanation::Near { node: *node, near })
        }
        _ => None,
    }
}
