//! Fastscan (CiA 305): find one device without a node-id by its identity, bit by bit, at a
//! pace measured from the bus.

use crate::bus::lss::LssMaster;
use crate::bus::Bus;
use crate::cancel::Cancel;
use crate::canopen::lss::{FastscanError, Pace};
use crate::error::{Error, Result};
use crate::ops::progress::Progress;
use serde::Serialize;
use std::time::Duration;

use super::identified::Identified;

/// How fastscan paces itself, and what it already knows.
#[derive(Clone, Debug)]
pub struct FastscanOptions {
    /// The first probe's window, when no step is given.
    pub timeout: Duration,
    /// Wait this long for each answer instead of learning it from the devices (lengthened
    /// only if answers come later still).
    pub step: Option<Duration>,
    /// Identity parts known in advance: not searched.
    pub vendor: Option<u32>,
    /// The product code, when known.
    pub product: Option<u32>,
    /// The revision number, when known.
    pub revision: Option<u32>,
}

impl FastscanOptions {
    /// A search of every identity part, its pace learnt from the devices; `timeout` for the first probe.
    pub fn new(timeout: Duration) -> FastscanOptions {
        FastscanOptions { timeout, step: None, vendor: None, product: None, revision: None }
    }

    pub(super) fn given(&self) -> [Option<u32>; 4] {
        [self.vendor, self.product, self.revision, None]
    }

    pub(super) fn pace(&self) -> Pace {
        self.step.map_or_else(|| Pace::measured(self.timeout), |step| Pace::fixed(step, self.timeout))
    }
}

/// The pace a fastscan used and what it was learned from.
#[derive(Clone, Debug, Serialize)]
pub struct PaceUsed {
    /// The longest step waited.
    pub step_ms: u64,
    /// The slowest answer seen.
    pub slowest_answer_ms: Option<f64>,
    /// How often answers came later than the step and it was lengthened.
    pub escalations: u32,
}

impl From<&Pace> for PaceUsed {
    fn from(p: &Pace) -> PaceUsed {
        PaceUsed {
            step_ms: p.longest_step().as_millis() as u64,
            slowest_answer_ms: p.slowest().map(|s| s.as_secs_f64() * 1e3),
            escalations: p.escalations(),
        }
    }
}

/// A device without a node-id, found by fastscan.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Found {
    /// The device's LSS identity.
    #[serde(flatten)]
    pub identity: Identified,
    /// Fastscan requests sent.
    pub steps: u32,
    /// The longest step waited, in ms.
    pub step_ms: u64,
    /// The pace used and what it was learnt from.
    pub pace: PaceUsed,
    /// How long the search took, in ms.
    pub elapsed_ms: u64,
}

pub(super) fn fastscan_error(error: FastscanError, pace: &Pace) -> Error {
    Error::Fastscan { error, step: pace.longest_step() }
}

/// Fastscan requests for one identity when all goes well: a reset, then 32 bits and a
/// confirmation for each part not given, one request for each part given. A bar's length,
/// not a limit: a search that has to slow down takes more.
pub(super) fn fastscan_steps(given: [Option<u32>; 4]) -> u64 {
    1 + given.iter().map(|g| if g.is_some() { 1 } else { 33 }).sum::<u64>()
}

/// Find the identity of one device without a node-id, bit by bit. The device found is
/// sent back to waiting state, unchanged.
pub fn fastscan(bus: &mut dyn Bus, o: &FastscanOptions, interrupted: &Cancel) -> Result<Found> {
    fastscan_shown(bus, o, interrupted, &mut crate::ops::progress::Silent)
}

/// [`fastscan`], each request a step on `progress` (the search takes 13 s on slow devices).
pub fn fastscan_shown(
    bus: &mut dyn Bus,
    o: &FastscanOptions,
    interrupted: &Cancel,
    progress: &mut dyn Progress,
) -> Result<Found> {
    let start = bus.now();
    let mut m = LssMaster::new(bus, o.timeout);
    let len = fastscan_steps(o.given());
    progress.start("fastscan", len);
    let result = m.fastscan(o.pace(), o.given(), interrupted, &mut |sent| progress.advance(sent.min(len)));
    progress.finish();
    // The device found is in configuration state: whatever happened, every device goes
    // back to waiting, unchanged.
    let left = m.leave();
    let elapsed = m.bus().now().saturating_duration_since(start);
    let outcome = result?;
    left?;
    let Some(outcome) = outcome else { return Err(Error::Interrupted) };
    let id = outcome.found.map_err(|e| fastscan_error(e, &outcome.pace))?;
    let pace = PaceUsed::from(&outcome.pace);
    let (identity, steps, elapsed_ms) = (Identified(id), outcome.steps, elapsed.as_millis() as u64);
    Ok(Found { identity, steps, step_ms: pace.step_ms, pace, elapsed_ms })
}
