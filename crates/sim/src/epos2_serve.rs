//! Serve the simulated EPOS2 on a pseudo-terminal, speaking RS232 (with the 'O'/'F'
//! handshake) or USB framing, optionally at the pace of a real baud rate and with faults
//! injected for tests.

use super::epos2_device::{toggle_bit, Epos2Device};
use super::pty::failed;
use crate::epos2::command::{self, Command};
use crate::epos2::frame::{self, Frame as SerialFrame, UsbDecoder};
pub use crate::epos2::Framing;
use crate::error::{PtyOp, Result};
use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
use std::io::Write;
use std::os::fd::AsFd;
use std::time::{Duration, Instant};

pub use super::serial_fault::{Fault, FaultKind, BABBLE_TIME, LATE};

/// How a simulated EPOS2 is served on a pseudo-terminal.
pub struct ServeOptions {
    /// RS232 or USB framing, as the client is to speak it.
    pub framing: Framing,
    /// Pace bytes as a line at this many bit/s would (10 bits a byte); `None`: as fast as the pty goes.
    pub baud: Option<u32>,
    /// The serial faults to inject, each on the n-th command frame or on all.
    pub faults: Vec<Fault>,
}

/// The master side of the pty, with optional wire-speed pacing.
struct Wire {
    master: std::fs::File,
    byte_time: Option<Duration>,
    /// When the line is next free: received and sent bytes each take one byte time.
    clock: Instant,
    inbox: Vec<u8>,
    pos: usize,
}

impl Wire {
    /// Let `bytes` byte times pass on the line. A line that has stayed busy keeps its
    /// schedule, so that the lateness of each sleep does not add up over a frame.
    fn pace(&mut self, bytes: usize) {
        const SLACK: Duration = Duration::from_micros(300);
        let Some(t) = self.byte_time else { return };
        let now = Instant::now();
        if now > self.clock + SLACK {
            self.clock = now;
        }
        self.clock += t * bytes as u32;
        if self.clock > now {
            std::thread::sleep(self.clock - now);
        }
    }

    /// The next byte from the master, or `None` after `timeout` (forever when `None`).
    fn byte(&mut self, timeout: Option<Duration>) -> Result<Option<u8>> {
        if self.pos == self.inbox.len() {
            let capped =
                |t: Duration| PollTimeout::try_from(t.as_millis().min(60_000) as u32).unwrap_or(PollTimeout::MAX);
            let ms = timeout.map_or(PollTimeout::NONE, capped);
            let mut fds = [PollFd::new(self.master.as_fd(), PollFlags::POLLIN)];
            // A signal (the request to stop, caught) cuts the wait short: wait again.
            let ready = loop {
                match poll(&mut fds, ms) {
                    Err(nix::errno::Errno::EINTR) => continue,
                    r => break r.map_err(|e| failed(PtyOp::Poll, e))?,
                }
            };
            if ready == 0 {
                return Ok(None);
            }
            let mut buf = [0u8; 512];
            let n = std::io::Read::read(&mut self.master, &mut buf).map_err(|e| failed(PtyOp::Read, e))?;
            if n == 0 {
                return Ok(None);
            }
            self.inbox = buf[..n].to_vec();
            self.pos = 0;
            self.pace(n);
        }
        self.pos += 1;
        Ok(Some(self.inbox[self.pos - 1]))
    }

    fn send(&mut self, bytes: &[u8]) -> Result<()> {
        // The bytes leave once the line would have carried them.
        self.pace(bytes.len());
        self.master.write_all(bytes).map_err(|e| failed(PtyOp::Write, e))
    }

    fn unread(&mut self) {
        self.pos -= 1;
    }

    fn discard(&mut self) {
        self.pos = self.inbox.len();
    }
}

