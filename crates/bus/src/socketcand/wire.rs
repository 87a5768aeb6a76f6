//! The socketcand protocol's units, pure: each is ASCII between `<` and `>`, with no line
//! ends and no length, so TCP may cut a unit anywhere or bring several in one read.
//!
//! Raw mode (linux-can/socketcand `doc/protocol.md`, `state_raw.c`): the server greets with
//! `< hi >`; `< open can0 >` and `< rawmode >` are each answered `< ok >` (or `< error
//! TEXT >`). The client sends `< send ID LEN B0 B1 .. >` (hex id, 8 digits for a 29-bit
//! one; decimal length; one hex token a byte). The server sends `< frame ID SECS.USECS
//! DATA >`, DATA one hex string (socketcand) or one token a byte (the protocol document),
//! `< error CLASS SECS.USECS >` for an error frame (CLASS: the SocketCAN error class bits),
//! and, in newer versions, `< rtr ID SECS.USECS DLC >`.

use crate::frame::Frame;

/// The longest unit accepted: a frame with 8 spaced bytes and a 29-bit id is under 60
/// bytes; a peer that sends more without a `>` is not speaking the protocol.
pub const MAX_UNIT: usize = 256;

/// SocketCAN's error class bit for bus-off (`CAN_ERR_BUSOFF`, linux/can/error.h).
pub const ERR_BUSOFF: u32 = 0x40;

/// One unit of the protocol, either way.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Unit {
    /// `< hi >`: the server's greeting.
    Hi,
    /// `< ok >`.
    Ok,
    /// `< open IFACE >`.
    Open(String),
    /// `< rawmode >`.
    RawMode,
    /// `< echo >`: the server answers with the same.
    Echo,
    /// `< send ... >` (client to server) of an 11-bit data frame.
    Send(Frame),
    /// `< frame ... >` (server to client), or `< rtr ... >` as a remote frame; `micros`:
    /// the server's time stamp, microseconds since the Unix epoch.
    Frame {
        /// The frame.
        frame: Frame,
        /// When the server's interface received it.
        micros: u64,
    },
    /// A `send` or `frame` with a 29-bit id: not CANopen's, so not made a [`Frame`].
    Extended {
        /// The 29-bit id.
        id: u32,
    },
    /// `< error CLASS SECS.USECS >`: an error frame on the server's bus.
    ErrorFrame {
        /// The SocketCAN error class bits ([`ERR_BUSOFF`] ...).
        class: u32,
    },
    /// `< error TEXT >`: the server refused something.
    Refused(String),
    /// A unit this module does not know (`< bcmmode >`, `< stat ... >`), its text.
    Other(String),
}

/// A unit that does not parse, or bytes outside any unit; the text, cut short.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Malformed(pub String);

impl Unit {
    /// The bytes on the wire.
    pub fn encode(&self) -> Vec<u8> {
        let body = match self {
            Unit::Hi => "hi".to_string(),
            Unit::Ok => "ok".to_string(),
            Unit::Open(iface) => format!("open {iface}"),
            Unit::RawMode => "rawmode".to_string(),
            Unit::Echo => "echo".to_string(),
            Unit::Send(f) => {
                let mut s = format!("send {:03X} {}", f.id(), f.len());
                for b in f.data() {
                    s.push(' ');
                    push_hex(&mut s, *b);
                }
                s
            }
            Unit::Frame { frame, micros } if frame.is_remote() => {
                format!("rtr {:03X} {} {}", frame.id(), time_text(*micros), frame.len())
            }
            // As socketcand writes it: the data as one hex string, after a space even when
            // there is none (python-can's client needs that space).
            Unit::Frame { frame, micros } => {
                let mut s = format!("frame {:03X} {} ", frame.id(), time_text(*micros));
                for b in frame.data() {
                    push_hex(&mut s, *b);
                }
                s
            }
            Unit::Extended { id } => format!("frame {id:08X} 0.000000 "),
            Unit::ErrorFrame { class } => format!("error {class:03X} 0.000000"),
            Unit::Refused(text) => format!("error {text}"),
            Unit::Other(text) => text.clone(),
        };
        format!("< {body} >").into_bytes()
    }
}

