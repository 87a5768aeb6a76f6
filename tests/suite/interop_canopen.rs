//! Interoperability with a CANopen stack we did not write: the `canopen` Python package
//! (versions pinned in tests/interop/requirements.txt) on vcan0, both ways round. Kernel
//! tests (scripts/kernel-tests.sh): without vcan0 they print `SKIPPED` and pass, or fail
//! where `CANCTL_REQUIRE_KERNEL` is set.

use crate::common;

use common::{Run, Sim};
use serde_json::json;
use std::io::BufRead;
use std::path::Path;
use std::process::{Child, Command, Stdio};

fn script(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/interop").join(name).display().to_string()
}

struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn canctl(args: &[&str]) -> Run {
    let mut c = Command::new(common::canctl_bin());
    common::isolate(&mut c);
    c.env_remove("CANCTL_BUS").args(["--bus", common::vcan()]).args(args).stdin(Stdio::null());
    common::finish(c.output().unwrap())
}

#[test]
fn canctl_commissions_a_canopen_local_node() {
    if !common::has_interface(common::vcan()) {
        return;
    }
    let mut child = Command::new("python3")
        .args([&script("local_node.py"), common::vcan(), "20"])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("python3 with canopen (pip install -r tests/interop/requirements.txt)");
    // The device's lines: READY, then what it decoded from each write.
    let (tx, lines) = std::sync::mpsc::channel();
    let stdout = child.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in std::io::BufReader::new(stdout).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let next_line =
        || lines.recv_timeout(std::time::Duration::from_secs(60)).expect("a line from the canopen LocalNode");
    let _device = Killed(child);
    assert_eq!(next_line().trim(), "READY", "the canopen LocalNode did not start");

    // Python on the VM's emulated CPU may answer the probe later than scan's 100 ms quiet
    // window (seen under load): a window that only a missing node exceeds.
    let scan = canctl(&["scan", "--window", "2s", "--format", "json"]).ok().json();
    let nodes = scan["nodes"].as_array().unwrap();
    assert_eq!(nodes.len(), 1, "{scan}");
    let n = &nodes[0];
    assert_eq!((n["node"].clone(), n["device_type"].clone()), (20.into(), 0x191.into()));
    assert_eq!(n["vendor_id"], 0x123);
    assert_eq!(n["serial"], 0xBEEF);
    assert_eq!(n["name"], "python-canopen LocalNode");
    assert_eq!(n["state"], "pre-operational", "heartbeat seen during the scan");

    // Expedited (up to 4 bytes) and segmented (8-byte numbers, strings, domains): what
    // python-canopen decodes from canctl's bytes with its own codec for the object's type.
    let cases = [
        ("1", "b", "true", json!({ "bool": true })),
        ("2", "u8", "250", json!({ "int": "250" })),
        ("3", "u16", "0xBEEF", json!({ "int": "48879" })),
        ("4", "u32", "4000000000", json!({ "int": "4000000000" })),
        ("5", "u64", "18446744073709551615", json!({ "int": "18446744073709551615" })),
        ("6", "i8", "-100", json!({ "int": "-100" })),
        ("7", "i16", "-30000", json!({ "int": "-30000" })),
        ("8", "i32", "-2000000000", json!({ "int": "-2000000000" })),
        ("9", "i64", "-9000000000000000000", json!({ "int": "-9000000000000000000" })),
        ("10", "r32", "0.5", json!({ "float": "0.5" })),
        ("11", "r64", "3.141592653589793", json!({ "float": "3.141592653589793" })),
        ("12", "vs", "written by canctl", json!({ "str": "written by canctl" })),
        ("13", "os", "0011223344556677889900", json!({ "bytes": "0011223344556677889900" })),
        ("14", "d", "CAFEBABE0102030405", json!({ "bytes": "CAFEBABE0102030405" })),
    ];
    for (sub, t, value, decoded) in cases {
        let obj = format!("2000:{sub}");
        canctl(&["sdo", "write", "20", &obj, value, "--type", t]).ok();
        let seen: serde_json::Value = serde_json::from_str(&next_line()).unwrap();
        assert_eq!(
            seen,
            json!({ "index": 0x2000, "sub": sub.parse::<u8>().unwrap(), "value": decoded }),
            "{t} {value}"
        );
    }
    // And the values python-canopen encoded, as canctl reads them.
    let set_by_python = [
        ("1", "b", "true"),
        ("2", "u8", "255"),
        ("3", "u16", "48879"),
        ("4", "u32", "4294967295"),
        ("5", "u64", "18446744073709551615"),
        ("6", "i8", "-128"),
        ("7", "i16", "-12345"),
        ("8", "i32", "-2147483648"),
        ("9", "i64", "-9223372036854775808"),
        ("10", "r32", "-1.25"),
        ("11", "r64", "3.141592653589793"),
        ("12", "vs", "set by python-canopen"),
        ("13", "os", "007F80FF"),
        ("14", "d", "000102030405060708090A0B0C0D0E0F10111213"),
    ];
    for (sub, t, want) in set_by_python {
        let got = canctl(&["sdo", "read", "20", &format!("2001:{sub}"), "--type", t]).ok().stdout;
        assert_eq!(got.trim(), want, "2001:{sub} {t}");
    }
    assert_eq!(canctl(&["sdo", "read", "20", "1008", "--type", "vs"]).ok().stdout.trim(), "python-canopen LocalNode");

    // NMT commands change its state; its heartbeat says so.
    for (verb, state) in [("start", "operational"), ("stop", "stopped"), ("preop", "pre-operational")] {
        canctl(&["nmt", verb, "20"]).ok();
        let s = canctl(&["nmt", "state", "20", "--listen", "5s", "--format", "json"]).ok().json();
        assert_eq!((s["state"].as_str(), s["source"].as_str()), (Some(state), Some("heartbeat")), "after nmt {verb}");
    }
}

