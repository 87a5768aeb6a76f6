//! One node on a bus, as the operations see it: typed reads of its objects, objects it may
//! lack, its identity (0x1018), its NMT state and its error history (0x1003). Each of these
//! is learnt here and nowhere else, so that every command reads them the same way.

use super::sdo_options::sized;
use crate::bus::Bus;
use crate::canopen::emcy::{self, HistoryEntry, Origin, Source};
use crate::canopen::lss;
use crate::canopen::nmt::{self, ErrorControl};
use crate::canopen::{abort, ObjAddr};
use crate::error::{Error, Result};
use serde::Serialize;
use std::time::Duration;

/// The pre-defined error field (CiA 301 §7.5.2.5): sub 0 counts, sub 1 is the newest.
const ERROR_FIELD: u16 = 0x1003;
/// Its sub 0: how many errors are logged (writing 0 clears them).
pub(crate) const HISTORY_COUNT: ObjAddr = ObjAddr::new(ERROR_FIELD, 0);

/// Whether an error says the object (or its subindex) is not in the device's dictionary:
/// abort 0x06020000 or 0x06090011. The one test of "object missing".
pub(crate) fn is_missing(e: &Error) -> bool {
    lacks_index(e) || matches!(e.root(), Error::SdoAbort { code: abort::NO_SUBINDEX, .. })
}

/// Whether an error says the device has no object at that index at all (abort 0x06020000),
/// where a missing subindex would say the object is there.
pub(crate) fn lacks_index(e: &Error) -> bool {
    matches!(e.root(), Error::SdoAbort { code: abort::NO_OBJECT, .. })
}

/// A read of an object the device may lack: `Ok(None)` when it lacks it ([`is_missing`]),
/// other failures stay failures.
pub(crate) fn optional<T>(r: Result<T>) -> Result<Option<T>> {
    match r {
        Ok(v) => Ok(Some(v)),
        Err(e) if is_missing(&e) => Ok(None),
        Err(e) => Err(e),
    }
}

/// The first `size` bytes (at most 4) as a little-endian unsigned value, missing ones as 0.
fn le_unsigned(bytes: &[u8], size: usize) -> u32 {
    bytes.iter().take(size).rev().fold(0, |v, b| v << 8 | u32::from(*b))
}

/// One node of a bus, reached by SDO with one timeout.
pub struct Node<'a> {
    bus: &'a mut dyn Bus,
    id: u8,
    timeout: Duration,
}

