//! maxon EPOS2 serial protocol (seeds 000 and 002): frames, commands and transports. The
//! gateway that offers the `Bus` services through them is [`crate::backend::epos2`].

pub mod command;
pub mod error;
pub mod frame;
pub mod objects;
pub mod transport;

pub use error::{Epos2Error, Epos2Problem};

/// The two ways an EPOS2 frames its serial protocol.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Framing {
    /// RS232: OpCode, Len-1, words, CRC, with the 'O'/'F' handshake (seed 000 §5).
    Rs232,
    /// USB: DLE STX, OpCode, Len, words, CRC, DLE-stuffed, no handshake (seed 000 §4).
    Usb,
}

impl Framing {
    /// The bus URI scheme.
    pub fn scheme(self) -> &'static str {
        match self {
            Framing::Rs232 => "epos2-rs232",
            Framing::Usb => "epos2-usb",
        }
    }
}
