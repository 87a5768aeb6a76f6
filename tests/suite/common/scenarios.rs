//! What every bus that reaches the demo network's devices must show, whatever carries the
//! frames: the built-in sim bus, or the kernel's vcan with `canctl sim --socketcan`.

use super::{Run, Sim};
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// A bus under test: runs canctl on it, names it in traces, gives scratch files.
pub trait Under {
    fn run(&self, args: &[&str]) -> Run;
    /// The interface name in `-v` traces.
    fn iface(&self) -> &str;
    fn path(&self, name: &str) -> PathBuf;
    /// canctl on this bus, to spawn.
    fn command(&self, args: &[&str]) -> std::process::Command;
    /// The fastscan step for this bus.
    fn lss_step(&self) -> &'static str {
        "10ms"
    }
}

impl Under for Sim {
    fn run(&self, args: &[&str]) -> Run {
        Sim::run(self, args)
    }
    fn iface(&self) -> &str {
        "sim"
    }
    fn path(&self, name: &str) -> PathBuf {
        Sim::path(self, name)
    }
    fn command(&self, args: &[&str]) -> std::process::Command {
        Sim::command(self, args)
    }
}

/// A `-v` trace line for a frame on this bus, as candump prints it.
fn trace_has(bus: &dyn Under, stderr: &str, rest: &str) -> bool {
    let prefix = format!("{}  {rest}", bus.iface());
    stderr.lines().any(|l| l.trim_start().starts_with(&prefix))
}

pub fn scan_lists_the_demo_nodes_with_their_identities(bus: &dyn Under) {
    let json = bus.run(&["scan", "--format", "json"]).ok().json();
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
    // The sensor's heartbeat shows its state; the others send none and are asked by node
    // guarding.
    assert_eq!(n5["state"], "pre-operational");
    assert_eq!(n5["state_from"], "heartbeat");
    assert_eq!(nodes[2]["state"], "pre-operational");
    assert_eq!(nodes[2]["state_from"], "node guarding");
    assert_eq!(nodes[2]["name"], "CAN-2057C");
    // The SERS stepper has an identity object without entries (seed 003).
    assert_eq!(nodes[3]["device_type"], 0x0004_0192);
    assert_eq!(nodes[3]["vendor_id"], serde_json::Value::Null);

    // The same in the human table and in CSV.
    let human = bus.run(&["scan"]).ok().stdout;
    for needle in ["0x000000FB", "0x43787800", "CAN-2057C", "SERS-CAN", "pre-operational"] {
        assert!(human.contains(needle), "{needle} missing from\n{human}");
    }
    let csv = bus.run(&["scan", "--format", "csv"]).ok().stdout;
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "node,device_type,vendor_id,product_code,revision,serial,name,state");
    assert_eq!(lines.len(), 5);
    assert!(lines[1].starts_with("1,0x00020192,0x000000FB,"));
}

pub fn every_data_type_round_trips(bus: &dyn Under) {
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
        bus.run(&["sdo", "write", "1", &obj, value, "--type", t]).ok();
        let got = bus.run(&["sdo", "read", "1", &obj, "--type", t, "--format", "json"]).ok().json();
        let want =
            bus.run(&["sdo", "write", "1", &obj, value, "--type", t, "--verify", "--format", "json"]).ok().json();
        assert_eq!(got["value"], want["value"], "{t}");
        assert_eq!(want["verified"], true);
    }
    assert_eq!(bus.run(&["sdo", "read", "1", "5FF0:4", "--type", "u32"]).ok().stdout.trim(), "3735928559");
    assert_eq!(bus.run(&["sdo", "read", "1", "5FF0:10", "--type", "r32"]).ok().stdout.trim(), "-3.25");
    assert_eq!(bus.run(&["sdo", "read", "1", "5FF0:6", "--type", "i8"]).ok().stdout.trim(), "-128");
}

