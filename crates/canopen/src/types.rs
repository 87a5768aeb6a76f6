//! CiA 309-3 data type names and the conversion of values between text and the
//! little-endian bytes that travel in SDOs and PDOs.

use std::fmt;

/// A CANopen data type (CiA 301 §7.1), as object dictionaries name them.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
pub enum DataType {
    /// BOOLEAN.
    Bool,
    /// UNSIGNED8.
    U8,
    /// UNSIGNED16.
    U16,
    /// UNSIGNED32.
    U32,
    /// UNSIGNED64.
    U64,
    /// INTEGER8.
    I8,
    /// INTEGER16.
    I16,
    /// INTEGER32.
    I32,
    /// INTEGER64.
    I64,
    /// REAL32.
    R32,
    /// REAL64.
    R64,
    /// VISIBLE_STRING
    Vs,
    /// OCTET_STRING
    Os,
    /// DOMAIN
    D,
    /// UNSIGNED24.
    U24,
    /// UNSIGNED40.
    U40,
    /// UNSIGNED48.
    U48,
    /// UNSIGNED56.
    U56,
    /// INTEGER24.
    I24,
    /// INTEGER40.
    I40,
    /// INTEGER48.
    I48,
    /// INTEGER56.
    I56,
    /// TIME_OF_DAY: milliseconds after midnight (28 bits) and days since 1984-01-01.
    TimeOfDay,
    /// TIME_DIFFERENCE: milliseconds (28 bits) and days.
    TimeDifference,
    /// UNICODE_STRING: UTF-16, little-endian code units (as python-canopen reads it).
    Unicode,
}

/// Every data type canctl reads and writes.
pub const ALL_TYPES: [DataType; 25] = [
    DataType::Bool,
    DataType::U8,
    DataType::U16,
    DataType::U32,
    DataType::U64,
    DataType::I8,
    DataType::I16,
    DataType::I32,
    DataType::I64,
    DataType::R32,
    DataType::R64,
    DataType::Vs,
    DataType::Os,
    DataType::D,
    DataType::U24,
    DataType::U40,
    DataType::U48,
    DataType::U56,
    DataType::I24,
    DataType::I40,
    DataType::I48,
    DataType::I56,
    DataType::TimeOfDay,
    DataType::TimeDifference,
    DataType::Unicode,
];

/// The CiA 309-3 short names, in the order of [`ALL_TYPES`] (the enum's order).
const NAMES: [&str; 25] = [
    "b", "u8", "u16", "u32", "u64", "i8", "i16", "i32", "i64", "r32", "r64", "vs", "os", "d", "u24", "u40", "u48",
    "u56", "i24", "i40", "i48", "i56", "t", "td", "us",
];

/// The CiA 301 data type indexes, in the order of [`ALL_TYPES`].
const CODES: [u16; 25] = [
    0x01, 0x05, 0x06, 0x07, 0x1B, 0x02, 0x03, 0x04, 0x15, 0x08, 0x11, 0x09, 0x0A, 0x0F, 0x16, 0x18, 0x19, 0x1A, 0x10,
    0x12, 0x13, 0x14, 0x0C, 0x0D, 0x0B,
];

/// A failure to turn text into a value; always the user's input, so always a usage error.
#[derive(Debug, PartialEq, Eq)]
pub struct ValueError(pub String);

