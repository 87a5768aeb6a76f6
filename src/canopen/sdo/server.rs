//! The SDO server: the device side, used by the simulator.

use super::*;
use crate::canopen::abort;

/// What an SDO server needs from the object dictionary behind it. Errors are abort codes.
pub trait ObjectAccess {
    fn read(&mut self, addr: ObjAddr) -> Result<Vec<u8>, u32>;
    fn write(&mut self, addr: ObjAddr, data: &[u8]) -> Result<(), u32>;
    /// Checked when a segmented or block download starts, so that a write that cannot
    /// succeed is refused before its data crosses the bus.
    fn check_write(&self, addr: ObjAddr, size: Option<usize>) -> Result<(), u32>;
    /// The object's size when its type fixes it: an expedited download that does not
    /// indicate its size writes that many bytes (CiA 301: e=1, s=0).
    fn fixed_size(&self, _addr: ObjAddr) -> Option<usize> {
        None
    }
}

#[derive(Debug, Default)]
enum State {
    #[default]
    Idle,
    Upload {
        addr: ObjAddr,
        data: Vec<u8>,
        pos: usize,
        toggle: bool,
    },
    Download {
        addr: ObjAddr,
        data: Vec<u8>,
        size: Option<usize>,
        toggle: bool,
    },
    BlockDownload {
        addr: ObjAddr,
        data: Vec<u8>,
        size: Option<usize>,
        expected: u8,
        crc: bool,
    },
    BlockDownloadEnd {
        addr: ObjAddr,
        data: Vec<u8>,
        size: Option<usize>,
        crc: bool,
    },
    BlockUploadStart {
        addr: ObjAddr,
        data: Vec<u8>,
        blksize: u8,
        crc: bool,
    },
    BlockUpload {
        addr: ObjAddr,
        data: Vec<u8>,
        acked: usize,
        in_block: usize,
        crc: bool,
    },
    BlockUploadEnd,
}

#[derive(Debug)]
pub struct SdoServer {
    state: State,
    block: bool,
    block_size: u8,
    max_download: usize,
}

impl SdoServer {
    /// `block`: whether this device implements block transfer.
    pub fn new(block: bool) -> SdoServer {
        SdoServer { state: State::Idle, block, block_size: MAX_BLOCK_SIZE, max_download: 1 << 20 }
    }

    /// Handle one request payload; returns the payloads to send back (possibly none).
    pub fn handle(&mut self, raw: &[u8], od: &mut dyn ObjectAccess) -> Vec<[u8; 8]> {
        let p = pad(raw);
        let state = std::mem::take(&mut self.state);
        // In a block download sub-block every frame is a segment, whatever its first byte.
        if let State::BlockDownload { addr, data, size, expected, crc } = state {
            if p[0] == 0x80 {
                return vec![];
            }
            return self.block_download_segment(&p, addr, data, size, expected, crc);
        }
        if abort_code(&p).is_some() {
            return vec![];
        }
        match (p[0] >> 5, state) {
            (2, _) => self.initiate_upload(&p, od),
            (3, State::Upload { addr, data, pos, toggle }) => self.upload_segment(&p, addr, data, pos, toggle),
            (1, _) => self.initiate_download(&p, od),
            (0, State::Download { addr, data, size, toggle }) => {
                self.download_segment(&p, addr, data, size, toggle, od)
            }
            (6, state) if self.block => self.block_download_command(&p, state, od),
            (5, state) if self.block => self.block_upload_command(&p, state, od),
            (_, state) => {
                let addr = match state {
                    State::Upload { addr, .. } | State::Download { addr, .. } => addr,
                    _ => mux(&p),
                };
                vec![abort_frame(addr, abort::UNKNOWN_COMMAND)]
            }
        }
    }

    fn initiate_upload(&mut self, p: &[u8; 8], od: &mut dyn ObjectAccess) -> Vec<[u8; 8]> {
        let addr = mux(p);
        match od.read(addr) {
            Err(code) => vec![abort_frame(addr, code)],
            Ok(data) => self.plain_upload(addr, data),
        }
    }

    fn plain_upload(&mut self, addr: ObjAddr, data: Vec<u8>) -> Vec<[u8; 8]> {
        if (1..=4).contains(&data.len()) {
            return vec![frame(0x43 | ((4 - data.len()) as u8) << 2, addr, &data)];
        }
        let answer = frame(0x41, addr, &(data.len() as u32).to_le_bytes());
        self.state = State::Upload { addr, data, pos: 0, toggle: false };
        vec![answer]
    }

