//! One command on several buses: separate simulated networks (a state file each), each
//! set up differently, worked at once; one report with a bus column, a JUnit suite per
//! bus, the worst exit code.

use crate::common;

use common::{finish, Sim};
use std::process::Command;

/// The test's first network (its default state file) and a second one beside it.
fn two_networks(sim: &Sim) -> (String, String) {
    let second = format!("sim:{}", sim.path("second.json").display());
    sim.run(&["sim", "reset", "--virtual-time"]).ok();
    on(sim, &[&second], &["sim", "reset", "--virtual-time", "--bootloader", "9"]).ok();
    (sim.bus(), second)
}

/// canctl on exactly these buses, isolated as `Sim::command` isolates it.
fn on(sim: &Sim, buses: &[&str], args: &[&str]) -> common::Run {
    let mut c = Command::new(common::canctl_bin());
    let home = sim.path("");
    c.env("XDG_CONFIG_HOME", &home).env("XDG_CACHE_HOME", &home).env("XDG_STATE_HOME", &home);
    c.env_remove("CANCTL_BUS").stdin(std::process::Stdio::null());
    for bus in buses {
        c.args(["--bus", bus]);
    }
    finish(c.args(args).output().unwrap())
}

#[test]
fn scan_lists_each_networks_own_nodes_with_their_bus() {
    let sim = Sim::new();
    let (first, second) = two_networks(&sim);
    let run = on(&sim, &[&first, &second], &["scan"]).ok();
    let table: Vec<&str> = run.stdout.lines().collect();
    assert!(table[0].trim_start().starts_with("bus"), "{}", run.stdout);
    let rows = |bus: &str, node: &str| table.iter().filter(|l| l.split_whitespace().take(2).eq([bus, node])).count();
    assert_eq!((rows(&first, "5"), rows(&second, "5")), (1, 1), "{}", run.stdout);
    // The bootloader device is on the second network only: separate state files are
    // separate networks.
    assert_eq!((rows(&first, "9"), rows(&second, "9")), (0, 1), "{}", run.stdout);

    let json = on(&sim, &[&first, &second], &["scan", "--format", "json"]).ok().json();
    let buses = json["buses"].as_array().unwrap();
    assert_eq!(buses.iter().map(|b| b["bus"].as_str().unwrap()).collect::<Vec<_>>(), [&*first, &*second]);
    // One bus: the report as it always was, no bus list around it.
    let one = sim.run(&["scan", "--format", "json"]).ok().json();
    assert!(one.get("buses").is_none() && one["nodes"].is_array(), "{one}");
}

#[test]
fn health_gives_a_junit_suite_per_bus_and_the_worst_exit() {
    let sim = Sim::new();
    let (first, second) = two_networks(&sim);
    // Node 5 of the second network stops: it answers no SDO there, and is unhealthy.
    on(&sim, &[&second], &["nmt", "stop", "5"]).ok();
    let run = on(&sim, &[&first, &second], &["health", "--format", "junit"]);
    assert_eq!(run.code, 6, "{}\n{}", run.stdout, run.stderr);
    let suites: Vec<&str> = run.stdout.lines().filter(|l| l.trim_start().starts_with("<testsuite ")).collect();
    assert_eq!(suites.len(), 2, "{}", run.stdout);
    assert!(suites[0].contains(&first) && suites[0].contains("failures=\"0\""), "{}", suites[0]);
    assert!(suites[1].contains(&second) && !suites[1].contains("failures=\"0\""), "{}", suites[1]);
    assert!(run.stderr.contains("1 of 2 buses failed") && run.stderr.contains(&second), "{}", run.stderr);
}

#[test]
fn a_bus_that_cannot_be_opened_fails_alone_with_exit_5() {
    let sim = Sim::new();
    let (first, _) = two_networks(&sim);
    let run = on(&sim, &[&first, "socketcan:nosuch0"], &["health"]);
    assert_eq!(run.code, 5, "{}\n{}", run.stdout, run.stderr);
    // The network that opened is reported whole.
    assert!(run.stdout.lines().any(|l| l.split_whitespace().take(2).eq([&*first, "5"])), "{}", run.stdout);
    assert!(run.stdout.contains("socketcan:nosuch0: there is no network interface 'nosuch0'"), "{}", run.stdout);
}

#[test]
fn network_check_and_firmware_status_take_several_buses() {
    let sim = Sim::new();
    let (first, second) = two_networks(&sim);
    let third = format!("sim:{}", sim.path("third.json").display());
    on(&sim, &[&third], &["sim", "reset", "--virtual-time", "--bootloader", "9"]).ok();
    let status = on(&sim, &[&first, &second, &third], &["firmware", "status", "9", "--format", "json"]);
    let json = status.json();
    let buses = json["buses"].as_array().unwrap();
    // The first network has no node 9: that bus fails (no answer), the others report.
    assert!(buses[0]["error"].as_str().unwrap().contains("node 9"), "{json}");
    assert!(buses[1].get("error").is_none() && buses[2].get("error").is_none(), "{json}");
    assert_eq!(status.code, 3, "{}", status.stderr);

    let project = sim.path("machine");
    sim.run(&["network", "dump", project.to_str().unwrap()]).ok();
    let check = on(&sim, &[&first, &second], &["network", "check", project.to_str().unwrap(), "--format", "junit"]);
    // The second network has a node the project does not list (9): it differs, the first not.
    assert_eq!(check.code, 6, "{}\n{}", check.stdout, check.stderr);
    assert_eq!(check.stdout.matches("<testsuite ").count(), 2, "{}", check.stdout);
}

#[test]
fn other_commands_refuse_a_second_bus() {
    let sim = Sim::new();
    let (first, second) = two_networks(&sim);
    let run = on(&sim, &[&first, &second], &["sdo", "read", "5", "0x1000"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("only scan, health, network check and firmware status"), "{}", run.stderr);
}

#[test]
fn a_settings_file_may_list_the_buses() {
    let sim = Sim::new();
    let (first, second) = two_networks(&sim);
    let project = sim.path("bench");
    std::fs::create_dir_all(&project).unwrap();
    std::fs::write(project.join("canctl.toml"), format!("bus = [\"{first}\", \"{second}\"]\n")).unwrap();
    let mut c = Command::new(common::canctl_bin());
    let home = sim.path("");
    c.env("XDG_CONFIG_HOME", &home).env("XDG_CACHE_HOME", &home).env("XDG_STATE_HOME", &home);
    c.env_remove("CANCTL_BUS").current_dir(&project).stdin(std::process::Stdio::null());
    let json = finish(c.args(["scan", "--format", "json"]).output().unwrap()).ok().json();
    let buses: Vec<&str> = json["buses"].as_array().unwrap().iter().map(|b| b["bus"].as_str().unwrap()).collect();
    assert_eq!(buses, [&*first, &*second]);
}
