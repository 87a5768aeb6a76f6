//! The two EPOS2 links: RS232 with its 'O'/'F' handshake, USB with DLE/STX framing.
//!
//! Answers carry no reference to their command, so the link keeps itself in step: after
//! opening the port and after every failure it clears the input and sends a synchronisation
//! probe (an opcode that does not exist), discarding every answer before the probe's own —
//! answers still owed to an earlier client or to a command that timed out. Every answer is
//! then checked against its command (opcode, length, CRC); one that does not fit is
//! discarded, a few at most. Both links retry a command once after a failed handshake, a bad
//! CRC, a timeout or a misfit, then give up with a link error that says what happened.
//! Every wait is bounded: per frame by the timeout, in number by the discard limit, and the
//! wait for a quiet line by a total limit.

use super::command::{self, Command};
use super::error::Epos2Error;
pub use super::error::Failure;
use super::frame::{self, Frame, FrameError, UsbDecoder};
use super::Framing;
use crate::trace;
use std::time::{Duration, Instant};

const OKAY: u8 = b'O';
const FAILED: u8 = b'F';

use crate::serial::SerialIo;

/// Sends one command frame and returns the answer frame, if the command has one here.
pub trait Transport {
    /// Sends `command`; waits for its answer when `answered` (RS232 leaves some unanswered) and
    /// returns it.
    fn transact(&mut self, command: &Frame, answered: bool) -> Result<Option<Frame>, Epos2Error>;
    /// `epos2-rs232:/dev/ttyS0`, for messages.
    fn describe(&self) -> String;
    /// RS232 leaves some commands unanswered; USB answers all.
    fn is_rs232(&self) -> bool;
}

/// Answers that fit none of our commands, discarded in one exchange before giving up.
const MAX_DISCARDED: usize = 4;
/// The synchronisation probe waits at least this long for each answer: it may be queued
/// behind a command of an earlier client that the EPOS2 is still forwarding to a slow node.
const PROBE_WAIT: Duration = Duration::from_secs(1);

/// A serial port with a little read buffer and a per-frame timeout.
struct Port<S> {
    io: S,
    buf: Vec<u8>,
    pos: usize,
    timeout: Duration,
}

impl<S: SerialIo> Port<S> {
    fn new(io: S, timeout: Duration) -> Port<S> {
        Port { io, buf: Vec::new(), pos: 0, timeout }
    }

    /// Seed 000 §5.1.6: the frame timeout restarts with each frame.
    fn deadline(&self) -> Instant {
        Instant::now() + self.timeout
    }

    /// The next byte, or `None` once `deadline` has passed — also on a line that never
    /// stops sending.
    fn byte(&mut self, deadline: Instant) -> Result<Option<u8>, Failure> {
        if Instant::now() >= deadline {
            return Ok(None);
        }
        if self.pos == self.buf.len() {
            self.buf.resize(256, 0);
            let n = self.io.read_some(&mut self.buf, deadline).map_err(|e| Failure::Io(e.into()))?;
            self.buf.truncate(n);
            self.pos = 0;
            if n == 0 {
                return Ok(None);
            }
        }
        self.pos += 1;
        Ok(Some(self.buf[self.pos - 1]))
    }

    fn expect_byte(&mut self, deadline: Instant, stage: &'static str) -> Result<u8, Failure> {
        self.byte(deadline)?.ok_or(Failure::Timeout(stage))
    }

    fn send(&mut self, bytes: &[u8]) -> Result<(), Failure> {
        self.io.write_all(bytes).map_err(|e| Failure::Io(e.into()))
    }

    /// Drop what has arrived and not been read.
    fn clear(&mut self) -> Result<(), Failure> {
        self.buf.clear();
        self.pos = 0;
        self.io.discard_input().map_err(|e| Failure::Io(e.into()))
    }

    /// Drop whatever is in flight: wait for the line to fall quiet, then clear it. A line
    /// that keeps talking is given a few timeouts, not forever.
    fn resync(&mut self) -> Result<(), Failure> {
        let quiet = (self.timeout / 4).clamp(Duration::from_millis(5), Duration::from_millis(50));
        let start = Instant::now();
        let limit = start + (self.timeout * 4).max(Duration::from_millis(500));
        let mut scratch = [0u8; 256];
        let mut until = start + quiet;
        let mut bytes = self.buf.len() - self.pos;
        loop {
            if Instant::now() >= limit {
                return Err(Failure::Babble(bytes, start.elapsed().as_millis()));
            }
            // Quiet means a read that waited until `until` got nothing: a reader that was
            // merely slow finds the bytes waiting.
            let n = self.io.read_some(&mut scratch, until.min(limit)).map_err(|e| Failure::Io(e.into()))?;
            if n > 0 {
                bytes += n;
                until = Instant::now() + quiet;
            } else if Instant::now() >= until {
                break;
            }
        }
        self.clear()
    }
}

