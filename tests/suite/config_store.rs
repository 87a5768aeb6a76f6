//! store/restore, object names from EDS files, and configuration files, with the real
//! binary on the simulated network.

use crate::common;

use common::Sim;

/// `ParameterValue` of `[section]` in a DCF set to `value`.
fn set_parameter(dcf: &str, section: &str, value: &str) -> String {
    let start = dcf.find(&format!("[{section}]\n")).unwrap_or_else(|| panic!("no [{section}]"));
    let key = start + dcf[start..].find("ParameterValue=").expect("a ParameterValue");
    let end = key + dcf[key..].find('\n').unwrap();
    format!("{}ParameterValue={value}{}", &dcf[..key], &dcf[end..])
}

fn read(sim: &Sim, node: &str, obj: &str) -> String {
    sim.run(&["sdo", "read", node, obj]).ok().stdout.trim().to_string()
}

#[test]
fn dump_change_apply_diff_store_reset_restore() {
    let sim = Sim::new();
    let original = sim.path("io.dcf");
    sim.run(&["config", "dump", "10", "--out", original.to_str().unwrap()]).ok();
    let text = std::fs::read_to_string(&original).unwrap();
    assert!(text.contains("[DeviceComissioning]\nNodeID=10"));
    // Three values: heartbeat, an output, and a second TPDO1 mapping entry.
    let mut changed = set_parameter(&text, "1017", "100");
    changed = set_parameter(&changed, "6200sub1", "0x0F");
    changed = set_parameter(&changed, "1A00sub0", "2");
    changed = set_parameter(&changed, "1A00sub2", "0x62000108");
    let file = sim.path("io-changed.dcf");
    std::fs::write(&file, &changed).unwrap();
    let f = file.to_str().unwrap();

    let diff = sim.run(&["config", "diff", "10", f, "--format", "json"]).ok().json();
    assert_eq!(diff["differences"].as_array().unwrap().len(), 4);
    assert_eq!(sim.run(&["config", "diff", "10", f, "--check"]).code, 6);

    // A dry run writes nothing: the device still holds the old values.
    let dry = sim.run(&["config", "apply", "10", f, "--dry-run", "--format", "json"]).ok().json();
    assert!(dry["objects"]
        .as_array()
        .unwrap()
        .iter()
        .all(|o| o["result"].as_str().unwrap().starts_with("would write")));
    assert_eq!(read(&sim, "10", "1017"), "0");
    assert_eq!(read(&sim, "10", "1A00:0"), "1");

    let applied = sim.run(&["config", "apply", "10", f, "--verify", "--format", "json"]).ok().json();
    let objects = applied["objects"].as_array().unwrap();
    let order: Vec<(&str, &str)> =
        objects.iter().map(|o| (o["object"].as_str().unwrap(), o["new"].as_str().unwrap())).collect();
    // The safe order: plain objects; COB-ID invalid; count 0; entry; count; COB-ID valid.
    assert_eq!(
        order,
        [
            ("0x1017:0", "0x64"),
            ("0x6200:1", "0xF"),
            ("0x1800:1", "0x8000018A"),
            ("0x1A00:0", "0x0"),
            ("0x1A00:2", "0x62000108"),
            ("0x1A00:0", "0x2"),
            ("0x1800:1", "0x18A"),
        ]
    );
    assert!(objects.iter().filter(|o| o["object"] == "0x1A00:2").all(|o| o["result"] == "written, verified"));
    assert_eq!(
        sim.run(&["config", "diff", "10", f, "--format", "json"]).ok().json()["differences"],
        serde_json::json!([])
    );
    // Applied again: nothing to write.
    let again = sim.run(&["config", "apply", "10", f, "--format", "json"]).ok().json();
    assert_eq!(again["objects"], serde_json::json!([]));

    sim.run(&["store", "10"]).ok();
    sim.run(&["nmt", "reset", "10"]).ok();
    sim.run(&["config", "diff", "10", f, "--check"]).ok();

    let r = sim.run(&["restore", "10"]).ok();
    assert!(r.stdout.contains("after the next reset"), "{}", r.stdout);
    sim.run(&["config", "diff", "10", f, "--check"]).ok();
    sim.run(&["restore", "10", "--reset"]).ok();
    sim.run(&["config", "diff", "10", original.to_str().unwrap(), "--check"]).ok();
}