/// Serve until killed. `ready` receives the pty path once clients can open it.
pub fn serve(mut device: Epos2Device, opts: &ServeOptions, ready: impl FnOnce(&str) -> Result<()>) -> Result<()> {
    let (master, _slave, path) = super::pty::open_raw()?;
    let byte_time = opts.baud.map(|b| Duration::from_secs_f64(10.0 / b as f64));
    let mut wire =
        Wire { master: std::fs::File::from(master), byte_time, clock: Instant::now(), inbox: Vec::new(), pos: 0 };
    ready(&path)?;
    let mut count = 0u64;
    let mut usb = UsbDecoder::new();
    let encode = |answer: &SerialFrame| match opts.framing {
        Framing::Rs232 => frame::rs232_encode(answer),
        Framing::Usb => frame::usb_encode(answer),
    };
    loop {
        let request = match opts.framing {
            Framing::Rs232 => rs232_receive(&mut wire, opts, &mut count)?,
            Framing::Usb => usb_receive(&mut wire, &mut usb, &mut count)?,
        };
        let Some(request) = request else { continue };
        let fault = opts.faults.iter().find(|f| f.nth.is_none_or(|n| n == count)).map(|f| f.kind);
        if fault == Some(FaultKind::Nack) && opts.framing == Framing::Usb {
            wire.send(&frame::usb_encode(&command::answer(crate::canopen::abort::CRC_ERROR, &[])))?;
            continue;
        }
        if fault == Some(FaultKind::Stale) {
            let leftover = Command::ReadObject { node: 0, addr: crate::canopen::ObjAddr::new(0x1000, 0) };
            let leftover = device.execute(&leftover.to_frame())?;
            send_encoded(&mut wire, opts.framing, &encode(&leftover))?;
        }
        device.inject_wrong_answers(fault == Some(FaultKind::WrongObject));
        let cmd = Command::from_frame(&request);
        let answer = match (fault, &cmd) {
            (Some(FaultKind::EmptySegments), Some(Command::SegmentRead { toggle })) => {
                command::answer(0, &[toggle_bit(*toggle) | command::MORE])
            }
            (Some(FaultKind::EndlessSegments), Some(Command::SegmentRead { toggle })) => {
                let control = command::MAX_SEGMENT as u8 | toggle_bit(*toggle) | command::MORE;
                command::answer(0, &[&[control][..], &[0xEE; command::MAX_SEGMENT]].concat())
            }
            _ => device.execute(&request)?,
        };
        device.link_mut().save_if_changed()?;
        let answered = opts.framing == Framing::Usb || cmd.is_none_or(|c| c.answered_on_rs232());
        if !answered || fault == Some(FaultKind::Mute) {
            continue;
        }
        match fault {
            Some(FaultKind::Late) => std::thread::sleep(LATE),
            Some(FaultKind::Babble) => {
                babble(&mut wire)?;
                continue;
            }
            _ => {}
        }
        let mut bytes = encode(&answer);
        match fault {
            Some(FaultKind::Crc) => {
                let n = bytes.len();
                bytes[n - 2] ^= 0x5A;
                if opts.framing == Framing::Usb && bytes[n - 2] == frame::DLE {
                    bytes[n - 2] ^= 0x01;
                }
            }
            Some(FaultKind::Drop) => _ = bytes.pop(),
            Some(FaultKind::Garbage) => bytes = [&[0x55, frame::DLE, 0x13, 0xAA][..], &bytes].concat(),
            _ => {}
        }
        send_encoded(&mut wire, opts.framing, &bytes)?;
    }
}

/// An answer's bytes to the master: on RS232 with the handshake.
fn send_encoded(wire: &mut Wire, framing: Framing, bytes: &[u8]) -> Result<()> {
    match framing {
        Framing::Rs232 => rs232_answer(wire, bytes),
        Framing::Usb => wire.send(bytes),
    }
}

