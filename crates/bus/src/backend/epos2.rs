//! The `Bus` services through an EPOS2: node 0 (or the EPOS2's own node-id) is the EPOS2
//! itself, every other node is reached through it as a gateway to its CAN bus.

use crate::bus::{Bus, FrameLog, LssAnswer, LssExchange, LssWait, Observed, SdoJob, SdoOptions, ALL_NODES};
use crate::canopen::nmt::Command as NmtCommand;
use crate::canopen::{abort, ObjAddr};
use crate::epos2::command::{self, Command, GATEWAY_SEGMENT, LENGTH, MAX_SEGMENT, MORE, TOGGLE};
use crate::epos2::transport::Transport;
use crate::epos2::{Epos2Error, Epos2Problem};
use crate::error::{Error, LinkError, Moved, NodeIdRange, Result};
use crate::frame::Frame;
use std::time::{Duration, Instant};

/// The longest single ReadLSSFrame wait, in ms.
const READ_LSS_SLICE_MS: u128 = 100;

/// EPOS2 firmware specification: object 0x2000 holds the node-id set by DIP switch or SDO.
const OWN_NODE_ID: ObjAddr = ObjAddr::new(0x2000, 0);
/// Segments in a row that carry no data yet say more follow: the transfer makes no
/// progress, so after these it is a protocol error, not a loop.
const MAX_EMPTY_SEGMENTS: usize = 8;
/// The largest value read in segments through an EPOS2. Its answers do not say how long a
/// value is, so a device that keeps saying "more" is stopped here: a 1 MiB upload at 63
/// bytes a round trip is already minutes on a serial line.
pub(crate) const MAX_SEGMENTED_UPLOAD: usize = 1 << 20;

/// The `Bus` services through an EPOS2 over its serial protocol: its own objects by its
/// commands, every other node through its CAN bus (the gateway of seed 002).
pub struct Epos2Gateway<T: Transport> {
    link: T,
    /// The EPOS2's own node-id, read once when first needed; `None` until then.
    own_id: Option<u8>,
    /// Only what its own answers show: an EPOS2 passes on no traffic by itself.
    observed: Observed,
    /// Where the CAN frames this side puts on the bus or gets from it are logged.
    frame_log: Option<FrameLog>,
}

impl<T: Transport> Epos2Gateway<T> {
    /// A gateway over an open transport; it learns its own node-id when first needed.
    pub fn new(link: T) -> Epos2Gateway<T> {
        Epos2Gateway { link, own_id: None, observed: Observed::default(), frame_log: None }
    }

    /// Also log the CAN frames this side sees: NMT, LSS, SendCANFrame and RequestCANFrame
    /// (SDO transfers are the EPOS2's own business on its bus).
    pub fn with_frame_log(mut self, log: Option<FrameLog>) -> Epos2Gateway<T> {
        self.frame_log = log;
        self
    }

    fn log(&self, frame: &Frame) {
        if let Some(log) = &self.frame_log {
            log.record(&self.link.describe(), frame);
        }
    }

    /// One command; its error code and data, or `None` where RS232 has no answer.
    fn call(&mut self, cmd: &Command) -> Result<Option<(u32, Vec<u8>)>> {
        let answered = !self.link.is_rs232() || cmd.answered_on_rs232();
        let Some(answer) = self.link.transact(&cmd.to_frame(), answered)? else { return Ok(None) };
        let (code, data) = command::parse_answer(&answer)
            .ok_or_else(|| self.bad_answer(Epos2Problem::TooShort { command: cmd.name() }))?;
        Ok(Some((code, data.to_vec())))
    }

    /// A command whose answer, where RS232 has one, must carry error code 0.
    fn call_checked(&mut self, cmd: &Command, node: u8) -> Result<()> {
        match self.call(cmd)? {
            Some((code, _)) => self.check(code, node, None, cmd.name()),
            None => Ok(()),
        }
    }

