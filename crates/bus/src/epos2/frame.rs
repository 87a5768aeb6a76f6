//! EPOS2 serial frames (seed 000 §4.1 USB, §5.1 RS232): parse and emit, no I/O.
//!
//! A frame is an opcode and a whole number of 16-bit words, sent low byte first. The CRC is
//! CRC-CCITT (polynomial 0x1021, initial 0) over the header word and the data words, each
//! fed high byte first — which is CRC-16/XMODEM over those bytes. The header word is
//! `OpCode<<8 | Len-1` on RS232 and `Len<<8 | OpCode` on USB. USB frames start with DLE STX
//! and double every DLE after that.

use std::fmt;

/// USB framing's escape byte (seed 000 §4.1).
pub const DLE: u8 = 0x90;
/// USB framing's start byte, after a DLE.
pub const STX: u8 = 0x02;
/// The USB Len field counts words, 0..=143 (seed 000 §4.1.2).
pub(crate) const USB_MAX_WORDS: usize = 143;
/// RS232 carries 1..=256 words (Len-1 is one byte).
pub(crate) const RS232_MAX_WORDS: usize = 256;

/// One command or answer: opcode and data bytes (always an even number).
#[derive(Clone, PartialEq, Eq)]
pub struct Frame {
    /// The command's opcode (0x00 in answers).
    pub opcode: u8,
    /// Parameter bytes, little-endian words.
    pub data: Vec<u8>,
}

impl Frame {
    /// A frame from an opcode and parameter bytes; an odd byte count is padded with zero.
    pub fn new(opcode: u8, mut data: Vec<u8>) -> Frame {
        if !data.len().is_multiple_of(2) {
            data.push(0);
        }
        Frame { opcode, data }
    }

    /// The data length in 16-bit words, as the Len fields count it.
    pub fn words(&self) -> usize {
        self.data.len() / 2
    }
}

impl fmt::Debug for Frame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "op {:02X} [{}]", self.opcode, crate::canopen::types::hex(&self.data))
    }
}

/// Why received bytes are not a frame.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FrameError {
    /// The CRC the frame carries is not that of its data: a corrupted frame.
    #[error("CRC mismatch: frame says 0x{got:04X}, data gives 0x{want:04X}")]
    Crc {
        /// The CRC in the frame.
        got: u16,
        /// The CRC of the data received.
        want: u16,
    },
    /// A length word larger than any frame (the words it claims).
    #[error("frame of {0} words is longer than the protocol allows")]
    Oversize(usize),
    /// The bytes ended inside a frame (after this many).
    #[error("frame ends after {0} bytes")]
    Truncated(usize),
    /// RS232 byte stuffing broken: this byte followed a DLE.
    #[error("byte 0x{0:02X} after DLE is neither DLE nor STX (stuffing error)")]
    Stuffing(u8),
    /// A start of frame arrived before the frame under way ended.
    #[error("a new frame started inside a frame")]
    Interrupted,
    /// A frame with no data word, which no command is.
    #[error("a frame needs at least one data word")]
    Empty,
}

/// The CRC of a frame: XMODEM over the header word and the data words, high byte first.
pub fn crc(header: u16, data: &[u8]) -> u16 {
    let engine = crc::Crc::<u16>::new(&crc::CRC_16_XMODEM);
    let mut d = engine.digest();
    d.update(&header.to_be_bytes());
    for w in data.chunks(2) {
        d.update(&[w.get(1).copied().unwrap_or(0), w[0]]);
    }
    d.finalize()
}

fn rs232_header(opcode: u8, words: usize) -> u16 {
    (opcode as u16) << 8 | (words - 1) as u16
}

fn usb_header(opcode: u8, words: usize) -> u16 {
    (words as u16) << 8 | opcode as u16
}

/// RS232 bytes: OpCode, Len-1, data, CRC (low byte first).
pub fn rs232_encode(f: &Frame) -> Vec<u8> {
    let words = f.words();
    assert!((1..=RS232_MAX_WORDS).contains(&words), "RS232 frame of {words} words");
    with_crc(f, (words - 1) as u8, rs232_header(f.opcode, words))
}

/// OpCode, the length byte `len`, data, and the CRC over `header` and the data.
fn with_crc(f: &Frame, len: u8, header: u16) -> Vec<u8> {
    let crc = crc(header, &f.data).to_le_bytes();
    [&[f.opcode, len][..], &f.data, &crc].concat()
}

/// Bytes that follow OpCode and Len-1 on RS232: the data words and the CRC.
pub fn rs232_body_len(len_minus_1: u8) -> usize {
    (len_minus_1 as usize + 1) * 2 + 2
}

/// A complete RS232 frame.
pub fn rs232_decode(bytes: &[u8]) -> Result<Frame, FrameError> {
    let [opcode, lm1, rest @ ..] = bytes else { return Err(FrameError::Truncated(bytes.len())) };
    let need = rs232_body_len(*lm1);
    if rest.len() < need {
        return Err(FrameError::Truncated(bytes.len()));
    }
    let data = &rest[..need - 2];
    let got = u16::from_le_bytes([rest[need - 2], rest[need - 1]]);
    let want = crc(rs232_header(*opcode, *lm1 as usize + 1), data);
    if got != want {
        return Err(FrameError::Crc { got, want });
    }
    Ok(Frame { opcode: *opcode, data: data.to_vec() })
}

