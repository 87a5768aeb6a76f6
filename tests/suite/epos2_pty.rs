//! The EPOS2 backends against the simulator's EPOS2 device side on a real pseudo-terminal:
//! the same answers as on `--bus sim`, for the EPOS2 itself and for nodes behind it.

use crate::common;

use common::{DeviceSide, Sim};
use std::time::{Duration, Instant};

const FRAMINGS: [&str; 2] = ["--epos2-rs232", "--epos2-usb"];

fn without_state(mut scan: serde_json::Value) -> serde_json::Value {
    for n in scan["nodes"].as_array_mut().unwrap() {
        // How the state was learned differs by link: heartbeat or guarding on a bus that
        // shows traffic, a remote request through the EPOS2.
        n.as_object_mut().unwrap().remove("state");
        n.as_object_mut().unwrap().remove("state_from");
    }
    scan.as_object_mut().unwrap().remove("bus");
    // So does how often a silent id is asked: the EPOS2 sends a command again itself.
    assert_eq!(
        scan.as_object_mut().unwrap().remove("probe_rounds").and_then(|r| r.as_u64()).map(|r| r >= 1),
        Some(true)
    );
    scan
}

#[test]
fn scan_finds_the_same_nodes_as_on_sim() {
    let sim = Sim::new();
    let reference = without_state(sim.run(&["scan", "--format", "json"]).ok().json());
    for framing in FRAMINGS {
        let dev = DeviceSide::start(&sim, framing, &[]);
        let scan = dev.run(&["scan", "--format", "json"]).ok().json();
        assert_eq!(scan["bus"], dev.uri.as_str());
        assert_eq!(without_state(scan), reference, "{framing}");
    }
}

/// Through an EPOS2, which passes on no CAN traffic by itself, scan still shows each node's
/// NMT state (a remote request on 0x700+node), as README says.
#[test]
fn scan_through_the_epos2_shows_nmt_states_as_the_readme_says() {
    let sim = Sim::new();
    let dev = DeviceSide::start(&sim, "--epos2-rs232", &[]);
    let scan = dev.run(&["scan", "--format", "json"]).ok().json();
    for n in scan["nodes"].as_array().unwrap() {
        assert_eq!(n["state"], "pre-operational", "{n}");
        assert_eq!(n["state_from"], "remote request through the EPOS2", "{n}");
    }
    // README's sentences wrap: compare them with single blanks.
    let readme = include_str!("../../README.md").split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(!readme.contains("scan shows no NMT states"), "README says otherwise");
    assert!(readme.contains("scan asks each node its NMT state by a remote request"), "README says how");
}

/// Every type written and read back on node `node` gives what the sim bus gives.
fn every_type(dev: &DeviceSide, sim_ref: &Sim, node: &str) {
    let cases = [
        ("1", "b", "false"),
        ("2", "u8", "201"),
        ("3", "u16", "65534"),
        ("4", "u32", "0xCAFEF00D"),
        ("5", "u64", "18446744073709551614"),
        ("6", "i8", "-127"),
        ("7", "i16", "-32767"),
        ("8", "i32", "-2147483647"),
        ("9", "i64", "-9223372036854775807"),
        ("10", "r32", "2.5"),
        ("11", "r64", "-1e-300"),
        ("12", "vs", "a visible string that is longer than sixty-three bytes, so it needs two EPOS2 segments"),
        ("13", "os", "00112233445566778899AABBCCDDEEFF"),
        ("14", "d", "0102"),
    ];
    for (sub, t, value) in cases {
        let obj = format!("5FF0:{sub}");
        let w = dev.run(&["sdo", "write", node, &obj, value, "--type", t, "--verify"]);
        assert_eq!(w.code, 0, "{} write {t}: {}", dev.uri, w.stderr);
        let got = dev.run(&["sdo", "read", node, &obj, "--type", t, "--format", "json"]).ok().json();
        let reference_node = if node == "0" { "1" } else { node };
        sim_ref.run(&["sdo", "write", reference_node, &obj, value, "--type", t]).ok();
        let want = sim_ref.run(&["sdo", "read", reference_node, &obj, "--type", t, "--format", "json"]).ok().json();
        assert_eq!(got["value"], want["value"], "{} node {node} {t}", dev.uri);
        assert_eq!(got["raw"], want["raw"], "{} node {node} {t}", dev.uri);
    }
}

