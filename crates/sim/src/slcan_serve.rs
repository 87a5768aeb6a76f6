//! The simulated network behind a simulated slcan adapter on a pseudo-terminal: what a
//! CANable or CANUSB would show a host, with the sim devices on its bus. The adapter side
//! is a `FrameLink`, so `bridge::run` connects it to the devices as it does a CAN interface.

use super::pty::failed;
use super::serial_fault::{Fault, FaultKind};
use crate::bus::FrameLink;
use crate::error::{PtyOp, Result};
use crate::frame::Frame;
use crate::slcan::wire::{self, decode_command, Command, Message, Status, BELL, CR, MAX_LINE};
use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
use std::collections::VecDeque;
use std::io::{Read, Write};
use std::os::fd::{AsFd, OwnedFd};
use std::time::Instant;

/// The adapter side of the pty.
pub struct SlcanAdapter {
    master: std::fs::File,
    /// Kept open so that the pty outlives each host program.
    _slave: OwnedFd,
    path: String,
    /// The bus's rate (kbit/s): an adapter set to another hears nothing, as on a real bus.
    bus_kbit: u32,
    kbit: Option<u32>,
    open: bool,
    /// Opened with `L`: it hears the bus but sends nothing.
    listen_only: bool,
    timestamps: bool,
    started: Instant,
    line: Vec<u8>,
    /// Frames from the host, for the devices.
    rx: VecDeque<Frame>,
    faults: Vec<Fault>,
    /// Lines from the host so far, for `--fault KIND@N`.
    count: u64,
    /// Status flags since the host last asked ('F' reads and clears them, as on a Lawicel
    /// adapter): a frame sent at another rate than the bus's is acknowledged by nobody,
    /// and the controller counts its way to error passive.
    flags: u8,
    /// Its controller is bus-off (`--fault bus:off`): it neither sends nor receives. A frame
    /// to send is taken (`z`, as a CANable's bxCAN fills a mailbox) and never leaves, so the
    /// host sees silence and then the flags, as from a real one. Lawicel's
    /// `F` has no bus-off flag: it reports what an SJA1000 adapter raises on the way there,
    /// error warning, error passive and bus error, on every read, since the state lasts
    /// (restart-ms 0: no automatic restart is modelled).
    bus_off: bool,
}

/// What an SJA1000-based adapter reports after sending at the wrong bit rate: error
/// warning, error passive and bus error (the frame is never acknowledged).
const WRONG_RATE_FLAGS: u8 = 1 << 2 | 1 << 5 | 1 << 7;

impl SlcanAdapter {
    /// A new pty; `bus_kbit` is the sim network's bit rate.
    pub fn create(bus_kbit: u32, faults: Vec<Fault>) -> Result<SlcanAdapter> {
        let (master, slave, path) = super::pty::open_raw()?;
        Ok(SlcanAdapter {
            master: std::fs::File::from(master),
            _slave: slave,
            path,
            bus_kbit,
            kbit: None,
            open: false,
            listen_only: false,
            timestamps: false,
            started: Instant::now(),
            line: Vec::new(),
            rx: VecDeque::new(),
            faults,
            count: 0,
            flags: 0,
            bus_off: false,
        })
    }

    /// Its controller bus-off from the start, and for good (see the field's comment).
    pub fn bus_off(mut self) -> SlcanAdapter {
        self.bus_off = true;
        self
    }

    /// The pty the host opens (`/dev/pts/N`).
    pub fn path(&self) -> &str {
        &self.path
    }

    fn write(&mut self, bytes: &[u8]) -> Result<()> {
        self.master.write_all(bytes).map_err(|e| failed(PtyOp::Write, e))
    }

    /// Frames pass only on an open channel at the bus's rate.
    fn on_bus(&self) -> bool {
        self.open && self.kbit == Some(self.bus_kbit)
    }