/// USB bytes: DLE STX, then OpCode, Len, data and CRC with every DLE doubled.
pub fn usb_encode(f: &Frame) -> Vec<u8> {
    let words = f.words();
    assert!(words <= USB_MAX_WORDS, "USB frame of {words} words");
    [vec![DLE, STX], stuff(&with_crc(f, words as u8, usb_header(f.opcode, words)))].concat()
}

/// Double every DLE (seed 000 §4.1.4).
pub fn stuff(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(bytes.len() + 4);
    for &b in bytes {
        out.push(b);
        if b == DLE {
            out.push(DLE);
        }
    }
    out
}

#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
enum UsbState {
    #[default]
    Hunt,
    Sync,
    Body,
    BodyDle,
}

/// Reassembles USB frames from a byte stream: skips anything before DLE STX, undoes the
/// stuffing, checks length and CRC. Feed bytes one at a time.
#[derive(Debug, Default)]
pub struct UsbDecoder {
    state: UsbState,
    body: Vec<u8>,
}

impl UsbDecoder {
    /// A decoder waiting for a frame's start.
    pub fn new() -> UsbDecoder {
        UsbDecoder::default()
    }

    /// Whether a frame has started and not yet ended.
    pub(crate) fn in_frame(&self) -> bool {
        matches!(self.state, UsbState::Body | UsbState::BodyDle)
    }

    /// One byte in; a frame or an error out when one ends.
    pub fn push(&mut self, b: u8) -> Option<Result<Frame, FrameError>> {
        match self.state {
            UsbState::Hunt => {
                if b == DLE {
                    self.state = UsbState::Sync;
                }
                None
            }
            UsbState::Sync => {
                self.state = if b == STX {
                    self.body.clear();
                    UsbState::Body
                } else if b == DLE {
                    UsbState::Sync
                } else {
                    UsbState::Hunt
                };
                None
            }
            UsbState::Body if b == DLE => {
                self.state = UsbState::BodyDle;
                None
            }
            UsbState::Body => self.body_byte(b),
            UsbState::BodyDle => match b {
                DLE => {
                    self.state = UsbState::Body;
                    self.body_byte(DLE)
                }
                STX => {
                    // A sync inside a frame: the old frame is lost, the new one begins.
                    self.body.clear();
                    self.state = UsbState::Body;
                    Some(Err(FrameError::Interrupted))
                }
                other => {
                    self.state = UsbState::Hunt;
                    Some(Err(FrameError::Stuffing(other)))
                }
            },
        }
    }

    fn body_byte(&mut self, b: u8) -> Option<Result<Frame, FrameError>> {
        self.body.push(b);
        if self.body.len() < 2 {
            return None;
        }
        let words = self.body[1] as usize;
        if words > USB_MAX_WORDS {
            self.state = UsbState::Hunt;
            return Some(Err(FrameError::Oversize(words)));
        }
        let total = 2 + words * 2 + 2;
        if self.body.len() < total {
            return None;
        }
        self.state = UsbState::Hunt;
        let (opcode, data) = (self.body[0], &self.body[2..total - 2]);
        let got = u16::from_le_bytes([self.body[total - 2], self.body[total - 1]]);
        let want = crc(usb_header(opcode, words), data);
        Some(if got == want { Ok(Frame { opcode, data: data.to_vec() }) } else { Err(FrameError::Crc { got, want }) })
    }
}