#[test]
fn every_type_on_the_epos2_itself_and_behind_it() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let reference = Sim::new();
        let dev = DeviceSide::start(&sim, framing, &[]);
        every_type(&dev, &reference, "0");
        every_type(&dev, &reference, "1");
        every_type(&dev, &reference, "10");
    }
}

#[test]
fn names_and_the_64k_domain_come_back_whole() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let reference = sim.path("reference.bin");
        sim.run(&["sdo", "read", "1", "1F50:1", "--type", "d", "--out", reference.to_str().unwrap()]).ok();
        let dev = DeviceSide::start(&sim, framing, &[]);
        assert_eq!(dev.run(&["sdo", "read", "10", "1008", "--type", "vs"]).ok().stdout.trim(), "CAN-2057C");
        // The built-in dictionary gives 0x1008 its type.
        assert_eq!(dev.run(&["sdo", "read", "10", "1008"]).ok().stdout.trim(), "CAN-2057C");
        // No type known: ReadObject says it is too long, and the gateway reads it in segments.
        assert!(dev.run(&["sdo", "read", "10", "5FF0:12"]).ok().stdout.contains("\"canctl\""));
        let got = sim.path("got.bin");
        dev.run(&["sdo", "read", "1", "1F50:1", "--type", "d", "--out", got.to_str().unwrap()]).ok();
        assert_eq!(std::fs::read(&got).unwrap(), std::fs::read(&reference).unwrap(), "{framing}");
        // Write a new image through the EPOS2 and read it back.
        let image: Vec<u8> = (0..65536u32).map(|i| (i * 7 + (i >> 9)) as u8).collect();
        let file = sim.path("image.bin");
        std::fs::write(&file, &image).unwrap();
        dev.run(&["sdo", "write", "0", "1F50:1", &format!("@{}", file.display()), "--type", "d"]).ok();
        dev.run(&["sdo", "read", "0", "1F50:1", "--type", "d", "--out", got.to_str().unwrap()]).ok();
        assert_eq!(std::fs::read(&got).unwrap(), image, "{framing}");
    }
}

#[test]
fn nmt_through_the_gateway() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let dev = DeviceSide::start(&sim, framing, &[]);
        dev.run(&["nmt", "stop", "5"]).ok();
        let state = dev.run(&["nmt", "state", "5", "--format", "json"]).ok().json();
        assert_eq!(state["state"], "stopped", "{framing}");
        assert_eq!(
            dev.run(&["--timeout", "300ms", "sdo", "read", "5", "1000"]).code,
            3,
            "a stopped node serves no SDO"
        );
        let reset = dev.run(&["nmt", "reset", "5", "--format", "json"]).ok().json();
        assert_eq!(reset["booted"], serde_json::json!([5]));
        assert!(dev.run(&["nmt", "state", "5"]).ok().stdout.contains("pre-operational"));
        dev.run(&["nmt", "start", "32"]).ok();
        assert!(dev.run(&["nmt", "state", "32"]).ok().stdout.contains("node 32: operational"));
        let all = dev.run(&["nmt", "reset-comm", "all"]).ok();
        assert!(all.stdout.contains("check the nodes with `canctl scan`"), "{}", all.stdout);
    }
}

#[test]
fn refusals_and_absent_nodes() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let dev = DeviceSide::start(&sim, framing, &[]);
        let r = dev.run(&["sdo", "write", "5", "1000", "1", "--type", "u32"]);
        assert_eq!(r.code, 4, "{}", r.stderr);
        assert!(r.stderr.contains("0x06010002") && r.stderr.contains("Attempt to write a read only object"));
        let r = dev.run(&["sdo", "read", "10", "2222"]);
        assert_eq!(r.code, 4);
        assert!(r.stderr.contains("0x06020000"));
        let r = dev.run(&["sdo", "read", "0", "5FF0:15"]);
        assert_eq!(r.code, 4);
        assert!(r.stderr.contains("Attempt to read a write only object"));
        let r = dev.run(&["sdo", "read", "77", "1000"]);
        assert_eq!(r.code, 3, "{}", r.stderr);
        assert!(r.stderr.contains("node 77") && r.stderr.contains("0x05040000"));
        let r = dev.run(&["sdo", "write", "32", "1006", "1000", "--type", "u32", "--verify"]);
        assert_eq!(r.code, 6);
    }
}

