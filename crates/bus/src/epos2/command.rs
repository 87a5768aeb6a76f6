//! The EPOS2 command set (seed 000 chapter 3) as typed values, to and from frame payloads.

use super::frame::Frame;
use crate::canopen::{abort, ObjAddr};

/// The opcode of every answer frame.
pub(crate) const ANSWER: u8 = 0x00;
/// SendNMTService.
pub(crate) const SEND_NMT: u8 = 0x0E;
/// ReadObject: an expedited read (four bytes).
pub(crate) const READ_OBJECT: u8 = 0x10;
/// WriteObject: an expedited write (four bytes).
pub(crate) const WRITE_OBJECT: u8 = 0x11;
/// InitiateSegmentedRead.
pub(crate) const INITIATE_SEGMENTED_READ: u8 = 0x12;
/// InitiateSegmentedWrite.
pub(crate) const INITIATE_SEGMENTED_WRITE: u8 = 0x13;
/// SegmentRead.
pub(crate) const SEGMENT_READ: u8 = 0x14;
/// SegmentWrite.
pub(crate) const SEGMENT_WRITE: u8 = 0x15;
/// SendCANFrame: put a frame on the EPOS2's CAN bus.
pub(crate) const SEND_CAN_FRAME: u8 = 0x20;
/// RequestCANFrame: a remote request, answered with the data frame.
pub(crate) const REQUEST_CAN_FRAME: u8 = 0x21;
/// SendLSSFrame.
pub(crate) const SEND_LSS_FRAME: u8 = 0x30;
/// ReadLSSFrame: the next LSS slave answer.
pub(crate) const READ_LSS_FRAME: u8 = 0x31;
/// No command has this opcode. The EPOS2 answers a bad opcode with the error code
/// 0x0F00FFBF (seed 000 §4.1.3.1), an answer no real command of ours ever gets: sent after
/// opening the port or after a failure, it marks the point from which answers are ours.
pub(crate) const SYNC_PROBE: u8 = 0xFE;

/// Most data bytes in one SegmentRead/SegmentWrite (the control byte's six length bits).
pub const MAX_SEGMENT: usize = 63;
/// Through the gateway, a segment is one CANopen SDO segment.
pub const GATEWAY_SEGMENT: usize = 7;

/// A segment control byte's toggle bit.
pub const TOGGLE: u8 = 0x40;
/// A segment control byte's "more segments follow" bit.
pub const MORE: u8 = 0x80;
/// A segment control byte's length bits.
pub(crate) const LENGTH: u8 = 0x3F;

/// One EPOS2 command with its parameters.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Command {
    /// Read an object of up to 4 bytes (expedited, through the gateway).
    ReadObject {
        /// The CAN node the EPOS2 forwards to (0: itself).
        node: u8,
        /// The object read.
        addr: ObjAddr,
    },
    /// Write an object of up to 4 bytes.
    WriteObject {
        /// The CAN node the EPOS2 forwards to (0: itself).
        node: u8,
        /// The object written.
        addr: ObjAddr,
        /// The value, little-endian, zero-padded.
        data: [u8; 4],
    },
    /// Start a segmented read of a longer object.
    InitiateSegmentedRead {
        /// The CAN node the EPOS2 forwards to (0: itself).
        node: u8,
        /// The object read.
        addr: ObjAddr,
    },
    /// Start a segmented write of `length` bytes.
    InitiateSegmentedWrite {
        /// The CAN node the EPOS2 forwards to (0: itself).
        node: u8,
        /// The object written.
        addr: ObjAddr,
        /// The bytes to come, in all.
        length: u32,
    },
    /// Fetch the next segment of a segmented read.
    SegmentRead {
        /// The toggle bit, alternating from false.
        toggle: bool,
    },
    /// Send the next segment of a segmented write.
    SegmentWrite {
        /// The toggle bit, alternating from false.
        toggle: bool,
        /// The segment's bytes (at most 63).
        data: Vec<u8>,
    },
    /// Send an NMT command on the CAN bus.
    SendNmtService {
        /// The node it is for (0: all).
        node: u8,
        /// The NMT command specifier (1 start, 2 stop, ...).
        specifier: u8,
    },
    /// Send a raw CAN frame on the bus.
    SendCanFrame {
        /// Its 11-bit identifier.
        id: u16,
        /// How many of `data`'s bytes it carries.
        len: u8,
        /// Its data, zero-padded.
        data: [u8; 8],
    },
    /// Send a remote request for a CAN frame and return the answer.
    RequestCanFrame {
        /// The identifier requested.
        id: u16,
        /// The data length requested.
        len: u8,
    },
    /// Send an LSS request frame (0x7E5).
    SendLssFrame {
        /// The request's 8 bytes.
        data: [u8; 8],
    },
    /// Wait for an LSS answer frame (0x7E4).
    ReadLssFrame {
        /// How long the EPOS2 is to wait for it.
        timeout_ms: u16,
    },
}

