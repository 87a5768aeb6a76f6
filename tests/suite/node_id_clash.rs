//! Two devices on one node-id (issue 25): `lss set-id` refuses an id something on the bus
//! uses, and `scan` and `health` report the clash when there is one (`--force` made it,
//! as a device from the shelf with a stored id would).

use crate::common;

use common::Sim;

/// The sensor without a node-id that is of the same kind as node 5 (vendor 0x40, MH).
const TWIN: &str = "0x40:0x43787800:0x312E3031:0x09501301";

#[test]
fn set_id_refuses_an_id_in_use_and_gives_a_free_one() {
    let sim = Sim::new();
    let r = sim.run(&["lss", "set-id", "5", "--identity", TWIN]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    assert!(r.stderr.contains("node-id 5 is in use"), "{}", r.stderr);
    assert!(r.stderr.contains("0x09501234") && r.stderr.contains("--force"), "{}", r.stderr);
    // Nothing was given: node 5 is still the one device, the twin still waits.
    let scan = sim.run(&["scan", "--format", "json"]).ok().json();
    assert_eq!(scan["lss_unconfigured"], 3, "{scan}");
    assert!(scan.get("clashes").is_none(), "{scan}");
    // A free id is given; giving the device the id it has already is no clash.
    sim.run(&["lss", "set-id", "7", "--identity", TWIN]).ok();
    sim.run(&["lss", "set-id", "7", "--identity", TWIN]).ok();
    assert_eq!(sim.run(&["sdo", "read", "7", "1018:4", "--type", "u32"]).ok().stdout.trim(), "156242689");
}

#[test]
fn scan_and_health_report_two_devices_on_one_node_id() {
    let sim = Sim::new();
    sim.run(&["lss", "set-id", "5", "--identity", TWIN, "--force"]).ok();
    let scan = sim.run(&["scan", "--format", "json"]).ok().json();
    let clashes = scan["clashes"].as_array().unwrap_or_else(|| panic!("{scan}"));
    assert_eq!(clashes.len(), 1, "{scan}");
    assert_eq!(clashes[0]["node"], 5, "{scan}");
    assert_eq!(clashes[0]["evidence"], "sdo_answers", "{scan}");
    let human = sim.run(&["scan"]).ok();
    assert!(human.stderr.contains("warning: node-id 5 is used by 2 devices"), "{}", human.stderr);
    assert!(human.stderr.contains("0x09501234") && human.stderr.contains("0x09501301"), "{}", human.stderr);
    // The remedy, in canctl's words (the library's clash names no flag).
    let remedy = "give one of them another id (lss set-id NEW --identity ...)";
    assert!(human.stderr.contains(remedy), "{}", human.stderr);
    let health_human = sim.run(&["health"]);
    assert!(health_human.stdout.contains("node 5 node-id: node-id 5 is used by 2 devices"), "{}", health_human.stdout);
    assert!(health_human.stdout.contains(remedy), "{}", health_human.stdout);

    let health = sim.run(&["health", "--format", "json"]);
    assert_eq!(health.code, 6, "{}\n{}", health.stdout, health.stderr);
    let report = health.json();
    let node5 = report["nodes"].as_array().unwrap().iter().find(|n| n["node"] == 5).unwrap();
    let check = node5["checks"].as_array().unwrap().iter().find(|c| c["check"] == "node-id").unwrap();
    assert_eq!(check["ok"], false, "{node5}");
    assert!(check["detail"].as_str().unwrap().contains("used by 2 devices"), "{node5}");
    // The other nodes are not blamed.
    let node1 = report["nodes"].as_array().unwrap().iter().find(|n| n["node"] == 1).unwrap();
    assert_eq!(node1["ok"], true, "{node1}");
}
