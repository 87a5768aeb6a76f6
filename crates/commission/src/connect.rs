//! Bus addresses: `sim`, `sim:PATH`, `socketcan:can0` (or bare `can0`),
//! `epos2-rs232:/dev/ttyS0?baud=115200`, `epos2-usb:/dev/ttyUSB0`, `slcan:/dev/ttyACM0@500k`,
//! `socketcand:HOST[:PORT]/IFACE` — parsed with `FromStr`,
//! written back with `Display`, and opened by the one factory, [`open`].

use crate::backend::epos2::Epos2Gateway;
pub use crate::backend::{can_interfaces, serial_ports};
use crate::bus::{Bus, FrameLog, Master};
use crate::epos2::transport::SerialTransport;
use crate::epos2::Framing;
use crate::error::{Error, LinkError, Result};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

/// Where the bus is: parsed from a URI, printed back as the same URI.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum BusAddr {
    /// The simulated demo network; `state` overrides the default state file.
    Sim {
        /// The state file to use instead of the default one.
        state: Option<PathBuf>,
    },
    /// A SocketCAN interface (Linux).
    SocketCan {
        /// The interface's name: can0, vcan0.
        iface: String,
    },
    /// A maxon EPOS2 on a serial port.
    Epos2 {
        /// RS232 or USB framing.
        framing: Framing,
        /// The serial port: /dev/ttyUSB0, COM3.
        port: String,
        /// The serial line's baud rate (RS232; USB ignores it).
        baud: u32,
    },
    /// A serial-line CAN adapter (slcan) at this CAN bit rate.
    Slcan {
        /// The adapter's serial port.
        port: String,
        /// The CAN bit rate the adapter is to open the bus at, in kbit/s.
        kbit: u32,
    },
    /// A CAN interface of another machine, through its socketcand server (raw mode).
    Socketcand {
        /// The server's host name or address (an IPv6 address without brackets).
        host: String,
        /// The server's TCP port.
        port: u16,
        /// The CAN interface on the server's machine: can0, vcan0.
        iface: String,
    },
}

/// The serial bit rate of an `epos2-rs232:` bus without `?baud=` (the EPOS2's default).
pub(crate) const RS232_DEFAULT_BAUD: u32 = 115_200;
/// The bit rate of an `epos2-usb:` bus without `?baud=`.
pub(crate) const USB_DEFAULT_BAUD: u32 = 1_000_000;
/// The CAN bit rate of an slcan adapter named without `@RATE`.
pub(crate) const SLCAN_DEFAULT_KBIT: u32 = 500;

/// The serial bit rate of an EPOS2 bus without `?baud=`.
pub(crate) fn default_baud(framing: Framing) -> u32 {
    match framing {
        Framing::Rs232 => RS232_DEFAULT_BAUD,
        Framing::Usb => USB_DEFAULT_BAUD,
    }
}

/// `500k`, `1M`, `125000` (bit/s) → kbit/s.
fn parse_kbit(text: &str) -> Option<u32> {
    let t = text.trim();
    let (num, scale) = if let Some(n) = t.strip_suffix(['k', 'K']) {
        (n, 1.0)
    } else if let Some(n) = t.strip_suffix('M') {
        (n, 1000.0)
    } else {
        (t, 0.001)
    };
    let kbit = num.parse::<f64>().ok()? * scale;
    (kbit >= 1.0 && kbit.fract() == 0.0 && kbit <= 1000.0).then_some(kbit as u32)
}

/// A bit rate in kbit/s as canctl writes it (`500k`, `1M`).
pub fn kbit_text(kbit: u32) -> String {
    if kbit == 1000 {
        "1M".into()
    } else {
        format!("{kbit}k")
    }
}

impl std::str::FromStr for BusAddr {
    type Err = Error;