/// A byte as two upper-case hex digits: per byte of every frame, so without the
/// allocation a `format!` would make.
fn push_hex(s: &mut String, b: u8) {
    const DIGITS: &[u8; 16] = b"0123456789ABCDEF";
    s.push(DIGITS[usize::from(b >> 4)] as char);
    s.push(DIGITS[usize::from(b & 0xF)] as char);
}

fn time_text(micros: u64) -> String {
    format!("{}.{:06}", micros / 1_000_000, micros % 1_000_000)
}

/// `SECS.USECS` (or whole seconds) → microseconds.
fn parse_time(text: &str) -> Option<u64> {
    let (secs, frac) = text.split_once('.').unwrap_or((text, "0"));
    if frac.is_empty() || frac.len() > 6 || !frac.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let secs: u64 = secs.parse().ok()?;
    let frac: u64 = format!("{frac:0<6}").parse().ok()?;
    secs.checked_mul(1_000_000)?.checked_add(frac)
}

fn hex_byte(t: &str) -> Option<u8> {
    (1..=2).contains(&t.len()).then(|| u8::from_str_radix(t, 16).ok()).flatten()
}

/// The unit for an id token: `base` of it when 11-bit (up to 3 hex digits), an extended
/// frame's when 29-bit (exactly 8: socketcand's rule).
fn with_id(t: &str, base: impl FnOnce(u16) -> Unit) -> Option<Unit> {
    let v = u32::from_str_radix(t, 16).ok()?;
    match t.len() {
        8 if v <= 0x1FFF_FFFF => Some(Unit::Extended { id: v }),
        1..=3 if v <= 0x7FF => Some(base(v as u16)),
        _ => None,
    }
}

/// Frame data as one hex string (`11223344`) or one token a byte (`11 22 33 44`, `1 F1`).
fn parse_data(tokens: &[&str]) -> Option<Vec<u8>> {
    let data: Vec<u8> = match tokens {
        [] => Vec::new(),
        [one] if one.len() > 2 => {
            if one.len() % 2 != 0 {
                return None;
            }
            (0..one.len()).step_by(2).map(|i| one.get(i..i + 2).and_then(hex_byte)).collect::<Option<_>>()?
        }
        many => many.iter().map(|t| hex_byte(t)).collect::<Option<_>>()?,
    };
    (data.len() <= 8).then_some(data)
}

/// One unit's text between the brackets.
pub fn decode_unit(body: &str) -> Result<Unit, Malformed> {
    let bad = || Malformed(clip(body));
    let tokens: Vec<&str> = body.split_ascii_whitespace().collect();
    match tokens.as_slice() {
        ["hi"] => Ok(Unit::Hi),
        ["ok"] => Ok(Unit::Ok),
        ["open", iface] => Ok(Unit::Open(iface.to_string())),
        ["rawmode"] => Ok(Unit::RawMode),
        ["echo"] => Ok(Unit::Echo),
        ["send", id, len, data @ ..] => {
            let len: usize = len.parse().map_err(|_| bad())?;
            let bytes: Vec<u8> = data.iter().map(|t| hex_byte(t)).collect::<Option<_>>().ok_or_else(bad)?;
            if len > 8 || bytes.len() != len {
                return Err(bad());
            }
            with_id(id, |id| Unit::Send(Frame::new(id, &bytes))).ok_or_else(bad)
        }
        ["frame", id, time, data @ ..] => {
            let micros = parse_time(time).ok_or_else(bad)?;
            let bytes = parse_data(data).ok_or_else(bad)?;
            with_id(id, |id| Unit::Frame { frame: Frame::new(id, &bytes), micros }).ok_or_else(bad)
        }
        ["rtr", id, time, dlc] => {
            let micros = parse_time(time).ok_or_else(bad)?;
            let dlc: u8 = dlc.parse().ok().filter(|d| *d <= 8).ok_or_else(bad)?;
            with_id(id, |id| Unit::Frame { frame: Frame::remote(id, dlc), micros }).ok_or_else(bad)
        }
        ["error", class, time] if parse_time(time).is_some() && u32::from_str_radix(class, 16).is_ok() => {
            Ok(Unit::ErrorFrame { class: u32::from_str_radix(class, 16).map_err(|_| bad())? })
        }
        ["error", words @ ..] => Ok(Unit::Refused(clip(&words.join(" ")))),
        [] => Err(bad()),
        _ => Ok(Unit::Other(clip(body.trim()))),
    }
}

