//! The EPOS2 backends against the simulator's EPOS2 device side on a real pseudo-terminal:
//! the same answers as on `--bus sim`, for the EPOS2 itself and for nodes behind it.

mod common;

use common::{DeviceSide, Sim};
use std::time::{Duration, Instant};

const FRAMINGS: [&str; 2] = ["--epos2-rs232", "--epos2-usb"];

fn without_state(mut scan: serde_json::Value) -> serde_json::Value {
    for n in scan["nodes"].as_array_mut().unwrap() {
        n.as_object_mut().unwrap().remove("state");
    }
    scan.as_object_mut().unwrap().remove("bus");
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
        // Without --type the gateway finds out from the answer that it needs segments.
        assert!(dev.run(&["sdo", "read", "10", "1008"]).ok().stdout.contains("\"CAN-2057C\""));
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

#[test]
fn a_single_fault_is_retried() {
    for framing in FRAMINGS {
        for fault in ["nack@1", "crc@1", "garbage@1", "drop@1", "mute@1"] {
            let sim = Sim::new();
            let dev = DeviceSide::start(&sim, framing, &["--fault", fault]);
            let r = dev.run(&["--timeout", "200ms", "-v", "sdo", "read", "5", "1018:1", "--type", "u32"]);
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
        let child = dev
            .command(&["sdo", "read", "1", "1F50:1", "--type", "d", "--out", out.to_str().unwrap()])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(400));
        dev.kill();
        let start = Instant::now();
        let r = common::finish(child.wait_with_output().unwrap());
        assert_eq!(r.code, 5, "{framing}: {}", r.stderr);
        assert!(start.elapsed() < Duration::from_secs(5), "hung for {:?}", start.elapsed());
        assert!(!out.exists(), "a partial upload must not be written");
    }
}
