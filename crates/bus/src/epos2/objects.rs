//! The EPOS2's own objects canctl reads and writes (EPOS2 firmware specification): its
//! node-id and CAN bit rate, read at power-on, in the EPOS2's own coding.

use crate::canopen::ObjAddr;

/// 0x2000 "Node ID".
pub const NODE_ID: ObjAddr = ObjAddr::new(0x2000, 0);
/// 0x2001 "CAN Bitrate", coded by [`bit_rate_code`].
pub const CAN_BIT_RATE: ObjAddr = ObjAddr::new(0x2001, 0);
/// 0x2001's code for "detect the bus's bit rate".
pub const BIT_RATE_DETECTED: u16 = 9;

/// 0x2001 codes and the CiA 305 bit-rate indexes they mean: 0 = 1 Mbit/s, 1 = 800 k,
/// 2 = 500 k, 3 = 250 k, 4 = 125 k, 5 = 50 k, 6 = 20 k — not the CiA 305 table (there 5 is
/// reserved, 6 = 50 k, 7 = 20 k).
const CODES: [(u8, u16); 7] = [(0, 0), (1, 1), (2, 2), (3, 3), (4, 4), (6, 5), (7, 6)];

/// The 0x2001 code of a CiA 305 bit-rate index; `None` for a rate the EPOS2 does not have.
pub fn bit_rate_code(cia_index: u8) -> Option<u16> {
    CODES.iter().find(|(c, _)| *c == cia_index).map(|(_, e)| *e)
}

/// The CiA 305 bit-rate index a 0x2001 code means; `None` for 9 (it detects the bus's
/// rate) and codes it does not have.
pub fn bit_rate_index(code: u16) -> Option<u8> {
    CODES.iter().find(|(_, e)| *e == code).map(|(c, _)| *c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_epos2_codes_are_its_own_table() {
        assert_eq!(bit_rate_index(0), Some(0)); // 1 Mbit/s
        assert_eq!(bit_rate_index(2), Some(2)); // 500 kbit/s
        assert_eq!(bit_rate_index(5), Some(6)); // 50 kbit/s, CiA 305's index 6
        assert_eq!(bit_rate_index(6), Some(7)); // 20 kbit/s
        assert_eq!(bit_rate_index(BIT_RATE_DETECTED), None);
        assert_eq!(bit_rate_code(2), Some(2));
        assert_eq!(bit_rate_code(5), None); // CiA 305's reserved index
    }
}
