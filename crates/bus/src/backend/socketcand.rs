//! A CAN interface of another machine through a socketcand server, as a `FrameLink`: TCP
//! with no delay, the raw mode's handshake bounded in time, frames both ways, error frames
//! judged as SocketCAN's are. Raw mode carries no remote (RTR) frames: asked to send one,
//! the link refuses by name rather than let a guarding request vanish unsent.

use crate::bus::FrameLink;
use crate::error::{Error, LinkError, Result};
use crate::frame::Frame;
use crate::socketcand::wire::{Decoder, Unit, ERR_BUSOFF};
use crate::socketcand::SocketcandError;
use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::time::{Duration, Instant};

/// How long a TCP connection may take: a few SYN retransmissions across a network.
pub(crate) const CONNECT_WAIT: Duration = Duration::from_secs(5);

/// When reading stops before its deadline.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Until {
    /// A handshake answer came.
    Answer,
    /// A frame is queued.
    Frame,
    /// An `< echo >` came back after this many.
    Echo(u64),
}

/// A socketcand server's interface in raw mode as a [`FrameLink`].
pub struct SocketcandLink {
    stream: TcpStream,
    /// `socketcand:host:port/iface`, for messages and traces.
    name: String,
    decoder: Decoder,
    rx: VecDeque<Frame>,
    /// Answers to the handshake not yet taken.
    answers: VecDeque<Unit>,
    /// `< echo >`s the server sent back.
    echoes: u64,
    /// How long a write may wait for the server to take bytes.
    write_wait: Duration,
    /// The socket's mode and read timeout now, changed only when they must change: while a
    /// server streams frames (one TCP segment each, as socketcand sends them) a read is one
    /// system call, not three (mode, timeout, read).
    nonblocking: bool,
    read_timeout: Option<Duration>,
    /// Error classes already reported, so that a storm of them is one warning each.
    warned: Vec<u32>,
    /// Units that did not parse, and 29-bit frames, since the link was opened.
    pub(crate) garbled: u64,
    pub(crate) extended: u64,
    /// Writes to the server since the link was opened: a block's segments are one.
    writes: u64,
}

impl SocketcandLink {
    /// Writes to the server since the link was opened: a block's segments are one.
    pub fn writes(&self) -> u64 {
        self.writes
    }

    /// Connect to `host:port`, open `iface` and switch to raw mode, waiting at most
    /// `answer_wait` for each answer. `name` is the bus address, for messages.
    pub fn open(host: &str, port: u16, iface: &str, name: String, answer_wait: Duration) -> Result<Self> {
        let connect_error = |error: io::Error| SocketcandError::Connect { server: name.clone(), error: error.into() };
        let mut last = io::Error::new(io::ErrorKind::NotFound, format!("{host} has no address"));
        let stream = (host, port)
            .to_socket_addrs()
            .map_err(connect_error)?
            .find_map(|addr| TcpStream::connect_timeout(&addr, CONNECT_WAIT).map_err(|e| last = e).ok())
            .ok_or_else(|| connect_error(last))?;
        let io_error = |op, e: io::Error| LinkError::Io { port: name.clone(), op, error: e.into() };
        // Every SDO request waits for its answer: Nagle would hold each one back.
        stream.set_nodelay(true).map_err(|e| io_error("TCP no-delay", e))?;
        // A server that stops reading must not hold a command for ever once the socket's
        // buffers are full.
        stream.set_write_timeout(Some(answer_wait)).map_err(|e| io_error("TCP", e))?;
        let mut link = SocketcandLink {
            stream,
            name,
            decoder: Decoder::new(),
            rx: VecDeque::new(),
            answers: VecDeque::new(),
            echoes: 0,
            write_wait: answer_wait,
            nonblocking: false,
            read_timeout: None,
            warned: Vec::new(),
            garbled: 0,
            extended: 0,
            writes: 0,
        };
        link.expect_ok("< hi >", "greet", None, answer_wait)?;
        link.expect_ok("< ok >", &format!("open {iface}"), Some(Unit::Open(iface.to_string())), answer_wait)?;
        link.expect_ok("< ok >", "switch to raw mode", Some(Unit::RawMode), answer_wait)?;
        Ok(link)
    }

