//! Object addresses (`index:sub`) as users write them.

use std::fmt;

/// An object dictionary address.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct ObjAddr {
    /// The object's index, 0x1000 for the device type.
    pub index: u16,
    /// The sub-index within the object; 0 for a variable.
    pub sub: u8,
}

/// The CiA 301 objects canctl reads by name, each named once for every command.
impl ObjAddr {
    /// 0x1000: the device type (profile and its additional information).
    pub const DEVICE_TYPE: ObjAddr = ObjAddr::new(0x1000, 0);
    /// 0x1001: the error register.
    pub const ERROR_REGISTER: ObjAddr = ObjAddr::new(0x1001, 0);
    /// 0x1008: the manufacturer's device name.
    pub const DEVICE_NAME: ObjAddr = ObjAddr::new(0x1008, 0);
    /// 0x1010:1: store all parameters.
    pub const STORE_ALL: ObjAddr = ObjAddr::new(0x1010, 1);
    /// 0x1014: the COB-ID of the node's EMCY.
    pub const EMCY_COB_ID: ObjAddr = ObjAddr::new(0x1014, 0);
    /// 0x1017: the producer heartbeat time (ms).
    pub const HEARTBEAT_TIME: ObjAddr = ObjAddr::new(0x1017, 0);
    /// 0x1018:0: how many entries the identity object has.
    pub const IDENTITY: ObjAddr = ObjAddr::new(0x1018, 0);
    /// 0x1018:1: the vendor-ID.
    pub const VENDOR_ID: ObjAddr = ObjAddr::new(0x1018, 1);
    /// 0x1018:2: the product code.
    pub const PRODUCT_CODE: ObjAddr = ObjAddr::new(0x1018, 2);
    /// 0x1018:3: the revision number.
    pub const REVISION_NUMBER: ObjAddr = ObjAddr::new(0x1018, 3);
    /// 0x1018:4: the serial number.
    pub const SERIAL_NUMBER: ObjAddr = ObjAddr::new(0x1018, 4);
    /// 0x1018:1 to 4 in the order of an LSS address (`lss::Identity::part`): the objects
    /// code that reads or builds a whole identity walks, instead of `ObjAddr::new(0x1018, sub)`.
    pub const IDENTITY_PARTS: [ObjAddr; 4] =
        [ObjAddr::VENDOR_ID, ObjAddr::PRODUCT_CODE, ObjAddr::REVISION_NUMBER, ObjAddr::SERIAL_NUMBER];
}

impl ObjAddr {
    /// The address of sub-index `sub` of object `index`; `const` so tables can name objects.
    pub const fn new(index: u16, sub: u8) -> ObjAddr {
        ObjAddr { index, sub }
    }

    /// Index and subindex as they travel in SDO frames (bytes 1..4, index little-endian).
    pub(crate) fn to_mux(self) -> [u8; 3] {
        let [lo, hi] = self.index.to_le_bytes();
        [lo, hi, self.sub]
    }

    pub(crate) fn from_mux(b: &[u8]) -> ObjAddr {
        ObjAddr::new(u16::from_le_bytes([b[0], b[1]]), b[2])
    }
}

/// `0x1018:1` — the canonical spelling used in all output.
impl fmt::Display for ObjAddr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "0x{:04X}:{}", self.index, self.sub)
    }
}

/// Accepts `0x1018:1`, `1018:1`, `1018sub1`, `1018` (sub 0), `1018:0x01`.
/// The index is always hex; the subindex is decimal unless written with `0x`.
impl std::str::FromStr for ObjAddr {
    type Err = String;

    fn from_str(text: &str) -> Result<ObjAddr, String> {
        let s = text.trim();
        let lower = s.to_ascii_lowercase();
        let (index, sub) = match lower.split_once(':').or_else(|| lower.split_once("sub")) {
            Some((i, s)) => (i, Some(s)),
            None => (lower.as_str(), None),
        };
        let digits = index.strip_prefix("0x").unwrap_or(index);
        if digits.is_empty() || digits.len() > 4 || !digits.chars().all(|c| c.is_ascii_hexdigit()) {
            return Err(format!(
                "'{text}' is not an object address: the index is 1 to 4 hex digits, as in 0x1018:1, 1018:1 or 1018sub1"
            ));
        }
        let index = u16::from_str_radix(digits, 16).expect("checked hex digits");
        let sub = match sub {
            None => 0,
            Some(sub) => super::number::parse_number::<u8>(sub).ok_or_else(|| {
                format!("'{text}': subindex '{sub}' must be 0..255 (decimal, or hex with 0x, as in 1018:0x01)")
            })?,
        };
        Ok(ObjAddr::new(index, sub))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spellings() {
        let want = ObjAddr::new(0x1018, 1);
        for s in ["0x1018:1", "1018:1", "1018sub1", "0X1018SUB1", "1018:0x01", " 1018:01 "] {
            assert_eq!(s.parse::<ObjAddr>().unwrap(), want, "{s}");
        }
        assert_eq!("1000".parse::<ObjAddr>().unwrap(), ObjAddr::new(0x1000, 0));
        assert_eq!("1a00:10".parse::<ObjAddr>().unwrap(), ObjAddr::new(0x1A00, 10));
        assert_eq!(ObjAddr::new(0x1A00, 10).to_string(), "0x1A00:10");
    }

    #[test]
    fn pointed_errors() {
        assert!("10180:1".parse::<ObjAddr>().unwrap_err().contains("1 to 4 hex digits"));
        assert!("zz:1".parse::<ObjAddr>().is_err());
        assert!(":1".parse::<ObjAddr>().is_err());
        assert!("1018:256".parse::<ObjAddr>().unwrap_err().contains("0..255"));
        assert!("1018:x".parse::<ObjAddr>().is_err());
        assert!("1018:".parse::<ObjAddr>().is_err());
    }

    #[test]
    fn mux_is_little_endian() {
        let a = ObjAddr::new(0x1018, 2);
        assert_eq!(a.to_mux(), [0x18, 0x10, 0x02]);
        assert_eq!(ObjAddr::from_mux(&a.to_mux()), a);
    }
}