    fn upload_segment(&mut self, p: &[u8; 8], addr: ObjAddr, data: Vec<u8>, pos: usize, toggle: bool) -> Vec<[u8; 8]> {
        if (p[0] & 0x10 != 0) != toggle {
            return vec![abort_frame(addr, abort::TOGGLE_BIT)];
        }
        let end = (pos + SEGMENT_DATA).min(data.len());
        let n = (SEGMENT_DATA - (end - pos)) as u8;
        let last = end == data.len();
        let seg = segment((toggle as u8) << 4 | n << 1 | last as u8, &data[pos..end]);
        if !last {
            self.state = State::Upload { addr, data, pos: end, toggle: !toggle };
        }
        vec![seg]
    }

    fn initiate_download(&mut self, p: &[u8; 8], od: &mut dyn ObjectAccess) -> Vec<[u8; 8]> {
        let addr = mux(p);
        let expedited = p[0] & 0x02 != 0;
        let sized = p[0] & 0x01 != 0;
        if expedited {
            let len = if sized { expedited_len(p[0]) } else { od.fixed_size(addr).filter(|n| *n <= 4).unwrap_or(4) };
            return match od.write(addr, &p[4..4 + len]) {
                Ok(()) => vec![frame(0x60, addr, &[])],
                Err(code) => vec![abort_frame(addr, code)],
            };
        }
        let size = sized.then(|| le_u32(&p[4..]) as usize);
        if let Err(code) = self.check_download(addr, size, od) {
            return vec![abort_frame(addr, code)];
        }
        self.state = State::Download { addr, data: Vec::new(), size, toggle: false };
        vec![frame(0x60, addr, &[])]
    }

    fn check_download(&self, addr: ObjAddr, size: Option<usize>, od: &dyn ObjectAccess) -> Result<(), u32> {
        if size.is_some_and(|s| s > self.max_download) {
            return Err(abort::OUT_OF_MEMORY);
        }
        od.check_write(addr, size)
    }

    fn download_segment(
        &mut self,
        p: &[u8; 8],
        addr: ObjAddr,
        mut data: Vec<u8>,
        size: Option<usize>,
        toggle: bool,
        od: &mut dyn ObjectAccess,
    ) -> Vec<[u8; 8]> {
        if (p[0] & 0x10 != 0) != toggle {
            return vec![abort_frame(addr, abort::TOGGLE_BIT)];
        }
        let n = ((p[0] >> 1) & 7) as usize;
        data.extend_from_slice(&p[1..8 - n]);
        if data.len() > self.max_download {
            return vec![abort_frame(addr, abort::OUT_OF_MEMORY)];
        }
        let ack = segment(0x20 | (toggle as u8) << 4, &[]);
        if p[0] & 0x01 == 0 {
            self.state = State::Download { addr, data, size, toggle: !toggle };
            return vec![ack];
        }
        match finish_download(addr, &data, size, od) {
            Ok(()) => vec![ack],
            Err(code) => vec![abort_frame(addr, code)],
        }
    }

    fn block_download_command(&mut self, p: &[u8; 8], state: State, od: &mut dyn ObjectAccess) -> Vec<[u8; 8]> {
        match (p[0] & 0x01, state) {
            (0, _) => {
                let addr = mux(p);
                let size = (p[0] & 0x02 != 0).then(|| le_u32(&p[4..]) as usize);
                if let Err(code) = self.check_download(addr, size, od) {
                    return vec![abort_frame(addr, code)];
                }
                let crc = p[0] & 0x04 != 0;
                self.state = State::BlockDownload { addr, data: Vec::new(), size, expected: 1, crc };
                vec![frame(0xA4, addr, &[self.block_size])]
            }
            (1, State::BlockDownloadEnd { addr, mut data, size, crc }) => {
                let n = ((p[0] >> 2) & 7) as usize;
                if n > data.len() {
                    return vec![abort_frame(addr, abort::GENERAL_ERROR)];
                }
                data.truncate(data.len() - n);
                if crc && u16::from_le_bytes([p[1], p[2]]) != block_crc(&data) {
                    return vec![abort_frame(addr, abort::CRC_ERROR)];
                }
                match finish_download(addr, &data, size, od) {
                    Ok(()) => vec![segment(0xA1, &[])],
                    Err(code) => vec![abort_frame(addr, code)],
                }
            }
            _ => vec![abort_frame(mux(p), abort::UNKNOWN_COMMAND)],
        }
    }

