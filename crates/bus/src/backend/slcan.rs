//! A serial-line CAN adapter as a `FrameLink`: set the bit rate, open the channel, send and
//! receive frames as slcan text, close the channel however the command ends.

use crate::bus::controller::RateHeard;
use crate::bus::FrameLink;
use crate::error::{Error, LinkError, Result};
use crate::frame::Frame;
use crate::serial::SerialIo;
use crate::slcan::wire::{bit_rate_code, Command, Decoder, Message, Status, BIT_RATES};
use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// How long an adapter may take to answer a configuration command. Adapters answer from
/// their firmware, without the bus, so this does not depend on the devices.
const COMMAND_WAIT: Duration = Duration::from_millis(500);
/// How long an adapter may take to answer `V` behind the lines it was still working on.
const SYNC_WAIT: Duration = Duration::from_secs(2);

/// When reading stops before its deadline.
#[derive(Clone, Copy)]
enum Until {
    Answer,
    Frame,
    Deadline,
}

/// A serial-line CAN adapter as a [`FrameLink`]: Lawicel ASCII lines to and from frames.
pub struct SlcanLink<P: SerialIo> {
    port: P,
    /// `slcan:/dev/ttyACM0`, for messages and traces.
    name: String,
    decoder: Decoder,
    rx: VecDeque<Frame>,
    /// Whether the adapter answers `F`; clones that do not get asked once.
    has_status: bool,
    open: bool,
    /// The `Sn` code of the rate it was opened at, which a sweep goes back to.
    code: u8,
    /// Lines that were not slcan, and 29-bit frames, since the link was opened.
    pub garbled: u64,
    /// 29-bit frames received (canctl speaks 11-bit CANopen; they are counted and dropped).
    pub extended: u64,
}

impl<P: SerialIo> SlcanLink<P> {
    /// Set the adapter to `kbit` and open its channel.
    pub fn open(port: P, name: String, kbit: u32) -> Result<SlcanLink<P>> {
        let Some(code) = bit_rate_code(kbit) else {
            let supported = BIT_RATES.iter().map(|(_, k)| format!("{k}k")).collect();
            return Err(Error::SlcanBitRate { port: name, kbit, supported });
        };
        let mut link = SlcanLink {
            port,
            name,
            decoder: Decoder::new(),
            rx: VecDeque::new(),
            has_status: true,
            open: false,
            code,
            garbled: 0,
            extended: 0,
        };
        // Empty lines end whatever half-command an earlier program left in the adapter.
        link.write(b"\r\r\r")?;
        link.resynchronise()?;
        // A channel left open by another program must be closed before the rate can change;
        // closing a closed channel is refused by some adapters, which is fine.
        link.command(Command::Close, "close the channel").ok();
        link.command(Command::BitRate(code), "set the bit rate")?;
        link.command(Command::Open, "open the channel")?;
        link.open = true;
        Ok(link)
    }

    fn io_error(&self, op: &'static str, error: std::io::Error) -> Error {
        LinkError::Io { port: self.name.clone(), op, error: error.into() }.into()
    }

    fn write(&mut self, bytes: &[u8]) -> Result<()> {
        tracing::trace!(target: "canctl::slcan", "{} < {:?}", self.name, String::from_utf8_lossy(bytes));
        let written = self.port.write_all(bytes);
        written.map_err(|e| self.io_error("cannot write", e))
    }

    /// Read what arrives until `deadline`, or until `stop` holds, queueing frames; the answers
    /// to commands.
    fn read_until(&mut self, deadline: Instant, stop: Until) -> Result<Vec<Message>> {
        let mut answers = Vec::new();
        let mut buf = [0u8; 256];
        loop {
            let n = self.port.read_some(&mut buf, deadline).map_err(|e| self.io_error("the adapter is gone", e))?;
            if n == 0 {
                return Ok(answers);
            }
            tracing::trace!(target: "canctl::slcan", "{} > {:?}", self.name, String::from_utf8_lossy(&buf[..n]));
            for m in self.decoder.push(&buf[..n]) {
                match m {
                    Ok(Message::Frame(f)) => self.rx.push_back(f),
                    Ok(Message::Extended { .. }) => self.extended += 1,
                    Ok(other) => answers.push(other),
                    Err(_) => self.garbled += 1,
                }
            }
            let done = match stop {
                Until::Answer => !answers.is_empty(),
                Until::Frame => !self.rx.is_empty() || !answers.is_empty(),
                Until::Deadline => false,
            };
            if done {
                return Ok(answers);
            }
        }
    }

