//! Nothing answered: the nodes, or the link? An slcan adapter set to another bit rate than
//! the bus's hears nothing and says so only in its status flags (its frames went
//! unacknowledged). `scan` (no node at all) and SDO transfers (no answer from the node)
//! both ask the link through here, so the two say the same and end the same way (exit 5).

use crate::bus::Bus;
use crate::error::{Error, Result};

/// After a wait that nothing answered: the link's own evidence that nothing could (the
/// adapter reports bus errors), as [`Error::NothingAnswered`], whose remedy is giving the
/// bus's bit rate; `Ok` when the link has none, or cannot tell.
pub fn check(bus: &mut dyn Bus) -> Result<()> {
    bus.check_link().map_err(|e| Error::NothingAnswered { error: Box::new(e) })
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
