//! The SDO server: the device side, used by the simulator.

use super::shared::{
    abort_frame, block_crc, block_segment_count, block_segments, block_unused_in_last, pad, MAX_BLOCK_SIZE,
};
use super::wire::{BlockSegment, Initiate, Request, Response, Segment, SEGMENT_DATA};
use crate::abort;
use crate::ObjAddr;

/// What an SDO server needs from the object dictionary behind it. Errors are abort codes.
pub trait ObjectAccess {
    /// The bytes of the object at `addr`, or the abort code the server answers with.
    fn read(&mut self, addr: ObjAddr) -> Result<Vec<u8>, u32>;
    /// Stores `data` at `addr`, or returns the abort code the server answers with.
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

/// The server side of SDO transfers (the simulated devices'): fed requests, it answers them from an
/// [`ObjectAccess`], expedited, segmented or block.
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
        let request = Request::parse(&p);
        let state = std::mem::take(&mut self.state);
        // In a block download sub-block every frame is a segment, whatever its first byte.
        if let State::BlockDownload { addr, data, size, expected, crc } = state {
            if let Some(Request::Abort { .. }) = request {
                return vec![];
            }
            return self.block_download_segment(BlockSegment::parse(&p), addr, data, size, expected, crc);
        }
        match (request, state) {
            (Some(Request::Abort { .. }), _) => vec![],
            (Some(Request::InitiateUpload { addr }), _) => self.initiate_upload(addr, od),
            (Some(Request::UploadSegment { toggle }), State::Upload { addr, data, pos, toggle: expected }) => {
                self.upload_segment(toggle, addr, data, pos, expected)
            }
            (Some(Request::InitiateDownload { addr, init }), _) => self.initiate_download(addr, init, od),
            (Some(Request::DownloadSegment(seg)), State::Download { addr, data, size, toggle }) => {
                self.download_segment(seg, addr, data, size, toggle, od)
            }
            (
                Some(
                    r @ (Request::BlockDownload { .. }
                    | Request::BlockDownloadEnd { .. }
                    | Request::BlockUpload { .. }
                    | Request::BlockUploadStart
                    | Request::BlockUploadAck { .. }
                    | Request::BlockUploadEnd),
                ),
                state,
            ) if self.block => self.block_command(&p, r, state, od),
            (_, state) => {
                let addr = match state {
                    State::Upload { addr, .. } | State::Download { addr, .. } => addr,
                    _ => ObjAddr::from_mux(&p[1..4]),
                };
                vec![abort_frame(addr, abort::UNKNOWN_COMMAND)]
            }
        }
    }

    fn initiate_upload(&mut self, addr: ObjAddr, od: &mut dyn ObjectAccess) -> Vec<[u8; 8]> {
        od.read(addr).map_or_else(|code| vec![abort_frame(addr, code)], |data| self.plain_upload(addr, data))
    }

    fn plain_upload(&mut self, addr: ObjAddr, data: Vec<u8>) -> Vec<[u8; 8]> {
        if (1..=4).contains(&data.len()) {
            return vec![Response::InitiateUpload { addr, init: Initiate::expedited(&data) }.emit()];
        }
        let answer = Response::InitiateUpload { addr, init: Initiate::segmented(data.len()) }.emit();
        self.state = State::Upload { addr, data, pos: 0, toggle: false };
        vec![answer]
    }

    fn upload_segment(
        &mut self,
        toggle: bool,
        addr: ObjAddr,
        data: Vec<u8>,
        pos: usize,
        expected: bool,
    ) -> Vec<[u8; 8]> {
        if toggle != expected {
            return vec![abort_frame(addr, abort::TOGGLE_BIT)];
        }
        let end = (pos + SEGMENT_DATA).min(data.len());
        let last = end == data.len();
        let seg = Response::UploadSegment(Segment::new(toggle, &data[pos..end], last)).emit();
        if !last {
            self.state = State::Upload { addr, data, pos: end, toggle: !toggle };
        }
        vec![seg]
    }

    fn initiate_download(&mut self, addr: ObjAddr, init: Initiate, od: &mut dyn ObjectAccess) -> Vec<[u8; 8]> {
        let expedited = match init {
            Initiate::Expedited { data, len } => Some((data, len as usize)),
            Initiate::ExpeditedUnsized { data } => Some((data, od.fixed_size(addr).filter(|n| *n <= 4).unwrap_or(4))),
            Initiate::Size(_) | Initiate::Unsized => None,
        };
        if let Some((data, len)) = expedited {
            return match od.write(addr, &data[..len]) {
                Ok(()) => vec![Response::InitiateDownload { addr }.emit()],
                Err(code) => vec![abort_frame(addr, code)],
            };
        }
        let size = match init {
            Initiate::Size(s) => Some(announced(s)),
            _ => None,
        };
        if let Err(code) = self.check_download(addr, size, od) {
            return vec![abort_frame(addr, code)];
        }
        self.state = State::Download { addr, data: Vec::new(), size, toggle: false };
        vec![Response::InitiateDownload { addr }.emit()]
    }

    fn check_download(&self, addr: ObjAddr, size: Option<usize>, od: &dyn ObjectAccess) -> Result<(), u32> {
        if size.is_some_and(|s| s > self.max_download) {
            return Err(abort::OUT_OF_MEMORY);
        }
        od.check_write(addr, size)
    }

    fn download_segment(
        &mut self,
        seg: Segment,
        addr: ObjAddr,
        mut data: Vec<u8>,
        size: Option<usize>,
        toggle: bool,
        od: &mut dyn ObjectAccess,
    ) -> Vec<[u8; 8]> {
        if seg.toggle != toggle {
            return vec![abort_frame(addr, abort::TOGGLE_BIT)];
        }
        data.extend_from_slice(seg.data());
        if data.len() > self.max_download {
            return vec![abort_frame(addr, abort::OUT_OF_MEMORY)];
        }
        let ack = Response::DownloadSegment { toggle }.emit();
        if !seg.last {
            self.state = State::Download { addr, data, size, toggle: !toggle };
            return vec![ack];
        }
        finish_download(addr, &data, size, od).map_or_else(|code| vec![abort_frame(addr, code)], |()| vec![ack])
    }

    /// Block download and block upload requests outside a sub-block.
    fn block_command(
        &mut self,
        p: &[u8; 8],
        request: Request,
        state: State,
        od: &mut dyn ObjectAccess,
    ) -> Vec<[u8; 8]> {
        match (request, state) {
            (Request::BlockDownload { addr, crc, size }, _) => {
                let size = size.map(announced);
                if let Err(code) = self.check_download(addr, size, od) {
                    return vec![abort_frame(addr, code)];
                }
                self.state = State::BlockDownload { addr, data: Vec::new(), size, expected: 1, crc };
                vec![Response::BlockDownload { addr, crc: true, blksize: self.block_size }.emit()]
            }
            (Request::BlockDownloadEnd { unused, crc: sum }, State::BlockDownloadEnd { addr, mut data, size, crc }) => {
                let n = unused as usize;
                if n > data.len() {
                    return vec![abort_frame(addr, abort::GENERAL_ERROR)];
                }
                data.truncate(data.len() - n);
                if crc && sum != block_crc(&data) {
                    return vec![abort_frame(addr, abort::CRC_ERROR)];
                }
                let end = Response::BlockDownloadEnd.emit();
                finish_download(addr, &data, size, od).map_or_else(|code| vec![abort_frame(addr, code)], |()| vec![end])
            }
            (Request::BlockUpload { addr, crc, blksize, pst }, _) => {
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
                let size = u32::try_from(data.len()).ok();
                let answer = Response::BlockUpload { addr, crc: true, size }.emit();
                self.state = State::BlockUploadStart { addr, data, blksize, crc };
                vec![answer]
            }
            (Request::BlockUploadStart, State::BlockUploadStart { addr, data, blksize, crc }) => {
                self.send_upload_block(addr, data, 0, blksize, crc)
            }
            (
                Request::BlockUploadAck { ackseq, blksize },
                State::BlockUpload { addr, data, acked, in_block, crc, .. },
            ) => {
                let got = ackseq as usize;
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
                let unused = block_unused_in_last(data.len());
                let sum = if crc { block_crc(&data) } else { 0 };
                self.state = State::BlockUploadEnd;
                vec![Response::BlockUploadEnd { unused, crc: sum }.emit()]
            }
            (Request::BlockUploadEnd, State::BlockUploadEnd) => vec![],
            _ => vec![abort_frame(ObjAddr::from_mux(&p[1..4]), abort::UNKNOWN_COMMAND)],
        }
    }

    fn block_download_segment(
        &mut self,
        seg: BlockSegment,
        addr: ObjAddr,
        mut data: Vec<u8>,
        size: Option<usize>,
        mut expected: u8,
        crc: bool,
    ) -> Vec<[u8; 8]> {
        let BlockSegment { seqno: seq, last, data: chunk } = seg;
        if seq == expected {
            data.extend_from_slice(&chunk);
            if data.len() > self.max_download + SEGMENT_DATA {
                return vec![abort_frame(addr, abort::OUT_OF_MEMORY)];
            }
            expected += 1;
        }
        if seq == self.block_size || last {
            let ack = Response::BlockDownloadAck { ackseq: expected - 1, blksize: self.block_size }.emit();
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

/// A size a client announced, as CiA 301 carries it: 32 bits, unsigned.
fn announced(size: u32) -> usize {
    usize::try_from(size).unwrap_or(usize::MAX)
}

fn finish_download(addr: ObjAddr, data: &[u8], size: Option<usize>, od: &mut dyn ObjectAccess) -> Result<(), u32> {
    match size {
        Some(s) if s < data.len() => Err(abort::LENGTH_TOO_HIGH),
        Some(s) if s > data.len() => Err(abort::LENGTH_TOO_LOW),
        _ => od.write(addr, data),
    }
}
