//! The clock of a test link on virtual time and the frames it has yet to deliver: a frame is
//! received once the clock has reached the time it arrives; waiting for nothing moves the
//! clock to the deadline.

use crate::frame::Frame;
use std::collections::VecDeque;
use std::time::Instant;

pub(crate) struct Timeline {
    pub(crate) now: Instant,
    arriving: VecDeque<(Instant, Frame)>,
}

impl Timeline {
    pub(crate) fn starting_now() -> Timeline {
        Timeline { now: crate::bus::clock::monotonic_now(), arriving: VecDeque::new() }
    }

    /// `frame` arrives at `at`: after the frames that arrive before it, or with it and were
    /// sent before it.
    pub(crate) fn arrive(&mut self, at: Instant, frame: Frame) {
        self.arriving.push_back((at, frame));
        self.arriving.make_contiguous().sort_by_key(|(at, _)| *at);
    }

    /// The next frame that arrives by `deadline`, the clock moved to its arrival; none, the
    /// clock moved to the deadline.
    pub(crate) fn recv(&mut self, deadline: Instant) -> Option<Frame> {
        match self.arriving.front() {
            Some((at, _)) if *at <= deadline => {
                self.now = self.now.max(*at);
                self.arriving.pop_front().map(|(_, f)| f)
            }
            _ => {
                self.now = self.now.max(deadline);
                None
            }
        }
    }

    pub(crate) fn sleep_until(&mut self, t: Instant) {
        self.now = self.now.max(t);
    }
}