/// Commissioning by example: one sensor's setup, dumped, is applied to a new one. The new
/// sensor keeps its own COB-IDs, and a node matches its own dump.
#[test]
fn a_dump_applied_to_another_node_keeps_that_nodes_cob_ids() {
    let sim = Sim::new();
    let dcf = sim.path("sensor.dcf");
    let f = dcf.to_str().unwrap();
    sim.run(&["sdo", "write", "5", "1017", "250", "--type", "u16"]).ok();
    sim.run(&["config", "dump", "5", "--out", f]).ok();
    assert_eq!(sim.run(&["config", "diff", "5", f, "--check"]).code, 0, "a node matches its own dump");
    assert!(std::fs::read_to_string(&dcf).unwrap().contains("ParameterValue=$NODEID+0x180"));

    sim.run(&["lss", "assign", "--start", "20", "--no-store"]).ok();
    sim.run(&["config", "apply", "20", f, "--verify"]).ok();
    assert_eq!(read(&sim, "20", "1017"), read(&sim, "5", "1017"));
    let cob = sim.run(&["sdo", "read", "20", "1800:1", "--type", "u32", "--format", "json"]).ok().json();
    assert_eq!(cob["value"], 0x194, "{cob}");
}

#[test]
fn a_failure_part_way_says_what_was_written() {
    let sim = Sim::new();
    let dcf = sim.run(&["config", "dump", "32"]).ok().stdout;
    let mut changed = set_parameter(&dcf, "6040", "0x6");
    changed = set_parameter(&changed, "6060", "9");
    changed = set_parameter(&changed, "607A", "1000");
    let file = sim.path("stepper.dcf");
    std::fs::write(&file, changed).unwrap();
    let r = sim.run(&["config", "apply", "32", file.to_str().unwrap(), "--format", "json"]);
    assert_eq!(r.code, 4, "{}", r.stderr);
    let objects = r.json()["objects"].as_array().unwrap().clone();
    let results: Vec<(&str, &str)> =
        objects.iter().map(|o| (o["object"].as_str().unwrap(), o["result"].as_str().unwrap())).collect();
    assert_eq!(results[0], ("0x6040:0", "written"));
    assert!(results[1].1.starts_with("failed: node 32: SDO abort 0x06090031"), "{results:?}");
    assert_eq!(results[2], ("0x607A:0", "not written"));
    assert!(r.stderr.contains("written before the failure: 0x6040:0"), "{}", r.stderr);
    assert_eq!(read(&sim, "32", "607A"), "0");
}

