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
use canctl::canopen::cia402::{Goal, State as DriveState};
use canctl::canopen::lss::{Identity, STEP_CEILING};
use canctl::canopen::nmt::{self, Command};
use canctl::canopen::ObjAddr;
use canctl::frame::Frame;
use canctl::ops::Cancel;
use canctl::ops::{self, Silent};
use canctl::sim::timing::Rng;
use canctl::sim::{Profile, SimConfig, SimLink};
use canctl::{Error, Result};
use std::collections::BTreeMap;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

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
];

/// The first seed of the CI run; any other start runs other scenarios.
const CI_START: u64 = 0x5EED_0000;
/// What `cargo test` runs by default, on the debug build: the first of CI's scenarios.
const TEST_SCENARIOS: u64 = 500;

/// What every frame on the tape is: sent by canctl or received, when, and its bytes.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Taped {
    sent: bool,
    at: Duration,
    id: u16,
    data: Vec<u8>,
}

/// The simulated network behind a recorder of every frame.
struct Tape {
    sim: SimLink,
    zero: Instant,
    frames: Vec<Taped>,
    /// A loaded host: now and then canctl polls the link late; the bus and the devices
    /// go on meanwhile.
    stalls: Option<Stalls>,
}

/// When a loaded host holds canctl up: now and then right after it sent a frame (the
/// moment a system call hands the CPU to another task), for 1 ms to `longest`, drawn from
/// the generator, before it polls for the answer.
struct Stalls {
    rng: Rng,
    longest: u64,
    after_send: bool,
}

impl Stalls {
    fn sent(&mut self) {
        self.after_send = self.rng.chance(0.25);
    }

    /// How long canctl is held up before this poll, if it is.
    fn polling(&mut self) -> Option<Duration> {
        std::mem::take(&mut self.after_send).then(|| Duration::from_millis(self.rng.between(1, self.longest)))
    }
}

impl Tape {
    fn record(&mut self, sent: bool, at: Instant, f: &Frame) {
        let at = at.saturating_duration_since(self.zero);
        self.frames.push(Taped { sent, at, id: f.id(), data: f.data().to_vec() });
    }
}

impl FrameLink for Tape {
    fn send(&mut self, frame: &Frame) -> Result<()> {
        let now = self.sim.now();
        self.record(true, now, frame);
        if let Some(s) = &mut self.stalls {
            s.sent();
        }
        self.sim.send(frame)
    }
    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        Ok(self.recv_stamped(deadline)?.map(|(f, _)| f))
    }
    fn recv_stamped(&mut self, deadline: Instant) -> Result<Option<(Frame, Instant)>> {
        if let Some(late) = self.stalls.as_mut().and_then(Stalls::polling) {
            self.sim.sleep_until(self.sim.now() + late)?;
        }
        let got = self.sim.recv_stamped(deadline)?;
        if let Some((f, at)) = &got {
            self.record(false, *at, f);
        }
        Ok(got)
    }
    fn name(&self) -> String {
        "sim".into()
    }
    fn now(&self) -> Instant {
        self.sim.now()
    }
    fn sleep_until(&mut self, t: Instant) -> Result<()> {
        self.sim.sleep_until(t)
    }
    fn follows_bit_rate_switch(&self) -> bool {
        self.sim.follows_bit_rate_switch()
    }
    fn close(&mut self) -> Result<()> {
        self.sim.close()
    }
}

/// The procedures the harness runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Procedure {
    Scan,
    /// An expedited read (0x1000), a segmented one (0x1008, a name), a block one (the
    /// drive's 64 KiB domain).
    Read(ReadKind),
    /// A plain value write (the sensor's heartbeat time), with a read back.
    Write,
    /// A block download of the drive's domain.
    WriteDomain,
    Fastscan,
    Assign,
    /// NMT reset node with confirmation (the boot-up).
    Reset,
    ConfigApply,
    NetworkApply,
    SetBaud,
    DriveEnable,
    Health,
    /// `doctor` of the whole bus (drawn in place of a scan, see [`Scenario::of`]).
    Doctor,
    /// A read of the sensor's device type, and when it is not answered, the quick
    /// diagnosis `sdo read` adds (drawn in place of a scan).
    Diagnose,
    /// NMT stop sent to the sensor, then its state asked at once, as `nmt stop 5; nmt state
    /// 5` in one program (drawn in place of a reset).
    StopThenState,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ReadKind {
    Expedited,
    Segmented,
    Block,
}

const PROCEDURES: &[Procedure] = &[
    Procedure::Scan,
    Procedure::Read(ReadKind::Expedited),
    Procedure::Read(ReadKind::Segmented),
    Procedure::Read(ReadKind::Block),
    Procedure::Write,
    Procedure::WriteDomain,
    Procedure::Fastscan,
    Procedure::Assign,
    Procedure::Reset,
    Procedure::ConfigApply,
    Procedure::NetworkApply,
    Procedure::SetBaud,
    Procedure::DriveEnable,
    Procedure::Health,
];

/// One scenario, all drawn from its seed.
#[derive(Clone, Debug)]
struct Scenario {
    seed: u64,
    procedure: Procedure,
    config: SimConfig,
    /// Stop requested after this many confirmed SDO transfers or NMT commands.
    stop_after: Option<u32>,
    /// A scan or health check of a bus canctl has not scanned before (no scan cache): what
    /// the bus shows by itself is all it knows.
    first_look: bool,
    /// A loaded host that polls the link late, by up to this many ms now and then (0: never).
    host_stall_ms: u64,
}

const NODES: [u8; 4] = [1, 5, 10, 32];
/// How many times scan asks a node-id that does not answer, on a bus that shows its
/// traffic (ops::scan's rounds of the probe).
const SCAN_PROBE_ROUNDS: usize = 3;
const TIMEOUT: Duration = Duration::from_millis(200);

fn pick<T: Copy>(rng: &mut Rng, from: &[T]) -> T {
    from[rng.between(0, from.len() as u64 - 1) as usize]
}

