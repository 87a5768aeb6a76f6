//! The crate as a library, without the command line: everything here uses library APIs
//! only, so it builds and runs with `cargo test --no-default-features --test library`.

use canctl::bus::{self, Bus};
use canctl::cancel::Cancel;
use canctl::canopen::nmt;
use canctl::canopen::types::Value;
use canctl::canopen::DataType;
use canctl::canopen::ObjAddr;
use canctl::connect::{self, BusAddr, OpenOptions};
use canctl::ops::config::{self, ApplyOptions, Dcf};
use canctl::ops::dictionaries::Dictionaries;
use canctl::ops::monitor::Monitor;
use canctl::ops::nmt::{self as nmt_ops, Confirmation, ResetOptions, StateOptions};
use canctl::ops::pdo::{self, Session, Stream, StreamOptions};
use canctl::ops::scan::{self, ScanOptions};
use canctl::ops::scan_cache::SeenNode;
use canctl::ops::sdo::{self, ReadOptions, WriteOptions};
use canctl::ops::store::{self, Class, Timeouts};
use canctl::ops::Progress;
use canctl::settings::EdsFile;
use canctl::Error;
use std::time::Duration;

const TIMEOUT: Duration = Duration::from_millis(500);
/// The demo network's position sensor.
const SENSOR: u8 = 5;

fn demo() -> Box<dyn Bus> {
    let mut opts = OpenOptions::new(TIMEOUT);
    opts.ephemeral = true;
    connect::open(&"sim".parse::<BusAddr>().unwrap(), &opts).unwrap()
}

fn sensor_dcf() -> Dcf {
    Dcf::parse(include_bytes!("../examples/sensor.dcf"), "sensor.dcf").unwrap()
}

/// What a procedure reported, in order.
#[derive(Default)]
struct Recorder {
    calls: Vec<String>,
    events: Vec<canctl::ops::Event>,
}

impl Progress for Recorder {
    fn start(&mut self, what: &str, len: u64) {
        self.calls.push(format!("start {what} {len}"));
    }
    fn advance(&mut self, done: u64) {
        self.calls.push(format!("advance {done}"));
    }
    fn finish(&mut self) {
        self.calls.push("finish".into());
    }
    fn event(&mut self, event: canctl::ops::Event) {
        self.calls.push(format!("event {event:?}"));
        self.events.push(event);
    }
}

#[test]
fn bus_addresses_print_as_they_parse() {
    for text in ["sim", "sim:/tmp/x.json", "socketcan:can0", "epos2-rs232:/dev/ttyS0?baud=38400", "epos2-usb:COM4"] {
        assert_eq!(text.parse::<BusAddr>().unwrap().to_string(), text);
    }
}

#[test]
fn a_dcf_is_applied_verified_and_stored_then_matches() {
    let mut bus = demo();
    let dcf = sensor_dcf();
    let before = config::diff(bus.as_mut(), SENSOR, &dcf, TIMEOUT).unwrap();
    assert_eq!(before.differences.len(), 3, "{before:?}");
    assert!(before.check().is_err());

    let mut o = ApplyOptions::new(TIMEOUT);
    o.verify = true;
    o.store = true;
    let applied = config::apply(bus.as_mut(), SENSOR, &dcf, &o).unwrap();
    assert!(applied.stored);
    assert_eq!(applied.written.len(), 3);
    assert!(applied.objects.iter().all(|c| c.result.to_string() == "written, verified"), "{applied:?}");
    let json = serde_json::to_value(&applied).unwrap();
    assert_eq!(json["objects"][0]["object"], "0x1017:0");
    applied.outcome().unwrap();

    let after = config::diff(bus.as_mut(), SENSOR, &dcf, TIMEOUT).unwrap();
    assert!(after.differences.is_empty(), "{after:?}");
    assert_eq!(after.same, 3);
    // Idempotent: a second run has nothing to write.
    let again = config::apply(bus.as_mut(), SENSOR, &dcf, &o).unwrap();
    assert!(again.objects.is_empty() && again.written.is_empty(), "{again:?}");
    bus.close().unwrap();
}

