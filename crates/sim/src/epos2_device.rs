//! The EPOS2 as a device: executes the serial command set for itself (node 0 or its own
//! node-id, on its own dictionary) and, as a gateway, turns the rest into CANopen frames on
//! the simulated bus — one SDO exchange per command, nothing buffered (seed 002).

use super::SimLink;
use crate::bus::{FrameLink, FrameLog};
use crate::canopen::lss;
use crate::canopen::nmt::Command as NmtCommand;
use crate::canopen::sdo::wire::{Initiate, Request, Response, Segment};
use crate::canopen::sdo::{self, ObjectAccess};
use crate::canopen::{abort, ObjAddr};
use crate::epos2::command::{self, answer, Command, GATEWAY_SEGMENT, MAX_SEGMENT, MORE, TOGGLE};
use crate::epos2::frame::Frame as SerialFrame;
use crate::error::Result;
use crate::frame::Frame;
use crate::trace::{self as bus_trace, Dir};
use std::time::Duration;

/// The model key of the device this EPOS2 is on the sim network.
const SELF_MODEL: &str = "drive";
/// RequestCANFrame waits at least this long, so that a heartbeat producer's next beat (the
/// same COB-ID as a guarding answer) arrives as the answer, as on a real bus.
const REMOTE_REQUEST_WAIT: Duration = Duration::from_millis(150);

/// A segmented transfer in progress. `ForwardedShortRead`: the SDO server answered
/// expedited, and its bytes go out with the first SegmentRead.
enum Segmented {
    None,
    LocalRead { data: Vec<u8>, pos: usize },
    LocalWrite { addr: ObjAddr, data: Vec<u8>, length: usize },
    ForwardedShortRead { data: Vec<u8> },
    ForwardedRead { node: u8, addr: ObjAddr },
    ForwardedWrite { node: u8, addr: ObjAddr, left: usize },
}

/// A simulated EPOS2 on its serial link: answers the serial protocol's commands and passes its CAN
/// gateway's SDO requests to the simulated network.
pub struct Epos2Device {
    link: SimLink,
    can_timeout: Duration,
    /// Where the frames this EPOS2 puts on the sim bus and receives from it are logged.
    frame_log: Option<FrameLog>,
    segmented: Segmented,
    /// The last segment command and its answer: a master that lost an answer repeats the
    /// command with the same toggle bit, and gets the same answer without a second effect.
    last_segment: Option<(Command, SerialFrame)>,
    /// Fault injection: answer the next forwarded SDO request first for another object and
    /// from another node, as frames left on a real bus by earlier transfers do.
    wrong_answers: bool,
    /// Frames that arrive before anything the link delivers (the injected wrong answers).
    arrived: std::collections::VecDeque<Frame>,
}

impl Epos2Device {
    /// An EPOS2 gateway to the network behind `link`, waiting at most `can_timeout` for a device's
    /// SDO answer.
    pub fn new(link: SimLink, can_timeout: Duration) -> Epos2Device {
        Epos2Device {
            link,
            can_timeout,
            frame_log: None,
            segmented: Segmented::None,
            last_segment: None,
            wrong_answers: false,
            arrived: Default::default(),
        }
    }

    /// Also write the frames on the sim bus to `log`.
    pub fn with_frame_log(mut self, log: Option<FrameLog>) -> Epos2Device {
        self.frame_log = log;
        self
    }

    /// A frame on the sim bus: to the frame trace (`trace`) and the frame log.
    fn seen(&self, dir: Dir, f: &Frame, trace: bool) {
        if trace {
            bus_trace::frame("sim", dir, f);
        }
        if let Some(log) = &self.frame_log {
            log.record("sim", f);
        }
    }

    /// Whether forwarded SDO requests are first answered wrongly (a fault for tests).
    pub fn inject_wrong_answers(&mut self, on: bool) {
        self.wrong_answers = on;
    }

    /// The simulated CAN network behind the gateway, for tests that change it.
    pub fn link_mut(&mut self) -> &mut SimLink {
        &mut self.link
    }

    fn is_local(&mut self, node: u8) -> bool {
        node == 0 || self.link.network_mut().device_mut(SELF_MODEL).is_some_and(|d| d.node_id() == Some(node))
    }

    /// The EPOS2 itself, on the sim network.
    fn device(&mut self) -> &mut super::device::Device {
        self.link.network_mut().device_mut(SELF_MODEL).expect("the EPOS2 is on the sim network")
    }

    fn objects(&mut self) -> &mut super::device::ObjectStore {
        self.device().objects_mut()
    }

