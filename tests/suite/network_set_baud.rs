//! `canctl network set-baud`: the sim's bus follows an LSS switch of every node's bit rate;
//! its stepper (SERS: bit rate from DIP switches) refuses "configure bit timing", the others
//! take it; with a project its nodes are expected and its DCFs updated; through an EPOS2
//! gateway the switch is said to be unchecked; a project naming a file outside its folder
//! (by name or by a link) is refused before anything is sent.

use super::network::{check, dumped, reset};
use crate::common;
use common::{Run, Sim};
use std::path::Path;

fn nodes_of(scan: &Run) -> Vec<u64> {
    scan.json()["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect()
}

fn set_baud_rows(run: &Run) -> Vec<(u64, Option<bool>)> {
    run.json()["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| (n["node"].as_u64().unwrap(), n["after"].as_bool()))
        .collect()
}

#[test]
fn set_baud_is_a_broadcast_only_with_global() {
    let sim = Sim::new();
    reset(&sim, "instant", "0");
    let run = sim.run(&["network", "set-baud", "250k"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("a broadcast): add --global"), "{}", run.stderr);
    let run = sim.run(&["network", "set-baud", "auto", "--global"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    // Nothing was sent: every node still answers at the old rate.
    assert_eq!(nodes_of(&sim.run(&["scan", "--format", "json"]).ok()), [1, 5, 10, 32]);
}

#[test]
fn set_baud_switches_every_node_and_finds_them_at_the_new_rate() {
    let sim = Sim::new();
    // The stepper, which cannot change its rate over LSS, is switched off (mute).
    sim.run(&["sim", "reset", "--profile", "typical", "--unconfigured", "2", "--fault", "stepper:mute"]).ok();
    let run = sim.run(&["network", "set-baud", "250k", "--global", "--store", "--format", "json"]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let report = run.json();
    assert_eq!(report["configured"]["confirmed"], 5, "{report}");
    assert_eq!(report["stored"]["confirmed"], 5, "{report}");
    assert_eq!(report["bus_followed"], true);
    assert_eq!(report["unconfigured_after"], 2, "the devices without a node-id followed too");
    assert_eq!(set_baud_rows(&run), [(1, Some(true)), (5, Some(true)), (10, Some(true))]);
    // The sim keeps the new rate: the next invocation finds them there.
    assert_eq!(nodes_of(&sim.run(&["scan", "--format", "json"]).ok()), [1, 5, 10]);
    let human = sim.run(&["network", "set-baud", "500k", "--global"]).ok();
    assert!(human.stdout.contains("configure bit timing 500k: 5 device(s) confirmed\n"), "{}", human.stdout);
    assert!(human.stdout.contains("sim switched with the devices"), "{}", human.stdout);
}

#[test]
fn a_device_refusing_the_rate_stops_the_switch_and_force_leaves_it_behind() {
    let sim = Sim::new();
    reset(&sim, "typical", "0");
    let run = sim.run(&["network", "set-baud", "250k", "--global", "--format", "json"]);
    assert_eq!(run.code, 4, "{}\n{}", run.stdout, run.stderr);
    assert!(run.stderr.contains("LSS configure bit timing: error 1: bit timing not supported"), "{}", run.stderr);
    let report = run.json();
    assert_eq!(report["activated"], false);
    // Why, with the way past it, in canctl's words.
    assert_eq!(
        report["not_activated"], "1 device(s) refused 250k (--force switches the others and leaves them behind)",
        "{report}"
    );
    assert_eq!(report["configured"]["confirmed"], 3, "{report}");
    assert_eq!(report["configured"]["refused"].as_array().unwrap().len(), 1, "{report}");
    // Nothing was activated: all four still answer at the old rate.
    assert_eq!(nodes_of(&sim.run(&["scan", "--format", "json"]).ok()), [1, 5, 10, 32]);

    let run = sim.run(&["network", "set-baud", "250k", "--global", "--force"]);
    assert_eq!(run.code, 6, "{}\n{}", run.stdout, run.stderr);
    let row = run.stdout.lines().find(|l| l.starts_with(" 32 ")).unwrap_or_else(|| panic!("{}", run.stdout));
    assert!(row.contains("did not follow: answered before the switch, not at 250k"), "{row}");
    assert!(run.stderr.contains("node(s) 32 did not follow the switch to 250k"), "{}", run.stderr);
    assert_eq!(nodes_of(&sim.run(&["scan", "--format", "json"]).ok()), [1, 5, 10]);
}

#[test]
fn set_baud_with_a_project_expects_its_nodes_and_updates_its_dcfs() {
    let sim = Sim::new();
    let dir = dumped(&sim);
    let before = std::fs::read_to_string(dir.join("node5.dcf")).unwrap();
    let run = sim.run(&[
        "network",
        "set-baud",
        "125k",
        dir.to_str().unwrap(),
        "--global",
        "--force",
        "--update-project",
        "--format",
        "json",
    ]);
    // The project lists the stepper, which stays at 500k.
    assert_eq!(run.code, 6, "{}\n{}", run.stdout, run.stderr);
    let report = run.json();
    assert!(report["expected_from"].as_str().unwrap().ends_with("nodelist.cpj"), "{report}");
    assert_eq!(set_baud_rows(&run), [(1, Some(true)), (5, Some(true)), (10, Some(true)), (32, Some(false))]);
    // Only the nodes heard at the new rate get it in their DCFs: the stepper's says 500k.
    assert_eq!(report["updated"].as_array().unwrap().len(), 3, "{report}");
    assert_eq!(report["dcfs_left"], serde_json::json!([32]), "{report}");
    let after = std::fs::read_to_string(dir.join("node5.dcf")).unwrap();
    assert_eq!(after, before.replace("\nBaudrate=500\n", "\nBaudrate=125\n"));
    let stepper = std::fs::read_to_string(dir.join("node32.dcf")).unwrap();
    assert!(stepper.contains("\nBaudrate=500\n"), "{stepper}");
    // --update-project needs a project.
    assert_eq!(sim.run(&["network", "set-baud", "125k", "--global", "--update-project"]).code, 2);
}

/// An EPOS2 gateway does not change its own CAN rate with the devices: the switch is sent
/// and said to be unchecked, with what to do, never reported as followed.
#[test]
fn set_baud_through_the_epos2_gateway_says_the_gateway_must_be_switched() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--profile", "instant", "--unconfigured", "0", "--fault", "stepper:mute"]).ok();
    let gateway = common::DeviceSide::start(&sim, "--epos2-rs232", &[]);
    let run = gateway.run(&["network", "set-baud", "250k", "--global", "--format", "json"]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let report = run.json();
    assert_eq!(report["activated"], true, "{report}");
    assert_eq!(report["bus_followed"], false, "{report}");
    assert!(report["link_to_switch"].as_str().unwrap().contains("lss set-baud 250k --node 0"), "{report}");
    assert_eq!(report["ok"], false, "{report}");
    assert!(set_baud_rows(&run).iter().all(|(_, after)| after.is_none()), "{report}");
    let human = gateway.run(&["network", "set-baud", "500k", "--global"]);
    assert!(human.stdout.contains("does not switch by itself, so nothing is checked yet"), "{}", human.stdout);
}

/// A project names files in its own folder: `Node5DCFName=../outside.dcf` is refused
/// (file:line, exit 2) before anything is sent, and the file beside the project is not
/// rewritten by --update-project.
#[test]
fn a_project_cannot_name_a_dcf_outside_its_folder() {
    let sim = Sim::new();
    let dir = dumped(&sim);
    let cpj = dir.join("nodelist.cpj");
    let text = std::fs::read_to_string(&cpj).unwrap();
    std::fs::write(&cpj, text.replace("Node5DCFName=node5.dcf", "Node5DCFName=../outside.dcf")).unwrap();
    let outside = dir.parent().unwrap().join("outside.dcf");
    std::fs::copy(dir.join("node5.dcf"), &outside).unwrap();
    let before = std::fs::read_to_string(&outside).unwrap();
    let project = dir.to_str().unwrap();
    let run = sim.run(&["network", "set-baud", "250k", project, "--global", "--force", "--update-project"]);
    assert_eq!(run.code, 2, "{}\n{}", run.stdout, run.stderr);
    let line = text.lines().position(|l| l == "Node5DCFName=node5.dcf").unwrap() + 1;
    assert!(run.stderr.contains(&format!("nodelist.cpj:{line}: Node5DCFName=../outside.dcf: ")), "{}", run.stderr);
    assert_eq!(std::fs::read_to_string(&outside).unwrap(), before);
    assert_eq!(nodes_of(&sim.run(&["scan", "--format", "json"]).ok()), [1, 5, 10, 32], "nothing was switched");
    for args in [["network", "check", project], ["network", "apply", project]] {
        assert_eq!(sim.run(&args).code, 2, "{args:?}");
    }
}

/// Nor through a symbolic link: with node5.dcf a link to ../outside5.dcf, check,
/// set-baud --update-project and dump --force refuse (exit 2, naming the link and where it
/// points) before anything is sent or written, and the file outside is left as it was. A
/// link inside the folder to a file inside it is fine.
#[cfg(unix)]
#[test]
fn a_project_file_linked_outside_its_folder_is_refused() {
    let sim = Sim::new();
    let dir = dumped(&sim);
    let link = dir.join("node5.dcf");
    let outside = dir.parent().unwrap().join("outside5.dcf");
    std::fs::rename(&link, &outside).unwrap();
    std::os::unix::fs::symlink("../outside5.dcf", &link).unwrap();
    let before = std::fs::read(&outside).unwrap();
    let said = format!("{} is a link to {}, outside", link.display(), outside.canonicalize().unwrap().display());
    let refused = |args: &[&str]| {
        let run = sim.run(args);
        assert_eq!(run.code, 2, "{args:?}\n{}\n{}", run.stdout, run.stderr);
        assert!(run.stderr.contains(&said), "{args:?}: {}", run.stderr);
    };
    let project = dir.to_str().unwrap();
    refused(&["network", "check", project]);
    refused(&["network", "set-baud", "250k", project, "--global", "--force", "--update-project"]);
    assert_eq!(nodes_of(&sim.run(&["scan", "--format", "json"]).ok()), [1, 5, 10, 32], "nothing was switched");
    refused(&["network", "dump", project, "--force"]);
    assert_eq!(std::fs::read(&outside).unwrap(), before, "the file outside is left as it was");
    assert_eq!(std::fs::read_link(&link).unwrap(), Path::new("../outside5.dcf"));

    // Inside the folder, a link is an ordinary file of the project.
    std::fs::rename(&outside, dir.join("real5.dcf")).unwrap();
    std::fs::remove_file(&link).unwrap();
    std::os::unix::fs::symlink("real5.dcf", &link).unwrap();
    let run = check(&sim, &dir, "human");
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
}
