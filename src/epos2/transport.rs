//! The two EPOS2 links: RS232 with its 'O'/'F' handshake, USB with DLE/STX framing. Both
//! retry a command once after a failed handshake, a bad CRC or a timeout, then give up
//! with a link error that says what happened.

use super::frame::{self, Frame, FrameError, UsbDecoder};
use super::Framing;
use crate::error::{Error, Result};
use std::io;
use std::time::{Duration, Instant};

const OKAY: u8 = b'O';
const FAILED: u8 = b'F';

/// What a transport needs from a serial port.
pub trait SerialIo {
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()>;
    /// Read what is available, waiting until `deadline` for at least one byte; 0 means the
    /// deadline passed. A vanished port is an error, never a 0.
    fn read_some(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize>;
    fn discard_input(&mut self) -> io::Result<()>;
}

impl SerialIo for serialport::TTYPort {
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        io::Write::write_all(self, bytes)?;
        io::Write::flush(self)
    }

    fn read_some(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Ok(0);
        }
        serialport::SerialPort::set_timeout(self, left)?;
        match io::Read::read(self, buf) {
            Ok(0) => Err(io::Error::new(io::ErrorKind::UnexpectedEof, "the port closed")),
            Ok(n) => Ok(n),
            Err(e) if e.kind() == io::ErrorKind::TimedOut || e.kind() == io::ErrorKind::WouldBlock => Ok(0),
            Err(e) => Err(e),
        }
    }

    fn discard_input(&mut self) -> io::Result<()> {
        serialport::SerialPort::clear(self, serialport::ClearBuffer::Input).map_err(io::Error::from)
    }
}

/// Sends one command frame and returns the answer frame, if the command has one here.
pub trait Transport {
    fn transact(&mut self, command: &Frame, answered: bool) -> Result<Option<Frame>>;
    /// `epos2-rs232:/dev/ttyS0`, for messages.
    fn describe(&self) -> String;
    /// RS232 leaves some commands unanswered; USB answers all.
    fn is_rs232(&self) -> bool;
}

/// Why one attempt failed.
#[derive(Debug)]
enum Failure {
    Nack(&'static str),
    Timeout(&'static str),
    Frame(FrameError),
    Unexpected(u8, &'static str),
    Io(io::Error),
}

impl Failure {
    fn retryable(&self) -> bool {
        !matches!(self, Failure::Io(_))
    }
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Nack(stage) => write!(f, "the EPOS2 refused the frame: answered {stage}"),
            Failure::Timeout(stage) => write!(f, "no answer {stage}"),
            Failure::Frame(e) => write!(f, "bad answer frame: {e}"),
            Failure::Unexpected(b, stage) => write!(f, "unexpected byte 0x{b:02X} {stage}"),
            Failure::Io(e) => write!(f, "the port failed: {e}"),
        }
    }
}

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

    fn byte(&mut self, deadline: Instant) -> Result<Option<u8>, Failure> {
        if self.pos == self.buf.len() {
            self.buf.resize(256, 0);
            let n = self.io.read_some(&mut self.buf, deadline).map_err(Failure::Io)?;
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
        self.io.write_all(bytes).map_err(Failure::Io)
    }

    /// Drop whatever is in flight: wait for the line to fall quiet, then clear it.
    fn resync(&mut self) {
        self.buf.clear();
        self.pos = 0;
        let quiet = (self.timeout / 4).min(Duration::from_millis(50));
        let mut scratch = [0u8; 256];
        let mut until = Instant::now() + quiet;
        while let Ok(n) = self.io.read_some(&mut scratch, until) {
            if n == 0 {
                break;
            }
            until = Instant::now() + quiet;
        }
        let _ = self.io.discard_input();
    }
}

fn trace(enabled: bool, name: &str, dir: &str, bytes: &[u8]) {
    if enabled {
        let spaced: Vec<String> = bytes.iter().map(|b| format!("{b:02X}")).collect();
        eprintln!("  {name} {dir} {}", spaced.join(" "));
    }
}

/// Run `attempt` and, if it fails in a way a resync can cure, once more.
fn with_retry<S: SerialIo>(
    port: &mut Port<S>,
    describe: &str,
    command: &Frame,
    mut attempt: impl FnMut(&mut Port<S>) -> Result<Option<Frame>, Failure>,
) -> Result<Option<Frame>> {
    let what = super::command::Command::from_frame(command).map_or("command", |c| c.name());
    match attempt(port) {
        Ok(a) => Ok(a),
        Err(first) if first.retryable() => {
            port.resync();
            attempt(port).map_err(|second| {
                Error::Link(format!("{describe}: {what} failed: {first}; after a resync and retry: {second}"))
            })
        }
        Err(e) => Err(Error::Link(format!("{describe}: {what} failed: {e}"))),
    }
}

/// An EPOS2 on a serial port, with either framing.
pub struct SerialTransport<S> {
    port: Port<S>,
    framing: Framing,
    describe: String,
    trace: bool,
}

impl<S: SerialIo> SerialTransport<S> {
    pub fn new(io: S, framing: Framing, describe: String, timeout: Duration, trace: bool) -> SerialTransport<S> {
        SerialTransport { port: Port::new(io, timeout), framing, describe, trace }
    }
}

impl<S: SerialIo> Transport for SerialTransport<S> {
    fn transact(&mut self, command: &Frame, answered: bool) -> Result<Option<Frame>> {
        let (describe, trace, framing) = (&self.describe, self.trace, self.framing);
        with_retry(&mut self.port, describe, command, |port| match framing {
            Framing::Rs232 => rs232_attempt(port, describe, trace, command, answered),
            Framing::Usb => usb_attempt(port, describe, trace, command),
        })
    }