    /// The answer to one command frame from the master.
    pub fn execute(&mut self, request: &SerialFrame) -> Result<SerialFrame> {
        // The EPOS2's own objects change with time too (a simulated fault, its reaction).
        self.link.advance();
        let Some(cmd) = Command::from_frame(request) else { return Ok(answer(command::ILLEGAL_COMMAND, &[])) };
        if let Some((_, ans)) = self.last_segment.as_ref().filter(|(last, _)| *last == cmd) {
            return Ok(ans.clone());
        }
        let mut ans = self.run(&cmd)?;
        // An error answer is never longer than the command's answer (seed 000 chapter 3).
        ans.data.truncate(cmd.answer_len().1);
        self.last_segment =
            matches!(cmd, Command::SegmentRead { .. } | Command::SegmentWrite { .. }).then(|| (cmd, ans.clone()));
        Ok(ans)
    }

    fn run(&mut self, cmd: &Command) -> Result<SerialFrame> {
        Ok(match cmd.clone() {
            Command::ReadObject { node, addr } if self.is_local(node) => match self.objects().read(addr) {
                Ok(d) if d.len() <= 4 => answer(0, &padded::<4>(&d)),
                Ok(_) => answer(abort::LENGTH_TOO_HIGH, &[0; 4]),
                Err(code) => answer(code, &[0; 4]),
            },
            Command::WriteObject { node, addr, data } if self.is_local(node) => {
                let n = self.objects().fixed_size(addr).unwrap_or(4).min(4);
                answer(self.device().write_local(addr, &data[..n]).err().unwrap_or(0), &[])
            }
            Command::InitiateSegmentedRead { node, addr } if self.is_local(node) => {
                let read = self.objects().read(addr);
                let started = read.map(|data| self.segmented = Segmented::LocalRead { data, pos: 0 });
                answer(started.err().unwrap_or(0), &[])
            }
            Command::InitiateSegmentedWrite { node, addr, length } if self.is_local(node) => {
                let length = length as usize;
                let checked = self.objects().check_write(addr, Some(length));
                let started =
                    checked.map(|()| self.segmented = Segmented::LocalWrite { addr, data: Vec::new(), length });
                answer(started.err().unwrap_or(0), &[])
            }
            Command::ReadObject { node, addr } => self.forward_read_object(node, addr)?,
            Command::WriteObject { node, addr, data } => {
                // Expedited, size not indicated: the server writes as many bytes as its object holds.
                let init = Initiate::ExpeditedUnsized { data };
                match self.sdo(node, Request::InitiateDownload { addr, init })? {
                    Err(code) => answer(code, &[]),
                    Ok(Some(Response::InitiateDownload { .. })) => answer(0, &[]),
                    Ok(_) => self.sdo_abort(node, addr, abort::UNKNOWN_COMMAND)?,
                }
            }
            Command::InitiateSegmentedRead { node, addr } => match self.sdo(node, Request::InitiateUpload { addr })? {
                Err(code) => answer(code, &[]),
                Ok(Some(Response::InitiateUpload { init, .. })) => {
                    self.segmented = match init.expedited_data() {
                        Some(data) => Segmented::ForwardedShortRead { data: data.to_vec() },
                        None => Segmented::ForwardedRead { node, addr },
                    };
                    answer(0, &[])
                }
                Ok(_) => self.sdo_abort(node, addr, abort::UNKNOWN_COMMAND)?,
            },
            Command::InitiateSegmentedWrite { node, addr, length } => {
                match self.sdo(node, Request::InitiateDownload { addr, init: Initiate::Size(length) })? {
                    Err(code) => answer(code, &[]),
                    Ok(Some(Response::InitiateDownload { .. })) => {
                        self.segmented = Segmented::ForwardedWrite { node, addr, left: length as usize };
                        answer(0, &[])
                    }
                    Ok(_) => self.sdo_abort(node, addr, abort::UNKNOWN_COMMAND)?,
                }
            }
            Command::SegmentRead { toggle } => self.segment_read(toggle)?,
            Command::SegmentWrite { toggle, data } => self.segment_write(toggle, data)?,
            Command::SendNmtService { node, specifier } => match NmtCommand::from_specifier(specifier) {
                Some(c) => {
                    self.send(&c.frame(node))?;
                    answer(0, &[])
                }
                None => answer(abort::INVALID_VALUE, &[]),
            },
            Command::SendCanFrame { id, len, data } if id <= 0x7FF => {
                self.send(&Frame::new(id, &data[..len as usize]))?;
                answer(0, &[])
            }
            Command::SendCanFrame { .. } => answer(command::CAN_ID, &[]),
            Command::RequestCanFrame { id, len } if id <= 0x7FF => {
                self.send(&Frame::remote(id, len))?;
                match self.wait_for(|f| f.id() == id && !f.is_remote(), self.can_timeout.max(REMOTE_REQUEST_WAIT))? {
                    Some(f) => answer(0, &padded::<8>(f.data())),
                    None => answer(abort::TIMED_OUT, &[0; 8]),
                }
            }
            Command::RequestCanFrame { .. } => answer(command::CAN_ID, &[0; 8]),
            Command::SendLssFrame { data } => {
                // Slave messages still queued from an earlier request are dropped by
                // `send`, so that ReadLSSFrame hands over answers to this one.
                self.send(&Frame::new(lss::MASTER_COB, &data))?;
                answer(0, &[])
            }
            Command::ReadLssFrame { timeout_ms } => {
                match self.wait_for(
                    |f| f.id() == lss::SLAVE_COB && !f.is_remote(),
                    Duration::from_millis(timeout_ms as u64),
                )? {
                    Some(f) => answer(0, &padded::<8>(f.data())),
                    None => answer(abort::TIMED_OUT, &[0; 8]),
                }
            }
        })
    }