impl<'a> Node<'a> {
    /// Node `id` on `bus`; each SDO exchange waits up to `timeout` for an answer.
    pub fn new(bus: &'a mut dyn Bus, id: u8, timeout: Duration) -> Node<'a> {
        Node { bus, id, timeout }
    }

    /// An unsigned object (`u8`, `u16`, `u32`), little-endian as CANopen sends it; its size
    /// the size hint of the read. Missing bytes read as 0: a device that sends fewer than
    /// the type has is taken as zero-extended, as the SDO client does.
    pub fn read<T: TryFrom<u32>>(&mut self, addr: ObjAddr) -> Result<T> {
        let size = std::mem::size_of::<T>();
        let bytes = self.bus.sdo_upload(self.id, addr, &sized(self.timeout, Some(size)))?;
        Ok(T::try_from(le_unsigned(&bytes, size)).unwrap_or_else(|_| unreachable!("{size} bytes fit the type")))
    }

    /// An unsigned object the device may lack ([`optional`]).
    pub(crate) fn read_optional<T: TryFrom<u32>>(&mut self, addr: ObjAddr) -> Result<Option<T>> {
        optional(self.read(addr))
    }

    /// The identity object 0x1018; `None` when the device lacks its vendor-ID (0x1018:1,
    /// which CiA 301 makes mandatory).
    pub fn identity(&mut self) -> Result<Option<Identity>> {
        let Some(vendor) = self.read_optional::<u32>(ObjAddr::VENDOR_ID)? else { return Ok(None) };
        self.identity_of(vendor).map(Some)
    }

    /// The rest of the identity object, its vendor-ID (0x1018:1) read already.
    pub(crate) fn identity_of(&mut self, vendor: u32) -> Result<Identity> {
        let mut part = |addr| self.read_optional::<u32>(addr);
        let (product, revision) = (part(ObjAddr::PRODUCT_CODE)?, part(ObjAddr::REVISION_NUMBER)?);
        Ok(Identity { vendor, product, revision, serial: part(ObjAddr::SERIAL_NUMBER)? })
    }

    /// The vendor-ID and product code a file names, against the device's: each one the file
    /// names (not 0), read and compared as numbers.
    pub(crate) fn compare_identity(&mut self, vendor: u32, product: u32) -> Result<Vec<IdentityPart>> {
        let mut parts = Vec::new();
        let named = [(IdPart::Vendor, vendor, ObjAddr::VENDOR_ID), (IdPart::Product, product, ObjAddr::PRODUCT_CODE)];
        for (what, want, addr) in named.into_iter().filter(|(_, want, _)| *want != 0) {
            let device = match self.read::<u32>(addr) {
                Ok(v) => Ok(v),
                Err(Error::SdoAbort { code, .. }) => Err(code),
                Err(e) => return Err(e),
            };
            parts.push(IdentityPart { what, file: want, device });
        }
        Ok(parts)
    }

    /// The node's answer to one error-control remote request (node guarding; through an
    /// EPOS2 a RequestCANFrame), waited for up to `wait`; `None` when none came.
    pub(crate) fn guard(&mut self, wait: Duration) -> Result<Option<Guarded>> {
        Ok(self.error_control(wait)?.map(|answer| match answer {
            Some(ErrorControl::State { state, .. }) => Guarded::State(state),
            Some(ErrorControl::BootUp) => Guarded::BootUp,
            Some(ErrorControl::Unknown(_)) | None => Guarded::NotAState,
        }))
    }

    /// [`guard`](Node::guard)'s answer as it came, for what tells a state code CiA 301 does
    /// not define (`Some(Some(Unknown(code)))`) from an answer that is no error-control
    /// message at all (`Some(None)`); `None` when none came within `wait`.
    pub(crate) fn error_control(&mut self, wait: Duration) -> Result<Option<Option<ErrorControl>>> {
        match self.bus.request_frame(nmt::error_control_cob(self.id), 1, wait) {
            Ok(frame) => Ok(Some(ErrorControl::parse(&frame).map(|(_, ec)| ec))),
            Err(e) if e.is_timeout() => Ok(None),
            Err(e) => Err(e),
        }
    }

    /// The node's NMT state: from its heartbeat when one was seen on this bus, else by
    /// node guarding (waiting up to `wait`); `None` when neither tells it.
    pub fn nmt_state(&mut self, wait: Duration) -> Result<Option<(nmt::State, StateFrom)>> {
        if let Some(s) = self.bus.observed().states.get(&self.id) {
            return Ok(Some((*s, StateFrom::Heartbeat)));
        }
        let answer = self.guard(wait)?;
        Ok(answer.and_then(|g| Some((g.state()?, StateFrom::guarding(g, &*self.bus)))))
    }

    /// The error history 0x1003, newest first, each code with its meaning for a device of
    /// `origin`; `None` when the node keeps none (has no 0x1003).
    pub(crate) fn error_history(&mut self, origin: &Origin) -> Result<Option<ErrorField>> {
        let Some(count) = self.read_optional::<u8>(HISTORY_COUNT)? else { return Ok(None) };
        self.error_entries(count, origin).map(Some)
    }

    /// The `count` entries of 0x1003 (0x1003:0 read by the caller), all asked at once.
    pub(crate) fn error_entries(&mut self, count: u8, origin: &Origin) -> Result<ErrorField> {
        // CiA 301: at most 254 entries.
        let subs: Vec<(u8, ObjAddr)> = (1..=count.min(254)).map(|s| (self.id, ObjAddr::new(ERROR_FIELD, s))).collect();
        let values = self.bus.sdo_upload_many(&subs, &sized(self.timeout, Some(4)), &mut |_| {})?;
        let mut field = ErrorField { count, entries: Vec::new(), unreadable: Vec::new() };
        for ((_, addr), value) in subs.iter().zip(values) {
            match value {
                Ok(b) if b.len() >= 4 => {
                    field.entries.push(LoggedError::new(addr.sub, super::values::le_u32(&b), origin))
                }
                Ok(_) => field.unreadable.push(Unreadable { sub: addr.sub, error: "shorter than 4 bytes".into() }),
                Err(e) if e.is_timeout() => return Err(e),
                Err(e) => field.unreadable.push(Unreadable { sub: addr.sub, error: e.to_string() }),
            }
        }
        Ok(field)
    }
}

/// A node's identity object 0x1018: the vendor-ID, and the entries CiA 301 leaves optional
/// (`None` where the device has none).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[non_exhaustive]
pub struct Identity {
    /// 0x1018:1.
    pub vendor: u32,
    /// 0x1018:2.
    pub product: Option<u32>,
    /// 0x1018:3.
    pub revision: Option<u32>,
    /// 0x1018:4.
    pub serial: Option<u32>,
}

impl Identity {
    /// The LSS address (CiA 305), when the device has all four entries.
    pub fn lss(&self) -> Option<lss::Identity> {
        Some(lss::Identity {
            vendor: self.vendor,
            product: self.product?,
            revision: self.revision?,
            serial: self.serial?,
        })
    }
}

/// A part of the identity a file names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum IdPart {
    /// 0x1018:1.
    Vendor,
    /// 0x1018:2.
    Product,
}