impl Scenario {
    fn of(seed: u64) -> Scenario {
        let mut rng = Rng::new(seed);
        let procedure = pick(&mut rng, PROCEDURES);
        let profile = pick(&mut rng, &[Profile::Instant, Profile::Typical, Profile::Typical, Profile::Slow]);
        // 1M, 500k, 250k, 125k.
        let bit_rate = pick(&mut rng, &[0, 2, 2, 3, 4]);
        let unconfigured = match procedure {
            Procedure::NetworkApply => 5,
            Procedure::Fastscan | Procedure::Assign => rng.between(1, 4) as u8,
            _ => rng.between(0, 2) as u8,
        };
        let mut config = SimConfig::default()
            .profile(profile)
            .seed(rng.next_u64())
            .unconfigured(unconfigured)
            .bit_rate(bit_rate)
            .virtual_time(true);
        // Half the scenarios are clean: those must succeed.
        if rng.chance(0.5) {
            for _ in 0..rng.between(1, 2) {
                let spec = fault(&mut rng, unconfigured);
                config = config.fault(spec.parse().expect("a fault spec"));
            }
        }
        let stop_after = rng.chance(0.15).then(|| rng.between(0, 12) as u32);
        // Drawn last, so that the seeds found before it was added keep their scenarios.
        if rng.chance(0.06) {
            let target = pick(&mut rng, &NODES);
            config = config.fault(format!("{target}:reboot@{}", rng.between(1, 30)).parse().expect("a fault spec"));
        }
        // canctl's own frames lost on the way to one device (a lossy path, a receive queue
        // overrun): drawn after the reboot, for the same reason.
        if rng.chance(0.1) {
            let spec = format!("{}:miss@{}%", pick_target(&mut rng, unconfigured), pick(&mut rng, &[1, 2, 5, 10]));
            config = config.fault(spec.parse().expect("a fault spec"));
        }
        // A device whose SDO server misbehaves without end (an upload that never ends, by
        // segments or by blocks; a block download acknowledged "nothing received" for ever),
        // answers on the next node's COB-ID, or is off: drawn after the others, for the
        // same reason.
        // Only for the procedures that look at the whole bus: a read the user asks for runs
        // to the limit the user gives it (`sdo read --max-size`).
        let looking = matches!(procedure, Procedure::Scan | Procedure::Health);
        if looking && rng.chance(0.25) {
            let kind = pick(&mut rng, &["endless-segments", "endless-block", "ack-zero", "off", "wrong-cob"]);
            let spec = format!("{}:{kind}", pick(&mut rng, &NODES));
            config = config.fault(spec.parse().expect("a fault spec"));
        }
        // The other procedures that look at the whole bus, in place of a scan now and then.
        let mut procedure = procedure;
        if procedure == Procedure::Scan && rng.chance(0.5) {
            procedure = pick(&mut rng, &[Procedure::Doctor, Procedure::Diagnose]);
        }
        // Drawn last, for the same reason: now and then the bus is looked at for the first time.
        let first_look = rng.chance(0.3);
        // And after it: a stop, then the state asked at once, in place of a reset now and then.
        if procedure == Procedure::Reset && rng.chance(0.5) {
            procedure = Procedure::StopThenState;
        }
        // And after it: a loaded host.
        let host_stall_ms = if rng.chance(0.25) { rng.between(2, 60) } else { 0 };
        Scenario { seed, procedure, config, stop_after, first_look, host_stall_ms }
    }

    fn clean(&self) -> bool {
        self.config.faults.is_empty() && self.stop_after.is_none()
    }
}

/// One device of the network: a node-id, or the model key of a device waiting for one.
fn pick_target(rng: &mut Rng, unconfigured: u8) -> String {
    let mut targets: Vec<String> = NODES.iter().map(|n| n.to_string()).collect();
    targets.extend((1..=unconfigured).map(|i| format!("sensor-095013{i:02}")));
    targets[rng.between(0, targets.len() as u64 - 1) as usize].clone()
}

/// A fault drawn for one device of the network.
fn fault(rng: &mut Rng, unconfigured: u8) -> String {
    let target = pick_target(rng, unconfigured);
    let percent = pick(rng, &[1, 2, 2, 5, 20]);
    let kind = match rng.between(0, 8) {
        0 => format!("drop@{percent}%"),
        1 => format!("delay={}@{percent}%", rng.between(1, 150)),
        2 => format!("duplicate@{percent}%"),
        3 => format!("short-dlc@{percent}%"),
        4 => format!("corrupt@{percent}%"),
        5 => format!("mute@{}+", rng.between(1, 40)),
        6 => format!("abort@{}", rng.between(1, 10)),
        7 => "babble=0x7F0".to_string(),
        _ => format!("drop@{}", rng.between(1, 20)),
    };
    format!("{target}:{kind}")
}

/// What one run gave: every frame, and the invariant it broke, if any.
struct Outcome {
    frames: Vec<Taped>,
    broken: Option<String>,
    /// Bus time the procedure took.
    took: Duration,
    /// How it ended: `ok` or the error.
    ended: String,
}

/// The longest any procedure may take in bus time, faults included.
const BOUND: Duration = Duration::from_secs(5 * 60);

/// The bound of one scenario. An LSS search is 133 requests, and a step may grow to
/// [`STEP_CEILING`] when answers come late: so one whole search at the longest step per
/// device without a node-id, and one that finds nobody; five minutes for the rest.
fn bound(s: &Scenario) -> Duration {
    match s.procedure {
        Procedure::Fastscan | Procedure::Assign | Procedure::NetworkApply => {
            BOUND.max(STEP_CEILING * 133 * (u32::from(s.config.unconfigured) + 1))
        }
        Procedure::Scan | Procedure::Health | Procedure::Doctor => LOOKING_BOUND,
        Procedure::Diagnose => DIAGNOSE_BOUND,
        _ => BOUND,
    }
}

/// The bound of the commands that look at the whole bus (scan, health, doctor), faults
/// included: one device must not stretch them. With 200 ms answers, each node's reads are
/// bounded by their sizes (a number 8 bytes, a name 255) and run alongside the others'.
const LOOKING_BOUND: Duration = Duration::from_secs(30);

/// A read of a silent node (three requests of 200 ms) and its quick diagnosis (two waits
/// of at most 500 ms, and the probe's rounds), faults included.
const DIAGNOSE_BOUND: Duration = Duration::from_secs(5);

fn run(s: &Scenario) -> Outcome {
    let mut sim = SimLink::with_config(s.config.clone()).on_virtual_time(1_700_000_000_000);
    // The drive's domain holds 1 to 4 KiB to start with (its 64 KiB would make the block
    // read a hundred times the work of any other scenario).
    let len = 1024 + (s.seed % 3072) as usize;
    let domain: Vec<u8> = (0..len).map(|i| (i as u64 ^ s.seed) as u8).collect();
    let drive = sim.network_mut().devices_mut().iter_mut().find(|d| d.node_id() == Some(1)).expect("the drive");
    drive.write_local(DOMAIN, &domain).expect("the domain takes any length");
    let zero = sim.now();
    let stalls = (s.host_stall_ms > 0).then(|| Stalls {
        rng: Rng::new(s.seed ^ 0x57a11),
        longest: s.host_stall_ms,
        after_send: false,
    });
    let mut master = Master::new(Tape { sim, zero, frames: Vec::new(), stalls }, "sim".into());
    let before = Devices::of(&master.link_mut().sim);
    let stop = Cancel::new();
    let result = {
        let flag = stop.clone();
        let at = s.stop_after;
        let mut steps = 0;
        let mut tapped = AfterSdo::new(&mut master, move |_, _| {
            steps += 1;
            if at.is_some_and(|n| steps >= n) {
                flag.cancel();
            }
        });
        if s.stop_after == Some(0) {
            stop.cancel();
        }
        let mut bus = Stoppable::new(&mut tapped, stop.clone());
        procedure(&mut bus, s, &stop)
    };
    let took = master.link_mut().now().saturating_duration_since(zero);
    // What canctl queued reaches the devices (as the kernel sends what a closed socket
    // queued) before they are looked at.
    let closed = Bus::close(&mut master);
    let after = Devices::of(&master.link_mut().sim);
    let tape = master.link_mut();
    let mut broken = check(s, &result, &before, &after, &tape.sim, &tape.frames).err();
    if let Err(e) = closed {
        broken.get_or_insert(format!("closing the link failed: {e}"));
    }
    if took > bound(s) {
        broken.get_or_insert(format!("took {took:?} of bus time (bound {:?})", bound(s)));
    }
    if broken.is_none() && s.clean() && s.procedure != Procedure::SetBaud {
        if let Err(e) = &result {
            broken = Some(format!("a clean run failed: {e}"));
        }
    }
    let ended = match &result {
        Ok(Report::Assigned(_, false, _, _)) => "ended part-way".to_string(),
        Ok(_) => "ok".to_string(),
        Err(e) => format!("{e}").chars().take(60).collect(),
    };
    Outcome { frames: std::mem::take(&mut master.link_mut().frames), broken, took, ended }
}

