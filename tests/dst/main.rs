//! Deterministic simulation testing: every procedure, run through the library against a
//! seeded random simulated network (device mix, latency profile, bit rate) with a seeded
//! fault mix (loss, delay, duplicates, short frames, corrupt answers, babble, a device
//! muted mid-transfer, a reboot, a device missing canctl's frames, a stop request at a
//! random step), on virtual time. After
//! each run the devices are compared with the report:
//!
//! - the run ended within its bound in bus time;
//! - a run without faults and without a stop succeeded (exit 0);
//! - success means the devices hold what the report says (values read are the device's,
//!   values written are in the device, node-ids given are the devices', states reached are
//!   the devices');
//! - no node-id is held by two devices, and no device is left in LSS configuration state;
//! - a scan that ends ok lists every node that is there, unless nothing of it reached canctl
//!   after it was asked in each round of the probe (loss, damaged answers included);
//! - a failed or interrupted run's report matches the devices (what it says it did, they
//!   show).
//!
//! The same seed gives the same frames, byte for byte and at the same bus times. A failing
//! seed prints the command that replays it. `cargo test` runs [`TEST_SCENARIOS`] from
//! [`CI_START`]; CI runs 10,000 from there on the release build (`scripts/dst.sh 10000
//! 0x5EED0000`, in .ci/run). `CANCTL_DST_SCENARIOS=N` runs N scenarios
//! (`scripts/dst.sh N` for a million), `CANCTL_DST_SEED=S` just one. Counts are fixed, never
//! a wall-time budget: a loaded machine takes longer, it does not test less.

use canctl::bus::stoppable::Stoppable;
use canctl::bus::tap::AfterSdo;
use canctl::bus::{Bus, FrameLink, Master, SdoOptions};
use canctl::cancel::Cancel;
use canctl::canopen::cia402::{Goal, State as DriveState};
use canctl::canopen::lss::{Identity, STEP_CEILING};
use canctl::canopen::nmt::{self, Command};
use canctl::canopen::ObjAddr;
use canctl::frame::Frame;
use canctl::ops::{self, Silent};
use canctl::sim::timing::Rng;
use canctl::sim::{Profile, SimConfig, SimLink};
use canctl::{Error, Result};
use std::collections::BTreeMap;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

mod cases;
mod check;
mod run;
mod scenario;
mod tape;

use check::*;
use run::*;
use scenario::*;
use tape::*;

