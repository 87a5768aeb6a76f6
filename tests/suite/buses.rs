//! `canctl buses` finds `canctl sim --socketcand` by its beacon, with the exact `--bus`
//! value that then works, and completion offers it afterwards. Each test moves the beacon
//! to a UDP port of its own (CANCTL_BEACON_PORT), so that test runs at once, and a real
//! socketcand on this machine, do not hear each other.

use crate::common;

use common::{canctl_bin, finish, Run, Sim};
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

/// A UDP port free on every address now.
fn free_udp_port() -> u16 {
    std::net::UdpSocket::bind("0.0.0.0:0").unwrap().local_addr().unwrap().port()
}

/// `canctl sim --socketcand 127.0.0.1:0` with `extra`, beacons to `port`; its `--bus` value.
fn serve(sim: &Sim, port: u16, extra: &[&str]) -> (Child, String) {
    let mut args = vec!["sim", "--socketcand", "127.0.0.1:0"];
    args.extend_from_slice(extra);
    let mut c = sim.command(&args);
    c.env("CANCTL_BEACON_PORT", port.to_string()).stdout(Stdio::piped()).stderr(Stdio::null());
    let mut child = c.spawn().unwrap();
    let mut bus = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut bus).unwrap();
    (child, bus.trim().to_string())
}

/// canctl with `args`, the test's cache and beacon port, no bus.
fn canctl(sim: &Sim, port: u16, args: &[&str]) -> Run {
    let mut c = Command::new(canctl_bin());
    c.env("XDG_CONFIG_HOME", sim.path("")).env("XDG_CACHE_HOME", sim.path("")).env_remove("CANCTL_BUS");
    c.env("CANCTL_BEACON_PORT", port.to_string()).args(args).stdin(Stdio::null());
    finish(c.output().unwrap())
}

#[test]
fn buses_hears_the_sim_server_and_its_bus_value_scans() {
    let (sim, quiet) = (Sim::new(), Sim::new());
    let port = free_udp_port();
    let (mut server, bus) = serve(&sim, port, &[]);
    let (mut silent, silent_bus) = serve(&quiet, port, &["--no-beacon"]);
    let run = canctl(&sim, port, &["buses", "--wait", "4s", "--format", "json"]).ok();
    let report = run.json();
    let rows = report["buses"].as_array().unwrap();
    let heard: Vec<&str> =
        rows.iter().filter(|r| r["kind"] == "socketcand").map(|r| r["bus"].as_str().unwrap()).collect();
    assert_eq!(heard, [bus.as_str()], "the server with a beacon, once; not the one with --no-beacon ({silent_bus})");
    assert_eq!(report["beacon_port"], port);
    let scan = canctl(&sim, port, &["--bus", heard[0], "scan", "--format", "json"]).ok();
    let nodes: Vec<u64> =
        scan.json()["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect();
    assert_eq!(nodes, [1, 5, 10, 32]);
    // Completion offers what was heard, without listening again.
    let offered = || {
        let mut c = Command::new(canctl_bin());
        c.env("XDG_CONFIG_HOME", sim.path("")).env("XDG_CACHE_HOME", sim.path("")).env_remove("CANCTL_BUS");
        c.env("COMPLETE", "fish").args(["--", "canctl", "--bus", "socketcand:"]);
        let offered = finish(c.output().unwrap()).ok().stdout;
        assert!(offered.lines().any(|l| l.starts_with(&format!("{bus}\tsocketcand on "))), "{offered}");
    };
    offered();
    // A run that did not listen does not forget what the last one heard.
    canctl(&sim, port, &["buses", "--wait", "0s"]).ok();
    offered();
    let _ = (server.kill(), silent.kill(), server.wait(), silent.wait());
}

#[test]
fn nothing_heard_is_said_and_a_wait_beyond_a_minute_is_refused() {
    let sim = Sim::new();
    let port = free_udp_port();
    let run = canctl(&sim, port, &["buses", "--wait", "0s"]).ok();
    assert!(run.stderr.contains("no socketcand beacon heard"), "{}", run.stderr);
    let refused = canctl(&sim, port, &["buses", "--wait", "2m"]);
    assert_eq!(refused.code, 2, "{}", refused.stderr);
    assert!(refused.stderr.contains("at most 60s"), "{}", refused.stderr);
}

/// `buses --format csv` is CSV whatever was found: its header row first, never the
/// sentence people get ("no bus found" read as a row by a script).
#[test]
fn buses_in_csv_is_a_table_even_when_nothing_is_found() {
    let sim = Sim::new();
    let run = canctl(&sim, free_udp_port(), &["buses", "--wait", "0s", "--format", "csv"]).ok();
    assert_eq!(run.stdout.lines().next(), Some("--bus,kind,what"), "{}", run.stdout);
    assert!(!run.stdout.contains("no bus found"), "{}", run.stdout);
}
