//! The EPOS2 link against a misbehaving device side on a real pseudo-terminal: answers left
//! in the line, late answers, a babbling line, segments that never end, answers for another
//! object. Each must end with the right value or a documented exit code, never a wrong value
//! and never a hang.

use crate::common;

use common::{DeviceSide, Run, Sim};
use std::io::BufRead;
use std::process::Stdio;
use std::time::Duration;

const FRAMINGS: [&str; 2] = ["--epos2-rs232", "--epos2-usb"];
/// Far beyond any bound canctl should need; only reached by a hang.
const HANG: Duration = Duration::from_secs(90);

/// Run canctl on the device side; a run that outlives `HANG` is killed and fails the test.
fn run_bounded(dev: &DeviceSide, args: &[&str]) -> Run {
    common::run_within(dev.command(args), HANG)
}

/// Scan's nodes without their NMT state: the EPOS2 shows no heartbeats.
fn nodes(scan: &serde_json::Value) -> serde_json::Value {
    let mut nodes = scan["nodes"].clone();
    for n in nodes.as_array_mut().unwrap() {
        // How the state was learned differs by link: heartbeat or guarding on a bus that
        // shows traffic, a remote request through the EPOS2.
        n.as_object_mut().unwrap().remove("state");
        n.as_object_mut().unwrap().remove("state_from");
    }
    nodes
}

#[test]
fn an_answer_left_in_the_line_is_not_taken_for_ours() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let reference = sim.run(&["scan", "--format", "json"]).ok().json();
        // The first frame the device side gets is preceded by an answer owed to a client
        // that went away: ReadObject 0x1000 of the EPOS2 (device type 0x00020192).
        let dev = DeviceSide::start(&sim, framing, &["--fault", "stale@1"]);
        let got = run_bounded(&dev, &["sdo", "read", "5", "1018:1", "--type", "u32"]).ok();
        assert_eq!(got.stdout.trim(), "64", "{framing}: vendor-id of node 5");
        // Nothing is left over for the next command or the next client.
        let scan = run_bounded(&dev, &["scan", "--format", "json"]).ok().json();
        assert_eq!(nodes(&scan), nodes(&reference), "{framing}");

        // A whole scan run while the leftover answer is in the line sees the same nodes.
        drop(dev);
        let dev = DeviceSide::start(&sim, framing, &["--fault", "stale@1"]);
        let scan = run_bounded(&dev, &["scan", "--format", "json"]).ok().json();
        assert_eq!(nodes(&scan), nodes(&reference), "{framing}");
    }
}

/// A client sends a command and is killed before the (late) answer comes; the next client
/// on the same port must get its own answer, not the dead client's.
#[test]
fn a_client_killed_mid_transaction_leaves_nothing_for_the_next() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let want = sim.run(&["sdo", "read", "5", "1018:2", "--type", "u32"]).ok().stdout;
        let dev = DeviceSide::start(&sim, framing, &["--fault", "late@*"]);
        // The first client reads node 5's device type; it is killed once its ReadObject
        // (opcode 0x10) is on the line.
        let mut first = dev
            .command(&["-v", "--timeout", "5s", "sdo", "read", "5", "1000", "--type", "u32"])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut stderr = std::io::BufReader::new(first.stderr.take().unwrap());
        let read_object = if framing == "--epos2-usb" { "< 90 02 10 02" } else { "< 10 01" };
        loop {
            let mut line = String::new();
            assert!(stderr.read_line(&mut line).unwrap() > 0, "{framing}: first client ended early");
            if line.contains(read_object) {
                break;
            }
        }
        // The trace line comes just before the bytes are written, and the device side
        // answers LATE (800 ms) after it gets them: a kill 300 ms after the trace line
        // lands while the device works on the command. (Positions the kill; waits for
        // nothing.)
        std::thread::sleep(Duration::from_millis(300));
        let _ = first.kill();
        let _ = first.wait();
        let second = run_bounded(&dev, &["--timeout", "3s", "sdo", "read", "5", "1018:1", "--type", "u32"]);
        assert_eq!((second.code, second.stdout.trim()), (0, "64"), "{framing}: {}", second.stderr);
        let third = run_bounded(&dev, &["--timeout", "3s", "sdo", "read", "5", "1018:2", "--type", "u32"]);
        assert_eq!(third.stdout, want, "{framing}: {}", third.stderr);
    }
}

