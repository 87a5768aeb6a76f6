//! The SDO frames of CiA 301 §7.2.4.3 as typed values: `parse` reads an 8-byte payload,
//! `emit` writes one. This is the only place that knows the command specifiers and the bit
//! layout of the command byte; client, server, the EPOS2 device and the monitor go
//! through it.
//!
//! The first byte of a frame means different things in each direction (the client's
//! command specifiers are not the server's), so there is one type for each: [`Request`]
//! (client → server) and [`Response`] (server → client). Inside a block-transfer sub-block
//! every frame is a [`BlockSegment`], whatever its first byte; only the receiver's state
//! knows that, so block segments are parsed on their own.
//!
//! Parsing takes a payload padded to 8 bytes (see [`super::pad`]): how many bytes really
//! arrived is for the caller to check against what the frame kind needs. Bits CiA 301
//! marks "x" (not used) are ignored on parsing and written as zero.

use crate::frame::command;
use crate::ObjAddr;

/// Data bytes in one segment.
pub const SEGMENT_DATA: usize = 7;

/// The abort frame's first byte (cs = 4, the other bits zero). Only this exact byte is an
/// abort: inside a sub-block the other bytes with the top bit set are segments.
const ABORT: u8 = 0x80;

/// What the e, s and n bits and bytes 4 to 7 of an initiate download request or an
/// initiate upload response carry.
// The fields carry CiA 301's names (data, len): each variant's doc says what they hold.
#[allow(missing_docs)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Initiate {
    /// Expedited with the size indicated (e=1, s=1): the first `len` bytes of `data`,
    /// `len` from 1 to 4.
    Expedited { data: [u8; 4], len: u8 },
    /// Expedited without the size (e=1, s=0): four bytes, of which as many are data as the
    /// object's type holds.
    ExpeditedUnsized { data: [u8; 4] },
    /// Segmented, with the size of the data that follows (e=0, s=1). CiA 301 carries it
    /// in 32 bits.
    Size(u32),
    /// Segmented, size not indicated (e=0, s=0).
    Unsized,
}

impl Initiate {
    /// The expedited form of 1 to 4 bytes of data, size indicated.
    pub fn expedited(bytes: &[u8]) -> Initiate {
        assert!((1..=4).contains(&bytes.len()), "expedited transfer carries 1 to 4 bytes");
        let mut data = [0u8; 4];
        data[..bytes.len()].copy_from_slice(bytes);
        Initiate::Expedited { data, len: bytes.len() as u8 }
    }

    /// The announcement of `len` bytes to follow in segments: with its size when it fits
    /// the 32 bits CiA 301 gives it, else without (never a size cut to 32 bits).
    pub fn segmented(len: usize) -> Initiate {
        u32::try_from(len).map_or(Initiate::Unsized, Initiate::Size)
    }

    /// The command byte's bits 0 to 3 (n, e, s) for this.
    fn bits(&self) -> u8 {
        match self {
            Initiate::Expedited { len, .. } => (4 - len) << 2 | 0x03,
            Initiate::ExpeditedUnsized { .. } => 0x02,
            Initiate::Size(_) => 0x01,
            Initiate::Unsized => 0x00,
        }
    }

    fn bytes(&self) -> [u8; 4] {
        match self {
            Initiate::Expedited { data, .. } | Initiate::ExpeditedUnsized { data } => *data,
            Initiate::Size(size) => size.to_le_bytes(),
            Initiate::Unsized => [0; 4],
        }
    }

    fn parse(cmd: u8, p: &[u8; 8]) -> Initiate {
        let data = [p[4], p[5], p[6], p[7]];
        match (cmd & 0x02 != 0, cmd & 0x01 != 0) {
            (true, true) => Initiate::Expedited { data, len: 4 - ((cmd >> 2) & 3) },
            (true, false) => Initiate::ExpeditedUnsized { data },
            (false, true) => Initiate::Size(u32::from_le_bytes(data)),
            (false, false) => Initiate::Unsized,
        }
    }

