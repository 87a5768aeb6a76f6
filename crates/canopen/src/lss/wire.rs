//! LSS frames (CiA 305), pure: the identity an LSS address is, the bit-timing table, the
//! master's requests and the slaves' answers, encoded and decoded with byte vectors. Master
//! requests go on 0x7E5, slave answers on 0x7E4; all frames are 8 bytes.

use crate::frame::command;
use std::fmt;

/// The COB-ID of LSS master requests; slaves answer on 0x7E4.
pub const MASTER_COB: u16 = 0x7E5;
/// The COB-ID of LSS slave answers (CiA 305).
pub const SLAVE_COB: u16 = 0x7E4;
/// The node-id of a device that has none ("not configured").
pub const UNCONFIGURED: u8 = 0xFF;

/// The LSS address: the four entries of the identity object 0x1018.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
pub struct Identity {
    /// The vendor-id (0x1018:1).
    pub vendor: u32,
    /// The product code (0x1018:2).
    pub product: u32,
    /// The revision number (0x1018:3).
    pub revision: u32,
    /// The serial number (0x1018:4).
    pub serial: u32,
}

impl Identity {
    /// Part `i` of the identity: 0 vendor, 1 product, 2 revision, 3 serial.
    pub fn part(&self, i: u8) -> u32 {
        [self.vendor, self.product, self.revision, self.serial][usize::from(i.min(3))]
    }
}

/// `0x00000040:0x43787800:0x312E3031:0x09501234`
impl fmt::Display for Identity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "0x{:08X}:0x{:08X}:0x{:08X}:0x{:08X}", self.vendor, self.product, self.revision, self.serial)
    }
}

/// VENDOR:PRODUCT:REVISION:SERIAL, each decimal or 0x hex.
impl std::str::FromStr for Identity {
    type Err = String;

    fn from_str(s: &str) -> Result<Identity, String> {
        let parts: Vec<&str> = s.split(':').collect();
        let [vendor, product, revision, serial] = parts[..] else {
            return Err(format!("'{s}' is not an LSS identity: use VENDOR:PRODUCT:REVISION:SERIAL, e.g. 0x40:0x43787800:0x312E3031:0x09501234"));
        };
        let number = |p: &str| {
            crate::number::parse_number(p)
                .ok_or_else(|| format!("'{p}' in '{s}' is not a 32-bit number (decimal, or hex with 0x)"))
        };
        Ok(Identity {
            vendor: number(vendor)?,
            product: number(product)?,
            revision: number(revision)?,
            serial: number(serial)?,
        })
    }
}

/// CiA 305 table of bit timings (selector 0): index → bit rate in kbit/s.
pub const BIT_TIMINGS: [(u8, Option<u32>); 10] = [
    (0, Some(1000)),
    (1, Some(800)),
    (2, Some(500)),
    (3, Some(250)),
    (4, Some(125)),
    (5, None), // reserved
    (6, Some(50)),
    (7, Some(20)),
    (8, Some(10)),
    (9, None), // automatic bit rate detection
];
/// The CiA 305 bit timing index of automatic bit rate detection.
pub const AUTO_BIT_RATE: u8 = 9;

/// `500k`, `1M`, `125000`, `auto` → CiA 305 table index.
pub fn parse_bit_rate(text: &str) -> Result<u8, String> {
    let t = text.trim().to_ascii_lowercase();
    if t == "auto" {
        return Ok(AUTO_BIT_RATE);
    }
    let kbit = if let Some(k) = t.strip_suffix('k') {
        k.parse::<f64>().ok()
    } else if let Some(m) = t.strip_suffix('m') {
        m.parse::<f64>().ok().map(|m| m * 1000.0)
    } else {
        t.parse::<f64>().ok().map(|b| b / 1000.0)
    };
    let valid = "1M 800k 500k 250k 125k 50k 20k 10k or auto (CiA 305 has no entry for 100k)";
    let kbit = kbit.ok_or_else(|| format!("'{text}' is not a bit rate: use {valid}"))?;
    BIT_TIMINGS
        .iter()
        .find(|(_, k)| k.is_some_and(|k| k as f64 == kbit))
        .map(|(i, _)| *i)
        .ok_or_else(|| format!("{text} is not in the CiA 305 bit timing table: use {valid}"))
}

/// A CiA 305 bit timing index as people say it ("500k", "auto"), or the index itself.
pub fn bit_rate_name(index: u8) -> String {
    match BIT_TIMINGS.get(index as usize) {
        Some((_, Some(k))) if *k >= 1000 => format!("{}M", k / 1000),
        Some((_, Some(k))) => format!("{k}k"),
        Some((AUTO_BIT_RATE, None)) => "auto".into(),
        _ => format!("reserved ({index})"),
    }
}