    fn from_str(uri: &str) -> Result<BusAddr> {
        let usage = |reason: String| Error::BadBusAddr { uri: uri.to_string(), reason };
        let (scheme, rest) = uri.split_once(':').map_or((uri, None), |(s, r)| (s, Some(r)));
        match (scheme, rest) {
            ("sim", None) => Ok(BusAddr::Sim { state: None }),
            ("sim", Some("")) => Err(usage("sim: needs a state file path after the colon, or use plain sim".into())),
            ("sim", Some(path)) => Ok(BusAddr::Sim { state: Some(PathBuf::from(path)) }),
            ("socketcan", Some(iface)) => Ok(BusAddr::SocketCan { iface: check_iface(iface).map_err(usage)? }),
            ("epos2-rs232" | "epos2-usb", Some(rest)) => {
                let (port, query) = rest.split_once('?').map_or((rest, None), |(p, q)| (p, Some(q)));
                if port.is_empty() {
                    return Err(usage("the serial port is missing, as in epos2-rs232:/dev/ttyS0".into()));
                }
                let framing = if scheme == "epos2-rs232" { Framing::Rs232 } else { Framing::Usb };
                let mut baud = default_baud(framing);
                let not_positive = |v: &str| usage(format!("baud '{v}' is not a positive number"));
                for pair in query.into_iter().flat_map(|q| q.split('&')) {
                    match pair.split_once('=') {
                        Some(("baud", v)) => baud = v.parse().ok().filter(|b| *b > 0).ok_or_else(|| not_positive(v))?,
                        _ => return Err(usage(format!("unknown option '{pair}' (the only one is baud=N)"))),
                    }
                }
                Ok(BusAddr::Epos2 { framing, port: port.to_string(), baud })
            }
            ("slcan", Some(rest)) => {
                let (port, rate) = rest.rsplit_once('@').map_or((rest, None), |(p, r)| (p, Some(r)));
                if port.is_empty() {
                    return Err(usage("the serial port is missing, as in slcan:/dev/ttyACM0@500k".into()));
                }
                let refused = |r: &str| {
                    usage(format!("'{r}' is not an slcan bit rate: use 10k 20k 50k 100k 125k 250k 500k 800k or 1M"))
                };
                let slcan_rate = |k: &u32| crate::slcan::wire::bit_rate_code(*k).is_some();
                let kbit = match rate {
                    None => SLCAN_DEFAULT_KBIT,
                    Some(r) => parse_kbit(r).filter(slcan_rate).ok_or_else(|| refused(r))?,
                };
                Ok(BusAddr::Slcan { port: port.to_string(), kbit })
            }
            ("socketcand", Some(rest)) => parse_socketcand(rest).map_err(usage),
            (iface, None) if iface.starts_with('/') => Err(usage(format!(
                "a serial port needs its protocol: slcan:{iface}, epos2-rs232:{iface} or epos2-usb:{iface}"
            ))),
            (iface, None) => Ok(BusAddr::SocketCan { iface: check_iface(iface).map_err(usage)? }),
            (other, Some(_)) => Err(usage(format!(
                "unknown kind of bus '{}'; use sim, socketcan:IFACE, slcan:PORT, epos2-rs232:PORT, epos2-usb:PORT \
                 or socketcand:HOST[:PORT]/IFACE",
                crate::error::clipped(other)
            ))),
        }
    }
}

/// The canonical URI: `socketcan:` spelled out, the baud only when it is not the default.
impl std::fmt::Display for BusAddr {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BusAddr::Sim { state: None } => f.write_str("sim"),
            BusAddr::Sim { state: Some(path) } => write!(f, "sim:{}", path.display()),
            BusAddr::SocketCan { iface } => write!(f, "socketcan:{iface}"),
            BusAddr::Epos2 { framing, port, baud } => {
                write!(f, "{}:{port}", framing.scheme())?;
                if *baud != default_baud(*framing) {
                    write!(f, "?baud={baud}")?;
                }
                Ok(())
            }
            BusAddr::Slcan { port, kbit } => write!(f, "slcan:{port}@{}", kbit_text(*kbit)),
            BusAddr::Socketcand { host, port, iface } => {
                let host = if host.contains(':') { format!("[{host}]") } else { host.clone() };
                write!(f, "socketcand:{host}")?;
                if *port != crate::socketcand::DEFAULT_PORT {
                    write!(f, ":{port}")?;
                }
                write!(f, "/{iface}")
            }
        }
    }
}

