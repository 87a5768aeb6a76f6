//! The crate as a library, without the command line: everything here uses library APIs
//! only, so it builds and runs with `cargo test --no-default-features --test library`.

use canctl::bus::{self, Bus, BusAddr, OpenOptions};
use canctl::canopen::nmt;
use canctl::canopen::ObjAddr;
use canctl::ops::config::{self, ApplyOptions, Dcf};
use canctl::ops::monitor::Monitor;
use canctl::ops::pdo::{self, Session, Stream, StreamOptions};
use canctl::ops::store::{self, Class, Timeouts};
use canctl::ops::Progress;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

const TIMEOUT: Duration = Duration::from_millis(500);
/// The demo network's position sensor.
const SENSOR: u8 = 5;

fn demo() -> Box<dyn Bus> {
    let mut opts = OpenOptions::new(TIMEOUT);
    opts.ephemeral = true;
    bus::open(&"sim".parse::<BusAddr>().unwrap(), &opts).unwrap()
}

fn sensor_dcf() -> Dcf {
    Dcf::parse(include_bytes!("../examples/sensor.dcf"), "sensor.dcf").unwrap()
}

/// What a procedure reported, in order.
#[derive(Default)]
struct Recorder {
    calls: Vec<String>,
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
    fn note(&mut self, text: &str) {
        self.calls.push(format!("note {text}"));
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
    assert!(applied.objects.iter().all(|c| c.result == "written, verified"), "{applied:?}");
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
    assert!(report.objects.iter().all(|c| c.result == "would write") && !report.stored);
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
    let never = AtomicBool::new(false);
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
