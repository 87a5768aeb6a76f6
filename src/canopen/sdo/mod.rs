//! SDO (CiA 301 §7.2.4): expedited, segmented and block transfer, as pure state machines.
//!
//! Both sides take a received 8-byte payload and return the payloads to send; the caller
//! owns the link, the clock and the timeouts.

pub mod client;
pub mod server;

pub use client::{SdoClient, SdoError, Step};
pub use server::{ObjectAccess, SdoServer};

use crate::canopen::ObjAddr;

/// Client → server COB-ID of the default SDO channel.
pub fn request_cob(node: u8) -> u16 {
    0x600 + node as u16
}

/// Server → client COB-ID of the default SDO channel.
pub fn response_cob(node: u8) -> u16 {
    0x580 + node as u16
}

/// Payload bytes in one segment.
pub const SEGMENT_DATA: usize = 7;
/// Largest block size CiA 301 allows (segments per block).
pub const MAX_BLOCK_SIZE: u8 = 127;

/// The two CRC-16 variants named in CiA 301 for block transfer are the same polynomial
/// 0x1021 with initial value 0, i.e. CRC-16/XMODEM.
pub fn block_crc(data: &[u8]) -> u16 {
    crc::Crc::<u16>::new(&crc::CRC_16_XMODEM).checksum(data)
}

pub fn abort_frame(addr: ObjAddr, code: u32) -> [u8; 8] {
    frame(0x80, addr, &code.to_le_bytes())
}

/// If this payload is an abort, the abort code.
pub fn abort_code(p: &[u8; 8]) -> Option<u32> {
    (p[0] == 0x80).then(|| u32::from_le_bytes([p[4], p[5], p[6], p[7]]))
}

/// A payload with command byte, multiplexer and up to four data bytes.
pub fn frame(cmd: u8, addr: ObjAddr, data: &[u8]) -> [u8; 8] {
    let mut f = [0u8; 8];
    f[0] = cmd;
    f[1..4].copy_from_slice(&addr.to_mux());
    f[4..4 + data.len()].copy_from_slice(data);
    f
}

/// A segment: command byte then up to seven bytes of data.
pub fn segment(cmd: u8, data: &[u8]) -> [u8; 8] {
    let mut f = [0u8; 8];
    f[0] = cmd;
    f[1..1 + data.len()].copy_from_slice(data);
    f
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

/// Data bytes in an expedited transfer: `4 - n` when the size is indicated, else all four.
pub fn expedited_len(cmd: u8) -> usize {
    if cmd & 0x01 != 0 {
        4 - ((cmd >> 2) & 3) as usize
    } else {
        4
    }
}

/// Segments needed for `len` bytes in block transfer (at least one, even for no data).
fn block_segment_count(len: usize) -> usize {
    len.div_ceil(SEGMENT_DATA).max(1)
}

/// The `n` of a block end frame: bytes of the last segment that carry no data.
fn block_unused_in_last(len: usize) -> u8 {
    (SEGMENT_DATA * block_segment_count(len) - len) as u8
}

/// One sub-block: `count` segments starting at segment index `first`, numbered from 1,
/// the overall last one flagged with bit 7.
fn block_segments(data: &[u8], first: usize, count: usize) -> Vec<[u8; 8]> {
    let total = block_segment_count(data.len());
    (0..count)
        .map(|i| {
            let start = ((first + i) * SEGMENT_DATA).min(data.len());
            let chunk = &data[start..(start + SEGMENT_DATA).min(data.len())];
            segment(((first + i + 1 == total) as u8) << 7 | (i + 1) as u8, chunk)
        })
        .collect()
}

fn mux(p: &[u8; 8]) -> ObjAddr {
    ObjAddr::from_mux(&p[1..4])
}

fn le_u32(b: &[u8]) -> u32 {
    u32::from_le_bytes([b[0], b[1], b[2], b[3]])
}

#[cfg(test)]
mod tests;