/// How to open a bus: what every backend needs besides its address.
#[derive(Clone, Debug)]
pub struct OpenOptions {
    /// How long a serial link waits for each answer.
    pub timeout: Duration,
    /// `sim` only: a fresh demo network in memory, no state file read or kept.
    pub ephemeral: bool,
    /// Write every frame sent and received here (candump log format). Through an EPOS2,
    /// the frames the backend itself exchanges: NMT, LSS, RequestCANFrame and SendCANFrame
    /// (an SDO transfer is the EPOS2's own business on its CAN bus).
    pub frame_log: Option<FrameLog>,
    /// `sim` only: how long to wait for another process using the same sim network.
    pub lock_wait: Duration,
}

impl OpenOptions {
    /// Options with this answer timeout: the saved sim network, no frame log, the default
    /// wait for the sim network's lock.
    pub fn new(timeout: Duration) -> OpenOptions {
        OpenOptions { timeout, ephemeral: false, frame_log: None, lock_wait: crate::sim::state::DEFAULT_LOCK_WAIT }
    }
}

/// Open the bus at `addr`: the one place that knows which backend serves which address.
pub fn open(addr: &BusAddr, opts: &OpenOptions) -> Result<Box<dyn Bus>> {
    match addr {
        BusAddr::Sim { state } => {
            let link = if opts.ephemeral {
                crate::sim::SimLink::ephemeral()
            } else {
                let path = state.clone().unwrap_or_else(crate::sim::state::default_path);
                crate::sim::SimLink::open(crate::sim::state::StateFile::lock_within(&path, opts.lock_wait)?)?
            };
            // Nothing else shares this bus: it may run on virtual time, its devices' clock
            // going on from the wall clock's (their timed state is kept in wall-clock ms).
            let link = if link.wants_virtual_time() { link.on_virtual_time(crate::sim::wall_ms()) } else { link };
            // Messages name the demo network, not its state file.
            Ok(master(link, BusAddr::Sim { state: None }.to_string(), opts))
        }
        #[cfg(target_os = "linux")]
        BusAddr::SocketCan { iface } => {
            Ok(master(crate::backend::socketcan::SocketCanLink::open(iface)?, addr.to_string(), opts))
        }
        #[cfg(not(target_os = "linux"))]
        BusAddr::SocketCan { .. } => Err(Error::NoSocketCan { bus: addr.to_string() }),
        BusAddr::Epos2 { framing, port, baud } => {
            let io = open_serial(port, *baud, opts.timeout)?;
            let link = SerialTransport::new(io, *framing, addr.to_string(), opts.timeout);
            Ok(Box::new(Epos2Gateway::new(link).with_frame_log(opts.frame_log.clone())))
        }
        BusAddr::Slcan { port, kbit } => {
            // The adapter's own serial speed does not matter on USB; 115200 suits the
            // adapters that sit behind a real UART.
            let io = open_serial(port, 115_200, opts.timeout)?;
            Ok(master(crate::backend::slcan::SlcanLink::open(io, addr.to_string(), *kbit)?, addr.to_string(), opts))
        }
        BusAddr::Socketcand { host, port, iface } => {
            let link =
                crate::backend::socketcand::SocketcandLink::open(host, *port, iface, addr.to_string(), opts.timeout)?;
            Ok(master(link, addr.to_string(), opts))
        }
    }
}

/// The bus over a link of frames, named `describe`, its frames logged as `opts` ask.
fn master<L: crate::bus::FrameLink + 'static>(link: L, describe: String, opts: &OpenOptions) -> Box<dyn Bus> {
    Box::new(Master::new(link, describe).with_frame_log(opts.frame_log.clone()))
}

