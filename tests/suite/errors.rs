//! `canctl errors` on the simulated network: the I/O module's history with its manual's
//! meanings, the faulted drive's entry with CiA 402's, clearing, and a node without one.

use crate::common;

use common::Sim;

#[test]
fn the_io_modules_history_is_named_newest_first() {
    let sim = Sim::new();
    let run = sim.run(&["errors", "10"]).ok();
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert_eq!(
        lines[0], "node 10 (CAN-2057C): 2 error(s) logged in 0x1003, newest first; error register 0x00",
        "{}",
        run.stdout
    );
    assert!(lines[2].contains("0x8110  0x0006  CAN controller overrun  device manual"), "{}", run.stdout);
    assert!(lines[3].contains("0x5000  0x0002  EEPROM access error     device manual"), "{}", run.stdout);
    let json = sim.run(&["errors", "10", "--format", "json"]).ok().json();
    assert_eq!(json["entries"][0]["raw"], 0x0006_8110);
    assert_eq!(json["entries"][1]["code"], "0x5000");
    assert_eq!(json["entries"][1]["manufacturer"], "0x0002");
}

#[test]
fn the_faulted_drives_error_is_logged_and_cleared() {
    let sim = Sim::new();
    sim.run(&["sdo", "write", "1", "5FFE", "1", "--type", "u16"]).ok();
    let json = sim.run(&["errors", "1", "--format", "json"]).ok().json();
    assert_eq!(json["count"], 1, "{json}");
    assert_eq!(json["entries"][0]["code"], "0x3220");
    assert_eq!(json["entries"][0]["meaning"], "DC link under-voltage");
    assert_eq!(json["entries"][0]["source"], "CiA 402");
    assert_ne!(json["error_register"], 0);

    let cleared = sim.run(&["errors", "1", "--clear"]).ok();
    assert!(cleared.stdout.contains("0x3220"), "what was cleared is shown: {}", cleared.stdout);
    assert!(
        cleared.stdout.contains("node 1 (EPOS2 24/5): error history cleared (0x1003:0 reads back 0)"),
        "{}",
        cleared.stdout
    );
    let after = sim.run(&["errors", "1"]).ok();
    assert!(after.stdout.starts_with("node 1 (EPOS2 24/5): no errors logged in 0x1003"), "{}", after.stdout);
}

/// One code, one meaning: `drive status` names each entry of the history as `errors` does
/// (for the faulted drive, CiA 402's "DC link under-voltage", not CiA 301's class).
#[test]
fn drive_status_and_errors_give_a_code_the_same_meaning() {
    let sim = Sim::new();
    sim.run(&["sdo", "write", "1", "5FFE", "1", "--type", "u16"]).ok();
    let errors = sim.run(&["errors", "1", "--format", "json"]).ok().json();
    let status = sim.run(&["drive", "status", "1", "--format", "json"]).ok().json();
    let meanings = |entries: &serde_json::Value| -> Vec<String> {
        entries.as_array().unwrap().iter().map(|e| e["meaning"].as_str().unwrap().to_string()).collect()
    };
    assert_eq!(meanings(&status["errors"]), meanings(&errors["entries"]), "{status}\n{errors}");
    assert_eq!(meanings(&status["errors"]), ["DC link under-voltage"]);
}

#[test]
fn a_node_without_a_history_says_so() {
    let sim = Sim::new();
    let run = sim.run(&["errors", "5"]).ok();
    assert_eq!(run.stdout.trim(), "node 5 (C01) keeps no error history (it has no object 0x1003); error register 0x00");
    assert_eq!(sim.run(&["errors", "5", "--format", "json"]).ok().json()["kept"], false);
    let clear = sim.run(&["errors", "5", "--clear"]);
    assert_eq!(clear.code, 4, "{}", clear.stderr);
    assert!(
        clear.stderr.contains("node 5 keeps no error history (it has no object 0x1003): there is nothing to clear"),
        "{}",
        clear.stderr
    );
}
