//! A number as CANopen people write it, on a command line, in a settings file, an identity
//! or a CiA 306 file: decimal (`500`), or hex after `0x` or `0X` (`0x1F4`). One reading for
//! every place that takes one, so that what one accepts the others accept too; the two
//! variants (a sign, and CiA 306's octal) are this reading with one thing added, here too.
//!
//! Only the digits of the base are digits: `str::parse` and `from_str_radix` also take a
//! sign, so `0x+1F` and `-0x-5` read as numbers before; they are none. Hex-only fields of a
//! format (an EDS section name, candump's `123#`, an XDD `dataType`) are not read here.

/// `text` as a `T`: decimal, or hex after `0x`/`0X`; `None` when it is neither or does not
/// fit a `T`. No spaces (the caller trims what its input may carry) and no `-`; a leading
/// `+` is taken, as `str::parse` took it at every call site before this one reading.
pub fn parse_number<T: TryFrom<u64>>(text: &str) -> Option<T> {
    let n = magnitude(text.strip_prefix('+').unwrap_or(text))?;
    T::try_from(u64::try_from(n).ok()?).ok()
}

/// `text` as a signed integer: [`parse_number`]'s forms after an optional `+` or `-`
/// (`-0x80` is -128). The caller checks the range of its type.
pub fn parse_signed(text: &str) -> Option<i128> {
    signed(text, magnitude)
}

/// A CiA 306 integer (EDS, DCF): [`parse_signed`]'s forms, and a leading `0` makes it octal
/// (`017` is 15), as CiA 306 says; `0` alone is zero.
pub fn parse_cia306(text: &str) -> Option<i128> {
    signed(text, |body| match body.strip_prefix('0') {
        Some(octal) if !octal.is_empty() && !octal.starts_with(['x', 'X']) => digits(octal, 8),
        _ => magnitude(body),
    })
}

/// An optional sign, then `body` read by `unsigned`; `-` negates what fits an `i128`.
fn signed(text: &str, unsigned: impl Fn(&str) -> Option<u128>) -> Option<i128> {
    let (negative, body) = match text.strip_prefix('-') {
        Some(body) => (true, body),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let m = unsigned(body)?;
    match negative {
        // 2^127 is i128::MIN's magnitude: `as` wraps it to MIN, negating keeps it there.
        true => (m <= 1 << 127).then(|| (m as i128).wrapping_neg()),
        false => i128::try_from(m).ok(),
    }
}

/// Decimal digits, or hex digits after `0x`/`0X`; nothing else (no sign).
fn magnitude(text: &str) -> Option<u128> {
    text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")).map_or_else(|| digits(text, 10), |hex| digits(hex, 16))
}

/// One or more digits of `radix` and nothing else; `None` past `u128`.
fn digits(text: &str, radix: u32) -> Option<u128> {
    // from_str_radix takes a leading sign; a number's digits have none.
    if text.is_empty() || !text.chars().all(|c| c.is_digit(radix)) {
        return None;
    }
    u128::from_str_radix(text, radix).ok()
}

#[cfg(test)]
mod tests {
    use super::{parse_cia306, parse_number, parse_signed};

    #[test]
    fn decimal_and_hex_either_case_of_prefix() {
        assert_eq!(parse_number::<u32>("500"), Some(500));
        assert_eq!(parse_number::<u32>("0x1F4"), Some(500));
        assert_eq!(parse_number::<u32>("0X1f4"), Some(500));
        assert_eq!(parse_number::<u8>("0x7F"), Some(0x7F));
        assert_eq!(parse_number::<u8>("0"), Some(0));
        assert_eq!(parse_number::<u8>("0x0"), Some(0));
        // Leading zeros are decimal here (only CiA 306 files read them as octal).
        assert_eq!(parse_number::<u32>("017"), Some(17));
        assert_eq!(parse_number::<u32>("0x00000000000000000000000000000000001"), Some(1));
        assert_eq!(parse_number::<u32>("+5"), Some(5));
        assert_eq!(parse_number::<u32>("+0x10"), Some(16));
    }

    #[test]
    fn each_type_takes_what_fits_it() {
        assert_eq!(parse_number::<u8>("255"), Some(255));
        assert_eq!(parse_number::<u8>("0xFF"), Some(255));
        assert_eq!(parse_number::<u16>("0xFFFF"), Some(0xFFFF));
        assert_eq!(parse_number::<u32>("4294967295"), Some(u32::MAX));
        assert_eq!(parse_number::<u64>("0xFFFFFFFFFFFFFFFF"), Some(u64::MAX));
        assert_eq!(parse_number::<u8>("256"), None);
        assert_eq!(parse_number::<u8>("0x100"), None);
        assert_eq!(parse_number::<u32>("4294967296"), None);
        assert_eq!(parse_number::<u64>("0x1_0000_0000_0000_0000"), None);
        assert_eq!(parse_number::<u64>("0x10000000000000000"), None);
        assert_eq!(parse_number::<u64>("0x100000000000000000000000000000000"), None, "past u128");
    }

    #[test]
    fn what_is_not_a_number_is_none() {
        for text in [
            "", "0x", "0X", "x10", "0x 1", "12k", "1.5", "1e3", "0b101", "0o17", "1F", "0xG", "10h", "1_000", "-1",
            "-0", " 5", "5 ", "++5", "+", "+-5", "0x+1F", "0x-1", "0x0x1", "٣", "１",
        ] {
            assert_eq!(parse_number::<u64>(text), None, "{text:?}");
        }
    }

    #[test]
    fn signed_takes_a_sign_before_either_form() {
        assert_eq!(parse_signed("-5"), Some(-5));
        assert_eq!(parse_signed("+5"), Some(5));
        assert_eq!(parse_signed("-0x80"), Some(-128));
        assert_eq!(parse_signed("0xFF"), Some(255));
        assert_eq!(parse_signed("-0"), Some(0));
        assert_eq!(parse_signed("-0x80000000000000000000000000000000"), Some(i128::MIN));
        assert_eq!(parse_signed("0x7FFFFFFFFFFFFFFFFFFFFFFFFFFFFFFF"), Some(i128::MAX));
        assert_eq!(parse_signed("0x80000000000000000000000000000000"), None);
        assert_eq!(parse_signed("-0x80000000000000000000000000000001"), None);
        for text in ["", "-", "+", "--5", "+-5", "-+5", "- 5", "-0x", "-0x-5", "0x+5", "5-", "1_000", "0x_FF"] {
            assert_eq!(parse_signed(text), None, "{text:?}");
        }
    }

    #[test]
    fn cia306_reads_a_leading_zero_as_octal() {
        assert_eq!(parse_cia306("017"), Some(15));
        assert_eq!(parse_cia306("-017"), Some(-15));
        assert_eq!(parse_cia306("00"), Some(0));
        assert_eq!(parse_cia306("0"), Some(0));
        assert_eq!(parse_cia306("-0"), Some(0));
        assert_eq!(parse_cia306("17"), Some(17));
        assert_eq!(parse_cia306("0x1F"), Some(31));
        assert_eq!(parse_cia306("0X1f"), Some(31));
        assert_eq!(parse_cia306("-5"), Some(-5));
        assert_eq!(parse_cia306("+5"), Some(5));
        for text in ["08", "019", "0+7", "0-7", "0x", "-", "", "0_7", "0o17", "1U", "0x10L"] {
            assert_eq!(parse_cia306(text), None, "{text:?}");
        }
    }
}