pub fn untyped_reads_show_bytes_and_the_plain_reading(bus: &dyn Under) {
    // 0x5FF0:4 is in no dictionary: raw bytes and the plain unsigned reading.
    let out = bus.run(&["sdo", "read", "1", "0x5FF0:4"]).ok().stdout;
    assert_eq!(out.trim(), "78 56 34 12  (u32 305419896 = 0x12345678)");
    let json = bus.run(&["sdo", "read", "1", "5FF0:4", "--format", "json"]).ok().json();
    assert_eq!(json["raw"], "78563412");
    assert_eq!(json["value"], 0x1234_5678);
    assert_eq!(json["type"], serde_json::Value::Null);
    // 0x1000 is in the built-in dictionary: its type comes from there.
    let json = bus.run(&["sdo", "read", "1", "1000", "--format", "json"]).ok().json();
    assert_eq!((json["type"].as_str(), json["name"].as_str()), (Some("u32"), Some("Device type")));
    assert_eq!(json["value"], 131474);
}

pub fn a_long_name_comes_back_whole_by_segmented_transfer(bus: &dyn Under) {
    let out = bus.run(&["-v", "sdo", "read", "10", "1008", "--type", "vs"]).ok();
    assert_eq!(out.stdout.trim(), "CAN-2057C");
    // 0x41: initiate answer of a segmented upload, size indicated.
    assert!(out.stderr.contains("58A   [8]  41 08 10 00 09 00 00 00"), "{}", out.stderr);
}

pub fn the_64k_domain_moves_byte_exact_by_block_and_by_segmented(bus: &dyn Under) {
    let original = bus.path("original.bin");
    let out = bus.run(&["-v", "sdo", "read", "1", "1F50:1", "--type", "d", "--out", original.to_str().unwrap()]).ok();
    let data = std::fs::read(&original).unwrap();
    assert_eq!(data.len(), 65536);
    // Block upload initiate (0xA4) and the server's block answer (0xC6).
    assert!(trace_has(bus, &out.stderr, "601   [8]  A4 50 1F 01"), "no block upload");
    assert!(trace_has(bus, &out.stderr, "581   [8]  C6 50 1F 01 00 00 01 00"));

    // Write a different 64 KiB image by block, read it back by segmented.
    let image: Vec<u8> = (0..65536u32).map(|i| (i.wrapping_mul(2654435761) >> 13) as u8).collect();
    let image_file = bus.path("image.bin");
    std::fs::write(&image_file, &image).unwrap();
    let at = format!("@{}", image_file.display());
    let out = bus.run(&["-v", "sdo", "write", "1", "1F50:1", &at, "--type", "d", "--verify"]).ok();
    assert!(trace_has(bus, &out.stderr, "601   [8]  C6 50 1F 01 00 00 01 00"), "no block download");
    let back = bus.path("back.bin");
    let out = bus
        .run(&["-v", "sdo", "read", "1", "1F50:1", "--type", "d", "--no-block", "--out", back.to_str().unwrap()])
        .ok();
    assert!(!trace_has(bus, &out.stderr, "601   [8]  A4"), "--no-block used block transfer");
    assert!(trace_has(bus, &out.stderr, "581   [8]  41 50 1F 01 00 00 01 00"));
    assert_eq!(std::fs::read(&back).unwrap(), image);

    // And the original back by segmented download, read by block.
    let at = format!("@{}", original.display());
    let out = bus.run(&["-v", "sdo", "write", "1", "1F50:1", &at, "--type", "d", "--no-block"]).ok();
    assert!(trace_has(bus, &out.stderr, "601   [8]  21 50 1F 01 00 00 01 00"));
    bus.run(&["sdo", "read", "1", "1F50:1", "--type", "d", "--out", back.to_str().unwrap()]).ok();
    assert_eq!(std::fs::read(&back).unwrap(), data);
}

pub fn a_device_without_block_transfer_is_read_all_the_same(bus: &dyn Under) {
    let out = bus.run(&["-v", "sdo", "read", "5", "1008", "--type", "vs"]).ok();
    assert_eq!(out.stdout.trim(), "C01");
    // Asked for block, refused with 0x05040001, then read plainly.
    assert!(trace_has(bus, &out.stderr, "585   [8]  80 08 10 00 01 00 04 05"), "{}", out.stderr);
}

