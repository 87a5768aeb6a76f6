//! SDO options and upload limits for the values procedures read: how many bytes a number,
//! a name or a value of a known type may bring.

use crate::bus::SdoOptions;
use crate::canopen::DataType;
use std::time::Duration;

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