#[test]
fn values_outside_the_eds_range_are_refused_before_any_write() {
    let sim = Sim::new();
    let eds = format!("1={}/eds/canctl-sim-drive.eds", env!("CARGO_MANIFEST_DIR"));
    let dcf = sim.run(&["--eds", &eds, "config", "dump", "1"]).ok().stdout;
    assert!(dcf.contains("LowLimit=-6"), "the range comes from the EDS");
    let mut changed = set_parameter(&dcf, "607A", "5000");
    changed = set_parameter(&changed, "6060", "20");
    let file = sim.path("drive.dcf");
    std::fs::write(&file, changed).unwrap();
    let r = sim.run(&["config", "apply", "1", file.to_str().unwrap()]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    // The file's own limits refuse it, at its line, as `config check` does.
    assert!(
        r.stderr.contains("ParameterValue 20 of 0x6060:0 (Modes of operation) is outside the file's limits, -6 to 7"),
        "{}",
        r.stderr
    );
    assert_eq!(read(&sim, "1", "607A"), "0", "nothing was written");
}

#[test]
fn store_and_restore_check_what_the_device_supports() {
    let sim = Sim::new();
    assert_eq!(
        sim.run(&["store", "1", "comm"]).ok().stdout.trim(),
        "node 1: communication parameters stored (0x1010:2)"
    );
    let r = sim.run(&["store", "5", "app"]);
    assert_eq!(r.code, 4);
    assert!(
        r.stderr.contains("cannot store application parameters (0x1010:0 = 1; it offers: all parameters)"),
        "{}",
        r.stderr
    );
    let r = sim.run(&["restore", "5", "--reset", "--format", "json"]).ok().json();
    assert_eq!(r["reset"], true);
    assert_eq!(sim.run(&["store", "77"]).code, 3);
}

#[test]
fn object_names_from_an_eds_or_the_built_in_dictionary() {
    let sim = Sim::new();
    assert_eq!(sim.run(&["sdo", "read", "5", "ProducerHeartbeatTime"]).ok().stdout.trim(), "40");
    sim.run(&["sdo", "write", "5", "producer heartbeat time", "60", "--verify"]).ok();
    let eds = format!("1={}/eds/canctl-sim-drive.eds", env!("CARGO_MANIFEST_DIR"));
    let r = sim
        .run(&["--eds", &eds, "sdo", "read", "1", "Simulator data types: unsigned16", "--format", "json"])
        .ok()
        .json();
    assert_eq!((r["object"].as_str(), r["value"].as_u64()), (Some("0x5FF0:3"), Some(0x1234)));
    let r = sim.run(&["sdo", "read", "5", "ProducerHeartbeatTme"]);
    assert_eq!(r.code, 2);
    assert!(r.stderr.contains("did you mean 'Producer heartbeat time' (0x1017:0)?"), "{}", r.stderr);
    // An object the EDS describes so that it cannot be understood is left out, said with
    // file:line; the command goes on. A file that is not an EDS at all is refused.
    let broken = format!("{}/tests/fixtures/eds/broken-access.eds", env!("CARGO_MANIFEST_DIR"));
    let r = sim.run(&["--eds", &broken, "sdo", "read", "1", "1000"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(
        r.stderr.contains("broken-access.eds:4: 0x1000:0 (Device type) left out: AccessType 'readwrite'"),
        "{}",
        r.stderr
    );
    let broken = format!("{}/tests/fixtures/eds/broken-line.eds", env!("CARGO_MANIFEST_DIR"));
    let r = sim.run(&["--eds", &broken, "sdo", "read", "1", "1000"]);
    assert_eq!(r.code, 2);
    assert!(r.stderr.contains("broken-line.eds:3: expected KEY=VALUE or [SECTION]"), "{}", r.stderr);
}

/// A DCF names itself after the file it is written to, and claims no name on stdout.
#[test]
fn a_dumped_dcf_names_the_file_it_is_in() {
    let sim = Sim::new();
    let stdout = sim.run(&["config", "dump", "10"]).ok().stdout;
    assert!(!stdout.contains("FileName="), "{stdout}");
    let out = sim.path("io.dcf");
    sim.run(&["config", "dump", "10", "--out", out.to_str().unwrap()]).ok();
    let dcf = std::fs::read_to_string(&out).unwrap();
    assert!(dcf.contains("FileName=io.dcf"), "{dcf}");
}

/// A sensor's DCF is not written into the drive: both identities named, nothing written,
/// exit 6; `--force` is the way to mean it.
#[test]
fn a_dcf_for_another_device_is_refused_before_any_write() {
    let sim = Sim::new();
    let dcf = sim.path("sensor.dcf");
    let dcf = dcf.to_str().unwrap();
    sim.run(&["config", "dump", "5", "--out", dcf]).ok();
    let r = sim.run(&["-v", "config", "apply", "1", dcf]);
    assert_eq!(r.code, 6, "{}", r.stderr);
    assert!(r.stderr.contains("vendor-ID 0x000000FB on node 1, 0x00000040 in the file"), "{}", r.stderr);
    assert!(r.stderr.contains("--force"), "{}", r.stderr);
    assert!(!r.stderr.lines().any(|l| l.contains(" 601 ") && l.contains("[8]  2")), "no download: {}", r.stderr);
    // The same file on a device of its kind goes through the check.
    sim.run(&["config", "apply", "5", dcf, "--dry-run"]).ok();
}

/// A dry run predicts the real run: a write the device must refuse (an object it does not
/// have) is shown as refused, with the same exit code, and nothing is written.
#[test]
fn a_dry_run_predicts_a_refused_write() {
    let sim = Sim::new();
    let dcf = sim.path("io.dcf");
    sim.run(&["config", "dump", "10", "--out", dcf.to_str().unwrap()]).ok();
    let mut text = std::fs::read_to_string(&dcf).unwrap();
    text.push_str("\n[5FFD]\nParameterName=Not on this device\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\nDefaultValue=0\nPDOMapping=0\nParameterValue=5\n");
    std::fs::write(&dcf, text).unwrap();
    let dry = sim.run(&["config", "apply", "10", dcf.to_str().unwrap(), "--dry-run"]);
    assert_eq!(dry.code, 4, "{}", dry.stderr);
    assert!(dry.stdout.contains("would be refused: Object does not exist"), "{}", dry.stdout);
    assert!(dry.stderr.contains("nothing was written"), "{}", dry.stderr);
    let real = sim.run(&["config", "apply", "10", dcf.to_str().unwrap()]);
    assert_eq!(real.code, 4, "{}", real.stderr);
}

/// The DCF with one section's keys changed: `edit` gets the section's lines (without its
/// `[header]`) and returns the new ones.
fn edit_section(dcf: &str, header: &str, edit: impl Fn(Vec<String>) -> Vec<String>) -> String {
    let mut out = String::new();
    for (i, section) in dcf.split("\n[").enumerate() {
        let (head, body) = section.split_once('\n').unwrap_or((section, ""));
        let lines: Vec<String> = body.lines().map(str::to_string).collect();
        let lines = if head == format!("{header}]") { edit(lines) } else { lines };
        if i > 0 {
            out.push_str("\n[");
        }
        out.push_str(head);
        out.push('\n');
        out.push_str(&lines.join("\n"));
    }
    out
}

fn set_key(key: &'static str, value: &'static str) -> impl Fn(Vec<String>) -> Vec<String> {
    move |lines| {
        lines
            .into_iter()
            .map(|l| if l.starts_with(&format!("{key}=")) { format!("{key}={value}") } else { l })
            .collect()
    }
}

/// A hand-edited DCF is judged by the target's own dictionary, as the device will judge it:
/// a value outside the range the drive's profile gives is refused before anything is
/// written, in the dry run and in the real run alike.
#[test]
fn a_value_out_of_the_targets_range_is_refused_before_any_write() {
    let sim = Sim::new();
    let path = sim.path("drive.dcf");
    sim.run(&["config", "dump", "1", "--out", path.to_str().unwrap()]).ok();
    let text = std::fs::read_to_string(&path).unwrap();
    // Limits a file need not carry, and a heartbeat that would be written first.
    let text = edit_section(&text, "6060", |lines| {
        let lines = lines.into_iter().filter(|l| !l.contains("Limit=")).collect();
        set_key("ParameterValue", "99")(lines)
    });
    let text = edit_section(&text, "1017", set_key("ParameterValue", "250"));
    std::fs::write(&path, text).unwrap();
    let before = sim.run(&["sdo", "read", "1", "1017"]).ok().stdout;
    for dry in [true, false] {
        let mut args = vec!["config", "apply", "1", path.to_str().unwrap()];
        if dry {
            args.push("--dry-run");
        }
        let r = sim.run(&args);
        assert_eq!(r.code, 2, "dry run {dry}: {}", r.stderr);
        assert!(
            r.stderr.contains(
                "99 is outside the range of 0x6060:0: use -128 to 10 (the built-in dictionary (profile 402))"
            ),
            "{}",
            r.stderr
        );
        assert_eq!(sim.run(&["sdo", "read", "1", "1017"]).ok().stdout, before, "nothing written");
    }
}

/// An object the target's dictionary has read-only: the dry run shows the write refused,
/// with the exit code the real run then ends with.
#[test]
fn a_dry_run_predicts_a_read_only_object_by_the_targets_dictionary() {
    let sim = Sim::new();
    let path = sim.path("drive.dcf");
    sim.run(&["config", "dump", "1", "--out", path.to_str().unwrap()]).ok();
    let text = std::fs::read_to_string(&path).unwrap();
    let text = edit_section(&text, "1018sub4", |l| set_key("ParameterValue", "0x77")(set_key("AccessType", "rw")(l)));
    std::fs::write(&path, text).unwrap();
    let dry = sim.run(&["config", "apply", "1", path.to_str().unwrap(), "--dry-run"]);
    assert_eq!(dry.code, 4, "{}", dry.stderr);
    assert!(
        dry.stdout.contains("would be refused: read only in the built-in dictionary (profile 402)"),
        "{}",
        dry.stdout
    );
    let real = sim.run(&["config", "apply", "1", path.to_str().unwrap()]);
    assert_eq!(real.code, 4, "{}", real.stderr);
    assert!(real.stderr.contains("0x06010002"), "{}", real.stderr);
}

/// Objects the target lacks are met with suggestions from the target's dictionary (the
/// drive's profile), not from the file's or every profile's (a sensor's 0x6004 "Position
/// value" for a drive).
#[test]
fn suggestions_come_from_the_targets_dictionary() {
    let sim = Sim::new();
    let path = sim.path("sensor.dcf");
    sim.run(&["config", "dump", "5", "--out", path.to_str().unwrap()]).ok();
    let drive = canctl::od::builtin::dictionary(Some(402));
    for dry in [true, false] {
        let mut args = vec!["config", "apply", "1", path.to_str().unwrap(), "--force"];
        if dry {
            args.push("--dry-run");
        }
        let r = sim.run(&args);
        assert_eq!(r.code, 4, "{}", r.stderr);
        let line = r.stderr.lines().find(|l| l.contains("SDO abort 0x06020000 on 0x6000:0")).expect(&r.stderr);
        let near = line.split("did you mean ").nth(1).expect(line).trim_end_matches('?');
        for name in near.split(", ") {
            let addr: canctl::canopen::ObjAddr = name.split(' ').next().unwrap().parse().unwrap();
            assert!(drive.get(addr).is_some(), "{name} is not a drive's object: {line}");
        }
        let json = sim.run(&[args, vec!["--format", "json"]].concat()).json();
        assert!(json["did_you_mean"].as_array().is_some_and(|a| !a.is_empty()), "{json}");
    }
}

/// The answer to the 'save' write lost (node 5 drops its third answer): the save is an
/// action, so it is sent once, never again behind the user's back, and the message says
/// that whether the device stored is unknown, not that nothing happened.
#[test]
fn a_lost_answer_to_the_save_is_not_repeated_and_reported_as_unknown() {
    let sim = Sim::new();
    sim.run(&["sim", "reset", "--fault", "5:drop@3"]).ok();
    let r = sim.run(&["-v", "--timeout", "300ms", "store", "5"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    let saves = r.stderr.lines().filter(|l| l.contains("605") && l.contains("23 10 10 01 73 61 76 65")).count();
    assert_eq!(saves, 1, "the save sent once:\n{}", r.stderr);
    assert!(r.stderr.contains("unknown whether node 5 stored"), "{}", r.stderr);
}