/// What the procedure reported, reduced to what the devices can be checked against.
enum Report {
    /// The NMT state a node was reported in.
    State(u8, nmt::State),
    /// Values read from a node's object.
    Read(u8, ObjAddr, Vec<u8>),
    Wrote(u8, ObjAddr, Vec<u8>),
    /// Nodes and identities a scan reported, whether it was stopped part-way, and the
    /// nodes it said lost frames (answered only a repeat of the probe).
    Scanned(Vec<(u8, Option<u32>)>, bool, Vec<u8>),
    Found(Identity),
    /// Identities given node-ids (all of them, also when interrupted or failed part-way).
    /// And whether it said every device has one now (exit 0), and the device it said may
    /// hold a node-id (set-id unanswered); and whether it said a device stayed in
    /// configuration state.
    Assigned(Vec<(Identity, u8)>, bool, Option<(Identity, u8)>, bool),
    Booted(Vec<u8>),
    /// Objects of the sensor's DCF written (and verified) on `node`.
    Applied(u8, Vec<ObjAddr>),
    /// The nodes of the example project and whether each was reported brought to its DCF.
    Project(Vec<(u8, bool)>),
    Nodes(Vec<(u8, bool)>),
    /// Nodes and whether each answered at the new rate (CiA 305 table index) after the switch.
    Followed(u8, Vec<(u8, Option<bool>)>),
    DriveState(u8, Option<DriveState>, bool),
    /// Whether doctor found nothing wrong.
    Doctor(bool),
    Nothing,
}

fn procedure(bus: &mut dyn Bus, s: &Scenario, stop: &Cancel) -> Result<Report> {
    let opts = SdoOptions::new(TIMEOUT);
    match s.procedure {
        Procedure::Scan => {
            let o = ops::scan::ScanOptions { window: Duration::from_millis(300), timeout: TIMEOUT };
            // As canctl scans a bus it scanned before (knowing the nodes the last scan saw),
            // or one it never scanned.
            let scan = ops::scan::scan_against(bus, &o, last_seen(s), &mut Silent)?;
            let lost = scan.answered_on_repeat.iter().map(|r| r.node).collect();
            Ok(Report::Scanned(scan.nodes.iter().map(|n| (n.node, n.serial)).collect(), scan.interrupted, lost))
        }
        Procedure::Read(kind) => {
            let (node, addr, opts) = match kind {
                ReadKind::Expedited => (5, ObjAddr::new(0x1000, 0), opts),
                ReadKind::Segmented => (10, ObjAddr::new(0x1008, 0), opts),
                ReadKind::Block => (1, DOMAIN, SdoOptions { block_upload: true, ..opts }),
            };
            let data = bus.sdo_upload(node, addr, &opts)?;
            Ok(Report::Read(node, addr, data))
        }
        Procedure::Write => {
            let addr = ObjAddr::new(0x1017, 0);
            let value = (100 + (s.seed % 900) as u16).to_le_bytes().to_vec();
            bus.sdo_download(5, addr, &value, &SdoOptions { size_hint: Some(2), ..opts })?;
            Ok(Report::Wrote(5, addr, value))
        }
        Procedure::WriteDomain => {
            let data: Vec<u8> = (0..3000u32).map(|i| (i as u64 * 7 + s.seed) as u8).collect();
            bus.sdo_download(1, DOMAIN, &data, &opts)?;
            Ok(Report::Wrote(1, DOMAIN, data))
        }
        Procedure::Fastscan => {
            let found = ops::lss::fastscan(bus, &ops::lss::FastscanOptions::new(TIMEOUT), stop)?;
            Ok(Report::Found(found.identity.0))
        }
        Procedure::Assign => {
            let o = ops::lss::AssignOptions {
                start: 20,
                fastscan: ops::lss::FastscanOptions::new(TIMEOUT),
                listen: None,
                store: true,
            };
            let a = ops::lss::assign(bus, &o, &mut Silent, stop)?;
            // Failed or interrupted part-way: what it says it did must still be so.
            let complete = a.failure.is_none() && !a.interrupted;
            let maybe = match a.failure {
                Some(Error::LssSetIdUnknown { identity, node, .. }) => Some((identity, node)),
                _ => None,
            };
            let says_left =
                matches!(a.failure, Some(Error::LssLeftInConfiguration { .. } | Error::LssStillConfiguring { .. }));
            let given = a.assigned.iter().map(|d| (d.identity.0, d.node)).collect();
            Ok(Report::Assigned(given, complete, maybe, says_left))
        }
        Procedure::Reset => {
            let o = ops::nmt::ResetOptions { wait: Duration::from_secs(2), timeout: TIMEOUT };
            let r = ops::nmt::reset(bus, Command::ResetNode, 5, &o)?;
            Ok(match r.confirmed {
                true => Report::Booted(r.booted.unwrap_or_default()),
                false => Report::Nothing,
            })
        }
        Procedure::StopThenState => {
            // The program did something else for a while: the sensor's beats (every 40 ms)
            // wait unread, from before the stop.
            let idle = bus.now() + Duration::from_millis(100);
            bus.sleep_until(idle)?;
            ops::nmt::send(bus, Command::Stop, 5)?;
            let o = ops::nmt::StateOptions { listen: Duration::from_millis(300), timeout: TIMEOUT };
            let state = ops::nmt::state(bus, 5, &o)?;
            Ok(Report::State(5, state.state))
        }
        Procedure::ConfigApply => {
            let mut o = ops::config::ApplyOptions::new(TIMEOUT);
            o.verify = true;
            let applied = ops::config::apply(bus, 5, sensor_dcf(), &o)?;
            if let Some(e) = applied.failure {
                return Err(e);
            }
            if applied.interrupted {
                return Err(Error::Interrupted);
            }
            // A value that reads back otherwise (a device that rebooted mid-apply lost it)
            // is exit 6, as the command ends, not a success.
            if !applied.mismatch.is_empty() {
                return Err(Error::ReadBackMany { node: 5, objects: applied.mismatch });
            }
            Ok(Report::Applied(5, applied.written))
        }
        Procedure::NetworkApply => {
            let loaded = machine();
            let mut config = ops::config::ApplyOptions::new(TIMEOUT);
            config.verify = true;
            let o = ops::network::ApplyOptions {
                config,
                assign: true,
                window: Duration::from_millis(300),
                boot_wait: Duration::from_secs(2),
                jobs: 4,
                reset: false,
                interrupted: stop.clone(),
            };
            let applied = ops::network::apply(bus, loaded, &o, &mut Silent)?;
            if let Some(e) = applied.failure {
                return Err(e);
            }
            Ok(Report::Project(applied.nodes.iter().map(|n| (n.node, n.ok)).collect()))
        }
        Procedure::SetBaud => {
            let loaded = machine();
            let o = ops::network::SetBaudOptions {
                timeout: TIMEOUT,
                window: Duration::from_millis(300),
                index: 4,
                delay_ms: 50,
                store: false,
                // The sim's stepper refuses every other rate: it is left behind.
                force: true,
                interrupted: stop.clone(),
            };
            let r = ops::network::set_baud(bus, Some(loaded), &o, &mut Silent)?;
            Ok(Report::Followed(4, r.nodes.iter().map(|n| (n.node, n.after)).collect()))
        }
        Procedure::DriveEnable => {
            bus.nmt(Command::Start, 1)?;
            let o = ops::drive::Options { timeout: TIMEOUT, wait: Duration::from_millis(500) };
            let w = ops::drive::walk(bus, 1, Goal::Enable, &o, stop)?;
            Ok(Report::DriveState(1, w.state, w.done))
        }
        Procedure::Health => {
            let o = ops::health::HealthOptions {
                window: Duration::from_millis(300),
                timeout: TIMEOUT,
                watch: None,
                state: None,
                last_seen: last_seen(s).to_vec(),
            };
            let h = ops::health::health(bus, &o, &mut Silent)?;
            Ok(Report::Nodes(h.nodes.iter().map(|n| (n.node, n.ok)).collect()))
        }
        Procedure::Doctor => {
            let o = ops::doctor::DoctorOptions {
                node: None,
                listen: Duration::from_millis(300),
                timeout: TIMEOUT,
                last_scan: last_scan(),
                lss: false,
            };
            Ok(Report::Doctor(ops::doctor::doctor(bus, &o)?.ok))
        }
        Procedure::Diagnose => {
            // As `sdo read 5 1000` reads a u32: up to 8 bytes.
            let opts = SdoOptions { size_hint: Some(4), max_upload: 8, ..opts };
            let read = bus.sdo_upload(5, ObjAddr::new(0x1000, 0), &opts);
            if let Err(Error::NoAnswer { .. }) = read {
                ops::doctor::quick(bus, 5, last_seen(s), Duration::from_millis(500))?;
            }
            read.map(|_| Report::Nothing)
        }
    }
}