    /// The data of an expedited transfer (all four bytes when the size is not indicated);
    /// `None` when the data follows in segments.
    pub fn expedited_data(&self) -> Option<&[u8]> {
        match self {
            Initiate::Expedited { data, len } => Some(&data[..*len as usize]),
            Initiate::ExpeditedUnsized { data } => Some(data),
            Initiate::Size(_) | Initiate::Unsized => None,
        }
    }
}

/// A segment of a segmented transfer: a download request or an upload response.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Segment {
    /// The toggle bit (t): alternates from segment to segment.
    pub toggle: bool,
    /// No more segments follow (c).
    pub last: bool,
    data: [u8; SEGMENT_DATA],
    len: u8,
}

impl Segment {
    /// Up to seven bytes of data.
    pub fn new(toggle: bool, chunk: &[u8], last: bool) -> Segment {
        assert!(chunk.len() <= SEGMENT_DATA, "a segment carries at most 7 bytes");
        let mut data = [0u8; SEGMENT_DATA];
        data[..chunk.len()].copy_from_slice(chunk);
        Segment { toggle, last, data, len: chunk.len() as u8 }
    }

    /// The segment's data bytes.
    pub fn data(&self) -> &[u8] {
        &self.data[..self.len as usize]
    }

    /// The bytes a frame must have to carry all of this segment's data.
    pub(crate) fn frame_len(&self) -> usize {
        1 + self.len as usize
    }

    fn parse(cmd: u8, p: &[u8; 8]) -> Segment {
        let len = SEGMENT_DATA as u8 - ((cmd >> 1) & 7);
        let mut data = [0u8; SEGMENT_DATA];
        data.copy_from_slice(&p[1..8]);
        data[len as usize..].fill(0);
        Segment { toggle: cmd & 0x10 != 0, last: cmd & 0x01 != 0, data, len }
    }

    fn emit(&self, scs: u8) -> [u8; 8] {
        let n = SEGMENT_DATA as u8 - self.len;
        let mut f = [0u8; 8];
        f[0] = scs << 5 | (self.toggle as u8) << 4 | n << 1 | self.last as u8;
        f[1..8].copy_from_slice(&self.data);
        f
    }
}

/// One segment of a block-transfer sub-block: sequence number 1 to 127, and whether it is
/// the last of the whole transfer. It always has room for seven bytes; how many of the
/// last segment's are data, the end frame says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockSegment {
    /// Its sequence number in the block (1 to 127).
    pub seqno: u8,
    /// No more segments follow (c).
    pub last: bool,
    /// Seven bytes: data, and in the last segment padding after it.
    pub data: [u8; SEGMENT_DATA],
}

impl BlockSegment {
    /// Up to seven bytes of data, padded with zeros.
    pub fn new(seqno: u8, chunk: &[u8], last: bool) -> BlockSegment {
        let mut data = [0u8; SEGMENT_DATA];
        data[..chunk.len()].copy_from_slice(chunk);
        BlockSegment { seqno, last, data }
    }

    /// A segment from its frame's eight bytes.
    pub fn parse(p: &[u8; 8]) -> BlockSegment {
        let mut data = [0u8; SEGMENT_DATA];
        data.copy_from_slice(&p[1..8]);
        BlockSegment { seqno: p[0] & 0x7F, last: p[0] & 0x80 != 0, data }
    }

    /// The frame's eight bytes.
    pub fn emit(&self) -> [u8; 8] {
        let mut f = [0u8; 8];
        f[0] = (self.last as u8) << 7 | self.seqno & 0x7F;
        f[1..8].copy_from_slice(&self.data);
        f
    }
}