/// `HOST[:PORT]/IFACE`, the host an IPv6 address in brackets if it is one.
fn parse_socketcand(rest: &str) -> std::result::Result<BusAddr, String> {
    let form = "as in socketcand:bench1/can0 or socketcand:192.168.1.20:29536/can0";
    let Some((server, iface)) = rest.rsplit_once('/') else {
        return Err(format!("the CAN interface is missing, {form}"));
    };
    let (host, port) = match server.strip_prefix('[') {
        Some(v6) => match v6.split_once(']') {
            Some((host, "")) => (host, None),
            Some((host, port)) => (host, Some(port.strip_prefix(':').ok_or(format!("'{server}' is not HOST:PORT"))?)),
            None => return Err(format!("'{server}' lacks its closing ']'")),
        },
        None => match server.split_once(':') {
            Some((host, port)) => (host, Some(port)),
            None => (server, None),
        },
    };
    if host.is_empty() || host.contains(['/', ' ', '[', ']']) || (!server.starts_with('[') && host.contains(':')) {
        return Err(format!("the server's host is missing or malformed, {form}"));
    }
    let port = match port {
        None => crate::socketcand::DEFAULT_PORT,
        Some(p) => p.parse().ok().filter(|p| *p > 0).ok_or(format!("port '{p}' is not a TCP port (1-65535)"))?,
    };
    Ok(BusAddr::Socketcand { host: host.to_string(), port, iface: check_iface(iface)? })
}

#[cfg(unix)]
type NativePort = serialport::TTYPort;
#[cfg(windows)]
type NativePort = serialport::COMPort;

/// 8N1 at `baud`, no flow control (seed 000 §5.1.5).
fn open_serial(port: &str, baud: u32, timeout: Duration) -> Result<NativePort> {
    #[allow(unused_mut)]
    let mut io = serialport::new(port, baud)
        .data_bits(serialport::DataBits::Eight)
        .parity(serialport::Parity::None)
        .stop_bits(serialport::StopBits::One)
        .flow_control(serialport::FlowControl::None)
        .timeout(timeout)
        .open_native()
        .map_err(|e| open_error(port, e))?;
    // A pseudo-terminal (the simulator's device side) is opened again by every command;
    // the exclusive flag would outlive this process and lock the next one out.
    #[cfg(unix)]
    if port.starts_with("/dev/pts/") {
        let io_error =
            |e: serialport::Error| LinkError::Io { port: port.to_string(), op: "", error: Arc::new(e.into()) };
        io.set_exclusive(false).map_err(io_error)?;
    }
    Ok(io)
}

/// Why a serial port did not open; a path that is no terminal (ENOTTY: `/dev/null`, a
/// file) said to be no serial port, with the ones there are.
fn open_error(port: &str, e: serialport::Error) -> Error {
    #[cfg(unix)]
    if e.description == nix::errno::Errno::ENOTTY.desc() {
        return LinkError::NotSerialPort { port: port.to_string(), available: serial_ports() }.into();
    }
    LinkError::Open { port: port.to_string(), error: Arc::new(e.into()) }.into()
}