    fn lost(&self, error: Option<io::Error>) -> Error {
        SocketcandError::Lost { server: self.name.clone(), error: error.map(Into::into) }.into()
    }

    /// Put the socket in (non-)blocking mode, with a system call only when that changes it.
    fn set_nonblocking(&mut self, on: bool) -> Result<()> {
        if self.nonblocking != on {
            self.stream.set_nonblocking(on).map_err(|e| self.lost(Some(e)))?;
            self.nonblocking = on;
        }
        Ok(())
    }

    /// A read waits at most `left`: the timeout set is kept while it is no longer than
    /// that (never past the deadline) and at least half of it (a read that ends early only
    /// costs one more turn of the loop).
    fn set_read_timeout(&mut self, left: Duration) -> Result<()> {
        if !self.read_timeout.is_some_and(|t| t <= left && t * 2 >= left) {
            self.stream.set_read_timeout(Some(left)).map_err(|e| self.lost(Some(e)))?;
            self.read_timeout = Some(left);
        }
        Ok(())
    }

    fn write(&mut self, unit: &Unit) -> Result<()> {
        self.write_bytes(&unit.encode())
    }

    /// One write of whole units. socketcand takes several units from one read, but ends
    /// the connection when a read brings no complete one: units are never split between
    /// writes by canctl (TCP may still cut them; the rest then comes in the next read).
    fn write_bytes(&mut self, bytes: &[u8]) -> Result<()> {
        self.set_nonblocking(false)?;
        tracing::trace!(target: "canctl::socketcand", "{} < {}", self.name, String::from_utf8_lossy(bytes));
        self.writes += 1;
        self.stream.write_all(bytes).map_err(|e| match e.kind() {
            io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut => {
                SocketcandError::Stalled { server: self.name.clone(), waited: self.write_wait }.into()
            }
            _ => self.lost(Some(e)),
        })
    }

    /// Send `request` (if any) and wait for the answer that ends one handshake step
    /// (`< hi >` or `< ok >`); frames that come with it are kept.
    fn expect_ok(&mut self, want: &'static str, what: &str, request: Option<Unit>, wait: Duration) -> Result<()> {
        if let Some(request) = &request {
            self.write(request)?;
        }
        let deadline = Instant::now() + wait;
        let Some(answer) = self.read_until(deadline, Until::Answer)? else {
            return Err(SocketcandError::NoAnswer { server: self.name.clone(), waiting_for: want, waited: wait }.into());
        };
        let (server, what) = (self.name.clone(), what.to_string());
        match answer {
            Unit::Hi if request.is_none() => Ok(()),
            Unit::Ok if request.is_some() => Ok(()),
            Unit::Refused(answer) => Err(SocketcandError::Refused { server, what, answer }.into()),
            other => {
                let answer = String::from_utf8_lossy(&other.encode()).into_owned();
                Err(SocketcandError::Unexpected { server, what, answer }.into())
            }
        }
    }

