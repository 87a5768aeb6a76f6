//! Fastscan (CiA 305 §8.4.3), the master side, sans I/O: the state machine that finds one
//! device without a node-id bit by bit. What it does when answers go missing or come late
//! follows `policy`.

use super::policy::{Pace, BACKTRACKS, MAX_SEARCHES, REPEATS, SEARCH_BUDGET, STEP_FLOOR};
use super::wire::{is_answer, Identity, Inquiry, Request, FASTSCAN_RESET};
use std::time::Duration;

/// Why a fastscan found no device.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
// Exhaustive on purpose: canctl words every variant, and the compiler says when one is new.
pub enum FastscanError {
    /// Nobody answered: no non-configured device in waiting state.
    NoDevice,
    /// A part that every bit matched was not confirmed, even with the longest step:
    /// devices changed meanwhile, or frames were lost.
    Unconfirmed(u8),
    /// No device without a node-id has this part (given by the user) of its identity.
    NoMatch {
        /// The identity part (0 vendor .. 3 serial).
        part: u8,
        /// The value asked for.
        value: u32,
    },
    /// A device answered once, then no more, even with the longest step.
    Lost,
}

/// What the fastscan driver wants done next.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum FastscanNext {
    /// Send this request and collect its answers.
    Send(Ask),
    /// The device found; it is in configuration state now.
    Found(Identity),
    /// The search ended without a device.
    Failed(FastscanError),
}

/// One request and how to wait for its answers.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Ask {
    /// The request to send.
    pub request: Request,
    /// The command specifier an answer must carry.
    pub expect: u8,
    /// How long after sending answers count.
    pub window: Duration,
    /// After the first answer, wait this much longer for others (capped by the window);
    /// `None`: collect every answer within the window.
    pub settle: Option<Duration>,
}

/// One identity part, as far as the search knows it.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Part {
    Unknown,
    /// Given by the user: confirmed in one step, never searched.
    Given(u32),
    /// Found bit by bit and confirmed.
    Found(u32),
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Phase {
    /// "Identify non-configured remote slave" with a generous window: is anybody there,
    /// and how late do they answer?
    Probe,
    /// Fastscan reset: every non-configured device takes part again from part 0.
    Reset,
    /// Asking whether bit `n` of the current part is 0 (the bits above as found).
    Bit(u8),
    /// The current part's whole value, bit-checked 0: the matching devices move on.
    Confirm,
    /// Part `n` of the identity found, asked of the device in configuration state: a
    /// fastscan answer says nothing of the request it answers, so one held up into the
    /// serial's confirmation "confirms" a value nobody has. The device's own answer does.
    Verify(u8),
    /// Nobody answered the reset at the learned pace: ask once more with a long window
    /// before saying nobody is there.
    FinalProbe,
    /// The last part's confirmation went unanswered: the device may have taken it (and
    /// its answer been lost), so it is in configuration state, out of every later search,
    /// and would take the next device's node-id too. Every device back to waiting state
    /// (no answer to this) before the search goes again.
    Waiting,
    Over,
}

/// Fastscan (CiA 305 §8.4.3), the master side, sans I/O: says which request to send and
/// how long to wait; the caller reports the answers with their times. Finds the whole
/// identity of one non-configured device in waiting state (133 fastscan requests when
/// nothing is known), skipping the parts the user gives. A part found bit by bit and not
/// confirmed (an answer lost, or late into another request's window) is searched again,
/// keeping the parts found; the step is lengthened only on evidence of lateness (an answer
/// seen later than the step, or one that came between windows), since a longer step
/// brings no lost answer back. At most [`MAX_SEARCHES`] searches and [`SEARCH_BUDGET`].
#[derive(Clone, Debug)]
pub struct Fastscan {
    pace: Pace,
    parts: [Part; 4],
    sub: u8,
    /// The value of the current part as far as searched.
    value: u32,
    phase: Phase,
    outcome: Option<Result<Identity, FastscanError>>,
    /// Fastscan requests sent.
    steps: u32,
    /// Whether any device answered so far: silence afterwards is lateness or loss.
    seen: bool,
    /// How many times the current request was sent again after a silence ([`REPEATS`]).
    repeats: u32,
    /// How many times the search started again from a reset ([`MAX_SEARCHES`]).
    searches: u32,
    /// The bus time waited for answers so far ([`SEARCH_BUDGET`]).
    waited: Duration,
    /// A fastscan answer came between two windows (late for its own): the driver says so.
    late: bool,
    /// How many times the current part was searched again from a bit ([`BACKTRACKS`]).
    backtracks: u32,
    /// How many times somebody answered "anybody there?" after the reset went unanswered
    /// (three times): more than [`REPEATS`] is no loss, the answers are not the device's.
    unanswered_resets: u32,
    /// Another device answered the verification ([`Fastscan::crowded`]).
    crowded: bool,
}