/// Linux interface names: 1 to 15 bytes, no '/', no whitespace.
fn check_iface(iface: &str) -> std::result::Result<String, String> {
    if iface.is_empty() || iface.len() > 15 || iface.contains(['/', ' ', '\t', ':']) {
        return Err(format!("'{}' is not a network interface name (like can0 or vcan0)", crate::error::clipped(iface)));
    }
    Ok(iface.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_form() {
        assert_eq!(
            "socketcand:bench1/can0".parse::<BusAddr>().unwrap(),
            BusAddr::Socketcand { host: "bench1".into(), port: 29536, iface: "can0".into() }
        );
        assert_eq!(
            "socketcand:[::1]:4000/vcan0".parse::<BusAddr>().unwrap(),
            BusAddr::Socketcand { host: "::1".into(), port: 4000, iface: "vcan0".into() }
        );
        assert_eq!("sim".parse::<BusAddr>().unwrap(), BusAddr::Sim { state: None });
        assert_eq!("sim:/tmp/s.json".parse::<BusAddr>().unwrap(), BusAddr::Sim { state: Some("/tmp/s.json".into()) });
        assert_eq!("can0".parse::<BusAddr>().unwrap(), BusAddr::SocketCan { iface: "can0".into() });
        assert_eq!("socketcan:vcan0".parse::<BusAddr>().unwrap(), BusAddr::SocketCan { iface: "vcan0".into() });
        assert_eq!(
            "epos2-rs232:/dev/ttyS0?baud=38400".parse::<BusAddr>().unwrap(),
            BusAddr::Epos2 { framing: Framing::Rs232, port: "/dev/ttyS0".into(), baud: 38400 }
        );
        assert_eq!(
            "epos2-usb:/dev/ttyUSB0".parse::<BusAddr>().unwrap(),
            BusAddr::Epos2 { framing: Framing::Usb, port: "/dev/ttyUSB0".into(), baud: USB_DEFAULT_BAUD }
        );
    }

    #[test]
    fn display_round_trips_for_every_backend() {
        let forms = [
            ("sim", "sim"),
            ("sim:/tmp/state.json", "sim:/tmp/state.json"),
            ("socketcan:vcan0", "socketcan:vcan0"),
            ("can0", "socketcan:can0"),
            ("epos2-rs232:/dev/ttyS0?baud=38400", "epos2-rs232:/dev/ttyS0?baud=38400"),
            ("epos2-rs232:/dev/ttyS0?baud=115200", "epos2-rs232:/dev/ttyS0"),
            ("epos2-rs232:COM3", "epos2-rs232:COM3"),
            ("epos2-usb:/dev/ttyUSB0", "epos2-usb:/dev/ttyUSB0"),
            ("epos2-usb:/dev/ttyUSB0?baud=115200", "epos2-usb:/dev/ttyUSB0?baud=115200"),
            ("slcan:/dev/ttyACM0", "slcan:/dev/ttyACM0@500k"),
            ("slcan:/dev/ttyACM0@1M", "slcan:/dev/ttyACM0@1M"),
            ("slcan:COM5@125000", "slcan:COM5@125k"),
            ("slcan:/dev/tty.usbmodem1101@100k", "slcan:/dev/tty.usbmodem1101@100k"),
            ("socketcand:bench1/can0", "socketcand:bench1/can0"),
            ("socketcand:bench1:29536/can0", "socketcand:bench1/can0"),
            ("socketcand:127.0.0.1:4000/vcan0", "socketcand:127.0.0.1:4000/vcan0"),
            ("socketcand:[::1]:4000/vcan0", "socketcand:[::1]:4000/vcan0"),
            ("socketcand:[fe80::1]/can1", "socketcand:[fe80::1]/can1"),
        ];
        for (text, canonical) in forms {
            let addr: BusAddr = text.parse().unwrap();
            assert_eq!(addr.to_string(), canonical, "{text}");
            assert_eq!(canonical.parse::<BusAddr>().unwrap(), addr, "{canonical}");
        }
    }

    #[test]
    fn the_ephemeral_sim_needs_no_state_file() {
        let mut opts = OpenOptions::new(Duration::from_millis(500));
        opts.ephemeral = true;
        let mut bus = open(&BusAddr::Sim { state: Some("/nonexistent/dir/state.json".into()) }, &opts).unwrap();
        assert_eq!(bus.describe(), "sim");
        bus.close().unwrap();
    }

    #[test]
    fn rejects_with_a_hint() {
        let msg = |s: &str| s.parse::<BusAddr>().unwrap_err().to_string();
        assert!(msg("/dev/ttyUSB0").contains("epos2-rs232:/dev/ttyUSB0"));
        assert!(msg("epos2-rs232:/dev/ttyS0?baud=fast").contains("baud"));
        assert!(msg("epos2-rs232:/dev/ttyS0?parity=odd").contains("unknown option"));
        assert!(msg("canbus:can0").contains("unknown kind"));
        assert!(msg("slcan:/dev/ttyACM0@83k").contains("not an slcan bit rate"));
        assert!(msg("slcan:@500k").contains("serial port is missing"));
        assert!(msg("socketcan:").contains("interface name"));
        assert!(msg("averyveryverylongname").contains("interface name"));
        assert!(msg("socketcand:bench1").contains("CAN interface is missing"));
        assert!(msg("socketcand:/can0").contains("host is missing"));
        assert!(msg("socketcand:bench1:0/can0").contains("not a TCP port"));
        assert!(msg("socketcand:bench1:http/can0").contains("not a TCP port"));
        assert!(msg("socketcand:[::1/can0").contains("closing ']'"));
        assert!(msg("socketcand:bench1/").contains("interface name"));
        assert!(msg("socketcand:::1/can0").contains("host is missing"));
    }
}
