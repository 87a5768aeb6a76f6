//! stream-pdo and monitor with the real binary on the simulated network.

use crate::common;

use common::{scenarios, Sim};
use std::process::Stdio;
use std::time::{Duration, Instant};

#[test]
fn stream_pdo_yields_the_sensors_values() {
    scenarios::stream_pdo_yields_the_sensors_values(&Sim::new());
}

#[test]
fn one_pdo_per_sync_with_transmission_type_1() {
    scenarios::one_pdo_per_sync_with_transmission_type_1(&Sim::new());
}

#[test]
fn map_reconfigures_for_the_session_and_restores() {
    scenarios::map_reconfigures_for_the_session_and_restores(&Sim::new());
}

#[test]
fn ctrl_c_restores_and_exits_130() {
    scenarios::ctrl_c_restores_and_exits_130(&Sim::new());
}

#[test]
fn a_pdo_of_the_wrong_length_is_warned_about_once() {
    // The CAN-2057C sends 8-byte PDOs whatever its mapping says (seed 004's frames).
    let sim = Sim::new();
    sim.run(&["sdo", "write", "10", "1800:5", "5"]).ok();
    // Listen until several such PDOs have come, however slow this machine is.
    let mut listen = 100;
    let r = loop {
        let duration = format!("{listen}ms");
        let r = sim.run(&["-v", "stream-pdo", "10", "--start", "--duration", &duration, "--format", "csv"]).ok();
        let pdos = r.stderr.lines().filter(|l| l.trim_start().starts_with("sim  18A   [8]")).count();
        if pdos >= 3 {
            break r;
        }
        assert!(listen < 30_000, "no three PDOs from node 10 in {listen} ms:\n{}", r.stderr);
        listen *= 2;
    };
    assert_eq!(r.stderr.matches("came with 8 bytes, its mapping makes 1").count(), 1, "{}", r.stderr);
    assert_eq!(r.stdout.lines().count(), 1, "only the header: nothing decoded as garbage");
}

/// `canctl monitor` on the sim, streaming until `done`, shown each line as it comes, says
/// it has seen enough (or a generous bound passes), then stopped. Waits for the events,
/// not for a time window.
fn monitor_until(sim: &Sim, args: &[&str], mut done: impl FnMut(&str) -> bool) -> Vec<String> {
    use std::io::BufRead;
    let mut child = sim.command(args).stdout(Stdio::piped()).stderr(Stdio::null()).spawn().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    let stdout = child.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in std::io::BufReader::new(stdout).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let give_up = Instant::now() + Duration::from_secs(60);
    let mut lines: Vec<String> = Vec::new();
    loop {
        let left = give_up.saturating_duration_since(Instant::now());
        match rx.recv_timeout(left) {
            Ok(line) => {
                let enough = done(&line);
                lines.push(line);
                if enough {
                    break;
                }
            }
            Err(_) => {
                let _ = child.kill();
                panic!("monitor ended or stalled before the events came:\n{}", lines.join("\n"));
            }
        }
    }
    let _ = child.kill();
    let _ = child.wait();
    lines
}

/// Arms the sensor's simulated fault. The sim network is one process at a time (a locked
/// state file), so the fault is armed before `monitor` starts, far enough ahead (3 s)
/// that the monitor is listening when it strikes.
fn arm_the_sensors_fault(sim: &Sim) {
    sim.run(&["nmt", "start", "5"]).ok();
    sim.run(&["sdo", "write", "5", "5FFE", "3000", "--type", "u16"]).ok();
}

#[test]
fn monitor_decodes_an_emcy_and_a_heartbeat_state_change() {
    let sim = Sim::new();
    arm_the_sensors_fault(&sim);
    let parse = |lines: &[String]| -> Vec<serde_json::Value> {
        lines.iter().map(|l| serde_json::from_str(l).unwrap()).collect()
    };
    // Until the EMCY and a pre-operational heartbeat after it.
    let mut emcy_seen = false;
    let lines = monitor_until(&sim, &["monitor", "--node", "5", "--format", "json"], |line| {
        let e: serde_json::Value = serde_json::from_str(line).unwrap();
        emcy_seen |= e["kind"] == "emcy";
        emcy_seen && e["kind"] == "heartbeat" && e["state"] == "pre-operational"
    });
    let events = parse(&lines);
    let states: Vec<&str> =
        events.iter().filter(|e| e["kind"] == "heartbeat").map(|e| e["state"].as_str().unwrap()).collect();
    let emcy = events.iter().position(|e| e["kind"] == "emcy").expect("an EMCY");
    assert_eq!(events[emcy]["code"], "0x5000");
    assert_eq!(events[emcy]["meaning"], "Device hardware");
    assert_eq!(events[emcy]["register"], 0x81);
    assert_eq!(events[emcy]["register_bits"], serde_json::json!(["generic", "manufacturer"]));
    assert_eq!(events[emcy]["node"], 5);
    assert_eq!(states.first(), Some(&"operational"), "{lines:?}");
    assert_eq!(states.last(), Some(&"pre-operational"));
    // Before the EMCY operational, after it pre-operational (CiA 301 error behaviour).
    assert!(events[..emcy].iter().filter(|e| e["kind"] == "heartbeat").all(|e| e["state"] == "operational"));

    // The same in human form.
    let sim2 = Sim::new();
    arm_the_sensors_fault(&sim2);
    let mut emcy_seen = false;
    let lines = monitor_until(&sim2, &["monitor", "--node", "5"], |line| {
        emcy_seen |= line.contains("emcy");
        emcy_seen && line.contains("heartbeat     pre-operational")
    });
    assert!(
        lines
            .iter()
            .any(|l| l.contains("emcy          0x5000 Device hardware; error register 0x81 [generic, manufacturer]")),
        "{lines:?}"
    );
}