fn object(addr: ObjAddr, node: u8) -> Vec<u8> {
    let [lo, hi] = addr.index.to_le_bytes();
    vec![lo, hi, addr.sub, node]
}

impl Command {
    /// Its name in seed 000 (`ReadObject`), for messages.
    pub fn name(&self) -> &'static str {
        match self {
            Command::ReadObject { .. } => "ReadObject",
            Command::WriteObject { .. } => "WriteObject",
            Command::InitiateSegmentedRead { .. } => "InitiateSegmentedRead",
            Command::InitiateSegmentedWrite { .. } => "InitiateSegmentedWrite",
            Command::SegmentRead { .. } => "SegmentRead",
            Command::SegmentWrite { .. } => "SegmentWrite",
            Command::SendNmtService { .. } => "SendNMTService",
            Command::SendCanFrame { .. } => "SendCANFrame",
            Command::RequestCanFrame { .. } => "RequestCANFrame",
            Command::SendLssFrame { .. } => "SendLSSFrame",
            Command::ReadLssFrame { .. } => "ReadLSSFrame",
        }
    }

    /// RS232 has no answer frame for the commands that only put a frame on the CAN bus
    /// (seed 000 chapter 3, remark "no response with RS232"); USB answers everything.
    pub fn answered_on_rs232(&self) -> bool {
        !matches!(self, Command::SendNmtService { .. } | Command::SendCanFrame { .. } | Command::SendLssFrame { .. })
    }

    /// Whether `f` can be the answer to this command (seed 000 chapter 3): the answer
    /// opcode and, with error code 0, exactly the length of this command's answer; with an
    /// error code, at least the code and at most that length. An "illegal command" answer
    /// is never one to a command canctl sends: it answers a synchronisation probe.
    pub(crate) fn answer_fits(&self, f: &Frame) -> bool {
        let Some((code, _)) = parse_answer(f) else { return false };
        let (min, max) = self.answer_len();
        let len = f.data.len();
        code != ILLEGAL_COMMAND && len <= max && (len >= min || code != 0)
    }

    /// The shortest and longest answer to this command in bytes, error code included,
    /// when it succeeds (seed 000 chapter 3).
    pub fn answer_len(&self) -> (usize, usize) {
        match self {
            Command::ReadObject { .. } => (8, 8),
            Command::SegmentRead { .. } => (6, 4 + (1 + MAX_SEGMENT).next_multiple_of(2)),
            Command::SegmentWrite { .. } => (6, 6),
            Command::RequestCanFrame { .. } | Command::ReadLssFrame { .. } => (12, 12),
            _ => (4, 4),
        }
    }

    /// The command frame.
    pub fn to_frame(&self) -> Frame {
        match self {
            Command::ReadObject { node, addr } => Frame::new(READ_OBJECT, object(*addr, *node)),
            Command::WriteObject { node, addr, data } => {
                Frame::new(WRITE_OBJECT, [object(*addr, *node), data.to_vec()].concat())
            }
            Command::InitiateSegmentedRead { node, addr } => Frame::new(INITIATE_SEGMENTED_READ, object(*addr, *node)),
            Command::InitiateSegmentedWrite { node, addr, length } => {
                Frame::new(INITIATE_SEGMENTED_WRITE, [object(*addr, *node), length.to_le_bytes().to_vec()].concat())
            }
            Command::SegmentRead { toggle } => Frame::new(SEGMENT_READ, vec![if *toggle { TOGGLE } else { 0 }, 0]),
            Command::SegmentWrite { toggle, data } => {
                Frame::new(SEGMENT_WRITE, [&[data.len() as u8 | if *toggle { TOGGLE } else { 0 }][..], data].concat())
            }
            Command::SendNmtService { node, specifier } => Frame::new(SEND_NMT, vec![*node, 0, *specifier, 0]),
            Command::SendCanFrame { id, len, data } => {
                Frame::new(SEND_CAN_FRAME, [&id.to_le_bytes()[..], &(*len as u16).to_le_bytes(), data].concat())
            }
            Command::RequestCanFrame { id, len } => {
                Frame::new(REQUEST_CAN_FRAME, [id.to_le_bytes(), (*len as u16).to_le_bytes()].concat())
            }
            Command::SendLssFrame { data } => Frame::new(SEND_LSS_FRAME, data.to_vec()),
            Command::ReadLssFrame { timeout_ms } => Frame::new(READ_LSS_FRAME, timeout_ms.to_le_bytes().to_vec()),
        }
    }

    /// The command in a frame from a master; `None` for an unknown opcode or a payload of
    /// the wrong size.
    pub fn from_frame(f: &Frame) -> Option<Command> {
        let d = &f.data;
        let obj = || (d.len() >= 4).then(|| (d[3], ObjAddr::new(u16::from_le_bytes([d[0], d[1]]), d[2])));
        let word = |i: usize| u16::from_le_bytes([d[i], d[i + 1]]);
        Some(match (f.opcode, d.len()) {
            (READ_OBJECT, 4) => obj().map(|(node, addr)| Command::ReadObject { node, addr })?,
            (WRITE_OBJECT, 8) => {
                let (node, addr) = obj()?;
                Command::WriteObject { node, addr, data: d[4..8].try_into().ok()? }
            }
            (INITIATE_SEGMENTED_READ, 4) => obj().map(|(node, addr)| Command::InitiateSegmentedRead { node, addr })?,
            (INITIATE_SEGMENTED_WRITE, 8) => {
                let (node, addr) = obj()?;
                Command::InitiateSegmentedWrite { node, addr, length: u32::from_le_bytes(d[4..8].try_into().ok()?) }
            }
            (SEGMENT_READ, 2) => Command::SegmentRead { toggle: d[0] & TOGGLE != 0 },
            (SEGMENT_WRITE, n) if n >= 2 => {
                let len = (d[0] & LENGTH) as usize;
                if 1 + len > n {
                    return None;
                }
                Command::SegmentWrite { toggle: d[0] & TOGGLE != 0, data: d[1..1 + len].to_vec() }
            }
            (SEND_NMT, 4) => Command::SendNmtService { node: word(0) as u8, specifier: word(2) as u8 },
            (SEND_CAN_FRAME, 12) => {
                Command::SendCanFrame { id: word(0), len: word(2).min(8) as u8, data: d[4..12].try_into().ok()? }
            }
            (REQUEST_CAN_FRAME, 4) => Command::RequestCanFrame { id: word(0), len: word(2).min(8) as u8 },
            (SEND_LSS_FRAME, 8) => Command::SendLssFrame { data: d[..8].try_into().ok()? },
            (READ_LSS_FRAME, 2) => Command::ReadLssFrame { timeout_ms: word(0) },
            _ => return None,
        })
    }
}

