//! `canctl network dump|check|apply` against the simulated network: a machine read into a
//! CiA 306-3 project checks clean against itself, a changed object is named with exit 6,
//! the example project provisions the sim from factory state (node-ids over LSS included)
//! and a second run writes nothing; the JUnit report is read by an independent parser
//! (junitparser from PyPI, tests/interop/requirements.txt).

use crate::common;

use common::{Run, Sim};
use serde_json::Value as J;
use std::path::{Path, PathBuf};

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/sim-machine")
}

pub(crate) fn reset(sim: &Sim, profile: &str, unconfigured: &str) {
    sim.run(&["sim", "reset", "--profile", profile, "--unconfigured", unconfigured]).ok();
}

/// A sim with every device numbered (no LSS device waiting), dumped into `dir`.
pub(crate) fn dumped(sim: &Sim) -> PathBuf {
    reset(sim, "instant", "0");
    let dir = sim.path("machine");
    let run = sim.run(&["network", "dump", dir.to_str().unwrap(), "--bit-rate", "500k", "--format", "json"]).ok();
    let nodes: Vec<u64> = run.json()["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect();
    assert_eq!(nodes, [1, 5, 10, 32], "{}", run.stdout);
    dir
}

pub(crate) fn check(sim: &Sim, project: &Path, format: &str) -> Run {
    sim.run(&["network", "check", project.to_str().unwrap(), "--format", format])
}

#[test]
fn dump_then_check_on_the_same_network_reports_no_difference() {
    let sim = Sim::new();
    let dir = dumped(&sim);
    let cpj = std::fs::read_to_string(dir.join("nodelist.cpj")).unwrap();
    assert!(cpj.starts_with("[Topology]\r\nNetName=canctl network\r\nNodes=0x04\r\n"), "{cpj}");
    assert!(cpj.contains("Node5Present=0x01\r\nNode5Name=C01\r\nNode5DCFName=node5.dcf\r\n"), "{cpj}");
    let dcf = std::fs::read_to_string(dir.join("node5.dcf")).unwrap();
    assert!(
        dcf.contains("[DeviceComissioning]\nNodeID=5\nNodeName=C01\nBaudrate=500\nLSS_SerialNumber=0x09501234\n"),
        "{dcf}"
    );

    let run = check(&sim, &dir, "json");
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let report = run.json();
    assert_eq!(report["ok"], true);
    for node in report["nodes"].as_array().unwrap() {
        let checks: Vec<&str> =
            node["checks"].as_array().unwrap().iter().map(|c| c["check"].as_str().unwrap()).collect();
        assert_eq!(checks, ["present", "identity", "objects"], "{node}");
    }
}

#[test]
fn a_changed_object_fails_the_check_with_exit_6_naming_it() {
    let sim = Sim::new();
    let dir = dumped(&sim);
    sim.run(&["sdo", "write", "5", "0x1017", "250", "--type", "u16"]).ok();

    let run = check(&sim, &dir, "human");
    assert_eq!(run.code, 6, "{}\n{}", run.stdout, run.stderr);
    let line = run.stdout.lines().find(|l| l.contains("DIFFERS")).unwrap_or_else(|| panic!("{}", run.stdout));
    assert!(line.contains("0x1017:0") && line.contains("0xFA on the node, 0x28 in the file"), "{line}");
    assert_eq!(run.stdout.matches("DIFFERS").count(), 1, "{}", run.stdout);

    let report = check(&sim, &dir, "json").json();
    let node5 = report["nodes"].as_array().unwrap().iter().find(|n| n["node"] == 5).unwrap();
    let objects = node5["checks"].as_array().unwrap().iter().find(|c| c["check"] == "objects").unwrap();
    assert_eq!(objects["ok"], false);
    assert_eq!(objects["differences"][0]["object"], "0x1017:0");
    assert_eq!(objects["differences"][0]["device"], "0xFA");
}

/// An unlisted node fails the check; devices waiting for a node-id are counted and said,
/// but are no difference (they have no node-id, so no place in a project; a listed device
/// that lost its id fails its own `present` check).
#[test]
fn an_unlisted_node_fails_the_check_and_devices_without_a_node_id_do_not() {
    let sim = Sim::new();
    let dir = dumped(&sim);
    let cpj = std::fs::read_to_string(dir.join("nodelist.cpj")).unwrap();
    let cpj = cpj.replace("Nodes=0x04", "Nodes=0x03").replace("Node10Present=0x01", "Node10Present=0x00");
    std::fs::write(dir.join("nodelist.cpj"), cpj).unwrap();
    reset(&sim, "instant", "2");
    let run = check(&sim, &dir, "json");
    assert_eq!(run.code, 6, "{}\n{}", run.stdout, run.stderr);
    let report = run.json();
    assert_eq!(report["unlisted"][0]["node"], 10, "{report}");
    assert_eq!(report["unconfigured"], 2, "{report}");
    assert!(report["nodes"].as_array().unwrap().iter().all(|n| n["checks"]
        .as_array()
        .unwrap()
        .iter()
        .all(|c| c["ok"] == true)));
    // apply cannot make node 10 leave: it does not say the network matches, and fails alike.
    let apply = sim.run(&["network", "apply", dir.to_str().unwrap(), "--assign"]);
    assert_eq!(apply.code, 6, "{}\n{}", apply.stdout, apply.stderr);
    assert!(!apply.stderr.contains("already matches"), "{}", apply.stderr);
    assert!(apply.stderr.contains("node(s) 10 answer but are not in the project"), "{}", apply.stderr);
}

/// Right after `network dump` on the default sim (three devices without a node-id), check
/// and apply agree: the network matches the project (exit 0 both), and both say the
/// devices waiting for a node-id are not in it.
#[test]
fn check_and_apply_agree_right_after_a_dump_of_the_default_sim() {
    let sim = Sim::new();
    let dir = sim.path("machine");
    sim.run(&["network", "dump", dir.to_str().unwrap()]).ok();
    let run = check(&sim, &dir, "human");
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert!(!run.stdout.contains("DIFFERS"), "{}", run.stdout);
    assert!(run.stderr.contains("3 device(s) without a node-id"), "{}", run.stderr);
    let junit = check(&sim, &dir, "junit").ok();
    assert!(!junit.stdout.contains("<failure"), "{}", junit.stdout);
    let apply = sim.run(&["network", "apply", dir.to_str().unwrap(), "--assign"]);
    assert_eq!(apply.code, 0, "{}", apply.stderr);
    assert!(apply.stderr.contains("already matches"), "{}", apply.stderr);
}

#[test]
fn a_dcf_made_for_another_node_id_is_refused() {
    let sim = Sim::new();
    let dir = dumped(&sim);
    let cpj = std::fs::read_to_string(dir.join("nodelist.cpj")).unwrap();
    std::fs::write(dir.join("nodelist.cpj"), cpj.replace("Node5DCFName=node5.dcf", "Node5DCFName=node10.dcf")).unwrap();
    let run = check(&sim, &dir, "human");
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("node10.dcf is for node-id 10 ([DeviceComissioning] NodeID), but"), "{}", run.stderr);
}

