//! `canctl health` on the simulated network: healthy as it starts; a faulted drive and a
//! node whose heartbeat stopped are named, exit 6, in every format.

use crate::common;

use common::{Run, Sim};
use serde_json::Value as J;

fn node(report: &J, id: u64) -> &J {
    report["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["node"] == id)
        .unwrap_or_else(|| panic!("no node {id}: {report}"))
}

fn failed(n: &J) -> Vec<&str> {
    n["checks"].as_array().unwrap().iter().filter(|c| c["ok"] == false).map(|c| c["check"].as_str().unwrap()).collect()
}

/// The demo network with its drive (node 1) in Fault and the I/O module (node 10)
/// configured to beat every 100 ms but sending nothing.
fn troubled() -> Sim {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--fault", "10:no-heartbeat"]).ok();
    sim.run(&["sdo", "write", "10", "1017", "100", "--type", "u16"]).ok();
    // The fault strikes 1 ms later: by the next command at the latest.
    sim.run(&["sdo", "write", "1", "5FFE", "1", "--type", "u16"]).ok();
    sim
}

fn health(sim: &Sim, format: &str) -> Run {
    sim.run(&["health", "--format", format])
}

#[test]
fn the_demo_network_is_healthy() {
    let sim = Sim::new();
    let run = health(&sim, "json");
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let report = run.json();
    assert_eq!(report["ok"], true);
    let ids: Vec<u64> = report["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect();
    assert_eq!(ids, [1, 5, 10, 32]);
    // The sensor beats every 40 ms: several beats were watched, on time.
    let sensor = node(&report, 5);
    assert!(sensor["heartbeats"].as_u64().unwrap() >= 2, "{sensor}");
    assert_eq!(sensor["nmt"], "pre-operational");
    // The drives' states come from their statuswords.
    assert_eq!(node(&report, 1)["drive_state"], "switch_on_disabled");
    assert_eq!(node(&report, 32)["drive_state"], "switch_on_disabled");
    assert_eq!(node(&report, 10)["errors_logged"], 2, "logged errors are shown, not a failure");
    let human = health(&sim, "human").ok();
    assert!(human.stderr.contains("all 4 node(s) healthy"), "{}", human.stderr);
}

#[test]
fn a_faulted_drive_and_a_stopped_heartbeat_are_named_with_exit_6() {
    let sim = troubled();
    let run = health(&sim, "json");
    assert_eq!(run.code, 6, "{}\n{}", run.stdout, run.stderr);
    let report = run.json();
    assert_eq!(report["ok"], false);
    let drive = node(&report, 1);
    assert_eq!(failed(drive), ["error register", "drive"], "{drive}");
    assert_eq!(drive["drive_state"], "fault");
    assert_eq!(drive["errors_logged"], 1);
    let io = node(&report, 10);
    assert_eq!(failed(io), ["nmt", "heartbeat"], "{io}");
    assert_eq!((io["heartbeat_ms"].as_u64(), io["heartbeats"].as_u64()), (Some(100), Some(0)));
    assert!(failed(node(&report, 5)).is_empty() && failed(node(&report, 32)).is_empty(), "{report}");
    assert!(run.stderr.contains("2 of 4 node(s) not healthy"), "{}", run.stderr);

    let human = health(&sim, "human");
    assert_eq!(human.code, 6);
    assert!(human.stdout.contains("node 1 drive: Fault (statusword 0x"), "{}", human.stdout);
    assert!(human.stdout.contains("node 10 heartbeat: 0x1017 says every 100 ms, but none came in"), "{}", human.stdout);
    let row = human.stdout.lines().find(|l| l.trim_start().starts_with("10 ")).unwrap();
    assert!(row.contains("100 ms, NONE") && row.contains("UNHEALTHY: nmt, heartbeat"), "{row}");

    let csv = health(&sim, "csv");
    assert_eq!(csv.code, 6);
    assert!(
        csv.stdout.starts_with("node,name,nmt,heartbeat,error register,logged,emcy,drive,health\n"),
        "{}",
        csv.stdout
    );
    assert_eq!(csv.stdout.lines().count(), 5, "{}", csv.stdout);
}

#[test]
fn junit_has_a_case_per_node_and_check() {
    let sim = troubled();
    let run = health(&sim, "junit");
    assert_eq!(run.code, 6, "{}", run.stderr);
    let x = &run.stdout;
    // Five checks for each of the two drives, four for the others; four failures.
    assert!(x.contains("<testsuites name=\"canctl health: sim\" tests=\"18\" failures=\"4\""), "{x}");
    assert!(x.contains("<testcase classname=\"node 1 (EPOS2 24/5)\" name=\"drive\">\n      <failure"), "{x}");
    assert!(
        x.contains("<testcase classname=\"node 5 (C01)\" name=\"heartbeat\">\n      <system-out>every 40 ms, on time"),
        "{x}"
    );
    // Other commands still refuse it.
    let scan = sim.run(&["scan", "--format", "junit"]);
    assert_eq!(scan.code, 2);
    assert!(scan.stderr.contains("canctl network check, canctl health"), "{}", scan.stderr);
}

/// Through an EPOS2, which passes on no traffic: the states by remote request, no watch,
/// and the summary says what was not watched.
#[test]
fn through_an_epos2_nothing_is_watched_and_it_says_so() {
    let sim = Sim::new();
    let dev = common::DeviceSide::start(&sim, "--epos2-usb", &[]);
    let run = dev.run(&["health", "--format", "json"]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let report = run.json();
    assert_eq!(report["watched_ms"], 0);
    let sensor = node(&report, 5);
    assert_eq!(sensor["nmt"], "pre-operational");
    let heartbeat = sensor["checks"].as_array().unwrap().iter().find(|c| c["check"] == "heartbeat").unwrap();
    assert_eq!(heartbeat["detail"], "every 40 ms (not watched: this link shows no traffic)");
    let human = dev.run(&["health"]).ok();
    assert!(
        human.stderr.contains("all 4 node(s) healthy (no traffic watched: this link shows none)"),
        "{}",
        human.stderr
    );
}

/// An EMCY sent while health watches fails its node, with the code's meaning.
#[test]
fn an_emcy_during_the_watch_is_named() {
    let sim = Sim::new();
    // On virtual time: the 10 s watch takes no wall time, the fault strikes at its bus time.
    sim.run(&["sim", "reset", "--virtual-time"]).ok();
    // The sensor's magnet goes missing 3 s from now: well inside a 10 s watch that begins
    // once the scan is done.
    sim.run(&["sdo", "write", "5", "5FFE", "3000", "--type", "u16"]).ok();
    let run = sim.run(&["health", "--watch", "10s", "--format", "json"]);
    assert_eq!(run.code, 6, "{}\n{}", run.stdout, run.stderr);
    let sensor = node(&run.json(), 5).clone();
    assert!(failed(&sensor).contains(&"emcy"), "{sensor}");
    assert_eq!(sensor["emcy"][0]["code"], "0x5000");
    assert!(sensor["emcy"][0]["meaning"].as_str().unwrap().starts_with("Device hardware: no stop pulses"), "{sensor}");
}

/// A device whose SDO server answers on the next node's COB-ID (its 0x1200 changed): no
/// node is listed that is not there (node 6 used to be, with node 5's device type), node 5
/// is said to answer elsewhere, and health does not give it the remedy of a Stopped node.
#[test]
fn a_device_answering_on_another_nodes_cob_id_makes_no_phantom_node() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--fault", "5:wrong-cob"]).ok();
    let scan = sim.run(&["scan", "--format", "json"]).ok().json();
    let ids: Vec<u64> = scan["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect();
    assert_eq!(ids, [1, 5, 10, 32], "{scan}");
    assert_eq!(scan["answers_elsewhere"], serde_json::json!([{ "node": 5, "cob_id": 0x586 }]), "{scan}");
    let human = sim.run(&["scan"]).ok();
    assert!(human.stdout.contains("node 5: seen by its heartbeat (pre-operational), but it answered none of the 3 SDO probes: its SDO server answers on 0x586, not 0x585"), "{}", human.stdout);
    let run = health(&sim, "human");
    assert_eq!(run.code, 6, "{}", run.stderr);
    assert!(!run.stdout.contains("| 6 ") && !run.stdout.contains("\n 6 "), "{}", run.stdout);
    assert!(!run.stdout.contains("nmt preop 5"), "{}", run.stdout);
    assert!(run.stdout.contains("its SDO server does not answer on 0x605/0x585"), "{}", run.stdout);
}

/// The same device beating no heartbeat, on a bus canctl never scanned: nothing shows node 5,
/// so the probe's answer on 0x586 is all there is of it. Node 6 answers none of its identity
/// and nothing asked alone: it is not listed, and the scan and health say why (node 6 used to
/// be listed, and its six identity reads took 9 s).
#[test]
fn a_first_scan_lists_no_node_for_another_devices_answer() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--fault", "5:wrong-cob", "--fault", "5:no-heartbeat"]).ok();
    let scan = sim.run(&["scan", "--format", "json"]).ok().json();
    let ids: Vec<u64> = scan["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect();
    assert_eq!(ids, [1, 10, 32], "{scan}");
    assert_eq!(scan["not_there"], serde_json::json!([6]), "{scan}");
    let run = sim.run(&["health"]);
    assert!(!run.stdout.lines().any(|l| l.split_whitespace().next() == Some("6")), "{}", run.stdout);
    assert!(
        run.stderr.contains("node 6: not listed: an answer to the probe came on its COB-ID 0x586"),
        "{}",
        run.stderr
    );
}