/// A frame from the SDO client to the server.
// The fields carry CiA 301's names for the frame's fields (addr: its index and sub-index;
// toggle, ackseq, blksize, pst, crc, size, unused, code): each variant's doc says which frame.
#[allow(missing_docs)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Request {
    /// ccs = 1.
    InitiateDownload { addr: ObjAddr, init: Initiate },
    /// ccs = 0.
    DownloadSegment(Segment),
    /// ccs = 2.
    InitiateUpload { addr: ObjAddr },
    /// ccs = 3.
    UploadSegment { toggle: bool },
    /// ccs = 6, cs = 0: `crc` says the client can use CRCs; the size is optional.
    BlockDownload { addr: ObjAddr, crc: bool, size: Option<u32> },
    /// ccs = 6, cs = 1: `unused` bytes of the last segment carry no data.
    BlockDownloadEnd { unused: u8, crc: u16 },
    /// ccs = 5, cs = 0: `pst` is the protocol switch threshold (0: no switch).
    BlockUpload { addr: ObjAddr, crc: bool, blksize: u8, pst: u8 },
    /// ccs = 5, cs = 1: the client confirms the block upload end.
    BlockUploadEnd,
    /// ccs = 5, cs = 2: segments received in sequence, and the next block's size.
    BlockUploadAck { ackseq: u8, blksize: u8 },
    /// ccs = 5, cs = 3: the client asks the server to start sending.
    BlockUploadStart,
    /// cs = 4.
    Abort { addr: ObjAddr, code: u32 },
}

/// A frame from the SDO server to the client.
// The fields carry CiA 301's names for the frame's fields (addr: its index and sub-index;
// toggle, ackseq, blksize, pst, crc, size, unused, code): each variant's doc says which frame.
#[allow(missing_docs)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Response {
    /// scs = 2.
    InitiateUpload { addr: ObjAddr, init: Initiate },
    /// scs = 0.
    UploadSegment(Segment),
    /// scs = 3.
    InitiateDownload { addr: ObjAddr },
    /// scs = 1.
    DownloadSegment { toggle: bool },
    /// scs = 5, ss = 0: `crc` says the server can use CRCs.
    BlockDownload { addr: ObjAddr, crc: bool, blksize: u8 },
    /// scs = 5, ss = 1: the server confirms the block download end.
    BlockDownloadEnd,
    /// scs = 5, ss = 2: segments received in sequence, and the next block's size.
    BlockDownloadAck { ackseq: u8, blksize: u8 },
    /// scs = 6, ss = 0: the size, when indicated, as CiA 301 carries it: 32 bits.
    BlockUpload { addr: ObjAddr, crc: bool, size: Option<u32> },
    /// scs = 6, ss = 1: `unused` bytes of the last segment carry no data.
    BlockUploadEnd { unused: u8, crc: u16 },
    /// cs = 4.
    Abort { addr: ObjAddr, code: u32 },
}

fn mux(p: &[u8; 8]) -> ObjAddr {
    ObjAddr::from_mux(&p[1..4])
}

fn le_u32(p: &[u8; 8]) -> u32 {
    u32::from_le_bytes([p[4], p[5], p[6], p[7]])
}

/// A frame with command byte, multiplexer and four data bytes.
fn with_mux(cmd: u8, addr: ObjAddr, data: [u8; 4]) -> [u8; 8] {
    let mut f = [0u8; 8];
    f[0] = cmd;
    f[1..4].copy_from_slice(&addr.to_mux());
    f[4..8].copy_from_slice(&data);
    f
}

fn abort(addr: ObjAddr, code: u32) -> [u8; 8] {
    with_mux(ABORT, addr, code.to_le_bytes())
}

/// Block download request and block upload response open the same way: the CRC bit
/// (cc/sc), the object, and the size when s=1.
fn block_initiate(addr: ObjAddr, crc: bool, size: Option<u32>) -> [u8; 8] {
    let s = if size.is_some() { 0x02 } else { 0 };
    with_mux(0xC0 | (crc as u8) << 2 | s, addr, size.unwrap_or(0).to_le_bytes())
}

/// The last frame of a block's data, in either direction: `unused` bytes of the last
/// segment carry no data, and the CRC.
fn block_end(unused: u8, crc: u16) -> [u8; 8] {
    command(0xC1 | (unused & 7) << 2, &crc.to_le_bytes())
}

