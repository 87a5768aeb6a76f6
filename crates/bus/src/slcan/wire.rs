//! The Lawicel "slcan" ASCII protocol of serial-line CAN adapters (CANUSB, CANable, USBtin
//! and their clones): pure encoding of commands and decoding of what the adapter sends.
//!
//! Every command and every answer ends with a carriage return; an adapter that refuses a
//! command answers with a bell (0x07) instead. Frames are hex text: `t`, 3 id digits, the
//! DLC and the data for an 11-bit data frame; `T` and 8 id digits for a 29-bit one; `r`/`R`
//! for remote frames. Adapters with time stamps on (`Z1`) append 4 hex digits of milliseconds.

use crate::frame::Frame;

/// Ends every line, and is the adapter's "OK".
pub const CR: u8 = b'\r';
/// The adapter's "refused".
pub const BELL: u8 = 0x07;
/// The longest line an adapter sends: `T` + 8 + 1 + 16 data + 4 time stamp digits.
pub const MAX_LINE: usize = 30;

/// The `S0`..`S8` bit rates, in kbit/s.
pub const BIT_RATES: [(u8, u32); 9] =
    [(0, 10), (1, 20), (2, 50), (3, 100), (4, 125), (5, 250), (6, 500), (7, 800), (8, 1000)];

/// The `Sn` code for a bit rate in kbit/s, if slcan has one.
pub fn bit_rate_code(kbit: u32) -> Option<u8> {
    BIT_RATES.iter().find(|(_, k)| *k == kbit).map(|(c, _)| *c)
}

/// What canctl asks of an adapter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// `Sn`: the bit rate, by code (see `BIT_RATES`); only while the channel is closed.
    BitRate(u8),
    /// `O`: open the channel.
    Open,
    /// `L`: open the channel listen-only: the adapter neither sends nor acknowledges, so
    /// a trial at a wrong bit rate disturbs nobody.
    ListenOnly,
    /// `C`: close the channel.
    Close,
    /// `F`: read the status flags.
    Status,
    /// `V`: hardware and software version.
    Version,
    /// `N`: serial number.
    Serial,
    /// `Z0`/`Z1`: time stamps off/on.
    Timestamps(bool),
    /// `t`/`r`: send a frame.
    Transmit(Frame),
}

impl Command {
    /// The command line, CR included.
    pub fn encode(&self) -> Vec<u8> {
        let mut out = match self {
            Command::BitRate(code) => format!("S{code}"),
            Command::Open => "O".into(),
            Command::ListenOnly => "L".into(),
            Command::Close => "C".into(),
            Command::Status => "F".into(),
            Command::Version => "V".into(),
            Command::Serial => "N".into(),
            Command::Timestamps(on) => format!("Z{}", u8::from(*on)),
            Command::Transmit(f) => frame_text(f),
        }
        .into_bytes();
        out.push(CR);
        out
    }
}

/// `t12380011223344556677` or `r1238`.
fn frame_text(f: &Frame) -> String {
    let kind = if f.is_remote() { 'r' } else { 't' };
    let mut s = format!("{kind}{:03X}{}", f.id(), f.len());
    for b in f.data() {
        s.push_str(&format!("{b:02X}"));
    }
    s
}

/// The status flags of `F` (Lawicel): which of them is set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Status(pub u8);

impl Status {
    const NAMES: [&'static str; 8] = [
        "receive FIFO full",
        "transmit FIFO full",
        "error warning",
        "data overrun",
        "(unused)",
        "error passive",
        "arbitration lost",
        "bus error",
    ];

    /// The names of the flags set.
    pub fn names(&self) -> Vec<&'static str> {
        (0..8).filter(|b| self.0 & (1 << b) != 0).map(|b| Status::NAMES[b]).collect()
    }

    /// Whether frames may have been lost or the bus is unusable.
    #[cfg(test)]
    pub(crate) fn is_trouble(&self) -> bool {
        self.0 & !(1 << 4) != 0
    }
}

