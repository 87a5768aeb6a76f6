//! What both sides of an SDO transfer share: the default channel's COB-IDs, the abort
//! frame, padding a short payload, and cutting data into block-transfer segments.

use super::wire::{BlockSegment, Request, SEGMENT_DATA};
use crate::ObjAddr;

/// Client → server COB-ID of the default SDO channel.
pub fn request_cob(node: u8) -> u16 {
    0x600 + node as u16
}

/// Server → client COB-ID of the default SDO channel.
pub fn response_cob(node: u8) -> u16 {
    0x580 + node as u16
}

/// Largest block size CiA 301 allows (segments per block).
pub const MAX_BLOCK_SIZE: u8 = 127;

/// The two CRC-16 variants named in CiA 301 for block transfer are the same polynomial
/// 0x1021 with initial value 0, i.e. CRC-16/XMODEM.
pub(crate) fn block_crc(data: &[u8]) -> u16 {
    crc::Crc::<u16>::new(&crc::CRC_16_XMODEM).checksum(data)
}

/// The abort frame for `addr` with `code` (either side sends the same).
pub fn abort_frame(addr: ObjAddr, code: u32) -> [u8; 8] {
    Request::Abort { addr, code }.emit()
}

/// A payload of up to 8 bytes in an 8-byte array, the missing bytes as zero. Devices may
/// send frames with a DLC under 8 (seed 004 shows a 5-byte expedited answer); whoever reads
/// the padded array must know how many bytes were really there: the SDO client checks that
/// every byte the command specifier makes meaningful arrived, and never takes padding as data.
pub fn pad(data: &[u8]) -> [u8; 8] {
    let mut f = [0u8; 8];
    let n = data.len().min(8);
    f[..n].copy_from_slice(&data[..n]);
    f
}

/// Segments needed for `len` bytes in block transfer (at least one, even for no data).
pub(super) fn block_segment_count(len: usize) -> usize {
    len.div_ceil(SEGMENT_DATA).max(1)
}

/// The `n` of a block end frame: bytes of the last segment that carry no data.
pub(super) fn block_unused_in_last(len: usize) -> u8 {
    (SEGMENT_DATA * block_segment_count(len) - len) as u8
}

/// One sub-block: `count` segments starting at segment index `first`, numbered from 1,
/// the overall last one flagged.
pub(super) fn block_segments(data: &[u8], first: usize, count: usize) -> Vec<[u8; 8]> {
    let total = block_segment_count(data.len());
    (0..count)
        .map(|i| {
            let start = ((first + i) * SEGMENT_DATA).min(data.len());
            let chunk = &data[start..(start + SEGMENT_DATA).min(data.len())];
            BlockSegment::new((i + 1) as u8, chunk, first + i + 1 == total).emit()
        })
        .collect()
}
