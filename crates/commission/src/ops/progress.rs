//! How a procedure tells its caller what it does while it runs: [`Progress`], the typed
//! states and ends of the items of a phase, and [`Silent`], progress nobody watches.

use super::event::Event;
use super::firmware::step::{DownloadEnd, Step};
use super::network::report::{NodeApplied, NodeCheck};
use crate::error::Result;

/// What a long procedure tells its caller while it runs, the one observer of a procedure:
/// phases and steps, items under way at once, and typed [`Event`]s (warnings and notices).
/// The CLI shows a progress bar and words the events on stderr, a test records the calls,
/// a program may ignore them ([`Silent`]).
pub trait Progress {
    /// A phase of `len` steps begins.
    fn start(&mut self, _what: &str, _len: u64) {}
    /// `done` steps of the phase are finished.
    fn advance(&mut self, _done: u64) {}
    /// The phase is over.
    fn finish(&mut self) {}
    /// A warning or notice, for the caller to word (or record, or ignore).
    fn event(&mut self, _event: Event) {}
    /// One of several items of the phase under way at once (a node configured alongside
    /// others) moved on: `status` says where it is, for the caller to word.
    fn item(&mut self, _item: &str, _status: ItemStatus) {}
    /// One of those items ended: `end` says how, for the caller to word.
    fn item_ended(&mut self, _item: &str, _end: ItemEnd<'_>) {}
    /// A phase that is one transfer begins, of `len` bytes when known: the hook the SDO
    /// client tells the bytes moved so far as segments and blocks come, when anyone watches
    /// (`None`: nobody does). The phase ends with [`finish`](Progress::finish).
    fn transfer(&mut self, _what: &str, _len: Option<u64>) -> Option<crate::bus::TransferHook> {
        None
    }
}

/// Where an item of a phase is ([`Progress::item`]), typed for the caller to word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ItemStatus {
    /// Begun; nothing to count yet.
    Begun,
    /// The SDO transfers its work has made so far.
    Transfers {
        /// Reads (uploads).
        reads: u32,
        /// Writes (downloads).
        writes: u32,
    },
    /// The `number`th of `of` items done one after the other.
    Step {
        /// Its place, from 1.
        number: usize,
        /// How many there are.
        of: usize,
    },
    /// A firmware download's step just done (shown as it happens, not only at the end).
    Firmware(Step),
}

/// How an item of a phase ended ([`Progress::item_ended`]), typed for the caller to word.
#[derive(Debug, Clone, Copy)]
pub enum ItemEnd<'a> {
    /// A node of a network project brought to its DCF, or not: its row as it stands then
    /// (before any reset, and before the node-id given over LSS is set on it).
    Applied(&'a NodeApplied),
    /// A node of a network project checked: its checks, or the error that ended them.
    Checked(&'a Result<NodeCheck>),
    /// A node's firmware download.
    Downloaded(DownloadEnd),
}

/// Progress nobody watches.
pub struct Silent;

impl Progress for Silent {}
