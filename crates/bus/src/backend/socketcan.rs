//! SocketCAN as a frame link: the kernel's CAN stack, any interface with a driver (can0,
//! vcan0, slcan0). Receive filters keep a busy bus cheap; error frames are reported.

use crate::bus::controller::{Controller, ErrorFrameCounts, LinkReport, CAN_ERR_FLAG};
use crate::bus::FrameLink;
use crate::error::{Error, LinkError, Result};
use crate::frame::Frame;
use socketcan::{
    CanError, CanFilter, CanFrame, CanSocket, EmbeddedFrame, ErrorCause, Id, Socket, SocketOptions, StandardId,
};
use std::io;
use std::time::{Duration, Instant};

/// How long a send may wait for room in a full transmit queue before it is a link failure.
const TX_QUEUE_PATIENCE: Duration = Duration::from_secs(2);

/// A Linux CAN interface (`can0`, `vcan0`) as a [`FrameLink`].
pub struct SocketCanLink {
    sock: CanSocket,
    /// The longest frame at the interface's bit rate, as netlink gave it when opened.
    frame_time: Option<Duration>,
    iface: String,
    filters: Vec<(u16, u16)>,
    /// Error kinds already reported, so that a storm of them is one warning each.
    warned: Vec<String>,
    /// Every error frame heard, counted by what it said (doctor tells a bus nobody
    /// acknowledges on from one at another bit rate by them).
    errors: ErrorFrameCounts,
    /// Frames that found the transmit queue full and waited: a queue too short for the
    /// bursts canctl sends (doctor names the txqueuelen command).
    queue_full: u32,
}

/// Why `iface` cannot carry CAN frames, if it cannot; read from sysfs before opening.
fn check_interface(iface: &str) -> Result<()> {
    let dir = std::path::Path::new("/sys/class/net").join(iface);
    let present = super::can_interfaces();
    if !dir.exists() {
        return Err(LinkError::NoInterface { iface: iface.to_string(), available: present }.into());
    }
    if !present.iter().any(|p| p == iface) {
        return Err(LinkError::NotCan { iface: iface.to_string() }.into());
    }
    let flags = std::fs::read_to_string(dir.join("flags")).unwrap_or_default();
    let flags = u32::from_str_radix(flags.trim().trim_start_matches("0x"), 16).unwrap_or(1);
    if flags & 1 == 0 {
        return Err(LinkError::Down { iface: iface.to_string() }.into());
    }
    Ok(())
}

/// ENOPROTOOPT: the socket layer does not know the CAN option asked for.
fn no_socket_option(e: &io::Error) -> bool {
    e.raw_os_error() == Some(nix::libc::ENOPROTOOPT)
}

impl SocketCanLink {
    /// Open `iface`, after checking that it exists, is a CAN interface and is up (each
    /// with its own error and what to do).
    pub fn open(iface: &str) -> Result<SocketCanLink> {
        check_interface(iface)?;
        let io = |op: &'static str| {
            move |error: std::io::Error| LinkError::Io { port: iface.to_string(), op, error: error.into() }
        };
        let sock =
            CanSocket::open(iface).map_err(|error| LinkError::Open { port: iface.to_string(), error: error.into() })?;
        // Every error class: bus-off must end a command, the others are worth a warning. A
        // socket layer that knows no CAN socket options (qemu-user running an ARM build on an
        // x86 kernel) still carries frames: go on without error frames, and say so.
        match sock.set_error_filter_accept_all() {
            Err(e) if no_socket_option(&e) => {
                tracing::warn!(target: "canctl::socketcan", iface, "{iface}: error frames cannot be asked for here ({e}): a bus-off will show only as silence");
            }
            other => other.map_err(io("error filter"))?,
        }
        sock.set_nonblocking(true).map_err(io(""))?;
        // A vcan interface, or one whose rate netlink does not give: not known.
        let frame_time = match super::can_netlink::read(iface) {
            Ok(Controller::Can { bitrate: Some(bps), .. }) => Some(crate::frame::longest_frame_time(bps.into())),
            _ => None,
        };
        Ok(SocketCanLink {
            frame_time,
            sock,
            iface: iface.to_string(),
            filters: vec![(0, 0)],
            warned: Vec::new(),
            errors: ErrorFrameCounts::default(),
            queue_full: 0,
        })
    }

    fn io_error(&self, op: &'static str, error: io::Error) -> Error {
        LinkError::Io { port: self.iface.clone(), op, error: error.into() }.into()
    }

    fn error_frame(&mut self, err: CanError) -> Result<()> {
        if err.causes().any(|c| matches!(c, ErrorCause::BusOff)) {
            return Err(LinkError::BusOff { iface: self.iface.clone(), detail: err.to_string() }.into());
        }
        let text = err.to_string();
        if !self.warned.contains(&text) {
            tracing::warn!(target: "canctl::socketcan", iface = %self.iface, "{}: {text}", self.iface);
            self.warned.push(text);
        }
        Ok(())
    }
}

