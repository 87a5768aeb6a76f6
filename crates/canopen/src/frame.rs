//! A classic CAN frame with an 11-bit identifier, and the can-utils notations for it.

use std::fmt;

/// One classic CAN frame. CANopen uses 11-bit identifiers only, so that is all we model;
/// links drop extended frames before they reach protocol code.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Frame {
    id: u16,
    rtr: bool,
    len: u8,
    data: [u8; 8],
}

impl Frame {
    /// A data frame. `data` longer than 8 bytes or an id over 0x7FF is a programming error.
    pub fn new(id: u16, data: &[u8]) -> Frame {
        assert!(id <= 0x7FF, "CAN id {id:#x} is not 11-bit");
        assert!(data.len() <= 8, "CAN payload of {} bytes", data.len());
        let mut buf = [0u8; 8];
        buf[..data.len()].copy_from_slice(data);
        Frame { id, rtr: false, len: data.len() as u8, data: buf }
    }

    /// A remote (RTR) frame asking for `len` bytes.
    pub fn remote(id: u16, len: u8) -> Frame {
        assert!(id <= 0x7FF && len <= 8);
        Frame { id, rtr: true, len, data: [0; 8] }
    }

    /// The 11-bit CAN id.
    pub fn id(&self) -> u16 {
        self.id
    }
    /// A remote request (RTR)?
    pub fn is_remote(&self) -> bool {
        self.rtr
    }
    /// The data length code (of a remote request: the length asked for).
    pub fn len(&self) -> usize {
        self.len as usize
    }
    /// No data bytes?
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// The payload; empty for a remote frame.
    pub fn data(&self) -> &[u8] {
        if self.rtr {
            &[]
        } else {
            &self.data[..self.len as usize]
        }
    }

    /// One line as `candump` prints it: `  vcan0  605   [8]  40 00 10 00 00 00 00 00`.
    pub fn candump_line(&self, iface: &str) -> String {
        let tail: String =
            if self.rtr { " remote request".into() } else { self.data().iter().map(|b| format!(" {b:02X}")).collect() };
        format!("  {iface}  {:03X}   [{}] {tail}", self.id, self.len)
    }
}

/// can-utils compact notation (`cansend`): `123#DEADBEEF`, `123#R`, `123#R4`.
impl fmt::Display for Frame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.rtr, self.len) {
            (true, 0) => write!(f, "{:03X}#R", self.id),
            (true, len) => write!(f, "{:03X}#R{len}", self.id),
            (false, _) => {
                write!(f, "{:03X}#{}", self.id, self.data().iter().map(|b| format!("{b:02X}")).collect::<String>())
            }
        }
    }
}

impl fmt::Debug for Frame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

impl std::str::FromStr for Frame {
    type Err = String;

    fn from_str(s: &str) -> Result<Frame, String> {
        let (id, rest) = s
            .split_once('#')
            .ok_or_else(|| format!("'{s}' is not a frame: expected ID#DATA, e.g. 605#4000100000000000"))?;
        let id = u16::from_str_radix(id, 16)
            .ok()
            .filter(|id| *id <= 0x7FF)
            .ok_or_else(|| format!("'{id}' is not an 11-bit CAN id (hex, at most 7FF)"))?;
        if let Some(len) = rest.strip_prefix(['R', 'r']) {
            let len = if len.is_empty() {
                0
            } else {
                len.parse::<u8>()
                    .ok()
                    .filter(|l| *l <= 8)
                    .ok_or_else(|| format!("'{len}' is not an RTR length 0..8"))?
            };
            return Ok(Frame::remote(id, len));
        }
        let hex: String = rest.chars().filter(|c| *c != '.').collect();
        let data = parse_hex(&hex).map_err(|e| format!("frame data: {e}"))?;
        if data.len() > 8 {
            return Err(format!("frame data has {} bytes; classic CAN carries at most 8", data.len()));
        }
        Ok(Frame::new(id, &data))
    }
}

/// The 8 data bytes of a protocol's command frame (SDO, LSS): the command byte, `data`
/// after it, zeros to the end.
pub(crate) fn command(cs: u8, data: &[u8]) -> [u8; 8] {
    let mut f = [0u8; 8];
    f[0] = cs;
    f[1..1 + data.len()].copy_from_slice(data);
    f
}

/// Hex text to bytes: `DEADBEEF`, `de ad be ef`, `0xdeadbeef`.
pub fn parse_hex(text: &str) -> Result<Vec<u8>, String> {
    let t = text.trim();
    let t = t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")).unwrap_or(t);
    let digits: Vec<u8> = t.bytes().filter(|b| !b.is_ascii_whitespace() && *b != b'.').collect();
    if let Some(bad) = digits.iter().find(|b| !b.is_ascii_hexdigit()) {
        return Err(format!("'{text}' is not hex bytes: '{}' is not a hex digit", *bad as char));
    }
    if !digits.len().is_multiple_of(2) {
        return Err(format!("'{text}' is not hex bytes: odd number of hex digits"));
    }
    Ok(digits.chunks(2).map(|p| u8::from_str_radix(std::str::from_utf8(p).unwrap(), 16).unwrap()).collect())
}

/// The most bits a CAN 2.0A data frame with `len` data bytes occupies on the bus, stuff bits
/// at their worst: 47 + 8n + ⌊(34 + 8n − 1) / 4⌋ (135 for 8 bytes).
pub fn worst_case_bits(len: usize) -> u32 {
    let n = len.min(8) as u32;
    47 + 8 * n + (34 + 8 * n - 1) / 4
}

/// The longest an 8-byte data frame occupies a bus of `bits_per_second` (zero for zero).
pub fn longest_frame_time(bits_per_second: u64) -> std::time::Duration {
    let nanos = (u64::from(worst_case_bits(8)) * 1_000_000_000).checked_div(bits_per_second).unwrap_or(0);
    std::time::Duration::from_nanos(nanos)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compact_notation_round_trips() {
        for text in ["605#4000100000000000", "000#0105", "705#R", "185#R8", "080#"] {
            let f: Frame = text.parse().unwrap();
            assert_eq!(f.to_string(), text);
        }
        let f: Frame = "123#de.ad.be.ef".parse().unwrap();
        assert_eq!(f.data(), &[0xDE, 0xAD, 0xBE, 0xEF]);
        assert!("800#00".parse::<Frame>().is_err());
        assert!("123#001122334455667788".parse::<Frame>().is_err());
        assert!("123".parse::<Frame>().is_err());
        assert!("123#R9".parse::<Frame>().is_err());
    }

    #[test]
    fn candump_line_matches_can_utils() {
        let f = Frame::new(0x605, &[0x40, 0x00, 0x10, 0, 0, 0, 0, 0]);
        assert_eq!(f.candump_line("vcan0"), "  vcan0  605   [8]  40 00 10 00 00 00 00 00");
        assert_eq!(Frame::remote(0x705, 1).candump_line("can0"), "  can0  705   [1]  remote request");
    }

    #[test]
    fn the_longest_frame_counts_every_stuff_bit_it_can_have() {
        assert_eq!(worst_case_bits(0), 55);
        assert_eq!(worst_case_bits(8), 135);
        assert_eq!(longest_frame_time(500_000), std::time::Duration::from_micros(270));
        assert_eq!(longest_frame_time(1_000_000), std::time::Duration::from_micros(135));
        assert_eq!(longest_frame_time(0), std::time::Duration::ZERO);
    }
}