    /// A command that must be answered; its data when the error code is 0.
    fn call_ok(&mut self, cmd: &Command, node: u8, addr: Option<ObjAddr>) -> Result<Vec<u8>> {
        let (code, data) = self.call(cmd)?.expect("answered command");
        self.check(code, node, addr, cmd.name())?;
        Ok(data)
    }

    fn check(&self, code: u32, node: u8, obj: Option<ObjAddr>, command: &'static str) -> Result<()> {
        match (code, obj) {
            (0, _) => Ok(()),
            (abort::TIMED_OUT, _) => Err(Error::Epos2NoCanAnswer { node, command, obj }),
            (code, Some(obj)) if !command::is_maxon_code(code) => Err(Error::SdoAbort { node, obj, code }),
            (code, obj) => Err(Error::Epos2Refused { node, command, obj, code }),
        }
    }

    fn bad_answer(&self, problem: Epos2Problem) -> Error {
        Epos2Error::Answer { bus: self.link.describe(), problem }.into()
    }

    /// Segment size: 63 bytes to the EPOS2 itself, one CAN SDO segment through it.
    fn segment_size(&mut self, node: u8) -> usize {
        if node == 0 || node == self.own_id() {
            MAX_SEGMENT
        } else {
            GATEWAY_SEGMENT
        }
    }

    /// The EPOS2's own node-id, read once (0 when it cannot be read: node 0 is always its own).
    fn own_id(&mut self) -> u8 {
        if let Some(id) = self.own_id {
            return id;
        }
        let id = self.read_object(0, OWN_NODE_ID, Some(1)).ok().and_then(|d| d.first().copied()).unwrap_or(0);
        *self.own_id.insert(id)
    }

    fn read_object(&mut self, node: u8, addr: ObjAddr, size: Option<usize>) -> Result<Vec<u8>> {
        let mut data = self.call_ok(&Command::ReadObject { node, addr }, node, Some(addr))?;
        // ReadObject always carries four bytes; beyond the object's size they mean nothing.
        data.truncate(size.unwrap_or(4).min(4));
        Ok(data)
    }

    /// A segmented read; more than `max_upload` bytes are refused, as the SDO client does
    /// (the EPOS2's answers never say the size, so only what arrives can be counted).
    fn segmented_read(&mut self, node: u8, addr: ObjAddr, opts: &SdoOptions) -> Result<Vec<u8>> {
        let max_upload = opts.max_upload;
        self.call_ok(&Command::InitiateSegmentedRead { node, addr }, node, Some(addr))?;
        let mut out = Vec::new();
        let mut toggle = false;
        let mut empty_in_a_row = 0;
        loop {
            stop_point(opts, node, addr, true, Moved { bytes: out.len(), total: None })?;
            let data = self.call_ok(&Command::SegmentRead { toggle }, node, Some(addr))?;
            let ctrl = *data.first().ok_or_else(|| self.bad_answer(Epos2Problem::EmptySegment))?;
            if (ctrl & TOGGLE != 0) != toggle {
                return Err(self.bad_answer(Epos2Problem::ToggleNotAlternated { node, obj: addr }));
            }
            let len = (ctrl & LENGTH) as usize;
            let chunk = data
                .get(1..1 + len)
                .ok_or_else(|| self.bad_answer(Epos2Problem::ShortSegment { node, claimed: len }))?;
            out.extend_from_slice(chunk);
            if let Some(hook) = opts.on_progress.as_ref().filter(|_| ctrl & MORE != 0) {
                hook(out.len());
            }
            if out.len() > max_upload && max_upload < MAX_SEGMENTED_UPLOAD {
                let (limit, received) = (max_upload, out.len());
                return Err(LinkError::UploadOverLimit { node, obj: addr, limit, received }.into());
            }
            if ctrl & MORE == 0 {
                return Ok(out);
            }
            empty_in_a_row = if chunk.is_empty() { empty_in_a_row + 1 } else { 0 };
            if empty_in_a_row == MAX_EMPTY_SEGMENTS {
                let problem = Epos2Problem::EmptySegments { node, obj: addr, count: MAX_EMPTY_SEGMENTS };
                return Err(self.bad_answer(problem));
            }
            if out.len() >= MAX_SEGMENTED_UPLOAD {
                let problem =
                    Epos2Problem::TooLong { node, obj: addr, bytes: out.len(), limit_kib: MAX_SEGMENTED_UPLOAD >> 10 };
                return Err(self.bad_answer(problem));
            }
            toggle = !toggle;
        }
    }

