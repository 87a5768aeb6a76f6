//! Kernel test: `canctl network` through the Linux CAN stack on vcan0, with `canctl sim
//! --socketcan vcan0` as the devices (five sensors waiting for a node-id). The example
//! project is applied with --assign and checks clean; the bus is then dumped into a project
//! that checks clean against itself; `network set-baud` says how to switch the interface.
//! `scripts/kernel-tests.sh network` runs them in a VM;
//! without vcan0 it prints `SKIPPED` and passes, or fails where `CANCTL_REQUIRE_KERNEL` is set.

use crate::common;

use common::{Run, Sim};
use std::path::Path;
use std::process::{Command, Stdio};

fn canctl(sim: &Sim, args: &[&str]) -> Run {
    let mut c = Command::new(common::canctl_bin());
    c.env("XDG_CONFIG_HOME", sim.path("")).env("XDG_CACHE_HOME", sim.path(""));
    c.env_remove("CANCTL_BUS").args(["--bus", common::vcan()]).args(args).stdin(Stdio::null());
    common::run_within(c, std::time::Duration::from_secs(600))
}

fn junit_failures(xml: &str) -> Option<&str> {
    let suite = xml.lines().find(|l| l.trim_start().starts_with("<testsuite "))?;
    let at = suite.find(" failures=\"")? + " failures=\"".len();
    suite[at..].split('"').next()
}

#[test]
fn network_apply_assign_then_dump_and_check_round_trip_on_vcan() {
    if !common::has_interface(common::vcan()) {
        return;
    }
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--profile", "instant", "--unconfigured", "5"]).ok();
    let mut devices = common::sim_on_interface(&sim, common::vcan());
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/sim-machine");
    let example = example.to_str().unwrap();

    let applied = canctl(&sim, &["network", "apply", example, "--assign", "--format", "json"]).ok().json();
    let assigned = applied["nodes"].as_array().unwrap().iter().filter(|n| !n["assigned"].is_null()).count();
    assert_eq!(assigned, 5, "{applied}");
    let again = canctl(&sim, &["network", "apply", example, "--format", "json"]).ok().json();
    assert_eq!(again["written"], 0, "{again}");
    let check = canctl(&sim, &["network", "check", example, "--format", "junit"]);
    assert_eq!(check.code, 0, "{}\n{}", check.stdout, check.stderr);
    assert_eq!(junit_failures(&check.stdout), Some("0"), "{}", check.stdout);

    let dir = sim.path("dumped");
    canctl(&sim, &["network", "dump", dir.to_str().unwrap()]).ok();
    let round_trip = canctl(&sim, &["network", "check", dir.to_str().unwrap()]);
    assert_eq!(round_trip.code, 0, "{}\n{}", round_trip.stdout, round_trip.stderr);
    assert!(round_trip.stderr.contains("all 9 node(s) as the project says"), "{}", round_trip.stderr);

    let _ = devices.kill();
    let _ = devices.wait();
}

/// A CAN interface does not change its bit rate with the devices: `network set-baud` sends
/// the switch, says it could not check it, and gives the `ip link` command for vcan0.
#[test]
fn network_set_baud_on_socketcan_says_how_to_switch_the_interface() {
    if !common::has_interface(common::vcan()) {
        return;
    }
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--profile", "instant", "--unconfigured", "0", "--fault", "stepper:mute"]).ok();
    let mut devices = common::sim_on_interface(&sim, common::vcan());
    let run = canctl(&sim, &["network", "set-baud", "250k", "--global", "--format", "json"]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let report = run.json();
    assert_eq!(report["configured"]["confirmed"], 3, "{report}");
    assert_eq!(report["activated"], true, "{report}");
    assert_eq!(report["bus_followed"], false, "{report}");
    let hint = report["link_to_switch"].as_str().unwrap();
    let iface = common::vcan();
    let fix = format!("sudo ip link set {iface} down && sudo ip link set {iface} up type can bitrate 250000");
    assert!(hint.contains(&fix), "{hint}");
    let _ = devices.kill();
    let _ = devices.wait();
}
