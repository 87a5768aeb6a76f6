//! Small helpers on the values procedures read, write and report: a little-endian number
//! from an answer, a value checked against the dictionary's limits, a value serialised as text.

use crate::error::{Error, Result};
use crate::od::Entry;

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

/// A little-endian u32 from an answer of exactly 4 bytes.
pub(crate) fn as_u32(bytes: &[u8]) -> Option<u32> {
    bytes.try_into().ok().map(u32::from_le_bytes)
}
