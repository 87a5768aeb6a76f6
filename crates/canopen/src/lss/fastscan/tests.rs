//! The fastscan state machine against slaves on a virtual bus: pace, loss, lateness,
//! floods, bounds.

use super::*;
use crate::lss::policy::{MAX_ESCALATIONS, STEP_CEILING};
use crate::lss::slave::{Slave, SlaveCaps, SlaveState};
use crate::lss::wire::UNCONFIGURED;

const MS: Duration = Duration::from_millis(1);
const CAPS: SlaveCaps = SlaveCaps { store: true, bit_timing: true, fastscan_in_configuration: false };

fn three() -> [Identity; 3] {
    [
        Identity { vendor: 0x40, product: 0x4378_7800, revision: 0x312E_3031, serial: 0x0950_1302 },
        Identity { vendor: 0x40, product: 0x4378_7800, revision: 0x312E_3031, serial: 0x0950_1301 },
        Identity { vendor: 0x444, product: 0x2057, revision: 1, serial: 7 },
    ]
}

type Latency = Box<dyn FnMut(usize, u32) -> Option<Duration>>;
type Extra = Box<dyn FnMut(u32) -> Vec<(Duration, [u8; 8])>>;

/// A bus in virtual time, as a real one behaves: slaves take each request at once and
/// answer `latency` later (`None`: the answer is lost); an answer counts for whichever
/// request's window it arrives in, and one that arrives between windows is drained.
struct VirtualBus {
    slaves: Vec<Slave>,
    now: Duration,
    in_flight: Vec<(Duration, [u8; 8])>,
    /// (slave, request number) → answer latency.
    latency: Latency,
    /// Other frames on 0x7E4 after request number n, timed from it.
    extra: Extra,
    sent: u32,
}

impl VirtualBus {
    fn new(ids: &[Identity], latency: Latency) -> VirtualBus {
        VirtualBus {
            slaves: ids.iter().map(|i| Slave::new(*i, CAPS)).collect(),
            now: Duration::ZERO,
            in_flight: vec![],
            latency,
            extra: Box::new(|_| vec![]),
            sent: 0,
        }
    }

    fn exchange(&mut self, ask: &Ask) -> Vec<(Duration, [u8; 8])> {
        let t0 = self.now;
        self.in_flight.retain(|(t, _)| *t >= t0);
        self.sent += 1;
        for i in 0..self.slaves.len() {
            if let (Some(a), _) = self.slaves[i].handle(ask.request, UNCONFIGURED) {
                if let Some(lat) = (self.latency)(i, self.sent) {
                    self.in_flight.push((t0 + lat, a.encode()));
                }
            }
        }
        for (t, f) in (self.extra)(self.sent) {
            self.in_flight.push((t0 + t, f));
        }
        self.in_flight.sort_by_key(|(t, _)| *t);
        let mut end = t0 + ask.window;
        let mut got = vec![];
        let mut answered = false;
        for (t, f) in &self.in_flight {
            if *t > end {
                break;
            }
            got.push((*t - t0, *f));
            if f[0] == ask.expect && !answered {
                answered = true;
                if let Some(settle) = ask.settle {
                    end = end.min(*t + settle);
                }
            }
        }
        self.now = end;
        self.in_flight.retain(|(t, _)| *t > end);
        got
    }

    fn run(&mut self, scan: &mut Fastscan) -> Result<Identity, FastscanError> {
        for _ in 0..5000 {
            match scan.next() {
                FastscanNext::Send(ask) => {
                    let answers = self.exchange(&ask);
                    scan.on_answers(&answers);
                }
                FastscanNext::Found(id) => return Ok(id),
                FastscanNext::Failed(e) => return Err(e),
            }
        }
        panic!("fastscan did not end");
    }
}

fn fixed_latency(ms: u64) -> Latency {
    Box::new(move |_, _| Some(MS * ms as u32))
}

fn fresh() -> Fastscan {
    Fastscan::new(Pace::measured(MS * 500), [None; 4])
}

/// Against several slaves at once the master finds the lowest identity, 133 fastscan
/// requests for a whole one; the found device is in configuration state and the next
/// search (with the pace already learned) finds the next.
#[test]
fn fastscan_finds_every_identity_in_133_steps() {
    let mut bus = VirtualBus::new(&three(), fixed_latency(0));
    let mut pace = Pace::measured(MS * 500);
    let mut found = vec![];
    for _ in 0..3 {
        let mut scan = Fastscan::new(pace, [None; 4]);
        let id = bus.run(&mut scan).unwrap();
        assert_eq!(scan.steps(), 133);
        let s = bus.slaves.iter().find(|s| s.identity == id).unwrap();
        assert_eq!(s.state, SlaveState::Configuration);
        found.push(id);
        pace = scan.into_pace();
        assert_eq!(pace.step(), STEP_FLOOR);
    }
    let mut want = three().to_vec();
    want.sort();
    assert_eq!(found, want);
    // Every device is configured: the reset is silent, and so is the last probe.
    let mut scan = Fastscan::new(pace, [None; 4]);
    assert_eq!(bus.run(&mut scan), Err(FastscanError::NoDevice));
    assert!(matches!(scan.next(), FastscanNext::Failed(FastscanError::NoDevice)));
}

