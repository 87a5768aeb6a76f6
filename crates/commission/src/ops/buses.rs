//! `canctl buses`: what this machine can reach — its CAN interfaces, serial ports whose USB
//! vendor and product say they are an slcan adapter or a maxon EPOS2, and the socketcand
//! servers whose beacons are heard within a bounded wait — each with the `--bus` value that
//! reaches it. The socketcand buses heard are kept for shell completion of `--bus`.

use crate::cancel::Cancel;
use crate::connect::BusAddr;
use crate::epos2::Framing;
use crate::socketcand::beacon::{self, Beacon};
use serde::{Deserialize, Serialize};
use std::net::UdpSocket;
use std::time::{Duration, Instant};

/// What kind of link a found bus is.
#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum BusKind {
    /// A CAN interface of this machine's kernel (SocketCAN).
    CanInterface,
    /// A serial-line CAN adapter (slcan firmware), by its USB ids.
    Slcan,
    /// A maxon EPOS2 on USB, by its USB ids.
    Epos2Usb,
    /// A CAN interface of another machine, announced by its socketcand server.
    Socketcand,
}

/// One bus this machine can reach.
#[derive(Serialize, Deserialize, Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct FoundBus {
    /// What kind of link it is.
    pub kind: BusKind,
    /// The exact `--bus` value that reaches it.
    pub bus: String,
    /// What it is, in words: the adapter's USB product, the server's name.
    pub what: String,
}

/// What `canctl buses` found.
#[derive(Serialize, Debug)]
#[non_exhaustive]
pub struct Buses {
    /// Every bus found, CAN interfaces first, then serial adapters, then socketcand servers.
    pub buses: Vec<FoundBus>,
    /// Serial ports that are no known adapter (an EPOS2 on RS232 has no USB ids to know it
    /// by; `--bus epos2-rs232:PORT` tries one).
    pub other_serial_ports: Vec<String>,
    /// How long beacons were listened for, in milliseconds.
    pub listened_ms: u64,
    /// The UDP port listened on.
    pub beacon_port: u16,
    /// Why no beacon could be heard (the port taken by another program), if so.
    pub not_listened: Option<String>,
    /// Whether the wait was cut short by a request to stop.
    pub interrupted: bool,
}

/// USB ids of the serial adapters canctl knows, and the link each speaks.
const KNOWN_USB: &[(u16, u16, BusKind, &str)] = &[
    // The FTDI chip with maxon's own product id (maxon's EPOS driver's udev rule).
    (0x0403, 0xA8B0, BusKind::Epos2Usb, "maxon EPOS2"),
    // CANable 2 / CANtact with slcan firmware (MCS Electronics' vendor id).
    (0x16D0, 0x117E, BusKind::Slcan, "CANable/CANtact (slcan)"),
    // CANable (openmoko id) where it shows as a serial port.
    (0x1D50, 0x606F, BusKind::Slcan, "CANable"),
];

/// What a serial port with these USB ids is, if canctl knows it.
pub fn usb_kind(vid: u16, pid: u16) -> Option<(BusKind, &'static str)> {
    KNOWN_USB.iter().find(|(v, p, ..)| (*v, *p) == (vid, pid)).map(|(_, _, kind, what)| (*kind, *what))
}

/// The `--bus` rows of a beacon: one per bus it offers.
pub fn beacon_rows(b: &Beacon) -> Vec<FoundBus> {
    let what = match b.description.is_empty() {
        true => format!("socketcand on {}", b.name),
        false => format!("socketcand on {} ({})", b.name, b.description),
    };
    let row = |iface: &String| {
        let bus = BusAddr::Socketcand { host: b.host.clone(), port: b.port, iface: iface.clone() }.to_string();
        FoundBus { kind: BusKind::Socketcand, bus, what: what.clone() }
    };
    b.buses.iter().map(row).collect()
}

/// Beacons heard on `socket` until `deadline` (or a request to stop), each server's bus
/// once. Datagrams that are no beacon are passed over (logged).
pub fn listen(socket: &UdpSocket, deadline: Instant, cancel: &Cancel) -> Vec<FoundBus> {
    let mut found: Vec<FoundBus> = Vec::new();
    let mut buf = [0u8; 2048];
    loop {
        // A host socket, not a bus: the links' monotonic clock is the time here.
        let left = deadline.saturating_duration_since(crate::bus::clock::monotonic_now());
        if left.is_zero() || cancel.is_cancelled() {
            return found;
        }
        // Short reads, so that a request to stop is seen soon.
        let _ = socket.set_read_timeout(Some(left.min(Duration::from_millis(100))));
        let Ok((n, from)) = socket.recv_from(&mut buf) else { continue };
        match beacon::parse(&buf[..n]) {
            Ok(b) => {
                for row in beacon_rows(&b) {
                    if !found.iter().any(|f| f.bus == row.bus) {
                        found.push(row);
                    }
                }
            }
            Err(e) => tracing::debug!(target: "canctl::buses", "datagram from {from} is no socketcand beacon: {e}"),
        }
    }
}

