//! The simulator's profiles, device counts and faults, through the binary: what a user of
//! `canctl sim reset` sees. No timing is asserted; slow answers only make runs longer.

use crate::common;

use common::{DeviceSide, Run, Sim};

fn reset(sim: &Sim, args: &[&str]) -> Run {
    let mut all = vec!["sim", "reset"];
    all.extend_from_slice(args);
    sim.run(&all).ok()
}

#[test]
fn each_profile_serves_sdo_and_scan() {
    for profile in ["instant", "typical", "slow"] {
        let sim = Sim::new();
        let r = reset(&sim, &["--profile", profile, "--format", "json"]);
        assert_eq!(r.json()["profile"], profile);
        let name = sim.run(&["sdo", "read", "1", "1008"]).ok();
        assert_eq!(name.stdout.trim(), "EPOS2 24/5", "{profile}");
        // A slow slave answers up to 80 ms late: the probe window must wait for it.
        let scan = sim.run(&["scan", "--window", "300ms", "--format", "json"]).ok().json();
        let nodes: Vec<u64> = scan["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect();
        assert_eq!(nodes, [1, 5, 10, 32], "{profile}: {scan}");
    }
}

#[test]
fn slow_profile_with_eight_unconfigured_devices_is_seen_by_scan() {
    let sim = Sim::new();
    reset(&sim, &["--profile", "slow", "--unconfigured", "8", "--virtual-time"]);
    let scan = sim.run(&["scan", "--window", "300ms", "--format", "json"]).ok().json();
    assert_eq!(scan["lss_unconfigured"], 8, "{scan}");
}

#[test]
fn the_configuration_is_kept_between_invocations() {
    let sim = Sim::new();
    reset(&sim, &["--profile", "instant", "--unconfigured", "0", "--seed", "7", "--fault", "10:drop"]);
    // Two invocations: the same network both times.
    for _ in 0..2 {
        let scan = sim.run(&["scan", "--format", "json"]).ok().json();
        let nodes: Vec<u64> = scan["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect();
        assert_eq!(nodes, [1, 5, 32], "{scan}");
        assert_eq!(scan["lss_unconfigured"], 0, "{scan}");
    }
}

#[test]
fn a_dropping_device_is_named_in_a_timeout() {
    let sim = Sim::new();
    reset(&sim, &["--fault", "5:drop"]);
    let r = sim.run(&["sdo", "read", "5", "1000"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    assert!(r.stderr.contains("node 5"), "{}", r.stderr);
    // The others still answer.
    sim.run(&["sdo", "read", "1", "1000"]).ok();
}

#[test]
fn a_device_muted_mid_transfer_ends_the_upload_with_a_timeout() {
    let sim = Sim::new();
    // The drive answers the initiate and 9 segments of the 64 KiB domain, then falls silent.
    reset(&sim, &["--fault", "drive:mute@11+"]);
    let r = sim.run(&["sdo", "read", "1", "1F50:1", "--out", sim.path("domain.bin").to_str().unwrap()]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    assert!(r.stderr.contains("node 1"), "{}", r.stderr);
}

#[test]
fn an_injected_abort_is_reported_with_its_code() {
    let sim = Sim::new();
    reset(&sim, &["--fault", "10:abort=0x06010000"]);
    let r = sim.run(&["sdo", "read", "10", "1000"]);
    assert_eq!(r.code, 4, "{}", r.stderr);
    assert!(r.stderr.contains("0x06010000"), "{}", r.stderr);
}

#[test]
fn a_corrupted_answer_is_a_protocol_failure() {
    let sim = Sim::new();
    reset(&sim, &["--fault", "32:corrupt"]);
    let r = sim.run(&["sdo", "read", "32", "1000"]);
    assert_eq!(r.code, 5, "{}", r.stderr);
}

#[test]
fn an_answer_on_the_wrong_id_is_not_taken_for_the_nodes() {
    let sim = Sim::new();
    reset(&sim, &["--fault", "5:wrong-cob"]);
    let r = sim.run(&["sdo", "read", "5", "1000"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
}

#[test]
fn a_babbling_device_with_the_highest_priority_hides_the_bus() {
    let sim = Sim::new();
    // On a bus with timing (an instant bus has room for everything).
    reset(&sim, &["--fault", "5:babble=0x001"]);
    let r = sim.run(&["sdo", "read", "1", "1000"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
}

#[test]
fn bad_fault_specs_are_usage_errors() {
    let sim = Sim::new();
    for bad in ["5:explode", "drop", "5:drop@0", "200:drop"] {
        let r = sim.run(&["sim", "reset", "--fault", bad]);
        assert_eq!(r.code, 2, "{bad}: {}", r.stderr);
    }
    let r = sim.run(&["sim", "reset", "--profile", "fast"]);
    assert_eq!(r.code, 2, "{}", r.stderr);
}

/// Issue 12: mapping more than 64 bits panicked the simulator. A CiA 301 device refuses
/// the mapping count with abort 0x06040042, and canctl reports it.
#[test]
fn mapping_more_than_64_bits_is_refused_by_the_device() {
    let sim = Sim::new();
    reset(&sim, &["--profile", "instant"]);
    // 32 + 32 + 16 bits.
    let r = sim.run(&["stream-pdo", "1", "--start", "--map", "6064:0,606C:0,6041:0", "--event", "20", "--count", "1"]);
    assert_eq!(r.code, 4, "{}", r.stderr);
    assert!(r.stderr.contains("0x06040042"), "{}", r.stderr);
    // The mapping as it was: the statusword alone.
    assert_eq!(sim.run(&["sdo", "read", "1", "1A00:0"]).ok().stdout.trim(), "1");
    assert_eq!(
        sim.run(&["sdo", "read", "1", "1A00:1", "--type", "u32"]).ok().stdout.trim(),
        0x6041_0010u32.to_string()
    );
}

#[test]
fn the_epos2_device_side_reaches_slow_devices_behind_it() {
    let sim = Sim::new();
    reset(&sim, &["--profile", "slow"]);
    let dev = DeviceSide::start(&sim, "--epos2-usb", &[]);
    assert_eq!(dev.run(&["sdo", "read", "5", "1008"]).ok().stdout.trim(), "C01");
    assert_eq!(dev.run(&["sdo", "read", "10", "1008"]).ok().stdout.trim(), "CAN-2057C");
}

#[test]
fn a_fault_applies_behind_the_epos2_too() {
    let sim = Sim::new();
    reset(&sim, &["--fault", "10:abort=0x06010000"]);
    let dev = DeviceSide::start(&sim, "--epos2-rs232", &[]);
    let r = dev.run(&["sdo", "read", "10", "1000"]);
    assert_eq!(r.code, 4, "{}", r.stderr);
}

/// A device that fills every idle moment of the bus (at the lowest priority, so the others
/// still get through) must not keep a listening command past its wait: scan and LSS assign
/// listen for heartbeats and answers, and end.
#[test]
fn a_bus_that_never_falls_quiet_does_not_keep_a_listener() {
    let sim = Sim::new();
    reset(&sim, &["--fault", "10:babble=0x7F0"]);
    let limit = std::time::Duration::from_secs(90);
    let scan = common::run_within(sim.command(&["scan", "--format", "json"]), limit);
    assert_eq!(scan.code, 0, "{}", scan.stderr);
    let assign = common::run_within(sim.command(&["lss", "assign", "--start", "20"]), limit);
    assert_eq!(assign.code, 0, "{}", assign.stderr);
    assert!(assign.stderr.contains("3 device(s) given a node-id"), "{}", assign.stderr);
}

/// At its defaults, scan finds every node of a slow network (answers up to 80 ms late)
/// and of a slow bus (at 125 kbit/s the 127 probes alone take 100 ms to leave): its window
/// counts from the last answer, not from when the probes were queued.
#[test]
fn scan_at_defaults_finds_every_node_of_a_slow_network_or_bus() {
    for setup in
        [&["--profile", "slow"][..], &["--bit-rate", "125k"][..], &["--profile", "slow", "--bit-rate", "125k"][..]]
    {
        let sim = Sim::new();
        reset(&sim, setup);
        for _ in 0..3 {
            let scan = sim.run(&["scan", "--format", "json"]).ok().json();
            let nodes: Vec<u64> =
                scan["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect();
            assert_eq!(nodes, [1, 5, 10, 32], "{setup:?}: {scan}");
        }
    }
}

/// `canctl sim` says in its own words what it will not serve (the simulator reports it as a
/// typed value): a fault the slcan adapter does not take, where device faults go instead;
/// a bus that is not the sim network, which bus to name. Both are usage errors (exit 2).
#[cfg(unix)]
#[test]
fn sim_refusals_say_what_to_use_instead() {
    let sim = Sim::new();
    let run = sim.run(&["sim", "--slcan", "--fault", "stale@1"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("not Stale; device faults go to `canctl sim reset --fault`"), "{}", run.stderr);
    assert!(run.stdout.is_empty(), "no pty was served: {}", run.stdout);

    let mut c = std::process::Command::new(common::canctl_bin());
    c.env("XDG_STATE_HOME", sim.path("state")).env_remove("CANCTL_BUS").args(["--bus", "can0", "sim", "reset"]);
    let run = common::finish(c.output().unwrap());
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("use --bus sim or sim:PATH (or no --bus)"), "{}", run.stderr);
}