/// An answer frame: the 32-bit error code, then the data.
pub fn answer(error: u32, data: &[u8]) -> Frame {
    let mut d = error.to_le_bytes().to_vec();
    d.extend_from_slice(data);
    Frame::new(ANSWER, d)
}

/// The synchronisation probe: an opcode that does not exist, one zero word.
pub(crate) fn sync_probe() -> Frame {
    Frame::new(SYNC_PROBE, vec![0, 0])
}

/// Whether `f` is the EPOS2's answer to the synchronisation probe.
pub(crate) fn is_probe_answer(f: &Frame) -> bool {
    parse_answer(f).is_some_and(|(code, _)| code == ILLEGAL_COMMAND)
}

/// Error code and data of an answer frame.
pub fn parse_answer(f: &Frame) -> Option<(u32, &[u8])> {
    if f.opcode != ANSWER || f.data.len() < 4 {
        return None;
    }
    Some((u32::from_le_bytes(f.data[..4].try_into().unwrap()), &f.data[4..]))
}

/// maxon error: the device is in the wrong NMT state.
pub const WRONG_NMT_STATE: u32 = 0x0F00_FFC0;
/// maxon error: no command has this opcode.
pub const ILLEGAL_COMMAND: u32 = 0x0F00_FFBF;
/// maxon error: wrong password.
pub(crate) const PASSWORD: u32 = 0x0F00_FFBE;
/// maxon error: the device is not in service mode.
pub(crate) const SERVICE_MODE: u32 = 0x0F00_FFBC;
/// maxon error: wrong CAN id.
pub const CAN_ID: u32 = 0x0F00_FFB9;

/// The maxon-specific error codes (seed 000 §8.2).
const MAXON: &[(u32, &str)] = &[
    (WRONG_NMT_STATE, "Device is in wrong NMT state"),
    (ILLEGAL_COMMAND, "RS232 command is illegal (does not exist)"),
    (PASSWORD, "Password is incorrect"),
    (SERVICE_MODE, "Device is not in service mode"),
    (CAN_ID, "Wrong CAN ID"),
];

/// Whether `code` is one of the maxon-specific codes of seed 000 §8.2.
pub(crate) fn is_maxon_code(code: u32) -> bool {
    MAXON.iter().any(|(c, _)| *c == code)
}