#[test]
fn monitor_ends_with_a_summary() {
    let sim = Sim::new();
    // Three frames of node 5: its heartbeats, whenever they come.
    let r = sim.run(&["monitor", "--node", "5", "--count", "3", "--format", "json"]).ok();
    let events: Vec<serde_json::Value> = r.stdout.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    assert_eq!(events.len(), 4, "three frames and the summary");
    assert!(events[..3].iter().all(|e| e["kind"] == "heartbeat" && e["node"] == 5), "{}", r.stdout);
    let summary = &events[3]["summary"];
    assert_eq!(summary["frames"], 3);
    assert_eq!(summary["per_cob_id"], serde_json::json!({ "0x705": 3 }));
    assert_eq!(summary["nodes"], serde_json::json!([5]));
    assert_eq!(summary["emcy"], 0);
    let r = sim.run(&["monitor", "--node", "5", "--count", "2"]).ok();
    assert!(
        r.stderr.contains("2 frame(s) in") && r.stderr.contains("705×2") && r.stderr.contains("EMCYs: 0"),
        "{}",
        r.stderr
    );
}

/// Every CSV has a header row, and every stream's time column is one convention: Unix
/// time in seconds, to the millisecond (as stream-pdo's and drive status --watch's).
#[test]
fn monitor_csv_has_a_header_and_unix_time_as_stream_pdo() {
    let sim = Sim::new();
    let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap().as_secs_f64();
    let r = sim.run(&["monitor", "--node", "5", "--count", "2", "--format", "csv"]).ok();
    let lines: Vec<&str> = r.stdout.lines().collect();
    assert_eq!(lines.len(), 3, "{}", r.stdout);
    assert_eq!(lines[0], "time,cob,node,kind,text");
    let pdo = sim.run(&["stream-pdo", "5", "--start", "--count", "1", "--format", "csv"]).ok();
    assert!(pdo.stdout.starts_with("time,pdo,"), "{}", pdo.stdout);
    for row in [lines[1], lines[2], pdo.stdout.lines().nth(1).unwrap()] {
        let time: f64 = row.split(',').next().unwrap().parse().unwrap();
        // Unix time: after this test began, within the hour (not seconds since the start).
        assert!(time >= now.floor() && time < now + 3600.0, "{row} (now {now})");
    }
    let json = sim.run(&["monitor", "--node", "5", "--count", "1", "--format", "json"]).ok();
    let first: serde_json::Value = serde_json::from_str(json.stdout.lines().next().unwrap()).unwrap();
    assert!(first["time"].as_f64().unwrap() >= now.floor(), "{first}");
}

#[test]
fn monitor_through_an_epos2_says_why_not() {
    let sim = Sim::new();
    let dev = common::DeviceSide::start(&sim, "--epos2-usb", &[]);
    let r = dev.run(&["monitor", "--duration", "100ms"]);
    assert_eq!(r.code, 2);
    assert!(r.stderr.contains("shows no bus traffic"), "{}", r.stderr);
}

