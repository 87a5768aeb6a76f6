//! `canctl doctor` (issue 30) on the simulator, one cause each, set up the way a real bus
//! gets there (an NMT stop, an LSS renumbering, a device forced onto a taken id, devices
//! powered off, an adapter at another bit rate); each diagnosis must name the cause with
//! the frames that show it, and the fix it gives must clear it.

use crate::common;

use common::{Run, Sim};
use serde_json::Value;

/// A sim network on virtual time: the listen and every timeout take no wall time.
fn network(extra: &[&str]) -> Sim {
    let sim = Sim::new();
    let mut args = vec!["sim", "reset", "--virtual-time"];
    args.extend_from_slice(extra);
    sim.run(&args).ok();
    sim
}

fn doctor(sim: &Sim, args: &[&str]) -> Run {
    let mut all = vec!["doctor", "--format", "json"];
    all.extend_from_slice(args);
    sim.run(&all)
}

/// The first finding of a diagnosis that found something (exit 6).
fn first_finding(r: &Run) -> Value {
    assert_eq!(r.code, 6, "expected a finding\n{}\n{}", r.stdout, r.stderr);
    let d = r.json();
    assert_eq!(d["ok"], false, "{d}");
    d["findings"][0].clone()
}

fn evidence<'a>(finding: &'a Value, kind: &str) -> &'a Value {
    let all = finding["evidence"].as_array().unwrap_or_else(|| panic!("{finding}"));
    all.iter().find(|e| e["kind"] == kind).unwrap_or_else(|| panic!("no {kind} evidence: {finding}"))
}

#[test]
fn a_healthy_node_is_fine_and_says_what_showed_it() {
    let sim = network(&[]);
    let d = doctor(&sim, &["5"]).ok().json();
    assert_eq!(d["findings"], serde_json::json!([]), "{d}");
    let fine = d["fine"].as_array().unwrap();
    assert!(fine.iter().any(|e| e["kind"] == "sdo_answer" && e["value"] == 0x0950_1234), "{d}");
    assert!(fine.iter().any(|e| e["kind"] == "one_device"), "{d}");
}

#[test]
fn a_stopped_node_is_named_by_its_heartbeat_and_the_fix_clears_it() {
    let sim = network(&[]);
    sim.run(&["nmt", "stop", "5"]).ok();
    let f = first_finding(&doctor(&sim, &["5"]));
    assert_eq!(f["cause"], "stopped", "{f}");
    assert_eq!(evidence(&f, "heartbeats")["state"], "stopped", "{f}");
    assert_eq!(evidence(&f, "no_sdo_answer")["node"], 5, "{f}");
    assert!(f["fix"].as_str().unwrap().contains("canctl nmt preop 5"), "{f}");
    // In words too, most likely cause first.
    let human = sim.run(&["doctor", "5"]);
    assert_eq!(human.code, 6);
    assert!(human.stdout.contains("1. node 5 is alive but stopped"), "{}", human.stdout);
    // The bus alone: node 5 beats but does not answer its read.
    let bus = first_finding(&doctor(&sim, &[]));
    assert_eq!((bus["cause"].as_str(), bus["node"].as_u64()), (Some("stopped"), Some(5)), "{bus}");
    sim.run(&["nmt", "preop", "5"]).ok();
    doctor(&sim, &["5"]).ok();
}

#[test]
fn a_node_that_beats_but_answers_sdo_elsewhere_is_told_apart() {
    // Its SDO answers leave on 0x586, as with a changed 0x1200 (its server COB-IDs).
    let sim = network(&["--fault", "5:wrong-cob"]);
    let f = first_finding(&doctor(&sim, &["5"]));
    assert_eq!(f["cause"], "sdo_silent", "{f}");
    assert_eq!(evidence(&f, "heartbeats")["state"], "pre-operational", "{f}");
    assert_eq!(evidence(&f, "sdo_answer_on")["cob_id"], 0x586, "{f}");
    assert_eq!(f["remedy"]["remedy"], "reset_communication", "{f}");
}