/// An answer that comes after canctl gave up on it must not be taken as the answer to the
/// retry, nor stay in the line for the command after.
#[test]
fn a_late_answer_is_not_one_answer_behind() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let reference = sim.run(&["scan", "--format", "json"]).ok().json();
        let dev = DeviceSide::start(&sim, framing, &["--fault", "late@3"]);
        let r = run_bounded(&dev, &["--timeout", "300ms", "scan", "--format", "json"]);
        assert_eq!(r.code, 0, "{framing}: {}", r.stderr);
        assert_eq!(nodes(&r.json()), nodes(&reference), "{framing}");
    }
}

#[test]
fn a_babbling_line_ends_with_exit_5() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let dev = DeviceSide::start(&sim, framing, &["--fault", "babble@1"]);
        let r = run_bounded(&dev, &["--timeout", "200ms", "sdo", "read", "5", "1018:1", "--type", "u32"]);
        assert_eq!(r.code, 5, "{framing}: {}", r.stderr);
        assert!(r.stdout.is_empty(), "{framing}: {}", r.stdout);
        assert!(r.stderr.contains("does not fall quiet") && r.stderr.contains("baud"), "{framing}: {}", r.stderr);
    }
}

#[test]
fn segments_without_data_stop_with_exit_5() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let dev = DeviceSide::start(&sim, framing, &["--fault", "empty-segments@*"]);
        for node in ["0", "10"] {
            let r = run_bounded(&dev, &["sdo", "read", node, "1008", "--type", "vs"]);
            assert_eq!(r.code, 5, "{framing} node {node}: {}", r.stderr);
            assert!(r.stdout.is_empty());
            assert!(r.stderr.contains("segments in a row without data"), "{}", r.stderr);
        }
    }
}

#[test]
fn endless_segments_stop_with_exit_5() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let dev = DeviceSide::start(&sim, framing, &["--fault", "endless-segments@*"]);
        let out = sim.path("endless.bin");
        let r = run_bounded(&dev, &["sdo", "read", "10", "1008", "--type", "d", "--out", out.to_str().unwrap()]);
        assert_eq!(r.code, 5, "{framing}: {}", r.stderr);
        assert!(r.stderr.contains("still says more follow"), "{}", r.stderr);
        assert!(!out.exists(), "{framing}: nothing of an unfinished upload is written");
    }
}

/// A device name that never ends (no size announced, segment after segment) stops at the
/// limit for strings, 64 KiB, not at the 1 MiB of a domain (minutes at 125 kbit/s); the
/// type comes from the dictionary, or --type; --max-size raises the limit.
#[test]
fn an_endless_device_name_stops_at_the_string_limit() {
    let sim = Sim::new();
    let dev = DeviceSide::start(&sim, "--epos2-usb", &["--fault", "endless-segments@*"]);
    for args in [&["sdo", "read", "10", "1008"][..], &["sdo", "read", "10", "1008", "--type", "os"]] {
        let r = run_bounded(&dev, args);
        assert_eq!(r.code, 5, "{args:?}: {}", r.stderr);
        assert!(r.stdout.is_empty());
        assert!(r.stderr.contains("did not end within the limit of 65536 bytes"), "{args:?}: {}", r.stderr);
        assert!(r.stderr.contains("--max-size raises the limit"), "{args:?}: {}", r.stderr);
    }
    let r = run_bounded(&dev, &["sdo", "read", "10", "1008", "--max-size", "100k"]);
    assert_eq!(r.code, 5, "{}", r.stderr);
    assert!(r.stderr.contains("did not end within the limit of 102400 bytes"), "{}", r.stderr);
}

#[test]
fn answers_for_another_object_or_node_are_not_taken() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let dev = DeviceSide::start(&sim, framing, &["--fault", "wrong-object@*"]);
        let r = run_bounded(&dev, &["sdo", "read", "5", "1018:1", "--type", "u32"]).ok();
        assert_eq!(r.stdout.trim(), "64", "{framing}");
        let r = run_bounded(&dev, &["sdo", "read", "10", "1008", "--type", "vs"]).ok();
        assert_eq!(r.stdout.trim(), "CAN-2057C", "{framing}");
        run_bounded(&dev, &["sdo", "write", "10", "5FF0:3", "4242", "--type", "u16", "--verify"]).ok();
    }
}