impl fmt::Display for ValueError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl DataType {
    /// The CiA 309-3 short name.
    pub fn name(self) -> &'static str {
        NAMES[self as usize]
    }

    /// The CiA 301 data type index (0x0001 BOOLEAN ... 0x001B UNSIGNED64), as EDS files use.
    pub fn code(self) -> u16 {
        CODES[self as usize]
    }

    /// Size in bytes of a fixed-size type; `None` for strings and domains.
    pub fn size(self) -> Option<usize> {
        Some(match self {
            DataType::Bool | DataType::U8 | DataType::I8 => 1,
            DataType::U16 | DataType::I16 => 2,
            DataType::U24 | DataType::I24 => 3,
            DataType::U32 | DataType::I32 | DataType::R32 => 4,
            DataType::U40 | DataType::I40 => 5,
            DataType::U48 | DataType::I48 | DataType::TimeOfDay | DataType::TimeDifference => 6,
            DataType::U56 | DataType::I56 => 7,
            DataType::U64 | DataType::I64 | DataType::R64 => 8,
            DataType::Vs | DataType::Os | DataType::D | DataType::Unicode => return None,
        })
    }

    /// Whether the type is a signed integer (INTEGER8 to INTEGER64).
    pub fn is_signed(self) -> bool {
        use DataType::*;
        matches!(self, I8 | I16 | I24 | I32 | I40 | I48 | I56 | I64)
    }

    /// Inclusive range of an integer type.
    pub fn int_range(self) -> Option<(i128, i128)> {
        use DataType::*;
        let bits = match self {
            Bool => return Some((0, 1)),
            t if t.is_signed() || matches!(t, U8 | U16 | U24 | U32 | U40 | U48 | U56 | U64) => {
                8 * t.size().unwrap() as u32
            }
            _ => return None,
        };
        Some(if self.is_signed() {
            (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
        } else {
            (0, (1i128 << bits) - 1)
        })
    }

    /// Text to bytes. Integers take decimal, `0x` hex and a sign; reals take any float
    /// syntax; `vs` takes the text as it is; `os` and `d` take hex (spaces and `.` allowed).
    /// `@file` is handled by the caller, which owns file I/O.
    pub fn parse(self, text: &str) -> Result<Vec<u8>, ValueError> {
        let t = text.trim();
        match self {
            DataType::Bool => match t.to_ascii_lowercase().as_str() {
                "1" | "true" | "on" | "yes" => Ok(vec![1]),
                "0" | "false" | "off" | "no" => Ok(vec![0]),
                _ => Err(ValueError(format!("'{text}' is not a boolean: use true/false or 1/0"))),
            },
            DataType::R32 => {
                let v: f32 = t.parse().map_err(|_| self.not_a(text, "a number like 1.5 or -2e3"))?;
                if v.is_infinite() && !t.to_ascii_lowercase().contains("inf") {
                    return Err(ValueError(format!("'{text}' is out of range for r32 (about ±3.4e38)")));
                }
                Ok(v.to_le_bytes().to_vec())
            }
            DataType::R64 => {
                let v: f64 = t.parse().map_err(|_| self.not_a(text, "a number like 1.5 or -2e3"))?;
                Ok(v.to_le_bytes().to_vec())
            }
            DataType::Vs => Ok(text.as_bytes().to_vec()),
            DataType::Unicode => Ok(text.encode_utf16().flat_map(u16::to_le_bytes).collect()),
            DataType::TimeOfDay | DataType::TimeDifference => {
                let (days, ms) = time::parse(t, self == DataType::TimeOfDay).map_err(ValueError)?;
                Ok([ms.to_le_bytes().as_slice(), &days.to_le_bytes()].concat())
            }
            DataType::Os | DataType::D => {
                parse_hex(t).map_err(|e| ValueError(format!("{e} (or @FILE to read the bytes from a file)")))
            }
            _ => {
                let v = parse_int(t).ok_or_else(|| self.not_a(text, "an integer (decimal, or hex with 0x)"))?;
                let (lo, hi) = self.int_range().expect("integer type");
                if v < lo || v > hi {
                    return Err(ValueError(format!("{text} is out of range for {}: use {lo} to {hi}", self.name())));
                }
                let size = self.size().unwrap();
                Ok(v.to_le_bytes()[..size].to_vec())
            }
        }
    }

    fn not_a(self, text: &str, what: &str) -> ValueError {
        ValueError(format!("'{text}' is not a valid {} value: expected {what}", self.name()))
    }

    /// Bytes to a typed value. `None` when the length does not fit the type.
    pub fn decode(self, bytes: &[u8]) -> Option<Value> {
        let mut wide = [0u8; 16];
        if let Some(size) = self.size() {
            if bytes.len() != size {
                return None;
            }
            wide[..size].copy_from_slice(bytes);
            if self.is_signed() && bytes[size - 1] & 0x80 != 0 {
                wide[size..].fill(0xFF);
            }
        }
        let int = i128::from_le_bytes(wide);
        Some(match self {
            DataType::Bool => Value::Bool(int != 0),
            DataType::R32 => Value::Real(f32::from_le_bytes(bytes.try_into().unwrap()) as f64, self),
            DataType::R64 => Value::Real(f64::from_le_bytes(bytes.try_into().unwrap()), self),
            DataType::Vs => Value::Text(visible_string(bytes)),
            DataType::Unicode => Value::Text(unicode_string(bytes)?),
            DataType::TimeOfDay | DataType::TimeDifference => {
                // The 4 bits above the 28 of milliseconds are reserved (CiA 301): not read.
                let ms = u32::from_le_bytes(bytes[..4].try_into().unwrap()) & 0x0FFF_FFFF;
                let days = u16::from_le_bytes([bytes[4], bytes[5]]);
                Value::Text(time::format(days, ms, self == DataType::TimeOfDay))
            }
            DataType::Os | DataType::D => Value::Bytes(bytes.to_vec()),
            t if t.is_signed() => Value::Int(int as i64),
            _ => Value::Uint(int as u64),
        })
    }
}

