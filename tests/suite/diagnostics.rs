//! What canctl says on stderr (-v, -q), the frame log of --log-frames, and the sim network
//! held by another process: the real binary, with real second processes.

use crate::common;

use common::{DeviceSide, Sim};
use std::io::BufRead;
use std::process::Stdio;

/// The frames of a candump log file, each as (interface, frame in compact notation); every
/// line must be `(SECONDS.MICROS) IFACE ID#DATA` exactly.
fn logged(path: &std::path::Path) -> Vec<(String, String)> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .map(|line| {
            let fields: Vec<&str> = line.split(' ').collect();
            assert_eq!(fields.len(), 3, "not a candump log line: '{line}'");
            let time = fields[0].strip_prefix('(').and_then(|t| t.strip_suffix(')')).expect("(time)");
            let (secs, micros) = time.split_once('.').expect("SECONDS.MICROS");
            assert!(secs.len() == 10 && secs.bytes().all(|b| b.is_ascii_digit()), "{line}");
            assert!(micros.len() == 6 && micros.bytes().all(|b| b.is_ascii_digit()), "{line}");
            let frame: canctl::frame::Frame = fields[2].parse().unwrap_or_else(|e| panic!("{line}: {e}"));
            assert_eq!(frame.to_string(), fields[2], "not can-utils' own notation: {line}");
            (fields[1].to_string(), fields[2].to_string())
        })
        .collect()
}

fn has(log: &[(String, String)], iface: &str, frame: &str) -> bool {
    log.iter().any(|(i, f)| i == iface && f == frame)
}

#[test]
fn log_frames_on_the_sim_holds_the_request_and_its_answer() {
    let sim = Sim::new();
    let log = sim.path("frames.log");
    let r = sim.run(&["--log-frames", log.to_str().unwrap(), "sdo", "read", "1", "1018:1"]).ok();
    assert_eq!(r.stdout.trim(), "251");
    // The request and its answer, in order; what else came is the devices' heartbeats.
    let frames = logged(&log);
    let sdo: Vec<&str> = frames
        .iter()
        .filter(|(_, f)| !f.starts_with('7'))
        .map(|(i, f)| {
            assert_eq!(i, "sim");
            f.as_str()
        })
        .collect();
    assert_eq!(sdo, ["601#4018100100000000", "581#43181001FB000000"], "{frames:?}");
    // A later command starts a new log: the file holds one session.
    sim.run(&["--log-frames", log.to_str().unwrap(), "nmt", "stop", "5"]).ok();
    assert_eq!(logged(&log), [("sim".to_string(), "000#0205".to_string())]);
}

#[test]
fn log_frames_through_an_slcan_adapter_names_the_link() {
    let sim = Sim::new();
    let adapter = DeviceSide::start(&sim, "--slcan", &[]);
    let log = sim.path("slcan.log");
    let r = adapter.run(&["--log-frames", log.to_str().unwrap(), "sdo", "read", "1", "1018:1"]).ok();
    assert_eq!(r.stdout.trim(), "251");
    let iface = format!("{}@500k", adapter.uri);
    let frames = logged(&log);
    assert!(has(&frames, &iface, "601#4018100100000000"), "{frames:?}");
    assert!(has(&frames, &iface, "581#43181001FB000000"), "{frames:?}");
}

/// Through an EPOS2 the backend sees the frames it has the EPOS2 send and receive for it
/// (NMT, remote requests, LSS); the EPOS2's device side logs what it puts on its CAN bus,
/// SDO transfers included.
#[test]
fn log_frames_through_an_epos2_gateway_and_on_its_device_side() {
    let sim = Sim::new();
    let device_log = sim.path("device.log");
    let dev = DeviceSide::start(&sim, "--epos2-rs232", &["--log-frames", device_log.to_str().unwrap()]);
    let log = sim.path("gateway.log");
    let r = dev.run(&["--log-frames", log.to_str().unwrap(), "nmt", "reset", "5", "--format", "json"]).ok();
    let frames = logged(&log);
    assert_eq!(r.json()["booted"], serde_json::json!([5]), "{}\n{frames:?}", r.stdout);
    assert!(has(&frames, &dev.uri, "000#8105"), "{frames:?}");
    assert!(has(&frames, &dev.uri, "705#R1"), "the guarding request: {frames:?}");
    assert!(has(&frames, &dev.uri, "705#00"), "the boot-up, as the answer: {frames:?}");

    dev.run(&["sdo", "read", "5", "1018:1"]).ok();
    let on_bus = logged(&device_log);
    assert!(has(&on_bus, "sim", "000#8105"), "{on_bus:?}");
    assert!(has(&on_bus, "sim", "605#4018100100000000"), "the forwarded SDO request: {on_bus:?}");
    assert!(on_bus.iter().any(|(i, f)| i == "sim" && f == "585#4318100140000000"), "{on_bus:?}");
}

