//! Cases the seeded scenarios found once or keep close to: each its own test.

use super::*;

/// `lss assign` of three devices whose answers are lost 2 % of the time (a USB adapter or
/// gateway under load), on virtual time: whatever each run ends with, it never says every
/// device has a node-id while one still waits (exit 0 is only for a confirmed bus).
#[test]
pub fn lss_assign_under_two_percent_loss_never_calls_a_waiting_device_done() {
    let mut outcomes = BTreeMap::new();
    for seed in 1..=24 {
        let mut config = SimConfig::default().seed(seed).unconfigured(3).virtual_time(true);
        for i in 1..=3 {
            config = config.fault(format!("sensor-0950130{i}:drop@2%").parse().unwrap());
        }
        let s = Scenario::plain(seed, Procedure::Assign, config);
        let out = run_unbroken(&s);
        *outcomes.entry(out.ended).or_insert(0) += 1;
    }
    eprintln!("lss assign under 2 % loss, 24 runs: {outcomes:?}");
}

/// SDO under loss (issue 27): every device loses 2 % of its answers. Reads and plain value
/// writes must finish (a lost answer is retried, not waited out) and hold what they say;
/// a store (0x1010, an action) is sent at most once, and ends done or "outcome unknown".
#[test]
pub fn sdo_under_two_percent_loss_reads_and_plain_writes_finish_actions_are_sent_once() {
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
        let s = Scenario::plain(seed, procedure, config);
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
pub fn store_under_loss(seed: u64) -> (String, usize) {
    let config = SimConfig::default().seed(seed).virtual_time(true).fault("5:drop@33%".parse().unwrap());
    let sim = SimLink::with_config(config).on_virtual_time(1_700_000_000_000);
    let mut master = Master::new(Tape::new(sim, None), "sim".into());
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
pub fn lss_assign_with_set_id_unanswered_says_the_device_may_hold_the_id() {
    let config = SimConfig::default().seed(7).unconfigured(1).virtual_time(true);
    let clean = Scenario::plain(7, Procedure::Assign, config.clone());
    let out = run(&clean);
    assert!(out.broken.is_none() && out.ended == "ok", "{:?} {}", out.broken, out.ended);
    // The device's answers are counted from 1; the one to set-id is the first 0x11.
    let answers: Vec<&Taped> = out.frames.iter().filter(|f| !f.sent && f.id == 0x7E4).collect();
    let n = 1 + answers.iter().position(|f| f.data[0] == 0x11).expect("an answer to set-id");
    let config = config.fault(format!("sensor-09501301:short-dlc@{n}+").parse().unwrap());
    let s = Scenario::plain(7, Procedure::Assign, config);
    let out = run_unbroken(&s);
    assert_eq!(out.ended, "ended part-way");
}

/// Found against CANopenNode behind `netem delay 15ms loss 2%` (issue 27's vcan run): a node
/// with an id already, beating no heartbeat (CANopenNode's default, 0x1017 = 0; the drive
/// here), whose one answer to the SDO probe of the ids in use is lost. `lss assign` must
/// not give its node-id to a device without one: two devices would answer to it.
#[test]
pub fn lss_assign_never_gives_the_id_of_a_node_whose_probe_answer_was_lost() {
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
pub fn virtual_master(config: SimConfig) -> Master<SimLink> {
    Master::new(SimLink::with_config(config).on_virtual_time(1_700_000_000_000), "sim".into())
}

/// A scan of `config`'s network on virtual time, through the library (a 100 ms window, as
/// the command's default): its report, and the master with the network as it left it.
pub fn scan_run(
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
pub fn first_probe_answer_of_node_1_lost() -> SimConfig {
    SimConfig::default().seed(1).virtual_time(true).fault("1:drop@1".parse().unwrap())
}

/// Found against CANopenNode behind `netem loss 2%` in the VM: a node beating no heartbeat
/// (CANopenNode's default; the drive, node 1, here) whose answer to the one SDO probe is
/// lost vanished from `scan`, exit 0, and from the scan cache. It is there: scan must list
/// it, and say that it answered only when asked again (the bus is losing frames).
#[test]
pub fn scan_lists_a_node_without_heartbeat_whose_probe_answer_was_lost() {
    let (scan, _) = scan_run(first_probe_answer_of_node_1_lost(), |_| {});
    let scan = scan.unwrap();
    let nodes: Vec<u8> = scan.nodes.iter().map(|n| n.node).collect();
    assert_eq!(nodes, [1, 5, 10, 32], "{scan:?}");
    assert!(scan.nodes.iter().all(|n| n.answers_sdo), "{scan:?}");
    // The technician learns the bus loses frames: the drive answered the second probe.
    assert_eq!(scan.answered_on_repeat, [ops::scan::Repeat { node: 1, probes: 2, answered: 1 }]);
    assert_eq!(scan.probe_rounds, 3);
    let json = serde_json::to_value(&scan).unwrap();
    assert_eq!(json["answered_on_repeat"][0]["node"], 1, "{json}");
}

/// `health` is a scan and then each node's checks: a node whose probe answer was lost must
/// not be left out of the checks (a silent pass).
#[test]
pub fn health_checks_a_node_whose_probe_answer_was_lost() {
    let mut master = virtual_master(first_probe_answer_of_node_1_lost());
    let h = ops::health::health(&mut master, &health_options(), &mut Silent).unwrap();
    let nodes: Vec<u8> = h.nodes.iter().map(|n| n.node).collect();
    assert_eq!(nodes, [1, 5, 10, 32], "{h:?}");
    assert_eq!(h.answered_on_repeat, [ops::scan::Repeat { node: 1, probes: 2, answered: 1 }]);
}

/// `network check` probes once too: a listed node whose one answer was lost failed its
/// `present` check (exit 6, "did not answer") without being asked again.
#[test]
pub fn network_check_finds_a_listed_node_whose_probe_answer_was_lost() {
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
pub fn scan_lists_a_stopped_node_seen_only_by_its_heartbeat() {
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
pub fn network_check_says_a_stopped_listed_node_is_there() {
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
pub fn network_check_counts_a_stopped_node_the_project_does_not_list() {
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
pub fn health_does_not_pass_a_bus_with_a_node_that_answers_no_sdo() {
    let mut master = virtual_master(SimConfig::default().seed(1).virtual_time(true));
    master.nmt(Command::Stop, 5).unwrap();
    let h = ops::health::health(&mut master, &health_options(), &mut Silent).unwrap();
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
pub fn scan_under_five_percent_loss_lists_every_node() {
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
pub fn taped(seed: u64, faults: &[&str]) -> Master<Tape> {
    let mut config = SimConfig::default().profile(Profile::Typical).seed(seed).virtual_time(true);
    for f in faults {
        config = config.fault(f.parse().expect("a fault spec"));
    }
    let sim = SimLink::with_config(config).on_virtual_time(1_700_000_000_000);
    Master::new(Tape::new(sim, None), "sim".into())
}

/// One device that answers without end must not stretch the wait for a silent one: the
/// silent node's requests all go out, and it is given up, while the endless transfer is
/// still under way (it used to wait until that transfer ended: a hang behind one device).
#[test]
pub fn a_node_answering_without_end_does_not_hold_up_giving_up_a_silent_one() {
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
pub fn a_stop_ends_a_batch_within_half_a_second_whatever_the_devices_do() {
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
    // The two under way stopped; the silent one, let finish for the grace, not asked again,
    // and not said to be silent: the stop cut its wait short (250 ms of 500).
    assert!(matches!(got[..2], [Err(Error::SdoInterrupted { .. }), Err(Error::SdoInterrupted { .. })]), "{got:?}");
    assert!(matches!(got[2], Err(Error::Interrupted)), "{:?}", got[2]);
    let tape = master.link_mut();
    assert_eq!(tape.frames.iter().filter(|f| f.id == 0x605 && f.sent).count(), 1, "node 5 asked again after the stop");
    let took = tape.now().saturating_duration_since(zero);
    // The stop came with the 127th segment of the first sub-block.
    let stopped_at = tape.frames.iter().filter(|f| f.id == 0x581 && !f.sent).nth(127).expect("a sub-block").at;
    assert!(took <= stopped_at + Duration::from_millis(500), "stopped at {stopped_at:?}, ended at {took:?}");
}

/// Run `s`, which must keep every invariant (its frames traced when it does not, with
/// `CANCTL_DST_TRACE`).
fn run_unbroken(s: &Scenario) -> Outcome {
    let out = run(s);
    if let Some(broken) = &out.broken {
        trace(&out.frames);
        panic!("seed {}: {broken}", s.seed);
    }
    out
}

/// `health` with a 100 ms window, for the first time on this bus.
fn health_options() -> ops::health::HealthOptions {
    ops::health::HealthOptions {
        window: Duration::from_millis(100),
        timeout: TIMEOUT,
        watch: None,
        state: None,
        last_seen: Vec::new(),
    }
}
