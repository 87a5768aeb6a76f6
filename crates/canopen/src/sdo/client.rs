//! The SDO client: one transfer per `SdoClient`.

use super::shared::{pad, MAX_BLOCK_SIZE};
use super::wire::{BlockSegment, Initiate, Request, Response, Segment, SEGMENT_DATA};
use crate::abort;
use crate::ObjAddr;
use std::time::Duration;

mod block;

/// Downloads of at least this many bytes use block transfer when allowed: below it the
/// four extra frames of block set-up cost more than block saves.
pub(crate) const BLOCK_DOWNLOAD_MIN: usize = 64;
/// Segments per block we ask servers for on block upload.
const UPLOAD_BLOCK_SIZE: u8 = MAX_BLOCK_SIZE;
/// On block upload, a server may switch to plain upload for objects this small (CiA 301 "pst").
const PROTOCOL_SWITCH_THRESHOLD: u8 = 21;
/// Uploads stop at this size unless the caller allows more: a device that never ends an
/// upload must not fill memory (or the terminal) first. Objects read in the field are far
/// smaller; firmware read-back raises it (`sdo read --max-size`).
pub const DEFAULT_MAX_UPLOAD: usize = 1 << 20;
/// Sub-blocks in a row that move no data before the client gives up on a block transfer:
/// a device that never acknowledges in sequence (or never sends in sequence) would
/// otherwise be answered with the same sub-block forever.
pub const MAX_BLOCK_RETRANSMISSIONS: u32 = 4;

/// Why an SDO transfer failed, as the client state machine sees it.
#[derive(Debug, PartialEq, Eq)]
// Exhaustive on purpose: canctl words every variant, and the compiler says when one is new.
pub enum SdoError {
    /// The server aborted the transfer with this code.
    ServerAbort(u32),
    /// We must abort: send `abort_frame(addr, code)` and report `reason`.
    ClientAbort {
        /// The abort code to send.
        code: u32,
        /// What went wrong, in words.
        reason: String,
    },
    /// The transfer finished but what arrived is inconsistent; nothing more to send.
    Inconsistent(String),
    /// An upload went on past the limit without ending (a device that never sets the
    /// last-segment bit): we must abort with `abort::OUT_OF_MEMORY`.
    OverLimit {
        /// The limit, in bytes.
        limit: usize,
        /// The bytes that had arrived when it was stopped.
        received: usize,
    },
}

/// What to do after feeding a response.
#[derive(Debug, PartialEq, Eq)]
pub struct Step {
    /// Frames to send now, in order.
    pub send: Vec<[u8; 8]>,
    /// The uploaded bytes (empty for a download) once the transfer is complete.
    pub done: Option<Vec<u8>>,
    /// Whether this answer advanced the transfer. Duplicates, late answers for another
    /// object and retransmission requests do not: the caller's no-progress timer keeps
    /// running through them.
    pub progress: bool,
}