#[test]
fn a_dry_run_writes_nothing() {
    let mut bus = demo();
    let mut o = ApplyOptions::new(TIMEOUT);
    o.dry_run = true;
    let report = config::apply(bus.as_mut(), SENSOR, &sensor_dcf(), &o).unwrap();
    assert!(report.objects.iter().all(|c| c.result.action == config::Action::WouldWrite) && !report.stored);
    assert_eq!(config::diff(bus.as_mut(), SENSOR, &sensor_dcf(), TIMEOUT).unwrap().differences.len(), 3);
}

#[test]
fn a_dump_reports_its_progress_and_reads_back_as_the_node() {
    let mut bus = demo();
    let mut progress = Recorder::default();
    let dump = config::dump(bus.as_mut(), SENSOR, None, "node5.dcf", TIMEOUT, &mut progress).unwrap();
    assert!(dump.objects > 10, "{dump:?}");
    assert!(progress.calls[0].starts_with("start reading "), "{:?}", progress.calls);
    assert_eq!(progress.calls.last().map(String::as_str), Some("finish"));
    let dcf = Dcf::parse(&dump.dcf, "node5.dcf").unwrap();
    let diff = config::diff(bus.as_mut(), SENSOR, &dcf, TIMEOUT).unwrap();
    assert!(diff.differences.is_empty(), "{diff:?}");
}

#[test]
fn store_and_restore_report_the_object_written() {
    let mut bus = demo();
    let t = Timeouts { answer: TIMEOUT, write: Duration::from_secs(5) };
    let stored = store::store(bus.as_mut(), SENSOR, Class::All, t).unwrap();
    assert_eq!(stored.object, ObjAddr::new(0x1010, 1));
    assert_eq!(serde_json::to_value(&stored).unwrap()["stored"], "all parameters");
    let restored = store::restore(bus.as_mut(), SENSOR, Class::All, t).unwrap();
    assert_eq!((restored.object, restored.reset), (ObjAddr::new(0x1011, 1), false));
}

#[test]
fn the_sensors_tpdo_streams_and_the_session_is_put_back() {
    let mut bus = demo();
    let dict = canctl::od::builtin::dictionary(Some(406));
    let mut progress = Recorder::default();
    let layouts = pdo::read_layouts(bus.as_mut(), SENSOR, dict, &[1], false, TIMEOUT, &mut progress).unwrap();
    assert_eq!(layouts.len(), 1);
    assert_eq!(layouts[0].1.fields.len(), 2, "{layouts:?}");

    let mut session = Session::default();
    session.start(bus.as_mut(), SENSOR, nmt::State::PreOperational).unwrap();
    let opts = StreamOptions {
        count: Some(3),
        duration: Some(Duration::from_secs(10)),
        sync: None,
        interval: TIMEOUT,
        timeout: TIMEOUT,
        silence: None,
    };
    let never = Cancel::new();
    let mut stream = Stream::new(bus.as_ref(), SENSOR, &layouts, opts, &never);
    let mut records = Vec::new();
    while let Some(r) = stream.next(bus.as_mut(), &mut progress).unwrap() {
        records.push(r);
    }
    assert_eq!(records.len(), 3, "{progress:?}", progress = progress.calls);
    assert!(records.iter().all(|r| r.layout == 0 && r.values.len() == 2));
    session.restore(bus.as_mut(), SENSOR, TIMEOUT).unwrap();
}

#[test]
fn the_monitor_sees_the_sensors_heartbeat() {
    let mut bus = demo();
    let mut monitor =
        Monitor::new(bus.as_ref(), Default::default(), &[SENSOR], Some(Duration::from_secs(10)), None).unwrap();
    let heartbeat = std::iter::from_fn(|| monitor.next(bus.as_mut()).unwrap()).find(|e| e.kind == "heartbeat");
    let heartbeat = heartbeat.expect("a heartbeat within 10 s");
    assert_eq!(heartbeat.node, Some(SENSOR));
    assert!(monitor.summary().frames() >= 1);
}

