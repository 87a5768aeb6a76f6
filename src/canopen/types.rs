//! CiA 309-3 data type names and the conversion of values between text and the
//! little-endian bytes that travel in SDOs and PDOs.

use std::fmt;

#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
pub enum DataType {
    Bool,
    U8,
    U16,
    U32,
    U64,
    I8,
    I16,
    I32,
    I64,
    R32,
    R64,
    /// VISIBLE_STRING
    Vs,
    /// OCTET_STRING
    Os,
    /// DOMAIN
    D,
}

pub const ALL_TYPES: [DataType; 14] = [
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
        match self {
            DataType::Bool => "b",
            DataType::U8 => "u8",
            DataType::U16 => "u16",
            DataType::U32 => "u32",
            DataType::U64 => "u64",
            DataType::I8 => "i8",
            DataType::I16 => "i16",
            DataType::I32 => "i32",
            DataType::I64 => "i64",
            DataType::R32 => "r32",
            DataType::R64 => "r64",
            DataType::Vs => "vs",
            DataType::Os => "os",
            DataType::D => "d",
        }
    }

    /// The CiA 301 data type index (0x0001 BOOLEAN ... 0x001B UNSIGNED64), as EDS files use.
    pub fn code(self) -> u16 {
        match self {
            DataType::Bool => 0x01,
            DataType::I8 => 0x02,
            DataType::I16 => 0x03,
            DataType::I32 => 0x04,
            DataType::U8 => 0x05,
            DataType::U16 => 0x06,
            DataType::U32 => 0x07,
            DataType::R32 => 0x08,
            DataType::Vs => 0x09,
            DataType::Os => 0x0A,
            DataType::D => 0x0F,
            DataType::R64 => 0x11,
            DataType::I64 => 0x15,
            DataType::U64 => 0x1B,
        }
    }

    /// Size in bytes of a fixed-size type; `None` for strings and domains.
    pub fn size(self) -> Option<usize> {
        Some(match self {
            DataType::Bool | DataType::U8 | DataType::I8 => 1,
            DataType::U16 | DataType::I16 => 2,
            DataType::U32 | DataType::I32 | DataType::R32 => 4,
            DataType::U64 | DataType::I64 | DataType::R64 => 8,
            DataType::Vs | DataType::Os | DataType::D => return None,
        })
    }

    pub fn is_signed(self) -> bool {
        matches!(self, DataType::I8 | DataType::I16 | DataType::I32 | DataType::I64)
    }

    /// Inclusive range of an integer type.
    pub fn int_range(self) -> Option<(i128, i128)> {
        let bits = match self {
            DataType::Bool => return Some((0, 1)),
            t if t.is_signed() || matches!(t, DataType::U8 | DataType::U16 | DataType::U32 | DataType::U64) => {
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
        if let Some(size) = self.size() {
            if bytes.len() != size {
                return None;
            }
        }
        let mut wide = [0u8; 16];
        if let Some(size) = self.size() {
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
    Bool(bool),
    Uint(u64),
    Int(i64),
    Real(f64, DataType),
    Text(String),
    Bytes(Vec<u8>),
}

impl Value {
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

/// Strings from devices are often NUL-padded to their buffer size; the padding is not text.
fn visible_string(bytes: &[u8]) -> String {
    let end = bytes.iter().rposition(|b| *b != 0).map_or(0, |p| p + 1);
    String::from_utf8_lossy(&bytes[..end]).into_owned()
}

fn parse_int(t: &str) -> Option<i128> {
    let (neg, body) = match t.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, t.strip_prefix('+').unwrap_or(t)),
    };
    let body = body.replace('_', "");
    let magnitude = match body.strip_prefix("0x").or_else(|| body.strip_prefix("0X")) {
        Some(hex) if !hex.is_empty() && hex.len() <= 30 => i128::from_str_radix(hex, 16).ok()?,
        Some(_) => return None,
        None if !body.is_empty() && body.len() <= 38 && body.chars().all(|c| c.is_ascii_digit()) => {
            body.parse().ok()?
        }
        None => return None,
    };
    Some(if neg { -magnitude } else { magnitude })
}

/// Hex text to bytes: `DEADBEEF`, `de ad be ef`, `0xdeadbeef`.
pub fn parse_hex(text: &str) -> Result<Vec<u8>, String> {
    let t = text.trim();
    let t = t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")).unwrap_or(t);
    let digits: Vec<u8> = t.bytes().filter(|b| !b.is_ascii_whitespace() && *b != b'.').collect();
    if let Some(bad) = digits.iter().find(|b| !b.is_ascii_hexdigit()) {
        return Err(format!("'{text}' is not hex bytes: '{}' is not a hex digit", *bad as char));
    }
    if !digits.len().is_multiple_of(2) {
        return Err(format!("'{text}' is not hex bytes: odd number of hex digits"));
    }
    Ok(digits.chunks(2).map(|p| u8::from_str_radix(std::str::from_utf8(p).unwrap(), 16).unwrap()).collect())
}

/// Bytes to contiguous upper-case hex, as can-utils writes payloads.
pub fn hex(bytes: &[u8]) -> String {
    const DIGITS: &[u8; 16] = b"0123456789ABCDEF";
    let mut s = String::with_capacity(bytes.len() * 2);
    for b in bytes {
        s.push(DIGITS[(b >> 4) as usize] as char);
        s.push(DIGITS[(b & 15) as usize] as char);
    }
    s
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
        ];
        for (t, text, bytes) in cases {
            let parsed = t.parse(text).unwrap();
            assert_eq!(&parsed, bytes, "{t} {text}");
            let shown = t.decode(&parsed).unwrap().to_string();
            assert_eq!(t.parse(&shown).unwrap(), parsed, "{t}: {shown}");
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
        assert!("u24".parse::<DataType>().unwrap_err().contains("u8 u16"));
    }
}
