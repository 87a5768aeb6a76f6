//! CiA 302-3 program download: the objects a bootloader offers, the program control
//! commands, what the flash status says, and the identification a device gives its
//! program (the CRC-32 of the image, as Zephyr's CANopen bootloader does). Pure.

use super::ObjAddr;

/// Program data (domain, write only): the image is written to sub N for program N.
pub const PROGRAM_DATA: u16 = 0x1F50;
/// Program control (u8): a command when written, the program's state when read.
pub const PROGRAM_CONTROL: u16 = 0x1F51;
/// Program software identification (u32): the CRC-32 of the program that will run.
pub const SOFTWARE_ID: u16 = 0x1F56;
/// Flash status identification (u32): bit 0 busy, bits 1..7 an error code.
pub const FLASH_STATUS: u16 = 0x1F57;

/// One of the objects above for program `n`.
pub fn object(index: u16, program: u8) -> ObjAddr {
    ObjAddr::new(index, program)
}

/// A program control command (written to 0x1F51:N) or state (read from it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Control {
    /// Stop the program: the device stays in its bootloader.
    Stop,
    /// Start the program.
    Start,
    /// Resets the flash status (CiA 302-3 "reset").
    Reset,
    /// Erases the program's flash area.
    Clear,
    /// Zephyr's extension: a new program that runs on trial asks to be kept; writing it
    /// makes the program permanent (else the bootloader reverts at the next reset).
    Confirm,
    /// A value CiA 302-3 does not define.
    Other(u8),
}

/// The commands and states CiA 302-3 defines: their value in 0x1F51, and what reading it
/// says about the program.
const CONTROLS: [(Control, u8, &str); 5] = [
    (Control::Stop, 0, "stopped (in the bootloader)"),
    (Control::Start, 1, "started (the program runs)"),
    (Control::Reset, 2, "reset"),
    (Control::Clear, 3, "cleared (no program)"),
    (Control::Confirm, 0x80, "started on trial, waiting for confirmation (0x80)"),
];

impl Control {
    /// The value written to or read from 0x1F51.
    pub fn code(self) -> u8 {
        match self {
            Control::Other(v) => v,
            known => CONTROLS.iter().find(|c| c.0 == known).map_or(0, |c| c.1),
        }
    }

    /// The command or state a value of 0x1F51 codes.
    pub fn from_code(v: u8) -> Control {
        CONTROLS.iter().find(|c| c.1 == v).map_or(Control::Other(v), |c| c.0)
    }

    /// What reading this state from 0x1F51 says about the program.
    pub fn state_meaning(self) -> &'static str {
        CONTROLS.iter().find(|c| c.0 == self).map_or("a state CiA 302-3 does not define", |c| c.2)
    }
}

/// Bit 0 of the flash status: the device is still erasing or writing.
pub const BUSY: u32 = 1;

/// The error codes of bits 1..7 of the flash status (CiA 302-3 table, as Zephyr's
/// bootloader uses them).
pub mod code {
    /// No error.
    pub const OK: u8 = 0;
    /// No valid program.
    pub const NO_VALID_PROGRAM: u8 = 1;
    pub(crate) const DATA_FORMAT_UNKNOWN: u8 = 2;
    pub(crate) const DATA_FORMAT_ERROR: u8 = 3;
    pub(crate) const FLASH_NOT_CLEARED: u8 = 4;
    /// Writing the flash failed.
    pub const FLASH_WRITE_ERROR: u8 = 5;
    pub(crate) const GENERAL_ADDRESS_ERROR: u8 = 6;
    pub(crate) const FLASH_SECURED: u8 = 7;
    pub(crate) const UNSPECIFIED: u8 = 63;
}

/// A flash status value, decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct FlashStatus {
    /// The value as read from 0x1F57.
    pub raw: u32,
    /// Bit 0: still erasing or writing.
    pub busy: bool,
    /// Bits 1..7.
    pub code: u8,
}

impl FlashStatus {
    /// The status in a 0x1F57 value.
    pub fn decode(raw: u32) -> FlashStatus {
        FlashStatus { raw, busy: raw & BUSY != 0, code: ((raw >> 1) & 0x7F) as u8 }
    }

    /// The raw value for `code`, busy or not.
    pub fn encode(code: u8, busy: bool) -> u32 {
        (u32::from(code & 0x7F) << 1) | u32::from(busy)
    }

    /// Whether the status reports an error.
    pub fn is_error(&self) -> bool {
        self.code != code::OK
    }

    /// The meaning of the error code, in words.
    pub fn meaning(&self) -> &'static str {
        match self.code {
            code::OK => "no error",
            code::NO_VALID_PROGRAM => "no valid program",
            code::DATA_FORMAT_UNKNOWN => "data format unknown",
            code::DATA_FORMAT_ERROR => "data format error or data CRC error",
            code::FLASH_NOT_CLEARED => "flash not cleared before write",
            code::FLASH_WRITE_ERROR => "flash write error",
            code::GENERAL_ADDRESS_ERROR => "general address error",
            code::FLASH_SECURED => "flash secured (write access denied)",
            code::UNSPECIFIED => "unspecified error",
            8..=62 => "reserved error code",
            _ => "manufacturer-specific error",
        }
    }
}

impl std::fmt::Display for FlashStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}{}", self.meaning(), if self.busy { ", busy" } else { "" })
    }
}

/// The identification a bootloader gives an image: its CRC-32 (ISO-HDLC, as zlib's).
pub fn image_id(image: &[u8]) -> u32 {
    crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC).checksum(image)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flash_status_bits_decode_to_their_meanings() {
        let s = FlashStatus::decode(0x0000_0001);
        assert!(s.busy && !s.is_error());
        assert_eq!(s.to_string(), "no error, busy");
        let s = FlashStatus::decode(0x0000_000A);
        assert_eq!((s.busy, s.code), (false, code::FLASH_WRITE_ERROR));
        assert_eq!(s.meaning(), "flash write error");
        assert_eq!(FlashStatus::decode(0x0000_0002).meaning(), "no valid program");
        assert_eq!(FlashStatus::decode(0x7E).meaning(), "unspecified error");
        assert_eq!(FlashStatus::decode(0x80).code, 64);
        assert_eq!(FlashStatus::decode(0x80).meaning(), "manufacturer-specific error");
        assert_eq!(FlashStatus::encode(code::FLASH_WRITE_ERROR, false), 0x0A);
        assert_eq!(FlashStatus::encode(code::OK, true), 1);
    }

    #[test]
    fn control_codes_round_trip() {
        for v in [0u8, 1, 2, 3, 0x80, 0x42] {
            assert_eq!(Control::from_code(v).code(), v);
        }
        assert_eq!(Control::from_code(0x80), Control::Confirm);
    }

    #[test]
    fn the_identification_is_zlibs_crc32() {
        // The CRC-32 check value of "123456789".
        assert_eq!(image_id(b"123456789"), 0xCBF4_3926);
        assert_eq!(object(PROGRAM_DATA, 1), ObjAddr::new(0x1F50, 1));
    }
}