    fn forward_read_object(&mut self, node: u8, addr: ObjAddr) -> Result<SerialFrame> {
        Ok(match self.sdo(node, Request::InitiateUpload { addr })? {
            Err(code) => answer(code, &[0; 4]),
            Ok(Some(Response::InitiateUpload { init, .. })) => match init.expedited_data() {
                Some(data) => answer(0, &padded::<4>(data)),
                // A segmented answer: too long for ReadObject. End the SDO transfer properly.
                None => {
                    self.send(&Frame::new(sdo::request_cob(node), &sdo::abort_frame(addr, abort::LENGTH_TOO_HIGH)))?;
                    answer(abort::LENGTH_TOO_HIGH, &[0; 4])
                }
            },
            Ok(_) => self.sdo_abort(node, addr, abort::UNKNOWN_COMMAND)?,
        })
    }

    fn segment_read(&mut self, toggle: bool) -> Result<SerialFrame> {
        let t = toggle_bit(toggle);
        Ok(match std::mem::replace(&mut self.segmented, Segmented::None) {
            Segmented::LocalRead { data, pos } => {
                let end = (pos + MAX_SEGMENT).min(data.len());
                let more = end < data.len();
                let mut d = vec![(end - pos) as u8 | t | if more { MORE } else { 0 }];
                d.extend_from_slice(&data[pos..end]);
                if more {
                    self.segmented = Segmented::LocalRead { data, pos: end };
                }
                answer(0, &d)
            }
            Segmented::ForwardedShortRead { data } => {
                let mut d = vec![data.len() as u8 | t];
                d.extend_from_slice(&data);
                answer(0, &d)
            }
            Segmented::ForwardedRead { node, addr } => match self.sdo(node, Request::UploadSegment { toggle })? {
                Err(code) => answer(code, &[0]),
                Ok(Some(Response::UploadSegment(seg))) => {
                    let mut d = vec![seg.data().len() as u8 | t | if seg.last { 0 } else { MORE }];
                    d.extend_from_slice(seg.data());
                    if !seg.last {
                        self.segmented = Segmented::ForwardedRead { node, addr };
                    }
                    answer(0, &d)
                }
                Ok(_) => self.sdo_abort(node, addr, abort::UNKNOWN_COMMAND)?,
            },
            _ => answer(abort::UNKNOWN_COMMAND, &[0]),
        })
    }

    fn segment_write(&mut self, toggle: bool, chunk: Vec<u8>) -> Result<SerialFrame> {
        let t = toggle_bit(toggle);
        let confirm = [chunk.len() as u8 | t, 0];
        Ok(match std::mem::replace(&mut self.segmented, Segmented::None) {
            Segmented::LocalWrite { addr, mut data, length } => {
                data.extend_from_slice(&chunk);
                if data.len() < length {
                    self.segmented = Segmented::LocalWrite { addr, data, length };
                    answer(0, &confirm)
                } else if data.len() > length {
                    answer(abort::LENGTH_TOO_HIGH, &confirm)
                } else {
                    answer(self.objects().write(addr, &data).err().unwrap_or(0), &confirm)
                }
            }
            Segmented::ForwardedWrite { node, addr, left } => {
                if chunk.len() > GATEWAY_SEGMENT || chunk.len() > left {
                    return self.sdo_abort(node, addr, abort::LENGTH_TOO_HIGH);
                }
                let left = left - chunk.len();
                let segment = Segment::new(toggle, &chunk, left == 0);
                match self.sdo(node, Request::DownloadSegment(segment))? {
                    Err(code) => answer(code, &confirm),
                    Ok(Some(Response::DownloadSegment { .. })) => {
                        if left > 0 {
                            self.segmented = Segmented::ForwardedWrite { node, addr, left };
                        }
                        answer(0, &confirm)
                    }
                    Ok(_) => self.sdo_abort(node, addr, abort::UNKNOWN_COMMAND)?,
                }
            }
            _ => answer(abort::UNKNOWN_COMMAND, &confirm),
        })
    }