#[test]
fn nobody_there_is_no_device_after_two_generous_probes() {
    let mut bus = VirtualBus::new(&[], fixed_latency(0));
    let mut scan = fresh();
    assert_eq!(bus.run(&mut scan), Err(FastscanError::NoDevice));
    assert_eq!(bus.sent, 2, "the probe and one reset");
    assert_eq!(bus.now, MS * 1000);
}

/// Slaves that answer 60 ms late (as real ones do): the probe measures it and every
/// step waits long enough, with no escalation.
#[test]
fn the_pace_is_learned_from_the_first_probe() {
    let mut bus = VirtualBus::new(&three(), fixed_latency(60));
    let mut scan = fresh();
    let id = bus.run(&mut scan).unwrap();
    assert_eq!(id, three()[1]);
    assert_eq!(scan.steps(), 133);
    assert_eq!(scan.pace().escalations(), 0);
    assert_eq!(scan.pace().step(), MS * 95);
    assert_eq!(scan.pace().longest_step(), MS * 95);
}

/// `--step 10ms` (the old default) against 60 ms slaves: every answer comes in the
/// next window, parts are not confirmed, and the step doubles until answers fit.
/// Slaves slower than the step can ever become: a bounded failure.
#[test]
fn a_fixed_step_too_short_is_lengthened_or_fails_bounded() {
    let mut bus = VirtualBus::new(&three(), fixed_latency(60));
    let mut scan = Fastscan::new(Pace::fixed(MS * 10, MS * 500), [None; 4]);
    assert_eq!(bus.run(&mut scan), Ok(three()[1]));
    assert_eq!(scan.pace().longest_step(), MS * 80);
    let mut bus = VirtualBus::new(&three(), fixed_latency(300));
    let mut scan = Fastscan::new(Pace::fixed(MS * 10, MS * 500), [None; 4]);
    let r = bus.run(&mut scan);
    assert!(matches!(r, Err(FastscanError::Unconfirmed(_) | FastscanError::Lost)), "{r:?}");
    assert_eq!(scan.pace().escalations(), MAX_ESCALATIONS);
    assert!(bus.sent < 1000);
}

/// One answer far later than the probe showed, once (it is lost to its window, as a
/// lost answer is): the bit looks like 1, the part is not confirmed, the confirmation
/// is asked twice more, then that part alone is searched again at the same step.
/// Lateness that goes on lengthens the step ([`a_fixed_step_too_short_is_lengthened_or_fails_bounded`]).
#[test]
fn a_late_answer_once_searches_that_part_again_at_the_same_step() {
    let id = three()[1];
    let latency: Latency = Box::new(|_, n| Some(if n == 60 { MS * 45 } else { MS * 5 }));
    let mut bus = VirtualBus::new(&[id], latency);
    let mut scan = fresh();
    assert_eq!(bus.run(&mut scan), Ok(id));
    assert_eq!(scan.pace().escalations(), 0);
    // Request 60 is in part 1 (the product): its confirmation three times, a reset,
    // part 0 confirmed in one step, part 1 searched again (33 steps, and its silent
    // bits asked twice now that a loss was seen); parts 2 and 3 likewise.
    assert!(scan.steps() > 133 + 2 + 1 + 1 + 33, "{}", scan.steps());
    assert!(scan.steps() < 2 * (133 + 2 + 1 + 1 + 33), "{}", scan.steps());
}

/// Seed 0x109bc6 of tests/dst/: an answer to a bit check of the serial held up
/// 45 ms (four short steps) made that bit look like 1, and arrived in the window of
/// the serial's confirmation, so a value no device has was "confirmed". Fastscan
/// answers carry nothing to tell which request they answer: the identity found is
/// asked of the device in configuration state before it is trusted, and searched
/// again when no device there has it.
#[test]
fn an_answer_late_into_a_confirmation_does_not_find_an_identity_nobody_has() {
    let id = three()[1];
    // Request 131 is the check of the serial's bit 2 (a 0 in 0x09501301): probe,
    // reset, three parts of 33, then bits 31 down to 3.
    let latency: Latency = Box::new(|_, n| Some(if n == 131 { MS * 45 } else { MS * 5 }));
    let mut bus = VirtualBus::new(&[id], latency);
    let mut scan = fresh();
    assert_eq!(bus.run(&mut scan), Ok(id));
    assert_eq!(bus.slaves[0].state, SlaveState::Configuration);
}