#[test]
fn an_empty_value_is_really_written() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let dev = DeviceSide::start(&sim, framing, &[]);
        for node in ["0", "10"] {
            run_bounded(&dev, &["sdo", "write", node, "5FF0:12", "not empty", "--type", "vs"]).ok();
            let w = run_bounded(&dev, &["sdo", "write", node, "5FF0:12", "", "--type", "vs", "--verify"]);
            assert_eq!(w.code, 0, "{framing} node {node}: {}", w.stderr);
            let r = run_bounded(&dev, &["sdo", "read", node, "5FF0:12", "--type", "vs", "--format", "json"]).ok();
            assert_eq!(r.json()["value"], "", "{framing} node {node}");
            let d = run_bounded(&dev, &["sdo", "read", node, "5FF0:14", "--type", "d", "--format", "json"]).ok();
            run_bounded(&dev, &["sdo", "write", node, "5FF0:14", "", "--type", "d", "--verify"]).ok();
            let e = run_bounded(&dev, &["sdo", "read", node, "5FF0:14", "--type", "d", "--format", "json"]).ok();
            assert_ne!(d.json()["raw"], e.json()["raw"], "{framing} node {node}: the domain changed");
            assert_eq!(e.json()["raw"], "", "{framing} node {node}");
        }
    }
}

/// An EPOS2 passes on no boot-up message: a reset is confirmed only by what the node's
/// answers show, and otherwise reported as sent and not confirmed.
#[test]
fn nmt_reset_through_the_gateway_says_what_was_confirmed() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        // Devices that answer at once send their boot-up before the remote request that
        // follows the reset can catch it (with latency the boot-up may be caught, and then
        // it rightly confirms the reset): this test is about the case where nothing can.
        sim.run(&["sim", "reset", "--profile", "instant"]).ok();
        let dev = DeviceSide::start(&sim, framing, &[]);
        // Pre-operational before and after: nothing tells a reset from none.
        let r = run_bounded(&dev, &["nmt", "reset", "5", "--format", "json"]).ok().json();
        assert_eq!(r["sent"], true, "{framing}");
        assert_eq!(r["confirmed"], false, "{framing}");
        assert_eq!(r["booted"], serde_json::Value::Null, "{framing}");
        let human = run_bounded(&dev, &["nmt", "reset", "5"]).ok().stdout;
        assert!(human.contains("sent to node 5; not confirmed"), "{framing}: {human}");
        assert!(!human.contains("booted"), "{framing}: {human}");
        // Stopped before, pre-operational after: that is a reset.
        run_bounded(&dev, &["nmt", "stop", "5"]).ok();
        let r = run_bounded(&dev, &["nmt", "reset", "5", "--format", "json"]).ok().json();
        assert_eq!(r["confirmed"], true, "{framing}");
        assert_eq!(r["booted"], serde_json::json!([5]), "{framing}");
        assert!(r["seen_by"].as_str().unwrap().contains("stopped before"), "{framing}: {r}");
        // Nobody there: exit 3, and the reset is not claimed.
        let r = run_bounded(&dev, &["--timeout", "200ms", "nmt", "reset", "77", "--wait", "500ms"]);
        assert_eq!(r.code, 3, "{framing}: {}", r.stderr);
        assert!(r.stderr.contains("not confirmed"), "{framing}: {}", r.stderr);
    }
}

/// Frame 1 is the synchronisation probe; a fault on the command after it is retried too,
/// and the retry's answer is the command's own.
#[test]
fn a_fault_on_the_command_after_the_probe_is_retried() {
    for framing in FRAMINGS {
        for fault in ["nack@2", "crc@2", "garbage@2", "drop@2", "mute@2", "late@2"] {
            let sim = Sim::new();
            let product = sim.run(&["sdo", "read", "5", "1018:2", "--type", "u32"]).ok().stdout;
            let dev = DeviceSide::start(&sim, framing, &["--fault", fault]);
            let r = run_bounded(&dev, &["--timeout", "200ms", "sdo", "read", "5", "1018:1", "--type", "u32"]);
            assert_eq!((r.code, r.stdout.trim()), (0, "64"), "{framing} {fault}: {}", r.stderr);
            let r = run_bounded(&dev, &["--timeout", "200ms", "sdo", "read", "5", "1018:2", "--type", "u32"]).ok();
            assert_eq!(r.stdout, product, "{framing} {fault}: the next client gets its own answer");
        }
    }
}