/// Which identity part an inquiry asks for, or the node-id; its value is its command
/// specifier.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum Inquiry {
    /// The vendor-id.
    Vendor = 0x5A,
    /// The product code.
    Product,
    /// The revision number.
    Revision,
    /// The serial number.
    Serial,
    /// The active node-id.
    NodeId,
}

impl Inquiry {
    pub(super) fn cs(self) -> u8 {
        self as u8
    }

    /// The inquiry of command specifier `cs` (0x5A..0x5E).
    fn of(cs: u8) -> Option<Inquiry> {
        use Inquiry::*;
        [Vendor, Product, Revision, Serial, NodeId].get(usize::from(cs.wrapping_sub(0x5A))).copied()
    }
}

/// A master request.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Request {
    /// Switch every device to configuration state, or back to waiting.
    SwitchGlobal {
        /// True: to configuration state.
        configuration: bool,
    },
    /// Part 0..3 of the identity: vendor, product, revision, serial.
    SwitchSelective {
        /// Which part.
        part: u8,
        /// Its value.
        value: u32,
    },
    /// Give the device in configuration state this node-id.
    ConfigureNodeId(u8),
    /// Set the bit rate the device takes at the next activation.
    ConfigureBitTiming {
        /// The bit timing table (0: CiA 301's).
        table: u8,
        /// The entry in it (0 = 1 Mbit/s .. 8 = 10 kbit/s).
        index: u8,
    },
    /// Switch every device to the configured bit rate after a delay.
    ActivateBitTiming {
        /// How long to stay silent before and after the switch.
        delay_ms: u16,
    },
    /// Store the configured node-id and bit rate in the device.
    StoreConfiguration,
    /// Ask the device in configuration state for an identity part or its node-id.
    Inquire(Inquiry),
    /// 0x46..0x4B: vendor, product, revision low/high, serial low/high.
    IdentifyRemote {
        /// Which field (0x46..0x4B).
        field: u8,
        /// Its value (for revision and serial, a bound of the range).
        value: u32,
    },
    /// Ask devices without a node-id to say so.
    IdentifyNonConfigured,
    /// One fastscan request.
    Fastscan {
        /// The identity bits asked for.
        id: u32,
        /// The lowest bit compared (31..0), or 0x80 to reset the search.
        bit_checked: u8,
        /// The identity part being searched.
        sub: u8,
        /// The part to search after this one.
        next: u8,
    },
}

/// Fastscan's "bit checked" value that restarts the search.
pub const FASTSCAN_RESET: u8 = 0x80;

impl Request {
    /// The request's 8 data bytes.
    pub fn encode(&self) -> [u8; 8] {
        match *self {
            Request::SwitchGlobal { configuration } => command(0x04, &[configuration as u8]),
            Request::SwitchSelective { part, value } => command(0x40 + part, &value.to_le_bytes()),
            Request::ConfigureNodeId(id) => command(0x11, &[id]),
            Request::ConfigureBitTiming { table, index } => command(0x13, &[table, index]),
            Request::ActivateBitTiming { delay_ms } => command(0x15, &delay_ms.to_le_bytes()),
            Request::StoreConfiguration => command(0x17, &[]),
            Request::Inquire(q) => command(q.cs(), &[]),
            Request::IdentifyRemote { field, value } => command(field, &value.to_le_bytes()),
            Request::IdentifyNonConfigured => command(0x4C, &[]),
            Request::Fastscan { id, bit_checked, sub, next } => {
                let [a, b, c, d] = id.to_le_bytes();
                command(0x51, &[a, b, c, d, bit_checked, sub, next])
            }
        }
    }

    /// The request in these data bytes; `None` for one not known.
    pub fn decode(d: &[u8]) -> Option<Request> {
        let d: &[u8; 8] = d.try_into().ok()?;
        let v = u32::from_le_bytes([d[1], d[2], d[3], d[4]]);
        Some(match d[0] {
            0x04 if d[1] <= 1 => Request::SwitchGlobal { configuration: d[1] == 1 },
            0x40..=0x43 => Request::SwitchSelective { part: d[0] - 0x40, value: v },
            0x11 => Request::ConfigureNodeId(d[1]),
            0x13 => Request::ConfigureBitTiming { table: d[1], index: d[2] },
            0x15 => Request::ActivateBitTiming { delay_ms: u16::from_le_bytes([d[1], d[2]]) },
            0x17 => Request::StoreConfiguration,
            cs @ 0x5A..=0x5E => Request::Inquire(Inquiry::of(cs)?),
            0x46..=0x4B => Request::IdentifyRemote { field: d[0], value: v },
            0x4C => Request::IdentifyNonConfigured,
            0x51 => Request::Fastscan { id: v, bit_checked: d[5], sub: d[6], next: d[7] },
            _ => return None,
        })
    }
}