#[test]
fn a_listed_node_that_does_not_answer_fails_present() {
    let sim = Sim::new();
    let dir = dumped(&sim);
    let cpj = std::fs::read_to_string(dir.join("nodelist.cpj")).unwrap();
    std::fs::write(
        dir.join("nodelist.cpj"),
        cpj.replace("Nodes=0x04", "Nodes=0x05") + "Node40Present=0x01\r\nNode40Name=ghost\r\n",
    )
    .unwrap();
    let run = check(&sim, &dir, "human");
    assert_eq!(run.code, 6, "{}\n{}", run.stdout, run.stderr);
    let line = run.stdout.lines().find(|l| l.contains("ghost")).unwrap();
    assert!(line.contains("present") && line.contains("DIFFERS") && line.contains("did not answer"), "{line}");
}

/// The example project from factory state: every listed node-id given over LSS, only what
/// differs written, and a second run that writes nothing.
#[test]
fn the_example_project_provisions_the_sim_and_a_second_run_writes_nothing() {
    let sim = Sim::new();
    reset(&sim, "typical", "5");
    let project = example();
    let project = project.to_str().unwrap();

    let refused = sim.run(&["network", "apply", project]);
    assert_eq!(refused.code, 3, "{}\n{}", refused.stdout, refused.stderr);
    assert!(refused.stderr.contains("--assign"), "{}", refused.stderr);
    // Each absent node's row says how to give it its node-id, in the table and in JSON.
    let remedy = "did not answer; --assign gives it its node-id over LSS (";
    assert_eq!(refused.stdout.lines().filter(|l| l.contains(remedy)).count(), 5, "{}", refused.stdout);
    let rows = sim.run(&["network", "apply", project, "--format", "json"]).json();
    let results: Vec<&str> = rows["nodes"].as_array().unwrap().iter().filter_map(|n| n["result"].as_str()).collect();
    assert_eq!(results.iter().filter(|r| r.contains(remedy)).count(), 5, "{rows}");

    let first = sim.run(&["network", "apply", project, "--assign", "--format", "json"]).ok().json();
    let assigned: Vec<u64> = first["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|n| !n["assigned"].is_null())
        .map(|n| n["node"].as_u64().unwrap())
        .collect();
    assert_eq!(assigned, [20, 21, 22, 23, 24], "{first}");
    assert!(first["written"].as_u64().unwrap() > 0, "{first}");
    assert!(first["nodes"].as_array().unwrap().iter().all(|n| n["ok"] == true), "{first}");

    let second = sim.run(&["network", "apply", project, "--assign"]).ok();
    assert!(second.stderr.contains("0 objects written"), "{}", second.stderr);
    assert!(second.stdout.lines().skip(1).all(|l| l.contains("up to date: nothing written")), "{}", second.stdout);
    let json = sim.run(&["network", "apply", project, "--format", "json"]).ok().json();
    assert_eq!(json["written"], 0);

    let run = check(&sim, Path::new(project), "junit");
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert_eq!(junit_counts(&run.stdout), Some((9 * 3 + 2, 0)));
}

#[test]
fn check_junit_is_read_by_an_independent_parser_and_names_the_failure() {
    let sim = Sim::new();
    let dir = dumped(&sim);
    sim.run(&["sdo", "write", "10", "0x1017", "300", "--type", "u16"]).ok();
    let run = check(&sim, &dir, "junit");
    assert_eq!(run.code, 6, "{}\n{}", run.stdout, run.stderr);
    assert!(run.stdout.starts_with("<?xml"), "{}", run.stdout);
    let Some(parsed) = junitparser(&run.stdout) else { return };
    assert_eq!(parsed["tests"], 4 * 3 + 2, "{parsed}");
    assert_eq!(parsed["failures"], 1, "{parsed}");
    let failed = parsed["failed"].as_array().unwrap();
    assert_eq!(failed.len(), 1, "{parsed}");
    assert_eq!(failed[0]["classname"], "node 10 (CAN-2057C)");
    assert_eq!(failed[0]["name"], "objects");
    assert!(failed[0]["text"].as_str().unwrap().contains("0x1017:0"), "{parsed}");
}

#[test]
fn other_commands_refuse_junit() {
    let sim = Sim::new();
    for args in [&["scan"][..], &["network", "apply", "x.cpj"], &["sdo", "read", "5", "0x1017"]] {
        let mut all = args.to_vec();
        all.extend(["--format", "junit"]);
        let run = sim.run(&all);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains("--format junit is for commands that check things"), "{}", run.stderr);
    }
}