/// A lost answer makes a bit 1 as well: the same recovery.
#[test]
fn a_lost_answer_is_recovered() {
    let id = three()[0];
    let latency: Latency = Box::new(|_, n| (n != 110).then_some(MS * 3));
    let mut bus = VirtualBus::new(&[id], latency);
    let mut scan = fresh();
    assert_eq!(bus.run(&mut scan), Ok(id));
    assert!(scan.steps() > 133);
    assert_eq!(scan.pace().escalations(), 0, "a loss is not lateness");
}

/// Every answer twice (a device, or a gateway, repeating itself): still one answer.
#[test]
fn duplicated_answers_count_once() {
    let mut dup_bus = VirtualBus::new(&three(), Box::new(|_, _| Some(MS * 2)));
    let mut scan = fresh();
    let mut sent = 0;
    let id = loop {
        match scan.next() {
            FastscanNext::Send(ask) => {
                sent += 1;
                let mut answers = dup_bus.exchange(&ask);
                let copies = answers.clone();
                answers.extend(copies.iter().map(|(t, f)| (*t + MS, *f)));
                scan.on_answers(&answers);
            }
            FastscanNext::Found(id) => break id,
            FastscanNext::Failed(e) => panic!("{e:?}"),
        }
    };
    assert!(sent < 200);
    assert_eq!(id, three()[1]);
    assert_eq!(scan.steps(), 133);
}

/// Frames on 0x7E4 that are not fastscan answers (another command specifier: a
/// heartbeat-like byte, a stray "non-configured" answer, garbage) never count, however
/// many: with nobody there it is still "no device", in bounded time.
#[test]
fn bogus_frames_on_the_slave_id_never_count() {
    let flood = |_: u32| -> Vec<(Duration, [u8; 8])> {
        (0..200).map(|i| (MS * (i % 10) / 2, [[0x7F, 0x05, 0x50, 0x44][i as usize % 4], 0, 0, 0, 0, 0, 0, 0])).collect()
    };
    let mut bus = VirtualBus::new(&[], fixed_latency(0));
    bus.extra = Box::new(flood);
    let mut scan = fresh();
    // 0x50 is the answer the probe expects: the flood includes it, so the probe
    // "sees" devices, yet no fastscan reset is ever answered.
    let r = bus.run(&mut scan);
    assert!(matches!(r, Err(FastscanError::NoDevice | FastscanError::Lost)), "{r:?}");
    assert!(bus.sent < 20, "bounded: {} requests", bus.sent);
    // With real devices among the flood, the right one is found in 133 steps.
    let mut bus = VirtualBus::new(&three(), fixed_latency(1));
    bus.extra = Box::new(|_| (0..50).map(|i| (MS * i / 10, [0x7F, 5, 0, 0, 0, 0, 0, 0])).collect());
    let mut scan = fresh();
    assert_eq!(bus.run(&mut scan), Ok(three()[1]));
    assert_eq!(scan.steps(), 133);
}

/// Known vendor and product: those parts are confirmed in one step each.
#[test]
fn given_parts_are_confirmed_not_searched() {
    let mut bus = VirtualBus::new(&three(), fixed_latency(1));
    let mut scan = Fastscan::new(Pace::measured(MS * 500), [Some(0x444), Some(0x2057), None, None]);
    assert_eq!(bus.run(&mut scan), Ok(three()[2]));
    assert_eq!(scan.steps(), 1 + 1 + 1 + 33 + 33);
    // A vendor nobody has: refused after the bounded searches, by name. Nothing came
    // late: the step stays.
    let mut bus = VirtualBus::new(&three(), fixed_latency(1));
    let mut scan = Fastscan::new(Pace::measured(MS * 500), [Some(0x99), None, None, None]);
    assert_eq!(bus.run(&mut scan), Err(FastscanError::NoMatch { part: 0, value: 0x99 }));
    assert_eq!(scan.pace().escalations(), 0);
    assert!(bus.sent <= 2 + 4 * (MAX_SEARCHES + 1), "bounded: {} requests", bus.sent);
}

#[test]
fn every_answer_late_by_a_lot_stops_at_the_ceiling() {
    let mut bus = VirtualBus::new(&three(), Box::new(|_, n| Some(if n < 3 { MS } else { MS * 3000 })));
    let mut scan = fresh();
    let r = bus.run(&mut scan);
    assert!(r.is_err());
    assert!(scan.pace().longest_step() <= STEP_CEILING);
    assert!(bus.sent < 500);
}