#[test]
fn a_renumbered_node_is_found_on_its_new_id() {
    let sim = network(&[]);
    sim.run(&["scan"]).ok();
    sim.run(&["lss", "set-id", "7", "--identity", "0x40:0x43787800:0x312E3031:0x09501234"]).ok();
    let f = first_finding(&doctor(&sim, &["5"]));
    assert_eq!((f["cause"].as_str(), f["node"].as_u64(), f["now"].as_u64()), (Some("moved"), Some(5), Some(7)), "{f}");
    assert_eq!(evidence(&f, "last_scan")["name"], "C01", "{f}");
    assert_eq!(evidence(&f, "identity")["node"], 7, "{f}");
    // The fix names the device by its identity; done, node 5 is itself again.
    let fix = "canctl lss set-id 5 --identity 0x00000040:0x43787800:0x312E3031:0x09501234";
    assert!(f["fix"].as_str().unwrap().contains(fix), "{f}");
    sim.run(&["lss", "set-id", "5", "--identity", "0x00000040:0x43787800:0x312E3031:0x09501234"]).ok();
    doctor(&sim, &["5"]).ok();
    // Without a last scan to compare with, the node is only silent: nothing is made up.
    let fresh = network(&[]);
    fresh.run(&["lss", "set-id", "7", "--identity", "0x40:0x43787800:0x312E3031:0x09501234"]).ok();
    let f = first_finding(&doctor(&fresh, &["5"]));
    assert_eq!(f["cause"], "node_silent", "{f}");
    let probe = evidence(&f, "probe_answers");
    assert!(probe["nodes"].as_array().unwrap().contains(&Value::from(7)), "{f}");
}

#[test]
fn two_devices_on_one_id_show_in_their_answers() {
    let sim = network(&[]);
    sim.run(&["lss", "set-id", "5", "--identity", "0x40:0x43787800:0x312E3031:0x09501301", "--force"]).ok();
    let f = first_finding(&doctor(&sim, &["5"]));
    assert_eq!((f["cause"].as_str(), f["node"].as_u64()), (Some("node_id_clash"), Some(5)), "{f}");
    let clash = evidence(&f, "clash");
    assert_eq!(clash["shown_by"]["evidence"], "sdo_answers", "{f}");
    let values = clash["shown_by"]["values"].as_array().unwrap();
    assert!(values.contains(&Value::from(0x0950_1234)) && values.contains(&Value::from(0x0950_1301)), "{f}");
}

#[test]
fn a_bus_with_every_device_off_is_silent_and_a_missing_node_is_not() {
    let off = ["--unconfigured", "0", "--fault", "drive:off", "--fault", "sensor:off", "--fault", "io:off"];
    let sim = network(&[&off[..], &["--fault", "stepper:off"]].concat());
    for args in [&["5"][..], &[]] {
        let f = first_finding(&doctor(&sim, args));
        assert_eq!(f["cause"], "bus_silent", "{args:?}: {f}");
        assert_eq!(evidence(&f, "probe_answers")["nodes"], serde_json::json!([]), "{f}");
        assert_eq!(f["remedy"]["remedy"], "check_bus_or_lss", "{f}");
    }
    // One device off among others: that node is silent, the bus is not.
    let sim = network(&["--fault", "io:off"]);
    let f = first_finding(&doctor(&sim, &["10"]));
    assert_eq!((f["cause"].as_str(), f["node"].as_u64()), (Some("node_silent"), Some(10)), "{f}");
    assert_eq!(evidence(&f, "probe_answers")["nodes"], serde_json::json!([1, 5, 32]), "{f}");
    assert_eq!(evidence(&f, "no_guarding_answer")["node"], 10, "{f}");
}

#[test]
fn a_link_that_cannot_be_opened_is_a_finding_about_the_host() {
    let r = common::bare(&["--bus", "socketcan:vcan9", "doctor", "--format", "json"]);
    let f = first_finding(&r);
    assert_eq!((f["cause"].as_str(), f["problem"].as_str()), (Some("host"), Some("no_interface")), "{f}");
    assert!(evidence(&f, "link_reported")["message"].as_str().unwrap().contains("vcan9"), "{f}");
}

