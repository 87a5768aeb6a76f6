//! SDO abort codes (CiA 301 table 22; the same list appears in seeds 000, 001 and 003).

/// Toggle bit not alternated.
pub(crate) const TOGGLE_BIT: u32 = 0x0503_0000;
/// SDO protocol timed out (the client gave up waiting).
pub const TIMED_OUT: u32 = 0x0504_0000;
/// Client/server command specifier not valid or unknown.
pub const UNKNOWN_COMMAND: u32 = 0x0504_0001;
/// Invalid block size (block mode only).
pub(crate) const INVALID_BLOCK_SIZE: u32 = 0x0504_0002;
/// Invalid sequence number (block transfer).
pub const INVALID_SEQUENCE: u32 = 0x0504_0003;
/// CRC error (block mode only).
pub const CRC_ERROR: u32 = 0x0504_0004;
/// Out of memory: the server cannot take a transfer that large.
pub const OUT_OF_MEMORY: u32 = 0x0504_0005;
/// Unsupported access to an object.
pub(crate) const UNSUPPORTED_ACCESS: u32 = 0x0601_0000;
/// Attempt to read a write only object.
pub const WRITE_ONLY: u32 = 0x0601_0001;
/// Attempt to write a read-only object.
pub const READ_ONLY: u32 = 0x0601_0002;
/// The object does not exist in the object dictionary.
pub const NO_OBJECT: u32 = 0x0602_0000;
/// Data type does not match, length of service parameter does not match.
pub(crate) const LENGTH_MISMATCH: u32 = 0x0607_0010;
/// Data type does not match, length of service parameter too high.
pub const LENGTH_TOO_HIGH: u32 = 0x0607_0012;
/// Data type does not match, length of service parameter too low.
pub const LENGTH_TOO_LOW: u32 = 0x0607_0013;
/// Sub-index does not exist.
pub const NO_SUBINDEX: u32 = 0x0609_0011;
/// Invalid value for parameter (download only).
pub const INVALID_VALUE: u32 = 0x0609_0030;
/// Value of parameter written too high (download only).
pub const VALUE_TOO_HIGH: u32 = 0x0609_0031;
/// Value of parameter written too low (download only).
pub const VALUE_TOO_LOW: u32 = 0x0609_0032;
/// General error.
pub const GENERAL_ERROR: u32 = 0x0800_0000;
/// Data cannot be transferred or stored to the application.
pub const CANNOT_STORE: u32 = 0x0800_0020;
/// Data cannot be transferred or stored to the application because of the present device state.
pub const WRONG_STATE: u32 = 0x0800_0022;

const TABLE: &[(u32, &str)] = &[
    (TOGGLE_BIT, "Toggle bit not alternated"),
    (TIMED_OUT, "SDO protocol timed out"),
    (UNKNOWN_COMMAND, "Client/server command specifier not valid or unknown"),
    (INVALID_BLOCK_SIZE, "Invalid block size (block mode only)"),
    (INVALID_SEQUENCE, "Invalid sequence number (block mode only)"),
    (CRC_ERROR, "CRC error (block mode only)"),
    (OUT_OF_MEMORY, "Out of memory"),
    (UNSUPPORTED_ACCESS, "Unsupported access to an object"),
    (WRITE_ONLY, "Attempt to read a write only object"),
    (READ_ONLY, "Attempt to write a read only object"),
    (NO_OBJECT, "Object does not exist in the object dictionary"),
    (0x0604_0041, "Object cannot be mapped to the PDO"),
    (0x0604_0042, "The number and length of the objects to be mapped would exceed PDO length"),
    (0x0604_0043, "General parameter incompatibility reason"),
    (0x0604_0047, "General internal incompatibility in the device"),
    (0x0606_0000, "Access failed due to a hardware error"),
    (LENGTH_MISMATCH, "Data type does not match, length of service parameter does not match"),
    (LENGTH_TOO_HIGH, "Data type does not match, length of service parameter too high"),
    (LENGTH_TOO_LOW, "Data type does not match, length of service parameter too low"),
    (NO_SUBINDEX, "Sub-index does not exist"),
    (INVALID_VALUE, "Invalid value for parameter (download only)"),
    (VALUE_TOO_HIGH, "Value of parameter written too high (download only)"),
    (VALUE_TOO_LOW, "Value of parameter written too low (download only)"),
    (0x0609_0036, "Maximum value is less than minimum value"),
    (0x060A_0023, "Resource not available: SDO connection"),
    (GENERAL_ERROR, "General error"),
    (CANNOT_STORE, "Data cannot be transferred or stored to the application"),
    (0x0800_0021, "Data cannot be transferred or stored to the application because of local control"),
    (WRONG_STATE, "Data cannot be transferred or stored to the application because of the present device state"),
    (0x0800_0023, "Object dictionary dynamic generation fails or no object dictionary is present"),
    (0x0800_0024, "No data available"),
];

/// The standard meaning of an abort code, or a plain statement that it is not a CiA 301 code.
pub fn meaning(code: u32) -> &'static str {
    TABLE
        .iter()
        .find(|(c, _)| *c == code)
        .map(|(_, m)| *m)
        .unwrap_or("not a CiA 301 abort code (manufacturer-specific)")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_001_table_7_codes_are_known() {
        for code in
            [0x0609_0011, 0x0609_0030, 0x0602_0000, 0x0601_0001, 0x0601_0002, 0x0800_0020, 0x0800_0000, 0x0800_0022]
        {
            assert!(!meaning(code).starts_with("not a CiA"), "{code:08X}");
        }
        assert_eq!(meaning(READ_ONLY), "Attempt to write a read only object");
        assert!(meaning(0x0F00_FFC0).contains("manufacturer"));
    }

    #[test]
    fn seed_003_list_is_complete() {
        let seed = [
            0x0503_0000,
            0x0504_0000,
            0x0504_0001,
            0x0504_0002,
            0x0504_0003,
            0x0504_0004,
            0x0504_0005,
            0x0601_0000,
            0x0601_0001,
            0x0601_0002,
            0x0602_0000,
            0x0604_0041,
            0x0604_0042,
            0x0604_0043,
            0x0604_0047,
            0x0606_0000,
            0x0607_0010,
            0x0607_0012,
            0x0607_0013,
            0x0609_0011,
            0x0609_0030,
            0x0609_0031,
            0x0609_0032,
            0x0609_0036,
            0x0800_0000,
            0x0800_0020,
            0x0800_0021,
            0x0800_0022,
            0x0800_0023,
        ];
        for code in seed {
            assert!(!meaning(code).starts_with("not a CiA"), "{code:08X}");
        }
    }
}