#[test]
fn the_io_modules_fault_is_an_emcy_recorded_in_its_history() {
    let sim = Sim::new();
    let older = sim.run(&["sdo", "read", "10", "1003:2", "--type", "u32"]).ok().stdout;
    // Armed 3 s ahead, so that the monitor is listening when it strikes. In pre-operational
    // the module sends nothing else, so its first frame is the EMCY; the monitor ends
    // there (and the sim keeps what happened), or after a generous bound.
    sim.run(&["sdo", "write", "10", "5FFE", "3000", "--type", "u16"]).ok();
    let r = sim.run(&["monitor", "--node", "10", "--count", "1", "--duration", "60s", "--format", "json"]).ok();
    let emcy: serde_json::Value = r
        .stdout
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
        .find(|e| e["kind"] == "emcy")
        .expect("an EMCY");
    // Seed 004: "81 10 11 06 .. CAN Controller Overrun".
    assert_eq!(
        (emcy["code"].as_str(), emcy["register"].as_u64(), emcy["vendor"].as_str()),
        (Some("0x8110"), Some(0x11), Some("0600000000"))
    );
    assert_eq!(emcy["register_bits"], serde_json::json!(["generic", "communication"]));
    assert_eq!(sim.run(&["sdo", "read", "10", "1003:0"]).ok().stdout.trim(), "3");
    assert_eq!(
        sim.run(&["sdo", "read", "10", "1003:1", "--type", "u32"]).ok().stdout.trim(),
        (0x0006_8110u32).to_string()
    );
    assert_eq!(sim.run(&["sdo", "read", "10", "1003:3", "--type", "u32"]).ok().stdout, older, "the history moved down");
    assert_eq!(sim.run(&["sdo", "read", "10", "1001"]).ok().stdout.trim(), "17");
}

/// A pre-operational node sends no PDOs: the stream says so, and why, instead of waiting in
/// silence.
#[test]
fn a_silent_stream_says_why() {
    let sim = Sim::new();
    let r = sim.run(&["stream-pdo", "5", "--duration", "2s"]).ok();
    assert!(r.stderr.contains("nothing from node 5 after"), "{}", r.stderr);
    assert!(r.stderr.contains("node 5 is pre-operational") && r.stderr.contains("--start"), "{}", r.stderr);
    let sync = sim.run(&["stream-pdo", "10", "--start", "--sync", "10ms", "--duration", "2s"]).ok();
    assert!(
        sync.stderr.contains("event-driven") && sync.stderr.contains("--sync does not make it send"),
        "{}",
        sync.stderr
    );
}

/// A device whose mapping is read-only refuses `--map` part-way (the sensor's 0x1A00 is
/// fixed, as on the MH sensor): the TPDO it switched off for the remapping is switched on
/// again, the transmission type put back, and the command says so.
#[test]
fn a_refused_map_puts_the_tpdo_back() {
    let sim = Sim::new();
    let read = |o: &str| sim.run(&["sdo", "read", "5", o]).ok().stdout;
    let before: Vec<String> = ["1800:1", "1800:2", "1A00:0", "1A00:1"].iter().map(|o| read(o)).collect();
    let r = sim.run(&["stream-pdo", "5", "--map", "6064:0", "--count", "1"]);
    assert_eq!(r.code, 4, "{}", r.stderr);
    assert!(r.stderr.contains("0x06010002"), "{}", r.stderr);
    assert!(r.stderr.contains("put back node 5's TPDO1"), "{}", r.stderr);
    let after: Vec<String> = ["1800:1", "1800:2", "1A00:0", "1A00:1"].iter().map(|o| read(o)).collect();
    assert_eq!(after, before);
    // The TPDO still streams.
    let again = sim.run(&["stream-pdo", "5", "--start", "--count", "1"]);
    assert_eq!(again.code, 0, "{}", again.stderr);
}

/// `--sync` does nothing for an event-driven TPDO: said before the stream, not only when
/// it is silent.
#[test]
fn sync_for_an_event_driven_tpdo_is_warned_about() {
    let sim = Sim::new();
    let r = sim.run(&["stream-pdo", "5", "--start", "--sync", "10ms", "--count", "3"]).ok();
    assert!(
        r.stderr.contains("warning: --sync does not drive node 5's TPDO1: transmission type 254 (event-driven)"),
        "{}",
        r.stderr
    );
    let plain = sim.run(&["stream-pdo", "5", "--start", "--count", "3"]).ok();
    assert!(!plain.stderr.contains("--sync"), "{}", plain.stderr);
}

/// A device that refuses the writes that would put its mapping back: the command says
/// what was not put back and how to recover, and the NMT state goes back all the same.
#[test]
fn a_mapping_that_cannot_be_put_back_is_said_and_the_state_still_goes_back() {
    let sim = Sim::new();
    // Node 1's 17th SDO request on is refused: the first write of the putting back.
    sim.run(&["sim", "reset", "--fault", "1:abort=0x08000020@17+"]).ok();
    let r = sim.run(&["stream-pdo", "1", "--start", "--map", "6064:0", "--event", "10", "--count", "1"]);
    assert_eq!(r.code, 4, "{}", r.stderr);
    assert!(r.stderr.contains("TPDO1 was not put back") && r.stderr.contains("canctl restore 1"), "{}", r.stderr);
    assert!(sim.run(&["nmt", "state", "1"]).ok().stdout.contains("pre-operational"));
}