    /// Read until `deadline`, queueing frames, or until `until` holds: returns the first
    /// answer that is no frame for [`Until::Answer`], else `None`.
    fn read_until(&mut self, deadline: Instant, until: Until) -> Result<Option<Unit>> {
        let answers = until == Until::Answer;
        let mut buf = [0u8; 4096];
        loop {
            match until {
                Until::Answer if !self.answers.is_empty() => return Ok(self.answers.pop_front()),
                Until::Frame if !self.rx.is_empty() => return Ok(None),
                Until::Echo(before) if self.echoes != before => return Ok(None),
                _ => {}
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                // A poll still takes what has already arrived.
                self.set_nonblocking(true)?;
            } else {
                self.set_nonblocking(false)?;
                self.set_read_timeout(left)?;
            }
            let n = match self.stream.read(&mut buf) {
                Ok(0) => return Err(self.lost(None)),
                Ok(n) => n,
                Err(e) if matches!(e.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut) => {
                    if left.is_zero() {
                        return Ok(None);
                    }
                    continue;
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(self.lost(Some(e))),
            };
            tracing::trace!(target: "canctl::socketcand", "{} > {}", self.name, String::from_utf8_lossy(&buf[..n]));
            for unit in self.decoder.push(&buf[..n]) {
                match unit {
                    Ok(Unit::Frame { frame, .. }) => self.rx.push_back(frame),
                    Ok(Unit::Extended { .. }) => self.extended += 1,
                    Ok(Unit::ErrorFrame { class }) => self.error_frame(class)?,
                    Ok(Unit::Echo) => self.echoes += 1,
                    // Kept in order: two answers may come in one read.
                    Ok(answer) if answers => self.answers.push_back(answer),
                    // In raw mode the server answers nothing canctl asks; an `< error >` is
                    // its word about something it could not do.
                    Ok(Unit::Refused(text)) => {
                        tracing::warn!(target: "canctl::socketcand", "{}: the server says: {text}", self.name)
                    }
                    Ok(other) => {
                        tracing::debug!(target: "canctl::socketcand", "{}: {other:?} not asked for", self.name)
                    }
                    Err(bad) => {
                        self.garbled += 1;
                        tracing::debug!(target: "canctl::socketcand", "{}: not socketcand: {:?}", self.name, bad.0);
                    }
                }
            }
        }
    }

    /// Bus-off ends the command, as on a local interface; other error frames (a missing
    /// acknowledge, error passive) are worth one warning each.
    fn error_frame(&mut self, class: u32) -> Result<()> {
        if class & ERR_BUSOFF != 0 {
            let detail = format!("error frame class 0x{class:03X} from the server");
            return Err(LinkError::BusOff { iface: self.name.clone(), detail }.into());
        }
        if !self.warned.contains(&class) {
            tracing::warn!(target: "canctl::socketcand", "{}: error frame, class 0x{class:03X} (linux/can/error.h)", self.name);
            self.warned.push(class);
        }
        Ok(())
    }
}

impl FrameLink for SocketcandLink {
    fn send(&mut self, frame: &Frame) -> Result<()> {
        self.send_all(std::slice::from_ref(frame))
    }

    /// The frames in one write: a block of 127 segments is one system call and a few TCP
    /// segments, not 127 of each (and socketcand reads them in one go as well).
    fn send_all(&mut self, frames: &[Frame]) -> Result<()> {
        if frames.iter().any(Frame::is_remote) {
            return Err(Error::NoRemoteFrames { bus: self.name.clone(), backend: "socketcand's raw mode" });
        }
        if frames.is_empty() {
            return Ok(());
        }
        self.write_bytes(&frames.iter().flat_map(|f| Unit::Send(*f).encode()).collect::<Vec<u8>>())
    }

    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        if let Some(f) = self.rx.pop_front() {
            return Ok(Some(f));
        }
        self.read_until(deadline, Until::Frame)?;
        Ok(self.rx.pop_front())
    }

    fn name(&self) -> String {
        self.name.clone()
    }

    /// After a silence: the server must still answer `< echo >`, or the silence may be a
    /// stuck server or a broken network (TCP notices neither by itself), not an empty bus.
    fn check(&mut self) -> Result<()> {
        let before = self.echoes;
        self.write(&Unit::Echo)?;
        let deadline = Instant::now() + self.write_wait;
        self.read_until(deadline, Until::Echo(before))?;
        if self.echoes == before {
            let (server, waited) = (self.name.clone(), self.write_wait);
            return Err(SocketcandError::NoAnswer { server, waiting_for: "< echo >", waited }.into());
        }
        Ok(())
    }

