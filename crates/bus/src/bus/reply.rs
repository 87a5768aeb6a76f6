//! An SDO server's first answer to an upload, read from its frame whoever's transfer it is:
//! what the checks that listen beside the transfers (two devices on one node-id, another
//! device's answers on a COB-ID, a batch counting its answers) need to know of it.

use crate::canopen::ObjAddr;

/// What an SDO server's first answer to an upload says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reply {
    /// An expedited answer: the value (little-endian, zero-filled past what was sent).
    Value(u32),
    /// An abort.
    Aborted,
    /// The start of a segmented upload: the value follows in segments, not read here.
    Unread,
}

impl Reply {
    /// The value it carries: an expedited answer's; `None` for an abort or a segmented start.
    pub(crate) fn carried(self) -> Option<u32> {
        match self {
            Reply::Value(v) => Some(v),
            Reply::Aborted | Reply::Unread => None,
        }
    }

    /// The value, `None` for an abort; nothing for an answer whose value was not read.
    pub fn value(self) -> Option<Option<u32>> {
        match self {
            Reply::Value(v) => Some(Some(v)),
            Reply::Aborted => Some(None),
            Reply::Unread => None,
        }
    }
}

/// Whether `data`, an SDO server's frame, answers an upload of `addr`, and how.
pub fn upload_answer(data: &[u8], addr: ObjAddr) -> Option<Reply> {
    let [cs, lo, hi, sub, a, b, c, d] = <[u8; 8]>::try_from(data).ok()?;
    if u16::from_le_bytes([lo, hi]) != addr.index || sub != addr.sub {
        return None;
    }
    match cs {
        0x80 => Some(Reply::Aborted),
        // e = 1: the value is in this frame (as many bytes as s and n say; the rest zero).
        cs if cs >> 5 == 2 && cs & 0x02 != 0 => {
            let len = if cs & 0x01 != 0 { 4 - usize::from((cs >> 2) & 3) } else { 4 };
            let mut bytes = [0u8; 4];
            bytes[..len].copy_from_slice(&[a, b, c, d][..len]);
            Some(Reply::Value(u32::from_le_bytes(bytes)))
        }
        cs if cs >> 5 == 2 => Some(Reply::Unread),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn upload_answers_are_matched_by_object() {
        // CiA 301 expedited upload response, 4 bytes: 0x43; abort: 0x80 with the code.
        assert_eq!(
            upload_answer(&[0x43, 0x18, 0x10, 0x04, 0x34, 0x12, 0x50, 0x09], ObjAddr::SERIAL_NUMBER),
            Some(Reply::Value(0x0950_1234))
        );
        assert_eq!(
            upload_answer(&[0x80, 0x18, 0x10, 0x04, 0x00, 0x00, 0x02, 0x06], ObjAddr::SERIAL_NUMBER),
            Some(Reply::Aborted)
        );
        // Two bytes (n = 2): the rest of the frame is not the value.
        assert_eq!(
            upload_answer(&[0x4B, 0x18, 0x10, 0x04, 0x34, 0x12, 0xFF, 0xFF], ObjAddr::SERIAL_NUMBER),
            Some(Reply::Value(0x1234))
        );
        // A segmented upload's start: its data bytes are a size, not the value.
        assert_eq!(
            upload_answer(&[0x41, 0x18, 0x10, 0x04, 0x04, 0x00, 0x00, 0x00], ObjAddr::SERIAL_NUMBER),
            Some(Reply::Unread)
        );
        assert_eq!(
            upload_answer(&[0x40, 0x18, 0x10, 0x04, 0x00, 0x00, 0x00, 0x00], ObjAddr::SERIAL_NUMBER),
            Some(Reply::Unread)
        );
        // Another object, a download answer, a short frame: not an answer to this read.
        assert_eq!(upload_answer(&[0x43, 0x18, 0x10, 0x03, 1, 0, 0, 0], ObjAddr::SERIAL_NUMBER), None);
        assert_eq!(upload_answer(&[0x60, 0x18, 0x10, 0x04, 0, 0, 0, 0], ObjAddr::SERIAL_NUMBER), None);
        assert_eq!(upload_answer(&[0x43, 0x18, 0x10], ObjAddr::SERIAL_NUMBER), None);
    }
}