#[test]
fn the_canopen_client_talks_to_canctl_sim() {
    if !common::has_interface(common::vcan()) {
        return;
    }
    let sim = Sim::new();
    let _devices = Killed(common::sim_on_interface(&sim, common::vcan()));
    let out = Command::new("python3").args([&script("client.py"), common::vcan()]).output().expect("python3");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "canopen client failed:\n{stdout}\n{stderr}");
    assert!(stdout.contains("all interop checks passed"), "{stdout}");
}

/// python-canopen's CiA 402 master walks the simulated EPOS2 through its states, by its
/// TPDO (statusword) and SDO (controlword), and through a simulated fault and its reset.
#[test]
fn cia402_python_canopen_base_node_402_drives_the_simulated_epos2() {
    if !common::has_interface(common::vcan()) {
        return;
    }
    let sim = Sim::new();
    let _devices = Killed(common::sim_on_interface(&sim, common::vcan()));
    let eds = Path::new(env!("CARGO_MANIFEST_DIR")).join("eds/canctl-sim-drive.eds");
    let out = Command::new("python3")
        .args([&script("p402.py"), common::vcan(), eds.to_str().unwrap()])
        .output()
        .expect("python3");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    // The run's record, for the test log.
    println!("{stdout}");
    assert!(out.status.success(), "BaseNode402 failed:\n{stdout}\n{stderr}");
    assert!(stdout.contains("all p402 checks passed"), "{stdout}");
    let seen: Vec<&str> =
        stdout.lines().filter_map(|l| l.strip_prefix("seen ")).map(|l| l.split(" (").next().unwrap()).collect();
    for state in
        ["SWITCH ON DISABLED", "READY TO SWITCH ON", "SWITCHED ON", "OPERATION ENABLED", "QUICK STOP ACTIVE", "FAULT"]
    {
        assert!(seen.contains(&state), "{state} never seen in the TPDO: {seen:?}");
    }
}

/// `canctl drive` over SocketCAN against the simulated drive on the same vcan0.
#[test]
fn cia402_canctl_drive_over_vcan_against_the_sim() {
    if !common::has_interface(common::vcan()) {
        return;
    }
    let sim = Sim::new();
    let _devices = Killed(common::sim_on_interface(&sim, common::vcan()));
    let enable = canctl(&["drive", "enable", "1"]).ok();
    println!("{}", enable.stdout);
    assert!(enable.stdout.contains("node 1: Operation enabled"), "{}", enable.stdout);
    canctl(&["sdo", "write", "1", "5FFE", "1", "--type", "u16"]).ok();
    let end = std::time::Instant::now() + std::time::Duration::from_secs(30);
    while canctl(&["drive", "status", "1", "--format", "json"]).ok().json()["state"] != "fault" {
        assert!(std::time::Instant::now() < end, "the drive never showed its fault");
    }
    canctl(&["sdo", "write", "1", "5FFE", "0", "--type", "u16"]).ok();
    let reset = canctl(&["drive", "fault-reset", "1"]).ok();
    println!("{}", reset.stdout);
    assert!(reset.stdout.contains("Fault → Switch on disabled"), "{}", reset.stdout);
    canctl(&["drive", "enable", "1"]).ok();
    let disable = canctl(&["drive", "disable", "1"]).ok();
    println!("{}", disable.stdout);
    assert!(disable.stdout.contains("Operation enabled → Switch on disabled"), "{}", disable.stdout);
    let refused = canctl(&["drive", "enable", "10"]);
    assert_eq!(refused.code, 2, "{}", refused.stderr);
}
