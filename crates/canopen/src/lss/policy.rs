//! How LSS copes with a bus that loses frames and devices that answer late, in one place:
//! how often a missing answer is asked again, how a search starts over and when it gives
//! up, how many empty searches make "nobody waits", and the fastscan step (`Pace`),
//! learned from the answers and lengthened only when they come later than it. A lost
//! answer is not a late one: a longer step cannot bring it back, asking again can.

use std::collections::VecDeque;
use std::time::Duration;

/// The shortest fastscan step: enough for slaves on the same machine or a quiet bus.
pub const STEP_FLOOR: Duration = Duration::from_millis(10);
/// The longest: a slave slower than this is broken, not slow.
pub const STEP_CEILING: Duration = Duration::from_secs(2);
/// How many times a search may lengthen its step (or, at a fixed step, retry) before it
/// gives up.
pub const MAX_ESCALATIONS: u32 = 4;
/// How many more times a request whose answer is missing where one is due (a confirmation,
/// a reset, the last "anybody there?") is sent before the silence counts: a frame lost on
/// the way, to or from the slaves, is not a slow slave, and asking again brings the answer
/// back where a longer step cannot.
pub const REPEATS: u32 = 2;
/// How many times one fastscan may search again from a reset (a part not confirmed, a
/// device that answered the last "anybody there?" but not the reset) before it gives up:
/// under heavy loss every search has a fair chance, and none is certain.
pub const MAX_SEARCHES: u32 = 24;
/// How many times a part whose confirmation went unanswered is searched again from the
/// bit that was likely lost, before the whole part is searched again from a reset.
pub const BACKTRACKS: u32 = 4;
/// The bus time one fastscan may spend waiting for answers: one whole search at the
/// longest step. Searches again at a long step run out of this before [`MAX_SEARCHES`].
pub const SEARCH_BUDGET: Duration = Duration::from_secs(2 * 133);
/// How many of the latest answer times the step is learned from.
const RECENT_ANSWERS: usize = 64;

/// How long fastscan waits for answers: learned from the slaves' own answer times (or
/// fixed by the user), lengthened when answers turn out to come later than that.
#[derive(Clone, Debug)]
pub struct Pace {
    pub(super) fixed: Option<Duration>,
    /// The slowest answer seen so far, timed from its request.
    pub(super) slowest: Option<Duration>,
    /// The latest answer times: the step follows these, so that one answer held up once
    /// (a busy bus, a busy host) does not slow every later step.
    recent: VecDeque<Duration>,
    pub(super) escalations: u32,
    /// The window of the first probe, before anything is known.
    probe_window: Duration,
    /// The longest step used so far.
    pub(super) longest_used: Duration,
    /// Frames were lost on this bus (a request asked again was answered, a part had to be
    /// searched again): from then on a silent bit check is asked once more too.
    pub(super) loss_seen: bool,
}

impl Pace {
    /// A pace still to be measured; the first probe waits `probe_window`.
    pub fn measured(probe_window: Duration) -> Pace {
        Pace {
            fixed: None,
            slowest: None,
            recent: VecDeque::new(),
            escalations: 0,
            probe_window: probe_window.clamp(STEP_FLOOR, STEP_CEILING),
            longest_used: Duration::ZERO,
            loss_seen: false,
        }
    }

    /// The step the user chose (`--step`): used instead of one learned from the answer
    /// times, and lengthened only when answers come later than it.
    pub fn fixed(step: Duration, probe_window: Duration) -> Pace {
        Pace { fixed: Some(step), ..Pace::measured(probe_window) }
    }

    /// Whether a step can be derived yet.
    pub fn known(&self) -> bool {
        self.fixed.is_some() || self.slowest.is_some()
    }

    /// A slave answered `after` its request was sent.
    pub fn observe(&mut self, after: Duration) {
        self.slowest = Some(self.slowest.map_or(after, |s| s.max(after)));
        if self.recent.len() == RECENT_ANSWERS {
            self.recent.pop_front();
        }
        self.recent.push_back(after);
    }

    /// The slowest and fastest of the latest answers.
    pub(super) fn recent_range(&self) -> Option<(Duration, Duration)> {
        Some((*self.recent.iter().max()?, *self.recent.iter().min()?))
    }

    /// How long one fastscan step waits for an answer: half as long again as the slowest
    /// of the latest answers plus a margin, doubled for each escalation.
    pub fn step(&self) -> Duration {
        let base = match self.fixed {
            Some(step) => step,
            None => {
                let slowest = self.recent_range().map_or(self.probe_window, |(s, _)| s);
                (slowest * 3 / 2 + Duration::from_millis(5)).clamp(STEP_FLOOR, STEP_CEILING)
            }
        };
        (base * (1 << self.escalations.min(8))).min(STEP_CEILING.max(base))
    }

    /// After the first answer to a request, how much longer the others may come: the
    /// spread of the answer times seen and a quarter step more, so that a straggler does
    /// not count for the next request.
    pub(crate) fn settle(&self) -> Duration {
        let spread = self.recent_range().map_or(Duration::ZERO, |(s, f)| s - f);
        (spread + (self.step() / 4).max(Duration::from_millis(2))).min(self.step())
    }

    pub(crate) fn probe_window(&self) -> Duration {
        self.probe_window
    }

    /// The window of the "is anybody still there?" probe before fastscan says nobody is:
    /// several times the slowest answer seen.
    pub(crate) fn final_window(&self) -> Duration {
        let several = self.recent_range().map_or(self.probe_window, |(s, _)| s * 4);
        several.max(self.step() * 2).clamp(STEP_FLOOR, STEP_CEILING)
    }

    /// Answers came later than the step allowed: lengthen it. False when no more.
    pub fn escalate(&mut self) -> bool {
        if self.escalations >= MAX_ESCALATIONS || self.step() >= STEP_CEILING {
            return false;
        }
        self.escalations += 1;
        true
    }

    /// How many times the pace was slowed since the start: each one a step that went unanswered.
    pub fn escalations(&self) -> u32 {
        self.escalations
    }

    /// The slowest answer seen so far.
    pub fn slowest(&self) -> Option<Duration> {
        self.slowest
    }

    /// The longest step a fastscan waited.
    pub fn longest_step(&self) -> Duration {
        self.longest_used
    }
}

/// How many searches in a row must find nobody before `assign` says no device waits: one
/// lost answer must not be taken for "every device has a node-id".
pub const NO_DEVICE_PROBES: u32 = 3;

#[cfg(test)]
mod tests {
    use super::*;

    const MS: Duration = Duration::from_millis(1);

    /// One answer held up once (a busy host) lengthens the step for a while, not for ever.
    #[test]
    fn the_step_follows_the_latest_answers() {
        let mut pace = Pace::measured(MS * 500);
        pace.observe(MS * 170);
        assert_eq!(pace.step(), MS * 260);
        for _ in 0..RECENT_ANSWERS {
            pace.observe(MS * 20);
        }
        assert_eq!(pace.step(), MS * 35);
        assert_eq!(pace.slowest(), Some(MS * 170), "reported as seen");
    }
}