impl Fastscan {
    /// `given`: identity parts (vendor, product, revision, serial) already known.
    pub fn new(pace: Pace, given: [Option<u32>; 4]) -> Fastscan {
        let phase = if pace.known() { Phase::Reset } else { Phase::Probe };
        Fastscan {
            pace,
            parts: given.map(|g| g.map_or(Part::Unknown, Part::Given)),
            sub: 0,
            value: 0,
            phase,
            outcome: None,
            steps: 0,
            seen: false,
            repeats: 0,
            searches: 0,
            waited: Duration::ZERO,
            late: false,
            unanswered_resets: 0,
            backtracks: 0,
            crowded: false,
        }
    }

    /// Whether a device other than the one found answered the verification: it is in
    /// configuration state too (it missed a switch back to waiting), and would take the
    /// node-id meant for the device found.
    pub fn crowded(&self) -> bool {
        self.crowded
    }

    /// Fastscan requests sent so far.
    pub fn steps(&self) -> u32 {
        self.steps
    }

    /// The pace the search is at: how long it waits for answers.
    pub fn pace(&self) -> &Pace {
        &self.pace
    }

    /// The pace learned, for the next search on the same bus.
    pub fn into_pace(self) -> Pace {
        self.pace
    }

    /// LSS frames that came between two requests' windows (the driver drains them before
    /// each request): a fastscan answer among them came later than its window allowed,
    /// which is evidence of lateness.
    pub fn on_strays(&mut self, frames: &[[u8; 8]]) {
        self.late |= frames.iter().any(|f| is_answer(f, 0x4F));
    }

    /// Whether answers are known to come later than the step: one came between windows,
    /// or the step is the user's and shorter than answers seen in a longer window (a
    /// probe). A learned step follows the answers by itself.
    fn lateness_seen(&self) -> bool {
        self.late || (self.pace.fixed.is_some() && self.pace.slowest.is_some_and(|s| s > self.pace.step()))
    }

    /// What to do next, given the answers fed so far.
    pub fn next(&self) -> FastscanNext {
        if let Some(outcome) = self.outcome {
            return outcome.map_or_else(FastscanNext::Failed, FastscanNext::Found);
        }
        let fastscan = |request: Request| Ask {
            request,
            expect: 0x4F,
            window: self.pace.step(),
            settle: Some(self.pace.settle()),
        };
        let probe = |window| Ask { request: Request::IdentifyNonConfigured, expect: 0x50, window, settle: None };
        let reset = fastscan(Request::Fastscan { id: 0, bit_checked: FASTSCAN_RESET, sub: 0, next: 0 });
        let sub = self.sub;
        FastscanNext::Send(match self.phase {
            Phase::Probe => probe(self.pace.probe_window()),
            Phase::FinalProbe => probe(self.pace.final_window()),
            Phase::Reset if !self.pace.known() => Ask { window: self.pace.probe_window(), ..reset },
            Phase::Reset => reset,
            Phase::Bit(bit) => fastscan(Request::Fastscan { id: self.value, bit_checked: bit, sub, next: sub }),
            Phase::Waiting => Ask {
                request: Request::SwitchGlobal { configuration: false },
                expect: 0,
                window: STEP_FLOOR,
                settle: None,
            },
            Phase::Verify(part) => {
                let inquiry = [Inquiry::Vendor, Inquiry::Product, Inquiry::Revision, Inquiry::Serial][part as usize];
                Ask { expect: inquiry.cs(), ..fastscan(Request::Inquire(inquiry)) }
            }
            Phase::Confirm | Phase::Over => {
                fastscan(Request::Fastscan { id: self.value, bit_checked: 0, sub, next: (sub + 1) % 4 })
            }
        })
    }