#[test]
fn a_scan_finds_the_demo_network_with_identities_and_states() {
    let mut bus = demo();
    let mut progress = Recorder::default();
    let o = ScanOptions { window: Duration::from_millis(100), timeout: TIMEOUT };
    let found = scan::scan(bus.as_mut(), &o, &mut progress).unwrap();
    let ids: Vec<u8> = found.nodes.iter().map(|n| n.node).collect();
    assert_eq!(ids, [1, 5, 10, 32], "{found:?}");
    let sensor = &found.nodes[1];
    assert_eq!((sensor.vendor_id, sensor.product_code), (Some(0x40), Some(0x4378_7800)));
    assert_eq!(sensor.name.as_deref(), Some("C01"));
    assert_eq!(found.nodes[3].vendor_id, None, "node 32 has no 0x1018:1");
    assert!(found.nodes.iter().all(|n| n.state == Some(nmt::State::PreOperational)), "{found:?}");
    assert_eq!(found.lss_unconfigured, 3);
    assert_eq!(found.lss_configuration.count, 0);
    assert!(progress.calls.contains(&"start probing 127".to_string()), "{:?}", progress.calls);
    assert!(progress.calls.contains(&format!("start identity {}", 4 * 6)), "{:?}", progress.calls);

    let json = serde_json::to_value(&found).unwrap();
    assert_eq!(json["bus"], found.bus);
    assert_eq!(json["nodes"][1]["state"], "pre-operational");
    assert_eq!(json["lss_configuration"]["devices"], serde_json::json!([]));
    let seen = SeenNode::from_scan(&found, &canctl::ops::dictionaries::Dictionaries::default());
    let sensor = &seen[1];
    assert_eq!(
        (sensor.node, sensor.name.as_deref(), sensor.vendor_id, sensor.device_type),
        (5, Some("C01"), Some(0x40), Some(0x000A_0196))
    );
    // What the scan read of it is known to be there; no description was given for it.
    assert!(sensor.answered.contains(&(0x1018, 4)) && sensor.answered.contains(&(0x1000, 0)), "{sensor:?}");
    assert_eq!(sensor.dictionary, None);
}

#[test]
fn a_stopped_node_shows_its_state_and_a_scan_lists_it_as_not_answering_sdo() {
    let mut bus = demo();
    let sent = nmt_ops::send(bus.as_mut(), nmt::Command::Stop, SENSOR).unwrap();
    assert_eq!(serde_json::to_value(&sent).unwrap(), serde_json::json!({"command": "stop", "target": 5, "sent": true}));
    let o = StateOptions { listen: Duration::from_millis(300), timeout: TIMEOUT };
    let state = nmt_ops::state(bus.as_mut(), SENSOR, &o).unwrap();
    assert_eq!(state.state, nmt::State::Stopped, "{state:?}");
    // Stopped, it answers no SDO, but its heartbeat shows it is there: a scan lists it so.
    let o = ScanOptions { window: Duration::from_millis(100), timeout: TIMEOUT };
    let found = scan::scan(bus.as_mut(), &o, &mut Recorder::default()).unwrap();
    let sensor = found.nodes.iter().find(|n| n.node == SENSOR).expect("the stopped sensor listed");
    assert_eq!(
        (sensor.answers_sdo, sensor.state, sensor.vendor_id),
        (false, Some(nmt::State::Stopped), None),
        "{found:?}"
    );
}