/// A slave answer.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Response {
    /// The selected device is now in configuration state.
    SwitchSelectiveAck,
    /// Answer to configure node-id (0x11), configure bit timing (0x13) or store (0x17):
    /// the command, its error code and the implementation-specific code.
    Result {
        /// The command specifier answered.
        cs: u8,
        /// 0: done; else refused.
        error: u8,
        /// The implementation-specific code, when `error` is 255.
        specific: u8,
    },
    /// An inquiry's answer.
    InquiredValue {
        /// What was asked.
        inquiry: Inquiry,
        /// The value.
        value: u32,
    },
    /// A device inside the range of an identify-remote request (or a fastscan match).
    IdentifySlave,
    /// A device without a node-id.
    IdentifyNonConfiguredSlave,
}

impl Response {
    /// The answer's 8 data bytes.
    pub fn encode(&self) -> [u8; 8] {
        match *self {
            Response::SwitchSelectiveAck => command(0x44, &[]),
            Response::Result { cs, error, specific } => command(cs, &[error, specific]),
            Response::InquiredValue { inquiry: Inquiry::NodeId, value } => command(0x5E, &[value as u8]),
            Response::InquiredValue { inquiry, value } => command(inquiry.cs(), &value.to_le_bytes()),
            Response::IdentifySlave => command(0x4F, &[]),
            Response::IdentifyNonConfiguredSlave => command(0x50, &[]),
        }
    }

    /// The answer in these data bytes; `None` for one not known.
    pub fn decode(d: &[u8]) -> Option<Response> {
        let d: &[u8; 8] = d.try_into().ok()?;
        let v = u32::from_le_bytes([d[1], d[2], d[3], d[4]]);
        Some(match d[0] {
            0x44 => Response::SwitchSelectiveAck,
            cs @ (0x11 | 0x13 | 0x17) => Response::Result { cs, error: d[1], specific: d[2] },
            0x5E => Response::InquiredValue { inquiry: Inquiry::NodeId, value: d[1] as u32 },
            cs @ 0x5A..=0x5D => Response::InquiredValue { inquiry: Inquiry::of(cs)?, value: v },
            0x4F => Response::IdentifySlave,
            0x50 => Response::IdentifyNonConfiguredSlave,
            _ => return None,
        })
    }
}

/// The meaning of an error code in the answer to command `cs` (CiA 305; seed 001 §10.1).
pub fn error_meaning(cs: u8, error: u8) -> &'static str {
    match (cs, error) {
        (_, 0) => "protocol successfully completed",
        (0x11, 1) => "node-id out of range",
        (0x13, 1) => "bit timing not supported",
        (0x17, 1) => "store configuration not supported",
        (0x17, 2) => "storage media access error",
        (_, 255) => "implementation-specific error (see the specific code)",
        _ => "reserved error code",
    }
}

impl Request {
    /// The command specifier of the slave answer this request expects, if it has one:
    /// only a frame with it counts as an answer (a heartbeat or a stray frame on 0x7E4
    /// does not).
    pub fn expected_answer(&self) -> Option<u8> {
        match *self {
            Request::SwitchSelective { part: 3, .. } => Some(0x44),
            Request::ConfigureNodeId(_) => Some(0x11),
            Request::ConfigureBitTiming { .. } => Some(0x13),
            Request::StoreConfiguration => Some(0x17),
            Request::Inquire(q) => Some(q.cs()),
            Request::IdentifyRemote { field: 0x4B, .. } | Request::Fastscan { .. } => Some(0x4F),
            Request::IdentifyNonConfigured => Some(0x50),
            _ => None,
        }
    }
}

