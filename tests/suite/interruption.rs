//! Interrupted, terminated or killed at every write of a PDO remapping: `config apply`
//! leaves node 10's TPDO1 either with its old mapping intact or with the new one complete,
//! and its report says exactly what it wrote. SIGKILL cannot be caught: the next
//! `config diff` sees the half-done mapping and `config apply` finishes it.
//!
//! The device is the sim behind a simulated slcan adapter (`canctl sim --slcan`), a process
//! of its own that keeps what was written when canctl dies, as a real device does. The
//! point of interruption is exact without any timing: [`common::interrupted`] with `K:SIG`
//! runs the test build of canctl (tests/seams/canctl.rs), which sends itself SIG right
//! after the answer to its K-th SDO write.
//!
//! `cargo test --test suite interruption:: -- --nocapture` prints the table.

use crate::common;

use serde_json::Value;
use std::collections::BTreeMap;

/// The objects of TPDO1 the remapping touches.
const OBJECTS: [&str; 4] = ["0x1800:1", "0x1A00:0", "0x1A00:1", "0x1A00:2"];

/// Set `ParameterValue` of the DCF's sections `[SECTION]` to new values.
fn edit_dcf(text: &str, values: &[(&str, &str)]) -> String {
    let mut out = String::new();
    let mut section = String::new();
    for line in text.lines() {
        if line.starts_with('[') {
            section = line.trim_matches(['[', ']']).to_ascii_lowercase();
        }
        let key = line.split('=').next().unwrap_or("").trim().to_ascii_lowercase();
        match values.iter().find(|(s, _)| s.to_ascii_lowercase() == section) {
            Some((_, v)) if key == "parametervalue" => out.push_str(&format!("ParameterValue={v}")),
            _ => out.push_str(line),
        }
        out.push('\n');
    }
    out
}

fn read(dev: &common::DeviceSide, obj: &str) -> u64 {
    let r = dev.run(&["sdo", "read", "10", obj, "--type", if obj.ends_with(":0") { "u8" } else { "u32" }]).ok();
    r.stdout.trim().parse().unwrap_or_else(|_| panic!("{obj}: {}", r.stdout))
}

fn state(dev: &common::DeviceSide) -> BTreeMap<String, u64> {
    OBJECTS.iter().map(|o| (o.to_string(), read(dev, o))).collect()
}

/// What a report says was written, in order: (object, value), the rollback included.
fn writes_reported(report: &Value) -> Vec<(String, u64)> {
    report["objects"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["result"].as_str().unwrap().starts_with("written"))
        .map(|r| {
            let new = r["new"].as_str().unwrap();
            // Hex first then decimal read a decimal 10 as 16: the one reading tells them apart.
            let v = canctl::canopen::number::parse_number(new).unwrap_or_else(|| panic!("'{new}' is not a number"));
            (r["object"].as_str().unwrap().to_string(), v)
        })
        .collect()
}

fn describe(s: &BTreeMap<String, u64>, old: &BTreeMap<String, u64>, new: &BTreeMap<String, u64>) -> String {
    if s == old {
        "old mapping intact".into()
    } else if s == new {
        "new mapping complete".into()
    } else {
        let cob = s["0x1800:1"];
        format!(
            "half-done: COB-ID 0x{cob:X}{}, count {}",
            if cob & 0x8000_0000 != 0 { " (invalid)" } else { "" },
            s["0x1A00:0"]
        )
    }
}

struct Row {
    step: u32,
    write: String,
    signal: &'static str,
    said: String,
    held: String,
    code: String,
}

fn print_table(rows: &[Row]) {
    use std::io::Write;
    let mut out = String::new();
    out.push_str(&format!(
        "\n{:<4} {:<24} {:<7} {:<64} {:<44} {}\n",
        "step", "write k", "signal", "report", "device after", "exit"
    ));
    for r in rows {
        out.push_str(&format!(
            "{:<4} {:<24} {:<7} {:<64} {:<44} {}\n",
            r.step, r.write, r.signal, r.said, r.held, r.code
        ));
    }
    // On the real stdout: shown with --nocapture.
    let _ = std::io::stdout().lock().write_all(out.as_bytes());
}

