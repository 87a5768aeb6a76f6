//! The SDO client: one transfer per `SdoClient`.

use super::*;
use crate::canopen::abort;

/// Downloads of at least this many bytes use block transfer when allowed: below it the
/// four extra frames of block set-up cost more than block saves.
pub const BLOCK_DOWNLOAD_MIN: usize = 64;
/// Segments per block we ask servers for on block upload.
const UPLOAD_BLOCK_SIZE: u8 = MAX_BLOCK_SIZE;
/// On block upload, a server may switch to plain upload for objects this small (CiA 301 "pst").
const PROTOCOL_SWITCH_THRESHOLD: u8 = 21;
/// Refuse uploads larger than this rather than grow without bound on a device's word.
pub const DEFAULT_MAX_UPLOAD: usize = 64 << 20;

#[derive(Debug, PartialEq, Eq)]
pub enum SdoError {
    /// The server aborted the transfer with this code.
    ServerAbort(u32),
    /// We must abort: send `abort_frame(addr, code)` and report `reason`.
    ClientAbort { code: u32, reason: String },
    /// The transfer finished but what arrived is inconsistent; nothing more to send.
    Inconsistent(String),
}

/// What to do after feeding a response.
#[derive(Debug, PartialEq, Eq)]
pub struct Step {
    pub send: Vec<[u8; 8]>,
    /// The uploaded bytes (empty for a download) once the transfer is complete.
    pub done: Option<Vec<u8>>,
}

impl Step {
    fn send(frames: Vec<[u8; 8]>) -> Step {
        Step { send: frames, done: None }
    }
    fn wait() -> Step {
        Step { send: Vec::new(), done: None }
    }
    fn done(send: Vec<[u8; 8]>, data: Vec<u8>) -> Step {
        Step { send, done: Some(data) }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    UploadInit,
    UploadSegment,
    BlockUploadInit,
    BlockUploadData { expected: u8 },
    BlockUploadEnd,
    DownloadInit,
    DownloadSegment,
    BlockDownloadInit,
    BlockDownloadData { in_block: usize },
    BlockDownloadEnd,
    Finished,
}

#[derive(Debug)]
pub struct SdoClient {
    addr: ObjAddr,
    state: State,
    /// Upload: bytes received. Download: bytes to send.
    buf: Vec<u8>,
    /// Download: bytes confirmed by the server.
    pos: usize,
    toggle: bool,
    size: Option<usize>,
    crc: bool,
    blksize: u8,
    max_upload: usize,
    fell_back: bool,
}

impl SdoClient {
    fn new(addr: ObjAddr, state: State, buf: Vec<u8>) -> SdoClient {
        SdoClient {
            addr,
            state,
            buf,
            pos: 0,
            toggle: false,
            size: None,
            crc: false,
            blksize: 0,
            max_upload: DEFAULT_MAX_UPLOAD,
            fell_back: false,
        }
    }

    /// An upload; `block` asks for block transfer (servers without it are handled).
    pub fn upload(addr: ObjAddr, block: bool) -> SdoClient {
        let state = if block { State::BlockUploadInit } else { State::UploadInit };
        SdoClient::new(addr, state, Vec::new())
    }

    /// A download; the protocol follows from the size: expedited up to 4 bytes, block from
    /// `BLOCK_DOWNLOAD_MIN` when `block` allows it, segmented otherwise.
    pub fn download(addr: ObjAddr, data: Vec<u8>, block: bool) -> SdoClient {
        let state =
            if block && data.len() >= BLOCK_DOWNLOAD_MIN { State::BlockDownloadInit } else { State::DownloadInit };
        SdoClient::new(addr, state, data)
    }

    pub fn with_max_upload(mut self, max: usize) -> SdoClient {
        self.max_upload = max;
        self
    }

    pub fn addr(&self) -> ObjAddr {
        self.addr
    }

    /// True when block transfer was asked for and the server refused it, so the transfer
    /// went on without it; callers remember this per node.
    pub fn fell_back(&self) -> bool {
        self.fell_back
    }

    /// Bytes moved so far, and the total when known.
    pub fn progress(&self) -> (usize, Option<usize>) {
        match self.state {
            State::UploadInit
            | State::UploadSegment
            | State::BlockUploadInit
            | State::BlockUploadData { .. }
            | State::BlockUploadEnd => (self.buf.len(), self.size),
            _ => (self.pos, Some(self.buf.len())),
        }
    }

