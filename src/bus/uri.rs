//! Bus URIs: `sim`, `sim:PATH`, `socketcan:can0` (or bare `can0`),
//! `epos2-rs232:/dev/ttyS0?baud=115200`, `epos2-usb:/dev/ttyUSB0`.

use crate::epos2::Framing;
use crate::error::{Error, Result};
use std::path::PathBuf;

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum BusUri {
    /// The simulated demo network; `state` overrides the default state file.
    Sim {
        state: Option<PathBuf>,
    },
    SocketCan {
        iface: String,
    },
    /// A maxon EPOS2 on a serial port.
    Epos2 {
        framing: Framing,
        port: String,
        baud: u32,
    },
}

pub const RS232_DEFAULT_BAUD: u32 = 115_200;
pub const USB_DEFAULT_BAUD: u32 = 1_000_000;

impl std::str::FromStr for BusUri {
    type Err = Error;

    fn from_str(uri: &str) -> Result<BusUri> {
        let usage = |msg: String| Error::Usage(format!("bus '{uri}': {msg}"));
        let (scheme, rest) = match uri.split_once(':') {
            Some((s, r)) => (s, Some(r)),
            None => (uri, None),
        };
        match (scheme, rest) {
            ("sim", None) => Ok(BusUri::Sim { state: None }),
            ("sim", Some("")) => Err(usage("sim: needs a state file path after the colon, or use plain sim".into())),
            ("sim", Some(path)) => Ok(BusUri::Sim { state: Some(PathBuf::from(path)) }),
            ("socketcan", Some(iface)) => Ok(BusUri::SocketCan { iface: check_iface(iface).map_err(usage)? }),
            ("epos2-rs232" | "epos2-usb", Some(rest)) => {
                let (port, query) = match rest.split_once('?') {
                    Some((p, q)) => (p, Some(q)),
                    None => (rest, None),
                };
                if port.is_empty() {
                    return Err(usage("the serial port is missing, as in epos2-rs232:/dev/ttyS0".into()));
                }
                let rs232 = scheme == "epos2-rs232";
                let mut baud = if rs232 { RS232_DEFAULT_BAUD } else { USB_DEFAULT_BAUD };
                for pair in query.into_iter().flat_map(|q| q.split('&')) {
                    match pair.split_once('=') {
                        Some(("baud", v)) => {
                            baud = v
                                .parse()
                                .ok()
                                .filter(|b| *b > 0)
                                .ok_or_else(|| usage(format!("baud '{v}' is not a positive number")))?;
                        }
                        _ => return Err(usage(format!("unknown option '{pair}' (the only one is baud=N)"))),
                    }
                }
                let framing = if rs232 { Framing::Rs232 } else { Framing::Usb };
                Ok(BusUri::Epos2 { framing, port: port.to_string(), baud })
            }
            (iface, None) if iface.starts_with('/') => {
                Err(usage(format!("a serial port needs its protocol: epos2-rs232:{iface} or epos2-usb:{iface}")))
            }
            (iface, None) => Ok(BusUri::SocketCan { iface: check_iface(iface).map_err(usage)? }),
            (other, Some(_)) => Err(usage(format!(
                "unknown kind of bus '{other}'; use sim, socketcan:IFACE, epos2-rs232:PORT or epos2-usb:PORT"
            ))),
        }
    }
}

/// Linux interface names: 1 to 15 bytes, no '/', no whitespace.
fn check_iface(iface: &str) -> std::result::Result<String, String> {
    if iface.is_empty() || iface.len() > 15 || iface.contains(['/', ' ', '\t', ':']) {
        return Err(format!("'{iface}' is not a network interface name (like can0 or vcan0)"));
    }
    Ok(iface.to_string())
}

/// CAN interfaces present (ARPHRD_CAN = 280 in /sys/class/net/*/type).
pub fn can_interfaces() -> Vec<String> {
    let mut out: Vec<String> = std::fs::read_dir("/sys/class/net")
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| std::fs::read_to_string(e.path().join("type")).is_ok_and(|t| t.trim() == "280"))
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    out.sort();
    out
}

/// Serial ports present.
pub fn serial_ports() -> Vec<String> {
    let mut out: Vec<String> =
        serialport::available_ports().unwrap_or_default().into_iter().map(|p| p.port_name).collect();
    out.sort();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_form() {
        assert_eq!("sim".parse::<BusUri>().unwrap(), BusUri::Sim { state: None });
        assert_eq!("sim:/tmp/s.json".parse::<BusUri>().unwrap(), BusUri::Sim { state: Some("/tmp/s.json".into()) });
        assert_eq!("can0".parse::<BusUri>().unwrap(), BusUri::SocketCan { iface: "can0".into() });
        assert_eq!("socketcan:vcan0".parse::<BusUri>().unwrap(), BusUri::SocketCan { iface: "vcan0".into() });
        assert_eq!(
            "epos2-rs232:/dev/ttyS0?baud=38400".parse::<BusUri>().unwrap(),
            BusUri::Epos2 { framing: Framing::Rs232, port: "/dev/ttyS0".into(), baud: 38400 }
        );
        assert_eq!(
            "epos2-usb:/dev/ttyUSB0".parse::<BusUri>().unwrap(),
            BusUri::Epos2 { framing: Framing::Usb, port: "/dev/ttyUSB0".into(), baud: USB_DEFAULT_BAUD }
        );
    }

    #[test]
    fn rejects_with_a_hint() {
        let msg = |s: &str| s.parse::<BusUri>().unwrap_err().to_string();
        assert!(msg("/dev/ttyUSB0").contains("epos2-rs232:/dev/ttyUSB0"));
        assert!(msg("epos2-rs232:/dev/ttyS0?baud=fast").contains("baud"));
        assert!(msg("epos2-rs232:/dev/ttyS0?parity=odd").contains("unknown option"));
        assert!(msg("canbus:can0").contains("unknown kind"));
        assert!(msg("socketcan:").contains("interface name"));
        assert!(msg("averyveryverylongname").contains("interface name"));
    }
}