/// An EPOS2 on a serial port, with either framing.
pub struct SerialTransport<S> {
    port: Port<S>,
    framing: Framing,
    describe: String,
    /// Whether every answer still owed to someone else has been received and discarded.
    in_step: bool,
}

impl<S: SerialIo> SerialTransport<S> {
    /// A transport over `io`; `describe` names the bus in messages, `timeout` bounds each
    /// frame's answer (seed 000 §5.1.6).
    pub fn new(io: S, framing: Framing, describe: String, timeout: Duration) -> SerialTransport<S> {
        SerialTransport { port: Port::new(io, timeout), framing, describe, in_step: false }
    }

    /// Clear the input and send the probe; every answer before the probe's is discarded.
    fn synchronise(&mut self) -> Result<(), Failure> {
        self.port.clear()?;
        let probe = command::sync_probe();
        let wait = (self.port.timeout * 2).max(PROBE_WAIT);
        let mut discarded = 0;
        let mut answer = self.send_and_receive(&probe, wait)?;
        loop {
            match answer {
                Ok(f) if command::is_probe_answer(&f) => break,
                // An answer someone else was owed, or the remains of one cut by the clear.
                _ if discarded < MAX_DISCARDED => discarded += 1,
                _ => return Err(Failure::Misfit(discarded)),
            }
            answer = self.receive(wait)?;
        }
        self.in_step = true;
        Ok(())
    }

    /// Send a frame and receive the first answer frame, or a frame error.
    fn send_and_receive(&mut self, f: &Frame, wait: Duration) -> Result<Result<Frame, FrameError>, Failure> {
        match self.framing {
            Framing::Rs232 => rs232_send(&mut self.port, &self.describe, f, wait)?,
            Framing::Usb => {
                let bytes = frame::usb_encode(f);
                trace::bytes(&self.describe, "<", &bytes);
                self.port.send(&bytes)?;
            }
        }
        self.receive(wait)
    }

    fn receive(&mut self, wait: Duration) -> Result<Result<Frame, FrameError>, Failure> {
        let until = Instant::now() + wait;
        match self.framing {
            Framing::Rs232 => rs232_receive(&mut self.port, &self.describe, until),
            Framing::Usb => usb_receive(&mut self.port, &self.describe, until),
        }
    }

    /// One try: in step first, then the command and its answer.
    fn attempt(&mut self, command: &Frame, answered: bool) -> Result<Option<Frame>, Failure> {
        if !self.in_step {
            self.synchronise()?;
        }
        let cmd = Command::from_frame(command);
        let timeout = self.port.timeout;
        if !answered {
            rs232_send(&mut self.port, &self.describe, command, timeout)?;
            return Ok(None);
        }
        let mut answer = self.send_and_receive(command, timeout)?;
        let mut discarded = 0;
        loop {
            let f = answer.map_err(Failure::Frame)?;
            // Seed 000 §4.1.3.1: a frame the EPOS2 could not read comes back as an answer
            // carrying the CRC error code: USB's counterpart of RS232's 'F'.
            if command::parse_answer(&f).is_some_and(|(code, _)| code == crate::canopen::abort::CRC_ERROR) {
                return Err(Failure::Nack("with error 0x05040004: it saw a bad CRC"));
            }
            if cmd.as_ref().is_none_or(|c| c.answer_fits(&f)) {
                return Ok(Some(f));
            }
            if discarded == MAX_DISCARDED {
                return Err(Failure::Misfit(discarded + 1));
            }
            discarded += 1;
            answer = self.receive(timeout)?;
        }
    }
}