impl Request {
    /// `None` for a command specifier CiA 301 does not define (ccs 7, or 4 other than the
    /// abort's exact byte).
    pub fn parse(p: &[u8; 8]) -> Option<Request> {
        let cmd = p[0];
        let crc = cmd & 0x04 != 0;
        Some(match cmd >> 5 {
            0 => Request::DownloadSegment(Segment::parse(cmd, p)),
            1 => Request::InitiateDownload { addr: mux(p), init: Initiate::parse(cmd, p) },
            2 => Request::InitiateUpload { addr: mux(p) },
            3 => Request::UploadSegment { toggle: cmd & 0x10 != 0 },
            4 if cmd == ABORT => Request::Abort { addr: mux(p), code: le_u32(p) },
            5 => match cmd & 0x03 {
                0 => Request::BlockUpload { addr: mux(p), crc, blksize: p[4], pst: p[5] },
                1 => Request::BlockUploadEnd,
                2 => Request::BlockUploadAck { ackseq: p[1], blksize: p[2] },
                _ => Request::BlockUploadStart,
            },
            6 if cmd & 0x01 == 0 => {
                Request::BlockDownload { addr: mux(p), crc, size: (cmd & 0x02 != 0).then(|| le_u32(p)) }
            }
            6 => Request::BlockDownloadEnd { unused: (cmd >> 2) & 7, crc: u16::from_le_bytes([p[1], p[2]]) },
            _ => return None,
        })
    }

    /// The frame's eight bytes.
    pub fn emit(&self) -> [u8; 8] {
        match *self {
            Request::DownloadSegment(seg) => seg.emit(0),
            Request::InitiateDownload { addr, init } => with_mux(0x20 | init.bits(), addr, init.bytes()),
            Request::InitiateUpload { addr } => with_mux(0x40, addr, [0; 4]),
            Request::UploadSegment { toggle } => command(0x60 | (toggle as u8) << 4, &[]),
            Request::Abort { addr, code } => abort(addr, code),
            Request::BlockUpload { addr, crc, blksize, pst } => {
                with_mux(0xA0 | (crc as u8) << 2, addr, [blksize, pst, 0, 0])
            }
            Request::BlockUploadEnd => command(0xA1, &[]),
            Request::BlockUploadAck { ackseq, blksize } => command(0xA2, &[ackseq, blksize]),
            Request::BlockUploadStart => command(0xA3, &[]),
            Request::BlockDownload { addr, crc, size } => block_initiate(addr, crc, size),
            Request::BlockDownloadEnd { unused, crc } => block_end(unused, crc),
        }
    }
}

impl Response {
    /// `None` for a command specifier CiA 301 does not define for a server (scs 7, scs 5
    /// with ss 3, or 4 other than the abort's exact byte).
    pub fn parse(p: &[u8; 8]) -> Option<Response> {
        let cmd = p[0];
        let crc = cmd & 0x04 != 0;
        Some(match cmd >> 5 {
            0 => Response::UploadSegment(Segment::parse(cmd, p)),
            1 => Response::DownloadSegment { toggle: cmd & 0x10 != 0 },
            2 => Response::InitiateUpload { addr: mux(p), init: Initiate::parse(cmd, p) },
            3 => Response::InitiateDownload { addr: mux(p) },
            4 if cmd == ABORT => Response::Abort { addr: mux(p), code: le_u32(p) },
            5 => match cmd & 0x03 {
                0 => Response::BlockDownload { addr: mux(p), crc, blksize: p[4] },
                1 => Response::BlockDownloadEnd,
                2 => Response::BlockDownloadAck { ackseq: p[1], blksize: p[2] },
                _ => return None,
            },
            6 if cmd & 0x01 == 0 => {
                Response::BlockUpload { addr: mux(p), crc, size: (cmd & 0x02 != 0).then(|| le_u32(p)) }
            }
            6 => Response::BlockUploadEnd { unused: (cmd >> 2) & 7, crc: u16::from_le_bytes([p[1], p[2]]) },
            _ => return None,
        })
    }