impl std::fmt::Display for IdPart {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            IdPart::Vendor => "vendor-ID",
            IdPart::Product => "product code",
        })
    }
}

/// One part of the identity as the file names it and as the device has it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct IdentityPart {
    /// Which part.
    pub what: IdPart,
    /// The value the file names.
    pub file: u32,
    /// The device's value, or the abort code with which it refused to show it.
    pub device: std::result::Result<u32, u32>,
}

impl IdentityPart {
    /// Whether the device has the value the file names.
    pub fn matches(&self) -> bool {
        self.device == Ok(self.file)
    }

    /// The device's value in words: `0x0000001E`, or `unreadable (why)`.
    pub fn device_text(&self) -> String {
        match self.device {
            Ok(v) => format!("0x{v:08X}"),
            Err(code) => format!("unreadable ({})", abort::meaning(code)),
        }
    }
}

/// What a node's answer to node guarding says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Guarded {
    /// Its NMT state.
    State(nmt::State),
    /// A boot-up message: the node has just started, so it is pre-operational.
    BootUp,
    /// An error-control frame with a state CiA 301 does not define, or no error-control frame.
    NotAState,
}

impl Guarded {
    /// The NMT state the answer shows (a boot-up: pre-operational, CiA 301 §7.3.2).
    pub fn state(&self) -> Option<nmt::State> {
        match self {
            Guarded::State(s) => Some(*s),
            Guarded::BootUp => ErrorControl::BootUp.state(),
            Guarded::NotAState => None,
        }
    }
}

/// The error field 0x1003 as read.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ErrorField {
    /// 0x1003:0: how many errors the node says it logged.
    pub count: u8,
    /// The entries, newest (0x1003:1) first.
    pub entries: Vec<LoggedError>,
    /// Entries the node counts but would not show.
    pub unreadable: Vec<Unreadable>,
}

/// One entry of the pre-defined error field 0x1003.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[non_exhaustive]
pub struct LoggedError {
    /// The subindex of 0x1003 it was read from: 1 is the newest.
    pub sub: u8,
    /// The entry as the node sent it.
    pub raw: u32,
    /// Bits 0..15: the error code.
    #[serde(serialize_with = "hex16")]
    pub code: u16,
    /// Bits 16..31: manufacturer-specific information.
    #[serde(serialize_with = "hex16")]
    pub manufacturer: u16,
    /// What the code means ([`emcy::meaning`]).
    pub meaning: &'static str,
    /// The table the meaning comes from.
    pub source: Source,
}

impl LoggedError {
    fn new(sub: u8, raw: u32, origin: &Origin) -> LoggedError {
        let e = HistoryEntry { raw };
        let m = emcy::meaning(e.code(), e.manufacturer(), origin);
        LoggedError { sub, raw, code: e.code(), manufacturer: e.manufacturer(), meaning: m.text, source: m.source }
    }
}

/// An entry the node counts but would not show.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[non_exhaustive]
pub struct Unreadable {
    /// Its subindex of 0x1003.
    pub sub: u8,
    /// Why it could not be read.
    pub error: String,
}

/// A 16-bit code as JSON gives it: `0x1000`.
pub(crate) fn hex16<S: serde::Serializer>(v: &u16, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("0x{v:04X}"))
}

/// How a node's NMT state was learnt, or why it is not known: the one answer to "from
/// what?" for every command that shows a state (`nmt state`, scan, health, network check,
/// a stream's silence). JSON gives it as its text, as the human form does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum StateFrom {
    /// Not looked for: the scan was stopped first (its text is empty).
    #[default]
    NotAsked,
    /// The node's heartbeat.
    Heartbeat,
    /// Its answer to node guarding.
    NodeGuarding,
    /// Its answer to a remote request through the EPOS2 gateway.
    Epos2Remote,
    /// Its boot-up message.
    BootUp,
    /// Unknown: it answered the probe only after the window, and beat no heartbeat.
    LateWithoutHeartbeat,
    /// Unknown: no heartbeat heard, and this bus carries no remote frames for node guarding.
    NoRemoteFrames,
    /// Unknown: its error-control answer was not a state.
    NotAState,
    /// Unknown: neither a heartbeat (`heartbeat`: one is configured) nor an answer to node
    /// guarding came.
    Silent {
        /// Whether the node reports a heartbeat period (0x1017 not 0).
        heartbeat: bool,
    },
}