    /// Answer one line from the host.
    fn on_line(&mut self, line: &[u8]) -> Result<()> {
        self.count += 1;
        let fault = self.faults.iter().find(|f| f.nth.is_none_or(|n| n == self.count)).map(|f| f.kind);
        match fault {
            Some(FaultKind::Mute) => return Ok(()),
            Some(FaultKind::Nack) => return self.write(&[BELL]),
            Some(FaultKind::Garbage) => self.write(b"\x55junk\r")?,
            // Busy: the line and everything after it are answered late, in order.
            Some(FaultKind::Late) => std::thread::sleep(super::serial_fault::LATE),
            _ => {}
        }
        let answer = match decode_command(line) {
            Ok(Some(Command::BitRate(code))) if !self.open => {
                self.kbit = wire::BIT_RATES.iter().find(|(c, _)| *c == code).map(|(_, k)| *k);
                Message::Ok
            }
            Ok(Some(cmd @ (Command::Open | Command::ListenOnly))) if !self.open && self.kbit.is_some() => {
                self.open = true;
                self.listen_only = cmd == Command::ListenOnly;
                // Opening starts the controller afresh: errors of an earlier channel (at
                // another rate, another program's) are not this one's.
                self.flags = 0;
                Message::Ok
            }
            Ok(Some(Command::Close)) if self.open => {
                self.open = false;
                Message::Ok
            }
            Ok(Some(Command::Status)) if self.bus_off => Message::Status(Status(WRONG_RATE_FLAGS)),
            Ok(Some(Command::Status)) => Message::Status(Status(std::mem::take(&mut self.flags))),
            // Taken, never sent: the controller is bus-off.
            Ok(Some(Command::Transmit(_))) if self.bus_off && self.open && !self.listen_only => Message::Sent,
            Ok(Some(Command::Version)) => Message::Version("1013".into()),
            Ok(Some(Command::Serial)) => Message::Serial("SIM1".into()),
            Ok(Some(Command::Timestamps(on))) if !self.open => {
                self.timestamps = on;
                Message::Ok
            }
            Ok(Some(Command::Transmit(f))) if self.open && !self.listen_only => {
                if self.on_bus() && fault != Some(FaultKind::Drop) {
                    self.rx.push_back(f);
                } else if !self.on_bus() {
                    self.flags |= WRONG_RATE_FLAGS;
                }
                Message::Sent
            }
            Ok(None) if self.open => Message::Sent,
            // Refused: a command out of place, or a line that is not slcan.
            _ => Message::Refused,
        };
        let mut bytes = answer.encode();
        if fault == Some(FaultKind::Crc) && bytes.len() > 1 {
            bytes[0] ^= 0x20;
        }
        self.write(&bytes)
    }

    /// Read and answer what the host sent, waiting until `deadline` for something.
    fn poll_host(&mut self, deadline: Instant) -> Result<()> {
        let left = deadline.saturating_duration_since(Instant::now());
        let ms = PollTimeout::try_from(left.as_millis().min(60_000) as u32).unwrap_or(PollTimeout::MAX);
        let mut fds = [PollFd::new(self.master.as_fd(), PollFlags::POLLIN)];
        match poll(&mut fds, ms) {
            // A signal (the request to stop, caught) cut the wait short: the caller waits again.
            Ok(0) | Err(nix::errno::Errno::EINTR) => return Ok(()),
            r => r.map_err(|e| failed(PtyOp::Poll, e))?,
        };
        let mut buf = [0u8; 512];
        let n = match self.master.read(&mut buf) {
            Ok(n) => n,
            // No host has the pty open: wait for one, as an unplugged adapter would.
            Err(e) if e.raw_os_error() == Some(nix::libc::EIO) => {
                std::thread::sleep(left.min(std::time::Duration::from_millis(20)));
                return Ok(());
            }
            Err(e) => return Err(failed(PtyOp::Read, e)),
        };
        for &b in &buf[..n] {
            match b {
                CR => {
                    let line = std::mem::take(&mut self.line);
                    if line.len() <= MAX_LINE {
                        self.on_line(&line)?;
                    } else {
                        self.write(&[BELL])?;
                    }
                }
                b'\n' => {}
                _ if self.line.len() <= MAX_LINE => self.line.push(b),
                _ => {}
            }
        }
        Ok(())
    }
}

impl FrameLink for SlcanAdapter {
    /// A frame from the devices, to the host.
    fn send(&mut self, frame: &Frame) -> Result<()> {
        // A bus-off controller hears nothing; traffic at another bit rate decodes as nothing
        // but bus errors.
        if self.bus_off || !self.on_bus() {
            if self.open && !self.bus_off {
                self.flags |= WRONG_RATE_FLAGS;
            }
            return Ok(());
        }
        let mut bytes = Message::Frame(*frame).encode();
        if self.timestamps {
            let ms = (self.started.elapsed().as_millis() % 60_000) as u16;
            bytes.pop();
            bytes.extend(format!("{ms:04X}\r").into_bytes());
        }
        self.write(&bytes)
    }

    /// A frame from the host, for the devices.
    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        loop {
            if let Some(f) = self.rx.pop_front() {
                return Ok(Some(f));
            }
            if Instant::now() >= deadline {
                return Ok(None);
            }
            self.poll_host(deadline)?;
        }
    }

    fn name(&self) -> String {
        format!("slcan:{}", self.path)
    }
}