/// Whether `data` (a frame on 0x7E4) is a well-formed slave answer with command specifier
/// `expect`: 8 bytes, that specifier, and for the answers that carry nothing but it
/// (0x44, 0x4F, 0x50) the reserved bytes 0, so that a babbling device's counter on 0x7E4
/// does not pass for a device.
pub fn is_answer(data: &[u8], expect: u8) -> bool {
    data.len() == 8 && data[0] == expect && (!matches!(expect, 0x44 | 0x4F | 0x50) || data[1..] == [0; 7])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sensor() -> Identity {
        // Seed 001 table 5, with the serial of figure 10's example.
        Identity { vendor: 0x40, product: 0x4378_7800, revision: 0x312E_3031, serial: 0x0950_1234 }
    }

    #[test]
    fn every_request_round_trips() {
        let all = [
            Request::SwitchGlobal { configuration: false },
            Request::SwitchSelective { part: 3, value: 7 },
            Request::ConfigureNodeId(255),
            Request::ConfigureBitTiming { table: 0, index: 8 },
            Request::ActivateBitTiming { delay_ms: 1000 },
            Request::StoreConfiguration,
            Request::Inquire(Inquiry::Vendor),
            Request::Inquire(Inquiry::NodeId),
            Request::IdentifyRemote { field: 0x4B, value: 9 },
            Request::IdentifyNonConfigured,
            Request::Fastscan { id: 0x1234, bit_checked: 7, sub: 2, next: 3 },
        ];
        for r in all {
            assert_eq!(Request::decode(&r.encode()), Some(r));
        }
        let answers = [
            Response::SwitchSelectiveAck,
            Response::Result { cs: 0x13, error: 1, specific: 0 },
            Response::InquiredValue { inquiry: Inquiry::Serial, value: 0xDEAD_BEEF },
            Response::InquiredValue { inquiry: Inquiry::NodeId, value: 5 },
            Response::IdentifySlave,
            Response::IdentifyNonConfiguredSlave,
        ];
        for a in answers {
            assert_eq!(Response::decode(&a.encode()), Some(a));
        }
    }

    #[test]
    fn bit_rates() {
        assert_eq!(parse_bit_rate("500k"), Ok(2));
        assert_eq!(parse_bit_rate("1M"), Ok(0));
        assert_eq!(parse_bit_rate("125000"), Ok(4));
        assert_eq!(parse_bit_rate("auto"), Ok(9));
        assert!(parse_bit_rate("100k").unwrap_err().contains("no entry for 100k"));
        assert!(parse_bit_rate("fast").is_err());
        assert_eq!(bit_rate_name(0), "1M");
        assert_eq!(bit_rate_name(3), "250k");
        assert_eq!(bit_rate_name(5), "reserved (5)");
    }

    #[test]
    fn identities_parse() {
        let id: Identity = "0x40:0x43787800:0x312E3031:0x09501234".parse().unwrap();
        assert_eq!(id, sensor());
        assert_eq!(id.to_string(), "0x00000040:0x43787800:0x312E3031:0x09501234");
        assert_eq!("64:1:2:3".parse::<Identity>().unwrap().vendor, 64);
        assert!("1:2:3".parse::<Identity>().is_err());
        assert!("1:2:3:x".parse::<Identity>().is_err());
    }

    #[test]
    fn only_well_formed_answers_count() {
        assert!(is_answer(&[0x4F, 0, 0, 0, 0, 0, 0, 0], 0x4F));
        assert!(!is_answer(&[0x4F, 0, 0, 0, 0, 0, 0], 0x4F), "7 bytes");
        assert!(!is_answer(&[0x4F, 1, 1, 0, 0, 0, 0, 0], 0x4F), "a babbler's counter");
        assert!(!is_answer(&[0x50, 0, 0, 0, 0, 0, 0, 0], 0x4F), "another service's answer");
        assert!(!is_answer(&[0x7F], 0x4F), "a heartbeat-like frame");
        assert!(is_answer(&[0x5A, 0x40, 0, 0, 0, 0, 0, 0], 0x5A), "inquiry answers carry a value");
        assert!(is_answer(&[0x11, 1, 0, 0, 0, 0, 0, 0], 0x11), "results carry an error code");
    }

    #[test]
    fn expected_answers() {
        assert_eq!(Request::Fastscan { id: 0, bit_checked: 0x80, sub: 0, next: 0 }.expected_answer(), Some(0x4F));
        assert_eq!(Request::IdentifyNonConfigured.expected_answer(), Some(0x50));
        assert_eq!(Request::SwitchSelective { part: 3, value: 1 }.expected_answer(), Some(0x44));
        assert_eq!(Request::SwitchSelective { part: 2, value: 1 }.expected_answer(), None);
        assert_eq!(Request::Inquire(Inquiry::NodeId).expected_answer(), Some(0x5E));
        assert_eq!(Request::SwitchGlobal { configuration: false }.expected_answer(), None);
    }
}