/// Seeds that once broke an invariant: each is run on every `cargo test`.
const FIXED: &[u64] = &[
    // drive enable: the answer to a controlword was lost; the report kept the state from
    // before it, which the drive had left (fixed: the walk reads the state back).
    0x5eed_053d,
    0x5eed_0621,
    // lss assign, one device losing 20 % of its answers: the answer to the search's first
    // probe was lost, and assign said every device had a node-id (fixed: silence is
    // believed when three searches in a row find nobody).
    0x5eed_0af1,
    // fastscan, a device's answers held up 45 ms one time in five: one answer to a bit
    // check of the serial arrived in the window of its confirmation, and a serial no
    // device has was "found" (fixed: the identity found is asked of the device in
    // configuration state before it is trusted).
    0x10_9bc6,
    // lss assign, a device whose answers are short one time in five: set-id went
    // unanswered three times, the device had taken node 20 all the same, and the error
    // said only that nobody answered (fixed: it says the device may hold the node-id, and
    // how to see).
    0x10_a00f,
    // lss assign, one device of four late by 135 ms one time in five, another babbling:
    // 421 s of bus time (450 s now), past the 5 minutes then allowed for every procedure.
    // The late answers spoil the search of the serial again and again, each search again
    // at the same step: slow, and within the rules of a search (the bound of an LSS search
    // follows them now: 133 requests a device at the step ceiling).
    0xf_ddda,
    // lss assign, a device whose answers are corrupt one time in five (slow devices,
    // 125 kbit/s): 2,272 s of bus time against a bound of 532 s. Parts not confirmed were
    // taken for lateness and the step doubled four times, which brings no lost answer back
    // (fixed: the step is lengthened only on evidence of lateness, a part not confirmed
    // is checked again from the bits a lost or late answer spoiled, and the searches of a
    // fastscan are bounded; 132 s now).
    0xf_7686,
    // fastscan, a device losing 20 % of its answers: 786 s against 532 s, the same way
    // (38 s now; 0xfddda above 230 s).
    0xf_b02c,
    // lss assign, a device missing frames (the fault `miss`, found at one in five): it missed the
    // switch back after its node-id and then the inquiry that would have shown it still in
    // configuration state; the next device found took its node-id with it, and both held
    // node 23 (fixed: a search that hears a second device in configuration state sends
    // everyone back and searches again).
    0x5eed_12f6,
    // network apply, the same with a device given its node-id by identity: two held 22.
    0x5eed_0ac0,
    // network set-baud, the drive missing the switch back to waiting after the new rate:
    // left in configuration state, exit 0 (fixed: the switch back is confirmed by two
    // unanswered inquiries, and sent again).
    0x5eed_1156,
    // health, a device answering on the next node's COB-ID and corrupting one answer in
    // five: the one request that asked it alone got a damaged answer, and the node whose
    // COB-ID it took was reported (fixed: each is asked alone as often as the probe asks).
    0x5eed_1a0d,
    // scan, the drive answering the probe with an upload without end, then aborting the
    // repeat: "answered only on the 2nd probe: frames are being lost", where no frame was
    // (fixed: a node whose earlier answer was malformed answered; only silence counts).
    0x5eed_0d81,
    // nmt stop, then the state asked at once, on a host that may hold canctl up 57 ms: the
    // sensor's beat due after it had heard the stop said pre-operational (the simulator
    // made the beats of the held-up time before it let the stop reach the devices; fixed:
    // in the order they happened).
    0x5eed_087f,
    // scan, the sensor rebooting on the probe (silent 300 ms while it booted, then its
    // boot-up): "answered only on the 2nd probe: frames are being lost", where none was
    // (fixed: a node whose boot-up was heard restarted, it lost nothing). Found by a run of
    // 100,000 from 0x7A110000.
    0x7a11_2ce4,
    // nmt stop, then the state asked at once, the stop sent while one of the sensor's beats
    // was on the wire or about to be: that beat, from before the stop, was believed (fixed:
    // beats count from when the frames ahead of a command, and one that lost arbitration to
    // it, have left). Found by a run of 3,000 once the stop was aimed at a beat.
    0x5eed_03b6,
    0x5eed_060e,
    0x5eed_072e,
    0x5eed_0830,
    // doctor and scan, a device answering a read by segments without end, once the harness
    // passed the link's frame time on as hardware links do: the read, heard, kept its time to
    // ask again, always past, and the batch's wait spun on it (on hardware a core burnt, on
    // virtual time no end). Fixed: a time to ask again applies while nothing was heard.
    0x5eed_0087,
    0x5eed_00a6,
    // health, a device answering on the next node's COB-ID and muted from its third frame
    // on (or rebooting on its first), on a host holding canctl up: the id it answered on
    // was reported not healthy, which the invariant called a node no device has. Nothing
    // could show whose answer it was (the device was silent when asked alone): the
    // invariant now allows that id to be said not healthy, never healthy. Found by a run of
    // 20,000 from 0x7A200000, and by CI's 10,000 once the tape passed the frame time on.
    0x7a20_13f8,
    0x5eed_0dc4,
    // network apply, a sensor missing one frame in ten, on a host holding canctl up: the
    // device given node 20 missed every switch back to waiting, was said to stay in
    // configuration state, and the next device selected took node 21 with it: two devices
    // on 21 (fixed: a node-id is given only when the device selected is alone in
    // configuration state). Found by a run of 60,000 from 0x3A000000.
    0x3a00_289b,
    // scan stopped by the user, a node asked again while canctl was held up: the answer to
    // the second request was not waited for, and the count said frames were lost (fixed: a
    // count the stop cut short says nothing). Same run.
    0x3a00_a4ad,
    // scan, a device answering by segments without end: the request for a segment waited
    // behind a hundred probes, its answer was waited for from when it was queued, and the
    // node was said to lose frames (fixed: from when it left the bus). Same run.
    0x3a00_e6b8,
    // scan, a slow device answering by segments without end, asked again: the answers to
    // the other requests came during the transfer, taken for repeats, and the count said
    // frames were lost; and, a late segment of that transfer coming first into the next
    // read, the count said a second device answered. Fixed: only a read that ends on its
    // first frame, and that frame an answer to it, is counted. Found by a run of 100,000
    // from 0x7B000000.
    0x7b01_708f,
    0x7b00_cfe7,
    // network set-baud, the I/O module missing one frame in ten: it missed the switch back to
    // waiting, answered the inquiry after it, then missed the next two inquiries; that
    // silence was taken for the switch confirmed, and it was left in configuration state,
    // exit 0. Nothing sent after its answer could have sent it back (fixed: silence confirms
    // the switch only when nobody answered since it was sent; else it is sent again). Found
    // by a run from 0x1C000000.
    0x1c01_4bab,
    // scan, node 10 answering on node 11's COB-ID and rebooting on the probe (no answer on
    // 0x58B to it): its boot-up had it asked alone, it answered on 0x58B, and the bus's
    // observer took that answer for node 11 showing itself: node 11 was listed, no device
    // has it. Not the class health allows (a device silent when asked alone): the scan had
    // asked it alone and seen whose answer it was, so the invariant stays as it is; a user
    // wants no node listed that nothing shows (fixed: the node-id a suspect answers on is
    // asked alone too where the probe did not find it and it shows itself no other way;
    // silent, it is not listed, and the scan says node 10 answers on 0x58B). Same run.
    0x1c00_0b94,
    // network set-baud, the I/O module muted from its third frame and missing one frame in
    // fifty: it refused the rate, missed the switch back to waiting, and could answer no
    // inquiry; nothing on the bus could show it stayed in configuration state. The
    // invariant now leaves a muted device out of that check (it holds for every device
    // that can answer). Found by a run of 60,000 from 0x6A000000.
    0x6a00_d3be,
];