    /// The first request.
    pub fn start(&mut self) -> [u8; 8] {
        let a = self.addr;
        match self.state {
            State::UploadInit => frame(0x40, a, &[]),
            State::BlockUploadInit => frame(0xA4, a, &[UPLOAD_BLOCK_SIZE, PROTOCOL_SWITCH_THRESHOLD]),
            State::BlockDownloadInit => frame(0xC6, a, &(self.buf.len() as u32).to_le_bytes()),
            State::DownloadInit => self.initiate_download(),
            s => panic!("start() called in state {s:?}"),
        }
    }

    fn initiate_download(&mut self) -> [u8; 8] {
        let len = self.buf.len();
        if (1..=4).contains(&len) {
            // e=1, s=1, n = 4 - len
            frame(0x23 | (((4 - len) as u8) << 2), self.addr, &self.buf)
        } else {
            frame(0x21, self.addr, &(len as u32).to_le_bytes())
        }
    }

    fn local_abort(&self, code: u32, reason: impl Into<String>) -> SdoError {
        SdoError::ClientAbort { code, reason: reason.into() }
    }

    /// Feed one payload that arrived on the response COB-ID.
    pub fn on_response(&mut self, raw: &[u8]) -> Result<Step, SdoError> {
        let p = pad(raw);
        if let State::BlockUploadData { expected } = self.state {
            // Inside a sub-block every frame is a segment; 0x80 (sequence 0) is an abort.
            if let Some(code) = abort_code(&p) {
                self.state = State::Finished;
                return Err(SdoError::ServerAbort(code));
            }
            return self.block_upload_segment(&p, expected);
        }
        if let Some(code) = abort_code(&p) {
            return self.on_abort(code);
        }
        match self.state {
            State::UploadInit => self.upload_initiated(&p),
            State::UploadSegment => self.upload_segment(&p),
            State::BlockUploadInit => self.block_upload_initiated(&p),
            State::BlockUploadEnd => self.block_upload_end(&p),
            State::DownloadInit => self.download_initiated(&p),
            State::DownloadSegment => self.download_segment_acked(&p),
            State::BlockDownloadInit => self.block_download_initiated(&p),
            State::BlockDownloadData { in_block } => self.block_download_acked(&p, in_block),
            State::BlockDownloadEnd => self.block_download_end(&p),
            State::BlockUploadData { .. } => unreachable!(),
            State::Finished => Ok(Step::wait()),
        }
    }

    fn on_abort(&mut self, code: u32) -> Result<Step, SdoError> {
        // A server without block transfer says "command specifier unknown"; the same
        // transfer then goes on with the plain protocol (CiA 301 leaves this to the client).
        if code == abort::UNKNOWN_COMMAND {
            match self.state {
                State::BlockUploadInit => {
                    self.fell_back = true;
                    self.state = State::UploadInit;
                    return Ok(Step::send(vec![self.start()]));
                }
                State::BlockDownloadInit => {
                    self.fell_back = true;
                    self.state = State::DownloadInit;
                    return Ok(Step::send(vec![self.start()]));
                }
                _ => {}
            }
        }
        self.state = State::Finished;
        Err(SdoError::ServerAbort(code))
    }

    fn check_mux(&self, p: &[u8; 8]) -> Result<(), SdoError> {
        if mux(p) != self.addr {
            return Err(self
                .local_abort(abort::GENERAL_ERROR, format!("the answer names object {}, not {}", mux(p), self.addr)));
        }
        Ok(())
    }

    fn unexpected(&mut self, p: &[u8; 8]) -> SdoError {
        self.state = State::Finished;
        self.local_abort(abort::UNKNOWN_COMMAND, format!("unexpected command byte 0x{:02X} from the server", p[0]))
    }

    fn check_size(&mut self, size: usize) -> Result<(), SdoError> {
        if size > self.max_upload {
            self.state = State::Finished;
            return Err(self.local_abort(
                abort::OUT_OF_MEMORY,
                format!("the object is {size} bytes, over the {} byte limit", self.max_upload),
            ));
        }
        Ok(())
    }