impl fmt::Display for DataType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for DataType {
    type Err = String;

    fn from_str(s: &str) -> Result<DataType, String> {
        let lower = s.to_ascii_lowercase();
        let aliases: &[(&str, DataType)] = &[
            ("bool", DataType::Bool),
            ("boolean", DataType::Bool),
            ("visible_string", DataType::Vs),
            ("octet_string", DataType::Os),
            ("domain", DataType::D),
            ("f32", DataType::R32),
            ("f64", DataType::R64),
        ];
        ALL_TYPES
            .iter()
            .find(|t| t.name() == lower)
            .copied()
            .or_else(|| aliases.iter().find(|(n, _)| *n == lower).map(|(_, t)| *t))
            .ok_or_else(|| {
                let names: Vec<_> = ALL_TYPES.iter().map(|t| t.name()).collect();
                format!("'{s}' is not a data type; use one of {}", names.join(" "))
            })
    }
}

/// A decoded value, ready to print as text or JSON.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A BOOLEAN.
    Bool(bool),
    /// Any unsigned integer.
    Uint(u64),
    /// Any signed integer.
    Int(i64),
    /// A REAL32 or REAL64 (which one, for printing it exactly).
    Real(f64, DataType),
    /// A string (VISIBLE_STRING, UNICODE_STRING), or a time in words.
    Text(String),
    /// Bytes shown as hex (OCTET_STRING, DOMAIN).
    Bytes(Vec<u8>),
}

impl Value {
    /// The value as JSON: numbers as numbers (a REAL that is not finite as text), the rest
    /// as text.
    pub fn to_json(&self) -> serde_json::Value {
        use serde_json::Value as J;
        match self {
            Value::Bool(b) => J::Bool(*b),
            Value::Uint(u) => J::from(*u),
            Value::Int(i) => J::from(*i),
            Value::Real(r, _) => {
                serde_json::Number::from_f64(*r).map(J::Number).unwrap_or_else(|| J::String(self.to_string()))
            }
            Value::Text(s) => J::String(s.clone()),
            Value::Bytes(b) => J::String(hex(b)),
        }
    }
}

/// The text form parses back to the same bytes with the same type.
impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Bool(b) => write!(f, "{b}"),
            Value::Uint(u) => write!(f, "{u}"),
            Value::Int(i) => write!(f, "{i}"),
            // Shortest text that reads back to the same value at the type's precision.
            Value::Real(r, DataType::R32) => write!(f, "{}", *r as f32),
            Value::Real(r, _) => write!(f, "{r}"),
            Value::Text(s) => f.write_str(s),
            Value::Bytes(b) => f.write_str(&hex(b)),
        }
    }
}

/// UTF-16LE code units, NUL padding dropped; `None` for an odd length or a lone surrogate.
fn unicode_string(bytes: &[u8]) -> Option<String> {
    if !bytes.len().is_multiple_of(2) {
        return None;
    }
    let mut units: Vec<u16> = bytes.chunks(2).map(|c| u16::from_le_bytes([c[0], c[1]])).collect();
    while units.last() == Some(&0) {
        units.pop();
    }
    String::from_utf16(&units).ok()
}

/// TIME_OF_DAY as a date and time (`2024-05-01T12:34:56.789`, days counted from
/// 1984-01-01 as CiA 301 counts them); TIME_DIFFERENCE as days and a time (`3d 01:02:03.004`).
mod time {
    const MS_PER_DAY: u32 = 86_400_000;
    /// Days from 1970-01-01 to 1984-01-01, the CiA 301 epoch.
    const EPOCH: i64 = 5113;