    /// Abort the SDO transfer on the bus and report the code.
    fn sdo_abort(&mut self, node: u8, addr: ObjAddr, code: u32) -> Result<SerialFrame> {
        self.segmented = Segmented::None;
        self.send(&Frame::new(sdo::request_cob(node), &sdo::abort_frame(addr, code)))?;
        Ok(answer(code, &[0; 4]))
    }

    /// Put a frame on the bus. Frames that came in before it are no answer to it: the
    /// gateway waits only for answers to what it sends, so they are dropped first.
    fn send(&mut self, f: &Frame) -> Result<()> {
        // Dropped unseen by the trace, as ever; the log keeps everything that came.
        while let Some(stale) = self.link.recv(self.link.now())? {
            self.seen(Dir::Rx, &stale, false);
        }
        self.seen(Dir::Tx, f, true);
        self.link.send(f)
    }

    /// One SDO request and its answer: the server's answer (`None` for a command
    /// specifier no server sends), its abort code, or the SDO-timeout code when nothing came.
    fn sdo(&mut self, node: u8, request: Request) -> Result<std::result::Result<Option<Response>, u32>> {
        if !(1..=127).contains(&node) {
            return Ok(Err(command::CAN_ID));
        }
        let request = request.emit();
        self.send(&Frame::new(sdo::request_cob(node), &request))?;
        // An initiate (or abort) answer names its object: one that names another answers
        // some other request, from an earlier transfer, and is not ours.
        let initiate = match Request::parse(&request) {
            Some(Request::InitiateUpload { addr }) => Some((addr, true)),
            Some(Request::InitiateDownload { addr, .. }) => Some((addr, false)),
            _ => None,
        };
        if let Some((own, upload)) = initiate.filter(|_| self.wrong_answers) {
            let other = ObjAddr::new(own.index ^ 1, own.sub);
            let stray = |addr| match upload {
                true => Response::InitiateUpload { addr, init: Initiate::expedited(&[0xEF, 0xBE, 0xAD, 0xDE]) },
                false => Response::InitiateDownload { addr },
            };
            self.arrived.push_back(Frame::new(sdo::response_cob(node), &stray(other).emit()));
            self.arrived.push_back(Frame::new(sdo::response_cob(node % 127 + 1), &stray(own).emit()));
        }
        let same_object = |f: &Frame| initiate.is_none() || f.data().get(1..4) == Some(&request[1..4]);
        let answers_request = |f: &Frame| f.id() == sdo::response_cob(node) && !f.is_remote() && same_object(f);
        let answer = self.wait_for(answers_request, self.can_timeout)?;
        Ok(match answer {
            None => Err(abort::TIMED_OUT),
            Some(f) => match Response::parse(&sdo::pad(f.data())) {
                Some(Response::Abort { code, .. }) => {
                    self.segmented = Segmented::None;
                    Err(code)
                }
                other => Ok(other),
            },
        })
    }

    fn wait_for(&mut self, want: impl Fn(&Frame) -> bool, timeout: Duration) -> Result<Option<Frame>> {
        let deadline = self.link.now() + timeout;
        while let Some(f) = self.arrived.pop_front().map_or_else(|| self.link.recv(deadline), |f| Ok(Some(f)))? {
            self.seen(Dir::Rx, &f, true);
            if want(&f) {
                return Ok(Some(f));
            }
        }
        Ok(None)
    }
}

/// `d` in `N` bytes: cut, or filled up with zeros.
fn padded<const N: usize>(d: &[u8]) -> [u8; N] {
    let mut out = [0u8; N];
    out[..d.len().min(N)].copy_from_slice(&d[..d.len().min(N)]);
    out
}

/// A segment's control byte with its toggle bit.
pub(crate) fn toggle_bit(toggle: bool) -> u8 {
    if toggle {
        TOGGLE
    } else {
        0
    }
}