    fn describe(&self) -> String {
        self.describe.clone()
    }

    fn is_rs232(&self) -> bool {
        self.framing == Framing::Rs232
    }
}

fn rs232_attempt<S: SerialIo>(
    port: &mut Port<S>,
    name: &str,
    tracing: bool,
    command: &Frame,
    answered: bool,
) -> Result<Option<Frame>, Failure> {
    let bytes = frame::rs232_encode(command);
    trace(tracing, name, "<", &bytes);
    // Seed 000 §5.1.1.2: OpCode, wait for the ready ack, the rest, wait for the end ack.
    port.send(&bytes[..1])?;
    match port.expect_byte(port.deadline(), "to the opcode (ready acknowledge)")? {
        OKAY => {}
        FAILED => return Err(Failure::Nack("'F' to the opcode (not ready)")),
        b => return Err(Failure::Unexpected(b, "instead of the ready acknowledge")),
    }
    port.send(&bytes[1..])?;
    match port.expect_byte(port.deadline(), "to the frame (end acknowledge)")? {
        OKAY => {}
        FAILED => return Err(Failure::Nack("'F' to the frame (CRC or length refused)")),
        b => return Err(Failure::Unexpected(b, "instead of the end acknowledge")),
    }
    if !answered {
        return Ok(None);
    }
    // §5.1.1.3: the answer's OpCode 0x00, our ready ack, the rest, our end ack.
    let op = port.expect_byte(port.deadline(), "with the answer")?;
    if op != super::command::ANSWER {
        return Err(Failure::Unexpected(op, "instead of the answer opcode 0x00"));
    }
    port.send(&[OKAY])?;
    let until = port.deadline();
    let lm1 = port.expect_byte(until, "in the answer's length")?;
    let mut raw = vec![op, lm1];
    for _ in 0..frame::rs232_body_len(lm1) {
        raw.push(port.expect_byte(until, "in the middle of the answer")?);
    }
    trace(tracing, name, ">", &raw);
    match frame::rs232_decode(&raw) {
        Ok(f) => {
            port.send(&[OKAY])?;
            Ok(Some(f))
        }
        Err(e) => {
            port.send(&[FAILED])?;
            Err(Failure::Frame(e))
        }
    }
}

fn usb_attempt<S: SerialIo>(
    port: &mut Port<S>,
    name: &str,
    tracing: bool,
    command: &Frame,
) -> Result<Option<Frame>, Failure> {
    let bytes = frame::usb_encode(command);
    trace(tracing, name, "<", &bytes);
    port.send(&bytes)?;
    let until = port.deadline();
    let mut decoder = UsbDecoder::new();
    let mut raw = Vec::new();
    loop {
        let stage = if decoder.in_frame() { "in the middle of the answer" } else { "with the answer" };
        let b = port.expect_byte(until, stage)?;
        raw.push(b);
        match decoder.push(b) {
            None => {}
            Some(Ok(f)) => {
                trace(tracing, name, ">", &raw);
                if f.opcode != super::command::ANSWER {
                    return Err(Failure::Unexpected(f.opcode, "as the answer's opcode"));
                }
                // Seed 000 §4.1.3.1: a frame the EPOS2 could not read comes back as an
                // answer carrying the CRC error code: USB's counterpart of RS232's 'F'.
                if super::command::parse_answer(&f).is_some_and(|(code, _)| code == crate::canopen::abort::CRC_ERROR) {
                    return Err(Failure::Nack("with error 0x05040004: it saw a bad CRC"));
                }
                return Ok(Some(f));
            }
            Some(Err(e)) => {
                trace(tracing, name, ">", &raw);
                return Err(Failure::Frame(e));
            }
        }
    }
}