#[test]
fn a_reset_is_confirmed_by_the_boot_up_of_each_node() {
    let mut bus = demo();
    let o = ResetOptions { wait: Duration::from_secs(5), timeout: TIMEOUT };
    nmt_ops::send(bus.as_mut(), nmt::Command::Start, SENSOR).unwrap();
    let one = nmt_ops::reset(bus.as_mut(), nmt::Command::ResetNode, SENSOR, &o).unwrap();
    assert!(one.confirmed && one.why.is_none(), "{one:?}");
    assert_eq!(one.booted, Some(vec![SENSOR]));
    assert_eq!(one.seen_by, Some(nmt_ops::SeenBy::BootUpMessage));
    let state =
        nmt_ops::state(bus.as_mut(), SENSOR, &StateOptions { listen: Duration::from_millis(300), timeout: TIMEOUT });
    assert_eq!(state.unwrap().state, nmt::State::PreOperational);

    let all = nmt_ops::reset_and_wait(bus.as_mut(), nmt::Command::ResetCommunication, bus::ALL_NODES, &o).unwrap();
    assert_eq!(all, Confirmation::Confirmed(vec![1, 5, 10, 32], nmt_ops::SeenBy::BootUpMessage));
    let json = serde_json::to_value(nmt_ops::reset(bus.as_mut(), nmt::Command::ResetNode, bus::ALL_NODES, &o).unwrap());
    assert_eq!(json.unwrap()["target"], "all");
}

#[test]
fn a_reset_of_a_node_that_is_not_there_times_out() {
    let mut bus = demo();
    let o = ResetOptions { wait: Duration::from_millis(300), timeout: TIMEOUT };
    let err = nmt_ops::reset(bus.as_mut(), nmt::Command::ResetNode, 99, &o).unwrap_err();
    assert!(matches!(err, Error::NoAnswer { node: 99, .. }), "{err}");
    assert_eq!(err.exit_code(), 3);
}

#[test]
fn an_sdo_write_takes_its_type_from_the_dictionary_and_reads_back() {
    let mut bus = demo();
    let dicts = Dictionaries::default();
    let dict = dicts.for_node(SENSOR);
    let (object, _) = dicts.resolve(SENSOR, "ProducerHeartbeatTime").unwrap();
    let w = WriteOptions { timeout: TIMEOUT, dtype: None, block: true, verify: true };
    let written = sdo::write(bus.as_mut(), dict, SENSOR, object, "250", &w).unwrap();
    assert_eq!((written.dtype, written.size, written.verified), (DataType::U16, 2, true));
    assert_eq!(written.value, Some(Value::Uint(250)));

    let r = ReadOptions { timeout: TIMEOUT, dtype: None, block: true, max_size: None };
    let read = sdo::read(bus.as_mut(), dict, SENSOR, object, &r).unwrap();
    assert_eq!((read.bytes.as_slice(), &read.value), (&[250u8, 0][..], &Some(Value::Uint(250))));
    assert_eq!(read.name.as_deref(), Some("Producer heartbeat time"));
    let json = serde_json::to_value(&read).unwrap();
    assert_eq!(
        (json["object"].as_str(), json["type"].as_str(), json["raw"].as_str()),
        (Some("0x1017:0"), Some("u16"), Some("FA00"))
    );
}

#[test]
fn an_sdo_read_without_a_type_shows_the_plain_number_and_a_wrong_type_is_refused() {
    let mut bus = demo();
    let empty = canctl::od::Dictionary::default();
    let r = ReadOptions { timeout: TIMEOUT, dtype: None, block: true, max_size: None };
    let read = sdo::read(bus.as_mut(), &empty, SENSOR, ObjAddr::new(0x1018, 1), &r).unwrap();
    assert_eq!((read.dtype, read.value, read.name), (None, Some(Value::Uint(0x40)), None));
    let r = ReadOptions { dtype: Some(DataType::U8), ..r };
    let err = sdo::read(bus.as_mut(), &empty, SENSOR, ObjAddr::new(0x1018, 1), &r).unwrap_err();
    assert!(matches!(err, Error::NotOfType { .. }) && err.to_string().contains("not a u8"), "{err}");
    assert_eq!(err.exit_code(), 2, "a usage error, as it was");
    let missing = sdo::read(bus.as_mut(), &empty, SENSOR, ObjAddr::new(0x1018, 7), &r).unwrap_err();
    assert!(matches!(missing, Error::SdoAbort { node: SENSOR, .. }), "{missing}");
}

