//! Values given on the command line that name a concept of the library: sizes, node lists,
//! NMT states, bit rates, LSS node-ids. Each refusal says what would be taken.

use super::parse_node;
use crate::canopen::lss::{parse_bit_rate, AUTO_BIT_RATE, UNCONFIGURED};
use crate::canopen::nmt::State;

/// A node-id for an SDO: 1 to 127, or 0 for an EPOS2 reached directly.
pub fn parse_sdo_node(text: &str) -> Result<u8, String> {
    if text.trim() == "0" {
        return Ok(0);
    }
    parse_node(text).map_err(|e| format!("{e} (or 0: the EPOS2 on an epos2-rs232/epos2-usb bus)"))
}

/// One node-id or several, as one argument: `5` or `5,10,20`.
#[derive(Clone, Debug)]
pub struct Nodes(pub Vec<u8>);

/// Node-ids as one argument, each read by `one`; none named twice.
pub fn parse_nodes(text: &str, one: fn(&str) -> Result<u8, String>) -> Result<Nodes, String> {
    let nodes = text.split(',').map(one).collect::<Result<Vec<u8>, String>>()?;
    if let Some((_, n)) = nodes.iter().enumerate().find(|(i, n)| nodes[..*i].contains(n)) {
        return Err(format!("node {n} is named twice"));
    }
    Ok(Nodes(nodes))
}

/// A byte count: `4096`, `64k`, `16M`, `1G` (binary multiples; `KiB`, `MB` and the like
/// read the same). At most 4 GiB - 1: CiA 301 sizes are 32-bit.
pub fn parse_size(s: &str) -> Result<usize, String> {
    let t = s.trim();
    let digits = t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
    let (number, unit) = t.split_at(digits);
    let number: u64 =
        number.parse().map_err(|_| format!("'{s}' is not a size: a number of bytes, e.g. 4096, 64k, 16M"))?;
    let shift = match unit.trim().to_ascii_lowercase().trim_end_matches('b').trim_end_matches('i') {
        "" => 0,
        "k" => 10,
        "m" => 20,
        "g" => 30,
        _ => return Err(format!("'{s}': unknown unit '{unit}' (k, M or G)")),
    };
    let bytes = number.checked_shl(shift).filter(|b| *b <= u64::from(u32::MAX) && b >> shift == number);
    bytes
        .and_then(|b| usize::try_from(b).ok())
        .ok_or_else(|| format!("'{s}' is over 4G - 1 bytes, the largest size CiA 301 can carry"))
}

/// An NMT state a node can be asked to be in.
pub fn parse_state(text: &str) -> Result<State, String> {
    match text.trim().to_ascii_lowercase().as_str() {
        "operational" => Ok(State::Operational),
        "pre-operational" | "preop" => Ok(State::PreOperational),
        "stopped" => Ok(State::Stopped),
        _ => Err(format!("'{text}' is not an NMT state: use operational, pre-operational or stopped")),
    }
}

/// A CiA 305 bit rate other than "auto" (a network is switched to one rate).
pub fn parse_fixed_bit_rate(text: &str) -> Result<u8, String> {
    match parse_bit_rate(text)? {
        AUTO_BIT_RATE => Err("a network is switched to one bit rate: use 1M 800k 500k 250k 125k 50k 20k or 10k".into()),
        index => Ok(index),
    }
}

/// `500k`, `1M`, `125000`: a CAN bit rate in kbit/s.
pub fn parse_kbit(text: &str) -> Result<u32, String> {
    let t = text.trim().to_ascii_lowercase();
    let k = if let Some(m) = t.strip_suffix('m') {
        m.parse::<u32>().ok().map(|m| m * 1000)
    } else if let Some(k) = t.strip_suffix('k') {
        k.parse().ok()
    } else {
        t.parse::<u32>().ok().map(|b| b / 1000)
    };
    k.filter(|k| [10, 20, 50, 125, 250, 500, 800, 1000].contains(k))
        .ok_or_else(|| format!("'{text}' is not a CAN bit rate: use 1M 800k 500k 250k 125k 50k 20k or 10k"))
}

/// A 32-bit number, decimal or 0x hex (an identity's part).
pub fn parse_u32(s: &str) -> Result<u32, String> {
    crate::canopen::number::parse_number(s)
        .ok_or_else(|| format!("'{s}' is not a 32-bit number (decimal, or hex with 0x)"))
}

/// A node-id to give over LSS: 1 to 127, or 255 to take it away; decimal or 0x hex, as
/// every other node-id (`parse_node`) is.
pub fn parse_lss_node_id(s: &str) -> Result<u8, String> {
    match crate::canopen::number::parse_number::<u8>(s) {
        Some(n) if (1..=127).contains(&n) || n == UNCONFIGURED => Ok(n),
        _ => Err(format!("'{s}' is not a node-id for LSS: use 1 to 127, or 255 to leave the device without one")),
    }
}

#[cfg(test)]
mod tests {
    use super::{parse_lss_node_id, parse_size};

    #[test]
    fn lss_node_ids_are_read_as_every_node_id_is() {
        assert_eq!(parse_lss_node_id("5"), Ok(5));
        assert_eq!(parse_lss_node_id("0x7F"), Ok(127));
        assert_eq!(parse_lss_node_id("255"), Ok(255));
        assert_eq!(parse_lss_node_id("0xFF"), Ok(255));
        for refused in ["0", "128", "254", "256", "0x100", "-1", "five", ""] {
            assert!(parse_lss_node_id(refused).unwrap_err().contains("use 1 to 127, or 255"), "{refused}");
        }
    }

    #[test]
    fn sizes_parse_in_binary_multiples_up_to_32_bits() {
        assert_eq!(parse_size("4096"), Ok(4096));
        assert_eq!(parse_size("64k"), Ok(64 << 10));
        assert_eq!(parse_size("16M"), Ok(16 << 20));
        assert_eq!(parse_size("16MiB"), Ok(16 << 20));
        assert_eq!(parse_size("1G"), Ok(1 << 30));
        assert_eq!(parse_size("4294967295"), Ok(u32::MAX as usize));
        assert!(parse_size("4G").unwrap_err().contains("over 4G - 1"));
        assert!(parse_size("2x").unwrap_err().contains("unknown unit"));
        assert!(parse_size("M").is_err());
        assert!(parse_size("99999999999999999999999").is_err());
    }
}
