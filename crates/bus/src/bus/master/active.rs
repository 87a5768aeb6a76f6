//! One SDO transfer of a batch in flight: its client, its deadlines, its retries.

use crate::canopen::sdo::SdoClient;
use crate::error::Error;
use std::time::Instant;

/// One SDO transfer in flight.
pub(super) struct Active {
    pub(super) slot: usize,
    pub(super) client: SdoClient,
    pub(super) started: Instant,
    /// No progress by then ends the transfer; only answers that advance it move this on.
    pub(super) idle_deadline: Instant,
    /// The transfer ends by then however busy the device keeps it (`SdoClient::time_budget`).
    pub(super) total_deadline: Instant,
    /// Whether the server has answered at all: a node that never did gets no abort frame.
    pub(super) heard: bool,
    /// Attempts left after this one (`SdoOptions::retries`).
    pub(super) retries_left: u8,
    /// Times the transfer was started, this one included: said when none was answered.
    pub(super) requests: u8,
    /// How the first attempt the device answered ended: said in the end when the later
    /// attempts got no answer at all, as it tells more (how far the transfer came).
    pub(super) answered_attempt: Option<Error>,
    /// Set once the user asked to stop: the transfer ends by then, whatever else says.
    pub(super) stop_by: Option<Instant>,
    /// When to ask again, not having heard anything ([`SdoOptions::ask_again_after`]).
    pub(super) ask_again_at: Option<Instant>,
    /// When the last request sent will have left the bus.
    pub(super) last_left: Instant,
}

impl Active {
    pub(super) fn deadline(&self) -> Instant {
        let own = self.idle_deadline.min(self.total_deadline);
        self.stop_by.map_or(own, |by| own.min(by))
    }

    /// When this read is asked again, while it may be: it has heard nothing, the user has not
    /// asked to stop, and it has attempts left. A time that no longer applies must not stay
    /// a deadline of the batch's wait: it would be always past, and the wait would spin.
    pub(super) fn asks_again_at(&self) -> Option<Instant> {
        self.ask_again_at.filter(|_| !self.heard && self.stop_by.is_none() && self.retries_left > 0)
    }
}
