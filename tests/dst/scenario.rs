//! The scenarios: what each seed draws (procedure, network, faults) and its bound.

use super::*;

/// The procedures the harness runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Procedure {
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
    /// 5` in one program (drawn in place of a reset). The stop is sent this long before one
    /// of the sensor's beats ends: while it is on the wire, or queued behind the stop.
    StopThenState {
        before_beat_ends: Duration,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReadKind {
    Expedited,
    Segmented,
    Block,
}

pub const PROCEDURES: &[Procedure] = &[
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
pub struct Scenario {
    pub seed: u64,
    pub procedure: Procedure,
    pub config: SimConfig,
    /// Stop requested after this many confirmed SDO transfers or NMT commands.
    pub stop_after: Option<u32>,
    /// A scan or health check of a bus canctl has not scanned before (no scan cache): what
    /// the bus shows by itself is all it knows.
    pub first_look: bool,
    /// A loaded host that polls the link late, by up to this many ms now and then (0: never).
    pub host_stall_ms: u64,
}

pub const NODES: [u8; 4] = [1, 5, 10, 32];
/// How many times scan asks a node-id that does not answer, on a bus that shows its
/// traffic (ops::scan's rounds of the probe).
pub const SCAN_PROBE_ROUNDS: usize = 3;
pub const TIMEOUT: Duration = Duration::from_millis(200);

pub fn pick<T: Copy>(rng: &mut Rng, from: &[T]) -> T {
    from[rng.between(0, from.len() as u64 - 1) as usize]
}

impl Scenario {
    pub fn of(seed: u64) -> Scenario {
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
        let stop_then_state = procedure == Procedure::Reset && rng.chance(0.5);
        // And after it: a loaded host.
        let host_stall_ms = if rng.chance(0.25) { rng.between(2, 60) } else { 0 };
        // And after it: when the stop goes, from 4 ms before a beat ends (well before it
        // was due) to just before (it is on the wire), by the µs.
        if stop_then_state {
            procedure = Procedure::StopThenState { before_beat_ends: Duration::from_micros(rng.between(1, 4_000)) };
        }
        Scenario { seed, procedure, config, stop_after, first_look, host_stall_ms }
    }

    /// A scenario of its own test: no stop, a bus scanned before, a host that keeps up.
    pub fn plain(seed: u64, procedure: Procedure, config: SimConfig) -> Scenario {
        Scenario { seed, procedure, config, stop_after: None, first_look: false, host_stall_ms: 0 }
    }

    pub fn clean(&self) -> bool {
        self.config.faults.is_empty() && self.stop_after.is_none()
    }
}

/// One device of the network: a node-id, or the model key of a device waiting for one.
pub fn pick_target(rng: &mut Rng, unconfigured: u8) -> String {
    let mut targets: Vec<String> = NODES.iter().map(|n| n.to_string()).collect();
    targets.extend((1..=unconfigured).map(|i| format!("sensor-095013{i:02}")));
    targets[rng.between(0, targets.len() as u64 - 1) as usize].clone()
}

/// A fault drawn for one device of the network.
pub fn fault(rng: &mut Rng, unconfigured: u8) -> String {
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
