//! `canctl drive`: the CiA 402 state machine of the simulated drives walked end to end,
//! through the binary, on the sim bus and through the simulated EPOS2 on a pty.

use crate::common;

use common::{DeviceSide, Run, Sim};
use serde_json::Value;
use std::time::{Duration, Instant};

fn states(walk: &Value) -> Vec<(String, String)> {
    walk["transitions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| (t["command"].as_str().unwrap().to_string(), t["reached"].as_str().unwrap_or("-").to_string()))
        .collect()
}

fn pairs(p: &[(&str, &str)]) -> Vec<(String, String)> {
    p.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect()
}

/// `drive status NODE` as JSON.
fn status(run: impl Fn(&[&str]) -> Run, node: &str) -> Value {
    run(&["drive", "status", node, "--format", "json"]).ok().json()
}

/// Read the status until the drive shows `state`, under a generous bound.
fn until_state(run: impl Fn(&[&str]) -> Run, node: &str, state: &str) -> Value {
    let end = Instant::now() + Duration::from_secs(20);
    loop {
        let s = status(&run, node);
        if s["state"] == state {
            return s;
        }
        assert!(Instant::now() < end, "node {node} never reached {state}: {s}");
    }
}

#[test]
fn enable_walks_shutdown_switch_on_enable_operation_and_the_statusword_shows_it() {
    let sim = Sim::new();
    let before = status(|a| sim.run(a), "1");
    assert_eq!(before["state"], "switch_on_disabled");
    assert_eq!(before["statusword"], 0x0540);
    let walk = sim.run(&["drive", "enable", "1", "--format", "json"]).ok().json();
    assert_eq!(
        states(&walk),
        pairs(&[
            ("shutdown", "ready_to_switch_on"),
            ("switch_on", "switched_on"),
            ("enable_operation", "operation_enabled")
        ])
    );
    assert_eq!(walk["done"], true);
    let after = status(|a| sim.run(a), "1");
    assert_eq!(after["state"], "operation_enabled");
    let set: Vec<&str> = after["flags"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["set"] == true)
        .map(|f| f["name"].as_str().unwrap())
        .collect();
    assert!(set.contains(&"voltage enabled") && set.contains(&"operation enabled"), "{set:?}");
    // Again: nothing to do.
    let again = sim.run(&["drive", "enable", "1"]).ok();
    assert!(again.stdout.contains("already Operation enabled"), "{}", again.stdout);
}

#[test]
fn quick_stop_then_disable_then_enable_from_quick_stop() {
    let sim = Sim::new();
    sim.run(&["drive", "enable", "1"]).ok();
    let qs = sim.run(&["drive", "quick-stop", "1", "--format", "json"]).ok().json();
    assert_eq!(states(&qs), pairs(&[("quick_stop", "quick_stop_active")]));
    let quick = status(|a| sim.run(a), "1");
    assert!(quick["flags"][5]["set"] == false, "quick stop bit is active low: {quick}");
    // Out of quick stop by way of switch on disabled.
    let en = sim.run(&["drive", "enable", "1", "--format", "json"]).ok().json();
    assert_eq!(states(&en)[0], ("disable_voltage".to_string(), "switch_on_disabled".to_string()));
    assert_eq!(en["state"], "operation_enabled");
    let off = sim.run(&["drive", "disable", "1"]).ok();
    assert!(off.stdout.contains("disable voltage (0x0000): Operation enabled → Switch on disabled"), "{}", off.stdout);
    assert_eq!(status(|a| sim.run(a), "1")["state"], "switch_on_disabled");
    // Quick stop from switched on leads to switch on disabled (transition 10).
    sim.run(&["sdo", "write", "1", "6040", "6", "--type", "u16"]).ok();
    sim.run(&["sdo", "write", "1", "6040", "7", "--type", "u16"]).ok();
    let qs = sim.run(&["drive", "quick-stop", "1", "--format", "json"]).ok().json();
    assert_eq!(states(&qs), pairs(&[("quick_stop", "switch_on_disabled")]));
}

#[test]
fn a_fault_stops_enable_and_fault_reset_clears_it_once_the_cause_is_gone() {
    let sim = Sim::new();
    sim.run(&["drive", "enable", "1"]).ok();
    sim.run(&["sdo", "write", "1", "5FFE", "1", "--type", "u16"]).ok();
    let faulted = until_state(|a| sim.run(a), "1", "fault");
    assert_eq!(faulted["error_register"], 0x05);
    assert_eq!(faulted["error_register_bits"], serde_json::json!(["generic", "voltage"]));
    assert_eq!(faulted["errors"][0]["code"], 0x3220);
    assert_eq!(faulted["errors"][0]["meaning"], "DC link under-voltage", "as `errors 1` names it");

    let enable = sim.run(&["drive", "enable", "1"]);
    assert_eq!(enable.code, 4, "{}{}", enable.stdout, enable.stderr);
    assert!(enable.stderr.contains("enable stopped in Fault: fault present"), "{}", enable.stderr);

    // The cause is still there: the reset does not take.
    let reset = sim.run(&["drive", "fault-reset", "1", "--wait", "300ms"]);
    assert_eq!(reset.code, 4, "{}{}", reset.stdout, reset.stderr);
    assert!(reset.stderr.contains("the fault remains after the reset"), "{}", reset.stderr);

    // Repaired: the fault stays latched until the reset, which clears the error register.
    sim.run(&["sdo", "write", "1", "5FFE", "0", "--type", "u16"]).ok();
    assert_eq!(status(|a| sim.run(a), "1")["state"], "fault");
    let reset = sim.run(&["drive", "fault-reset", "1"]).ok();
    assert!(reset.stdout.contains("fault reset (0x0080): Fault → Switch on disabled"), "{}", reset.stdout);
    let after = status(|a| sim.run(a), "1");
    assert_eq!(after["error_register"], 0);
    assert_eq!(after["errors"][0]["code"], 0x3220, "the history keeps it");
    sim.run(&["drive", "enable", "1"]).ok();
    // Nothing to reset.
    let idle = sim.run(&["drive", "fault-reset", "1"]).ok();
    assert!(idle.stdout.contains("already Operation enabled"), "{}", idle.stdout);
}

#[test]
fn the_stepper_without_supply_stops_with_voltage_missing() {
    let sim = Sim::new();
    let s = status(|a| sim.run(a), "32");
    assert_eq!(s["statusword"], 0x0250, "seed 003 after power on");
    // Seed 003 lists no 0x6061 and no 0x1003.
    assert_eq!(s["mode"]["from"], "0x6060:0");
    assert_eq!(s["mode"]["name"], "profile position");
    assert!(s["errors"].is_null(), "{s}");
    sim.run(&["sdo", "write", "32", "5FFD", "1", "--type", "u8"]).ok();
    let r = sim.run(&["drive", "enable", "32", "--wait", "300ms"]);
    assert_eq!(r.code, 4, "{}{}", r.stdout, r.stderr);
    assert!(r.stdout.contains("switch on (0x0007): Ready to switch on → still Ready to switch on"), "{}", r.stdout);
    assert!(r.stderr.contains("enable stopped in Ready to switch on: voltage missing"), "{}", r.stderr);
    sim.run(&["sdo", "write", "32", "5FFD", "0", "--type", "u8"]).ok();
    let r = sim.run(&["drive", "enable", "32", "--format", "json"]).ok().json();
    assert_eq!(r["state"], "operation_enabled");
    assert_eq!(status(|a| sim.run(a), "32")["statusword"], 0x0237);
}

#[test]
fn the_stepper_faults_and_resets_with_its_error_class_in_0x1002() {
    let sim = Sim::new();
    sim.run(&["sdo", "write", "32", "5FFE", "1", "--type", "u16"]).ok();
    until_state(|a| sim.run(a), "32", "fault");
    assert_eq!(sim.run(&["sdo", "read", "32", "1002"]).ok().stdout.trim(), "1");
    sim.run(&["sdo", "write", "32", "5FFE", "0", "--type", "u16"]).ok();
    sim.run(&["drive", "fault-reset", "32"]).ok();
    assert_eq!(sim.run(&["sdo", "read", "32", "1002"]).ok().stdout.trim(), "0");
}

#[test]
fn devices_that_are_not_drives_are_refused_with_their_profile() {
    let sim = Sim::new();
    for (node, profile) in
        [("10", "profile 401 (CiA 401, generic I/O modules)"), ("5", "profile 406 (CiA 406, encoders)")]
    {
        for verb in ["status", "enable", "disable", "quick-stop", "fault-reset"] {
            let r = sim.run(&["drive", verb, node]);
            assert_eq!(r.code, 2, "{verb} {node}: {}", r.stderr);
            assert!(r.stderr.contains(&format!("node {node} is not a CiA 402 drive")), "{}", r.stderr);
            assert!(r.stderr.contains(profile), "{}", r.stderr);
            assert!(r.stdout.is_empty(), "{}", r.stdout);
        }
    }
    // Nothing was written to them.
    assert!(sim.run(&["sdo", "read", "10", "6200:1"]).ok().stdout.starts_with("00 "));
}

#[test]
fn an_absent_node_is_a_timeout() {
    let sim = Sim::new();
    let r = sim.run(&["--timeout", "200ms", "drive", "enable", "42"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
}

#[cfg(unix)]
#[test]
fn watch_by_sdo_polls_and_ends_with_130_on_interrupt() {
    let sim = Sim::new();
    let lines = sim.run(&["drive", "status", "1"]).ok().stdout.lines().count();
    let r = common::signal_after_lines(
        sim.command(&["drive", "status", "1", "--watch"]),
        lines + 1,
        nix::sys::signal::Signal::SIGINT,
    );
    assert_eq!(r.code, 130, "{}", r.stderr);
    assert!(r.stdout.contains("node 1: Switch on disabled (statusword 0x0540, by SDO)"), "{}", r.stdout);
    assert!(r.stderr.contains("reading the statusword by SDO"), "{}", r.stderr);
    assert!(r.stderr.contains("last seen Switch on disabled"), "{}", r.stderr);
}

/// The watch's CSV rows come under their own header row (every CSV has one), their time
/// Unix time as every stream's.
#[cfg(unix)]
#[test]
fn watch_in_csv_has_a_header_row() {
    let sim = Sim::new();
    let report = sim.run(&["drive", "status", "1", "--format", "csv"]).ok().stdout.lines().count();
    let r = common::signal_after_lines(
        sim.command(&["drive", "status", "1", "--watch", "--format", "csv"]),
        report + 1,
        nix::sys::signal::Signal::SIGINT,
    );
    assert_eq!(r.code, 130, "{}", r.stderr);
    let lines: Vec<&str> = r.stdout.lines().collect();
    assert_eq!(lines.get(report), Some(&"time,node,statusword,state,source"), "{}", r.stdout);
    for row in &lines[report + 1..] {
        let time: f64 = row.split(',').next().unwrap().parse().unwrap();
        assert!(time > 1.6e9, "Unix time: {row}");
    }
}

#[cfg(unix)]
#[test]
fn watch_takes_the_statusword_from_its_tpdo_when_operational() {
    let sim = Sim::new();
    sim.run(&["nmt", "start", "1"]).ok();
    // The TPDO is event-driven: an event timer makes it come without a change.
    sim.run(&["sdo", "write", "1", "1800:5", "50", "--type", "u16"]).ok();
    let r = common::signal_after_lines(
        sim.command(&["drive", "status", "1", "--watch", "--format", "json"]),
        // The pretty JSON report ends with "}" alone on its line; the first change follows.
        serde_json::to_string_pretty(&status(|a| sim.run(a), "1")).unwrap().lines().count() + 1,
        nix::sys::signal::Signal::SIGINT,
    );
    assert_eq!(r.code, 130, "{}", r.stderr);
    let change: Value = serde_json::from_str(r.stdout.lines().last().unwrap()).unwrap();
    assert_eq!(change["source"], "tpdo", "{}", r.stdout);
    assert_eq!(change["statusword"], 0x0740, "remote while operational");
    assert!(r.stderr.contains("watching the statusword in TPDO 0x181"), "{}", r.stderr);
}

#[cfg(unix)]
#[test]
fn through_the_epos2_gateway_enable_fault_reset_and_disable() {
    for framing in ["--epos2-rs232", "--epos2-usb"] {
        let sim = Sim::new();
        let dev = DeviceSide::start(&sim, framing, &[]);
        let run = |a: &[&str]| dev.run(a);
        let enable = dev.run(&["drive", "enable", "1"]).ok();
        assert!(enable.stdout.contains("node 1: Operation enabled"), "{framing}: {}", enable.stdout);
        dev.run(&["sdo", "write", "1", "5FFE", "1", "--type", "u16"]).ok();
        until_state(run, "1", "fault");
        dev.run(&["sdo", "write", "1", "5FFE", "0", "--type", "u16"]).ok();
        let reset = dev.run(&["drive", "fault-reset", "1"]).ok();
        assert!(reset.stdout.contains("Fault → Switch on disabled"), "{framing}: {}", reset.stdout);
        dev.run(&["drive", "enable", "1"]).ok();
        let disable = dev.run(&["drive", "disable", "1"]).ok();
        assert!(disable.stdout.contains("Operation enabled → Switch on disabled"), "{framing}: {}", disable.stdout);
        // The EPOS2 itself, as node 0.
        assert_eq!(status(|a| dev.run(a), "0")["state"], "switch_on_disabled");
    }
}