#[test]
fn an_sdo_write_outside_the_eds_limits_is_refused_before_it_is_sent() {
    let mut bus = demo();
    let eds = EdsFile {
        node: Some(SENSOR),
        path: concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/eds/mh-sensor.eds").into(),
    };
    let dicts = Dictionaries::load(&[eds]).unwrap();
    let (object, entry) = dicts.resolve(SENSOR, "1017").unwrap();
    assert_eq!(entry.unwrap().range, Some((0, 60000)));
    let w = WriteOptions { timeout: TIMEOUT, dtype: None, block: true, verify: false };
    let err = sdo::write(bus.as_mut(), dicts.for_node(SENSOR), SENSOR, object, "60001", &w).unwrap_err();
    assert!(matches!(err, Error::OutOfRange { low: 0, high: 60000, .. }), "{err}");
    assert!(err.to_string().contains("use 0 to 60000"), "{err}");
    let r = ReadOptions { timeout: TIMEOUT, dtype: None, block: true, max_size: None };
    let unchanged = sdo::read(bus.as_mut(), dicts.for_node(SENSOR), SENSOR, object, &r).unwrap();
    assert_ne!(unchanged.value, Some(Value::Uint(60001)));
    // Without a type from anywhere, nothing can be encoded.
    let err = sdo::write(bus.as_mut(), &canctl::od::Dictionary::default(), SENSOR, object, "1", &w).unwrap_err();
    assert!(matches!(err, Error::TypeNeeded { .. }), "{err}");
    // Its words come from the command line's output layer: that part needs the cli feature.
    #[cfg(feature = "cli")]
    assert!(canctl::output::library_error_text(&err).contains("--type is needed"), "{err}");
}

/// The demo network's devices that have a node-id.
const DEMO_NODES: [u8; 4] = [1, 5, 10, 32];

#[test]
fn lss_assign_numbers_every_device_without_a_node_id_and_says_so() {
    use canctl::ops::lss::{self, AssignOptions, FastscanOptions, Target};
    let mut bus = demo();
    let never = Cancel::new();
    let o = AssignOptions { start: 20, fastscan: FastscanOptions::new(TIMEOUT), listen: None, store: true };
    let mut progress = Recorder::default();
    let report = lss::assign(bus.as_mut(), &o, &mut progress, &never).unwrap();
    let nodes: Vec<u8> = report.assigned.iter().map(|d| d.node).collect();
    assert_eq!(nodes, [20, 21, 22], "{report:?}");
    assert!(report.assigned.iter().all(|d| d.stored && d.store_error.is_none()), "{report:?}");
    assert!(DEMO_NODES.iter().all(|n| report.in_use_before.contains(n)), "{report:?}");
    assert!(!report.interrupted && report.failure.is_none());
    use canctl::ops::{Event, Notice};
    assert!(
        progress.events.iter().any(|e| matches!(e, Event::Notice(Notice::Assigned { identity, node: 20 })
            if *identity == report.assigned[0].identity.0)),
        "{:?}",
        progress.calls
    );
    let json = serde_json::to_value(&report).unwrap();
    assert_eq!(json["assigned"][0]["identity"], report.assigned[0].identity.0.to_string());
    assert_eq!(json["assigned"][0]["lss"]["serial"], report.assigned[0].identity.0.serial);
    assert_eq!(json["error"], serde_json::Value::Null);
    let first = report.assigned[0].identity.0;
    report.outcome().unwrap();

    // Each device answers with its new node-id; nobody is left to number.
    let asked = lss::inquire(bus.as_mut(), TIMEOUT, Target::One(first)).unwrap();
    assert_eq!((asked.identity.0, asked.node), (first, Some(20)));
    let again = lss::assign(bus.as_mut(), &o, &mut Recorder::default(), &never).unwrap();
    assert!(again.assigned.is_empty() && again.nothing_to_assign(), "{again:?}");
    again.outcome().unwrap();
}