    fn block_download_segment(
        &mut self,
        p: &[u8; 8],
        addr: ObjAddr,
        mut data: Vec<u8>,
        size: Option<usize>,
        mut expected: u8,
        crc: bool,
    ) -> Vec<[u8; 8]> {
        let seq = p[0] & 0x7F;
        let last = p[0] & 0x80 != 0;
        if seq == expected {
            data.extend_from_slice(&p[1..8]);
            if data.len() > self.max_download + SEGMENT_DATA {
                return vec![abort_frame(addr, abort::OUT_OF_MEMORY)];
            }
            expected += 1;
        }
        if seq == self.block_size || last {
            let ack = segment(0xA2, &[expected - 1, self.block_size]);
            self.state = if last && seq + 1 == expected {
                State::BlockDownloadEnd { addr, data, size, crc }
            } else {
                State::BlockDownload { addr, data, size, expected: 1, crc }
            };
            return vec![ack];
        }
        self.state = State::BlockDownload { addr, data, size, expected, crc };
        vec![]
    }

    fn block_upload_command(&mut self, p: &[u8; 8], state: State, od: &mut dyn ObjectAccess) -> Vec<[u8; 8]> {
        match (p[0] & 0x03, state) {
            (0, _) => {
                let addr = mux(p);
                let (blksize, pst) = (p[4], p[5]);
                if !(1..=MAX_BLOCK_SIZE).contains(&blksize) {
                    return vec![abort_frame(addr, abort::INVALID_BLOCK_SIZE)];
                }
                let data = match od.read(addr) {
                    Ok(d) => d,
                    Err(code) => return vec![abort_frame(addr, code)],
                };
                if pst > 0 && data.len() <= pst as usize {
                    return self.plain_upload(addr, data);
                }
                let crc = p[0] & 0x04 != 0;
                let answer = frame(0xC6, addr, &(data.len() as u32).to_le_bytes());
                self.state = State::BlockUploadStart { addr, data, blksize, crc };
                vec![answer]
            }
            (3, State::BlockUploadStart { addr, data, blksize, crc }) => {
                self.send_upload_block(addr, data, 0, blksize, crc)
            }
            (2, State::BlockUpload { addr, data, acked, in_block, crc, .. }) => {
                let got = p[1] as usize;
                let blksize = p[2];
                if got > in_block {
                    return vec![abort_frame(addr, abort::INVALID_SEQUENCE)];
                }
                if !(1..=MAX_BLOCK_SIZE).contains(&blksize) {
                    return vec![abort_frame(addr, abort::INVALID_BLOCK_SIZE)];
                }
                let acked = acked + got;
                if acked < block_segment_count(data.len()) {
                    return self.send_upload_block(addr, data, acked, blksize, crc);
                }
                let n = block_unused_in_last(data.len());
                let sum = if crc { block_crc(&data) } else { 0 };
                self.state = State::BlockUploadEnd;
                vec![segment(0xC1 | n << 2, &sum.to_le_bytes())]
            }
            (1, State::BlockUploadEnd) => vec![],
            (_, _) => vec![abort_frame(mux(p), abort::UNKNOWN_COMMAND)],
        }
    }

    fn send_upload_block(
        &mut self,
        addr: ObjAddr,
        data: Vec<u8>,
        acked: usize,
        blksize: u8,
        crc: bool,
    ) -> Vec<[u8; 8]> {
        let count = (block_segment_count(data.len()) - acked).min(blksize as usize);
        let frames = block_segments(&data, acked, count);
        self.state = State::BlockUpload { addr, data, acked, in_block: count, crc };
        frames
    }
}

fn finish_download(addr: ObjAddr, data: &[u8], size: Option<usize>, od: &mut dyn ObjectAccess) -> Result<(), u32> {
    match size {
        Some(s) if s < data.len() => Err(abort::LENGTH_TOO_HIGH),
        Some(s) if s > data.len() => Err(abort::LENGTH_TOO_LOW),
        _ => od.write(addr, data),
    }
}