    fn segmented_write(&mut self, node: u8, addr: ObjAddr, data: &[u8], opts: &SdoOptions) -> Result<()> {
        // ObjectLength is 32-bit, as CiA 301 sizes are: a larger value would be announced
        // by its low 32 bits.
        let length = u32::try_from(data.len()).map_err(|_| Error::TooLargeForSdo { len: data.len() })?;
        let size = self.segment_size(node);
        self.call_ok(&Command::InitiateSegmentedWrite { node, addr, length }, node, Some(addr))?;
        let mut toggle = false;
        // An empty value is one segment with no data (CiA 301 lets a segment carry none);
        // without it the device would wait for the value and never write it.
        let chunks: Vec<&[u8]> = if data.is_empty() { vec![&[]] } else { data.chunks(size).collect() };
        let mut sent = 0;
        for chunk in chunks {
            stop_point(opts, node, addr, false, Moved { bytes: sent, total: Some(data.len()) })?;
            let answer = self.call_ok(&Command::SegmentWrite { toggle, data: chunk.to_vec() }, node, Some(addr))?;
            let ctrl = answer.first().copied().unwrap_or(0);
            if (ctrl & TOGGLE != 0) != toggle || (ctrl & LENGTH) as usize != chunk.len() {
                return Err(self.bad_answer(Epos2Problem::ExtraSegment { node, obj: addr }));
            }
            sent += chunk.len();
            if let Some(hook) = opts.on_progress.as_ref().filter(|_| sent < data.len()) {
                hook(sent);
            }
            toggle = !toggle;
        }
        Ok(())
    }
}

/// Between two segments: the user asked to stop. The EPOS2 protocol has no command to
/// abort a segmented transfer, so the EPOS2 ends it at its own timeout.
fn stop_point(opts: &SdoOptions, node: u8, obj: ObjAddr, upload: bool, moved: Moved) -> Result<()> {
    if opts.stop.as_ref().is_some_and(crate::cancel::Cancel::is_cancelled) {
        return Err(Error::SdoInterrupted { node, obj, upload, moved, aborted: None });
    }
    Ok(())
}

fn check_node(node: u8) -> Result<()> {
    (node <= 127).then_some(()).ok_or(Error::NodeIdOutOfRange { node, range: NodeIdRange::Epos2 })
}

impl<T: Transport> Epos2Gateway<T> {
    /// Read an object: ReadObject when it fits, segments otherwise.
    fn upload(&mut self, node: u8, addr: ObjAddr, opts: &SdoOptions) -> Result<Vec<u8>> {
        check_node(node)?;
        let small = !opts.block_upload && opts.size_hint.is_none_or(|s| s <= 4);
        if small {
            match self.read_object(node, addr, opts.size_hint) {
                // Too big for ReadObject, and the caller did not know: read it in segments.
                Err(Error::SdoAbort { code: abort::LENGTH_TOO_HIGH, .. }) if opts.size_hint.is_none() => {}
                other => return other,
            }
        }
        self.segmented_read(node, addr, opts)
    }