#[test]
fn lss_fastscan_finds_a_device_that_set_id_then_numbers() {
    use canctl::ops::lss::{self, FastscanOptions, Setting, Target};
    let mut bus = demo();
    let never = Cancel::new();
    let found = lss::fastscan(bus.as_mut(), &FastscanOptions::new(TIMEOUT), &never).unwrap();
    assert!(found.steps > 0 && found.step_ms > 0, "{found:?}");
    let before = lss::inquire(bus.as_mut(), TIMEOUT, Target::One(found.identity.0)).unwrap();
    assert_eq!(before.node, None);

    let target = Target::One(found.identity.0);
    let set = lss::configure(bus.as_mut(), TIMEOUT, target, Setting::NodeId(40), &never).unwrap();
    assert_eq!((set.command, set.result, set.answers), ("set-id", canctl::ops::lss::Took::NodeId(40), 1));
    assert_eq!(lss::inquire(bus.as_mut(), TIMEOUT, target).unwrap().node, Some(40));

    // An EPOS2 reached directly has no LSS: refused before anything is sent.
    let refused = lss::inquire(bus.as_mut(), TIMEOUT, Target::DirectEpos2).unwrap_err();
    assert_eq!(refused.exit_code(), 2, "{refused}");
}

#[test]
fn settings_come_from_the_command_line_over_the_files_over_the_defaults() {
    use canctl::settings::{FileSettings, Given, Settings, Source, DEFAULT_TIMEOUT};
    let file = std::path::PathBuf::from("/project/canctl.toml");
    let files = FileSettings {
        bus: Some(("socketcan:can0".into(), file.clone())),
        files: vec![file.clone()],
        ..FileSettings::default()
    };
    let s = Settings::resolve(Given { timeout: Some(Duration::from_secs(1)), ..Given::default() }, files);
    let bus = s.bus.as_ref().unwrap();
    assert_eq!((bus.value.as_str(), &bus.from), ("socketcan:can0", &Source::File(file)));
    assert_eq!((s.timeout.value, &s.timeout.from), (Duration::from_secs(1), &Source::Flag));
    let shown = serde_json::to_value(s.report()).unwrap();
    assert_eq!(shown["bus_from"], "/project/canctl.toml");
    assert_eq!(shown["timeout_from"], "command line");
    let none = Settings::resolve(Given::default(), FileSettings::default());
    assert_eq!((none.bus, none.timeout.value, none.timeout.from), (None, DEFAULT_TIMEOUT, Source::Default));
}

#[test]
fn sim_reset_starts_the_saved_network_afresh_as_configured() {
    use canctl::sim::serve::{reset, state_path};
    use canctl::sim::{Profile, SimConfig};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sim.json");
    let uri = format!("sim:{}", path.display());
    assert_eq!(state_path(Some(&uri)).unwrap(), Some(path.clone()));
    // Another kind of bus has no state file: the command line says what to name instead.
    assert_eq!(state_path(Some("can0")).unwrap(), None);

    let report = reset(&path, &SimConfig::default().profile(Profile::Instant).unconfigured(1).seed(7)).unwrap();
    assert_eq!((report.profile.as_str(), report.unconfigured, report.seed), ("instant", 1, 7));
    assert_eq!(report.bit_rate, "500k");
    let mut bus = connect::open(&uri.parse::<BusAddr>().unwrap(), &OpenOptions::new(TIMEOUT)).unwrap();
    let waiting = canctl::bus::lss::count_unconfigured(bus.as_mut(), TIMEOUT).unwrap();
    assert_eq!(waiting, 1);
    bus.close().unwrap();
}

/// `examples/identities.rs`, compiled here, so that what it shows stays true.
#[allow(dead_code)]
#[path = "../examples/identities.rs"]
mod identities_example;

#[test]
fn the_identities_example_reads_every_node_of_the_demo_network() {
    let mut bus = demo();
    let found = identities_example::identities(bus.as_mut(), TIMEOUT).unwrap();
    let nodes: Vec<u8> = found.iter().map(|(n, _)| *n).collect();
    assert_eq!(nodes, [1, 5, 10, 32]);
    let sensor = found[1].1.expect("the sensor has 0x1018");
    assert_eq!((sensor.vendor, sensor.product), (0x40, Some(0x4378_7800)));
    assert_eq!(found[3].1, None, "node 32 has no 0x1018:1");
}