#[test]
fn a_frame_log_that_cannot_be_created_is_an_output_error() {
    let sim = Sim::new();
    let log = sim.path("no/such/dir/frames.log");
    let r = sim.run(&["--log-frames", log.to_str().unwrap(), "sdo", "read", "1", "1018:1"]);
    assert_eq!(r.code, 7, "{}", r.stderr);
    assert!(r.stderr.contains("--log-frames") && r.stderr.contains("frames.log"), "{}", r.stderr);
    assert!(r.stdout.is_empty(), "nothing done: {}", r.stdout);
}

/// -v: the frame trace and nothing else, as candump prints frames (no time, no level).
#[test]
fn one_v_is_the_candump_trace_alone() {
    let sim = Sim::new();
    let r = sim.run(&["-v", "sdo", "read", "1", "1018:1"]).ok();
    // Heartbeats that come along are traced too; nothing but frames is.
    for line in r.stderr.lines() {
        let id_and_len = line.strip_prefix("  sim  ").and_then(|l| l.get(3..8));
        assert!(id_and_len.is_some_and(|t| t.starts_with("   [")), "not a trace line: '{line}'");
    }
    let sdo: Vec<&str> = r.stderr.lines().filter(|l| !l.starts_with("  sim  7")).collect();
    assert_eq!(sdo, ["  sim  601   [8]  40 18 10 01 00 00 00 00", "  sim  581   [8]  43 18 10 01 FB 00 00 00"]);
    let r = sim.run(&["-vv", "sdo", "read", "1", "1018:1"]).ok();
    assert!(r.stderr.contains("  sim  601   [8]  40 18 10 01 00 00 00 00\n"), "{}", r.stderr);
    assert!(r.stderr.contains("node 1: SDO transfer of 0x1018:1 starts"), "{}", r.stderr);
}

/// A process serving the sim network's EPOS2 holds its state file for as long as it runs.
/// Another command waits a bounded time, then says who holds it and what to do (exit 5);
/// with -q only that error is printed. Once the holder is gone the network is free.
#[test]
fn the_sim_network_held_by_another_process_is_waited_for_then_named() {
    let sim = Sim::new();
    let mut holder =
        sim.command(&["sim", "--epos2-rs232"]).stdout(Stdio::piped()).stderr(Stdio::null()).spawn().unwrap();
    let mut pty = String::new();
    std::io::BufReader::new(holder.stdout.take().unwrap()).read_line(&mut pty).unwrap();
    assert!(pty.starts_with("/dev/"), "the holder did not start: '{pty}'");
    let named = format!("in use by pid {} (canctl --bus {} sim --epos2-rs232)", holder.id(), sim.bus());

    let quiet = std::thread::scope(|s| {
        let quiet = s.spawn(|| sim.run(&["-q", "sdo", "read", "1", "1018:1"]));
        let r = sim.run(&["sdo", "read", "1", "1018:1"]);
        assert_eq!(r.code, 5, "{}", r.stderr);
        assert!(
            r.stderr
                .contains(&format!("canctl: warning: the sim network ({}) is {named}", sim.path("sim.json").display())),
            "{}",
            r.stderr
        );
        assert!(r.stderr.contains("waiting up to 10 s"), "{}", r.stderr);
        assert!(
            r.stderr.contains(&format!(
                "canctl: the sim network is {named} (waited 10 s): it serves one command at a time"
            )),
            "{}",
            r.stderr
        );
        quiet.join().unwrap()
    });
    assert_eq!(quiet.code, 5, "{}", quiet.stderr);
    assert_eq!(quiet.stderr.lines().count(), 1, "the error alone: {}", quiet.stderr);
    assert!(quiet.stderr.contains(&named), "{}", quiet.stderr);

    // Killed outright: its record stays behind, but the lock went with the process.
    holder.kill().unwrap();
    holder.wait().unwrap();
    assert_eq!(sim.run(&["sdo", "read", "1", "1018:1"]).ok().stdout.trim(), "251");
}