/// Decode the first USB frame in `bytes` (test and fuzz convenience).
pub fn usb_decode(bytes: &[u8]) -> Result<Frame, FrameError> {
    let mut d = UsbDecoder::new();
    for &b in bytes {
        if let Some(r) = d.push(b) {
            return r;
        }
    }
    Err(FrameError::Truncated(bytes.len()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(ws: &[u16]) -> Vec<u8> {
        ws.iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    #[test]
    fn seed_000_usb_read_object_home_offset() {
        // §4.1.8: ReadObject 0x2081:0 node 1 → 90 02 10 02 81 20 00 01 0F 87
        let f = Frame::new(0x10, words(&[0x2081, 0x0100]));
        let bytes = usb_encode(&f);
        assert_eq!(bytes, [0x90, 0x02, 0x10, 0x02, 0x81, 0x20, 0x00, 0x01, 0x0F, 0x87]);
        assert_eq!(usb_decode(&bytes).unwrap(), f);
        // The answer holds 0x8090: its 0x90 byte is doubled on the wire; CRC 0x3514.
        let answer = Frame::new(0x00, words(&[0x0000, 0x0000, 0x0000, 0x8090]));
        let bytes = usb_encode(&answer);
        assert_eq!(bytes, [0x90, 0x02, 0x00, 0x04, 0, 0, 0, 0, 0, 0, 0x90, 0x90, 0x80, 0x14, 0x35]);
        assert_eq!(usb_decode(&bytes).unwrap(), answer);
    }

    #[test]
    fn seed_000_rs232_read_object_software_version() {
        // §5.1.8: ReadObject 0x2003:1 node 2 → 10 01 03 20 01 02 88 A8
        let f = Frame::new(0x10, words(&[0x2003, 0x0201]));
        let bytes = rs232_encode(&f);
        assert_eq!(bytes, [0x10, 0x01, 0x03, 0x20, 0x01, 0x02, 0x88, 0xA8]);
        assert_eq!(rs232_decode(&bytes).unwrap(), f);
        // Reception order of the answer: 00 03 00 00 00 00 10 20 10 62 10 26
        let answer = [0x00, 0x03, 0x00, 0x00, 0x00, 0x00, 0x10, 0x20, 0x10, 0x62, 0x10, 0x26];
        let a = rs232_decode(&answer).unwrap();
        assert_eq!(a.data, words(&[0, 0, 0x2010, 0x6210]));
        assert_eq!(rs232_encode(&a), answer);
    }

    #[test]
    fn seed_002_gateway_examples() {
        // ReadObject 0x1000:0 of node 2 over USB: CRC DF F2, answer CRC 9A ED.
        let req = Frame::new(0x10, vec![0x00, 0x10, 0x00, 0x02]);
        assert_eq!(usb_encode(&req), [0x90, 0x02, 0x10, 0x02, 0x00, 0x10, 0x00, 0x02, 0xDF, 0xF2]);
        let ans = Frame::new(0x00, vec![0, 0, 0, 0, 0x92, 0x01, 0x02, 0x00]);
        assert_eq!(usb_encode(&ans), [0x90, 0x02, 0x00, 0x04, 0, 0, 0, 0, 0x92, 0x01, 0x02, 0x00, 0x9A, 0xED]);
        // The same over RS232: CRC 10 CD, answer CRC EB 6D.
        assert_eq!(rs232_encode(&req), [0x10, 0x01, 0x00, 0x10, 0x00, 0x02, 0x10, 0xCD]);
        assert_eq!(rs232_encode(&ans), [0x00, 0x03, 0, 0, 0, 0, 0x92, 0x01, 0x02, 0x00, 0xEB, 0x6D]);
    }

    #[test]
    fn seed_000_stuffing_examples() {
        assert_eq!(stuff(&[0x21, 0x90, 0x45]), [0x21, 0x90, 0x90, 0x45]);
        assert_eq!(stuff(&[0x21, 0x90, 0x02, 0x45]), [0x21, 0x90, 0x90, 0x02, 0x45]);
        assert_eq!(stuff(&[0x21, 0x90, 0x90, 0x45]), [0x21, 0x90, 0x90, 0x90, 0x90, 0x45]);
    }

    #[test]
    fn usb_decoder_survives_bad_input() {
        let good = usb_encode(&Frame::new(0x10, vec![0x90, 0x90, 0x02, 0x90]));
        // Garbage (including lone DLEs) before the frame is skipped.
        let mut noisy = vec![0x00, 0x90, 0x55, 0x90, 0x90, 0x13];
        noisy.extend(&good);
        assert_eq!(usb_decode(&noisy).unwrap().data, vec![0x90, 0x90, 0x02, 0x90]);
        // A flipped bit fails the CRC.
        let mut bad = good.clone();
        bad[2] ^= 0x01; // the opcode

        assert!(matches!(usb_decode(&bad), Err(FrameError::Crc { .. })));
        // DLE followed by anything but DLE/STX inside a frame.
        assert_eq!(usb_decode(&[0x90, 0x02, 0x10, 0x90, 0x33]), Err(FrameError::Stuffing(0x33)));
        assert_eq!(usb_decode(&[0x90, 0x02, 0x10, 0x90, 0x02]), Err(FrameError::Interrupted));
        assert_eq!(usb_decode(&[0x90, 0x02, 0x10, 0xFF]), Err(FrameError::Oversize(255)));
        assert_eq!(usb_decode(&good[..good.len() - 1]), Err(FrameError::Truncated(good.len() - 1)));
    }

    #[test]
    fn rs232_decoder_checks_length_and_crc() {
        assert_eq!(rs232_decode(&[0x10]), Err(FrameError::Truncated(1)));
        assert_eq!(rs232_decode(&[0x10, 0x01, 0x03, 0x20]), Err(FrameError::Truncated(4)));
        assert!(matches!(rs232_decode(&[0x10, 0x01, 0x03, 0x20, 0x01, 0x02, 0x88, 0xA9]), Err(FrameError::Crc { .. })));
    }

    #[test]
    fn random_bytes_never_panic() {
        let mut x: u32 = 12345;
        for _ in 0..20_000 {
            let len = (x % 40) as usize;
            let bytes: Vec<u8> = (0..len)
                .map(|_| {
                    x ^= x << 13;
                    x ^= x >> 17;
                    x ^= x << 5;
                    if x.is_multiple_of(5) {
                        DLE
                    } else {
                        x as u8
                    }
                })
                .collect();
            let _ = usb_decode(&bytes);
            let _ = rs232_decode(&bytes);
        }
    }
}
