//! The foundation's promises, shown with the real binary on the simulated network.

mod common;

use common::{bare, Sim};
use std::time::{Duration, Instant};

#[test]
fn scan_lists_the_demo_nodes_with_their_identities() {
    let sim = Sim::new();
    let json = sim.run(&["scan", "--format", "json"]).ok().json();
    let nodes = json["nodes"].as_array().unwrap();
    let ids: Vec<u64> = nodes.iter().map(|n| n["node"].as_u64().unwrap()).collect();
    assert_eq!(ids, [1, 5, 10, 32]);
    let n1 = &nodes[0];
    assert_eq!(n1["device_type"], 0x0002_0192);
    assert_eq!(n1["vendor_id"], 0xFB);
    assert_eq!(n1["name"], "EPOS2 24/5");
    let n5 = &nodes[1];
    assert_eq!(n5["vendor_id"], 0x40);
    assert_eq!(n5["product_code"], 0x4378_7800);
    assert_eq!(n5["device_type"], 0x000A_0196);
    assert_eq!(n5["name"], "C01");
    // The sensor's heartbeat shows its state; the others send none.
    assert_eq!(n5["state"], "pre-operational");
    assert_eq!(nodes[2]["state"], serde_json::Value::Null);
    assert_eq!(nodes[2]["name"], "CAN-2057C");
    // The SERS stepper has an identity object without entries (seed 003).
    assert_eq!(nodes[3]["device_type"], 0x0004_0192);
    assert_eq!(nodes[3]["vendor_id"], serde_json::Value::Null);

    // The same in the human table and in CSV.
    let human = sim.run(&["scan"]).ok().stdout;
    for needle in ["0x000000FB", "0x43787800", "CAN-2057C", "SERS-CAN", "pre-operational"] {
        assert!(human.contains(needle), "{needle} missing from\n{human}");
    }
    let csv = sim.run(&["scan", "--format", "csv"]).ok().stdout;
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "node,device_type,vendor_id,product_code,revision,serial,name,state");
    assert_eq!(lines.len(), 5);
    assert!(lines[1].starts_with("1,0x00020192,0x000000FB,"));
}

#[test]
fn every_data_type_round_trips() {
    let sim = Sim::new();
    let cases = [
        ("1", "b", "false"),
        ("2", "u8", "200"),
        ("3", "u16", "65535"),
        ("4", "u32", "0xDEADBEEF"),
        ("5", "u64", "18446744073709551615"),
        ("6", "i8", "-128"),
        ("7", "i16", "-32768"),
        ("8", "i32", "-2147483648"),
        ("9", "i64", "-9223372036854775808"),
        ("10", "r32", "-3.25"),
        ("11", "r64", "6.02214076e23"),
        ("12", "vs", "a visible string longer than four bytes"),
        ("13", "os", "0102030405060708090A"),
        ("14", "d", "FFEEDDCCBBAA"),
    ];
    for (sub, t, value) in cases {
        let obj = format!("5FF0:{sub}");
        sim.run(&["sdo", "write", "1", &obj, value, "--type", t]).ok();
        let got = sim.run(&["sdo", "read", "1", &obj, "--type", t, "--format", "json"]).ok().json();
        let want =
            sim.run(&["sdo", "write", "1", &obj, value, "--type", t, "--verify", "--format", "json"]).ok().json();
        assert_eq!(got["value"], want["value"], "{t}");
        assert_eq!(want["verified"], true);
    }
    assert_eq!(sim.run(&["sdo", "read", "1", "5FF0:4", "--type", "u32"]).ok().stdout.trim(), "3735928559");
    assert_eq!(sim.run(&["sdo", "read", "1", "5FF0:10", "--type", "r32"]).ok().stdout.trim(), "-3.25");
    assert_eq!(sim.run(&["sdo", "read", "1", "5FF0:6", "--type", "i8"]).ok().stdout.trim(), "-128");
}

#[test]
fn untyped_reads_show_bytes_and_the_plain_reading() {
    let sim = Sim::new();
    let out = sim.run(&["sdo", "read", "1", "0x1000:0"]).ok().stdout;
    assert_eq!(out.trim(), "92 01 02 00  (u32 131474 = 0x00020192)");
    let json = sim.run(&["sdo", "read", "1", "1000", "--format", "json"]).ok().json();
    assert_eq!(json["raw"], "92010200");
    assert_eq!(json["value"], 131474);
}