/// One message from an adapter.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Message {
    /// A received 11-bit frame.
    Frame(Frame),
    /// A received 29-bit frame: CANopen has no use for it, but it is on the bus.
    Extended {
        /// Its 29-bit identifier.
        id: u32,
    },
    /// A bare CR: the last command was done.
    Ok,
    /// `z` / `Z`: a frame was queued for sending.
    Sent,
    /// A bell: the last command was refused.
    Refused,
    /// `Fxx`.
    Status(Status),
    /// `Vhhss`: hardware and software version.
    Version(String),
    /// `Nxxxx`.
    Serial(String),
}

/// Why a line could not be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum WireError {
    /// No carriage return within this many bytes: the adapter or the line is not speaking slcan.
    #[error("line too long ({0} bytes without a carriage return)")]
    TooLong(usize),
    /// A line no adapter sends (the line, as far as it is text).
    #[error("malformed line '{0}'")]
    Malformed(String),
}

impl Message {
    /// What an adapter sends for this message (the simulator's adapter side).
    pub fn encode(&self) -> Vec<u8> {
        let mut out = match self {
            Message::Frame(f) => frame_text(f).into_bytes(),
            Message::Extended { id } => format!("T{id:08X}0").into_bytes(),
            Message::Ok => Vec::new(),
            Message::Sent => b"z".to_vec(),
            Message::Refused => return vec![BELL],
            Message::Status(s) => format!("F{:02X}", s.0).into_bytes(),
            Message::Version(v) => format!("V{v}").into_bytes(),
            Message::Serial(n) => format!("N{n}").into_bytes(),
        };
        out.push(CR);
        out
    }
}

/// Decode a command line from the host (without its CR), as an adapter does; `None` for a
/// 29-bit frame, which an adapter accepts but a CANopen network has no use for.
#[cfg_attr(not(unix), allow(dead_code))] // its one caller, the simulated adapter, is served on a pty
pub fn decode_command(line: &[u8]) -> Result<Option<Command>, WireError> {
    let bad = || WireError::Malformed(String::from_utf8_lossy(line).into_owned());
    Ok(Some(match line {
        [b'S', code @ b'0'..=b'8'] => Command::BitRate(code - b'0'),
        b"O" => Command::Open,
        b"L" => Command::ListenOnly,
        b"C" => Command::Close,
        b"F" => Command::Status,
        b"V" => Command::Version,
        b"N" => Command::Serial,
        b"Z0" => Command::Timestamps(false),
        b"Z1" => Command::Timestamps(true),
        [b't' | b'r', ..] => match decode_line(line)? {
            Message::Frame(f) => Command::Transmit(f),
            _ => return Err(bad()),
        },
        [b'T' | b'R', ..] => {
            decode_line(line)?;
            return Ok(None);
        }
        _ => return Err(bad()),
    }))
}

/// Decode one line (without its CR).
pub(crate) fn decode_line(line: &[u8]) -> Result<Message, WireError> {
    let bad = || WireError::Malformed(String::from_utf8_lossy(line).into_owned());
    let Some((&kind, rest)) = line.split_first() else { return Ok(Message::Ok) };
    let text = std::str::from_utf8(rest).map_err(|_| bad())?;
    let hex = |s: &str| u32::from_str_radix(s, 16).ok().filter(|_| s.bytes().all(|b| b.is_ascii_hexdigit()));
    match kind {
        b't' | b'r' | b'T' | b'R' => {
            let id_len = if kind.is_ascii_lowercase() { 3 } else { 8 };
            let id = text.get(..id_len).and_then(hex).ok_or_else(bad)?;
            let dlc = text.get(id_len..id_len + 1).and_then(hex).filter(|d| *d <= 8).ok_or_else(bad)? as usize;
            let data_text = &text[id_len + 1..];
            let remote = kind == b'r' || kind == b'R';
            let data_len = if remote { 0 } else { dlc * 2 };
            // What follows the data is a time stamp (4 digits) or nothing.
            if data_text.len() != data_len && data_text.len() != data_len + 4 {
                return Err(bad());
            }
            let mut data = [0u8; 8];
            for (i, b) in data.iter_mut().enumerate().take(data_len / 2) {
                *b = data_text.get(2 * i..2 * i + 2).and_then(hex).ok_or_else(bad)? as u8;
            }
            if data_text.len() > data_len {
                hex(&data_text[data_len..]).ok_or_else(bad)?;
            }
            if id_len == 8 {
                if id > 0x1FFF_FFFF {
                    return Err(bad());
                }
                return Ok(Message::Extended { id });
            }
            if id > 0x7FF {
                return Err(bad());
            }
            let id = id as u16;
            Ok(Message::Frame(if remote { Frame::remote(id, dlc as u8) } else { Frame::new(id, &data[..dlc]) }))
        }
        b'z' | b'Z' if text.is_empty() => Ok(Message::Sent),
        b'F' if text.len() == 2 => Ok(Message::Status(Status(hex(text).ok_or_else(bad)? as u8))),
        b'V' if text.len() == 4 && hex(text).is_some() => Ok(Message::Version(text.to_string())),
        b'N' if !text.is_empty() && text.len() <= 8 => Ok(Message::Serial(text.to_string())),
        _ => Err(bad()),
    }
}