fn clip(text: &str) -> String {
    const MAX: usize = 80;
    match text.char_indices().nth(MAX) {
        Some((at, _)) => format!("{}...", &text[..at]),
        None => text.to_string(),
    }
}

/// Cuts a TCP byte stream into units, whatever the reads' boundaries.
#[derive(Debug, Default)]
pub struct Decoder {
    /// Bytes of a unit begun but not ended (from its `<`).
    pending: Vec<u8>,
    /// Bytes outside any unit since the last unit.
    garbage: Vec<u8>,
}

impl Decoder {
    /// A decoder at the start of a stream.
    pub fn new() -> Decoder {
        Decoder::default()
    }

    /// The units these bytes complete, in order; bytes outside any unit, and units that do
    /// not parse or grow beyond [`MAX_UNIT`], come out as [`Malformed`].
    pub fn push(&mut self, bytes: &[u8]) -> Vec<Result<Unit, Malformed>> {
        let mut out = Vec::new();
        for &b in bytes {
            if self.pending.is_empty() {
                if b == b'<' {
                    self.flush_garbage(&mut out);
                    self.pending.push(b);
                } else if !b.is_ascii_whitespace() {
                    self.garbage.push(b);
                }
                continue;
            }
            match b {
                // A new unit before the last one ended: the last one was cut off.
                b'<' => {
                    let cut = std::mem::replace(&mut self.pending, vec![b]);
                    out.push(Err(Malformed(clip(&String::from_utf8_lossy(&cut)))));
                }
                b'>' => {
                    let unit = std::mem::take(&mut self.pending);
                    out.push(match std::str::from_utf8(&unit[1..]) {
                        Ok(body) => decode_unit(body),
                        Err(_) => Err(Malformed(clip(&String::from_utf8_lossy(&unit)))),
                    });
                }
                _ if self.pending.len() >= MAX_UNIT => {
                    let long = std::mem::take(&mut self.pending);
                    out.push(Err(Malformed(clip(&String::from_utf8_lossy(&long)))));
                }
                _ => self.pending.push(b),
            }
        }
        if self.garbage.len() >= MAX_UNIT {
            self.flush_garbage(&mut out);
        }
        out
    }