const DOMAIN: ObjAddr = ObjAddr::new(0x1F50, 1);

/// What the last scan saw before each run: the demo network's nodes.
fn last_scan() -> Vec<ops::scan_cache::SeenNode> {
    let text = serde_json::json!(NODES.iter().map(|n| serde_json::json!({ "node": n })).collect::<Vec<_>>());
    serde_json::from_value(text).expect("seen nodes")
}

/// The example project (read once: parsing its DCFs would be most of a short scenario).
fn machine() -> &'static ops::network::Loaded {
    static LOADED: std::sync::OnceLock<ops::network::Loaded> = std::sync::OnceLock::new();
    LOADED.get_or_init(|| {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/sim-machine/nodelist.cpj");
        ops::network::load(&path).expect("the example project")
    })
}

fn sensor_dcf() -> &'static ops::config::Dcf {
    static DCF: std::sync::OnceLock<ops::config::Dcf> = std::sync::OnceLock::new();
    DCF.get_or_init(|| ops::config::Dcf::parse(include_bytes!("../examples/sensor.dcf"), "sensor.dcf").unwrap())
}

/// The network as the run left it, without its faults and on the instant profile: what
/// the devices hold, read back by a master nothing disturbs.
fn clean_copy(sim: &SimLink) -> Master<SimLink> {
    let mut state = sim.network().snapshot();
    if let Some(c) = state.config.as_mut() {
        c.faults.clear();
        c.profile = Profile::Instant;
    }
    let net = canctl::sim::Network::from_state(&state);
    Master::new(SimLink::of(net).on_virtual_time(1_700_000_000_000), "sim".into())
}

/// The devices as the network holds them.
struct Devices {
    /// By serial: node-id, LSS configuration state, NMT state.
    all: Vec<DeviceView>,
}

struct DeviceView {
    identity: Identity,
    node: Option<u8>,
    nmt: nmt::State,
    drive: Option<DriveState>,
    bit_rate: u8,
    /// Left in LSS configuration state.
    configuring: bool,
    /// The objects the procedures read and write.
    values: BTreeMap<ObjAddr, Vec<u8>>,
}

const WATCHED: [ObjAddr; 4] = [ObjAddr::new(0x1000, 0), ObjAddr::new(0x1008, 0), ObjAddr::new(0x1017, 0), DOMAIN];

impl Devices {
    fn of(sim: &SimLink) -> Devices {
        let all = sim
            .network()
            .devices()
            .iter()
            .map(|d| DeviceView {
                identity: d.identity(),
                node: d.node_id(),
                nmt: d.nmt_state(),
                drive: d.objects().drive_state(),
                bit_rate: d.bit_rate(),
                configuring: d.snapshot().lss_configuration,
                values: WATCHED.iter().filter_map(|a| Some((*a, d.objects().value(*a)?.to_vec()))).collect(),
            })
            .collect();
        Devices { all }
    }

    fn node(&self, node: u8) -> Option<&DeviceView> {
        self.all.iter().find(|d| d.node == Some(node))
    }

    fn value(&self, node: u8, addr: ObjAddr) -> Option<&[u8]> {
        self.node(node)?.values.get(&addr).map(|v| v.as_slice())
    }
}