/// The first seed of the CI run; any other start runs other scenarios.
const CI_START: u64 = 0x5EED_0000;
/// What `cargo test` runs by default, on the debug build: the first of CI's scenarios.
const TEST_SCENARIOS: u64 = 500;

fn replay_hint(seed: u64) -> String {
    format!("CANCTL_DST_SEED={seed:#x} cargo test --test dst seeded (CANCTL_DST_TRACE=1 for its frames)")
}

fn env_u64(name: &str) -> Option<u64> {
    canctl::canopen::number::parse_number(std::env::var(name).ok()?.trim())
}

/// Run `seeds` on every core; the seeds that broke an invariant, with what broke.
fn run_all(seeds: impl Iterator<Item = u64> + Send) -> (Vec<(u64, String)>, u64) {
    let ran = std::sync::atomic::AtomicU64::new(0);
    let seeds = std::sync::Mutex::new(seeds);
    let failed = std::sync::Mutex::new(Vec::new());
    let longest = std::sync::Mutex::new(Duration::ZERO);
    // Per procedure: runs, wall time, and the longest bus time (against its bound).
    let cost: std::sync::Mutex<BTreeMap<String, (u32, Duration, Duration)>> = Default::default();
    let slowest: std::sync::Mutex<Vec<(Duration, u64)>> = Default::default();
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    // `CANCTL_DST_ONLY=Assign`: only the scenarios of that procedure (for a closer look).
    let only = std::env::var("CANCTL_DST_ONLY").ok();
    std::thread::scope(|scope| {
        for _ in 0..threads {
            scope.spawn(|| loop {
                let Some(seed) = seeds.lock().unwrap().next() else { break };
                let s = Scenario::of(seed);
                if only.as_ref().is_some_and(|o| !format!("{:?}", s.procedure).starts_with(o.as_str())) {
                    continue;
                }
                let wall = Instant::now();
                ran.fetch_add(1, Ordering::Relaxed);
                let out = std::panic::catch_unwind(|| run(&s)).map_err(|p| {
                    p.downcast_ref::<String>().cloned().or(p.downcast_ref::<&str>().map(|s| s.to_string()))
                });
                // By the procedure, whatever it was drawn with.
                let kind = format!("{:?}", s.procedure).split(" {").next().unwrap_or_default().to_string();
                let mut c = cost.lock().unwrap();
                let e = c.entry(kind).or_default();
                e.0 += 1;
                e.1 += wall.elapsed();
                if let Ok(o) = &out {
                    e.2 = e.2.max(o.took);
                }
                drop(c);
                slowest.lock().unwrap().push((wall.elapsed(), seed));
                match out {
                    Ok(o) => {
                        if o.broken.is_some() {
                            trace(&o.frames);
                        }
                        let mut l = longest.lock().unwrap();
                        *l = (*l).max(o.took);
                        if let Some(why) = o.broken {
                            failed.lock().unwrap().push((seed, format!("{s:?}: {why}")));
                        }
                    }
                    Err(why) => failed.lock().unwrap().push((seed, format!("{s:?}: panicked: {why:?}"))),
                }
            });
        }
    });
    for (kind, (n, wall, took)) in cost.into_inner().unwrap() {
        eprintln!(
            "dst: {kind}: {n} run(s), {:?} of wall time each, the longest {took:.1?} of bus time",
            wall / n.max(1)
        );
    }
    let mut slowest = slowest.into_inner().unwrap();
    slowest.sort();
    for (wall, seed) in slowest.iter().rev().take(5) {
        eprintln!("dst: slow: {wall:?}: {:?}", Scenario::of(*seed));
    }
    eprintln!("dst: the longest run took {:?} of bus time", longest.into_inner().unwrap());
    let mut failed = failed.into_inner().unwrap();
    failed.sort();
    (failed, ran.into_inner())
}