#[test]
fn a_long_name_comes_back_whole_by_segmented_transfer() {
    let sim = Sim::new();
    let out = sim.run(&["-v", "sdo", "read", "10", "1008", "--type", "vs"]).ok();
    assert_eq!(out.stdout.trim(), "CAN-2057C");
    // 0x41: initiate answer of a segmented upload, size indicated.
    assert!(out.stderr.contains("58A   [8]  41 08 10 00 09 00 00 00"), "{}", out.stderr);
}

fn trace_has(stderr: &str, prefix: &str) -> bool {
    stderr.lines().any(|l| l.trim_start().starts_with(prefix))
}

#[test]
fn the_64k_domain_moves_byte_exact_by_block_and_by_segmented() {
    let sim = Sim::new();
    let original = sim.path("original.bin");
    let out = sim.run(&["-v", "sdo", "read", "1", "1F50:1", "--type", "d", "--out", original.to_str().unwrap()]).ok();
    let data = std::fs::read(&original).unwrap();
    assert_eq!(data.len(), 65536);
    // Block upload initiate (0xA4) and the server's block answer (0xC6).
    assert!(trace_has(&out.stderr, "sim  601   [8]  A4 50 1F 01"), "no block upload");
    assert!(trace_has(&out.stderr, "sim  581   [8]  C6 50 1F 01 00 00 01 00"));

    // Write a different 64 KiB image by block, read it back by segmented.
    let image: Vec<u8> = (0..65536u32).map(|i| (i.wrapping_mul(2654435761) >> 13) as u8).collect();
    let image_file = sim.path("image.bin");
    std::fs::write(&image_file, &image).unwrap();
    let at = format!("@{}", image_file.display());
    let out = sim.run(&["-v", "sdo", "write", "1", "1F50:1", &at, "--type", "d", "--verify"]).ok();
    assert!(trace_has(&out.stderr, "sim  601   [8]  C6 50 1F 01 00 00 01 00"), "no block download");
    let back = sim.path("back.bin");
    let out = sim
        .run(&["-v", "sdo", "read", "1", "1F50:1", "--type", "d", "--no-block", "--out", back.to_str().unwrap()])
        .ok();
    assert!(!trace_has(&out.stderr, "sim  601   [8]  A4"), "--no-block used block transfer");
    assert!(trace_has(&out.stderr, "sim  581   [8]  41 50 1F 01 00 00 01 00"));
    assert_eq!(std::fs::read(&back).unwrap(), image);

    // And the original back by segmented download, read by block.
    let at = format!("@{}", original.display());
    let out = sim.run(&["-v", "sdo", "write", "1", "1F50:1", &at, "--type", "d", "--no-block"]).ok();
    assert!(trace_has(&out.stderr, "sim  601   [8]  21 50 1F 01 00 00 01 00"));
    sim.run(&["sdo", "read", "1", "1F50:1", "--type", "d", "--out", back.to_str().unwrap()]).ok();
    assert_eq!(std::fs::read(&back).unwrap(), data);
}

#[test]
fn a_device_without_block_transfer_is_read_all_the_same() {
    let sim = Sim::new();
    let out = sim.run(&["-v", "sdo", "read", "5", "1008", "--type", "vs"]).ok();
    assert_eq!(out.stdout.trim(), "C01");
    // Asked for block, refused with 0x05040001, then read plainly.
    assert!(trace_has(&out.stderr, "sim  585   [8]  80 08 10 00 01 00 04 05"), "{}", out.stderr);
}