/// Splits the adapter's byte stream into messages: lines ended by CR, and bells.
#[derive(Default)]
pub struct Decoder {
    line: Vec<u8>,
    /// A line that grew past `MAX_LINE`: dropped up to its CR.
    overlong: bool,
}

impl Decoder {
    /// A decoder at the start of a line.
    pub fn new() -> Decoder {
        Decoder::default()
    }

    /// Feed bytes; every complete message (or error) in them, in order.
    pub fn push(&mut self, bytes: &[u8]) -> Vec<Result<Message, WireError>> {
        let mut out = Vec::new();
        for &b in bytes {
            match b {
                BELL | CR => {
                    out.push(match b {
                        BELL => Ok(Message::Refused),
                        _ if self.overlong => Err(WireError::TooLong(self.line.len())),
                        _ => decode_line(&self.line),
                    });
                    self.line.clear();
                    self.overlong = false;
                }
                // Some adapters end lines with CR LF.
                b'\n' if self.line.is_empty() => {}
                _ if self.overlong => {}
                _ => {
                    self.line.push(b);
                    if self.line.len() > MAX_LINE {
                        self.overlong = true;
                    }
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_as_lawicel_defines_them() {
        assert_eq!(Command::BitRate(6).encode(), b"S6\r");
        assert_eq!(Command::ListenOnly.encode(), b"L\r");
        assert_eq!(decode_command(b"L"), Ok(Some(Command::ListenOnly)));
        assert_eq!(Command::Open.encode(), b"O\r");
        assert_eq!(Command::Close.encode(), b"C\r");
        assert_eq!(Command::Status.encode(), b"F\r");
        assert_eq!(Command::Version.encode(), b"V\r");
        assert_eq!(Command::Serial.encode(), b"N\r");
        assert_eq!(Command::Timestamps(false).encode(), b"Z0\r");
        let sdo = Frame::new(0x605, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]);
        assert_eq!(Command::Transmit(sdo).encode(), b"t60584000100000000000\r");
        assert_eq!(Command::Transmit(Frame::new(0x000, &[0x01, 0x05])).encode(), b"t00020105\r");
        assert_eq!(Command::Transmit(Frame::new(0x080, &[])).encode(), b"t0800\r");
        assert_eq!(Command::Transmit(Frame::remote(0x185, 8)).encode(), b"r1858\r");
    }

    #[test]
    fn bit_rates_s0_to_s8() {
        assert_eq!(bit_rate_code(10), Some(0));
        assert_eq!(bit_rate_code(125), Some(4));
        assert_eq!(bit_rate_code(500), Some(6));
        assert_eq!(bit_rate_code(1000), Some(8));
        assert_eq!(bit_rate_code(83), None);
    }

    #[test]
    fn frames_received() {
        let heartbeat = decode_line(b"t70517F").unwrap();
        assert_eq!(heartbeat, Message::Frame(Frame::new(0x705, &[0x7F])));
        let with_stamp = decode_line(b"t585843001000000000011A2B").unwrap();
        assert_eq!(with_stamp, Message::Frame(Frame::new(0x585, &[0x43, 0, 0x10, 0, 0, 0, 0, 0x01])));
        assert_eq!(decode_line(b"r1858").unwrap(), Message::Frame(Frame::remote(0x185, 8)));
        assert_eq!(decode_line(b"T1234567820102").unwrap(), Message::Extended { id: 0x1234_5678 });
        assert_eq!(decode_line(b"R123456780").unwrap(), Message::Extended { id: 0x1234_5678 });
        assert_eq!(decode_line(b"t0000").unwrap(), Message::Frame(Frame::new(0, &[])));
    }

    #[test]
    fn answers_received() {
        assert_eq!(decode_line(b"").unwrap(), Message::Ok);
        assert_eq!(decode_line(b"z").unwrap(), Message::Sent);
        assert_eq!(decode_line(b"Z").unwrap(), Message::Sent);
        assert_eq!(decode_line(b"F00").unwrap(), Message::Status(Status(0)));
        let flags = decode_line(b"F84").unwrap();
        let Message::Status(s) = flags else { panic!("{flags:?}") };
        assert_eq!(s.names(), ["error warning", "bus error"]);
        assert!(s.is_trouble());
        assert_eq!(decode_line(b"V1013").unwrap(), Message::Version("1013".into()));
        assert_eq!(decode_line(b"NA123").unwrap(), Message::Serial("A123".into()));
    }

    #[test]
    fn malformed_lines_are_errors_never_frames() {
        for bad in [
            &b"t12"[..],
            b"t1239",        // DLC 9
            b"t123411",      // 1 data byte where 4 are announced
            b"t12341122334", // odd digit
            b"t800100",      // 11-bit id above 0x7FF
            b"tXYZ0",        // not hex
            b"t12321122x",   // junk where the time stamp would be
            b"T123456781",   // data missing
            b"F1",           // short flags
            b"Q",            // unknown
            b"t1230\xff",
        ] {
            assert!(decode_line(bad).is_err(), "{:?}", String::from_utf8_lossy(bad));
        }
    }

    #[test]
    fn the_adapter_side_reads_commands_and_writes_messages() {
        for cmd in [
            Command::BitRate(8),
            Command::Open,
            Command::Close,
            Command::Status,
            Command::Version,
            Command::Serial,
            Command::Timestamps(true),
            Command::Transmit(Frame::new(0x7E5, &[0x4C, 1, 2, 3, 4, 5, 6, 7])),
            Command::Transmit(Frame::remote(0x701, 1)),
        ] {
            let bytes = cmd.encode();
            assert_eq!(decode_command(&bytes[..bytes.len() - 1]), Ok(Some(cmd)), "{cmd:?}");
        }
        assert_eq!(decode_command(b"T12345678111"), Ok(None));
        assert!(decode_command(b"S9").is_err());
        assert!(decode_command(b"X").is_err());
        assert_eq!(Message::Frame(Frame::new(0x185, &[1, 2])).encode(), b"t18520102\r");
        assert_eq!(Message::Sent.encode(), b"z\r");
        assert_eq!(Message::Ok.encode(), b"\r");
        assert_eq!(Message::Refused.encode(), [BELL]);
        assert_eq!(Message::Status(Status(0x84)).encode(), b"F84\r");
        for m in [Message::Version("1013".into()), Message::Serial("A123".into()), Message::Status(Status(3))] {
            let bytes = m.encode();
            assert_eq!(decode_line(&bytes[..bytes.len() - 1]), Ok(m));
        }
    }

    #[test]
    fn the_stream_is_split_into_messages() {
        let mut d = Decoder::new();
        let mut got = d.push(b"z\rt70");
        assert_eq!(got, [Ok(Message::Sent)]);
        got = d.push(b"517F\r\x07\r\n");
        assert_eq!(got, [Ok(Message::Frame(Frame::new(0x705, &[0x7F]))), Ok(Message::Refused), Ok(Message::Ok)]);
        // A babbling line is cut at MAX_LINE and reported once, at its CR.
        let babble = vec![b'7'; 500];
        assert!(d.push(&babble).is_empty());
        assert_eq!(d.push(b"\r"), [Err(WireError::TooLong(MAX_LINE + 1))]);
        assert_eq!(d.push(b"t0000\r"), [Ok(Message::Frame(Frame::new(0, &[])))]);
    }
}