impl<S: SerialIo> Transport for SerialTransport<S> {
    fn transact(&mut self, command: &Frame, answered: bool) -> Result<Option<Frame>, Epos2Error> {
        let what = Command::from_frame(command).map_or("command", |c| c.name());
        let (failure, retry) = match self.attempt(command, answered) {
            Ok(a) => return Ok(a),
            Err(first) if first.retryable() => {
                tracing::trace!(target: "canctl::epos2", "{}: {what} failed: {first}; resync and retry", self.describe);
                self.in_step = false;
                match self.port.resync().and_then(|()| self.attempt(command, answered)) {
                    Ok(a) => return Ok(a),
                    Err(second) => (first, Some(second)),
                }
            }
            Err(e) => (e, None),
        };
        // Whatever is still on its way belongs to nobody now.
        self.in_step = false;
        Err(Epos2Error::Serial { bus: self.describe.clone(), command: what, failure, retry })
    }

    fn describe(&self) -> String {
        self.describe.clone()
    }

    fn is_rs232(&self) -> bool {
        self.framing == Framing::Rs232
    }
}

/// Seed 000 §5.1.1.2: OpCode, wait (up to `ready_wait`) for the ready ack, the rest, wait
/// for the end ack.
fn rs232_send<S: SerialIo>(
    port: &mut Port<S>,
    name: &str,
    command: &Frame,
    ready_wait: Duration,
) -> Result<(), Failure> {
    let bytes = frame::rs232_encode(command);
    trace::bytes(name, "<", &bytes);
    port.send(&bytes[..1])?;
    let until = Instant::now() + ready_wait;
    let mut skipped = 0;
    loop {
        match port.expect_byte(until, "to the opcode (ready acknowledge)")? {
            OKAY => break,
            FAILED => return Err(Failure::Nack("'F' to the opcode (not ready)")),
            // The start of an answer still owed to an earlier command, which the EPOS2
            // abandons when it gets our opcode instead of its ready acknowledge.
            command::ANSWER if skipped < MAX_DISCARDED => skipped += 1,
            b => return Err(Failure::Unexpected(b, "instead of the ready acknowledge")),
        }
    }
    port.send(&bytes[1..])?;
    match port.expect_byte(port.deadline(), "to the frame (end acknowledge)")? {
        OKAY => Ok(()),
        FAILED => Err(Failure::Nack("'F' to the frame (CRC or length refused)")),
        b => Err(Failure::Unexpected(b, "instead of the end acknowledge")),
    }
}

/// §5.1.1.3: the answer's OpCode 0x00, our ready ack, the rest, our end ack.
fn rs232_receive<S: SerialIo>(
    port: &mut Port<S>,
    name: &str,
    until: Instant,
) -> Result<Result<Frame, FrameError>, Failure> {
    let op = port.expect_byte(until, "with the answer")?;
    if op != command::ANSWER {
        return Err(Failure::Unexpected(op, "instead of the answer opcode 0x00"));
    }
    port.send(&[OKAY])?;
    let until = port.deadline();
    let lm1 = port.expect_byte(until, "in the answer's length")?;
    let mut raw = vec![op, lm1];
    for _ in 0..frame::rs232_body_len(lm1) {
        raw.push(port.expect_byte(until, "in the middle of the answer")?);
    }
    trace::bytes(name, ">", &raw);
    let decoded = frame::rs232_decode(&raw);
    port.send(&[if decoded.is_ok() { OKAY } else { FAILED }])?;
    Ok(decoded)
}