    fn close(&mut self) -> Result<()> {
        // Raw mode has no goodbye: closing the connection is how a client leaves.
        let _ = self.stream.shutdown(std::net::Shutdown::Both);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::net::TcpListener;

    /// A server on loopback that plays `script`: for each step, what to wait for from the
    /// client (bytes that must arrive, in order) and what to send then. The connection is
    /// closed when the script ends.
    fn server(script: Vec<(&'static [u8], &'static [u8])>) -> (u16, std::thread::JoinHandle<Vec<u8>>) {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = listener.local_addr().unwrap().port();
        let handle = std::thread::spawn(move || {
            let (mut s, _) = listener.accept().unwrap();
            s.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
            let mut heard = Vec::new();
            for (wait_for, reply) in script {
                while !wait_for.is_empty() && !heard.windows(wait_for.len()).any(|w| w == wait_for) {
                    let mut buf = [0u8; 256];
                    match s.read(&mut buf) {
                        Ok(0) | Err(_) => return heard,
                        Ok(n) => heard.extend_from_slice(&buf[..n]),
                    }
                }
                s.write_all(reply).unwrap();
                // Each reply in a segment of its own, as the server writes them.
                std::thread::sleep(Duration::from_millis(5));
            }
            heard
        });
        (port, handle)
    }

    fn open(port: u16, wait_ms: u64) -> Result<SocketcandLink> {
        let name = format!("socketcand:127.0.0.1:{port}/vcan0");
        SocketcandLink::open("127.0.0.1", port, "vcan0", name, Duration::from_millis(wait_ms))
    }

    const HANDSHAKE: [(&[u8], &[u8]); 3] =
        [(b"", b"< hi >"), (b"< open vcan0 >", b"< ok >"), (b"< rawmode >", b"< ok >< frame 705 1.000000 7F >")];

    #[test]
    fn handshake_then_frames_both_ways() {
        let mut script = HANDSHAKE.to_vec();
        // The answer cut in two, behind a frame in the spaced notation.
        script.push((b"< send 601 8 40 00 10 00 00 00 00 00 >", b"< frame 181 1.000100 01 02 >< frame 581 1.0"));
        script.push((b"", b"00200 4300100092010200 >"));
        let (port, server) = server(script);
        let mut link = open(port, 2000).unwrap();
        let soon = || Instant::now() + Duration::from_secs(2);
        // The frame that came with the last < ok > is not lost.
        assert_eq!(link.recv(soon()).unwrap(), Some(Frame::new(0x705, &[0x7F])));
        link.send(&Frame::new(0x601, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0])).unwrap();
        assert_eq!(link.recv(soon()).unwrap(), Some(Frame::new(0x181, &[1, 2])));
        assert_eq!(link.recv(soon()).unwrap(), Some(Frame::new(0x581, &[0x43, 0, 0x10, 0, 0x92, 1, 2, 0])));
        // The server has closed the connection: a lost link, not a silent bus.
        let e = link.recv(soon()).unwrap_err();
        assert_eq!(e.exit_code(), 5, "{e}");
        assert!(e.to_string().contains("connection to the server was lost"), "{e}");
        let heard = server.join().unwrap();
        assert!(heard.starts_with(b"< open vcan0 >< rawmode >< send 601 8 "), "{}", String::from_utf8_lossy(&heard));
    }

    #[test]
    fn a_refused_interface_is_a_link_failure_saying_so() {
        let (port, _server) = server(vec![(b"", b"< hi >"), (b"< open vcan0 >", b"< error could not open bus >")]);
        let e = open(port, 2000).err().unwrap();
        assert_eq!(e.exit_code(), 5, "{e}");
        assert!(e.to_string().contains("refused to open vcan0: could not open bus"), "{e}");
    }