fn to_socketcan(f: &Frame) -> CanFrame {
    let id = StandardId::new(f.id()).expect("11-bit id");
    if f.is_remote() {
        CanFrame::new_remote(id, f.len()).expect("dlc within 8")
    } else {
        CanFrame::new(id, f.data()).expect("at most 8 bytes")
    }
}

impl FrameLink for SocketCanLink {
    fn frame_time(&self) -> Option<Duration> {
        self.frame_time
    }

    fn send(&mut self, frame: &Frame) -> Result<()> {
        let f = to_socketcan(frame);
        let give_up = Instant::now() + TX_QUEUE_PATIENCE;
        let mut waited = false;
        loop {
            match self.sock.write_frame(&f) {
                Ok(()) => return Ok(()),
                // A full transmit queue (a burst of probes on a small txqueuelen): wait for
                // room; dropping the frame would lose a probe without a word.
                Err(e) if e.raw_os_error() == Some(nix::libc::ENOBUFS) || e.kind() == io::ErrorKind::WouldBlock => {
                    if !std::mem::replace(&mut waited, true) {
                        self.queue_full += 1;
                    }
                    if Instant::now() > give_up {
                        return Err(
                            LinkError::TxQueueFull { iface: self.iface.clone(), waited: TX_QUEUE_PATIENCE }.into()
                        );
                    }
                    std::thread::sleep(Duration::from_micros(200));
                }
                Err(e) => return Err(self.io_error("send failed", e)),
            }
        }
    }

    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        loop {
            // Frames already queued are taken without a clock read or a poll: in a block
            // transfer nearly all of them are.
            let f = match self.sock.read_frame() {
                Ok(f) => f,
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                    let left = deadline.saturating_duration_since(Instant::now());
                    if left.is_zero() {
                        return Ok(None);
                    }
                    match self.sock.read_frame_timeout(left) {
                        Ok(f) => f,
                        Err(e) if matches!(e.kind(), io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock) => continue,
                        Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                        Err(e) => return Err(self.io_error("receive failed", e)),
                    }
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(self.io_error("receive failed", e)),
            };
            match f {
                CanFrame::Error(e) => {
                    self.errors.take(e.error_bits() | CAN_ERR_FLAG, e.data());
                    self.error_frame(e.into_error())?
                }
                CanFrame::Data(d) => {
                    if let Id::Standard(id) = d.id() {
                        return Ok(Some(Frame::new(id.as_raw(), d.data())));
                    }
                }
                CanFrame::Remote(r) => {
                    if let Id::Standard(id) = r.id() {
                        return Ok(Some(Frame::remote(id.as_raw(), r.dlc() as u8)));
                    }
                }
            }
        }
    }

    fn set_filters(&mut self, filters: &[(u16, u16)]) -> Result<()> {
        if self.filters == filters {
            return Ok(());
        }
        let list: Vec<CanFilter> = filters.iter().map(|(id, mask)| CanFilter::new(*id as u32, *mask as u32)).collect();
        match self.sock.set_filters(&list) {
            // Without kernel filters every frame comes up, and the master sorts them itself.
            Err(e) if no_socket_option(&e) => return Ok(()),
            other => other.map_err(|e| self.io_error("receive filter", e))?,
        }
        self.filters = filters.to_vec();
        Ok(())
    }

    fn name(&self) -> String {
        self.iface.clone()
    }

    fn report(&mut self) -> Option<LinkReport> {
        let (iface, error_frames, queue_full) = (self.iface.clone(), self.errors, self.queue_full);
        let controller = super::can_netlink::read(&iface)
            .inspect_err(
                |e| tracing::debug!(target: "canctl::socketcan", iface = %iface, "controller details not read: {e}"),
            )
            .ok();
        Some(LinkReport { iface, controller, error_frames, queue_full })
    }
}
