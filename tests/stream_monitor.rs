//! stream-pdo and monitor with the real binary on the simulated network.

mod common;

use common::{scenarios, Sim};

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
    let r = sim.run(&["stream-pdo", "10", "--start", "--duration", "150ms", "--format", "csv"]).ok();
    assert_eq!(r.stderr.matches("came with 8 bytes, its mapping makes 1").count(), 1, "{}", r.stderr);
    assert_eq!(r.stdout.lines().count(), 1, "only the header: nothing decoded as garbage");
}

#[test]
fn monitor_decodes_an_emcy_and_a_heartbeat_state_change() {
    let sim = Sim::new();
    sim.run(&["nmt", "start", "5"]).ok();
    // The simulated sensor loses its magnet 250 ms from now.
    sim.run(&["sdo", "write", "5", "5FFE", "250", "--type", "u16"]).ok();
    let r = sim.run(&["monitor", "--node", "5", "--duration", "600ms", "--format", "json"]).ok();
    let events: Vec<serde_json::Value> = r.stdout.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    let states: Vec<&str> =
        events.iter().filter(|e| e["kind"] == "heartbeat").map(|e| e["state"].as_str().unwrap()).collect();
    let emcy = events.iter().position(|e| e["kind"] == "emcy").expect("an EMCY");
    assert_eq!(events[emcy]["code"], "0x5000");
    assert_eq!(events[emcy]["meaning"], "Device hardware");
    assert_eq!(events[emcy]["register"], 0x81);
    assert_eq!(events[emcy]["register_bits"], serde_json::json!(["generic", "manufacturer"]));
    assert_eq!(states.first(), Some(&"operational"));
    assert_eq!(states.last(), Some(&"pre-operational"));
    let summary = &events.last().unwrap()["summary"];
    assert_eq!(summary["emcy"], 1);
    assert_eq!(summary["nodes"], serde_json::json!([5]));
    // The same in human form; clearing the fault reports "error reset".
    let sim2 = Sim::new();
    sim2.run(&["nmt", "start", "5"]).ok();
    sim2.run(&["sdo", "write", "5", "5FFE", "200", "--type", "u16"]).ok();
    let r = sim2.run(&["monitor", "--node", "5", "--duration", "500ms"]).ok();
    assert!(
        r.stdout.contains("emcy          0x5000 Device hardware; error register 0x81 [generic, manufacturer]"),
        "{}",
        r.stdout
    );
    assert!(r.stdout.contains("heartbeat     pre-operational"));
    assert!(r.stderr.contains("EMCYs: 1"), "{}", r.stderr);
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
    sim.run(&["sdo", "write", "10", "5FFE", "150", "--type", "u16"]).ok();
    let r = sim.run(&["monitor", "--node", "10", "--duration", "400ms", "--format", "json"]).ok();
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