    /// The frame's eight bytes.
    pub fn emit(&self) -> [u8; 8] {
        match *self {
            Response::UploadSegment(seg) => seg.emit(0),
            Response::DownloadSegment { toggle } => command(0x20 | (toggle as u8) << 4, &[]),
            Response::InitiateUpload { addr, init } => with_mux(0x40 | init.bits(), addr, init.bytes()),
            Response::InitiateDownload { addr } => with_mux(0x60, addr, [0; 4]),
            Response::Abort { addr, code } => abort(addr, code),
            Response::BlockDownload { addr, crc, blksize } => {
                with_mux(0xA0 | (crc as u8) << 2, addr, [blksize, 0, 0, 0])
            }
            Response::BlockDownloadEnd => command(0xA1, &[]),
            Response::BlockDownloadAck { ackseq, blksize } => command(0xA2, &[ackseq, blksize]),
            Response::BlockUpload { addr, crc, size } => block_initiate(addr, crc, size),
            Response::BlockUploadEnd { unused, crc } => block_end(unused, crc),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bytes(hex: &str) -> [u8; 8] {
        let v: Vec<u8> = hex.split_whitespace().map(|b| u8::from_str_radix(b, 16).unwrap()).collect();
        super::super::pad(&v)
    }

    const A1008: ObjAddr = ObjAddr::new(0x1008, 0);

    /// Each request: its bytes, and what they parse to; emitting gives the bytes back.
    #[test]
    fn requests_round_trip() {
        let cases = [
            // Seed 004: CAN-2024C, 0x1605:1 = 0x64110210, expedited with size (ccs 1, n 0).
            (
                "23 05 16 01 10 02 11 64",
                Request::InitiateDownload {
                    addr: ObjAddr::new(0x1605, 1),
                    init: Initiate::expedited(&[0x10, 0x02, 0x11, 0x64]),
                },
            ),
            // Seed 004: 0x1801:5 = 1000, two bytes (n 2).
            (
                "2B 01 18 05 E8 03 00 00",
                Request::InitiateDownload { addr: ObjAddr::new(0x1801, 5), init: Initiate::expedited(&[0xE8, 0x03]) },
            ),
            // Seed 004: 0x1800:2 = 0xFD, one byte (n 3).
            (
                "2F 00 18 02 FD 00 00 00",
                Request::InitiateDownload { addr: ObjAddr::new(0x1800, 2), init: Initiate::expedited(&[0xFD]) },
            ),
            // Expedited without the size (e=1, s=0), as the EPOS2 gateway forwards WriteObject.
            (
                "22 00 10 00 01 02 03 04",
                Request::InitiateDownload {
                    addr: ObjAddr::new(0x1000, 0),
                    init: Initiate::ExpeditedUnsized { data: [1, 2, 3, 4] },
                },
            ),
            // Segmented download of 70000 bytes announced (e=0, s=1).
            ("21 08 10 00 70 11 01 00", Request::InitiateDownload { addr: A1008, init: Initiate::Size(70_000) }),
            ("20 08 10 00 00 00 00 00", Request::InitiateDownload { addr: A1008, init: Initiate::Unsized }),
            // Seed 004: the upload of 0x1008 starts with ccs 2.
            ("40 08 10 00 00 00 00 00", Request::InitiateUpload { addr: A1008 }),
            // Seed 004: the first upload segment request (ccs 3, t 0), then t 1.
            ("60 00 00 00 00 00 00 00", Request::UploadSegment { toggle: false }),
            ("70 00 00 00 00 00 00 00", Request::UploadSegment { toggle: true }),
            // Download segments: t 0, 7 bytes, more follow; t 1, 2 bytes (n 5), the last.
            ("00 43 41 4E 2D 32 30 35", Request::DownloadSegment(Segment::new(false, b"CAN-205", false))),
            ("1B 37 43 00 00 00 00 00", Request::DownloadSegment(Segment::new(true, b"7C", true))),
            // An empty last segment (n 7, c 1).
            ("0F 00 00 00 00 00 00 00", Request::DownloadSegment(Segment::new(false, &[], true))),
            // Block upload: CRC, 127 segments a block, protocol switch threshold 21.
            (
                "A4 50 1F 01 7F 15 00 00",
                Request::BlockUpload { addr: ObjAddr::new(0x1F50, 1), crc: true, blksize: 127, pst: 21 },
            ),
            ("A3 00 00 00 00 00 00 00", Request::BlockUploadStart),
            ("A2 05 7F 00 00 00 00 00", Request::BlockUploadAck { ackseq: 5, blksize: 127 }),
            ("A1 00 00 00 00 00 00 00", Request::BlockUploadEnd),
            // Block download of 65536 bytes with CRC and the size.
            (
                "C6 50 1F 01 00 00 01 00",
                Request::BlockDownload { addr: ObjAddr::new(0x1F50, 1), crc: true, size: Some(65_536) },
            ),
            (
                "C0 50 1F 01 00 00 00 00",
                Request::BlockDownload { addr: ObjAddr::new(0x1F50, 1), crc: false, size: None },
            ),
            // End: 3 bytes of the last segment unused (n 3), CRC 0x29B1.
            ("CD B1 29 00 00 00 00 00", Request::BlockDownloadEnd { unused: 3, crc: 0x29B1 }),
            // Abort: toggle bit not alternated.
            ("80 08 10 00 00 00 03 05", Request::Abort { addr: A1008, code: 0x0503_0000 }),
        ];
        for (hex, want) in cases {
            let p = bytes(hex);
            assert_eq!(Request::parse(&p), Some(want), "{hex}");
            assert_eq!(want.emit(), p, "{want:?}");
        }
    }

    /// Each response: its bytes, and what they parse to; emitting gives the bytes back.
    #[test]
    fn responses_round_trip() {
        let cases = [
            // Seed 004: 0x1003:2 = 0x00098210, expedited, four bytes.
            (
                "43 03 10 02 10 82 09 00",
                Response::InitiateUpload {
                    addr: ObjAddr::new(0x1003, 2),
                    init: Initiate::expedited(&[0x10, 0x82, 0x09, 0x00]),
                },
            ),
            // Seed 004: 0x1400:0 = 2, one byte (n 3).
            (
                "4F 00 14 00 02 00 00 00",
                Response::InitiateUpload { addr: ObjAddr::new(0x1400, 0), init: Initiate::expedited(&[0x02]) },
            ),
            // Seed 004: 0x1008 is 9 bytes, in segments (e 0, s 1).
            ("41 08 10 00 09 00 00 00", Response::InitiateUpload { addr: A1008, init: Initiate::Size(9) }),
            ("40 08 10 00 00 00 00 00", Response::InitiateUpload { addr: A1008, init: Initiate::Unsized }),
            (
                "42 08 10 00 41 42 43 44",
                Response::InitiateUpload { addr: A1008, init: Initiate::ExpeditedUnsized { data: *b"ABCD" } },
            ),
            // Seed 004: the first segment of 0x1008, "CAN-208" (t 0, n 0, c 0).
            ("00 43 41 4E 2D 32 30 38", Response::UploadSegment(Segment::new(false, b"CAN-208", false))),
            ("1B 37 43 00 00 00 00 00", Response::UploadSegment(Segment::new(true, b"7C", true))),
            // Seed 004: the download of 0x1605:1 confirmed (scs 3).
            ("60 05 16 01 00 00 00 00", Response::InitiateDownload { addr: ObjAddr::new(0x1605, 1) }),
            ("20 00 00 00 00 00 00 00", Response::DownloadSegment { toggle: false }),
            ("30 00 00 00 00 00 00 00", Response::DownloadSegment { toggle: true }),
            (
                "A4 50 1F 01 7F 00 00 00",
                Response::BlockDownload { addr: ObjAddr::new(0x1F50, 1), crc: true, blksize: 127 },
            ),
            ("A2 7F 7F 00 00 00 00 00", Response::BlockDownloadAck { ackseq: 127, blksize: 127 }),
            ("A1 00 00 00 00 00 00 00", Response::BlockDownloadEnd),
            (
                "C6 50 1F 01 FF FF FF FF",
                Response::BlockUpload { addr: ObjAddr::new(0x1F50, 1), crc: true, size: Some(u32::MAX) },
            ),
            ("C0 08 10 00 00 00 00 00", Response::BlockUpload { addr: A1008, crc: false, size: None }),
            ("D9 34 12 00 00 00 00 00", Response::BlockUploadEnd { unused: 6, crc: 0x1234 }),
            // Seed 001 figure 18: no such subindex.
            ("80 08 10 01 11 00 09 06", Response::Abort { addr: ObjAddr::new(0x1008, 1), code: 0x0609_0011 }),
        ];
        for (hex, want) in cases {
            let p = bytes(hex);
            assert_eq!(Response::parse(&p), Some(want), "{hex}");
            assert_eq!(want.emit(), p, "{want:?}");
        }
    }

    #[test]
    fn undefined_command_specifiers_are_none() {
        for cmd in [0xE0, 0xFF, 0x81, 0x9F] {
            assert_eq!(Request::parse(&[cmd, 0, 0, 0, 0, 0, 0, 0]), None, "{cmd:02X}");
        }
        for cmd in [0xE0, 0xA3, 0xA7, 0x84] {
            assert_eq!(Response::parse(&[cmd, 0, 0, 0, 0, 0, 0, 0]), None, "{cmd:02X}");
        }
    }

    #[test]
    fn unused_bits_are_ignored() {
        // Bit 4 of an initiate upload response is "x"; a device that sets it still answers.
        assert_eq!(
            Response::parse(&bytes("51 00 14 00 02 00 00 00")),
            Some(Response::InitiateUpload { addr: ObjAddr::new(0x1400, 0), init: Initiate::Size(2) })
        );
        // A segment's bytes beyond its data are not data.
        let Some(Response::UploadSegment(seg)) = Response::parse(&bytes("0B 41 42 FF FF FF FF FF")) else { panic!() };
        assert_eq!((seg.data(), seg.last, seg.frame_len()), (&b"AB"[..], true, 3));
    }

    #[test]
    fn block_segments_carry_their_number_and_the_last_flag() {
        let seg = BlockSegment::parse(&bytes("85 01 02 03 04 05 06 07"));
        assert_eq!((seg.seqno, seg.last, seg.data), (5, true, [1, 2, 3, 4, 5, 6, 7]));
        assert_eq!(seg.emit(), bytes("85 01 02 03 04 05 06 07"));
        assert_eq!(BlockSegment::new(127, &[9], false).emit(), bytes("7F 09"));
    }

    #[test]
    fn sizes_are_32_bit_and_never_cut() {
        assert_eq!(Initiate::segmented(9), Initiate::Size(9));
        assert_eq!(Initiate::segmented(u32::MAX as usize), Initiate::Size(u32::MAX));
        // 4 GiB + 10 bytes do not fit the size field: announced without a size, not as 10.
        assert_eq!(Initiate::segmented((1usize << 32) + 10), Initiate::Unsized);
        let p = bytes("41 08 10 00 FF FF FF FF");
        assert_eq!(Response::parse(&p), Some(Response::InitiateUpload { addr: A1008, init: Initiate::Size(u32::MAX) }));
    }

    #[test]
    fn expedited_data_is_what_the_size_indicates_or_all_four_bytes() {
        assert_eq!(Initiate::expedited(&[1, 2]).expedited_data(), Some(&[1, 2][..]));
        assert_eq!(Initiate::ExpeditedUnsized { data: [1, 2, 3, 4] }.expedited_data(), Some(&[1, 2, 3, 4][..]));
        assert_eq!(Initiate::Size(2).expedited_data(), None);
        assert_eq!(Initiate::Unsized.expedited_data(), None);
    }

    #[test]
    fn a_segment_says_which_bytes_must_have_arrived() {
        assert_eq!(Segment::new(true, b"ABCDEFG", false).frame_len(), 8);
        assert_eq!(Segment::new(false, &[], true).frame_len(), 1);
    }
}