/// The next USB frame (anything before DLE STX is skipped), or a frame error.
fn usb_receive<S: SerialIo>(
    port: &mut Port<S>,
    name: &str,
    until: Instant,
) -> Result<Result<Frame, FrameError>, Failure> {
    let mut decoder = UsbDecoder::new();
    let mut raw = Vec::new();
    loop {
        let stage = if decoder.in_frame() { "in the middle of the answer" } else { "with the answer" };
        let b = port.expect_byte(until, stage)?;
        raw.push(b);
        if let Some(r) = decoder.push(b) {
            trace::bytes(name, ">", &raw);
            return Ok(r);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canopen::ObjAddr;
    use std::collections::VecDeque;
    use std::io;

    /// A serial port whose device answers each write with the next scripted bytes.
    struct Scripted {
        /// Bytes that have arrived and not been read.
        input: VecDeque<u8>,
        /// What arrives after each write, in order.
        replies: VecDeque<Vec<u8>>,
        /// Bytes that keep arriving whatever is written (a babbling line).
        babble: bool,
        written: Vec<Vec<u8>>,
    }

    impl Scripted {
        fn new(already: &[u8], replies: Vec<Vec<u8>>) -> Scripted {
            Scripted {
                input: already.iter().copied().collect(),
                replies: replies.into(),
                babble: false,
                written: vec![],
            }
        }
    }

    impl SerialIo for Scripted {
        fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
            self.written.push(bytes.to_vec());
            if let Some(r) = self.replies.pop_front() {
                self.input.extend(r);
            }
            Ok(())
        }

        fn read_some(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
            if self.babble {
                buf.fill(0x55);
                return Ok(buf.len());
            }
            if self.input.is_empty() {
                std::thread::sleep(deadline.saturating_duration_since(Instant::now()));
                return Ok(0);
            }
            let n = buf.len().min(self.input.len());
            for b in buf.iter_mut().take(n) {
                *b = self.input.pop_front().unwrap();
            }
            Ok(n)
        }

        fn discard_input(&mut self) -> io::Result<()> {
            self.input.clear();
            Ok(())
        }
    }

    fn usb(f: &Frame) -> Vec<u8> {
        frame::usb_encode(f)
    }

    fn transport(io: Scripted) -> SerialTransport<Scripted> {
        SerialTransport::new(io, Framing::Usb, "test".into(), Duration::from_millis(30))
    }

    fn read_object() -> Frame {
        Command::ReadObject { node: 5, addr: ObjAddr::new(0x1018, 1) }.to_frame()
    }

    #[test]
    fn answers_owed_to_others_are_discarded_before_ours() {
        let stale = usb(&command::answer(0, &[0x92, 0x01, 0x02, 0x00]));
        let probe = usb(&command::answer(command::ILLEGAL_COMMAND, &[]));
        let ours = usb(&command::answer(0, &[0x40, 0, 0, 0]));
        // One answer already in the line (cleared on open), one still on its way when the
        // probe goes out, then the probe's answer; then ours.
        let mut late_then_probe = stale.clone();
        late_then_probe.extend(&probe);
        let io = Scripted::new(&stale, vec![late_then_probe, ours]);
        let mut t = transport(io);
        let got = t.transact(&read_object(), true).unwrap().unwrap();
        assert_eq!(command::parse_answer(&got).unwrap().1, [0x40, 0, 0, 0]);
        assert_eq!(t.port.io.written[0], usb(&command::sync_probe()), "the probe goes first");
        // In step now: the next command is sent without a probe.
        t.port.io.replies.push_back(usb(&command::answer(0, &[7, 0, 0, 0])));
        let got = t.transact(&read_object(), true).unwrap().unwrap();
        assert_eq!(command::parse_answer(&got).unwrap().1, [7, 0, 0, 0]);
        assert_eq!(t.port.io.written.len(), 3);
    }

    #[test]
    fn an_answer_that_does_not_fit_the_command_is_discarded() {
        let probe = usb(&command::answer(command::ILLEGAL_COMMAND, &[]));
        // A WriteObject answer (no data) cannot answer ReadObject; a second probe answer
        // neither.
        let mut misfits = usb(&command::answer(0, &[]));
        misfits.extend(&probe);
        misfits.extend(usb(&command::answer(0, &[0x40, 0, 0, 0])));
        let mut t = transport(Scripted::new(&[], vec![probe.clone(), misfits]));
        let got = t.transact(&read_object(), true).unwrap().unwrap();
        assert_eq!(command::parse_answer(&got).unwrap().1, [0x40, 0, 0, 0]);
    }

    #[test]
    fn only_misfits_are_a_link_error() {
        let probe = usb(&command::answer(command::ILLEGAL_COMMAND, &[]));
        let misfits: Vec<u8> = (0..=MAX_DISCARDED).flat_map(|_| usb(&command::answer(0, &[]))).collect();
        let replies = vec![probe.clone(), misfits.clone(), probe, misfits];
        let mut t = transport(Scripted::new(&[], replies));
        let e = crate::Error::from(t.transact(&read_object(), true).unwrap_err());
        assert_eq!(e.exit_code(), 5);
        assert!(e.to_string().contains("do not answer this command"), "{e}");
    }

    #[test]
    fn a_babbling_line_is_given_up_on() {
        let mut io = Scripted::new(&[], vec![]);
        io.babble = true;
        let mut t = transport(io);
        let start = Instant::now();
        let e = crate::Error::from(t.transact(&read_object(), true).unwrap_err());
        assert_eq!(e.exit_code(), 5);
        assert!(e.to_string().contains("does not fall quiet"), "{e}");
        assert!(start.elapsed() < Duration::from_secs(30), "bounded");
    }
}