#[test]
fn refusals_carry_the_abort_code_and_its_meaning() {
    let sim = Sim::new();
    let r = sim.run(&["sdo", "write", "1", "1000", "5", "--type", "u32"]);
    assert_eq!(r.code, 4);
    assert!(
        r.stderr.contains("0x06010002") && r.stderr.contains("Attempt to write a read only object"),
        "{}",
        r.stderr
    );
    assert!(r.stderr.contains("node 1") && r.stderr.contains("0x1000:0"));
    let r = sim.run(&["sdo", "read", "1", "2222"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("0x06020000"), "{}", r.stderr);
    let r = sim.run(&["sdo", "read", "1", "1018:9"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("0x06090011") && r.stderr.contains("Sub-index does not exist"));
    let r = sim.run(&["sdo", "read", "1", "5FF0:15"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("Attempt to read a write only object"));
    let r = sim.run(&["sdo", "write", "1", "6060", "9", "--type", "i8"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("0x06090031"), "{}", r.stderr);
    let r = sim.run(&["sdo", "write", "1", "6060", "1", "--type", "u16"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("0x06070012"), "{}", r.stderr);
}

#[test]
fn an_absent_node_times_out_with_exit_3() {
    let sim = Sim::new();
    let start = Instant::now();
    let r = sim.run(&["--timeout", "200ms", "sdo", "read", "77", "1000"]);
    assert_eq!(r.code, 3);
    assert!(r.stderr.contains("node 77") && r.stderr.contains("did not answer"), "{}", r.stderr);
    // It gives up after the timeout, not after some fixed long wait.
    assert!(start.elapsed() < Duration::from_secs(5));
}

#[test]
fn malformed_input_is_a_usage_error_with_a_pointed_message() {
    let sim = Sim::new();
    let cases: &[(&[&str], &str)] = &[
        (&["sdo", "read", "1", "10180:1"], "1 to 4 hex digits"),
        (&["sdo", "read", "1", "1018:300"], "0..255"),
        (&["sdo", "read", "0", "1000"], "0 is only for an EPOS2"),
        (&["sdo", "read", "128", "1000"], "not a node-id"),
        (&["sdo", "read", "1", "1000", "--type", "u24"], "not a data type"),
        (&["sdo", "write", "1", "5FF0:2", "300", "--type", "u8"], "out of range for u8 (0..=255)"),
        (&["sdo", "write", "1", "5FF0:3", "12abc", "--type", "u16"], "not a valid u16"),
        (&["sdo", "write", "1", "5FF0:13", "abc", "--type", "os"], "odd number of hex digits"),
        (&["sdo", "write", "1", "5FF0:3", "12"], "--type is needed"),
        (&["sdo", "write", "1", "5FF0:13", "@/nonexistent/file", "--type", "os"], "cannot read /nonexistent/file"),
        (&["sdo", "read", "1", "1000", "--type", "u16"], "not a u16"),
        (&["nmt", "stop", "200"], "1..127, or all"),
        (&["--timeout", "soon", "scan"], "not a duration"),
    ];
    for (args, needle) in cases {
        let r = sim.run(args);
        assert_eq!(r.code, 2, "{args:?}: {}", r.stderr);
        assert!(r.stderr.contains(needle), "{args:?}: expected '{needle}' in {}", r.stderr);
    }
}

#[test]
fn verify_catches_a_device_that_ignores_the_write() {
    // Seed 003: the SERS accepts any 0x1006 value but always reads 2000.
    let sim = Sim::new();
    let r = sim.run(&["sdo", "write", "32", "1006", "1000", "--type", "u32", "--verify"]);
    assert_eq!(r.code, 6, "{}", r.stderr);
    assert!(r.stderr.contains("reads back 2000 after writing 1000"));
}

#[test]
fn nmt_stop_state_and_reset() {
    let sim = Sim::new();
    assert_eq!(sim.run(&["nmt", "stop", "5"]).ok().stdout.trim(), "NMT stop sent to node 5");
    let state = sim.run(&["nmt", "state", "5", "--format", "json"]).ok().json();
    assert_eq!(state["state"], "stopped");
    assert_eq!(state["source"], "heartbeat");
    // Stopped nodes do not serve SDO.
    assert_eq!(sim.run(&["--timeout", "100ms", "sdo", "read", "5", "1000"]).code, 3);
    let reset = sim.run(&["-v", "nmt", "reset", "5", "--format", "json"]).ok();
    assert!(trace_has(&reset.stderr, "sim  000   [2]  81 05"));
    assert!(trace_has(&reset.stderr, "sim  705   [1]  00"), "no boot-up seen: {}", reset.stderr);
    assert_eq!(reset.json()["booted"], serde_json::json!([5]));
    assert!(sim.run(&["nmt", "state", "5"]).ok().stdout.contains("pre-operational"));
    sim.run(&["nmt", "start", "5"]).ok();
    assert!(sim.run(&["nmt", "state", "5"]).ok().stdout.contains("operational"));
}

#[test]
fn nmt_state_falls_back_to_node_guarding_with_toggle() {
    let sim = Sim::new();
    sim.run(&["nmt", "stop", "32"]).ok();
    let r = sim.run(&["-v", "nmt", "state", "32", "--listen", "50ms"]).ok();
    assert_eq!(r.stdout.trim(), "node 32: stopped (from node guarding)");
    assert!(trace_has(&r.stderr, "sim  720   [1]  remote request"));
    assert!(trace_has(&r.stderr, "sim  720   [1]  04"));
}

#[test]
fn nmt_all_is_the_only_broadcast() {
    let sim = Sim::new();
    let r = sim.run(&["-v", "nmt", "reset-comm", "all", "--format", "json"]).ok();
    assert!(trace_has(&r.stderr, "sim  000   [2]  82 00"));
    assert_eq!(r.json()["booted"], serde_json::json!([1, 5, 10, 32]));
    let r = sim.run(&["-v", "nmt", "stop", "10"]).ok();
    assert!(trace_has(&r.stderr, "sim  000   [2]  02 0A"));
    let r = sim.run(&["nmt", "stop"]);
    assert_eq!(r.code, 2);
}

#[test]
fn store_and_restore_survive_resets_as_on_hardware() {
    let sim = Sim::new();
    let hb = |sim: &Sim| sim.run(&["sdo", "read", "5", "1017", "--type", "u16"]).ok().stdout.trim().to_string();
    sim.run(&["sdo", "write", "5", "1017", "30", "--type", "u16"]).ok();
    sim.run(&["nmt", "reset", "5"]).ok();
    assert_eq!(hb(&sim), "40", "an unsaved value is lost on reset");
    sim.run(&["sdo", "write", "5", "1017", "30", "--type", "u16"]).ok();
    // 'save' = 0x65766173 to 0x1010:1
    sim.run(&["sdo", "write", "5", "1010:1", "0x65766173", "--type", "u32"]).ok();
    sim.run(&["nmt", "reset", "5"]).ok();
    assert_eq!(hb(&sim), "30", "a stored value survives reset");
    // A wrong signature is refused.
    let r = sim.run(&["sdo", "write", "5", "1010:1", "1", "--type", "u32"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("0x08000020"));
    // 'load' = 0x64616F6C to 0x1011:1: defaults after the next reset, not before.
    sim.run(&["sdo", "write", "5", "1011:1", "0x64616F6C", "--type", "u32"]).ok();
    assert_eq!(hb(&sim), "30");
    sim.run(&["nmt", "reset", "5"]).ok();
    assert_eq!(hb(&sim), "40");
}

#[test]
fn sim_reset_starts_afresh() {
    let sim = Sim::new();
    sim.run(&["sdo", "write", "1", "607A", "1234", "--type", "i32"]).ok();
    assert_eq!(sim.run(&["sdo", "read", "1", "607A", "--type", "i32"]).ok().stdout.trim(), "1234");
    sim.run(&["sim", "reset"]).ok();
    assert_eq!(sim.run(&["sdo", "read", "1", "607A", "--type", "i32"]).ok().stdout.trim(), "0");
}

#[test]
fn without_a_bus_it_says_how_to_pick_one() {
    let r = bare(&["scan"]);
    assert_eq!(r.code, 2);
    for needle in ["no bus given", "CAN interfaces here", "serial ports here", "--bus sim"] {
        assert!(r.stderr.contains(needle), "{needle}: {}", r.stderr);
    }
}

#[test]
fn unusable_buses_fail_as_link_errors() {
    for (bus, needle) in [
        ("socketcan:vcan0", "no SocketCAN backend yet"),
        ("can0", "no SocketCAN backend yet"),
        ("epos2-rs232:/dev/nonexistent-tty", "cannot open /dev/nonexistent-tty"),
        ("epos2-usb:/dev/nonexistent-tty", "cannot open /dev/nonexistent-tty"),
    ] {
        let r = bare(&["--bus", bus, "scan"]);
        assert_eq!(r.code, 5, "{bus}");
        assert!(r.stderr.contains(needle), "{bus}: {}", r.stderr);
    }
    let r = bare(&["--bus", "/dev/ttyUSB0", "scan"]);
    assert_eq!(r.code, 2);
    assert!(r.stderr.contains("epos2-rs232:/dev/ttyUSB0"));
}

#[test]
fn the_bus_can_come_from_the_environment() {
    let sim = Sim::new();
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_canctl"));
    c.env("CANCTL_BUS", sim.bus()).args(["sdo", "read", "1", "1000", "--type", "u32"]);
    let r = common::finish(c.output().unwrap()).ok();
    assert_eq!(r.stdout.trim(), "131474");
}

#[test]
fn a_closed_pipe_ends_quietly() {
    use std::process::Stdio;
    let sim = Sim::new();
    let mut child = sim.command(&["scan"]).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(out.status.code(), Some(0), "{stderr}");
}