    /// Write an object: WriteObject when its size is known and fits, segments otherwise.
    fn download(&mut self, node: u8, addr: ObjAddr, data: &[u8], opts: &SdoOptions) -> Result<()> {
        check_node(node)?;
        // WriteObject carries four bytes and no length: the device takes as many as its
        // object holds. Only a value of a fixed-size type that fits says its size that way.
        if opts.size_hint == Some(data.len()) && data.len() <= 4 {
            let mut four = [0u8; 4];
            four[..data.len()].copy_from_slice(data);
            self.call_ok(&Command::WriteObject { node, addr, data: four }, node, Some(addr))?;
            return Ok(());
        }
        self.segmented_write(node, addr, data, opts)
    }
}

impl<T: Transport> Bus for Epos2Gateway<T> {
    fn describe(&self) -> String {
        self.link.describe()
    }

    /// One transfer after another: the gateway makes one at a time.
    fn sdo_batch(&mut self, jobs: &[SdoJob], progress: &mut dyn FnMut(usize)) -> Result<Vec<Result<Vec<u8>>>> {
        crate::bus::one_by_one(jobs, progress, |job| match job {
            SdoJob::Upload { node, addr, opts } => self.upload(*node, *addr, opts),
            SdoJob::Download { node, addr, data, opts } => self.download(*node, *addr, data, opts).map(|_| Vec::new()),
        })
    }

    fn nmt(&mut self, cmd: NmtCommand, node: u8) -> Result<()> {
        check_node(node)?;
        self.log(&cmd.frame(node));
        self.call_checked(&Command::SendNmtService { node, specifier: cmd.specifier() }, node)
    }

    fn send_frame(&mut self, frame: &Frame) -> Result<()> {
        if frame.is_remote() {
            let why = "remote frames go through RequestCANFrame; use a request";
            return Err(Error::NotOnThisBus { bus: self.link.describe(), why });
        }
        let mut data = [0u8; 8];
        data[..frame.len()].copy_from_slice(frame.data());
        self.log(frame);
        self.call_checked(&Command::SendCanFrame { id: frame.id(), len: frame.len() as u8, data }, 0)
    }

    fn sees_traffic(&self) -> bool {
        false
    }

    fn own_node(&mut self) -> Option<u8> {
        Some(self.own_id())
    }

    fn recv_frame_stamped(&mut self, _deadline: Instant) -> Result<Option<(Frame, Instant)>> {
        let why = "an EPOS2 passes on no CAN traffic of its own accord (only answers to commands)";
        Err(Error::NotOnThisBus { bus: self.link.describe(), why })
    }

    /// A serial link to real hardware: the monotonic clock.
    fn now(&self) -> Instant {
        crate::bus::clock::monotonic_now()
    }
    fn sleep_until(&mut self, t: Instant) -> Result<()> {
        crate::bus::clock::sleep_until(t);
        Ok(())
    }
    fn request_frame(&mut self, id: u16, len: u8, _timeout: Duration) -> Result<Frame> {
        let c = Command::RequestCanFrame { id, len };
        self.log(&Frame::remote(id, len.min(8)));
        let data = self.call_ok(&c, (id & 0x7F) as u8, None)?;
        let n = (len as usize).min(8).min(data.len());
        let answer = Frame::new(id, &data[..n]);
        self.log(&answer);
        Ok(answer)
    }

