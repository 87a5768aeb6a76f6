//! A CAN interface's controller details over rtnetlink (what `ip -details link show can0`
//! shows): its state, error counters, restart-ms and bit rate; or that it is virtual. One
//! RTM_GETLINK request, read only: nothing about the interface is changed.
//!
//! The layouts are the kernel's (`linux/netlink.h`, `linux/rtnetlink.h`,
//! `linux/if_link.h`, `linux/can/netlink.h`); native byte order, as netlink is.

use crate::bus::controller::{CanState, Controller};
use nix::libc;
use std::io;
use std::time::Duration;

const NLMSG_HDR: usize = 16;
const IFINFOMSG: usize = 16;
const NLMSG_ERROR: u16 = 2;
const RTM_NEWLINK: u16 = 16;
const RTM_GETLINK: u16 = 18;
const NLM_F_REQUEST: u16 = 1;
const IFLA_LINKINFO: u16 = 18;
const IFLA_INFO_KIND: u16 = 1;
const IFLA_INFO_DATA: u16 = 2;
const IFLA_CAN_BITTIMING: u16 = 1;
const IFLA_CAN_STATE: u16 = 4;
const IFLA_CAN_RESTART_MS: u16 = 6;
const IFLA_CAN_BERR_COUNTER: u16 = 8;
/// The nested-attribute flag a type may carry.
const NLA_TYPE_MASK: u16 = 0x3FFF;
/// How long the kernel may take to answer: it answers at once, this only bounds a hang.
const ANSWER_WAIT: Duration = Duration::from_millis(500);

fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_ne_bytes(b.get(at..at + 2)?.try_into().ok()?))
}

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_ne_bytes(b.get(at..at + 4)?.try_into().ok()?))
}

/// The attributes in `b`, as (type, payload); a malformed one ends the list.
fn attributes(mut b: &[u8]) -> impl Iterator<Item = (u16, &[u8])> {
    std::iter::from_fn(move || {
        let len = usize::from(u16_at(b, 0)?);
        let kind = u16_at(b, 2)? & NLA_TYPE_MASK;
        if len < 4 || len > b.len() {
            return None;
        }
        let payload = &b[4..len];
        b = b.get((len + 3) & !3..).unwrap_or(&[]);
        Some((kind, payload))
    })
}

/// The controller from an RTM_NEWLINK answer (the whole netlink message); `None` when it
/// is not one, or names no link kind.
pub(crate) fn parse_link(msg: &[u8]) -> Option<Controller> {
    let len = u32_at(msg, 0)? as usize;
    if u16_at(msg, 4)? != RTM_NEWLINK || len > msg.len() {
        return None;
    }
    let attrs = msg.get(NLMSG_HDR + IFINFOMSG..len)?;
    let (_, info) = attributes(attrs).find(|(k, _)| *k == IFLA_LINKINFO)?;
    let kind = attributes(info).find(|(k, _)| *k == IFLA_INFO_KIND)?.1;
    let kind = std::str::from_utf8(kind).ok()?.trim_end_matches('\0');
    if kind != "can" {
        return Some(Controller::Virtual);
    }
    let (mut state, mut tx_errors, mut rx_errors, mut restart_ms, mut bitrate) = (None, None, None, None, None);
    if let Some((_, data)) = attributes(info).find(|(k, _)| *k == IFLA_INFO_DATA) {
        for (k, v) in attributes(data) {
            match k {
                IFLA_CAN_STATE => state = u32_at(v, 0).and_then(CanState::from_raw),
                IFLA_CAN_RESTART_MS => restart_ms = u32_at(v, 0),
                // struct can_bittiming starts with the bit rate.
                IFLA_CAN_BITTIMING => bitrate = u32_at(v, 0).filter(|r| *r > 0),
                // struct can_berr_counter { __u16 txerr; __u16 rxerr; }
                IFLA_CAN_BERR_COUNTER => {
                    tx_errors = u16_at(v, 0);
                    rx_errors = u16_at(v, 2);
                }
                _ => {}
            }
        }
    }
    Some(Controller::Can { state, tx_errors, rx_errors, restart_ms, bitrate })
}

/// The RTM_GETLINK request for the interface of index `index`.
fn request(index: i32) -> Vec<u8> {
    let mut m = Vec::with_capacity(NLMSG_HDR + IFINFOMSG);
    m.extend(((NLMSG_HDR + IFINFOMSG) as u32).to_ne_bytes());
    m.extend(RTM_GETLINK.to_ne_bytes());
    m.extend(NLM_F_REQUEST.to_ne_bytes());
    m.extend(1u32.to_ne_bytes()); // sequence
    m.extend(0u32.to_ne_bytes()); // port: the kernel's
    m.extend([libc::AF_UNSPEC as u8, 0]);
    m.extend(0u16.to_ne_bytes()); // device type
    m.extend(index.to_ne_bytes());
    m.extend(0u32.to_ne_bytes()); // flags
    m.extend(0u32.to_ne_bytes()); // change mask
    m
}