/// The invariants, for one run.
fn check(
    s: &Scenario,
    result: &Result<Report>,
    before: &Devices,
    after: &Devices,
    sim: &SimLink,
    frames: &[Taped],
) -> std::result::Result<(), String> {
    // No node-id held twice, whatever happened.
    let mut held = BTreeMap::new();
    for d in &after.all {
        if let Some(n) = d.node {
            if let Some(other) = held.insert(n, d.identity) {
                return Err(format!("node-id {n} held by {other} and {}", d.identity));
            }
        }
    }
    // Every LSS procedure sends the devices back to waiting, however it ended; a device
    // left at another bit rate (set-baud --force) cannot hear it, and one that missed every
    // switch back is what the error says.
    let rate = sim.network().bit_rate();
    let said_so = matches!(
        result,
        Err(Error::LssLeftInConfiguration { .. } | Error::LssStillConfiguring { .. })
            | Ok(Report::Assigned(_, _, _, true))
    );
    if let Some(d) = after.all.iter().find(|d| d.configuring && d.bit_rate == rate && !said_so) {
        return Err(format!("{} left in LSS configuration state", d.identity));
    }
    let Ok(report) = result else { return Ok(()) };
    match report {
        Report::Read(node, addr, data) => {
            let held = after.value(*node, *addr);
            if held != Some(data.as_slice()) {
                return Err(format!(
                    "read {} bytes from node {node} {addr}, the device holds {:?}",
                    data.len(),
                    held.map(|v| v.len())
                ));
            }
        }
        Report::Wrote(node, addr, data) => {
            if after.value(*node, *addr) != Some(data.as_slice()) {
                return Err(format!("wrote node {node} {addr}, the device does not hold it"));
            }
        }
        Report::Scanned(nodes, interrupted, lost) => {
            // Frames said lost were lost, damaged or held back past the window: never said
            // of a node that merely answers slowly.
            if let Some(n) = lost.iter().find(|n| !loses_frames(s, **n)) {
                return Err(format!("scan said node {n} lost frames, nothing of it was lost or held back"));
            }
            for (node, serial) in nodes {
                let Some(d) = after.node(*node) else {
                    // Stopped before the nodes found were asked alone (ops::answers_elsewhere),
                    // a scan may still list the id a device answers on in place of its own.
                    if *interrupted && answered_for(s).contains(node) {
                        continue;
                    }
                    return Err(format!("scan reported node {node}, no device has it"));
                };
                if serial.is_some_and(|s| s != d.identity.serial) {
                    return Err(format!(
                        "scan reported node {node} with serial {serial:?}, the device's is {}",
                        d.identity.serial
                    ));
                }
            }
            // Under loss, delay, damaged answers too: a scan that ends (exit 0) lists every
            // node that is there, unless canctl never heard of it: asked in each of the
            // probe's rounds, nothing of it came back (no answer, no heartbeat).
            if !interrupted {
                let got: Vec<u8> = nodes.iter().map(|(n, _)| *n).collect();
                for n in after.all.iter().filter_map(|d| d.node).filter(|n| !got.contains(n)) {
                    let probe = [0x40, 0x00, 0x10, 0x00];
                    let asked = frames
                        .iter()
                        .filter(|f| f.sent && f.id == 0x600 + u16::from(n) && f.data[..4] == probe)
                        .count();
                    let heard = frames.iter().any(|f| {
                        !f.sent
                            && ((f.id == 0x580 + u16::from(n) && f.data.len() == 8)
                                || (f.id == 0x700 + u16::from(n) && f.data.len() == 1))
                    });
                    if heard || asked < SCAN_PROBE_ROUNDS {
                        return Err(format!(
                            "scan found {got:?} and ended ok without node {n}, which is there (asked {asked} time(s), heard: {heard})"
                        ));
                    }
                }
            }
        }
        Report::Found(id) => {
            let waiting = before.all.iter().any(|d| d.node.is_none() && d.identity == *id);
            if !waiting {
                return Err(format!("fastscan found {id}, no device without a node-id has it"));
            }
        }
        Report::Assigned(given, complete, maybe, _) => {
            // A device muted by its fault cannot be told from one that is not there.
            let rate = sim.network().bit_rate();
            let seen = |d: &&DeviceView| d.bit_rate == rate && !muted(s, d);
            if let Some(d) = after.all.iter().filter(seen).find(|d| *complete && d.node.is_none()) {
                return Err(format!("assign ended as complete, {} still has no node-id", d.identity));
            }
            for (id, node) in given {
                let holder = after.all.iter().find(|d| d.identity == *id);
                if holder.and_then(|d| d.node) != Some(*node) {
                    return Err(format!("reported {id} -> node {node}, the device holds {:?}", holder.map(|d| d.node)));
                }
            }
            // Every device numbered is in the report.
            for d in &after.all {
                let was = before.all.iter().find(|b| b.identity == d.identity).and_then(|b| b.node);
                let said = given.iter().chain(maybe).any(|(id, n)| *id == d.identity && d.node == Some(*n));
                if was.is_none() && d.node.is_some() && !said {
                    return Err(format!("{} took node {:?}, the report does not say so", d.identity, d.node));
                }
            }
        }
        Report::Booted(nodes) => {
            for n in nodes {
                if after.node(*n).map(|d| d.nmt) != Some(nmt::State::PreOperational) {
                    return Err(format!("reset confirmed for node {n}, which is not pre-operational"));
                }
            }
        }
        Report::Applied(node, written) => {
            let diff =
                ops::config::diff(&mut clean_copy(sim), *node, sensor_dcf(), TIMEOUT).map_err(|e| e.to_string())?;
            if let Some(d) = diff.differences.iter().find(|d| written.contains(&d.object)) {
                return Err(format!(
                    "applied {} to node {node}: the device holds {}, the DCF {}",
                    d.object, d.device, d.file
                ));
            }
        }
        Report::Project(nodes) => {
            let loaded = machine();
            let o = ops::network::CheckOptions {
                timeout: TIMEOUT,
                window: Duration::from_millis(300),
                jobs: 1,
                state: None,
            };
            let checked =
                ops::network::check(&mut clean_copy(sim), loaded, &o, &mut Silent).map_err(|e| e.to_string())?;
            for (node, ok) in nodes.iter().filter(|(_, ok)| *ok) {
                let c = checked.nodes.iter().find(|c| c.node == *node);
                if !c.is_some_and(|c| c.checks.iter().all(|v| v.ok)) {
                    return Err(format!("node {node} reported brought to its DCF ({ok}), a check says {c:?}"));
                }
            }
        }
        Report::Nodes(nodes) => {
            for (n, ok) in nodes {
                // A node the last scan saw and that is gone now is reported, not healthy.
                let Some(d) = after.node(*n) else {
                    if *ok || !last_seen(s).contains(n) {
                        return Err(format!("reported node {n} (healthy: {ok}), no device has it"));
                    }
                    continue;
                };
                if *ok && !serves_sdo(s, d) {
                    return Err(format!("node {n} reported healthy, its device serves no SDO ({:?})", d.nmt));
                }
            }
            // Every node the last scan saw is judged: never left out of a pass.
            if let Some(n) = last_seen(s).iter().find(|n| !nodes.iter().any(|(r, _)| r == *n)) {
                return Err(format!("health left out node {n}, which the last scan saw"));
            }
        }
        Report::Doctor(ok) => {
            let rate = sim.network().bit_rate();
            let silent =
                NODES.iter().find(|n| !after.node(**n).is_some_and(|d| d.bit_rate == rate && serves_sdo(s, d)));
            if let (true, Some(n)) = (ok, silent) {
                return Err(format!("doctor found nothing wrong, node {n} of the last scan serves no SDO"));
            }
            if !ok && s.clean() {
                return Err("doctor found something wrong on a clean network".into());
            }
        }
        Report::DriveState(node, state, done) => {
            let held = after.node(*node).and_then(|d| d.drive);
            if state.is_some() && *state != held {
                return Err(format!("reported drive state {state:?}, the drive is in {held:?}"));
            }
            if *done && held != Some(DriveState::OperationEnabled) {
                return Err(format!("reported enabled, the drive is in {held:?}"));
            }
        }
        Report::Followed(rate, nodes) => {
            for (node, followed) in nodes {
                let held = after.node(*node).map(|d| d.bit_rate);
                if *followed == Some(true) && held != Some(*rate) {
                    return Err(format!("node {node} reported at the new rate, the device is at {held:?}"));
                }
            }
        }
        Report::State(node, state) => {
            // What the node says from the command on, never a beat from before it.
            // (A device that rebooted since may be pre-operational again: only a device left
            // stopped is held to it.)
            let stopped = after.node(*node).is_some_and(|d| d.nmt == nmt::State::Stopped);
            if stopped && *state != nmt::State::Stopped {
                return Err(format!("node {node} reported {state:?} after the stop, the device is stopped"));
            }
        }
        Report::Nothing => {}
    }
    Ok(())
}

/// With `CANCTL_DST_TRACE` set: every frame of a run, as canctl's `-v` trace shows them.
fn trace(frames: &[Taped]) {
    if std::env::var("CANCTL_DST_TRACE").is_err() {
        return;
    }
    for f in frames {
        eprintln!("{:>12.3?} {} {:03X} {:02X?}", f.at, if f.sent { "tx" } else { "rx" }, f.id, f.data);
    }
}

/// Whether a fault of the scenario makes this device fall silent for good.
fn muted(s: &Scenario, d: &DeviceView) -> bool {
    s.config.faults.iter().any(|f| {
        let spec = f.to_string();
        let (target, kind) = spec.split_once(':').unwrap_or_default();
        let node = target.parse::<u8>().ok();
        kind.starts_with("mute")
            && (target == format!("sensor-{:08x}", d.identity.serial) || node.is_some_and(|n| d.node == Some(n)))
    })
}

/// Whether a fault of the scenario loses, damages or holds back frames to or from this
/// node-id (a device with that node-id, or one that had none yet).
fn loses_frames(s: &Scenario, node: u8) -> bool {
    s.config.faults.iter().any(|f| {
        let spec = f.to_string();
        let (target, kind) = spec.split_once(':').unwrap_or_default();
        let ours = target.parse::<u8>().map_or(target.starts_with("sensor-"), |n| n == node);
        ours && ["drop", "miss", "mute", "delay", "corrupt", "short-dlc"].iter().any(|k| kind.starts_with(k))
    })
}