pub fn refusals_carry_the_abort_code_and_its_meaning(bus: &dyn Under) {
    let r = bus.run(&["sdo", "write", "1", "1000", "5", "--type", "u32"]);
    assert_eq!(r.code, 4);
    assert!(
        r.stderr.contains("0x06010002") && r.stderr.contains("Attempt to write a read only object"),
        "{}",
        r.stderr
    );
    assert!(r.stderr.contains("node 1") && r.stderr.contains("0x1000:0"));
    let r = bus.run(&["sdo", "read", "1", "2222"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("0x06020000"), "{}", r.stderr);
    let r = bus.run(&["sdo", "read", "1", "1018:9"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("0x06090011") && r.stderr.contains("Sub-index does not exist"));
    let r = bus.run(&["sdo", "read", "1", "5FF0:15"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("Attempt to read a write only object"));
    let r = bus.run(&["sdo", "write", "1", "6060", "9", "--type", "i8"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("0x06090031"), "{}", r.stderr);
    let r = bus.run(&["sdo", "write", "1", "6060", "1", "--type", "u16"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("0x06070012"), "{}", r.stderr);
}

pub fn an_absent_node_times_out_with_exit_3(bus: &dyn Under) {
    let start = Instant::now();
    let r = bus.run(&["--timeout", "200ms", "sdo", "read", "77", "1000"]);
    assert_eq!(r.code, 3);
    assert!(r.stderr.contains("node 77") && r.stderr.contains("did not answer"), "{}", r.stderr);
    // It gives up after the timeout, not after some fixed long wait.
    assert!(start.elapsed() < Duration::from_secs(5));
}

pub fn verify_catches_a_device_that_ignores_the_write(bus: &dyn Under) {
    // Seed 003: the SERS accepts any 0x1006 value but always reads 2000.
    let r = bus.run(&["sdo", "write", "32", "1006", "1000", "--type", "u32", "--verify"]);
    assert_eq!(r.code, 6, "{}", r.stderr);
    assert!(r.stderr.contains("reads back 2000 after writing 1000"));
}

pub fn nmt_stop_state_and_reset(bus: &dyn Under) {
    assert_eq!(bus.run(&["nmt", "stop", "5"]).ok().stdout.trim(), "NMT stop sent to node 5");
    let state = bus.run(&["nmt", "state", "5", "--listen", "5s", "--format", "json"]).ok().json();
    assert_eq!(state["state"], "stopped");
    assert_eq!(state["source"], "heartbeat");
    // Stopped nodes do not serve SDO.
    assert_eq!(bus.run(&["--timeout", "100ms", "sdo", "read", "5", "1000"]).code, 3);
    let reset = bus.run(&["-v", "nmt", "reset", "5", "--format", "json"]).ok();
    assert!(trace_has(bus, &reset.stderr, "000   [2]  81 05"));
    assert!(trace_has(bus, &reset.stderr, "705   [1]  00"), "no boot-up seen: {}", reset.stderr);
    assert_eq!(reset.json()["booted"], serde_json::json!([5]));
    assert!(bus.run(&["nmt", "state", "5"]).ok().stdout.contains("pre-operational"));
    bus.run(&["nmt", "start", "5"]).ok();
    assert!(bus.run(&["nmt", "state", "5"]).ok().stdout.contains("operational"));
}

pub fn nmt_state_falls_back_to_node_guarding_with_toggle(bus: &dyn Under) {
    bus.run(&["nmt", "stop", "32"]).ok();
    let r = bus.run(&["-v", "nmt", "state", "32", "--listen", "50ms"]).ok();
    assert_eq!(r.stdout.trim(), "node 32: stopped (from node guarding)");
    assert!(trace_has(bus, &r.stderr, "720   [1]  remote request"));
    assert!(trace_has(bus, &r.stderr, "720   [1]  04"));
}

pub fn nmt_all_is_the_only_broadcast(bus: &dyn Under) {
    let r = bus.run(&["-v", "nmt", "reset-comm", "all", "--format", "json"]).ok();
    assert!(trace_has(bus, &r.stderr, "000   [2]  82 00"));
    assert_eq!(r.json()["booted"], serde_json::json!([1, 5, 10, 32]));
    let r = bus.run(&["-v", "nmt", "stop", "10"]).ok();
    assert!(trace_has(bus, &r.stderr, "000   [2]  02 0A"));
    let r = bus.run(&["nmt", "stop"]);
    assert_eq!(r.code, 2);
}

pub fn store_and_restore_survive_resets_as_on_hardware(bus: &dyn Under) {
    let hb = |bus: &dyn Under| bus.run(&["sdo", "read", "5", "1017", "--type", "u16"]).ok().stdout.trim().to_string();
    bus.run(&["sdo", "write", "5", "1017", "30", "--type", "u16"]).ok();
    bus.run(&["nmt", "reset", "5"]).ok();
    assert_eq!(hb(bus), "40", "an unsaved value is lost on reset");
    bus.run(&["sdo", "write", "5", "1017", "30", "--type", "u16"]).ok();
    // 'save' = 0x65766173 to 0x1010:1
    bus.run(&["sdo", "write", "5", "1010:1", "0x65766173", "--type", "u32"]).ok();
    bus.run(&["nmt", "reset", "5"]).ok();
    assert_eq!(hb(bus), "30", "a stored value survives reset");
    // A wrong signature is refused.
    let r = bus.run(&["sdo", "write", "5", "1010:1", "1", "--type", "u32"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("0x08000020"));
    // 'load' = 0x64616F6C to 0x1011:1: defaults after the next reset, not before.
    bus.run(&["sdo", "write", "5", "1011:1", "0x64616F6C", "--type", "u32"]).ok();
    assert_eq!(hb(bus), "30");
    bus.run(&["nmt", "reset", "5"]).ok();
    assert_eq!(hb(bus), "40");
}

const SENSOR: &str = "0x40:0x43787800:0x312E3031:0x09501234";
const WAITING: [&str; 3] = ["0x09501301", "0x09501302", "0x09501303"];

pub fn lss_fastscan_and_assign_number_a_fresh_bus(bus: &dyn Under) {
    let scan = bus.run(&["scan", "--format", "json"]).ok().json();
    assert_eq!(scan["lss_unconfigured"], 3);
    let step = bus.lss_step();
    let found = bus.run(&["lss", "fastscan", "--step", step, "--format", "json"]).ok().json();
    assert_eq!(found["identity"], format!("0x00000040:0x43787800:0x312E3031:{}", WAITING[0]));
    // 133 fastscan requests for a whole identity; more when late answers made it search a
    // part again with a longer step.
    assert!(found["steps"].as_u64().unwrap() >= 133, "{found}");
    let assigned = bus.run(&["lss", "assign", "--start", "20", "--step", step, "--format", "json"]).ok().json();
    let rows = assigned["assigned"].as_array().unwrap();
    let got: Vec<(u64, String)> = rows
        .iter()
        .map(|r| (r["node"].as_u64().unwrap(), format!("0x{:08X}", r["lss"]["serial"].as_u64().unwrap())))
        .collect();
    let want: Vec<(u64, String)> = WAITING.iter().enumerate().map(|(i, s)| (20 + i as u64, s.to_string())).collect();
    assert_eq!(got, want);
    assert!(rows.iter().all(|r| r["stored"] == true));
    // They boot with their new node-ids and answer SDO with the right identity.
    let scan = bus.run(&["scan", "--format", "json"]).ok().json();
    assert_eq!(scan["lss_unconfigured"], 0);
    let nodes = scan["nodes"].as_array().unwrap();
    let ids: Vec<u64> = nodes.iter().map(|n| n["node"].as_u64().unwrap()).collect();
    assert_eq!(ids, [1, 5, 10, 20, 21, 22, 32]);
    for (i, serial) in WAITING.iter().enumerate() {
        let n = nodes.iter().find(|n| n["node"] == 20 + i as u64).unwrap();
        assert_eq!(format!("0x{:08X}", n["serial"].as_u64().unwrap()), *serial);
        assert_eq!(n["product_code"], 0x4378_7800);
    }
    // Nothing left to find: exit 3.
    let r = bus.run(&["lss", "fastscan"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    // A provisioning script run again: nothing to number is done, not a failure, once the
    // last "any device without a node-id?" probe went unanswered.
    let r = bus.run(&["lss", "assign", "--start", "20"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert_eq!(r.stdout, "no device without a node-id: nothing to assign\n", "{}", r.stderr);
    let r = bus.run(&["lss", "assign", "--start", "20", "--format", "json"]).ok().json();
    assert_eq!(r["assigned"], serde_json::json!([]), "{r}");
    assert_eq!(r["error"], serde_json::Value::Null, "{r}");
}

pub fn lss_selective_services(bus: &dyn Under) {
    // Seed 001 figure 10 on the wire: the four switch requests and the 0x44 answer.
    let r = bus.run(&["-v", "lss", "inquire", "--identity", SENSOR]).ok();
    assert_eq!(r.stdout.trim(), format!("0x00000040:0x43787800:0x312E3031:0x09501234  node-id 5"));
    for frame in [
        "7E5   [8]  40 40 00 00 00 00 00 00",
        "7E5   [8]  41 00 78 78 43 00 00 00",
        "7E5   [8]  42 31 30 2E 31 00 00 00",
        "7E5   [8]  43 34 12 50 09 00 00 00",
        "7E4   [8]  44 00 00 00 00 00 00 00",
    ] {
        assert!(trace_has(bus, &r.stderr, frame), "{frame} missing:\n{}", r.stderr);
    }
    // A new node-id takes effect at once: SDO and heartbeat follow it.
    bus.run(&["lss", "set-id", "6", "--identity", SENSOR]).ok();
    assert_eq!(bus.run(&["sdo", "read", "6", "1018:4", "--type", "u32"]).ok().stdout.trim(), "156242484");
    assert!(bus.run(&["nmt", "state", "6", "--listen", "5s"]).ok().stdout.contains("pre-operational (from heartbeat)"));
    assert_eq!(
        bus.run(&["sdo", "read", "6", "1800:1", "--type", "u32"]).ok().stdout.trim(),
        "390",
        "TPDO1 COB-ID 0x186"
    );
    bus.run(&["lss", "set-id", "5", "--identity", SENSOR]).ok();
    bus.run(&["lss", "store", "--identity", SENSOR]).ok();
    assert_eq!(bus.run(&["sdo", "read", "5", "100B", "--type", "u32"]).ok().stdout.trim(), "5");
}

pub fn lss_refusals(bus: &dyn Under) {
    let no_target = bus.run(&["lss", "set-id", "7"]);
    assert_eq!(no_target.code, 2);
    assert!(no_target.stderr.contains("--global"), "{}", no_target.stderr);
    for bad in ["0", "128", "254"] {
        let r = bus.run(&["lss", "set-id", bad, "--identity", SENSOR]);
        assert_eq!(r.code, 2, "set-id {bad}");
        assert!(r.stderr.contains("1 to 127, or 255"), "{}", r.stderr);
    }
    assert_eq!(bus.run(&["lss", "set-baud", "100k", "--global"]).code, 2);
    // The SERS stepper's bit rate comes from DIP switches; it cannot store either.
    let r = bus.run(&["lss", "set-baud", "250k", "--identity", "0:0:0:0"]);
    assert_eq!(r.code, 4, "{}", r.stderr);
    assert!(r.stderr.contains("bit timing not supported"), "{}", r.stderr);
    let r = bus.run(&["lss", "store", "--identity", "0:0:0:0"]);
    assert_eq!(r.code, 4);
    assert!(r.stderr.contains("store configuration not supported"));
    // Nobody with that identity.
    let r = bus.run(&["lss", "inquire", "--identity", "1:2:3:4"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    assert!(r.stderr.contains("no LSS device with identity"), "{}", r.stderr);
    // A global inquiry only makes sense with one device.
    let r = bus.run(&["lss", "inquire", "--global"]);
    assert_eq!(r.code, 2);
    assert!(r.stderr.contains("address one with --identity"));
}

/// `stream-pdo 5` gives the sensor's position and speed as the simulator moves them.
pub fn stream_pdo_yields_the_sensors_values(bus: &dyn Under) {
    let r = bus.run(&["stream-pdo", "5", "--start", "--count", "100", "--format", "csv"]).ok();
    let lines: Vec<&str> = r.stdout.lines().collect();
    assert_eq!(lines.len(), 101, "a header and 100 rows");
    assert_eq!(lines[0], "time,pdo,Position value (linear): Channel 1,Speed value: Channel 1");
    // Each row is a point of the simulated motion (a triangle between 100000 and 300000,
    // 20 steps a ms, speed +-2000), and from row to row the position moves the way the
    // speed says. How old a sample is when it is stamped depends
    // on the machine, so the stamps are not compared with the motion's clock.
    let rows: Vec<(i64, i64)> = lines[1..]
        .iter()
        .map(|row| {
            let cols: Vec<&str> = row.split(',').collect();
            (cols[2].parse().unwrap(), cols[3].parse().unwrap())
        })
        .collect();
    for (p, s) in &rows {
        assert!((100_000..=300_000).contains(p) && p % 20 == 0, "{p}: not a position of the motion");
        assert!(*s == 2000 || *s == -2000, "{s}: not the motion's speed");
    }
    for w in rows.windows(2) {
        let ((p0, s0), (p1, s1)) = (w[0], w[1]);
        if s0 == s1 {
            assert!((p1 - p0) * s0.signum() >= 0, "{p0} then {p1} against speed {s0}");
        }
    }
    assert!(rows.iter().any(|&(p, _)| p != rows[0].0), "the position never moved");
    // --start put the node back as it was.
    assert!(bus.run(&["nmt", "state", "5"]).ok().stdout.contains("pre-operational"));
}

fn mapping(bus: &dyn Under) -> Vec<String> {
    ["1A00:0", "1A00:1", "1A00:2", "1800:1", "1800:2", "1800:5"]
        .iter()
        .map(|o| bus.run(&["sdo", "read", "1", o]).ok().stdout.trim().to_string())
        .collect()
}

pub fn one_pdo_per_sync_with_transmission_type_1(bus: &dyn Under) {
    bus.run(&["sdo", "write", "5", "1800:2", "1"]).ok();
    // Until 20 PDOs have come, however long the devices take to answer.
    let r = bus.run(&["-v", "stream-pdo", "5", "--start", "--sync", "10ms", "--count", "20", "--format", "json"]).ok();
    assert_eq!(r.stdout.lines().count(), 20);
    for line in r.stdout.lines() {
        let j: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!((j["node"].as_u64(), j["pdo"].as_u64()), (Some(5), Some(1)));
    }
    // In the order of the trace, no PDO without a SYNC before it that is not yet answered:
    // never more than one per SYNC, and none by event. (The answers to the last SYNCs may
    // still be on their way when the 20th PDO ends the stream.)
    let (mut syncs, mut pdos) = (0, 0);
    let sync = format!("{}  080", bus.iface());
    let pdo = format!("{}  185", bus.iface());
    for line in r.stderr.lines().map(str::trim_start) {
        if line.starts_with(&sync) {
            syncs += 1;
        } else if line.starts_with(&pdo) {
            pdos += 1;
            assert!(pdos <= syncs, "PDO {pdos} after only {syncs} SYNC(s):\n{}", r.stderr);
        }
    }
    assert_eq!(pdos, 20, "{}", r.stderr);
}

pub fn map_reconfigures_for_the_session_and_restores(bus: &dyn Under) {
    let before = mapping(bus);
    let r = bus
        .run(&[
            "stream-pdo",
            "1",
            "--start",
            "--map",
            "6064:0,606C:0",
            "--event",
            "5",
            "--count",
            "5",
            "--format",
            "json",
        ])
        .ok();
    let first: serde_json::Value = serde_json::from_str(r.stdout.lines().next().unwrap()).unwrap();
    assert_eq!(first["Position actual value"], 0);
    assert_eq!(first["Velocity actual value"], 0);
    assert_eq!(r.stdout.lines().count(), 5);
    assert_eq!(mapping(bus), before, "mapping and communication parameters put back");
    assert!(bus.run(&["nmt", "state", "1"]).ok().stdout.contains("pre-operational"));
}

pub fn ctrl_c_restores_and_exits_130(bus: &dyn Under) {
    let before = mapping(bus);
    let stream = bus.command(&["stream-pdo", "1", "--start", "--map", "6064:0", "--event", "10", "--format", "csv"]);
    // Interrupt once it is streaming (the header and a few rows are out).
    let r = super::signal_after_lines(stream, 5, nix::sys::signal::Signal::SIGINT);
    assert_eq!(r.code, 130, "{}", r.stderr);
    assert_eq!(mapping(bus), before);
    assert!(bus.run(&["nmt", "state", "1"]).ok().stdout.contains("pre-operational"));
    // And it says so, not only does it.
    assert!(r.stderr.contains("put back node 1's TPDO1 mapping"), "{}", r.stderr);
    assert!(r.stderr.contains("node 1 back to pre-operational"), "{}", r.stderr);
}