    /// Forget what the adapter said before now: the answers to the empty lines just sent,
    /// and anything an earlier program left unread. A busy adapter may answer those long
    /// after any fixed pause, so the end of them is marked by asking its version: what
    /// comes before that answer is old. An adapter that does not answer `V` gets a pause.
    fn resynchronise(&mut self) -> Result<()> {
        self.write(&Command::Version.encode())?;
        let deadline = Instant::now() + SYNC_WAIT;
        let mut synced = false;
        while !synced && Instant::now() < deadline {
            synced = self.read_until(deadline, Until::Answer)?.iter().any(|m| matches!(m, Message::Version(_)));
        }
        if !synced {
            tracing::debug!(target: "canctl::slcan", "{}: no answer to V in {SYNC_WAIT:?}", self.name);
            self.read_until(Instant::now() + Duration::from_millis(20), Until::Deadline)?;
            self.port.discard_input().map_err(|e| self.io_error("cannot clear the input", e))?;
            self.decoder = Decoder::new();
        }
        // Frames heard before the channel is set up again are not this program's.
        self.rx.clear();
        Ok(())
    }

    /// Send a configuration command (`what` it does, for a refusal) and wait for its answer.
    fn command(&mut self, cmd: Command, what: &'static str) -> Result<Message> {
        self.write(&cmd.encode())?;
        let deadline = Instant::now() + COMMAND_WAIT;
        loop {
            // Acknowledges of frames sent earlier are not this command's answer.
            break match self.read_until(deadline, Until::Answer)?.into_iter().find(|m| *m != Message::Sent) {
                Some(Message::Refused) => Err(LinkError::AdapterRefused { port: self.name.clone(), what }.into()),
                Some(answer) => Ok(answer),
                None if Instant::now() < deadline => continue,
                None => Err(Error::AdapterNoAnswer {
                    port: self.name.clone(),
                    command: String::from_utf8_lossy(&cmd.encode()).trim_end().to_string(),
                    waited: COMMAND_WAIT,
                }),
            };
        }
    }

    /// Close the channel, set the bit rate of `code` and open the channel with `open`.
    fn reopen(&mut self, code: u8, open: Command, what: &'static str) -> Result<()> {
        self.command(Command::Close, "close the channel")?;
        self.open = false;
        self.command(Command::BitRate(code), "set the bit rate")?;
        self.command(open, what)?;
        self.open = true;
        Ok(())
    }

    /// The adapter's status flags, if it reports them.
    pub fn status(&mut self) -> Result<Option<Status>> {
        if !self.has_status {
            return Ok(None);
        }
        match self.command(Command::Status, "report its status") {
            Ok(Message::Status(s)) => Ok(Some(s)),
            Ok(_) | Err(Error::Link(LinkError::AdapterRefused { .. })) | Err(Error::AdapterNoAnswer { .. }) => {
                self.has_status = false;
                Ok(None)
            }
            Err(e) => Err(e),
        }
    }

    /// After a wait in which nothing arrived: a bus the adapter cannot use is a link failure
    /// (exit 5), not a device that does not answer.
    fn check_bus(&mut self) -> Result<()> {
        let Some(s) = self.status()? else { return Ok(()) };
        const BUS_ERROR: u8 = 1 << 7;
        const ERROR_PASSIVE: u8 = 1 << 5;
        if s.0 & (BUS_ERROR | ERROR_PASSIVE) != 0 {
            return Err(LinkError::AdapterBusError { port: self.name.clone(), flags: s.names() }.into());
        }
        Ok(())
    }
}

