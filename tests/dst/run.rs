//! One run: the procedure through the library, and what it reported.

use super::*;

/// What one run gave: every frame, and the invariant it broke, if any.
pub struct Outcome {
    pub frames: Vec<Taped>,
    pub broken: Option<String>,
    /// Bus time the procedure took.
    pub took: Duration,
    /// How it ended: `ok` or the error.
    pub ended: String,
}

/// The longest any procedure may take in bus time, faults included.
pub const BOUND: Duration = Duration::from_secs(5 * 60);

/// The bound of one scenario. An LSS search is 133 requests, and a step may grow to
/// [`STEP_CEILING`] when answers come late: so one whole search at the longest step per
/// device without a node-id, and one that finds nobody; five minutes for the rest.
pub fn bound(s: &Scenario) -> Duration {
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
pub const LOOKING_BOUND: Duration = Duration::from_secs(30);

/// A read of a silent node (three requests of 200 ms) and its quick diagnosis (two waits
/// of at most 500 ms, and the probe's rounds), faults included.
pub const DIAGNOSE_BOUND: Duration = Duration::from_secs(5);

pub fn run(s: &Scenario) -> Outcome {
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
    let mut master = Master::new(Tape::new(sim, stalls), "sim".into());
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
pub enum Report {
    /// The NMT state a node was reported in.
    State(u8, nmt::State),
    /// Values read from a node's object.
    Read(u8, ObjAddr, Vec<u8>),
    Wrote(u8, ObjAddr, Vec<u8>),
    /// Nodes and identities a scan reported, whether it was stopped part-way, and the
    /// nodes it said lost frames (answered only a repeat of the probe).
    /// The nodes found with their serials, whether interrupted, the nodes said to lose
    /// frames, the node-ids said to be used by two devices.
    Scanned(Vec<(u8, Option<u32>)>, bool, Vec<u8>, Vec<u8>),
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

pub fn procedure(bus: &mut dyn Bus, s: &Scenario, stop: &Cancel) -> Result<Report> {
    let opts = SdoOptions::new(TIMEOUT);
    match s.procedure {
        Procedure::Scan => {
            let o = ops::scan::ScanOptions { window: Duration::from_millis(300), timeout: TIMEOUT };
            // As canctl scans a bus it scanned before (knowing the nodes the last scan saw),
            // or one it never scanned.
            let scan = ops::scan::scan_against(bus, &o, last_seen(s), &mut Silent)?;
            let lost = scan.answered_on_repeat.iter().map(|r| r.node).collect();
            let clashes = scan.clashes.iter().map(|c| c.node).collect();
            let nodes = scan.nodes.iter().map(|n| (n.node, n.serial)).collect();
            Ok(Report::Scanned(nodes, scan.interrupted, lost, clashes))
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
        Procedure::StopThenState { before_beat_ends } => {
            // The program did something else for a while: the sensor's beats wait unread,
            // from before the stop, which is sent as one is about to end.
            let idle = bus.now() + Duration::from_millis(100);
            let stop_at = match sensor_beat_ends(bus)? {
                Some((last, period)) => {
                    let mut next = last + period;
                    while next < idle {
                        next += period;
                    }
                    next - before_beat_ends
                }
                None => idle,
            };
            bus.sleep_until(stop_at)?;
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
            // A failure ends the run; a verdict (a node not in the project) is the report's.
            if let Some(ops::unmet::Shortfall::Failed(e)) = applied.failure {
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

pub const DOMAIN: ObjAddr = ObjAddr::new(0x1F50, 1);

/// What the last scan saw before each run: the demo network's nodes.
/// When the sensor's last beat of two heard ended, and its period; `None` when it did not
/// beat twice within a second (a fault took it off, or it rebooted).
fn sensor_beat_ends(bus: &mut dyn Bus) -> Result<Option<(Instant, Duration)>> {
    let deadline = bus.now() + Duration::from_secs(1);
    let mut ends = Vec::new();
    while let Some((f, at)) = bus.recv_frame_stamped(deadline)? {
        if matches!(nmt::ErrorControl::parse(&f), Some((5, nmt::ErrorControl::State { .. }))) {
            ends.push(at);
        }
        if let [.., before, last] = ends[..] {
            return Ok(Some((last, last - before)));
        }
    }
    Ok(None)
}

pub fn last_scan() -> Vec<ops::scan_cache::SeenNode> {
    let text = serde_json::json!(NODES.iter().map(|n| serde_json::json!({ "node": n })).collect::<Vec<_>>());
    serde_json::from_value(text).expect("seen nodes")
}

/// The example project (read once: parsing its DCFs would be most of a short scenario).
pub fn machine() -> &'static ops::network::Loaded {
    static LOADED: std::sync::OnceLock<ops::network::Loaded> = std::sync::OnceLock::new();
    LOADED.get_or_init(|| {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/sim-machine/nodelist.cpj");
        ops::network::load(&path).expect("the example project")
    })
}

pub fn sensor_dcf() -> &'static ops::config::Dcf {
    static DCF: std::sync::OnceLock<ops::config::Dcf> = std::sync::OnceLock::new();
    DCF.get_or_init(|| ops::config::Dcf::parse(include_bytes!("../../examples/sensor.dcf"), "sensor.dcf").unwrap())
}
