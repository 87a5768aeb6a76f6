//! How long a scan's probes wait for answers: the shortest window accepted, the one that
//! waits for slow devices too, and the check of a window asked for.

use crate::error::{Error, Result};
use std::time::Duration;

/// The shortest quiet window a scan accepts: no device answers a probe sooner (see
/// [`crate::settings::MIN_TIMEOUT`]); a shorter one loses nodes and says nothing.
pub(crate) const MIN_WINDOW: Duration = crate::settings::MIN_TIMEOUT;

/// The window that waits for slow devices too (they answer up to 80 ms late): a scan
/// with a shorter one may have missed some, so it does not stand for the bus.
pub const FULL_WINDOW: Duration = Duration::from_millis(100);

/// Refuses a window no device can answer or be heard within: every command that probes
/// (scan, health, network) or listens (doctor, its sweep) waits at least `MIN_WINDOW`.
pub fn check_window(window: Duration) -> Result<()> {
    let (ms, min) = (window.as_millis(), MIN_WINDOW.as_millis());
    if window < MIN_WINDOW {
        return Err(Error::Usage(format!(
            "a window of {ms} ms is shorter than devices take to answer (what they say would be lost without a word); use at least {min}ms"
        )));
    }
    Ok(())
}
