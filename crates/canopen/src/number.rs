//! A number as CANopen people write it, on a command line, in a settings file or an
//! identity: decimal (`500`), or hex after `0x` or `0X` (`0x1F4`). One reading for every
//! place that takes one, so that what one accepts the others accept too.

/// `text` as a `T`: decimal, or hex after `0x`/`0X`; `None` when it is neither or does not
/// fit a `T`. No sign, no spaces: the caller trims what its input may carry.
pub fn parse_number<T: TryFrom<u64>>(text: &str) -> Option<T> {
    let n = match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u64::from_str_radix(hex, 16).ok()?,
        None => text.parse::<u64>().ok()?,
    };
    T::try_from(n).ok()
}

#[cfg(test)]
mod tests {
    use super::parse_number;

    #[test]
    fn decimal_and_hex_either_case_of_prefix() {
        assert_eq!(parse_number::<u32>("500"), Some(500));
        assert_eq!(parse_number::<u32>("0x1F4"), Some(500));
        assert_eq!(parse_number::<u32>("0X1f4"), Some(500));
        assert_eq!(parse_number::<u8>("0x7F"), Some(0x7F));
    }

    #[test]
    fn what_does_not_fit_or_is_not_a_number_is_none() {
        assert_eq!(parse_number::<u8>("256"), None);
        assert_eq!(parse_number::<u8>("0x100"), None);
        assert_eq!(parse_number::<u32>("0x"), None);
        assert_eq!(parse_number::<u32>(""), None);
        assert_eq!(parse_number::<u32>("12k"), None);
        assert_eq!(parse_number::<u32>("-1"), None);
        assert_eq!(parse_number::<u32>(" 5"), None);
        assert_eq!(parse_number::<u64>("0x1_0000_0000_0000_0000"), None);
    }
}