/// A node that does not answer through the gateway gets a likely cause, as on any bus: a node
/// the last scan saw answers a read, the gateway's own node (which answers from its own
/// dictionary) not counted; where none of the others answers either, no cause is named.
#[test]
fn an_absent_node_behind_the_gateway_gets_its_likely_cause() {
    let sim = Sim::new();
    let dev = DeviceSide::start(&sim, "--epos2-rs232", &[]);
    dev.run(&["scan"]).ok();
    let r = dev.run(&["sdo", "read", "44", "1000"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    assert!(r.stderr.contains("likely cause: node 44 is silent while the bus is not"), "{}", r.stderr);
    let r = dev.run(&["nmt", "state", "44"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    assert!(r.stderr.contains("likely cause: node 44 is silent"), "{}", r.stderr);
    // Every node behind the gateway stopped: only the EPOS2 itself (node 1) answers SDO now,
    // which shows nothing of the bus.
    for node in ["5", "10", "32"] {
        dev.run(&["nmt", "stop", node]).ok();
    }
    let r = dev.run(&["sdo", "read", "44", "1000"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    assert!(!r.stderr.contains("likely cause"), "{}", r.stderr);
    assert!(r.stderr.contains("nodes seen on the last scan"), "{}", r.stderr);
}

#[test]
fn a_single_fault_is_retried() {
    for framing in FRAMINGS {
        for fault in ["nack@1", "crc@1", "garbage@1", "drop@1", "mute@1"] {
            let sim = Sim::new();
            let dev = DeviceSide::start(&sim, framing, &["--fault", fault]);
            // A timeout generous enough that only the injected fault costs a retry, however
            // slow this machine is (the fault is what the test is about, not the clock).
            let r = dev.run(&["--timeout", "2s", "-v", "sdo", "read", "5", "1018:1", "--type", "u32"]);
            assert_eq!(r.code, 0, "{framing} {fault}: {}", r.stderr);
            assert_eq!(r.stdout.trim(), "64");
        }
    }
}

#[test]
fn persistent_faults_are_link_failures() {
    for framing in FRAMINGS {
        for fault in ["crc@*", "nack@*", "mute@*"] {
            let sim = Sim::new();
            let dev = DeviceSide::start(&sim, framing, &["--fault", fault]);
            let start = Instant::now();
            let r = dev.run(&["--timeout", "200ms", "sdo", "read", "5", "1018:1", "--type", "u32"]);
            assert_eq!(r.code, 5, "{framing} {fault}: {}", r.stderr);
            assert!(r.stderr.contains("after a resync and retry"), "{}", r.stderr);
            assert!(start.elapsed() < Duration::from_secs(5), "{framing} {fault} took {:?}", start.elapsed());
        }
    }
}

#[test]
fn a_vanishing_port_ends_with_exit_5() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        // At 9600 bit/s the 64 KiB read takes minutes; the device side goes away meanwhile.
        let mut dev = DeviceSide::start(&sim, framing, &["--baud", "9600"]);
        let out = sim.path("partial.bin");
        let mut child = dev
            .command(&["-v", "sdo", "read", "1", "1F50:1", "--type", "d", "--out", out.to_str().unwrap()])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // The port goes away once the transfer is under way: the device side has answered
        // (a `>` trace line), however long that took to start.
        let mut stderr = std::io::BufReader::new(child.stderr.take().unwrap());
        let mut seen = String::new();
        loop {
            let mut line = String::new();
            let n = std::io::BufRead::read_line(&mut stderr, &mut line).unwrap();
            assert!(n > 0, "{framing}: canctl ended before the device side answered: {seen}");
            seen += &line;
            if line.contains(&format!("{} > ", dev.uri)) {
                break;
            }
        }
        dev.kill();
        let start = Instant::now();
        std::io::Read::read_to_string(&mut stderr, &mut seen).unwrap();
        let mut r = common::finish(child.wait_with_output().unwrap());
        r.stderr = seen;
        assert_eq!(r.code, 5, "{framing}: {}", r.stderr);
        assert!(start.elapsed() < Duration::from_secs(5), "hung for {:?}", start.elapsed());
        assert!(!out.exists(), "a partial upload must not be written");
    }
}

#[test]
fn lss_through_the_gateway() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let dev = DeviceSide::start(&sim, framing, &[]);
        let found = dev.run(&["lss", "fastscan", "--format", "json"]).ok().json();
        assert_eq!(found["identity"], "0x00000040:0x43787800:0x312E3031:0x09501301", "{framing}");
        let assigned = dev.run(&["lss", "assign", "--start", "20", "--format", "json"]).ok().json();
        let nodes: Vec<u64> =
            assigned["assigned"].as_array().unwrap().iter().map(|r| r["node"].as_u64().unwrap()).collect();
        assert_eq!(nodes, [20, 21, 22], "{framing}");
        let scan = dev.run(&["scan", "--format", "json"]).ok().json();
        let ids: Vec<u64> = scan["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect();
        assert_eq!(ids, [1, 5, 10, 20, 21, 22, 32], "{framing}");
        assert_eq!(scan["lss_unconfigured"], 0);
        let r = dev.run(&["lss", "set-baud", "250k", "--identity", "0:0:0:0"]);
        assert_eq!(r.code, 4);
        assert!(r.stderr.contains("bit timing not supported"));
        assert_eq!(dev.run(&["lss", "fastscan"]).code, 3);
    }
}

#[test]
fn lss_verbs_on_the_epos2_itself_use_its_objects() {
    let sim = Sim::new();
    let dev = DeviceSide::start(&sim, "--epos2-rs232", &[]);
    dev.run(&["lss", "set-id", "3", "--node", "0"]).ok();
    assert_eq!(dev.run(&["sdo", "read", "0", "2000", "--type", "u8"]).ok().stdout.trim(), "3");
    dev.run(&["lss", "set-baud", "250k", "--node", "0"]).ok();
    assert_eq!(dev.run(&["sdo", "read", "0", "2001", "--type", "u16"]).ok().stdout.trim(), "3", "EPOS2 code for 250k");
    dev.run(&["lss", "set-baud", "20k", "--node", "0"]).ok();
    assert_eq!(dev.run(&["sdo", "read", "0", "2001", "--type", "u16"]).ok().stdout.trim(), "6", "EPOS2 code for 20k");
    let r = dev.run(&["lss", "set-baud", "10k", "--node", "0"]);
    assert_eq!(r.code, 2);
    assert!(r.stderr.contains("no 10k setting"));
    assert!(dev.run(&["lss", "store", "--node", "0"]).ok().stdout.contains("0x1010:1"));
    for verb in [vec!["inquire"], vec!["fastscan"], vec!["assign", "--start", "20"]] {
        let mut args = vec!["lss"];
        args.extend(verb.iter());
        args.extend(["--node", "0"]);
        let r = dev.run(&args);
        assert_eq!(r.code, 2, "{verb:?}");
        assert!(r.stderr.contains("has no LSS"), "{verb:?}: {}", r.stderr);
    }
}

#[test]
fn stream_pdo_by_polling_through_the_gateway() {
    for framing in FRAMINGS {
        let sim = Sim::new();
        let dev = DeviceSide::start(&sim, framing, &[]);
        let r = dev.run(&["stream-pdo", "5", "--start", "--count", "20", "--interval", "5ms", "--format", "csv"]).ok();
        assert!(r.stderr.contains("polled by remote frame"), "{}", r.stderr);
        let rows: Vec<&str> = r.stdout.lines().skip(1).collect();
        assert_eq!(rows.len(), 20, "{framing}");
        for row in rows {
            let cols: Vec<&str> = row.split(',').collect();
            let speed: i64 = cols[3].parse().unwrap();
            assert_eq!(speed.abs(), 2000, "{row}");
        }
        assert!(dev.run(&["nmt", "state", "5"]).ok().stdout.contains("pre-operational"), "{framing}");
    }
}

/// Ctrl-C (and SIGTERM) while canctl waits on the serial line for the EPOS2's answer: the
/// wait is cut short by the signal (EINTR), which is not a link failure. The procedure
/// stops at its safe point, puts node 5 back as it was, and ends with exit 130.
#[test]
fn a_signal_during_a_serial_wait_is_an_interruption_not_a_link_failure() {
    use nix::sys::signal::Signal;
    for (framing, signal) in [(FRAMINGS[0], Signal::SIGINT), (FRAMINGS[1], Signal::SIGTERM)] {
        let sim = Sim::new();
        let dev = DeviceSide::start(&sim, framing, &[]);
        let stream = dev.command(&["stream-pdo", "5", "--start", "--interval", "5ms", "--format", "csv"]);
        let r = common::signal_after_lines(stream, 5, signal);
        assert_eq!(r.code, 130, "{framing} {signal}: {}", r.stderr);
        assert!(dev.run(&["nmt", "state", "5"]).ok().stdout.contains("pre-operational"), "{framing}");
    }
}