    #[test]
    fn a_silent_server_and_no_server_are_bounded_link_failures() {
        let (port, _server) = server(vec![(b"< never >", b"")]);
        let e = open(port, 100).err().unwrap();
        assert_eq!(e.exit_code(), 5, "{e}");
        assert!(e.to_string().contains("no < hi > within 100 ms"), "{e}");
        let closed = TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
        let e = open(closed, 100).err().unwrap();
        assert_eq!(e.exit_code(), 5, "{e}");
        assert!(e.to_string().contains("cannot connect") && e.to_string().contains("socketcand -i"), "{e}");
    }

    #[test]
    fn something_else_than_socketcand_is_named_so() {
        let (port, _server) =
            server(vec![(b"", b"SSH-2.0-OpenSSH_9.6\r\n< hi >"), (b"< open", b"HTTP/1.1 400\r\n<html>")]);
        let e = open(port, 300).err().unwrap();
        assert_eq!(e.exit_code(), 5, "{e}");
        assert!(e.to_string().contains("to open vcan0, the server answered \"< html >\""), "{e}");
    }

    #[test]
    fn a_server_that_stops_reading_is_a_bounded_link_failure() {
        // The server answers the whole handshake at once (in one segment: the answers must
        // not be lost), then reads nothing more: once the socket's buffers are full, a send
        // must end, not block for ever.
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = listener.local_addr().unwrap().port();
        std::thread::spawn(move || {
            let (mut s, _) = listener.accept().unwrap();
            s.write_all(b"< hi >< ok >< ok >").unwrap();
            std::thread::sleep(Duration::from_secs(20));
        });
        let mut link = open(port, 100).unwrap();
        let frame = Frame::new(0x601, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]);
        let e = (0..10_000_000).find_map(|_| link.send(&frame).err()).expect("the sends never stalled");
        assert_eq!(e.exit_code(), 5, "{e}");
        assert!(e.to_string().contains("has taken nothing canctl sent for 100 ms"), "{e}");
    }

    #[test]
    fn after_a_silence_the_server_must_answer_an_echo() {
        let mut script = HANDSHAKE.to_vec();
        script.push((b"< echo >", b"< frame 705 2.0 7F >< echo >"));
        // The server hears the second one, and says nothing until it gives up on the client.
        script.push((b"< never >", b""));
        let (port, _server) = server(script);
        let mut link = open(port, 300).unwrap();
        link.check().unwrap();
        // The frames that came meanwhile are kept.
        let soon = Instant::now() + Duration::from_secs(1);
        assert_eq!(link.recv(soon).unwrap(), Some(Frame::new(0x705, &[0x7F])));
        assert_eq!(link.recv(soon).unwrap(), Some(Frame::new(0x705, &[0x7F])));
        // The second echo goes unanswered: a stuck server is a link failure.
        let e = link.check().unwrap_err();
        assert_eq!(e.exit_code(), 5, "{e}");
        assert!(e.to_string().contains("no < echo > within 300 ms"), "{e}");
    }

    #[test]
    fn remote_frames_are_refused_by_name_and_bus_off_ends_the_command() {
        let mut script = HANDSHAKE.to_vec();
        script.push((b"< send 000 2 01 00 >", b"< error 004 1.0 >< error 040 1.1 >"));
        let (port, _server) = server(script);
        let mut link = open(port, 2000).unwrap();
        let e = link.send(&Frame::remote(0x70A, 1)).unwrap_err();
        assert_eq!(e.exit_code(), 2, "{e}");
        assert!(e.to_string().contains("socketcand's raw mode carries no remote (RTR) frames"), "{e}");
        link.send(&Frame::new(0x000, &[1, 0])).unwrap();
        let soon = Instant::now() + Duration::from_secs(2);
        assert_eq!(link.recv(soon).unwrap(), Some(Frame::new(0x705, &[0x7F])));
        let e = link.recv(soon).unwrap_err();
        assert_eq!(e.exit_code(), 5, "{e}");
        assert!(e.to_string().contains("bus-off"), "{e}");
    }
}