#[test]
fn a_project_that_cannot_be_read_is_named_with_its_line() {
    let sim = Sim::new();
    let file = sim.path("bad.cpj");
    std::fs::write(&file, "[Topology]\r\nNodes=1\r\nNode1Present=maybe\r\n").unwrap();
    let run = sim.run(&["network", "check", file.to_str().unwrap()]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("bad.cpj:3: Node1Present=maybe must be 0x01"), "{}", run.stderr);
}

/// (tests, failures) from the JUnit XML's `<testsuite>` element, read by hand.
fn junit_counts(xml: &str) -> Option<(u64, u64)> {
    let suite = xml.lines().find(|l| l.trim_start().starts_with("<testsuite "))?;
    let attr = |name: &str| -> Option<u64> {
        let at = suite.find(&format!(" {name}=\""))? + name.len() + 3;
        suite[at..].split('"').next()?.parse().ok()
    };
    Some((attr("tests")?, attr("failures")?))
}

/// The report as junitparser reads it: totals and the failed cases; `None` (after saying
/// so) without python3 or junitparser, unless CANCTL_REQUIRE_PEERS is set.
fn junitparser(xml: &str) -> Option<J> {
    use std::io::Write;
    let required = std::env::var_os("CANCTL_REQUIRE_PEERS").is_some();
    let script = r#"
import json, sys
from junitparser import JUnitXml, Failure
xml = JUnitXml.fromstring(sys.stdin.read())
tests = failures = 0
failed = []
for suite in xml:
    tests += suite.tests
    failures += suite.failures
    for case in suite:
        for r in case.result:
            if isinstance(r, Failure):
                failed.append({"classname": case.classname, "name": case.name, "message": r.message, "text": r.text})
print(json.dumps({"tests": tests, "failures": failures, "failed": failed}))
"#;
    let child = std::process::Command::new("python3")
        .args(["-c", script])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) if !required => {
            common::skipped(&format!("no python3 ({e}); CI sets CANCTL_REQUIRE_PEERS=1"));
            return None;
        }
        Err(e) => panic!("python3: {e}"),
    };
    child.stdin.take().unwrap().write_all(xml.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        if !required && stderr.contains("No module named 'junitparser'") {
            common::skipped("python3 has no junitparser (pip install -r tests/interop/requirements.txt)");
            return None;
        }
        panic!("junitparser could not read the report: {stderr}\n{xml}");
    }
    Some(serde_json::from_slice(&out.stdout).unwrap())
}