impl<P: SerialIo> FrameLink for SlcanLink<P> {
    fn send(&mut self, frame: &Frame) -> Result<()> {
        self.write(&Command::Transmit(*frame).encode())?;
        // A refusal comes at once; frames and acknowledges already here are kept.
        if self.read_until(Instant::now(), Until::Deadline)?.contains(&Message::Refused) {
            let flags = self.status().ok().flatten().map(|s| s.names()).unwrap_or_default();
            return Err(LinkError::AdapterRefusedFrame { port: self.name.clone(), cob: Some(frame.id()), flags }.into());
        }
        Ok(())
    }

    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        if let Some(f) = self.rx.pop_front() {
            return Ok(Some(f));
        }
        let started = Instant::now();
        loop {
            let answers = self.read_until(deadline, Until::Frame).map(|a| a.contains(&Message::Refused));
            if let Some(f) = self.rx.pop_front() {
                return Ok(Some(f));
            }
            if answers? {
                let (port, flags) = (self.name.clone(), Vec::new());
                return Err(LinkError::AdapterRefusedFrame { port, cob: None, flags }.into());
            }
            if Instant::now() >= deadline {
                // Only after a real wait: a poll (deadline now) asks the adapter nothing.
                if deadline > started + Duration::from_millis(50) {
                    self.check_bus()?;
                }
                return Ok(self.rx.pop_front());
            }
        }
    }

    fn name(&self) -> String {
        self.name.clone()
    }

    fn check(&mut self) -> Result<()> {
        self.check_bus()
    }

    fn listen_at(&mut self, kbit: u32, window: Duration) -> Result<Option<RateHeard>> {
        let Some(code) = bit_rate_code(kbit) else { return Ok(None) };
        // Listen-only (`L`): at a wrong rate the adapter must not transmit nor acknowledge,
        // or it would destroy the traffic of the bus it is trying to hear.
        self.reopen(code, Command::ListenOnly, "open the channel listen-only")?;
        self.rx.clear();
        self.status()?; // clears the flags of the rate before
        let garbled = self.garbled;
        self.read_until(Instant::now() + window, Until::Deadline)?;
        let frames = self.rx.len() as u32;
        let flags = self.status()?;
        // Error warning, error passive, bus error: what receiving at a wrong rate raises
        // (an overrun only says the host read too slowly).
        const BUS_TROUBLE: u8 = 1 << 2 | 1 << 5 | 1 << 7;
        let errors = self.garbled > garbled || flags.is_some_and(|s| s.0 & BUS_TROUBLE != 0);
        self.rx.clear();
        self.reopen(self.code, Command::Open, "open the channel")?;
        self.status()?;
        Ok(Some(RateHeard { kbit, frames, errors }))
    }

    fn close(&mut self) -> Result<()> {
        if std::mem::take(&mut self.open) {
            self.command(Command::Close, "close the channel")?;
        }
        Ok(())
    }
}

impl<P: SerialIo> Drop for SlcanLink<P> {
    /// Whatever ended the command, the channel is closed: an adapter left open keeps
    /// acknowledging frames on the bus with nobody reading them.
    fn drop(&mut self) {
        if self.open {
            let _ = self.write(&Command::Close.encode());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io;

    /// A serial port that plays an adapter from a script: each write may be answered with
    /// bytes that become readable at once.
    type Script = Box<dyn FnMut(&[u8]) -> Vec<u8>>;

    struct Adapter {
        written: Vec<u8>,
        readable: VecDeque<u8>,
        answer: Script,
    }

    impl Adapter {
        fn new(answer: impl FnMut(&[u8]) -> Vec<u8> + 'static) -> Adapter {
            Adapter { written: Vec::new(), readable: VecDeque::new(), answer: Box::new(answer) }
        }
    }

    impl SerialIo for Adapter {
        fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
            self.written.extend_from_slice(bytes);
            let reply = (self.answer)(bytes);
            self.readable.extend(reply);
            Ok(())
        }
        fn read_some(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
            if self.readable.is_empty() {
                // As a real port: nothing comes, so the wait runs to its deadline.
                std::thread::sleep(deadline.saturating_duration_since(Instant::now()));
                return Ok(0);
            }
            let n = buf.len().min(self.readable.len());
            for b in buf.iter_mut().take(n) {
                *b = self.readable.pop_front().unwrap();
            }
            Ok(n)
        }
        fn discard_input(&mut self) -> io::Result<()> {
            self.readable.clear();
            Ok(())
        }
    }

    /// A well-behaved adapter: CR to commands, `z` to frames, one SDO answer to each request.
    fn good(cmd: &[u8]) -> Vec<u8> {
        match cmd.first() {
            Some(b't') if cmd.starts_with(b"t601") => b"z\rt581843001000FB000000\r".to_vec(),
            Some(b't') => b"z\r".to_vec(),
            Some(b'F') => b"F00\r".to_vec(),
            Some(b'V') => b"V1013\r".to_vec(),
            Some(b'\r') => b"\x07\x07\x07".to_vec(),
            _ => b"\r".to_vec(),
        }
    }

    #[test]
    fn open_sets_the_rate_and_opens_then_frames_flow() {
        let mut link = SlcanLink::open(Adapter::new(good), "slcan:test".into(), 500).unwrap();
        assert_eq!(link.port.written, b"\r\r\rV\rC\rS6\rO\r");
        link.send(&Frame::new(0x601, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0])).unwrap();
        let got = link.recv(Instant::now() + Duration::from_millis(100)).unwrap().unwrap();
        assert_eq!(got, Frame::new(0x581, &[0x43, 0x00, 0x10, 0x00, 0xFB, 0, 0, 0]));
        link.close().unwrap();
        assert!(link.port.written.ends_with(b"C\r"));
    }