/// An slcan adapter at another bit rate than the bus: its frames go unacknowledged, and
/// its status flags say so (bus error, error passive): the controller's finding.
#[cfg(unix)]
#[test]
fn an_adapter_at_another_bit_rate_is_a_finding_about_the_controller() {
    let sim = Sim::new();
    let dev = common::DeviceSide::start(&sim, "--slcan", &[]);
    let wrong = format!("{}@125k", dev.uri);
    let mut c = std::process::Command::new(common::canctl_bin());
    common::isolate(&mut c);
    c.env_remove("CANCTL_BUS").args(["--bus", &wrong, "--timeout", "100ms", "doctor", "5", "--window", "100ms"]);
    let r = common::finish(c.args(["--format", "json"]).output().unwrap());
    let f = first_finding(&r);
    assert_eq!((f["cause"].as_str(), f["state"].as_str()), (Some("controller"), Some("bus_errors")), "{f}");
    assert!(evidence(&f, "link_reported")["message"].as_str().unwrap().contains("error passive"), "{f}");
}

/// Every "did not answer" diagnoses itself: the quick checks name the cause in one line,
/// and --no-diagnose leaves them out.
#[test]
fn a_node_that_did_not_answer_gets_its_likely_cause() {
    let sim = network(&[]);
    sim.run(&["nmt", "stop", "5"]).ok();
    let r = sim.run(&["--timeout", "200ms", "sdo", "read", "5", "1018:1"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    assert!(r.stderr.contains("likely cause: node 5 is alive but stopped"), "{}", r.stderr);
    assert!(r.stderr.contains("fix: canctl nmt preop 5"), "{}", r.stderr);
    let r = sim.run(&["--timeout", "200ms", "--no-diagnose", "sdo", "read", "5", "1018:1"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    assert!(!r.stderr.contains("likely cause"), "{}", r.stderr);
    // A node-id nobody has, on a bus where others answer: that node alone is silent.
    let r = sim.run(&["--timeout", "200ms", "sdo", "read", "6", "1018:1"]);
    assert!(r.stderr.contains("likely cause: node 6 is silent while the bus is not"), "{}", r.stderr);
    // Not only SDO: its state asked by node guarding, its boot-up after a reset.
    for command in [&["nmt", "state", "6"][..], &["nmt", "reset", "6"]] {
        let r = sim.run(&[&["--timeout", "200ms"][..], command].concat());
        assert_eq!(r.code, 3, "{command:?}: {}", r.stderr);
        assert!(r.stderr.contains("likely cause: node 6 is silent while the bus is not"), "{command:?}: {}", r.stderr);
    }
}

/// A firmware download whose device does not answer is explained as any command's silent
/// node (its failure is the download's own error type, which wraps the bus's): a stopped
/// node is named as stopped, a node-id nobody has as silent, and JSON carries the diagnosis.
#[test]
fn a_firmware_download_to_a_silent_node_gets_its_likely_cause() {
    let sim = network(&[]);
    let image = sim.path("app.bin");
    std::fs::write(&image, [0x5Au8; 300]).unwrap();
    let image = image.display().to_string();
    sim.run(&["nmt", "stop", "5"]).ok();
    let r = sim.run(&["--timeout", "200ms", "firmware", "download", "5", &image]);
    assert_eq!(r.code, 3, "{}{}", r.stdout, r.stderr);
    assert!(r.stderr.contains("likely cause: node 5 is alive but stopped"), "{}", r.stderr);
    assert!(r.stdout.contains("nothing was changed on the device"), "{}", r.stdout);
    let r = sim.run(&["--timeout", "200ms", "firmware", "download", "6", &image]);
    assert_eq!(r.code, 3, "{}{}", r.stdout, r.stderr);
    assert!(r.stderr.contains("likely cause: node 6 is silent while the bus is not"), "{}", r.stderr);
    let r = sim.run(&["--timeout", "200ms", "--format", "json", "firmware", "download", "6", &image]);
    assert_eq!(r.code, 3, "{}{}", r.stdout, r.stderr);
    let error: serde_json::Value = serde_json::from_str(r.stderr.trim()).expect("one JSON object on stderr");
    assert!(error["diagnosis"].is_object(), "{error}");
}

/// A device that floods the bus with its EMCY id (0x08A, node 10): it wins every
/// arbitration, nothing else gets through; the flood is named, not "nothing answers".
#[test]
fn a_device_flooding_the_bus_is_named_by_its_id() {
    let sim = network(&["--fault", "io:babble"]);
    let f = first_finding(&doctor(&sim, &["--window", "100ms", "--timeout", "100ms"]));
    assert_eq!((f["cause"].as_str(), f["cob_id"].as_u64()), (Some("flood"), Some(0x08A)), "{f}");
    assert_eq!(evidence(&f, "traffic")["frames"][0]["cob_id"], 0x08A, "{f}");
    assert_eq!(evidence(&f, "probe_answers")["nodes"], serde_json::json!([]), "{f}");
}

/// The only device powered is the sensor (node 5), running: its TPDO 0x185 every
/// millisecond, no heartbeat, its SDO answers on 0x1F0 (as with a changed 0x1200).
fn sensor_answering_elsewhere() -> Sim {
    let faults = ["--fault", "sensor:no-heartbeat", "--fault", "sensor:wrong-cob=0x1F0"];
    let off = ["--unconfigured", "0", "--fault", "drive:off", "--fault", "io:off", "--fault", "stepper:off"];
    let sim = network(&[&off[..], &faults[..]].concat());
    sim.run(&["nmt", "start", "5"]).ok();
    sim
}

/// Frames on the bus but no SDO answer on any id, and no heartbeat to say why: the node
/// that sends (a running sensor's TPDO 0x185) answers its reads on another COB-ID, as with
/// a changed 0x1200, and beats no more. Doctor says nobody answers, with the traffic it
/// heard, not that the bus is silent; the traffic is not also called fine.
#[test]
fn frames_heard_but_nobody_answering_is_told_from_a_silent_bus() {
    let sim = sensor_answering_elsewhere();
    // A short listen: the sensor's one PDO a millisecond is traffic, not a flood.
    let r = doctor(&sim, &["--window", "50ms", "--timeout", "100ms"]);
    let f = first_finding(&r);
    assert_eq!(f["cause"], "no_answers", "{f}");
    assert_eq!(evidence(&f, "traffic")["frames"][0]["cob_id"], 0x185, "{f}");
    assert_eq!(evidence(&f, "probe_answers")["nodes"], serde_json::json!([]), "{f}");
    assert_eq!(f["remedy"]["remedy"], "watch_bus", "{f}");
    let fine = r.json()["fine"].clone();
    assert!(!fine.as_array().unwrap().iter().any(|e| e["kind"] == "traffic"), "{fine}");
}

/// `--format json`: the error of a node that did not answer is one JSON object on stderr,
/// its `diagnosis` the finding the human form words as the likely cause; null with
/// --no-diagnose. A link that fails has its finding too.
#[test]
fn a_silent_node_in_json_carries_its_diagnosis() {
    let sim = network(&[]);
    sim.run(&["nmt", "stop", "5"]).ok();
    let object =
        |r: &Run| -> Value { serde_json::from_str(r.stderr.trim()).unwrap_or_else(|e| panic!("{e}: {}", r.stderr)) };
    let r = sim.run(&["--timeout", "200ms", "--format", "json", "sdo", "read", "5", "1018:1"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    let e = object(&r);
    assert_eq!(e["exit_code"], 3, "{e}");
    assert!(e["error"].as_str().unwrap().contains("likely cause: node 5 is alive but stopped"), "{e}");
    let d = &e["diagnosis"];
    assert_eq!((d["cause"].as_str(), d["node"].as_u64()), (Some("stopped"), Some(5)), "{e}");
    assert_eq!(d["remedy"]["remedy"], "pre_operational", "{e}");
    assert!(d["evidence"].as_array().unwrap().iter().any(|v| v["state"] == "stopped"), "{e}");
    assert!(d["fix"].as_str().unwrap().contains("canctl nmt preop 5"), "{e}");
    let r = sim.run(&["--timeout", "200ms", "--format", "json", "--no-diagnose", "sdo", "read", "5", "1018:1"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    assert_eq!(object(&r)["diagnosis"], Value::Null, "{}", r.stderr);
    // Human form: the line as before, no JSON.
    let r = sim.run(&["--timeout", "200ms", "sdo", "read", "5", "1018:1"]);
    assert!(r.stderr.starts_with("canctl: "), "{}", r.stderr);

    let r = common::bare(&["--bus", "socketcan:vcan9", "--format", "json", "sdo", "read", "5", "1018:1"]);
    let e = object(&r);
    assert_eq!(e["exit_code"], r.code, "{e}");
    assert_eq!(
        (e["diagnosis"]["cause"].as_str(), e["diagnosis"]["problem"].as_str()),
        (Some("host"), Some("no_interface")),
        "{e}"
    );
}

/// `health` gives a node silent to SDO the doctor's finding, from its own scan and watch
/// (no request of its own): one line for people, `diagnosis` in JSON, the likely cause in
/// the JUnit failure; healthy nodes get none, and --no-diagnose leaves it out.
#[test]
fn health_diagnoses_a_node_silent_to_sdo() {
    let sim = network(&["--unconfigured", "0"]);
    sim.run(&["nmt", "stop", "5"]).ok();
    let r = sim.run(&["health", "--format", "json"]);
    assert_eq!(r.code, 6, "{}\n{}", r.stdout, r.stderr);
    let report = r.json();
    let node = |n: u64| report["nodes"].as_array().unwrap().iter().find(|v| v["node"] == n).unwrap().clone();
    let d = node(5)["diagnosis"].clone();
    assert_eq!((d["cause"].as_str(), d["node"].as_u64()), (Some("stopped"), Some(5)), "{report}");
    assert_eq!(evidence(&d, "heartbeats")["state"], "stopped", "{d}");
    let probe = evidence(&d, "probe_answers")["nodes"].as_array().unwrap().clone();
    assert!(!probe.contains(&Value::from(5)) && probe.contains(&Value::from(10)), "{d}");
    assert!(d["fix"].as_str().unwrap().contains("canctl nmt preop 5"), "{d}");
    assert_eq!(node(10)["diagnosis"], Value::Null, "{report}");

    let human = sim.run(&["health"]);
    assert_eq!(human.code, 6);
    let line =
        "node 5; likely cause: node 5 is alive but stopped: a stopped node serves no SDO; fix: canctl nmt preop 5";
    assert!(human.stdout.contains(line), "{}", human.stdout);
    assert_eq!(human.stdout.matches("likely cause").count(), 1, "{}", human.stdout);
    let junit = sim.run(&["health", "--format", "junit"]).stdout;
    assert!(junit.contains("likely cause: node 5 is alive but stopped"), "{junit}");

    let quiet = sim.run(&["--no-diagnose", "health", "--format", "json"]);
    assert_eq!(quiet.code, 6);
    assert_eq!(quiet.json()["nodes"].as_array().unwrap().iter().filter(|v| !v["diagnosis"].is_null()).count(), 0);
    assert!(!sim.run(&["--no-diagnose", "health"]).stdout.contains("likely cause"));

    // Beating, but its SDO answers go elsewhere (a changed 0x1200): alive, SDO server silent.
    let sim = network(&["--unconfigured", "0", "--fault", "5:wrong-cob=0x1F0"]);
    let r = sim.run(&["health", "--format", "json"]);
    let report = r.json();
    let d = report["nodes"].as_array().unwrap().iter().find(|v| v["node"] == 5).unwrap()["diagnosis"].clone();
    assert_eq!(d["cause"], "sdo_silent", "{report}");
    assert_eq!(d["remedy"]["remedy"], "reset_communication", "{d}");
}

/// A device waiting in LSS configuration without a node-id answers no SDO and sends no
/// heartbeat: doctor finds it only with --lss (its one LSS broadcast); without, the remedy
/// of a silent node or bus says that --lss would find one.
#[test]
fn a_device_without_a_node_id_is_found_only_when_lss_is_asked() {
    let off = ["--fault", "drive:off", "--fault", "sensor:off", "--fault", "io:off", "--fault", "stepper:off"];
    let sim = network(&[&["--unconfigured", "1"], &off[..]].concat());
    for args in [&["5"][..], &[]] {
        let f = first_finding(&doctor(&sim, args));
        assert_eq!(f["cause"], "bus_silent", "{args:?}: {f}");
        assert_eq!(f["remedy"]["remedy"], "check_bus_or_lss", "{f}");
        assert!(f["fix"].as_str().unwrap().contains("canctl doctor --lss"), "{f}");
        assert!(!f["evidence"].as_array().unwrap().iter().any(|e| e["kind"] == "lss_answers"), "not asked: {f}");

        let asked: Vec<&str> = [args, &["--lss"]].concat();
        let r = doctor(&sim, &asked);
        let f = first_finding(&r);
        assert_eq!((f["cause"].as_str(), f["count"].as_u64()), (Some("lss_unconfigured"), Some(1)), "{f}");
        assert_eq!(evidence(&f, "lss_answers")["count"], 1, "{f}");
        assert_eq!(f["remedy"]["remedy"], "lss_assign", "{f}");
        // The bus is not silent: a device answered.
        let causes: Vec<Value> = r.json()["findings"].as_array().unwrap().iter().map(|f| f["cause"].clone()).collect();
        assert!(!causes.contains(&Value::from("bus_silent")), "{causes:?}");
    }
    // No device without a node-id: the silent bus says LSS was asked, its remedy is the bus's.
    let sim = network(&[&["--unconfigured", "0"], &off[..]].concat());
    let f = first_finding(&doctor(&sim, &["--lss"]));
    assert_eq!((f["cause"].as_str(), f["remedy"]["remedy"].as_str()), (Some("bus_silent"), Some("check_bus")), "{f}");
    assert_eq!(evidence(&f, "lss_answers")["count"], 0, "{f}");
}

/// Through an EPOS2 (on its RS232 pty) canctl hears none of the bus: the EPOS2's own error
/// register 0x1001 and CAN bit rate 0x2001 are the evidence of its side of the bus. The
/// EPOS2 on the sim's 500 kbit/s bus holds that rate, in its own code (2): not 1M.
#[cfg(unix)]
#[test]
fn through_an_epos2_its_error_register_and_bit_rate_are_evidence() {
    let sim = network(&["--profile", "instant"]);
    let dev = common::DeviceSide::start(&sim, "--epos2-rs232", &[]);
    let gateway = |v: &Value| -> Value {
        let all = v.as_array().unwrap_or_else(|| panic!("{v}"));
        all.iter().find(|e| e["kind"] == "epos2_gateway").unwrap_or_else(|| panic!("no epos2_gateway: {v}")).clone()
    };
    let r = dev.run(&["--timeout", "200ms", "doctor", "5", "--format", "json"]);
    assert_eq!(r.code, 0, "{}\n{}", r.stdout, r.stderr);
    let seen = gateway(&r.json()["fine"]);
    assert_eq!((seen["error_register"].as_u64(), seen["bit_rate_code"].as_u64()), (Some(0), Some(2)), "{seen}");
    let human = dev.run(&["--timeout", "200ms", "doctor", "5"]);
    assert!(
        human.stdout.contains("the EPOS2 gateway: error register 0x00, CAN bit rate 500k (0x2001 = 2)"),
        "{}",
        human.stdout
    );
}

/// The quick checks after a silent node say "nothing on the bus" only when nothing came:
/// a running sensor's PDOs (its SDO answers on another COB-ID, no heartbeat) are frames,
/// and a silent bus's fix points at `doctor --lss` (they never ask LSS themselves).
#[test]
fn the_likely_cause_of_a_silent_node_says_what_the_bus_showed() {
    let sim = sensor_answering_elsewhere();
    let r = sim.run(&["--timeout", "100ms", "--format", "json", "sdo", "read", "5", "1018:1"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    let e: Value = serde_json::from_str(r.stderr.trim()).unwrap_or_else(|e| panic!("{e}: {}", r.stderr));
    assert_eq!(e["diagnosis"]["cause"], "no_answers", "{e}");
    assert!(evidence(&e["diagnosis"], "frames_received")["count"].as_u64().unwrap() > 0, "{e}");

    let off = ["--unconfigured", "1", "--fault", "drive:off", "--fault", "sensor:off", "--fault", "io:off"];
    let sim = network(&[&off[..], &["--fault", "stepper:off"]].concat());
    let r = sim.run(&["--timeout", "100ms", "sdo", "read", "5", "1018:1"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    assert!(r.stderr.contains("likely cause: nothing on the bus"), "{}", r.stderr);
    assert!(r.stderr.contains("canctl doctor --lss"), "{}", r.stderr);
}

/// Evidence says what was waited, measured on the bus's clock, not the timeout allowed:
/// through an EPOS2 the gateway says "no answer" after a wait of its own (two SDO reads
/// took 0.13 s, not "500 ms each"), and the read of every node-id goes one id after the
/// other (12.6 s, not "500 ms"). Together the waits stated are no more than the run took,
/// and the read of every node-id is most of it.
#[cfg(unix)]
#[test]
fn through_an_epos2_the_waits_stated_are_the_waits_measured() {
    let sim = network(&["--profile", "instant"]);
    let dev = common::DeviceSide::start(&sim, "--epos2-rs232", &[]);
    let started = std::time::Instant::now();
    let r = dev.run(&["--timeout", "1s", "doctor", "7", "--format", "json"]);
    let took_ms = started.elapsed().as_millis() as u64;
    assert_eq!(r.code, 6, "{}\n{}", r.stdout, r.stderr);
    let d = r.json();
    let evidence: Vec<&Value> =
        d["findings"].as_array().unwrap().iter().flat_map(|f| f["evidence"].as_array().unwrap()).collect();
    let waited = |kind: &str| {
        let e = evidence.iter().find(|e| e["kind"] == kind).unwrap_or_else(|| panic!("no {kind}: {d}"));
        e["waited_ms"].as_u64().unwrap()
    };
    let stated: u64 = ["no_guarding_answer", "no_sdo_answer", "probe_answers"].iter().map(|k| waited(k)).sum();
    assert!(stated <= took_ms, "{stated} ms of waits stated in a run of {took_ms} ms: {d}");
    assert!(waited("probe_answers") * 2 >= took_ms, "the read of every id, most of {took_ms} ms: {d}");
}

/// `doctor --window 0s` listened to nothing and went on as if it had; scan refuses a window
/// under 10 ms. One rule for both (and for the sweep's window): refused, exit 2, before the
/// bus is opened.
#[test]
fn a_window_too_short_to_hear_anything_is_refused_as_scan_refuses_it() {
    let sim = network(&[]);
    for args in [&["--window", "0s"][..], &["--window", "5ms"], &["--sweep-window", "0s"]] {
        let r = doctor(&sim, args);
        assert_eq!(r.code, 2, "{args:?}: {}{}", r.stdout, r.stderr);
        assert!(r.stderr.contains("shorter than") && r.stderr.contains("use at least 10ms"), "{args:?}: {}", r.stderr);
        let scan = sim.run(&["scan", "--window", args[1]]);
        assert_eq!(scan.code, 2, "scan {args:?}: {}", scan.stderr);
    }
}

/// In JUnit each passing check is named for what it checked (the evidence's kind, as JSON
/// names it): every one was named "fine", which a CI report cannot tell apart.
#[test]
fn junit_names_each_passing_check_by_what_it_checked() {
    let sim = network(&[]);
    let r = sim.run(&["doctor", "5", "--window", "100ms", "--format", "junit"]).ok();
    let names: Vec<&str> =
        r.stdout.split("<testcase ").skip(1).filter_map(|c| c.split(" name=\"").nth(1)?.split('"').next()).collect();
    assert!(names.len() >= 3, "{}", r.stdout);
    assert!(!names.contains(&"fine"), "{}", r.stdout);
    for kind in ["sdo_answer", "one_device", "link_quiet"] {
        assert!(names.contains(&kind), "no {kind}: {}", r.stdout);
    }
}