    fn lss(&mut self, exchange: &LssExchange) -> Result<Vec<LssAnswer>> {
        let LssExchange { request, expect, wait, collect } = *exchange;
        self.log(&Frame::new(crate::canopen::lss::MASTER_COB, &request));
        self.call_checked(&Command::SendLssFrame { data: request }, 0)?;
        let mut answers = Vec::new();
        if collect == LssWait::Nothing {
            return Ok(answers);
        }
        // ReadLSSFrame hands over one slave message per call, waiting up to its timeout.
        let sent = Instant::now();
        let mut deadline = sent + wait;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            // In slices well inside the link's own answer timeout: a long LSS wait (the
            // first fastscan probe) must not pass for a silent EPOS2.
            let timeout_ms = left.as_millis().clamp(1, READ_LSS_SLICE_MS) as u16;
            let read = Command::ReadLssFrame { timeout_ms };
            let (code, data) = self.call(&read)?.expect("ReadLSSFrame is answered");
            match code {
                abort::TIMED_OUT if Instant::now() < deadline => {}
                abort::TIMED_OUT => break,
                0 => {
                    // Only a whole answer with the expected command specifier counts; others
                    // do not make the wait longer.
                    let data = data.get(..8).and_then(|d| <[u8; 8]>::try_from(d).ok());
                    if let Some(d) = &data {
                        self.log(&Frame::new(crate::canopen::lss::SLAVE_COB, d));
                    }
                    if let Some(data) = data.filter(|d| crate::canopen::lss::is_answer(d, expect)) {
                        answers.push(LssAnswer { data, after: sent.elapsed() });
                        // Other slaves' answers to the same request may still be coming: read
                        // them here, or they would pass for answers to the next request.
                        match collect {
                            LssWait::First => break,
                            LssWait::Settle(more) if answers.len() == 1 => {
                                deadline = deadline.min(Instant::now() + more)
                            }
                            _ => {}
                        }
                    }
                    if left.is_zero() {
                        break;
                    }
                }
                c => self.check(c, 0, None, read.name())?,
            }
        }
        Ok(answers)
    }

    fn observed(&mut self) -> &mut Observed {
        &mut self.observed
    }

    fn close(&mut self) -> Result<()> {
        Ok(())
    }
}