    #[test]
    fn dropped_without_close_the_channel_is_closed() {
        let written = std::rc::Rc::new(std::cell::RefCell::new(Vec::new()));
        let w = written.clone();
        let link = SlcanLink::open(
            Adapter::new(move |c| {
                w.borrow_mut().extend_from_slice(c);
                good(c)
            }),
            "slcan:test".into(),
            125,
        )
        .unwrap();
        drop(link);
        assert!(written.borrow().ends_with(b"O\rC\r"), "{:?}", String::from_utf8_lossy(&written.borrow()));
    }

    /// An acknowledge of an earlier frame and the command's own answer in one read.
    #[test]
    fn an_answer_behind_an_acknowledge_is_not_lost() {
        let mut link = SlcanLink::open(
            Adapter::new(|c| if c == b"C\r" { b"z\r\r".to_vec() } else { good(c) }),
            "slcan:test".into(),
            500,
        )
        .unwrap();
        link.close().unwrap();
    }

    #[test]
    fn a_rate_slcan_lacks_is_a_usage_error() {
        let e = SlcanLink::open(Adapter::new(good), "slcan:test".into(), 83).err().unwrap();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("10k 20k 50k 100k 125k 250k 500k 800k 1000k"), "{e}");
    }

    #[test]
    fn an_adapter_that_refuses_to_open_is_a_link_failure() {
        let e =
            SlcanLink::open(Adapter::new(|c| if c == b"O\r" { vec![0x07] } else { good(c) }), "slcan:test".into(), 500)
                .err()
                .unwrap();
        assert_eq!(e.exit_code(), 5, "{e}");
        assert!(e.to_string().contains("refused to open the channel"), "{e}");
    }

    #[test]
    fn a_silent_port_is_a_timeout_not_a_hang() {
        let e = SlcanLink::open(Adapter::new(|_| Vec::new()), "slcan:test".into(), 500).err().unwrap();
        assert_eq!(e.exit_code(), 3, "{e}");
        assert!(e.to_string().contains("did not answer"), "{e}");
    }

    #[test]
    fn a_refused_frame_and_a_bus_error_are_link_failures() {
        let mut link = SlcanLink::open(
            Adapter::new(|c| match c.first() {
                Some(b't') => vec![0x07],
                Some(b'F') => b"F80\r".to_vec(),
                _ => good(c),
            }),
            "slcan:test".into(),
            500,
        )
        .unwrap();
        let e = link.send(&Frame::new(0x000, &[1, 0])).unwrap_err();
        assert_eq!(e.exit_code(), 5);
        assert!(e.to_string().contains("refused to send 000 (bus error)"), "{e}");
        let e = link.recv(Instant::now() + Duration::from_millis(60)).unwrap_err();
        assert!(e.to_string().contains("bus error") && e.to_string().contains("termination"), "{e}");
    }

    #[test]
    fn garbage_and_extended_frames_are_counted_not_delivered() {
        let mut link = SlcanLink::open(
            Adapter::new(|c| match c.first() {
                Some(b't') => b"z\rT123456780\rgarbage\rt70517F\r".to_vec(),
                _ => good(c),
            }),
            "slcan:test".into(),
            500,
        )
        .unwrap();
        link.send(&Frame::new(0x000, &[1, 0])).unwrap();
        let got = link.recv(Instant::now() + Duration::from_millis(10)).unwrap();
        assert_eq!(got, Some(Frame::new(0x705, &[0x7F])));
        assert_eq!((link.garbled, link.extended), (1, 1));
    }
}