#[cfg(unix)]
#[test]
fn a_pdo_remap_interrupted_at_every_step_is_rolled_back_or_complete() {
    let sim = common::Sim::new();
    let dev = common::DeviceSide::start(&sim, "--slcan", &[]);
    let old_dcf = sim.path("io.dcf");
    dev.run(&["config", "dump", "10", "--out", old_dcf.to_str().unwrap()]).ok();
    let text = std::fs::read_to_string(&old_dcf).unwrap();
    let new_dcf = sim.path("io-remapped.dcf");
    std::fs::write(
        &new_dcf,
        edit_dcf(&text, &[("1A00sub0", "2"), ("1A00sub1", "0x62000108"), ("1A00sub2", "0x62000208")]),
    )
    .unwrap();
    let old = state(&dev);
    assert_eq!(old["0x1800:1"], 0x18A);
    assert_eq!(old["0x1A00:0"], 1);

    // The plan, from a dry run: its writes are the steps.
    let plan =
        dev.run(&["config", "apply", "10", new_dcf.to_str().unwrap(), "--dry-run", "--format", "json"]).ok().json();
    let steps: Vec<String> = plan["objects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| format!("{} = {}", r["object"].as_str().unwrap(), r["new"].as_str().unwrap()))
        .collect();
    assert_eq!(steps.len(), 6, "{plan}");
    let mut new = old.clone();
    new.insert("0x1A00:0".into(), 2);
    new.insert("0x1A00:1".into(), 0x6200_0108);
    new.insert("0x1A00:2".into(), 0x6200_0208);

    let back_to_old = || {
        dev.run(&["config", "apply", "10", old_dcf.to_str().unwrap()]).ok();
        assert_eq!(state(&dev), old);
    };
    let mut rows = Vec::new();
    for k in 1..=steps.len() as u32 {
        for signal in ["INT", "TERM"] {
            back_to_old();
            let mut c = common::interrupted(
                dev.command(&["config", "apply", "10", new_dcf.to_str().unwrap(), "--format", "json"]),
                &format!("{k}:{signal}"),
            );
            let run = common::finish(c.output().unwrap());
            let report = run.json();
            let now = state(&dev);
            // The device holds exactly what the report says was written, in that order.
            let mut model = old.clone();
            let said = writes_reported(&report);
            for (obj, v) in &said {
                model.insert(obj.clone(), *v);
            }
            assert_eq!(now, model, "k={k} {signal}: the report's writes {said:?} do not make what the device holds");
            let last = k as usize == steps.len();
            if last {
                // The signal came after the last write: nothing left to stop.
                assert_eq!(run.code, 0, "{}", run.stderr);
                assert_eq!(now, new);
            } else {
                assert_eq!(run.code, 130, "k={k} {signal}: {}", run.stderr);
                assert_eq!(now, old, "k={k} {signal}: old mapping not intact");
                assert_eq!(report["interrupted"], true);
                assert!(run.stderr.contains("canctl: interrupted"), "{}", run.stderr);
                let done = said.len();
                let rollback = report["objects"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .filter(|r| r["result"] == "written (rollback)")
                    .count();
                assert_eq!(done - rollback, k as usize, "k={k}: {report}");
                assert_eq!(report["rolled_back"], serde_json::json!(["TPDO1 (0x1800, 0x1A00)"]), "{report}");
                assert_eq!(report["to_fix"], serde_json::json!([]));
                assert!(report["state"].as_str().unwrap().contains("is as it was"), "{report}");
            }
            let rollback: Vec<&str> = report["objects"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|r| r["result"] == "written (rollback)")
                .map(|r| r["object"].as_str().unwrap())
                .collect();
            rows.push(Row {
                step: k,
                write: steps[k as usize - 1].clone(),
                signal: if signal == "INT" { "SIGINT" } else { "SIGTERM" },
                said: if rollback.is_empty() {
                    format!("{} written, complete", said.len())
                } else {
                    format!("{k} written, rolled back {}", rollback.join(" "))
                },
                held: describe(&now, &old, &new),
                code: run.code.to_string(),
            });
        }
        // SIGKILL: no report, no rollback. The next diff sees it; the next apply finishes it.
        back_to_old();
        let mut c = common::interrupted(
            dev.command(&["config", "apply", "10", new_dcf.to_str().unwrap()]),
            &format!("{k}:KILL"),
        );
        let status = c.output().unwrap().status;
        use std::os::unix::process::ExitStatusExt;
        assert_eq!(status.signal(), Some(9), "k={k}: {status:?}");
        let killed = state(&dev);
        let diff = dev.run(&["config", "diff", "10", new_dcf.to_str().unwrap(), "--check", "--format", "json"]);
        let last = k as usize == steps.len();
        assert_eq!(diff.code, if last { 0 } else { 6 }, "k={k}: {}", diff.stdout);
        let repaired = dev.run(&["config", "apply", "10", new_dcf.to_str().unwrap()]).ok();
        assert_eq!(state(&dev), new, "k={k}: {}", repaired.stdout);
        dev.run(&["config", "diff", "10", new_dcf.to_str().unwrap(), "--check"]).ok();
        let differs = diff.json()["differences"].as_array().unwrap().len();
        rows.push(Row {
            step: k,
            write: steps[k as usize - 1].clone(),
            signal: "SIGKILL",
            said: if differs == 0 {
                "none; diff: 0 differ, apply: nothing to write".into()
            } else {
                format!("none; diff: {differs} differ, apply again: new mapping complete")
            },
            held: describe(&killed, &old, &new),
            code: "killed".into(),
        });
    }
    print_table(&rows);

    // The same in the human format: the report says what was written, what was put back
    // and what the device holds.
    back_to_old();
    let mut c = common::interrupted(dev.command(&["config", "apply", "10", new_dcf.to_str().unwrap()]), "3:TERM");
    let run = common::finish(c.output().unwrap());
    assert_eq!(run.code, 130);
    for said in [
        "interrupted after 3 write(s): written 0x1800:1, 0x1A00:0, 0x1A00:1; not written 0x1A00:2, 0x1A00:0, 0x1800:1",
        "TPDO1 (0x1800, 0x1A00): its change was under way; rolled back to its previous mapping and COB-ID",
        "node 10 is as it was before the run (the PDO that was being changed rolled back)",
    ] {
        assert!(run.stderr.contains(said), "missing '{said}' in\n{}", run.stderr);
    }
    assert!(run.stdout.contains("written (rollback)"), "{}", run.stdout);
}

/// A sim whose node 10 refuses every SDO answer from the 4th write of the remapping on,
/// with the files: (sim, io.dcf as it is, io-remapped.dcf).
fn refusing_after_three_writes() -> (common::Sim, std::path::PathBuf, std::path::PathBuf) {
    refusing("0x08000020", 4, "+")
}

/// A sim whose node 10 refuses (abort `code`) the remapping's `write`-th write, and every
/// answer after it with `then` = "+".
fn refusing(code: &str, write: usize, then: &str) -> (common::Sim, std::path::PathBuf, std::path::PathBuf) {
    let sim = common::Sim::new();
    let old_dcf = sim.path("io.dcf");
    sim.run(&["config", "dump", "10", "--out", old_dcf.to_str().unwrap()]).ok();
    let text = std::fs::read_to_string(&old_dcf).unwrap();
    let new_dcf = sim.path("io-remapped.dcf");
    let remapped = edit_dcf(&text, &[("1A00sub0", "2"), ("1A00sub1", "0x62000108"), ("1A00sub2", "0x62000208")]);
    std::fs::write(&new_dcf, remapped).unwrap();
    // The device's answers are counted per invocation: a dry run reads what the real run
    // reads, so the real run's 4th write is answer reads + 4.
    let dry = sim.run(&["-v", "config", "apply", "10", new_dcf.to_str().unwrap(), "--dry-run"]).ok();
    let reads = dry.stderr.lines().filter(|l| l.contains(" 58A ")).count();
    let fault = format!("10:abort={code}@{}{then}", reads + write);
    sim.run(&["sim", "reset", "--fault", &fault]).ok();
    (sim, old_dcf, new_dcf)
}

/// When putting the PDO back fails too (the device refuses from then on), the report names
/// the exact writes that would, with the old values; written as it says, they do.
#[test]
fn a_rollback_that_fails_names_the_writes_that_would_finish_it() {
    let (sim, old_dcf, new_dcf) = refusing_after_three_writes();
    let mut c = common::interrupted(
        sim.command(&["config", "apply", "10", new_dcf.to_str().unwrap(), "--format", "json"]),
        "3:TERM",
    );
    let run = common::finish(c.output().unwrap());
    assert_eq!(run.code, 130, "{}", run.stderr);
    let report = run.json();
    assert_eq!(report["rolled_back"], serde_json::json!([]), "{report}");
    let fixes: Vec<(String, String)> = report["to_fix"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| (f["object"].as_str().unwrap().to_string(), f["value"].as_str().unwrap().to_string()))
        .collect();
    let objects: Vec<&str> = fixes.iter().map(|(o, _)| o.as_str()).collect();
    assert_eq!(objects, ["0x1A00:1", "0x1A00:0", "0x1800:1"], "{report}");
    assert!(report["state"].as_str().unwrap().contains("a PDO is left unusable"), "{report}");

    // The fault gone (as a device that answers again), the writes named put it back.
    let state_file = sim.path("sim.json");
    let mut state: Value = serde_json::from_slice(&std::fs::read(&state_file).unwrap()).unwrap();
    state["config"]["faults"] = serde_json::json!([]);
    std::fs::write(&state_file, serde_json::to_vec(&state).unwrap()).unwrap();
    for (obj, value) in &fixes {
        let dtype = if obj.ends_with(":0") { "u8" } else { "u32" };
        sim.run(&["sdo", "write", "10", obj, value, "--type", dtype]).ok();
    }
    let diff = sim.run(&["config", "diff", "10", old_dcf.to_str().unwrap(), "--check", "--format", "json"]);
    assert_eq!(diff.code, 0, "the fixes did not bring the old mapping back: {}", diff.stdout);

    // The human report says the same, with the values.
    let (sim, _, new_dcf) = refusing_after_three_writes();
    let mut c = common::interrupted(sim.command(&["config", "apply", "10", new_dcf.to_str().unwrap()]), "3:INT");
    let human = common::finish(c.output().unwrap());
    assert_eq!(human.code, 130, "{}", human.stderr);
    let fixes: Vec<String> = fixes.iter().map(|(o, v)| format!("{o} = {v}")).collect();
    let said = format!("the rollback did not finish: to put the PDO back, write in this order {}", fixes.join(", "));
    assert!(human.stderr.contains(&said), "missing '{said}' in\n{}", human.stderr);
    assert!(human.stderr.contains("a PDO is left unusable"), "{}", human.stderr);
}

/// The drive's TPDO1 as `sdo read` shows it.
fn drive_mapping(sim: &common::Sim) -> Vec<String> {
    ["1A00:0", "1A00:1", "1A00:2", "1800:1", "1800:2", "1800:5"]
        .iter()
        .map(|o| sim.run(&["sdo", "read", "1", o]).ok().stdout.trim().to_string())
        .collect()
}

/// `stream-pdo --map` terminated (SIGTERM, as a CI job is cancelled) while it streams:
/// the original mapping and NMT state are put back, exit 130.
#[cfg(unix)]
#[test]
fn stream_pdo_map_terminated_puts_the_mapping_back() {
    let sim = common::Sim::new();
    let before = drive_mapping(&sim);
    let stream =
        sim.command(&["stream-pdo", "1", "--start", "--map", "6064:0,606C:0", "--event", "10", "--format", "csv"]);
    // The CSV header and a first record: the new mapping is in use.
    let r = common::signal_after_lines(stream, 2, nix::sys::signal::Signal::SIGTERM);
    assert!(r.stdout.contains("Position actual value"), "{}", r.stdout);
    assert_eq!(r.code, 130, "{}", r.stderr);
    assert_eq!(drive_mapping(&sim), before);
    assert!(sim.run(&["nmt", "state", "1"]).ok().stdout.contains("pre-operational"));
}

/// Interrupted or terminated in the middle of the remapping itself, after each of its
/// writes: the remapping is finished, nothing is streamed, and the mapping is put back.
#[cfg(unix)]
#[test]
fn stream_pdo_map_interrupted_while_remapping_puts_the_mapping_back() {
    let sim = common::Sim::new();
    let before = drive_mapping(&sim);
    for k in 1..=4 {
        for signal in ["INT", "TERM"] {
            let mut c = common::interrupted(
                sim.command(&["stream-pdo", "1", "--start", "--map", "6064:0,606C:0", "--event", "10"]),
                &format!("{k}:{signal}"),
            );
            let r = common::finish(c.output().unwrap());
            assert_eq!(r.code, 130, "k={k} {signal}: {}", r.stderr);
            assert_eq!(drive_mapping(&sim), before, "k={k} {signal}");
            assert!(sim.run(&["nmt", "state", "1"]).ok().stdout.contains("pre-operational"));
        }
    }
}

/// The library's side: `ApplyOptions::interrupted` is looked at before each transfer; set
/// from the start, nothing is read past it and nothing written.
#[test]
fn the_library_stops_at_its_flag() {
    use canctl::cancel::Cancel;
    use canctl::connect::{self, BusAddr, OpenOptions};
    use canctl::ops::config::{self, ApplyOptions, Dcf};
    let mut opts = OpenOptions::new(std::time::Duration::from_millis(500));
    opts.ephemeral = true;
    let mut bus = connect::open(&"sim".parse::<BusAddr>().unwrap(), &opts).unwrap();
    let dcf = Dcf::parse(include_bytes!("../../examples/sensor.dcf"), "sensor.dcf").unwrap();
    let mut o = ApplyOptions::new(std::time::Duration::from_millis(500));
    o.interrupted = Cancel::new();
    o.interrupted.cancel();
    let applied = config::apply(bus.as_mut(), 5, &dcf, &o).unwrap();
    assert!(applied.interrupted && applied.written.is_empty());
    assert_eq!(applied.state, Some(config::LeftIn::Unread { node: 5 }), "nothing was written");
    assert_eq!(applied.outcome().unwrap_err().exit_code(), 130);
    // Not set: the same file applies in full.
    o.interrupted = Cancel::new();
    let applied = config::apply(bus.as_mut(), 5, &dcf, &o).unwrap();
    assert!(!applied.interrupted && !applied.written.is_empty());
    applied.outcome().unwrap();
}

/// A write of the remapping refused by the device (an object it cannot map): the PDO is
/// put back as it was, and the failure is exit 4 with the report of what was undone.
#[test]
fn a_refused_mapping_entry_puts_the_pdo_back() {
    let (sim, old_dcf, new_dcf) = refusing("0x06040041", 3, "");
    let run = sim.run(&["config", "apply", "10", new_dcf.to_str().unwrap(), "--format", "json"]);
    assert_eq!(run.code, 4, "{}", run.stderr);
    let report = run.json();
    assert_eq!(report["interrupted"], false);
    assert_eq!(report["rolled_back"], serde_json::json!(["TPDO1 (0x1800, 0x1A00)"]), "{report}");
    let diff = sim.run(&["config", "diff", "10", old_dcf.to_str().unwrap(), "--check", "--format", "json"]);
    assert_eq!(diff.code, 0, "the old mapping is not back: {}", diff.stdout);
}

/// Interrupted while it reads the device, before any write: nothing written, the report
/// says so, exit 130.
#[test]
fn interrupted_while_reading_writes_nothing() {
    let sim = common::Sim::new();
    let old_dcf = sim.path("io.dcf");
    sim.run(&["config", "dump", "10", "--out", old_dcf.to_str().unwrap()]).ok();
    let text = std::fs::read_to_string(&old_dcf).unwrap();
    let new_dcf = sim.path("io-remapped.dcf");
    std::fs::write(&new_dcf, edit_dcf(&text, &[("1A00sub0", "2"), ("1A00sub1", "0x62000108")])).unwrap();
    for signal in ["INT", "TERM"] {
        let mut c = common::interrupted(
            sim.command(&["config", "apply", "10", new_dcf.to_str().unwrap()]),
            &format!("r5:{signal}"),
        );
        let run = common::finish(c.output().unwrap());
        assert_eq!(run.code, 130, "{}", run.stderr);
        assert!(
            run.stderr.contains("node 10 is as it was: interrupted while reading it, nothing was written"),
            "{}",
            run.stderr
        );
        assert!(!run.stderr.contains("already matches"), "{}", run.stderr);
        let diff = sim.run(&["config", "diff", "10", old_dcf.to_str().unwrap(), "--check"]);
        assert_eq!(diff.code, 0, "{}", diff.stdout);
    }
}