/// The README's CI job, its `canctl` steps run as written on the sim it names.
#[test]
fn the_readme_ci_job_provisions_the_sim_and_its_junit_report_passes() {
    let readme = include_str!("../../README.md");
    let job = &readme[readme.find("```yaml\njobs:\n  provision:").expect("the CI job in README")..];
    let steps: Vec<&str> = job
        .lines()
        .take_while(|l| *l != "```")
        .filter_map(|l| l.trim_start().strip_prefix("- run: "))
        .filter(|cmd| cmd.starts_with("canctl "))
        .collect();
    assert_eq!(steps.len(), 2, "{steps:?}");
    let sim = Sim::new();
    reset(&sim, "typical", "5");
    let dir = sim.path("ci");
    std::fs::create_dir_all(&dir).unwrap();
    std::os::unix::fs::symlink(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"), dir.join("examples")).unwrap();
    let path =
        format!("{}:{}", common::canctl_bin().parent().unwrap().display(), std::env::var("PATH").unwrap_or_default());
    for step in &steps {
        // The sim's own settings (a generous answer timeout) and state file.
        let out = std::process::Command::new("bash")
            .arg("-c")
            .arg(step)
            .current_dir(&dir)
            .env("PATH", &path)
            .env("CANCTL_BUS", sim.bus())
            .env("XDG_CONFIG_HOME", sim.path(""))
            .env("XDG_CACHE_HOME", sim.path(""))
            .stdin(std::process::Stdio::null())
            .output()
            .unwrap();
        let run = common::finish(out);
        assert_eq!(run.code, 0, "{step}\n{}\n{}", run.stdout, run.stderr);
    }
    let xml = std::fs::read_to_string(dir.join("network-check.xml")).unwrap();
    assert_eq!(junit_counts(&xml), Some((9 * 3 + 2, 0)), "{xml}");
    if let Some(parsed) = junitparser(&xml) {
        assert_eq!((parsed["tests"].as_u64(), parsed["failures"].as_u64()), (Some(29), Some(0)), "{parsed}");
    }
}

/// Node by node or all at once, the same objects are written to the same nodes, and the
/// check passes either way.
#[test]
fn parallel_and_sequential_apply_write_the_same() {
    let project = example();
    let project = project.to_str().unwrap();
    let mut reports = Vec::new();
    for jobs in ["1", "8"] {
        let sim = Sim::new();
        reset(&sim, "typical", "5");
        let report =
            sim.run(&["network", "apply", project, "--assign", "--jobs", jobs, "--format", "json"]).ok().json();
        let rows: Vec<(J, J, J)> = report["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| (n["node"].clone(), n["written"].clone(), n["result"].clone()))
            .collect();
        reports.push(rows);
        let checked = sim.run(&["network", "check", project, "--jobs", jobs, "--format", "json"]);
        assert_eq!(checked.code, 0, "--jobs {jobs}: {}", checked.stdout);
    }
    assert_eq!(reports[0], reports[1]);
    assert_eq!(reports[0].len(), 9);
}

/// A node that refuses its configuration fails alone: the others are configured, and the
/// exit code is the refusal's.
#[test]
fn one_node_refusing_does_not_stop_the_others() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--profile", "instant", "--unconfigured", "5", "--fault", "10:abort=0x08000020@10+"])
        .ok();
    let run = sim.run(&["network", "apply", example().to_str().unwrap(), "--assign", "--format", "json"]);
    assert_eq!(run.code, 4, "{}\n{}", run.stdout, run.stderr);
    let report = run.json();
    for n in report["nodes"].as_array().unwrap() {
        if n["node"] == 10 {
            assert_eq!(n["ok"], false, "{n}");
            assert!(n["result"].as_str().unwrap().starts_with("failed: node 10: SDO abort 0x08000020"), "{n}");
        } else {
            assert_eq!(n["ok"], true, "{n}");
        }
    }
    assert_eq!(report["ok"], false);
}

/// Through a maxon EPOS2 as RS232-to-CAN gateway (the sim's device side on a pty): node-ids
/// over LSS by SendLSSFrame/ReadLSSFrame, objects by ReadObject/WriteObject, and the
/// network checks clean afterwards.
#[test]
fn apply_assign_and_check_through_the_epos2_gateway() {
    let sim = Sim::new();
    reset(&sim, "instant", "5");
    let gateway = common::DeviceSide::start(&sim, "--epos2-rs232", &[]);
    let project = example();
    let project = project.to_str().unwrap();
    let applied = gateway.run(&["network", "apply", project, "--assign", "--format", "json"]).ok().json();
    let assigned = applied["nodes"].as_array().unwrap().iter().filter(|n| !n["assigned"].is_null()).count();
    assert_eq!(assigned, 5, "{applied}");
    assert!(applied["written"].as_u64().unwrap() > 0, "{applied}");
    let run = gateway.run(&["network", "check", project, "--format", "junit"]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert_eq!(junit_counts(&run.stdout), Some((9 * 3 + 2, 0)));
}

/// With --reset the nodes written to are reset and waited for; what was stored is what
/// they come back with.
#[test]
fn reset_after_apply_keeps_what_was_stored() {
    let sim = Sim::new();
    reset(&sim, "instant", "5");
    let project = example();
    let project = project.to_str().unwrap();
    let report = sim.run(&["network", "apply", project, "--assign", "--reset", "--format", "json"]).ok().json();
    for n in report["nodes"].as_array().unwrap() {
        assert!(n["result"].as_str().unwrap().ends_with(", stored, reset, booted"), "{n}");
    }
    let run = check(&sim, Path::new(project), "human");
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
}

/// --state: every listed node must be in that NMT state, learned from its heartbeat or by
/// node guarding (the stepper has no heartbeat).
#[test]
fn check_state_wants_every_node_in_that_nmt_state() {
    let sim = Sim::new();
    let dir = dumped(&sim);
    let dir = dir.to_str().unwrap();
    let run = sim.run(&["network", "check", dir, "--state", "operational", "--format", "json"]);
    assert_eq!(run.code, 6, "{}", run.stdout);
    let states = |report: &J| -> Vec<(u64, bool)> {
        report["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| {
                let c = n["checks"].as_array().unwrap().iter().find(|c| c["check"] == "state").unwrap();
                (n["node"].as_u64().unwrap(), c["ok"].as_bool().unwrap())
            })
            .collect()
    };
    assert_eq!(states(&run.json()), [(1, false), (5, false), (10, false), (32, false)]);
    sim.run(&["nmt", "start", "all"]).ok();
    let run = sim.run(&["network", "check", dir, "--state", "operational", "--format", "json"]);
    assert_eq!(run.code, 0, "{}", run.stdout);
    assert_eq!(states(&run.json()), [(1, true), (5, true), (10, true), (32, true)]);
}

// ---------------------------------------------------------------------------------------
// network apply interrupted: each node stops at its next safe point (between two SDO
// transfers; a PDO change under way rolled back), and the report says per node what was
// done and the state it is left in. `common::interrupted` with K:SIG runs the test build of
// canctl (tests/seams/canctl.rs), which signals itself right after its K-th confirmed SDO
// write: an exact point, no timing.

fn tpdo1_of_the_drive(sim: &Sim) -> Vec<String> {
    ["0x1800:1", "0x1A00:0", "0x1A00:1", "0x1A00:2"]
        .iter()
        .map(|obj| sim.run(&["sdo", "read", "1", obj]).ok().stdout)
        .collect()
}

fn interrupted_apply(sim: &Sim, jobs: &str, signal: &str) -> Run {
    let project = example().join("nodelist.cpj");
    let mut c = common::interrupted(
        sim.command(&["network", "apply", project.to_str().unwrap(), "--jobs", jobs, "--format", "json"]),
        signal,
    );
    common::finish(c.output().unwrap())
}

#[test]
fn an_interrupted_apply_stops_each_node_at_a_safe_point_and_says_where() {
    let sim = Sim::new();
    reset(&sim, "instant", "0");
    let factory = tpdo1_of_the_drive(&sim);
    // One node at a time: the drive (node 1) is stopped in the middle of its TPDO1 change.
    let run = interrupted_apply(&sim, "1", "5:INT");
    assert_eq!(run.code, 130, "{}\n{}", run.stdout, run.stderr);
    let report = run.json();
    let rows: Vec<(u64, String)> = report["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| (n["node"].as_u64().unwrap(), n["result"].as_str().unwrap().to_string()))
        .collect();
    let result = |node: u64| rows.iter().find(|(n, _)| *n == node).map(|(_, r)| r.as_str()).unwrap();
    assert!(
        result(1).starts_with("interrupted: TPDO1 (0x1800, 0x1A00): its change was under way; rolled back"),
        "{rows:?}"
    );
    assert!(result(1).contains("not stored (canctl store 1 keeps what was written)"), "{rows:?}");
    for node in [5, 10, 32] {
        assert_eq!(result(node), "not done: interrupted before this node was begun", "{rows:?}");
    }
    assert_eq!(tpdo1_of_the_drive(&sim), factory, "the drive's TPDO1 is put back as it was");

    // Several nodes at once: every node under way stops (or had finished), none is begun
    // after the signal, and the same command then finishes the job.
    reset(&sim, "instant", "5");
    let run = interrupted_apply(&sim, "4", "5:TERM");
    assert_eq!(run.code, 130, "{}\n{}", run.stdout, run.stderr);
    let report = run.json();
    let stopped = report["nodes"].as_array().unwrap().iter().filter(|n| {
        let r = n["result"].as_str().unwrap();
        assert!(
            r.starts_with("interrupted: ")
                || r.contains("written, verified, stored")
                || r.starts_with("failed: node 2"),
            "{r}"
        );
        r.starts_with("interrupted: ")
    });
    assert!(stopped.count() >= 1, "{report}");
    let project = example().join("nodelist.cpj");
    sim.run(&["network", "apply", project.to_str().unwrap(), "--assign"]).ok();
    assert_eq!(check(&sim, &project, "human").code, 0);
}

// ---------------------------------------------------------------------------------------
// Progress: one line per node under way when stderr is a terminal; none otherwise.

/// `args` run with stderr on a pseudo-terminal: its exit code and what the terminal showed.
fn on_a_terminal(sim: &Sim, args: &[&str]) -> (i32, String) {
    use std::io::Read;
    let pty = nix::pty::openpty(None, None).unwrap();
    let mut c = sim.command(args);
    c.stderr(std::process::Stdio::from(pty.slave));
    c.stdout(std::process::Stdio::piped());
    let child = c.spawn().unwrap();
    // The command holds the terminal's other side too: only canctl must, for EIO at its end.
    drop(c);
    let mut master = std::fs::File::from(pty.master);
    let reader = std::thread::spawn(move || {
        let mut shown = Vec::new();
        // Ends with EIO once canctl, the only holder of the terminal's other side, exits.
        let _ = master.read_to_end(&mut shown);
        String::from_utf8_lossy(&shown).into_owned()
    });
    let out = child.wait_with_output().unwrap();
    (out.status.code().unwrap_or(-1), reader.join().unwrap())
}

#[test]
fn apply_shows_one_progress_line_per_node_on_a_terminal_only() {
    let sim = Sim::new();
    reset(&sim, "instant", "0");
    let project = example().join("nodelist.cpj");
    let project = project.to_str().unwrap();
    // Nodes 20 to 24 wait for --assign (not given): their rows fail, exit 3.
    let (code, shown) = on_a_terminal(&sim, &["network", "apply", project, "--jobs", "4"]);
    assert_eq!(code, 3, "{shown}");
    for node in ["node 1 ", "node 5 ", "node 10 ", "node 32 "] {
        let line = shown
            .split(['\r', '\n'])
            .find(|l| l.contains(node) && l.contains("object(s) written, verified, stored"))
            .unwrap_or_else(|| panic!("no finished line for {node}: {shown:?}"));
        assert!(!line.is_empty());
    }
    assert!(shown.contains(" read(s), "), "{shown:?}");

    reset(&sim, "instant", "0");
    let run = sim.run(&["network", "apply", project, "--jobs", "4"]);
    assert_eq!(run.code, 3);
    assert!(!run.stderr.contains("read(s)") && !run.stderr.contains("applying"), "{}", run.stderr);
    reset(&sim, "instant", "0");
    let (_, quiet) = on_a_terminal(&sim, &["-q", "network", "apply", project, "--jobs", "4"]);
    assert!(!quiet.contains("read(s)") && !quiet.contains("applying"), "{quiet:?}");
}

/// The summary under an interrupted apply counts the table's own rows: a node stopped
/// before anything was written is not "stopped part-way", a node given its id but not
/// configured says so, and the objects written are counted on the nodes written to.
#[test]
fn an_interrupted_apply_summary_agrees_with_its_table() {
    let sim = Sim::new();
    reset(&sim, "instant", "5");
    let project = example().join("nodelist.cpj");
    let mut c = common::interrupted(
        sim.command(&["network", "apply", project.to_str().unwrap(), "--assign", "--jobs", "4"]),
        "5:INT",
    );
    let run = common::finish(c.output().unwrap());
    assert_eq!(run.code, 130, "{}\n{}", run.stdout, run.stderr);
    // node  name  written  result: the columns start where their headings do.
    let header = run.stdout.lines().next().unwrap();
    let (w, r) = (header.find("written").unwrap(), header.find("result").unwrap());
    let rows: Vec<(usize, String)> = run
        .stdout
        .lines()
        .skip(1)
        .map(|l| (l[w..r].trim().parse().unwrap(), l.get(r..).unwrap_or("").trim().to_string()))
        .collect();
    assert_eq!(rows.len(), 9, "{}", run.stdout);
    assert!(rows.iter().all(|(_, r)| !r.is_empty()), "every node says what happened:\n{}", run.stdout);
    let count = |f: &dyn Fn(&(usize, String)) -> bool| rows.iter().filter(|r| f(r)).count();
    let part_way = count(&|(w, r)| r.contains("interrupted") && !r.contains("nothing was written") && *w > 0);
    let unchanged = count(&|(_, r)| r.contains("interrupted") && r.contains("nothing was written"));
    let not_begun = count(&|(_, r)| r.contains("not begun"));
    let written_to = count(&|(w, _)| *w > 0);
    let written: usize = rows.iter().map(|(w, _)| w).sum();
    let notes = &run.stderr;
    let said = |n: usize, what: &str| notes.contains(&format!("{n} node(s) {what}"));
    assert!(
        part_way == 0 && !notes.contains("stopped part-way") || said(part_way, "stopped part-way"),
        "{part_way} part-way:\n{}{notes}",
        run.stdout
    );
    assert!(unchanged == 0 || said(unchanged, "stopped before anything was written"), "{}{notes}", run.stdout);
    assert!(not_begun == 0 || said(not_begun, "not begun"), "{}{notes}", run.stdout);
    assert!(
        notes.contains(&format!("{written} object(s) written on {written_to} of 9 node(s)")),
        "{}{notes}",
        run.stdout
    );
}
