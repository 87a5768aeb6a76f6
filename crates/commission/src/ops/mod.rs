//! The commissioning procedures, as functions over a [`Bus`](crate::bus::Bus): each takes
//! what the user asked for, talks to the devices, and returns a typed report (serialisable,
//! so that any front end can render it). Progress and remarks go through [`Progress`]; a
//! procedure never prints and knows nothing of the command line.

pub use event::{Event, Notice, Warning};
pub use stop::{install_interrupt_plan, InterruptPoint};

pub mod answers_elsewhere;
pub(crate) mod back;
pub mod buses;
pub mod check;
pub mod clash;
pub mod completion;
pub mod config;
pub mod counted;
pub mod dictionaries;
pub mod doctor;
pub mod drive;
pub mod errors;
pub(crate) mod event;
pub mod explain;
pub mod failure;
pub mod firmware;
pub mod health;
pub(crate) mod in_parallel;
pub mod lss;
pub mod many_buses;
pub mod monitor;
pub(crate) mod near;
pub mod network;
pub mod nmt;
pub mod node;
pub mod pdo;
pub mod project_files;
pub mod scan;
pub mod scan_cache;
pub mod sdo;
pub mod silence;
pub mod stop;
pub mod store;
pub mod store_all;
pub mod stored_eds;
pub mod stream_setup;
pub(crate) mod unheard;
pub mod unmet;
pub mod verdict;

use crate::bus::SdoOptions;
use crate::canopen::DataType;
use crate::error::{Error, Result};
use crate::od::Entry;
use std::time::Duration;

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
    Firmware(firmware::Step),
}

/// How an item of a phase ended ([`Progress::item_ended`]), typed for the caller to word.
#[derive(Debug, Clone, Copy)]
pub enum ItemEnd<'a> {
    /// A node of a network project brought to its DCF, or not: its row as it stands then
    /// (before any reset, and before the node-id given over LSS is set on it).
    Applied(&'a network::NodeApplied),
    /// A node of a network project checked: its checks, or the error that ended them.
    Checked(&'a Result<network::NodeCheck>),
    /// A node's firmware download.
    Downloaded(firmware::DownloadEnd),
}

/// Progress nobody watches.
pub struct Silent;

impl Progress for Silent {}

/// SDO options for a value of a known size: an upload that brings more than a number can
/// hold is stopped at [`NUMBER_LIMIT`] (or the size, if larger), not after 1 MiB.
pub(crate) fn sized(timeout: Duration, size: Option<usize>) -> SdoOptions {
    let o = SdoOptions { size_hint: size, ..SdoOptions::new(timeout) };
    SdoOptions { max_upload: size.map_or(o.max_upload, |size| size.max(NUMBER_LIMIT)), ..o }
}

/// SDO options for reads of at most `limit` bytes.
pub(crate) fn capped(timeout: Duration, limit: usize) -> SdoOptions {
    SdoOptions { max_upload: limit, ..SdoOptions::new(timeout) }
}

/// The most a number may bring: no CiA 301 basic type is longer than 8 bytes. A device that
/// answers a number with an upload that goes on and on is stopped at its second segment.
pub(crate) const NUMBER_LIMIT: usize = 8;

/// The most a device's name or version (0x1008..0x100A) may bring where a command reads it
/// from every node (scan, health, doctor, errors): a few dozen bytes in practice. A device
/// that sends one without end is stopped here, and that is its finding, not a wait that
/// stretches the whole command.
pub(crate) const NAME_LIMIT: usize = 255;

/// The most an upload of a small value may bring by default: a string or an octet string
/// (a device name, a version) is a few dozen bytes, so one that runs on without end (no
/// size announced, segment after segment) is stopped here, seconds into it at 125 kbit/s,
/// not minutes.
pub(crate) const SMALL_UPLOAD: usize = 64 * 1024;

/// How many bytes an upload of a `dtype` value may bring unless the user says more
/// (`sdo read --max-size`): a domain, or a value of unknown type (it may be one), up to
/// the SDO client's 1 MiB; a number, [`NUMBER_LIMIT`]; a string, [`SMALL_UPLOAD`].
pub(crate) fn upload_limit(dtype: Option<DataType>) -> usize {
    match dtype {
        None | Some(DataType::D) => crate::canopen::sdo::client::DEFAULT_MAX_UPLOAD,
        Some(t) => t.size().map_or(SMALL_UPLOAD, |size| size.max(NUMBER_LIMIT)),
    }
}

/// A little-endian u32 from the first bytes of an answer (0 when it is shorter).
pub(crate) fn le_u32(bytes: &[u8]) -> u32 {
    u32::from_le_bytes(bytes.get(..4).and_then(|b| b.try_into().ok()).unwrap_or([0; 4]))
}

/// A value beyond the dictionary's limits is refused before it is sent.
pub(crate) fn check_range(entry: &Entry, bytes: &[u8]) -> Result<()> {
    let Some(crate::od::OutsideLimits { value, low, high, .. }) = entry.outside_limits(bytes) else { return Ok(()) };
    let (object, value, dictionary) = (entry.addr, value.to_string(), "from the dictionary".into());
    Err(Error::OutOfRange { object, value, low, high, dictionary })
}

/// Serialise a value by its `Display` (object addresses as `0x1010:1`).
pub(crate) fn as_text<T: std::fmt::Display, S: serde::Serializer>(v: &T, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(v)
}
