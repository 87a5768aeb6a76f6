//! Nothing answered: the nodes, or the link? An slcan adapter set to another bit rate than
//! the bus's hears nothing and says so only in its status flags (its frames went
//! unacknowledged). `scan` (no node at all) and SDO transfers (no answer from the node)
//! both ask the link through here, so the two say the same and end the same way (exit 5).

use crate::bus::Bus;
use crate::error::{Error, LinkError, Result};

/// After a wait that nothing answered: the link's own evidence that nothing could (the
/// adapter reports bus errors), with how to give the bus's bit rate; `Ok` when the link
/// has none, or cannot tell.
pub fn check(bus: &mut dyn Bus) -> Result<()> {
    bus.check_link().map_err(|e| match e.root() {
        Error::Link(LinkError::AdapterBusError { port, .. }) => {
            let hint = bit_rate_hint(port);
            e.with_hint(hint)
        }
        _ => e,
    })
}

/// An SDO transfer's outcome; one that nobody answered becomes the link's failure when
/// the link has one to tell ([`check`]).
pub fn sdo<T>(bus: &mut dyn Bus, outcome: Result<T>) -> Result<T> {
    match outcome {
        Err(e) if e.is_timeout() => {
            check(bus)?;
            Err(e)
        }
        other => other,
    }
}

/// `; an adapter at another bit rate than the bus's ...`, with the address to give.
fn bit_rate_hint(port: &str) -> String {
    // The address without its rate: `slcan:/dev/ttyACM0@250k` -> `slcan:/dev/ttyACM0`.
    let base = port.split_once('@').map_or(port, |(base, _)| base);
    let rates: Vec<String> = crate::slcan::wire::BIT_RATES.iter().map(|(_, k)| crate::connect::kbit_text(*k)).collect();
    format!(
        "; frames nobody acknowledges are what an adapter at another bit rate than the bus's sees: give the \
         bus's rate in the address, --bus {base}@RATE (RATE one of {}), or bus = \"{base}@RATE\" in canctl.toml",
        rates.join(" ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hint_gives_the_address_without_its_rate() {
        let hint = bit_rate_hint("slcan:/dev/ttyACM0@250k");
        assert!(hint.contains("--bus slcan:/dev/ttyACM0@RATE"), "{hint}");
        assert!(hint.contains("bus = \"slcan:/dev/ttyACM0@RATE\" in canctl.toml"), "{hint}");
        assert!(hint.contains(" 500k ") && hint.contains(" 1M"), "{hint}");
    }
}