/// Frames lost as an overloaded adapter or gateway loses them: each request (2 %) and
/// each answer (2 %) independently, drawn from `seed`; answers 15 ms late with a few
/// ms of jitter. Deterministic for a seed.
fn lossy(seed: u64) -> Latency {
    let draw = move |a: u64, b: u64| {
        // splitmix64 of (seed, a, b): a fixed, well-spread draw per frame.
        let mut z = seed ^ a.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ b.wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    Box::new(move |slave, n| {
        let request_lost = draw(n as u64, 1000) % 100 < 2;
        let answer_lost = draw(n as u64, slave as u64) % 100 < 2;
        let jitter = draw(n as u64, 2000 + slave as u64) % 4;
        (!request_lost && !answer_lost).then_some(MS * (15 + jitter as u32))
    })
}

/// `lss assign`'s search under 2 % frame loss (the field report: three slaves behind a
/// 15 ms path, one numbered, then "part 0 found but not confirmed, even with a 1013 ms
/// step"): a lost answer is not a late one, so the search repeats what was lost instead
/// of lengthening the step, and finds all three devices, then nobody, on every seed.
#[test]
fn fastscan_finds_every_device_under_two_percent_loss() {
    let mut failed = vec![];
    for seed in 0..200u64 {
        let mut bus = VirtualBus::new(&three(), lossy(seed));
        let mut pace = Pace::measured(MS * 500);
        let mut found = vec![];
        let outcome = loop {
            let mut scan = Fastscan::new(pace.clone(), [None; 4]);
            let r = bus.run(&mut scan);
            pace = scan.into_pace();
            match r {
                // Numbered, as assign does next: no longer one without a node-id.
                Ok(id) => {
                    bus.slaves.retain(|s| s.identity != id);
                    found.push(id)
                }
                Err(e) => break e,
            }
        };
        found.sort();
        let mut want = three().to_vec();
        want.sort();
        if outcome != FastscanError::NoDevice || found != want {
            failed.push((seed, found.len(), outcome, pace.longest_step()));
        }
    }
    assert!(failed.is_empty(), "{} of 200 seeds failed: {failed:?}", failed.len());
}

/// Seeds 0xfb02c and 0xf7686 of tests/dst/: one slave losing 20 % of its answers.
/// Parts went unconfirmed again and again, were taken for lateness, and the step
/// doubled four times (786–2,272 s of bus time): a longer step brings no lost answer
/// back. The step stays, and the search ends, found or failed, within its bound.
#[test]
fn heavy_loss_never_lengthens_the_step_and_the_search_is_bounded() {
    let id = three()[1];
    let mut found = 0;
    for seed in 0..40u64 {
        // The 2 % of `lossy`, and 20 % of the answers more: a fixed, well-spread draw each.
        let mut draws = lossy(seed);
        let mut n = 0u64;
        let latency: Latency = Box::new(move |slave, req| {
            n += 1;
            let draw = (n.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ seed.wrapping_mul(0xBF58_476D_1CE4_E5B9)) >> 32;
            draws(slave, req).filter(|_| !draw.is_multiple_of(5))
        });
        let mut bus = VirtualBus::new(&[id], latency);
        let mut scan = fresh();
        let r = bus.run(&mut scan);
        assert_eq!(scan.pace().escalations(), 0, "seed {seed}: {r:?}, a loss is not lateness");
        assert!(bus.now <= STEP_CEILING * 133, "seed {seed}: {:?} of bus time", bus.now);
        match r {
            Ok(got) => {
                assert_eq!(got, id, "seed {seed}");
                found += 1;
            }
            // Two first answers lost: nobody seen (assign asks three times before it
            // believes that).
            Err(e) => assert!(
                matches!(e, FastscanError::Unconfirmed(_) | FastscanError::Lost | FastscanError::NoDevice),
                "seed {seed}: {e:?}"
            ),
        }
    }
    eprintln!("found on {found} of 40 seeds");
    assert!(found >= 36, "found on {found} of 40 seeds");
}

/// A device that missed the switch back to waiting (a lossy path) is still in
/// configuration state when the next device is found: it answers the verification with its
/// own identity. The search says so, so that the set-id that follows is not taken by both.
#[test]
fn a_second_device_in_configuration_state_is_told() {
    let [a, b, c] = three();
    let mut bus = VirtualBus::new(&[a, b], fixed_latency(0));
    let mut scan = fresh();
    let found = bus.run(&mut scan).unwrap();
    assert!(!scan.crowded(), "only the device found is in configuration state");
    // Another device, numbered earlier, never left configuration state.
    let mut stuck = Slave::new(c, CAPS);
    stuck.state = SlaveState::Configuration;
    bus.slaves.push(stuck);
    for s in bus.slaves.iter_mut().filter(|s| s.identity == found) {
        s.state = SlaveState::Waiting;
    }
    let mut scan = Fastscan::new(scan.into_pace(), [None; 4]);
    bus.run(&mut scan).unwrap();
    assert!(scan.crowded());
}