/// Find what this machine can reach, listening `wait` for socketcand beacons on UDP
/// `beacon_port`; the socketcand buses heard are kept for completion (unless none could be
/// listened for).
pub fn find(wait: Duration, beacon_port: u16, cancel: &Cancel) -> Buses {
    let interface = |iface| {
        let bus = BusAddr::SocketCan { iface }.to_string();
        FoundBus { kind: BusKind::CanInterface, bus, what: "CAN interface".into() }
    };
    let mut buses: Vec<FoundBus> = crate::connect::can_interfaces().into_iter().map(interface).collect();
    let mut other_serial_ports = Vec::new();
    let mut ports = serialport::available_ports().unwrap_or_default();
    ports.sort_by(|a, b| a.port_name.cmp(&b.port_name));
    for p in ports {
        let known = match &p.port_type {
            serialport::SerialPortType::UsbPort(u) => usb_kind(u.vid, u.pid).map(|k| (k, u.product.clone())),
            _ => None,
        };
        match known {
            Some(((kind, what), product)) => buses.push(serial_row(kind, p.port_name, what, product)),
            None => other_serial_ports.push(p.port_name),
        }
    }
    let started = crate::bus::clock::monotonic_now();
    let (heard, not_listened) = match UdpSocket::bind((std::net::Ipv4Addr::UNSPECIFIED, beacon_port)) {
        Ok(socket) => (listen(&socket, started + wait, cancel), None),
        Err(e) => (Vec::new(), Some(e.to_string())),
    };
    let interrupted = cancel.is_cancelled();
    // A run that did not listen (or not to its end) has not heard the servers go away.
    if not_listened.is_none() && !interrupted && !wait.is_zero() {
        // Kept in place of the last run's.
        super::scan_cache::write_cache(heard_file(), &heard);
    }
    buses.extend(heard);
    let listened_ms = started.elapsed().as_millis() as u64;
    Buses { buses, other_serial_ports, listened_ms, beacon_port, not_listened, interrupted }
}

fn serial_row(kind: BusKind, port: String, what: &str, product: Option<String>) -> FoundBus {
    let bus = match kind {
        BusKind::Epos2Usb => BusAddr::Epos2 { framing: Framing::Usb, port, baud: crate::connect::USB_DEFAULT_BAUD },
        _ => BusAddr::Slcan { port, kbit: crate::connect::SLCAN_DEFAULT_KBIT },
    };
    let what = match product.filter(|p| !p.is_empty() && p != what) {
        Some(p) => format!("{what}: {p}"),
        None => what.to_string(),
    };
    FoundBus { kind, bus: bus.to_string(), what }
}

fn heard_file() -> Option<std::path::PathBuf> {
    Some(crate::xdg::cache_dir()?.join("socketcand-heard.json"))
}

/// The socketcand buses the last `canctl buses` heard (for completion: files only).
pub fn last_heard() -> Vec<FoundBus> {
    super::scan_cache::read_cache(heard_file())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_bus_of_a_beacon_is_a_row_with_its_bus_value() {
        let b = beacon::parse(
            b"<CANBeacon name=\"pi\" type=\"SocketCAN\" description=\"bench 3\"><URL>can://10.0.0.7:29536</URL>\
              <Bus name=\"can0\"/><Bus name=\"can1\"/></CANBeacon>",
        )
        .unwrap();
        let rows = beacon_rows(&b);
        let buses: Vec<&str> = rows.iter().map(|r| r.bus.as_str()).collect();
        assert_eq!(buses, ["socketcand:10.0.0.7/can0", "socketcand:10.0.0.7/can1"]);
        assert_eq!(rows[0].what, "socketcand on pi (bench 3)");
        for bus in buses {
            bus.parse::<BusAddr>().unwrap();
        }
    }

    #[test]
    fn known_usb_ids_and_the_bus_values_they_give() {
        assert_eq!(usb_kind(0x0403, 0xA8B0).map(|k| k.0), Some(BusKind::Epos2Usb));
        assert_eq!(usb_kind(0x16D0, 0x117E).map(|k| k.0), Some(BusKind::Slcan));
        // An FTDI cable with its usual id is anything at all.
        assert_eq!(usb_kind(0x0403, 0x6001), None);
        let epos = serial_row(BusKind::Epos2Usb, "/dev/ttyUSB0".into(), "maxon EPOS2", Some("EPOS2".into()));
        assert_eq!(epos.bus.parse::<BusAddr>().unwrap().to_string(), epos.bus);
        assert!(epos.bus.starts_with("epos2-usb:/dev/ttyUSB0"), "{}", epos.bus);
        let slcan = serial_row(BusKind::Slcan, "/dev/ttyACM0".into(), "CANable", None);
        assert!(slcan.bus.starts_with("slcan:/dev/ttyACM0"), "{}", slcan.bus);
    }

    #[test]
    fn listening_ends_at_the_deadline_with_each_bus_once_and_garbage_passed_over() {
        let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
        let to = socket.local_addr().unwrap();
        let tx = UdpSocket::bind("127.0.0.1:0").unwrap();
        let b = beacon::encode("h", "d", "127.0.0.1:4000".parse().unwrap(), &["sim"]);
        for bytes in [&b[..], b"garbage", &b[..b.len() - 4], &b[..]] {
            tx.send_to(bytes, to).unwrap();
        }
        let found = listen(&socket, crate::bus::clock::monotonic_now() + Duration::from_millis(300), &Cancel::new());
        let buses: Vec<&str> = found.iter().map(|f| f.bus.as_str()).collect();
        assert_eq!(buses, ["socketcand:127.0.0.1:4000/sim"]);
    }
}