/// The nodes the last scan of the bus saw: none on a first look.
fn last_seen(s: &Scenario) -> &'static [u8] {
    match s.first_look {
        true => &[],
        false => &NODES,
    }
}

/// The node-ids a device with a wrong-cob fault answers on in place of its own.
fn answered_for(s: &Scenario) -> Vec<u8> {
    let claimed = |f: &canctl::sim::FaultSpec| {
        let spec = f.to_string();
        let (target, kind) = spec.split_once(':')?;
        match kind.strip_prefix("wrong-cob") {
            Some("") => target.parse::<u8>().ok().map(|n| n + 1),
            Some(id) => u16::from_str_radix(id.strip_prefix("=0x")?, 16).ok().map(|c| (c & 0x7F) as u8),
            None => None,
        }
    };
    s.config.faults.iter().filter_map(claimed).collect()
}

/// Whether the device answers SDO at all: not stopped, not muted or off from the start.
fn serves_sdo(s: &Scenario, d: &DeviceView) -> bool {
    let node = d.node.unwrap_or(0);
    let silent =
        s.config.faults.iter().any(|f| [format!("{node}:off"), format!("{node}:mute")].contains(&f.to_string()));
    d.nmt != nmt::State::Stopped && !silent
}

fn replay_hint(seed: u64) -> String {
    format!("CANCTL_DST_SEED={seed:#x} cargo test --test dst seeded (CANCTL_DST_TRACE=1 for its frames)")
}