/// `ALL_NODES` is node-id 0 in SendNMTService as in the CAN NMT frame.
const _: () = assert!(ALL_NODES == 0);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::epos2::frame::Frame as SerialFrame;

    /// A link whose EPOS2 answers each command with `answer(command)`; records the commands.
    struct Scripted<F: FnMut(&Command) -> SerialFrame> {
        answer: F,
        sent: Vec<Command>,
    }

    impl<F: FnMut(&Command) -> SerialFrame> Transport for Scripted<F> {
        fn transact(&mut self, frame: &SerialFrame, _answered: bool) -> Result<Option<SerialFrame>, Epos2Error> {
            let cmd = Command::from_frame(frame).expect("a command");
            let a = (self.answer)(&cmd);
            self.sent.push(cmd);
            Ok(Some(a))
        }
        fn describe(&self) -> String {
            "scripted".into()
        }
        fn is_rs232(&self) -> bool {
            false
        }
    }

    fn gateway<F: FnMut(&Command) -> SerialFrame>(answer: F) -> Epos2Gateway<Scripted<F>> {
        Epos2Gateway::new(Scripted { answer, sent: vec![] })
    }

    fn segment(toggle: bool, more: bool, data: &[u8]) -> SerialFrame {
        let mut d = vec![data.len() as u8 | if toggle { TOGGLE } else { 0 } | if more { MORE } else { 0 }];
        d.extend_from_slice(data);
        command::answer(0, &d)
    }

    const OBJ: ObjAddr = ObjAddr::new(0x1008, 0);

    fn block() -> SdoOptions {
        SdoOptions { block_upload: true, ..SdoOptions::new(Duration::from_millis(100)) }
    }

    #[test]
    fn segments_without_data_are_a_protocol_error() {
        let mut g = gateway(|c| match c {
            Command::SegmentRead { toggle } => segment(*toggle, true, &[]),
            _ => command::answer(0, &[]),
        });
        let e = g.sdo_upload(10, OBJ, &block()).unwrap_err();
        assert_eq!(e.exit_code(), 5, "{e}");
        assert!(e.to_string().contains("without data"), "{e}");
        assert_eq!(g.link.sent.len(), 1 + MAX_EMPTY_SEGMENTS);
    }

    #[test]
    fn a_few_empty_segments_between_data_are_read_through() {
        let mut n = 0;
        let mut g = gateway(move |c| match c {
            Command::SegmentRead { toggle } => {
                n += 1;
                match n {
                    1 | 3 => segment(*toggle, true, &[]),
                    2 => segment(*toggle, true, b"CAN-"),
                    _ => segment(*toggle, false, b"2057C"),
                }
            }
            _ => command::answer(0, &[]),
        });
        assert_eq!(g.sdo_upload(10, OBJ, &block()).unwrap(), b"CAN-2057C");
    }

    #[test]
    fn endless_segments_stop_at_the_limit() {
        let mut g = gateway(|c| match c {
            Command::SegmentRead { toggle } => segment(*toggle, true, &[0xEE; MAX_SEGMENT]),
            _ => command::answer(0, &[]),
        });
        let e = g.sdo_upload(0, OBJ, &block()).unwrap_err();
        assert_eq!(e.exit_code(), 5, "{e}");
        assert!(e.to_string().contains("still says more follow"), "{e}");
        assert_eq!(g.link.sent.len(), 1 + MAX_SEGMENTED_UPLOAD.div_ceil(MAX_SEGMENT));
    }

    /// Through an EPOS2 as over CAN, a value's size travels in 32 bits
    /// (InitiateSegmentedWrite's ObjectLength): 4 GiB + 10 bytes must not be announced as 10.
    /// (The zeroes are never touched: the allocation costs address space, not memory.)
    #[cfg(all(target_os = "linux", target_pointer_width = "64"))]
    #[test]
    fn a_value_over_4_gib_is_refused_before_anything_is_sent() {
        let mut g = gateway(|c| match c {
            Command::SegmentWrite { .. } => command::answer(abort::LENGTH_TOO_HIGH, &[0, 0]),
            _ => command::answer(0, &[]),
        });
        let huge = vec![0u8; (1 << 32) + 10];
        let e = g.sdo_download(5, OBJ, &huge, &SdoOptions::new(Duration::from_millis(100))).unwrap_err();
        assert_eq!(e.exit_code(), 2, "{e}");
        assert!(e.to_string().contains("4294967306 bytes") && e.to_string().contains("32-bit"), "{e}");
        assert_eq!(g.link.sent, []);
    }

    #[test]
    fn a_segmented_read_stops_at_the_callers_upload_limit() {
        let mut g = gateway(|c| match c {
            Command::SegmentRead { toggle } => segment(*toggle, true, &[0xEE; GATEWAY_SEGMENT]),
            _ => command::answer(0, &[]),
        });
        let opts = SdoOptions { max_upload: 100, ..block() };
        let e = g.sdo_upload(10, OBJ, &opts).unwrap_err();
        assert_eq!(e.exit_code(), 5, "{e}");
        assert!(e.to_string().contains("limit of 100 bytes"), "{e}");
        // The remedy (`--max-size raises the limit`) is the front end's: tests/suite/epos2_faults.rs.
        assert!(!e.to_string().contains("--"), "the remedy is the front end's: {e}");
        assert_eq!(g.link.sent.len(), 1 + 100usize.div_ceil(GATEWAY_SEGMENT), "stopped at the first segment past it");
    }

    #[test]
    fn an_empty_value_is_one_segment_without_data() {
        let mut g = gateway(|c| match c {
            Command::SegmentWrite { toggle, data } => {
                command::answer(0, &[data.len() as u8 | if *toggle { TOGGLE } else { 0 }, 0])
            }
            _ => command::answer(0, &[]),
        });
        g.sdo_download(0, ObjAddr::new(0x5FF0, 12), &[], &SdoOptions::new(Duration::from_millis(100))).unwrap();
        assert_eq!(
            g.link.sent,
            [
                Command::InitiateSegmentedWrite { node: 0, addr: ObjAddr::new(0x5FF0, 12), length: 0 },
                Command::SegmentWrite { toggle: false, data: vec![] },
            ]
        );
    }
}