/// The meaning of an EPOS2 error code: the CANopen codes of §8.1 are the CiA 301 abort
/// codes, the rest are maxon's own.
pub(crate) fn error_meaning(code: u32) -> &'static str {
    MAXON.iter().find(|(c, _)| *c == code).map(|(_, m)| *m).unwrap_or_else(|| abort::meaning(code))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_round_trip_through_frames() {
        let a = ObjAddr::new(0x2003, 1);
        let all = vec![
            Command::ReadObject { node: 2, addr: a },
            Command::WriteObject { node: 0, addr: a, data: [1, 2, 3, 4] },
            Command::InitiateSegmentedRead { node: 5, addr: a },
            Command::InitiateSegmentedWrite { node: 5, addr: a, length: 70_000 },
            Command::SegmentRead { toggle: true },
            Command::SegmentWrite { toggle: false, data: vec![9; 63] },
            Command::SegmentWrite { toggle: true, data: vec![1, 2, 3] },
            Command::SendNmtService { node: 0, specifier: 0x81 },
            Command::SendCanFrame { id: 0x605, len: 8, data: [0x40, 0, 0x10, 0, 0, 0, 0, 0] },
            Command::RequestCanFrame { id: 0x705, len: 1 },
            Command::SendLssFrame { data: [0x04, 1, 0, 0, 0, 0, 0, 0] },
            Command::ReadLssFrame { timeout_ms: 100 },
        ];
        for c in all {
            assert_eq!(Command::from_frame(&c.to_frame()), Some(c.clone()), "{c:?}");
        }
        // Seed 000 §5.1.8: ReadObject 0x2003:1 of node 2 is the words 0x2003, 0x0201.
        assert_eq!(Command::ReadObject { node: 2, addr: a }.to_frame().data, [0x03, 0x20, 0x01, 0x02]);
        assert_eq!(Command::from_frame(&Frame::new(0x77, vec![0, 0])), None);
        assert_eq!(Command::from_frame(&Frame::new(SEGMENT_WRITE, vec![10, 1])), None);
    }

    #[test]
    fn answers_are_checked_against_their_command() {
        let a = ObjAddr::new(0x1018, 1);
        let read = Command::ReadObject { node: 5, addr: a };
        let write = Command::WriteObject { node: 5, addr: a, data: [0; 4] };
        let segment = Command::SegmentRead { toggle: false };
        // Seed 002: the answer to ReadObject 0x1000 of node 2 is four words.
        assert!(read.answer_fits(&answer(0, &[0x92, 0x01, 0x02, 0x00])));
        assert!(read.answer_fits(&answer(abort::TIMED_OUT, &[0; 4])));
        assert!(read.answer_fits(&answer(abort::TIMED_OUT, &[])), "an error may come without data");
        assert!(!read.answer_fits(&answer(0, &[])), "a WriteObject answer is no ReadObject answer");
        assert!(!read.answer_fits(&answer(0, &[0; 8])), "a RequestCANFrame answer is no ReadObject answer");
        assert!(write.answer_fits(&answer(0, &[])));
        assert!(!write.answer_fits(&answer(0, &[1, 2, 3, 4])), "a ReadObject answer is no WriteObject answer");
        assert!(!write.answer_fits(&answer(ILLEGAL_COMMAND, &[])), "the probe's answer");
        assert!(!write.answer_fits(&Frame::new(READ_OBJECT, vec![0; 4])), "not an answer opcode");
        assert!(!write.answer_fits(&Frame::new(ANSWER, vec![0, 0])), "too short for an error code");
        assert!(segment.answer_fits(&answer(0, &[0x43, 1, 2, 3])));
        assert!(segment.answer_fits(&answer(0, &[0x3F; 64])));
        assert!(!segment.answer_fits(&answer(0, &[0x3F; 66])));
        assert!(!segment.answer_fits(&answer(0, &[])));
        assert!(is_probe_answer(&answer(ILLEGAL_COMMAND, &[])));
        assert_eq!(Command::from_frame(&sync_probe()), None, "the probe is no command");
    }

    #[test]
    fn error_codes_have_meanings() {
        assert_eq!(error_meaning(0x0F00_FFBF), "RS232 command is illegal (does not exist)");
        assert_eq!(error_meaning(0x0601_0002), "Attempt to write a read only object");
        assert!(is_maxon_code(CAN_ID));
        let refused = answer(0x0602_0000, &[]);
        let (code, data) = parse_answer(&refused).unwrap();
        assert_eq!((code, data.len()), (0x0602_0000, 0));
    }
}