/// A program using the library captures its diagnostics with a subscriber of its own: the
/// frame trace carries the interface, the direction and the frame as fields.
#[test]
fn a_program_embedding_the_library_captures_the_frame_trace() {
    use canctl::bus::SdoOptions;
    use canctl::connect::{open, BusAddr, OpenOptions};
    use std::sync::{Arc, Mutex};
    use std::time::Duration;

    #[derive(Clone, Default)]
    struct Captured(Arc<Mutex<Vec<u8>>>);
    impl std::io::Write for Captured {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    let out = Captured::default();
    let writer = out.clone();
    let subscriber = tracing_subscriber::fmt()
        .with_max_level(tracing::Level::DEBUG)
        .with_writer(move || writer.clone())
        .without_time()
        .finish();
    tracing::subscriber::with_default(subscriber, || {
        let mut opts = OpenOptions::new(Duration::from_secs(5));
        opts.ephemeral = true;
        let mut bus = open(&BusAddr::Sim { state: None }, &opts).unwrap();
        let vendor =
            bus.sdo_upload(1, canctl::canopen::ObjAddr::new(0x1018, 1), &SdoOptions::new(Duration::from_secs(5)));
        assert_eq!(vendor.unwrap(), 0xFBu32.to_le_bytes());
        bus.close().unwrap();
    });
    let text = String::from_utf8(out.0.lock().unwrap().clone()).unwrap();
    let request = text.lines().find(|l| l.contains("601   [8]  40 18 10 01")).unwrap_or_else(|| panic!("{text}"));
    assert!(request.contains("canctl::frames"), "{request}");
    assert!(request.contains("iface=\"sim\"") && request.contains("dir=\"tx\""), "{request}");
    assert!(request.contains("frame=601#4018100100000000"), "{request}");
}

/// Diagnostics are never worth dying for: a reader of stderr that went away (a device side
/// started by a script that read its first line only) loses them, and the command goes on.
#[test]
fn a_closed_stderr_does_not_end_the_command() {
    let sim = Sim::new();
    let mut child = sim
        .command(&["-v", "sdo", "read", "1", "1018:1"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stderr.take());
    let r = common::finish(child.wait_with_output().unwrap());
    assert_eq!(r.code, 0);
    assert_eq!(r.stdout.trim(), "251");
}

/// A process serving the sim network as a bus several commands share (`sim --socketcand`):
/// another command's error says the bus it serves on (it advised `sim --socketcan` instead).
#[test]
fn the_sim_network_served_by_another_process_is_reached_where_it_serves() {
    let sim = Sim::new();
    let mut server =
        sim.command(&["sim", "--socketcand", "0"]).stdout(Stdio::piped()).stderr(Stdio::null()).spawn().unwrap();
    let mut bus = String::new();
    std::io::BufReader::new(server.stdout.take().unwrap()).read_line(&mut bus).unwrap();
    let bus = bus.trim().to_string();
    assert!(bus.starts_with("socketcand:"), "the server did not start: '{bus}'");
    let r = sim.run(&["sdo", "read", "1", "1018:1"]);
    server.kill().unwrap();
    server.wait().unwrap();
    assert_eq!(r.code, 5, "{}", r.stderr);
    assert!(r.stderr.contains(&format!("use --bus {bus}")), "{}", r.stderr);
    assert!(!r.stderr.contains("sim --socketcan vcan0"), "{}", r.stderr);
}