    /// Civil date of a day number counted from 1970-01-01 (Howard Hinnant's algorithm).
    fn civil(z: i64) -> (i64, u32, u32) {
        let z = z + 719_468;
        let era = z.div_euclid(146_097);
        let doe = z - era * 146_097;
        let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
        let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
        let mp = (5 * doy + 2) / 153;
        let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
        let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
        (yoe + era * 400 + i64::from(m <= 2), m, d)
    }

    fn days_from_civil(y: i64, m: u32, d: u32) -> i64 {
        let y = if m <= 2 { y - 1 } else { y };
        let era = y.div_euclid(400);
        let yoe = y - era * 400;
        let mp = i64::from((m + 9) % 12);
        let doy = (153 * mp + 2) / 5 + i64::from(d) - 1;
        let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
        era * 146_097 + doe - 719_468
    }

    fn clock(ms: u32) -> String {
        let s = ms / 1000;
        format!("{:02}:{:02}:{:02}.{:03}", s / 3600, s / 60 % 60, s % 60, ms % 1000)
    }

    pub fn format(days: u16, ms: u32, of_day: bool) -> String {
        if of_day {
            let (y, m, d) = civil(EPOCH + i64::from(days));
            // A device may count past midnight: shown as it is, read back the same.
            format!("{y:04}-{m:02}-{d:02}T{}", clock(ms))
        } else {
            format!("{days}d {}", clock(ms))
        }
    }

    /// `HH:MM:SS[.mmm]` → milliseconds (hours beyond 23 allowed, up to 28 bits).
    fn parse_clock(t: &str) -> Option<u32> {
        let (hms, frac) = t.split_once('.').unwrap_or((t, ""));
        let parts: Vec<u64> = hms.split(':').map(|p| p.parse().ok()).collect::<Option<_>>()?;
        let [h, m, s] = parts[..] else { return None };
        if m > 59 || s > 59 || frac.len() > 3 || !frac.chars().all(|c| c.is_ascii_digit()) {
            return None;
        }
        let ms = format!("{frac:0<3}").parse::<u64>().ok()?;
        let total = ((h * 60 + m) * 60 + s) * 1000 + ms;
        u32::try_from(total).ok().filter(|v| *v <= 0x0FFF_FFFF)
    }

    pub fn parse(t: &str, of_day: bool) -> Result<(u16, u32), String> {
        let bad = |want: &str| format!("'{t}' is not a {want}");
        if of_day {
            let want = "time of day like 2024-05-01T12:34:56.789 (1984-01-01 to 2163-06-06)";
            let (date, clock) = t.split_once(['T', ' ']).ok_or_else(|| bad(want))?;
            let ymd: Vec<&str> = date.split('-').collect();
            let [y, m, d] = ymd[..] else { return Err(bad(want)) };
            let (y, m, d) = (y.parse::<i64>(), m.parse::<u32>(), d.parse::<u32>());
            let (Ok(y), Ok(m @ 1..=12), Ok(d @ 1..=31)) = (y, m, d) else { return Err(bad(want)) };
            let day = days_from_civil(y, m, d) - EPOCH;
            let ms = parse_clock(clock).filter(|ms| *ms < MS_PER_DAY).ok_or_else(|| bad(want))?;
            // 2023-02-30 would slide to March: refuse rather than guess.
            if civil(day + EPOCH) != (y, m, d) {
                return Err(bad(want));
            }
            Ok((u16::try_from(day).map_err(|_| bad(want))?, ms))
        } else {
            let want = "time difference like 3d 01:02:03.004 or 00:00:01.5";
            let (days, clock) = match t.split_once('d') {
                Some((d, rest)) => (d.trim().parse::<u16>().map_err(|_| bad(want))?, rest.trim()),
                None => (0, t),
            };
            Ok((days, parse_clock(clock).ok_or_else(|| bad(want))?))
        }
    }
}

/// Strings from devices are often NUL-padded to their buffer size; the padding is not text.
fn visible_string(bytes: &[u8]) -> String {
    let end = bytes.iter().rposition(|b| *b != 0).map_or(0, |p| p + 1);
    String::from_utf8_lossy(&bytes[..end]).into_owned()
}

