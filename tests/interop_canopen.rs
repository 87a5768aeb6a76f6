//! Interoperability with a CANopen stack we did not write: the `canopen` Python package
//! (versions pinned in tests/interop/requirements.txt) on vcan0, both ways round. Kernel
//! tests (scripts/kernel-tests.sh): without vcan0 they print `SKIPPED` and pass, or fail
//! where `CANCTL_REQUIRE_KERNEL` is set.

mod common;

use common::{Run, Sim};
use std::io::BufRead;
use std::path::Path;
use std::process::{Child, Command, Stdio};

const IFACE: &str = "vcan0";

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
    c.env_remove("CANCTL_BUS").args(["--bus", IFACE]).args(args).stdin(Stdio::null());
    common::finish(c.output().unwrap())
}

#[test]
fn canctl_commissions_a_canopen_local_node() {
    if !common::has_interface(IFACE) {
        return;
    }
    let mut child = Command::new("python3")
        .args([&script("local_node.py"), IFACE, "20"])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("python3 with canopen (pip install -r tests/interop/requirements.txt)");
    let mut line = String::new();
    std::io::BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
    let _device = Killed(child);
    assert_eq!(line.trim(), "READY", "the canopen LocalNode did not start");

    let scan = canctl(&["scan", "--format", "json"]).ok().json();
    let nodes = scan["nodes"].as_array().unwrap();
    assert_eq!(nodes.len(), 1, "{scan}");
    let n = &nodes[0];
    assert_eq!((n["node"].clone(), n["device_type"].clone()), (20.into(), 0x191.into()));
    assert_eq!(n["vendor_id"], 0x123);
    assert_eq!(n["serial"], 0xBEEF);
    assert_eq!(n["name"], "python-canopen LocalNode");
    assert_eq!(n["state"], "pre-operational", "heartbeat seen during the scan");

    // Expedited (up to 4 bytes) and segmented (8-byte numbers, strings, domains).
    let cases = [
        ("1", "b", "true"),
        ("2", "u8", "250"),
        ("3", "u16", "0xBEEF"),
        ("4", "u32", "4000000000"),
        ("5", "u64", "18446744073709551615"),
        ("6", "i8", "-100"),
        ("7", "i16", "-30000"),
        ("8", "i32", "-2000000000"),
        ("9", "i64", "-9000000000000000000"),
        ("10", "r32", "0.5"),
        ("11", "r64", "3.141592653589793"),
        ("12", "vs", "written by canctl, read back by canctl"),
        ("13", "os", "0011223344556677889900"),
        ("14", "d", "CAFEBABE0102030405"),
    ];
    for (sub, t, value) in cases {
        let obj = format!("2000:{sub}");
        canctl(&["sdo", "write", "20", &obj, value, "--type", t, "--verify"]).ok();
        let read = canctl(&["sdo", "read", "20", &obj, "--type", t]).ok().stdout;
        let want =
            canctl(&["sdo", "write", "20", &obj, value, "--type", t, "--format", "json"]).ok().json()["value"].clone();
        let got = canctl(&["sdo", "read", "20", &obj, "--type", t, "--format", "json"]).ok().json()["value"].clone();
        assert_eq!(got, want, "{t}: {read}");
    }
    assert_eq!(canctl(&["sdo", "read", "20", "1008", "--type", "vs"]).ok().stdout.trim(), "python-canopen LocalNode");

    // NMT commands change its state; its heartbeat says so.
    for (verb, state) in [("start", "operational"), ("stop", "stopped"), ("preop", "pre-operational")] {
        canctl(&["nmt", verb, "20"]).ok();
        let s = canctl(&["nmt", "state", "20", "--format", "json"]).ok().json();
        assert_eq!((s["state"].as_str(), s["source"].as_str()), (Some(state), Some("heartbeat")), "after nmt {verb}");
    }
}

#[test]
fn the_canopen_client_talks_to_canctl_sim() {
    if !common::has_interface(IFACE) {
        return;
    }
    let sim = Sim::new();
    let _devices = Killed(common::sim_on_interface(&sim, IFACE));
    let out = Command::new("python3").args([&script("client.py"), IFACE]).output().expect("python3");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "canopen client failed:\n{stdout}\n{stderr}");
    assert!(stdout.contains("all interop checks passed"), "{stdout}");
}