fn report(failed: &[(u64, String)]) {
    for (seed, why) in failed.iter().take(20) {
        eprintln!("seed {seed:#x}: {why}\n  replay: {}", replay_hint(*seed));
    }
    assert!(
        failed.is_empty(),
        "{} scenario(s) broke an invariant; replay the first with: {}",
        failed.len(),
        replay_hint(failed[0].0)
    );
}

#[test]
fn seeded_scenarios_keep_every_invariant() {
    let (seeds, label): (Box<dyn Iterator<Item = u64> + Send>, String) = match env_u64("CANCTL_DST_SEED") {
        Some(seed) => (Box::new(std::iter::once(seed)), format!("seed {seed:#x}")),
        None => {
            let start = env_u64("CANCTL_DST_START").unwrap_or(CI_START);
            let n = env_u64("CANCTL_DST_SCENARIOS").unwrap_or(TEST_SCENARIOS);
            (Box::new(start..start + n), format!("{n} scenarios from {start:#x}"))
        }
    };
    let wall = Instant::now();
    let (failed, ran) = run_all(seeds);
    let took = wall.elapsed();
    let per_minute = ran as f64 * 60.0 / took.as_secs_f64().max(1e-3);
    eprintln!("dst: {ran} of {label} in {took:.1?} of wall time ({per_minute:.0} a minute)");
    report(&failed);
}

#[test]
fn seeds_that_once_broke_an_invariant_keep_it_now() {
    let (failed, _) = run_all(FIXED.iter().copied());
    report(&failed);
}

#[test]
fn the_same_seed_gives_the_same_frames_byte_for_byte() {
    for seed in CI_START..CI_START + 20 {
        let s = Scenario::of(seed);
        let (a, b) = (run(&s), run(&s));
        assert!(!a.frames.is_empty(), "{s:?}");
        assert!(a.frames == b.frames, "seed {seed:#x}: two runs differ; {}", replay_hint(seed));
    }
    // And another seed, another run.
    assert!(run(&Scenario::of(CI_START)).frames != run(&Scenario::of(CI_START + 1)).frames);
}