/// An integer typed for a value: the one number reading with a sign
/// ([`crate::number::parse_signed`]), its digits grouped by `_` if the user likes
/// (`0x0950_1234`, as long values are written in Rust and in this crate's docs): only here,
/// where text is typed for one value; files and identities keep their formats' digits.
fn parse_int(t: &str) -> Option<i128> {
    crate::number::parse_signed(&t.replace('_', ""))
}

// Hex text is frame text too (`candump` lines); it lives with `Frame`, below this layer.
pub use crate::frame::parse_hex;

/// Bytes to contiguous upper-case hex, as can-utils writes payloads.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02X}")).collect()
}

/// The reading of bytes of unknown type that nobody would argue with: the unsigned
/// little-endian integer for 1, 2, 4 or 8 bytes.
pub fn obvious_unsigned(bytes: &[u8]) -> Option<u64> {
    match bytes.len() {
        1 | 2 | 4 | 8 => {
            let mut wide = [0u8; 8];
            wide[..bytes.len()].copy_from_slice(bytes);
            Some(u64::from_le_bytes(wide))
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use DataType::*;

    #[test]
    fn every_type_round_trips_through_text() {
        let cases: &[(DataType, &str, &[u8])] = &[
            (Bool, "true", &[1]),
            (U8, "255", &[0xFF]),
            (U16, "0x1234", &[0x34, 0x12]),
            (U32, "4294967295", &[0xFF; 4]),
            (U64, "18446744073709551615", &[0xFF; 8]),
            (I8, "-128", &[0x80]),
            (I16, "-2", &[0xFE, 0xFF]),
            (I32, "-0x10", &[0xF0, 0xFF, 0xFF, 0xFF]),
            (I64, "-9223372036854775808", &[0, 0, 0, 0, 0, 0, 0, 0x80]),
            (R32, "1.5", &[0, 0, 0xC0, 0x3F]),
            (R64, "-0.25", &[0, 0, 0, 0, 0, 0, 0xD0, 0xBF]),
            (Vs, "C01", b"C01"),
            (Os, "de ad be ef", &[0xDE, 0xAD, 0xBE, 0xEF]),
            (D, "0x0102", &[1, 2]),
            (U24, "0x123456", &[0x56, 0x34, 0x12]),
            (I24, "-8388608", &[0, 0, 0x80]),
            (U40, "1099511627775", &[0xFF; 5]),
            (I40, "-40", &[0xD8, 0xFF, 0xFF, 0xFF, 0xFF]),
            (U48, "48", &[0x30, 0, 0, 0, 0, 0]),
            (I48, "-48", &[0xD0, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF]),
            (U56, "0x01020304050607", &[7, 6, 5, 4, 3, 2, 1]),
            (I56, "-56", &[0xC8, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF]),
            (TimeOfDay, "1984-01-01T00:00:00.000", &[0; 6]),
            // 2024-01-01 is day 14610 (0x3912) of the CiA 301 epoch; noon is 43 200 000 ms.
            (TimeOfDay, "2024-01-01T12:00:00.000", &[0x00, 0x2E, 0x93, 0x02, 0x12, 0x39]),
            (TimeDifference, "1d 00:00:00.500", &[0xF4, 0x01, 0, 0, 0x01, 0]),
            (TimeDifference, "0d 01:02:03.004", &[0xFC, 0xCE, 0x38, 0x00, 0, 0]),
            (Unicode, "abc✓", &[0x61, 0, 0x62, 0, 0x63, 0, 0x13, 0x27]),
        ];
        for (t, text, bytes) in cases {
            let parsed = t.parse(text).unwrap();
            assert_eq!(&parsed, bytes, "{t} {text}");
            let shown = t.decode(&parsed).unwrap().to_string();
            assert_eq!(t.parse(&shown).unwrap(), parsed, "{t}: {shown}");
        }
    }

    #[test]
    fn typed_integers_take_a_sign_and_digits_grouped_by_underscores() {
        assert_eq!(U32.parse("0x0950_1234").unwrap(), 0x0950_1234u32.to_le_bytes());
        assert_eq!(U32.parse("1_000").unwrap(), 1000u32.to_le_bytes());
        assert_eq!(I8.parse("-0x80").unwrap(), [0x80]);
        assert_eq!(I8.parse("+7").unwrap(), [7]);
        // A sign belongs before the number, not among its hex digits.
        for refused in ["0x+5", "-0x-5", "0x", "--5", "1.0", "0b1"] {
            assert!(I32.parse(refused).unwrap_err().0.contains("not a valid i32"), "{refused}");
        }
    }

    #[test]
    fn range_errors_name_the_range() {
        assert_eq!(U8.parse("256").unwrap_err().0, "256 is out of range for u8: use 0 to 255");
        assert!(I8.parse("-129").unwrap_err().0.contains("-128 to 127"));
        assert!(U16.parse("-1").unwrap_err().0.contains("0 to 65535"));
        assert!(U32.parse("12abc").unwrap_err().0.contains("not a valid u32"));
        assert!(R32.parse("1e39").unwrap_err().0.contains("out of range"));
        assert!(Os.parse("abc").unwrap_err().0.contains("odd number"));
        assert!(Bool.parse("maybe").is_err());
        assert!(U64.parse("0x").is_err());
        assert!(U64.parse("99999999999999999999999999999999999999999").is_err());
    }

    #[test]
    fn decode_checks_length_and_sign() {
        assert_eq!(I16.decode(&[0xFE, 0xFF]), Some(Value::Int(-2)));
        assert_eq!(U16.decode(&[0xFE, 0xFF]), Some(Value::Uint(65534)));
        assert_eq!(U32.decode(&[1, 2]), None);
        assert_eq!(Vs.decode(b"CAN-2057C\0\0"), Some(Value::Text("CAN-2057C".into())));
        assert_eq!(obvious_unsigned(&[0x92, 0x01, 0x02, 0x00]), Some(0x0002_0192));
        assert_eq!(obvious_unsigned(&[1, 2, 3]), None);
    }

    #[test]
    fn type_names_parse() {
        for t in ALL_TYPES {
            assert_eq!(t.name().parse::<DataType>().unwrap(), t);
        }
        assert!("u12".parse::<DataType>().unwrap_err().contains("u8 u16"));
    }

    #[test]
    fn the_name_and_code_tables_follow_the_order_of_the_enum() {
        for (i, t) in ALL_TYPES.iter().enumerate() {
            assert_eq!(*t as usize, i, "{t:?}");
        }
        assert_eq!((Bool.name(), Bool.code()), ("b", 0x01));
        assert_eq!((U64.name(), U64.code()), ("u64", 0x1B));
        assert_eq!((D.name(), D.code()), ("d", 0x0F));
        assert_eq!((TimeDifference.name(), TimeDifference.code()), ("td", 0x0D));
        assert_eq!((Unicode.name(), Unicode.code()), ("us", 0x0B));
    }

    #[test]
    fn every_cia_301_basic_type_has_its_code() {
        let codes: Vec<u16> = ALL_TYPES.iter().map(|t| t.code()).collect();
        for code in (0x01..=0x1B).filter(|c| ![0x0E, 0x17].contains(c)) {
            assert!(codes.contains(&code), "CiA 301 basic type 0x{code:04X} has no DataType");
        }
    }

    #[test]
    fn times_and_wide_integers_refuse_what_does_not_fit() {
        assert!(U24.parse("16777216").unwrap_err().0.contains("0 to 16777215"));
        assert!(I56.parse("36028797018963968").is_err());
        assert!(TimeOfDay.parse("2023-02-30T00:00:00").is_err(), "no such day");
        assert!(TimeOfDay.parse("1983-12-31T00:00:00").is_err(), "before the epoch");
        assert!(TimeOfDay.parse("2024-01-01T24:00:00").is_err());
        assert!(TimeDifference.parse("00:61:00").is_err());
        assert_eq!(TimeDifference.parse("00:00:01.5").unwrap(), [0xDC, 0x05, 0, 0, 0, 0]);
        // The 4 reserved bits above the milliseconds are not part of the value.
        assert_eq!(TimeOfDay.decode(&[0, 0, 0, 0xF0, 0, 0]).unwrap().to_string(), "1984-01-01T00:00:00.000");
        assert_eq!(Unicode.decode(&[0x61, 0, 0, 0]), Some(Value::Text("a".into())), "NUL padding dropped");
        assert_eq!(Unicode.decode(&[0x61]), None, "odd length");
        assert_eq!(Unicode.decode(&[0x00, 0xD8]), None, "lone surrogate");
    }
}
