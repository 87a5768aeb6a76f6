//! Emergency messages (CiA 301 §7.2.7): 0x080 + node, error code, error register,
//! five manufacturer bytes.

use crate::frame::Frame;

pub fn cob(node: u8) -> u16 {
    0x080 + node as u16
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Emergency {
    pub code: u16,
    pub register: u8,
    pub vendor: [u8; 5],
}

impl Emergency {
    /// Node and message, if `frame` is an EMCY on the default COB-IDs. A zero-length frame
    /// on 0x80+node is the old "EMCY at power on" some drives send (seed 003): no EMCY.
    pub fn parse(frame: &Frame) -> Option<(u8, Emergency)> {
        let node = frame.id().checked_sub(0x080).filter(|n| (1..=127).contains(n))? as u8;
        let d = frame.data();
        if frame.is_remote() || d.len() != 8 {
            return None;
        }
        let mut vendor = [0u8; 5];
        vendor.copy_from_slice(&d[3..8]);
        Some((node, Emergency { code: u16::from_le_bytes([d[0], d[1]]), register: d[2], vendor }))
    }

    pub fn frame(&self, node: u8) -> Frame {
        let [lo, hi] = self.code.to_le_bytes();
        let mut d = [lo, hi, self.register, 0, 0, 0, 0, 0];
        d[3..].copy_from_slice(&self.vendor);
        Frame::new(cob(node), &d)
    }

    /// The 0x1003 history entry: error code in the low word, vendor bytes 0..2 high.
    pub fn history_entry(&self) -> u32 {
        self.code as u32 | (u16::from_le_bytes([self.vendor[0], self.vendor[1]]) as u32) << 16
    }
}

/// CiA 301 table 21 (error code classes) with the CiA 402 codes seed 003 lists.
pub fn code_meaning(code: u16) -> &'static str {
    const EXACT: &[(u16, &str)] = &[
        (0x0000, "Error reset or no error"),
        (0x1000, "Generic error"),
        (0x5000, "Device hardware"),
        (0x6100, "Internal software"),
        (0x8100, "Communication"),
        (0x8110, "CAN overrun (objects lost)"),
        (0x8120, "CAN in error passive mode"),
        (0x8130, "Life guard error or heartbeat error"),
        (0x8140, "Recovered from bus off"),
        (0x8150, "CAN-ID collision"),
        (0x8210, "PDO not processed due to length error"),
        (0x8220, "PDO length exceeded"),
        (0x8240, "Unexpected SYNC data length"),
        (0x8250, "RPDO timeout"),
        (0xFF00, "Device specific"),
    ];
    if let Some((_, m)) = EXACT.iter().find(|(c, _)| *c == code) {
        return m;
    }
    match code >> 8 {
        0x10 => "Generic error",
        0x20..=0x2F => "Current",
        0x30..=0x3F => "Voltage",
        0x40..=0x4F => "Temperature",
        0x50..=0x5F => "Device hardware",
        0x60..=0x6F => "Device software",
        0x70..=0x7F => "Additional modules",
        0x80 => "Monitoring",
        0x81 => "Communication",
        0x82 => "Protocol error",
        0x83..=0x8F => "Monitoring",
        0x90..=0x9F => "External error",
        0xF0 => "Additional functions",
        0xFF => "Device specific",
        _ => "Unknown error code class",
    }
}

/// Names of the error register (0x1001) bits that are set.
pub fn register_bits(register: u8) -> Vec<&'static str> {
    const BITS: [&str; 8] =
        ["generic", "current", "voltage", "temperature", "communication", "device profile", "reserved", "manufacturer"];
    (0..8).filter(|b| register & (1 << b) != 0).map(|b| BITS[b]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_004_emcy_table() {
        // The seed's table row "81 10 | 11 | 06 00 00 00 00  CAN Controller Overrun" lists
        // the code high byte first; on the wire it is little-endian.
        let f: Frame = "08A#1081110600000000".parse().unwrap();
        let (node, e) = Emergency::parse(&f).unwrap();
        assert_eq!(node, 10);
        assert_eq!(e.code, 0x8110);
        assert_eq!(code_meaning(e.code), "CAN overrun (objects lost)");
        assert_eq!(register_bits(e.register), vec!["generic", "communication"]);
        assert_eq!(e.frame(10), f);
        assert_eq!(code_meaning(0x2310), "Current");
        assert!(Emergency::parse(&"085#".parse().unwrap()).is_none());
    }
}