impl Step {
    fn send(frames: Vec<[u8; 8]>) -> Step {
        Step { send: frames, done: None, progress: true }
    }
    fn wait() -> Step {
        Step { send: Vec::new(), done: None, progress: true }
    }
    fn done(send: Vec<[u8; 8]>, data: Vec<u8>) -> Step {
        Step { send, done: Some(data), progress: true }
    }
    /// Something to send that moves nothing forward (a retransmission request).
    fn retry(frames: Vec<[u8; 8]>) -> Step {
        Step { send: frames, done: None, progress: false }
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

/// The client side of one SDO transfer (expedited, segmented or block), pure: fed the server's
/// frames, it says what to send next.
#[derive(Debug)]
pub struct SdoClient {
    addr: ObjAddr,
    state: State,
    upload: bool,
    /// Upload: bytes received. Download: bytes to send.
    buf: Vec<u8>,
    /// Download: bytes confirmed by the server.
    pos: usize,
    toggle: bool,
    /// Upload: the size the server announced.
    size: Option<usize>,
    crc: bool,
    blksize: u8,
    max_upload: usize,
    /// Upload: the size of the type the caller asked for, for an expedited answer that
    /// does not indicate its size.
    size_hint: Option<usize>,
    fell_back: bool,
    /// The answer being handled and its length (a frame may be shorter than 8 bytes); kept
    /// to recognise the next answer as a repeat of it.
    last: Option<([u8; 8], usize)>,
    /// Sub-blocks in a row that moved no data.
    fruitless: u32,
    /// Block upload: bytes of the final segment that its frame did not carry.
    tail_missing: usize,
    /// The last answer of the previous transfer with this server, which may come a second
    /// time (CAN double reception) before the first answer of this one.
    previous: Option<([u8; 8], usize)>,
    /// Answers set aside without effect, and what the last one was.
    ignored: usize,
    last_ignored: Option<String>,
    /// Whether this is a repeat attempt ([`SdoClient::restart`]): until its first answer,
    /// what the abandoned attempt still gets (a late segment, an acknowledgement) is set
    /// aside, not taken for an error or for this attempt's answer.
    restarted: bool,
    /// Whether the transfer began as a block transfer (what a restart begins with again,
    /// unless the server refused it).
    block: bool,
}

impl SdoClient {
    fn new(addr: ObjAddr, state: State, buf: Vec<u8>) -> SdoClient {
        SdoClient {
            addr,
            state,
            upload: matches!(state, State::UploadInit | State::BlockUploadInit),
            buf,
            pos: 0,
            toggle: false,
            size: None,
            crc: false,
            blksize: 0,
            max_upload: DEFAULT_MAX_UPLOAD,
            size_hint: None,
            fell_back: false,
            last: None,
            fruitless: 0,
            tail_missing: 0,
            previous: None,
            ignored: 0,
            last_ignored: None,
            restarted: false,
            block: matches!(state, State::BlockUploadInit | State::BlockDownloadInit),
        }
    }

    /// An upload; `block` asks for block transfer (servers without it are handled).
    pub fn upload(addr: ObjAddr, block: bool) -> SdoClient {
        let state = if block { State::BlockUploadInit } else { State::UploadInit };
        SdoClient::new(addr, state, Vec::new())
    }

    /// A download; the protocol follows from the size: expedited up to 4 bytes, block from
    /// `BLOCK_DOWNLOAD_MIN` when `block` allows it, segmented otherwise. Sizes travel as
    /// 32-bit values: callers refuse data over `u32::MAX` bytes before this.
    pub fn download(addr: ObjAddr, data: Vec<u8>, block: bool) -> SdoClient {
        let state =
            if block && data.len() >= BLOCK_DOWNLOAD_MIN { State::BlockDownloadInit } else { State::DownloadInit };
        SdoClient::new(addr, state, data)
    }

    /// Stop an upload that grows past `max` bytes, and refuse one announced larger.
    pub fn with_max_upload(mut self, max: usize) -> SdoClient {
        self.max_upload = max;
        self
    }

    /// The size of the type the caller expects: an expedited answer without its size
    /// indicated carries that many bytes (all four when unknown).
    pub fn with_size_hint(mut self, size: Option<usize>) -> SdoClient {
        self.size_hint = size;
        self
    }

    /// The last answer of the previous transfer with the same server: a second copy of it
    /// arriving before this transfer's first answer is set aside, not taken for an error.
    pub fn set_previous_answer(&mut self, raw: &[u8]) {
        self.previous = Some((pad(raw), raw.len().min(8)));
    }

    /// The object transferred.
    pub fn addr(&self) -> ObjAddr {
        self.addr
    }

    /// True when block transfer was asked for and the server refused it, so the transfer
    /// went on without it; callers remember this per node.
    pub fn fell_back(&self) -> bool {
        self.fell_back
    }

    /// A download's data.
    pub fn written(&self) -> Option<&[u8]> {
        (!self.upload).then_some(self.buf.as_slice())
    }

    /// Whether this transfer reads from the server.
    pub fn is_upload(&self) -> bool {
        self.upload
    }

    /// How many frames the server will still send for what this client has already sent,
    /// were it stopped now: the rest of a sub-block it is sending, or the one answer to
    /// the request it has. After an abort, a server that finishes what it started sends
    /// them anyway; a program that leaves before they arrive hands them to the next one.
    pub fn answers_in_flight(&self) -> usize {
        match self.state {
            State::BlockUploadData { expected } => {
                usize::from(self.blksize).saturating_sub(usize::from(expected.saturating_sub(1)))
            }
            State::Finished => 0,
            _ => 1,
        }
    }

    /// Bytes moved so far, and the total when known.
    pub fn progress(&self) -> (usize, Option<usize>) {
        if self.upload {
            (self.buf.len(), self.size)
        } else {
            (self.pos, Some(self.buf.len()))
        }
    }

    /// How many answers were set aside without effect (repeats, late answers for another
    /// object, segments out of sequence), and what the last of them was.
    pub fn ignored(&self) -> Option<(usize, &str)> {
        self.last_ignored.as_deref().map(|what| (self.ignored, what))
    }

    /// The longest the whole transfer may take when each answer may take `per_answer`:
    /// four answers' time to set up and finish, then half of one per segment of the size
    /// (the size when known, else the upload limit). A device that answers in time now
    /// and then, but keeps the transfer going far slower than that, ends here.
    pub fn time_budget(&self, per_answer: Duration) -> Duration {
        let size = match self.progress() {
            (_, Some(total)) => total,
            (_, None) => self.max_upload,
        };
        let segments = u32::try_from(size.div_ceil(SEGMENT_DATA)).unwrap_or(u32::MAX);
        per_answer.saturating_mul(4).saturating_add((per_answer / 2).saturating_mul(segments))
    }

    /// Whether the request that completes the transfer at the server has gone out: the
    /// expedited initiation, the last segment, the block end. Before it, a download has done
    /// nothing yet, whatever was lost.
    pub fn completing_request_sent(&self) -> bool {
        match self.state {
            State::DownloadInit => (1..=4).contains(&self.buf.len()),
            State::DownloadSegment => self.pos + SEGMENT_DATA >= self.buf.len(),
            State::BlockDownloadInit | State::BlockDownloadData { .. } => false,
            State::BlockDownloadEnd | State::Finished => true,
            _ => !self.upload,
        }
    }

    /// The first request of a new attempt at the same transfer, after the caller aborted
    /// the one that ran out of time: everything it moved is dropped (an upload starts from
    /// its first byte, a download from its first segment), and answers the abandoned
    /// attempt still gets are set aside until this one's first answer.
    pub fn restart(&mut self) -> [u8; 8] {
        let block = self.block && !self.fell_back;
        self.state = match (self.upload, block) {
            (true, true) => State::BlockUploadInit,
            (true, false) => State::UploadInit,
            (false, true) => State::BlockDownloadInit,
            (false, false) => State::DownloadInit,
        };
        if self.upload {
            self.buf.clear();
        }
        self.pos = 0;
        self.toggle = false;
        self.size = None;
        self.crc = false;
        self.blksize = 0;
        self.last = None;
        self.fruitless = 0;
        self.tail_missing = 0;
        self.restarted = true;
        self.start()
    }

    /// The first request.
    pub fn start(&mut self) -> [u8; 8] {
        let addr = self.addr;
        let request = match self.state {
            State::UploadInit => Request::InitiateUpload { addr },
            State::BlockUploadInit => {
                Request::BlockUpload { addr, crc: true, blksize: UPLOAD_BLOCK_SIZE, pst: PROTOCOL_SWITCH_THRESHOLD }
            }
            State::BlockDownloadInit => {
                Request::BlockDownload { addr, crc: true, size: u32::try_from(self.buf.len()).ok() }
            }
            State::DownloadInit => self.initiate_download(),
            s => panic!("start() called in state {s:?}"),
        };
        request.emit()
    }

    fn initiate_download(&self) -> Request {
        let len = self.buf.len();
        let init = if (1..=4).contains(&len) { Initiate::expedited(&self.buf) } else { Initiate::segmented(len) };
        Request::InitiateDownload { addr: self.addr, init }
    }

    /// End the transfer from our side: send `abort_frame(addr, code)` and report `reason`.
    fn fail(&mut self, code: u32, reason: impl Into<String>) -> SdoError {
        self.state = State::Finished;
        SdoError::ClientAbort { code, reason: reason.into() }
    }

    /// Set an answer aside: it changes nothing and is no progress.
    fn ignore(&mut self, what: String) -> Step {
        self.ignored += 1;
        self.last_ignored = Some(what);
        Step { send: Vec::new(), done: None, progress: false }
    }

    /// Feed one payload that arrived on the response COB-ID.
    pub fn on_response(&mut self, raw: &[u8]) -> Result<Step, SdoError> {
        let step = self.answer(raw);
        // This attempt's first answer: from now on nothing of the abandoned one can come
        // that is not also a repeat or an error of this one.
        if step.as_ref().is_ok_and(|s| s.progress) {
            self.restarted = false;
        }
        step
    }

    fn answer(&mut self, raw: &[u8]) -> Result<Step, SdoError> {
        if self.state == State::Finished {
            return Ok(self.ignore(format!("an answer after the transfer had ended ({})", spaced(raw))));
        }
        if raw.is_empty() {
            return Err(self.fail(abort::GENERAL_ERROR, "the device sent an empty frame (DLC 0) on the SDO channel"));
        }
        let p = pad(raw);
        let len = raw.len().min(8);
        if self.is_repeat(&p, len) {
            return Ok(self.ignore(format!("a repeat of its previous answer ({})", spaced(raw))));
        }
        self.last = Some((p, len));
        let response = Response::parse(&p);
        if let Some(Response::Abort { addr, code }) = response {
            self.require(8, "an abort (0x80) with its code")?;
            if let Some(aside) = self.abort_of_another(addr) {
                return Ok(aside);
            }
            // A server that gave up on the abandoned attempt says so (timed out): that is
            // not this attempt's answer. Any other refusal may well be. (Inside a sub-block,
            // reached only once this attempt was answered, it ends the transfer.)
            if self.restarted && code == abort::TIMED_OUT {
                return self.not_for_this_transfer(&p);
            }
            return self.on_abort(code);
        }
        // Inside a sub-block every frame is a segment, except the abort (sequence 0).
        if let State::BlockUploadData { expected } = self.state {
            return self.block_upload_segment(BlockSegment::parse(&p), expected);
        }
        let Some(response) = response else {
            // A command specifier no server sends: before the first answer it may still be
            // the previous transfer's last answer again, later it is an error.
            return match self.state {
                State::UploadInit | State::BlockUploadInit | State::DownloadInit | State::BlockDownloadInit => {
                    self.not_for_this_transfer(&p)
                }
                _ => Err(self.unexpected(&p)),
            };
        };
        match self.state {
            State::UploadInit => self.upload_initiated(&p, response),
            State::UploadSegment => self.upload_segment(&p, response),
            State::BlockUploadInit => self.block_upload_initiated(&p, response),
            State::BlockUploadEnd => self.block_upload_end(&p, response),
            State::DownloadInit => self.download_initiated(&p, response),
            State::DownloadSegment => self.download_segment_acked(&p, response),
            State::BlockDownloadInit => self.block_download_initiated(&p, response),
            State::BlockDownloadData { in_block } => self.block_download_acked(&p, response, in_block),
            State::BlockDownloadEnd => self.block_download_end(&p, response),
            State::BlockUploadData { .. } | State::Finished => unreachable!("handled above"),
        }
    }

    /// The same frame twice in a row is one answer received twice (CAN double reception,
    /// a device that resends): consecutive answers of one transfer always differ (toggle
    /// bit, sequence number, command), except block acknowledgements, where two identical
    /// ones confirm two whole sub-blocks.
    fn is_repeat(&self, p: &[u8; 8], len: usize) -> bool {
        let block_ack = matches!(self.state, State::BlockDownloadData { .. })
            && matches!(Response::parse(p), Some(Response::BlockDownloadAck { .. }));
        self.last == Some((*p, len)) && !block_ack
    }

    /// The answer must carry the `n` bytes its command specifier makes meaningful: missing
    /// bytes are never read as zero.
    fn require(&mut self, n: usize, what: &str) -> Result<(), SdoError> {
        let (p, len) = self.last.unwrap_or_default();
        if len >= n {
            return Ok(());
        }
        Err(self.fail(
            abort::GENERAL_ERROR,
            format!("the device sent {what} in a {len}-byte frame ({}), which needs {n} bytes", spaced(&p[..len])),
        ))
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

    /// An initiate answer naming another object answers an earlier request (one that timed
    /// out, or another client's): not ours, so it is set aside.
    fn other_object(&mut self, named: ObjAddr) -> Option<Step> {
        (named != self.addr).then(|| self.ignore(format!("an answer for object {named}, not {}", self.addr)))
    }

    /// An abort carries the object it ends (CiA 301): one naming another object ends an
    /// earlier transfer (a device that rebooted mid sub-block aborts the rest late), not
    /// this one, and is set aside. One that names no object (0x0000:00, left empty by some
    /// servers) is taken as this transfer's.
    fn abort_of_another(&mut self, named: ObjAddr) -> Option<Step> {
        if named == ObjAddr::new(0, 0) {
            return None;
        }
        self.other_object(named)
    }

    /// Before the server's first answer, an answer of another kind is an error, unless it
    /// is a second copy of the previous transfer's last answer (the write's 0x60 reaching
    /// the read-back of --verify): that one is set aside.
    fn not_for_this_transfer(&mut self, p: &[u8; 8]) -> Result<Step, SdoError> {
        if self.restarted {
            // Not this attempt's answer: it is no evidence of what this attempt's is, so
            // it is not kept to recognise repeats by either.
            let (_, len) = self.last.take().unwrap_or_default();
            return Ok(self.ignore(format!("an answer to the attempt abandoned before ({})", spaced(&p[..len]))));
        }
        if self.last.is_some() && self.last == self.previous {
            let (_, len) = self.last.unwrap_or_default();
            return Ok(
                self.ignore(format!("a second copy of the previous transfer's last answer ({})", spaced(&p[..len])))
            );
        }
        Err(self.unexpected(p))
    }

    fn unexpected(&mut self, p: &[u8; 8]) -> SdoError {
        self.fail(abort::UNKNOWN_COMMAND, format!("unexpected command byte 0x{:02X} from the server", p[0]))
    }

    /// The size a server announced, as CiA 301 carries it: 32 bits, unsigned.
    fn announce(&mut self, size: u32) -> Result<(), SdoError> {
        let size = usize::try_from(size).unwrap_or(usize::MAX);
        if size > self.max_upload {
            return Err(self.fail(
                abort::OUT_OF_MEMORY,
                format!("the device announces {size} bytes, more than the upload limit of {} bytes", self.max_upload),
            ));
        }
        self.size = Some(size);
        self.buf.reserve(size);
        Ok(())
    }

    /// After data arrived: at least `received` bytes so far, which must be neither more
    /// than the server announced nor more than the limit.
    fn check_received(&mut self, received: usize) -> Result<(), SdoError> {
        if let Some(size) = self.size.filter(|s| received > *s) {
            return Err(self.fail(
                abort::GENERAL_ERROR,
                format!("the device announced {size} bytes and sent more ({received} so far)"),
            ));
        }
        if received > self.max_upload {
            self.state = State::Finished;
            return Err(SdoError::OverLimit { limit: self.max_upload, received });
        }
        Ok(())
    }

    fn upload_initiated(&mut self, p: &[u8; 8], response: Response) -> Result<Step, SdoError> {
        let Response::InitiateUpload { addr, init } = response else { return self.not_for_this_transfer(p) };
        self.require(4, "an upload answer")?;
        if let Some(step) = self.other_object(addr) {
            return Ok(step);
        }
        match init {
            Initiate::Expedited { data, len } => self.expedited_upload(&data, len as usize),
            // Without the size indicated (which CiA 301 allows) the data is as long as the
            // type asked for, else all four bytes.
            Initiate::ExpeditedUnsized { data } => {
                self.expedited_upload(&data, self.size_hint.filter(|h| (1..=4).contains(h)).unwrap_or(4))
            }
            Initiate::Size(size) => {
                self.require(8, "a segmented upload answer with its size")?;
                self.announce(size)?;
                Ok(self.request_segments())
            }
            Initiate::Unsized => Ok(self.request_segments()),
        }
    }

    fn expedited_upload(&mut self, data: &[u8; 4], len: usize) -> Result<Step, SdoError> {
        self.require(4 + len, &format!("an expedited answer of {len} byte(s)"))?;
        self.state = State::Finished;
        Ok(Step::done(vec![], data[..len].to_vec()))
    }

    fn request_segments(&mut self) -> Step {
        self.state = State::UploadSegment;
        self.toggle = false;
        Step::send(vec![Request::UploadSegment { toggle: false }.emit()])
    }

    fn upload_segment(&mut self, p: &[u8; 8], response: Response) -> Result<Step, SdoError> {
        let Response::UploadSegment(seg) = response else { return Err(self.unexpected(p)) };
        if seg.toggle != self.toggle {
            return Err(self.fail(abort::TOGGLE_BIT, "toggle bit not alternated"));
        }
        self.require(seg.frame_len(), &format!("a segment of {} byte(s)", seg.data().len()))?;
        self.buf.extend_from_slice(seg.data());
        self.check_received(self.buf.len())?;
        if seg.last {
            self.state = State::Finished;
            return self.finish_upload(vec![]);
        }
        self.toggle = !self.toggle;
        let next = Request::UploadSegment { toggle: self.toggle }.emit();
        // A segment that carries nothing and is not the last moves nothing: an endless
        // stream of them is no progress.
        Ok(if seg.data().is_empty() { Step::retry(vec![next]) } else { Step::send(vec![next]) })
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

    fn download_initiated(&mut self, p: &[u8; 8], response: Response) -> Result<Step, SdoError> {
        let Response::InitiateDownload { addr } = response else { return self.not_for_this_transfer(p) };
        self.require(4, "a download answer")?;
        if let Some(step) = self.other_object(addr) {
            return Ok(step);
        }
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
        let last = end == self.buf.len();
        Request::DownloadSegment(Segment::new(self.toggle, &self.buf[self.pos..end], last)).emit()
    }

    fn download_segment_acked(&mut self, p: &[u8; 8], response: Response) -> Result<Step, SdoError> {
        let Response::DownloadSegment { toggle } = response else { return Err(self.unexpected(p)) };
        if toggle != self.toggle {
            return Err(self.fail(abort::TOGGLE_BIT, "toggle bit not alternated"));
        }
        self.pos = (self.pos + SEGMENT_DATA).min(self.buf.len());
        if self.pos == self.buf.len() {
            self.state = State::Finished;
            return Ok(Step::done(vec![], vec![]));
        }
        self.toggle = !self.toggle;
        Ok(Step::send(vec![self.next_segment()]))
    }
}

/// Bytes as candump shows them, for messages.
fn spaced(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02X}")).collect::<Vec<_>>().join(" ")
}