    fn flush_garbage(&mut self, out: &mut Vec<Result<Unit, Malformed>>) {
        if !self.garbage.is_empty() {
            let junk = std::mem::take(&mut self.garbage);
            out.push(Err(Malformed(clip(&String::from_utf8_lossy(&junk)))));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn units(chunks: &[&[u8]]) -> Vec<Result<Unit, Malformed>> {
        let mut d = Decoder::new();
        chunks.iter().flat_map(|c| d.push(c)).collect()
    }

    fn frame(id: u16, data: &[u8], micros: u64) -> Result<Unit, Malformed> {
        Ok(Unit::Frame { frame: Frame::new(id, data), micros })
    }

    #[test]
    fn the_handshake_both_ways() {
        assert_eq!(Unit::Hi.encode(), b"< hi >");
        assert_eq!(Unit::Open("vcan0".into()).encode(), b"< open vcan0 >");
        assert_eq!(Unit::RawMode.encode(), b"< rawmode >");
        assert_eq!(Unit::Ok.encode(), b"< ok >");
        assert_eq!(units(&[b"< hi >< ok >"]), [Ok(Unit::Hi), Ok(Unit::Ok)]);
        assert_eq!(units(&[b"< open can0 >"]), [Ok(Unit::Open("can0".into()))]);
    }

    #[test]
    fn send_is_hex_id_decimal_length_and_a_token_a_byte() {
        let sdo = Frame::new(0x601, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]);
        assert_eq!(Unit::Send(sdo).encode(), b"< send 601 8 40 18 10 01 00 00 00 00 >");
        assert_eq!(Unit::Send(Frame::new(0x000, &[])).encode(), b"< send 000 0 >");
        // Every hex digit, upper case, high nibble first, both ways.
        let digits = Frame::new(0x7E5, &[0x01, 0x23, 0x45, 0x67, 0x89, 0xAB, 0xCD, 0xEF]);
        assert_eq!(Unit::Send(digits).encode(), b"< send 7E5 8 01 23 45 67 89 AB CD EF >");
        assert_eq!(Unit::Frame { frame: digits, micros: 1 }.encode(), b"< frame 7E5 0.000001 0123456789ABCDEF >");
        // python-can writes the bytes unpadded and lower case.
        assert_eq!(units(&[b"< send 601 2 1 f1 >"]), [Ok(Unit::Send(Frame::new(0x601, &[0x01, 0xF1])))]);
        assert_eq!(units(&[b"< send 1AAAAAAA 2 1 F1 >"]), [Ok(Unit::Extended { id: 0x1AAA_AAAA })]);
        // The length must match the bytes, as socketcand checks.
        assert!(units(&[b"< send 601 3 1 2 >"])[0].is_err());
        assert!(units(&[b"< send 601 9 1 2 3 4 5 6 7 8 9 >"])[0].is_err());
        assert!(units(&[b"< send 801 0 >"])[0].is_err());
    }

    #[test]
    fn frames_in_either_data_notation() {
        let want = frame(0x581, &[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00], 1_700_000_000_123_456);
        assert_eq!(units(&[b"< frame 581 1700000000.123456 4300100092010200 >"]), std::slice::from_ref(&want));
        assert_eq!(units(&[b"< frame 581 1700000000.123456 43 00 10 00 92 01 02 00 >"]), [want]);
        // No data: socketcand leaves two spaces.
        assert_eq!(units(&[b"< frame 705 23.424242  >"]), [frame(0x705, &[], 23_424_242)]);
        assert_eq!(units(&[b"< frame 123 23.4 1 F1 >"]), [frame(0x123, &[0x01, 0xF1], 23_400_000)]);
        assert_eq!(units(&[b"< frame 0000070A 1.000000 05 >"]), [Ok(Unit::Extended { id: 0x70A })]);
        assert_eq!(
            units(&[b"< rtr 701 1.000000 1 >"]),
            [Ok(Unit::Frame { frame: Frame::remote(0x701, 1), micros: 1_000_000 })]
        );
        for bad in [&b"< frame 581 1.0 123 >"[..], b"< frame 581 x.0 12 >", b"< frame 581 1.0 112233445566778899 >"] {
            assert!(units(&[bad])[0].is_err(), "{}", String::from_utf8_lossy(bad));
        }
    }

    #[test]
    fn what_the_server_sends_decodes_to_the_same_frame() {
        for f in [Frame::new(0x181, &[1, 2, 3]), Frame::new(0x700, &[]), Frame::remote(0x70A, 1)] {
            let unit = Unit::Frame { frame: f, micros: 42 };
            assert_eq!(units(&[&unit.encode()]), [Ok(unit)]);
        }
    }

    #[test]
    fn a_unit_split_anywhere_and_units_merged_in_one_read() {
        let stream = b"< frame 705 1.000000 05 >< frame 181 1.000100 0102 >< ok >";
        let whole = units(&[stream]);
        assert_eq!(whole.len(), 3);
        for cut in 0..stream.len() {
            assert_eq!(units(&[&stream[..cut], &stream[cut..]]), whole, "cut at {cut}");
        }
        let bytes: Vec<&[u8]> = stream.chunks(1).collect();
        assert_eq!(units(&bytes), whole);
    }

    #[test]
    fn garbage_between_units_is_reported_and_skipped() {
        let got = units(&[b"\x00junk< ok >\r\n< frame 705 1.0 7F > tail"]);
        assert_eq!(got[0], Err(Malformed("\u{0}junk".into())));
        assert_eq!(got[1..], [Ok(Unit::Ok), frame(0x705, &[0x7F], 1_000_000)]);
        // A unit cut off by the next one, and one that never ends.
        let got = units(&[b"< frame 705 < ok >"]);
        assert!(got[0].is_err() && got[1] == Ok(Unit::Ok), "{got:?}");
        let endless = vec![b'x'; 3 * MAX_UNIT];
        let got = units(&[b"< ", &endless, b" >< hi >"]);
        assert!(got.iter().any(|u| u.is_err()) && got.last() == Some(&Ok(Unit::Hi)), "{got:?}");
        assert!(units(&[b"<>"])[0].is_err());
    }

    /// Bytes linux-can/socketcand 0.6.1 sent on vcan0 in the VM (scripts/vm-socketcand.sh),
    /// each read as it came: the answer to `< rawmode >` with the bus's frames behind it in
    /// the same read, an empty SYNC (two blanks), the echo and a refusal ahead of frames.
    #[test]
    fn what_linux_can_socketcand_sent() {
        let got = units(&[
            b"< hi >",
            b"< ok >",
            b"< ok >< frame 70A 1795720730.486578 7F >< frame 714 1795720730.529527 7F >",
            b"< echo >< frame 70A 1795720734.568222 7F >",
            b"< error unknown command >< frame 70A 1795720735.573752 7F >",
            b"< frame 080 1795720736.550207  >< frame 000 1795720737.652987 8014 >",
            b"< frame 594 1795720739.347977 431810010A0D0000 >",
        ]);
        let heartbeat = |id, micros| frame(id, &[0x7F], micros);
        assert_eq!(
            got,
            [
                Ok(Unit::Hi),
                Ok(Unit::Ok),
                Ok(Unit::Ok),
                heartbeat(0x70A, 1_795_720_730_486_578),
                heartbeat(0x714, 1_795_720_730_529_527),
                Ok(Unit::Echo),
                heartbeat(0x70A, 1_795_720_734_568_222),
                Ok(Unit::Refused("unknown command".into())),
                heartbeat(0x70A, 1_795_720_735_573_752),
                frame(0x080, &[], 1_795_720_736_550_207),
                frame(0x000, &[0x80, 0x14], 1_795_720_737_652_987),
                frame(0x594, &[0x43, 0x18, 0x10, 0x01, 0x0A, 0x0D, 0, 0], 1_795_720_739_347_977),
            ]
        );
    }

    #[test]
    fn error_frames_and_refusals() {
        assert_eq!(units(&[b"< error 040 1700000000.000001 >"]), [Ok(Unit::ErrorFrame { class: ERR_BUSOFF })]);
        assert_eq!(units(&[b"< error 004 1.5 >"]), [Ok(Unit::ErrorFrame { class: 0x004 })]);
        assert_eq!(units(&[b"< error could not open bus >"]), [Ok(Unit::Refused("could not open bus".into()))]);
        assert_eq!(units(&[b"< error unknown command >"]), [Ok(Unit::Refused("unknown command".into()))]);
        assert_eq!(Unit::Refused("could not open bus".into()).encode(), b"< error could not open bus >");
        assert_eq!(units(&[b"< stat 1 2 3 4 >"]), [Ok(Unit::Other("stat 1 2 3 4".into()))]);
    }
}