fn env_u64(name: &str) -> Option<u64> {
    let v = std::env::var(name).ok()?;
    let v = v.trim();
    match v.strip_prefix("0x") {
        Some(hex) => u64::from_str_radix(hex, 16).ok(),
        None => v.parse().ok(),
    }
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
                let kind = format!("{:?}", s.procedure);
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

/// `lss assign` of three devices whose answers are lost 2 % of the time (a USB adapter or
/// gateway under load), on virtual time: whatever each run ends with, it never says every
/// device has a node-id while one still waits (exit 0 is only for a confirmed bus).
#[test]
fn lss_assign_under_two_percent_loss_never_calls_a_waiting_device_done() {
    let mut outcomes = BTreeMap::new();
    for seed in 1..=24 {
        let mut config = SimConfig::default().seed(seed).unconfigured(3).virtual_time(true);
        for i in 1..=3 {
            config = config.fault(format!("sensor-0950130{i}:drop@2%").parse().unwrap());
        }
        let s = Scenario {
            seed,
            procedure: Procedure::Assign,
            config,
            stop_after: None,
            first_look: false,
            host_stall_ms: 0,
        };
        let out = run(&s);
        if out.broken.is_some() {
            trace(&out.frames);
        }
        assert!(out.broken.is_none(), "seed {seed}: {}", out.broken.unwrap());
        *outcomes.entry(out.ended).or_insert(0) += 1;
    }
    eprintln!("lss assign under 2 % loss, 24 runs: {outcomes:?}");
}

/// SDO under loss (issue 27): every device loses 2 % of its answers. Reads and plain value
/// writes must finish (a lost answer is retried, not waited out) and hold what they say;
/// a store (0x1010, an action) is sent at most once, and ends done or "outcome unknown".
#[test]
fn sdo_under_two_percent_loss_reads_and_plain_writes_finish_actions_are_sent_once() {
    let mut outcomes: BTreeMap<String, u32> = BTreeMap::new();
    let mut failed = Vec::new();
    for seed in 1..=60u64 {
        let procedure = match seed % 5 {
            0 => Procedure::Read(ReadKind::Expedited),
            1 => Procedure::Read(ReadKind::Segmented),
            2 => Procedure::Read(ReadKind::Block),
            3 => Procedure::Write,
            _ => Procedure::WriteDomain,
        };
        let mut config = SimConfig::default().profile(Profile::Typical).seed(seed).virtual_time(true);
        for node in NODES {
            config = config.fault(format!("{node}:drop@2%").parse().unwrap());
        }
        let s = Scenario { seed, procedure, config, stop_after: None, first_look: false, host_stall_ms: 0 };
        let out = run(&s);
        *outcomes.entry(format!("{:?}: {}", s.procedure, out.ended)).or_insert(0) += 1;
        if let Some(broken) = out.broken.or_else(|| (out.ended != "ok").then(|| out.ended.clone())) {
            failed.push(format!("seed {seed} {:?}: {broken}", s.procedure));
        }
        let (ended, stores) = store_under_loss(seed);
        *outcomes.entry(format!("store: {ended}")).or_insert(0) += 1;
        if stores > 1 || !(ended == "ok" || ended.contains("outcome unknown")) {
            failed.push(format!("seed {seed} store: sent {stores} times, ended {ended}"));
        }
    }
    eprintln!("SDO under 2 % loss, 60 seeds: {outcomes:#?}");
    assert!(failed.is_empty(), "{failed:#?}");
}

/// `store 5 all` (0x1010:1 "save") against a sensor losing a third of its answers: how it
/// ended, and how many times the request went out.
fn store_under_loss(seed: u64) -> (String, usize) {
    let config = SimConfig::default().seed(seed).virtual_time(true).fault("5:drop@33%".parse().unwrap());
    let sim = SimLink::with_config(config).on_virtual_time(1_700_000_000_000);
    let zero = sim.now();
    let mut master = Master::new(Tape { sim, zero, frames: Vec::new(), stalls: None }, "sim".into());
    let save = ObjAddr::new(0x1010, 1);
    let result = master.sdo_download(5, save, b"save", &SdoOptions::new(TIMEOUT));
    let request = [0x23, 0x10, 0x10, 0x01, b's', b'a', b'v', b'e'];
    let sent = master.link_mut().frames.iter().filter(|f| f.sent && f.id == 0x605 && f.data == request).count();
    let ended = match result {
        Ok(()) => "ok".to_string(),
        Err(e) => e.to_string(),
    };
    (ended, sent)
}

/// Seed 0x10a00f's finding, pinned (a later change to the requests moves a seed's faults
/// elsewhere): every answer of the device from its first answer to set-id on is cut
/// short. It took the node-id all the same (the request reached it), and the report must
/// not leave that out: the device may hold it, and the error says which and how to see.
#[test]
fn lss_assign_with_set_id_unanswered_says_the_device_may_hold_the_id() {
    let config = SimConfig::default().seed(7).unconfigured(1).virtual_time(true);
    let clean = Scenario {
        seed: 7,
        procedure: Procedure::Assign,
        config: config.clone(),
        stop_after: None,
        first_look: false,
        host_stall_ms: 0,
    };
    let out = run(&clean);
    assert!(out.broken.is_none() && out.ended == "ok", "{:?} {}", out.broken, out.ended);
    // The device's answers are counted from 1; the one to set-id is the first 0x11.
    let answers: Vec<&Taped> = out.frames.iter().filter(|f| !f.sent && f.id == 0x7E4).collect();
    let n = 1 + answers.iter().position(|f| f.data[0] == 0x11).expect("an answer to set-id");
    let config = config.fault(format!("sensor-09501301:short-dlc@{n}+").parse().unwrap());
    let s = Scenario {
        seed: 7,
        procedure: Procedure::Assign,
        config,
        stop_after: None,
        first_look: false,
        host_stall_ms: 0,
    };
    let out = run(&s);
    if out.broken.is_some() {
        trace(&out.frames);
    }
    assert!(out.broken.is_none(), "{}", out.broken.unwrap());
    assert_eq!(out.ended, "ended part-way");
}

/// Found against CANopenNode behind `netem delay 15ms loss 2%` (issue 27's vcan run): a node
/// with an id already, beating no heartbeat (CANopenNode's default, 0x1017 = 0; the drive
/// here), whose one answer to the SDO probe of the ids in use is lost. `lss assign` must
/// not give its node-id to a device without one: two devices would answer to it.
#[test]
fn lss_assign_never_gives_the_id_of_a_node_whose_probe_answer_was_lost() {
    let config = SimConfig::default().seed(1).unconfigured(1).virtual_time(true).fault("1:drop@1".parse().unwrap());
    let sim = SimLink::with_config(config).on_virtual_time(1_700_000_000_000);
    let mut master = Master::new(sim, "sim".into());
    let o = ops::lss::AssignOptions {
        start: 1,
        fastscan: ops::lss::FastscanOptions::new(TIMEOUT),
        listen: None,
        store: true,
    };
    let a = ops::lss::assign(&mut master, &o, &mut Silent, &Cancel::new());
    Bus::close(&mut master).unwrap();
    let on_1: Vec<Identity> =
        master.link_mut().network().devices().iter().filter(|d| d.node_id() == Some(1)).map(|d| d.identity()).collect();
    assert_eq!(on_1.len(), 1, "node-id 1 held by {on_1:?}; assign reported {a:?}");
}

/// A master over `config`'s network on virtual time.
fn virtual_master(config: SimConfig) -> Master<SimLink> {
    Master::new(SimLink::with_config(config).on_virtual_time(1_700_000_000_000), "sim".into())
}

/// A scan of `config`'s network on virtual time, through the library (a 100 ms window, as
/// the command's default): its report, and the master with the network as it left it.
fn scan_run(
    config: SimConfig,
    before: impl FnOnce(&mut Master<SimLink>),
) -> (Result<ops::scan::Scan>, Master<SimLink>) {
    let mut master = virtual_master(config);
    before(&mut master);
    let o = ops::scan::ScanOptions { window: Duration::from_millis(100), timeout: TIMEOUT };
    let scan = ops::scan::scan(&mut master, &o, &mut Silent);
    Bus::close(&mut master).unwrap();
    (scan, master)
}

/// The network of the scenarios with one answer of node 1 lost: the first, its answer to
/// the probe of node-ids.
fn first_probe_answer_of_node_1_lost() -> SimConfig {
    SimConfig::default().seed(1).virtual_time(true).fault("1:drop@1".parse().unwrap())
}

/// Found against CANopenNode behind `netem loss 2%` in the VM: a node beating no heartbeat
/// (CANopenNode's default; the drive, node 1, here) whose answer to the one SDO probe is
/// lost vanished from `scan`, exit 0, and from the scan cache. It is there: scan must list
/// it, and say that it answered only when asked again (the bus is losing frames).
#[test]
fn scan_lists_a_node_without_heartbeat_whose_probe_answer_was_lost() {
    let (scan, _) = scan_run(first_probe_answer_of_node_1_lost(), |_| {});
    let scan = scan.unwrap();
    let nodes: Vec<u8> = scan.nodes.iter().map(|n| n.node).collect();
    assert_eq!(nodes, [1, 5, 10, 32], "{scan:?}");
    assert!(scan.nodes.iter().all(|n| n.answers_sdo), "{scan:?}");
    // The technician learns the bus loses frames: the drive answered the second probe.
    assert_eq!(scan.answered_on_repeat, [ops::scan::Repeat { node: 1, probe: 2 }]);
    assert_eq!(scan.probe_rounds, 3);
    let json = serde_json::to_value(&scan).unwrap();
    assert_eq!(json["answered_on_repeat"][0]["node"], 1, "{json}");
}

/// `health` is a scan and then each node's checks: a node whose probe answer was lost must
/// not be left out of the checks (a silent pass).
#[test]
fn health_checks_a_node_whose_probe_answer_was_lost() {
    let mut master = virtual_master(first_probe_answer_of_node_1_lost());
    let o = ops::health::HealthOptions {
        window: Duration::from_millis(100),
        timeout: TIMEOUT,
        watch: None,
        state: None,
        last_seen: Vec::new(),
    };
    let h = ops::health::health(&mut master, &o, &mut Silent).unwrap();
    let nodes: Vec<u8> = h.nodes.iter().map(|n| n.node).collect();
    assert_eq!(nodes, [1, 5, 10, 32], "{h:?}");
    assert_eq!(h.answered_on_repeat, [ops::scan::Repeat { node: 1, probe: 2 }]);
}

/// `network check` probes once too: a listed node whose one answer was lost failed its
/// `present` check (exit 6, "did not answer") without being asked again.
#[test]
fn network_check_finds_a_listed_node_whose_probe_answer_was_lost() {
    let mut master = virtual_master(first_probe_answer_of_node_1_lost());
    let o = ops::network::CheckOptions { timeout: TIMEOUT, window: Duration::from_millis(100), jobs: 1, state: None };
    let checked = ops::network::check(&mut master, machine(), &o, &mut Silent).unwrap();
    let node_1 = checked.nodes.iter().find(|n| n.node == 1).expect("the project lists node 1");
    assert!(node_1.checks[0].ok, "{:?}", node_1.checks);
}

/// A node in Stopped answers no SDO but still beats its heartbeat: it is there, and scan
/// lists it with the state its heartbeat shows, marked as not answering SDO (after every
/// round of the probe), instead of leaving it out.
#[test]
fn scan_lists_a_stopped_node_seen_only_by_its_heartbeat() {
    let config = SimConfig::default().seed(1).virtual_time(true);
    let (scan, _) = scan_run(config, |m| m.nmt(Command::Stop, 5).unwrap());
    let scan = scan.unwrap();
    let nodes: Vec<u8> = scan.nodes.iter().map(|n| n.node).collect();
    assert_eq!(nodes, [1, 5, 10, 32], "{scan:?}");
    let sensor = &scan.nodes[1];
    assert_eq!((sensor.state, sensor.answers_sdo), (Some(nmt::State::Stopped), false), "{sensor:?}");
    assert!(scan.answered_on_repeat.is_empty(), "{scan:?}");
}

/// A listed node in Stopped answers no probe, but beats: `network check` fails its
/// `present` check all the same (nothing of it can be compared), saying it is there and
/// why it cannot be checked, not that it did not answer.
#[test]
fn network_check_says_a_stopped_listed_node_is_there() {
    let mut master = virtual_master(SimConfig::default().seed(1).virtual_time(true));
    master.nmt(Command::Stop, 5).unwrap();
    let o = ops::network::CheckOptions { timeout: TIMEOUT, window: Duration::from_millis(100), jobs: 1, state: None };
    let checked = ops::network::check(&mut master, machine(), &o, &mut Silent).unwrap();
    let sensor = checked.nodes.iter().find(|n| n.node == 5).expect("the project lists node 5");
    // "node 5 is there (stopped, by its heartbeat) but answered none of ...".
    let by_heartbeat = matches!(
        sensor.checks[0].detail,
        ops::network::Finding::SilentListed { node: 5, state: nmt::State::Stopped, .. }
    );
    assert!(!sensor.checks[0].ok && by_heartbeat, "{:?}", sensor.checks);
    assert!(!checked.ok);
}

/// A node the project does not list, in Stopped: it answers no probe but beats. `network
/// check` must not pass the network as the project's (a silent pass): it is unlisted.
#[test]
fn network_check_counts_a_stopped_node_the_project_does_not_list() {
    let mut master = virtual_master(SimConfig::default().seed(1).unconfigured(1).virtual_time(true));
    let o = ops::lss::AssignOptions {
        start: 40,
        fastscan: ops::lss::FastscanOptions::new(TIMEOUT),
        listen: None,
        store: false,
    };
    let a = ops::lss::assign(&mut master, &o, &mut Silent, &Cancel::new()).unwrap();
    assert_eq!(a.assigned.iter().map(|d| d.node).collect::<Vec<u8>>(), [40]);
    master.nmt(Command::Stop, 40).unwrap();
    let o = ops::network::CheckOptions { timeout: TIMEOUT, window: Duration::from_millis(100), jobs: 1, state: None };
    let checked = ops::network::check(&mut master, machine(), &o, &mut Silent).unwrap();
    assert_eq!(checked.unlisted.iter().map(|u| u.node).collect::<Vec<u8>>(), [40], "{checked:?}");
    assert!(!checked.ok);
}

/// A node in Stopped answers no SDO but beats: `health` passed the bus without it (a silent
/// pass). It is listed, not healthy, with the reason and what to do.
#[test]
fn health_does_not_pass_a_bus_with_a_node_that_answers_no_sdo() {
    let mut master = virtual_master(SimConfig::default().seed(1).virtual_time(true));
    master.nmt(Command::Stop, 5).unwrap();
    let o = ops::health::HealthOptions {
        window: Duration::from_millis(100),
        timeout: TIMEOUT,
        watch: None,
        state: None,
        last_seen: Vec::new(),
    };
    let h = ops::health::health(&mut master, &o, &mut Silent).unwrap();
    let sensor = h.nodes.iter().find(|n| n.node == 5).expect("the stopped sensor checked");
    let sdo = sensor.checks.iter().find(|c| c.check == "sdo").expect("an sdo check");
    // What to do is typed: the command line names the command (`canctl nmt preop 5`).
    assert!(!sdo.ok && format!("{:?}", sdo.remedy) == "Some(PreOperational { node: 5 })", "{sdo:?}");
    assert!(!h.ok && h.outcome().is_err());
}

/// `scan` with every node losing 5 % of its answers (more than `netem loss 2%` in the VM),
/// 24 seeds on virtual time: every node is listed each time, and a node found only on a
/// repeat is said.
#[test]
fn scan_under_five_percent_loss_lists_every_node() {
    let mut repeats = 0;
    for seed in 1..=24 {
        let mut config = SimConfig::default().profile(Profile::Typical).seed(seed).virtual_time(true);
        for node in NODES {
            config = config.fault(format!("{node}:drop@5%").parse().unwrap());
        }
        let (scan, _) = scan_run(config, |_| {});
        let scan = scan.unwrap();
        let nodes: Vec<u8> = scan.nodes.iter().map(|n| n.node).collect();
        assert_eq!(nodes, NODES, "seed {seed}: {scan:?}");
        repeats += scan.answered_on_repeat.len();
    }
    eprintln!("scan under 5 % loss, 24 runs: {repeats} node(s) found on a repeat");
}

/// The demo network with these faults (typical profile, seed `seed`) on virtual time,
/// behind a tape of every frame.
fn taped(seed: u64, faults: &[&str]) -> Master<Tape> {
    let mut config = SimConfig::default().profile(Profile::Typical).seed(seed).virtual_time(true);
    for f in faults {
        config = config.fault(f.parse().expect("a fault spec"));
    }
    let sim = SimLink::with_config(config).on_virtual_time(1_700_000_000_000);
    let zero = sim.now();
    Master::new(Tape { sim, zero, frames: Vec::new(), stalls: None }, "sim".into())
}

/// One device that answers without end must not stretch the wait for a silent one: the
/// silent node's requests all go out, and it is given up, while the endless transfer is
/// still under way (it used to wait until that transfer ended: a hang behind one device).
#[test]
fn a_node_answering_without_end_does_not_hold_up_giving_up_a_silent_one() {
    let mut master = taped(7, &["10:endless-segments", "5:off"]);
    // At 64 KiB the endless read is thousands of round trips.
    let opts = SdoOptions { max_upload: 64 * 1024, ..SdoOptions::new(TIMEOUT) };
    let reads = [(10, ObjAddr::new(0x1008, 0)), (5, ObjAddr::new(0x1000, 0))];
    let got = master.sdo_upload_many(&reads, &opts, &mut |_| {}).expect("the link works");
    assert!(matches!(got[1], Err(Error::NoAnswer { .. })), "{:?}", got[1]);
    assert!(got[0].as_ref().is_err_and(|e| e.to_string().contains("did not end")), "{:?}", got[0]);
    let frames = &master.link_mut().frames;
    let last = |id: u16, sent: bool| frames.iter().filter(|f| f.id == id && f.sent == sent).map(|f| f.at).max();
    let (silent, endless) = (last(0x605, true).expect("requests to node 5"), last(0x58A, false).expect("answers"));
    assert!(silent < endless / 2, "node 5 last asked at {silent:?}, node 10 answered until {endless:?}");
}

/// A request to stop ends a batch of reads within half a second of bus time, whatever the
/// devices do: one sending a block upload without end, one a name without end, one silent.
#[test]
fn a_stop_ends_a_batch_within_half_a_second_whatever_the_devices_do() {
    let mut master = taped(11, &["1:endless-block", "10:endless-segments", "5:off"]);
    let zero = master.link_mut().zero;
    let stop = Cancel::new();
    let flag = stop.clone();
    // Stopped once the endless block upload has brought its first sub-block (889 bytes).
    let hook: std::sync::Arc<dyn Fn(usize) + Send + Sync> = std::sync::Arc::new(move |moved| {
        if moved >= 700 {
            flag.cancel();
        }
    });
    let opts =
        SdoOptions { block_upload: true, on_progress: Some(hook), ..SdoOptions::new(Duration::from_millis(500)) };
    let reads = [(1, DOMAIN), (10, ObjAddr::new(0x1008, 0)), (5, ObjAddr::new(0x1000, 0))];
    let got = Stoppable::new(&mut master, stop.clone()).sdo_upload_many(&reads, &opts, &mut |_| {});
    let got = got.expect("the link works");
    // The two under way stopped; the silent one, let finish for the grace, not asked again.
    assert!(matches!(got[..2], [Err(Error::SdoInterrupted { .. }), Err(Error::SdoInterrupted { .. })]), "{got:?}");
    assert!(matches!(got[2], Err(Error::NoAnswer { .. })), "{:?}", got[2]);
    let tape = master.link_mut();
    assert_eq!(tape.frames.iter().filter(|f| f.id == 0x605 && f.sent).count(), 1, "node 5 asked again after the stop");
    let took = tape.now().saturating_duration_since(zero);
    // The stop came with the 127th segment of the first sub-block.
    let stopped_at = tape.frames.iter().filter(|f| f.id == 0x581 && !f.sent).nth(127).expect("a sub-block").at;
    assert!(took <= stopped_at + Duration::from_millis(500), "stopped at {stopped_at:?}, ended at {took:?}");
}