    /// The answers to the request `next` asked for: each with the time it came after the
    /// request was sent. Frames with another command specifier are not answers; answers
    /// after the window are late: they lengthen the step and the request is asked again.
    pub fn on_answers(&mut self, answers: &[(Duration, [u8; 8])]) {
        let FastscanNext::Send(ask) = self.next() else { return };
        let valid: Vec<Duration> = answers.iter().filter(|(_, d)| is_answer(d, ask.expect)).map(|(t, _)| *t).collect();
        for t in &valid {
            self.pace.observe(*t);
        }
        if matches!(ask.request, Request::Fastscan { .. }) {
            self.steps += 1;
            self.pace.longest_used = self.pace.longest_used.max(ask.window);
        }
        // What the driver waited: the window, or up to the settle after the first answer.
        let first = valid.iter().filter(|t| **t <= ask.window).min();
        self.waited += match (ask.settle, first) {
            (Some(settle), Some(first)) => (*first + settle).min(ask.window),
            _ => ask.window,
        };
        let in_time = valid.iter().any(|t| *t <= ask.window);
        if !in_time && !valid.is_empty() {
            // Only late answers: what silence would mean is not true. Ask again, slower.
            self.repeats = 0;
            if !self.pace.escalate() {
                self.fail(FastscanError::Lost);
            }
            return;
        }
        self.seen |= in_time;
        if let Phase::Verify(part) = self.phase {
            let found = self.found().part(part);
            let held: Vec<u32> = answers
                .iter()
                .filter(|(t, d)| *t <= ask.window && is_answer(d, ask.expect))
                .map(|(_, d)| u32::from_le_bytes([d[1], d[2], d[3], d[4]]))
                .collect();
            // Devices an earlier search left in configuration state answer too.
            let verified = held.contains(&found);
            self.crowded |= held.iter().any(|v| *v != found);
            if !verified && self.repeats < REPEATS {
                self.repeats += 1;
                return;
            }
            if verified && self.repeats > 0 {
                self.pace.loss_seen = true;
            }
            self.repeats = 0;
            match verified {
                true if part == 3 => {
                    self.outcome = Some(Ok(self.found()));
                    self.phase = Phase::Over;
                }
                true => self.phase = Phase::Verify(part + 1),
                // Nobody in configuration state has it: the serial was not the device's.
                false => self.unconfirmed(3),
            }
            return;
        }
        // Silence where an answer is due: first ask again, at the same step (a lost frame).
        // Silence to a bit check means a 1, or, once this bus has lost frames, perhaps a
        // lost answer: asked once more then.
        let repeats = match self.phase {
            Phase::Confirm | Phase::FinalProbe => REPEATS,
            Phase::Reset if self.seen => REPEATS,
            Phase::Bit(_) if self.pace.loss_seen => 1,
            _ => 0,
        };
        if !in_time && self.repeats < repeats {
            self.repeats += 1;
            return;
        }
        if in_time && self.repeats > 0 {
            self.pace.loss_seen = true;
        }
        self.repeats = 0;
        match self.phase {
            Phase::Probe | Phase::Waiting => self.phase = Phase::Reset,
            // Somebody is there, and did not answer the reset (lost three times, or late).
            Phase::FinalProbe if in_time => {
                // Late answers explain it (and lengthen the step); else it must not go on.
                self.unanswered_resets += u32::from(!self.lateness_seen());
                match self.unanswered_resets > REPEATS {
                    true => self.fail(FastscanError::Lost),
                    false => self.search_again_or(FastscanError::Lost),
                }
            }
            // A device answered earlier in this search and no more: it left.
            Phase::FinalProbe if self.seen => self.fail(FastscanError::Lost),
            Phase::FinalProbe => self.fail(FastscanError::NoDevice),
            Phase::Reset if in_time => {
                self.sub = 0;
                self.start_part();
            }
            Phase::Reset if !self.seen && !self.pace.known() => self.fail(FastscanError::NoDevice),
            Phase::Reset => self.phase = Phase::FinalProbe,
            Phase::Bit(bit) => {
                // No answer to "is bit `bit` 0?": every device still in the search has a 1.
                if !in_time {
                    self.value |= 1 << bit;
                }
                self.phase = if bit == 0 { Phase::Confirm } else { Phase::Bit(bit - 1) };
            }
            Phase::Confirm if in_time => {
                self.backtracks = 0;
                if self.parts[self.sub as usize] == Part::Unknown {
                    self.parts[self.sub as usize] = Part::Found(self.value);
                }
                if self.sub == 3 {
                    // The device that matched the serial is in configuration state now,
                    // if the answer was to this request.
                    self.phase = Phase::Verify(0);
                } else {
                    self.sub += 1;
                    self.start_part();
                }
            }
            Phase::Confirm => self.backtrack(),
            Phase::Verify(_) | Phase::Over => {}
        }
    }