    fn upload_initiated(&mut self, p: &[u8; 8]) -> Result<Step, SdoError> {
        if p[0] & 0xE0 != 0x40 {
            return Err(self.unexpected(p));
        }
        self.check_mux(p)?;
        let expedited = p[0] & 0x02 != 0;
        let sized = p[0] & 0x01 != 0;
        if expedited {
            let len = expedited_len(p[0]);
            self.state = State::Finished;
            return Ok(Step::done(vec![], p[4..4 + len].to_vec()));
        }
        if sized {
            let size = le_u32(&p[4..]) as usize;
            self.check_size(size)?;
            self.size = Some(size);
            self.buf.reserve(size);
        }
        self.state = State::UploadSegment;
        self.toggle = false;
        Ok(Step::send(vec![segment(0x60, &[])]))
    }

    fn upload_segment(&mut self, p: &[u8; 8]) -> Result<Step, SdoError> {
        if p[0] & 0xE0 != 0x00 {
            return Err(self.unexpected(p));
        }
        if (p[0] & 0x10 != 0) != self.toggle {
            self.state = State::Finished;
            return Err(self.local_abort(abort::TOGGLE_BIT, "toggle bit not alternated"));
        }
        let n = ((p[0] >> 1) & 7) as usize;
        self.buf.extend_from_slice(&p[1..8 - n]);
        self.check_size(self.buf.len())?;
        if p[0] & 0x01 != 0 {
            self.state = State::Finished;
            return self.finish_upload(vec![]);
        }
        self.toggle = !self.toggle;
        Ok(Step::send(vec![segment(0x60 | (self.toggle as u8) << 4, &[])]))
    }

    fn finish_upload(&mut self, send: Vec<[u8; 8]>) -> Result<Step, SdoError> {
        if let Some(size) = self.size {
            if size != self.buf.len() {
                return Err(SdoError::Inconsistent(format!(
                    "the server announced {size} bytes and sent {}",
                    self.buf.len()
                )));
            }
        }
        Ok(Step::done(send, std::mem::take(&mut self.buf)))
    }

    fn block_upload_initiated(&mut self, p: &[u8; 8]) -> Result<Step, SdoError> {
        match p[0] & 0xE0 {
            // The server used the protocol switch threshold: plain upload from here.
            0x40 => {
                self.state = State::UploadInit;
                self.upload_initiated(p)
            }
            0xC0 if p[0] & 0x01 == 0 => {
                self.check_mux(p)?;
                self.crc = p[0] & 0x04 != 0;
                if p[0] & 0x02 != 0 {
                    let size = le_u32(&p[4..]) as usize;
                    self.check_size(size)?;
                    self.size = Some(size);
                    self.buf.reserve(size);
                }
                self.blksize = UPLOAD_BLOCK_SIZE;
                self.state = State::BlockUploadData { expected: 1 };
                Ok(Step::send(vec![segment(0xA3, &[])]))
            }
            _ => Err(self.unexpected(p)),
        }
    }

    fn block_upload_segment(&mut self, p: &[u8; 8], expected: u8) -> Result<Step, SdoError> {
        let seq = p[0] & 0x7F;
        let last = p[0] & 0x80 != 0;
        let mut expected = expected;
        if seq == expected {
            self.buf.extend_from_slice(&p[1..8]);
            self.check_size(self.buf.len().saturating_sub(7))?;
            expected += 1;
        }
        // Lost or repeated segments are not stored; the acknowledgement below tells the
        // server the last one received in order, and it repeats from there.
        let in_order_last = last && seq + 1 == expected;
        if seq == self.blksize || last {
            let ack = segment(0xA2, &[expected - 1, self.blksize]);
            self.state = if in_order_last { State::BlockUploadEnd } else { State::BlockUploadData { expected: 1 } };
            return Ok(Step::send(vec![ack]));
        }
        self.state = State::BlockUploadData { expected };
        Ok(Step::wait())
    }

    fn block_upload_end(&mut self, p: &[u8; 8]) -> Result<Step, SdoError> {
        if p[0] & 0xE3 != 0xC1 {
            return Err(self.unexpected(p));
        }
        self.state = State::Finished;
        let n = ((p[0] >> 2) & 7) as usize;
        if n > self.buf.len() {
            return Err(self.local_abort(abort::GENERAL_ERROR, "block end claims more unused bytes than were sent"));
        }
        self.buf.truncate(self.buf.len() - n);
        if self.crc {
            let got = u16::from_le_bytes([p[1], p[2]]);
            let want = block_crc(&self.buf);
            if got != want {
                return Err(self.local_abort(
                    abort::CRC_ERROR,
                    format!("block CRC 0x{got:04X} does not match the data (0x{want:04X})"),
                ));
            }
        }
        self.finish_upload(vec![segment(0xA1, &[])])
    }