/// Ask the kernel for `iface`'s controller details.
pub(crate) fn read(iface: &str) -> io::Result<Controller> {
    let name = std::ffi::CString::new(iface).map_err(|_| io::Error::from(io::ErrorKind::InvalidInput))?;
    // SAFETY: a NUL-terminated name; the call only reads it.
    let index = unsafe { libc::if_nametoindex(name.as_ptr()) };
    if index == 0 {
        return Err(io::Error::last_os_error());
    }
    // SAFETY: plain socket calls on a descriptor owned here and closed by OwnedFd.
    let fd = unsafe { libc::socket(libc::AF_NETLINK, libc::SOCK_RAW | libc::SOCK_CLOEXEC, libc::NETLINK_ROUTE) };
    if fd < 0 {
        return Err(io::Error::last_os_error());
    }
    let fd = unsafe { <std::os::fd::OwnedFd as std::os::fd::FromRawFd>::from_raw_fd(fd) };
    let raw = std::os::fd::AsRawFd::as_raw_fd(&fd);
    let wait = libc::timeval { tv_sec: 0, tv_usec: ANSWER_WAIT.as_micros() as libc::suseconds_t };
    let req = request(index as i32);
    let mut buf = vec![0u8; 16 * 1024];
    // SAFETY: the option value, the request and the buffer outlive the calls.
    let got = unsafe {
        libc::setsockopt(
            raw,
            libc::SOL_SOCKET,
            libc::SO_RCVTIMEO,
            (&wait as *const libc::timeval).cast(),
            std::mem::size_of::<libc::timeval>() as libc::socklen_t,
        );
        if libc::send(raw, req.as_ptr().cast(), req.len(), 0) < 0 {
            return Err(io::Error::last_os_error());
        }
        libc::recv(raw, buf.as_mut_ptr().cast(), buf.len(), 0)
    };
    if got < 0 {
        return Err(io::Error::last_os_error());
    }
    let msg = &buf[..got as usize];
    if u16_at(msg, 4) == Some(NLMSG_ERROR) {
        let errno = u32_at(msg, NLMSG_HDR).map(|e| -(e as i32)).unwrap_or(libc::EIO);
        return Err(io::Error::from_raw_os_error(errno));
    }
    parse_link(msg).ok_or_else(|| io::Error::new(io::ErrorKind::InvalidData, "no link details in the answer"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn attr(kind: u16, payload: &[u8]) -> Vec<u8> {
        let mut a = Vec::new();
        a.extend(((4 + payload.len()) as u16).to_ne_bytes());
        a.extend(kind.to_ne_bytes());
        a.extend(payload);
        a.resize((a.len() + 3) & !3, 0);
        a
    }

    fn newlink(linkinfo: Vec<u8>) -> Vec<u8> {
        let mut body = vec![0u8; IFINFOMSG];
        body.extend(attr(3, b"can0\0")); // IFLA_IFNAME, before the link info as the kernel sends it
        body.extend(attr(IFLA_LINKINFO | 0x8000, &linkinfo));
        let mut m = Vec::new();
        m.extend(((NLMSG_HDR + body.len()) as u32).to_ne_bytes());
        m.extend(RTM_NEWLINK.to_ne_bytes());
        m.extend([0u8; 10]);
        m.extend(body);
        m
    }

    #[test]
    fn a_can_controller_bus_off_without_restart() {
        let mut data = attr(IFLA_CAN_BITTIMING, &[&250_000u32.to_ne_bytes()[..], &[0; 28]].concat());
        data.extend(attr(IFLA_CAN_STATE, &3u32.to_ne_bytes()));
        data.extend(attr(IFLA_CAN_RESTART_MS, &0u32.to_ne_bytes()));
        data.extend(attr(IFLA_CAN_BERR_COUNTER, &[&256u16.to_ne_bytes()[..], &3u16.to_ne_bytes()].concat()));
        let mut info = attr(IFLA_INFO_KIND, b"can\0");
        info.extend(attr(IFLA_INFO_DATA | 0x8000, &data));
        assert_eq!(
            parse_link(&newlink(info)),
            Some(Controller::Can {
                state: Some(CanState::BusOff),
                tx_errors: Some(256),
                rx_errors: Some(3),
                restart_ms: Some(0),
                bitrate: Some(250_000),
            })
        );
    }

    #[test]
    fn vcan_has_no_controller() {
        assert_eq!(parse_link(&newlink(attr(IFLA_INFO_KIND, b"vcan\0"))), Some(Controller::Virtual));
    }

    #[test]
    fn a_can_link_that_gives_no_details_says_none() {
        let info = attr(IFLA_INFO_KIND, b"can\0");
        assert_eq!(
            parse_link(&newlink(info)),
            Some(Controller::Can { state: None, tx_errors: None, rx_errors: None, restart_ms: None, bitrate: None })
        );
    }

    #[test]
    fn malformed_answers_give_nothing() {
        let mut m = newlink(attr(IFLA_INFO_KIND, b"can\0"));
        assert_eq!(parse_link(&m[..10]), None);
        // An attribute whose length runs past the message ends the list.
        let at = NLMSG_HDR + IFINFOMSG;
        m[at..at + 2].copy_from_slice(&500u16.to_ne_bytes());
        assert_eq!(parse_link(&m), None);
        m[4..6].copy_from_slice(&NLMSG_ERROR.to_ne_bytes());
        assert_eq!(parse_link(&m), None);
    }
}