/// Bytes without pause and without a frame start, as from a wrong bit rate or a broken
/// device; the pty blocks them once the client stops reading.
fn babble(wire: &mut Wire) -> Result<()> {
    let start = Instant::now();
    // No DLE: nothing that could start a USB frame.
    let mut bytes = super::profiles::pattern_bytes().map(|b| b.clamp(0x03, 0x8F));
    while start.elapsed() < BABBLE_TIME {
        wire.send(&bytes.by_ref().take(64).collect::<Vec<u8>>())?;
    }
    Ok(())
}

/// Seed 000 §5.1.1: take a frame with the handshake; `None` when it failed part-way.
fn rs232_receive(wire: &mut Wire, opts: &ServeOptions, count: &mut u64) -> Result<Option<SerialFrame>> {
    const FRAME_TIMEOUT: Option<Duration> = Some(Duration::from_millis(500));
    let Some(op) = wire.byte(None)? else { return Ok(None) };
    wire.send(b"O")?;
    let Some(lm1) = wire.byte(FRAME_TIMEOUT)? else { return Ok(None) };
    let mut raw = vec![op, lm1];
    for _ in 0..frame::rs232_body_len(lm1) {
        let Some(b) = wire.byte(FRAME_TIMEOUT)? else { return Ok(None) };
        raw.push(b);
    }
    *count += 1;
    let nack = opts.faults.iter().any(|f| f.kind == FaultKind::Nack && f.nth.is_none_or(|n| n == *count));
    match frame::rs232_decode(&raw) {
        Ok(f) if !nack => {
            wire.send(b"O")?;
            Ok(Some(f))
        }
        _ => {
            wire.send(b"F")?;
            wire.discard();
            Ok(None)
        }
    }
}

/// Send an answer with the handshake: OpCode, the master's 'O', the rest, its end ack.
fn rs232_answer(wire: &mut Wire, bytes: &[u8]) -> Result<()> {
    let timeout = Some(Duration::from_millis(500));
    wire.send(&bytes[..1])?;
    let Some(b) = wire.byte(timeout)? else { return Ok(()) };
    if b != b'O' {
        // The master gave up on this answer and starts anew: that byte opens its next frame.
        wire.unread();
        return Ok(());
    }
    wire.send(&bytes[1..])?;
    // The end acknowledge: 'F' means the master saw a bad CRC and will ask again; anything
    // else is the master starting over after losing part of the answer.
    if wire.byte(timeout)?.is_some_and(|b| b != b'O' && b != b'F') {
        wire.unread();
    }
    Ok(())
}

fn usb_receive(wire: &mut Wire, decoder: &mut UsbDecoder, count: &mut u64) -> Result<Option<SerialFrame>> {
    let Some(decoded) = wire.byte(None)?.and_then(|b| decoder.push(b)) else { return Ok(None) };
    *count += 1;
    match decoded {
        Ok(f) => Ok(Some(f)),
        // Seed 000 §4.1.3.1: a bad frame is answered with the error code.
        Err(_) => {
            wire.send(&frame::usb_encode(&command::answer(crate::canopen::abort::CRC_ERROR, &[])))?;
            Ok(None)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fault_syntax() {
        assert_eq!("crc@3".parse::<Fault>().unwrap(), Fault { kind: FaultKind::Crc, nth: Some(3) });
        assert_eq!("nack@*".parse::<Fault>().unwrap(), Fault { kind: FaultKind::Nack, nth: None });
        assert_eq!("mute".parse::<Fault>().unwrap(), Fault { kind: FaultKind::Mute, nth: Some(1) });
        assert!("melt@1".parse::<Fault>().is_err());
        assert!("crc@0".parse::<Fault>().is_err());
        assert_eq!("stale@1".parse::<Fault>().unwrap(), Fault { kind: FaultKind::Stale, nth: Some(1) });
        assert_eq!(
            "endless-segments@*".parse::<Fault>().unwrap(),
            Fault { kind: FaultKind::EndlessSegments, nth: None }
        );
    }
}