    /// The identity as searched and confirmed.
    fn found(&self) -> Identity {
        let v = |p: Part| match p {
            Part::Given(v) | Part::Found(v) => v,
            Part::Unknown => unreachable!("every part confirmed"),
        };
        let [vendor, product, revision, serial] = self.parts.map(v);
        Identity { vendor, product, revision, serial }
    }

    /// The confirmation of a part searched bit by bit went unanswered. When a bit check's
    /// answer is lost, that bit reads 1, and every check below it, matching nobody now,
    /// reads 1 too: the lost one is in the trailing run of ones. An answer late into
    /// another check's window makes a bit read 0, and every bit below it 1: it is the 0
    /// just above that run. Those bits are checked again (the bits above kept; a slave
    /// keeps its place in the search between checks), a few times before the whole part
    /// is searched again from a reset. Not the serial: its confirmation may have put the
    /// device in configuration state, its answer lost, and only a reset takes it back
    /// before another device is found.
    fn backtrack(&mut self) {
        if self.sub == 3 || self.parts[self.sub as usize] != Part::Unknown || self.backtracks >= BACKTRACKS {
            return self.unconfirmed(self.sub);
        }
        self.backtracks += 1;
        self.pace.loss_seen = true;
        let top = self.value.trailing_ones().min(31);
        self.value &= !((2u64 << top) - 1) as u32;
        self.phase = Phase::Bit(top as u8);
    }

    /// Part `sub` was not confirmed: a late answer made a bit look like 1 (or a device
    /// left). Search this part again, from a reset, keeping the parts before it.
    fn unconfirmed(&mut self, sub: u8) {
        self.backtracks = 0;
        let error = match self.parts[sub as usize] {
            Part::Given(value) => FastscanError::NoMatch { part: sub, value },
            _ => FastscanError::Unconfirmed(sub),
        };
        if let Part::Found(_) = self.parts[sub as usize] {
            self.parts[sub as usize] = Part::Unknown;
        }
        // Confirmations repeated in vain: a bit check's answer was lost (or came late).
        self.pace.loss_seen = true;
        self.search_again_or(error);
        if sub == 3 && self.phase == Phase::Reset {
            self.phase = Phase::Waiting;
        }
    }

    fn start_part(&mut self) {
        match self.parts[self.sub as usize] {
            Part::Given(v) | Part::Found(v) => {
                self.value = v;
                self.phase = Phase::Confirm;
            }
            Part::Unknown => {
                self.value = 0;
                self.phase = Phase::Bit(31);
            }
        }
    }

    /// Start over from a reset, with a longer step if answers are known to come late; or
    /// fail with `error` when the searches or the time are used up, or the step can grow
    /// no more.
    fn search_again_or(&mut self, error: FastscanError) {
        self.searches += 1;
        if self.searches > MAX_SEARCHES || self.waited >= SEARCH_BUDGET {
            return self.fail(error);
        }
        if self.lateness_seen() {
            self.late = false;
            if !self.pace.escalate() {
                return self.fail(error);
            }
        }
        self.phase = Phase::Reset;
    }

    fn fail(&mut self, error: FastscanError) {
        self.outcome = Some(Err(error));
        self.phase = Phase::Over;
    }
}

#[cfg(test)]
mod tests;