impl std::fmt::Display for StateFrom {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::NotAsked => "",
            Self::Heartbeat => "heartbeat",
            Self::NodeGuarding => "node guarding",
            Self::Epos2Remote => "remote request through the EPOS2",
            Self::BootUp => "boot-up",
            Self::LateWithoutHeartbeat => "it answered the probe only after the window, and beat no heartbeat",
            Self::NoRemoteFrames => "no heartbeat heard, and node guarding cannot go through this bus (no RTR frames)",
            Self::NotAState => "its error-control answer was not a state",
            Self::Silent { heartbeat: true } => "no heartbeat within the wait, and no answer to node guarding",
            Self::Silent { heartbeat: false } => "no heartbeat configured, and no answer to node guarding",
        })
    }
}

impl Serialize for StateFrom {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl StateFrom {
    /// How an answer to node guarding on `bus` tells the state: through an EPOS2 the guarding
    /// request is a remote request of the gateway's (which may bring the node's next
    /// heartbeat, on the same COB-ID).
    pub(crate) fn guarding(answer: Guarded, bus: &dyn Bus) -> StateFrom {
        match answer {
            Guarded::State(_) if bus.sees_traffic() => StateFrom::NodeGuarding,
            Guarded::State(_) => StateFrom::Epos2Remote,
            Guarded::BootUp => StateFrom::BootUp,
            Guarded::NotAState => StateFrom::NotAState,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::Master;
    use crate::sim::{SimConfig, SimLink};

    const T: Duration = Duration::from_secs(2);

    fn sim() -> Master<SimLink> {
        Master::new(SimLink::with_config(SimConfig::instant()), "sim".into())
    }

    #[test]
    fn both_missing_aborts_and_nothing_else_are_missing() {
        let abort = |code| Error::SdoAbort { node: 1, obj: ObjAddr::new(0x2000, 1), code };
        assert!(is_missing(&abort(abort::NO_OBJECT)));
        assert!(is_missing(&abort(abort::NO_SUBINDEX)));
        assert!(is_missing(&abort(abort::NO_OBJECT).advised(crate::error::Advice::PortTaken)));
        assert!(!is_missing(&abort(abort::WRITE_ONLY)));
        assert!(matches!(optional::<u8>(Err(abort(abort::NO_SUBINDEX))), Ok(None)));
        assert!(optional::<u8>(Err(abort(abort::READ_ONLY))).is_err());
    }

    #[test]
    fn typed_reads_take_the_little_endian_value() {
        assert_eq!(le_unsigned(&[0x92, 0x01, 0x02, 0x00], 4), 0x0002_0192);
        assert_eq!(le_unsigned(&[0x34], 2), 0x34, "a short answer is zero-extended");
        let mut bus = sim();
        let mut node = Node::new(&mut bus, 10, T);
        assert_eq!(node.read_optional::<u32>(ObjAddr::new(0x1018, 9)).unwrap(), None);
        let id = node.identity().unwrap().unwrap();
        assert_ne!(id.vendor, 0);
        let parts = node.compare_identity(id.vendor, id.product.unwrap().wrapping_add(1)).unwrap();
        assert_eq!(parts.iter().map(IdentityPart::matches).collect::<Vec<_>>(), [true, false]);
        assert!(node.compare_identity(0, 0).unwrap().is_empty(), "a file that names nothing is not compared");
        assert_eq!(Node::new(&mut bus, 32, T).identity().unwrap(), None, "node 32 has no 0x1018:1");
    }

    #[test]
    fn a_boot_up_answer_to_guarding_is_pre_operational() {
        assert_eq!(Guarded::BootUp.state(), Some(nmt::State::PreOperational));
        assert_eq!(Guarded::NotAState.state(), None);
    }

    #[test]
    fn the_error_field_is_read_newest_first() {
        let mut bus = sim();
        let field = Node::new(&mut bus, 10, T).error_history(&Origin::default()).unwrap().unwrap();
        assert_eq!(field.count, 2);
        assert_eq!(field.entries.iter().map(|e| (e.sub, e.code)).collect::<Vec<_>>(), [(1, 0x8110), (2, 0x5000)]);
        assert!(Node::new(&mut bus, 32, T).error_history(&Origin::default()).unwrap().is_none());
    }
}