    fn download_initiated(&mut self, p: &[u8; 8]) -> Result<Step, SdoError> {
        if p[0] & 0xE0 != 0x60 {
            return Err(self.unexpected(p));
        }
        self.check_mux(p)?;
        if (1..=4).contains(&self.buf.len()) {
            self.pos = self.buf.len();
            self.state = State::Finished;
            return Ok(Step::done(vec![], vec![]));
        }
        self.toggle = false;
        self.state = State::DownloadSegment;
        Ok(Step::send(vec![self.next_segment()]))
    }

    fn next_segment(&self) -> [u8; 8] {
        let end = (self.pos + SEGMENT_DATA).min(self.buf.len());
        let chunk = &self.buf[self.pos..end];
        let n = (SEGMENT_DATA - chunk.len()) as u8;
        let last = end == self.buf.len();
        segment((self.toggle as u8) << 4 | n << 1 | last as u8, chunk)
    }

    fn download_segment_acked(&mut self, p: &[u8; 8]) -> Result<Step, SdoError> {
        if p[0] & 0xE0 != 0x20 {
            return Err(self.unexpected(p));
        }
        if (p[0] & 0x10 != 0) != self.toggle {
            self.state = State::Finished;
            return Err(self.local_abort(abort::TOGGLE_BIT, "toggle bit not alternated"));
        }
        self.pos = (self.pos + SEGMENT_DATA).min(self.buf.len());
        if self.pos == self.buf.len() {
            self.state = State::Finished;
            return Ok(Step::done(vec![], vec![]));
        }
        self.toggle = !self.toggle;
        Ok(Step::send(vec![self.next_segment()]))
    }

    /// Send the next sub-block, starting at the first unconfirmed segment.
    fn send_block(&mut self) -> Step {
        let first = self.pos / SEGMENT_DATA;
        let count = (block_segment_count(self.buf.len()) - first).min(self.blksize as usize);
        self.state = State::BlockDownloadData { in_block: count };
        Step::send(block_segments(&self.buf, first, count))
    }

    fn block_download_initiated(&mut self, p: &[u8; 8]) -> Result<Step, SdoError> {
        if p[0] & 0xE3 != 0xA0 {
            return Err(self.unexpected(p));
        }
        self.check_mux(p)?;
        self.crc = p[0] & 0x04 != 0;
        self.blksize = p[4];
        if !(1..=MAX_BLOCK_SIZE).contains(&self.blksize) {
            self.state = State::Finished;
            return Err(
                self.local_abort(abort::INVALID_BLOCK_SIZE, format!("the server asked for block size {}", p[4]))
            );
        }
        Ok(self.send_block())
    }

    fn block_download_acked(&mut self, p: &[u8; 8], in_block: usize) -> Result<Step, SdoError> {
        if p[0] & 0xE3 != 0xA2 {
            return Err(self.unexpected(p));
        }
        let acked = p[1] as usize;
        if acked > in_block {
            self.state = State::Finished;
            return Err(self.local_abort(
                abort::INVALID_SEQUENCE,
                format!("acknowledged segment {acked} of a {in_block}-segment block"),
            ));
        }
        self.pos = ((self.pos / SEGMENT_DATA + acked) * SEGMENT_DATA).min(self.buf.len());
        self.blksize = p[2];
        if !(1..=MAX_BLOCK_SIZE).contains(&self.blksize) {
            self.state = State::Finished;
            return Err(
                self.local_abort(abort::INVALID_BLOCK_SIZE, format!("the server asked for block size {}", p[2]))
            );
        }
        if self.pos < self.buf.len() {
            return Ok(self.send_block());
        }
        let n = block_unused_in_last(self.buf.len());
        let crc = if self.crc { block_crc(&self.buf) } else { 0 };
        self.state = State::BlockDownloadEnd;
        let [lo, hi] = crc.to_le_bytes();
        Ok(Step::send(vec![segment(0xC1 | n << 2, &[lo, hi])]))
    }

    fn block_download_end(&mut self, p: &[u8; 8]) -> Result<Step, SdoError> {
        if p[0] & 0xE3 != 0xA1 {
            return Err(self.unexpected(p));
        }
        self.state = State::Finished;
        Ok(Step::done(vec![], vec![]))
    }
}
