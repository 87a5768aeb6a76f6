//! SIGINT and SIGTERM for every command that talks to the bus, the way a user meets them:
//! Ctrl-C in a terminal, a CI job cancelled. Each command stops at a safe point, prints
//! what it did, what it did not and the state the device is left in, and exits 130; the
//! device is checked afterwards. The point of interruption is exact, without timing:
//! [`common::interrupted`] runs the test build of canctl (tests/seams/canctl.rs), which
//! signals itself after its K-th SDO read (`rK`), write (`K`), NMT command (`nK`), or answer that
//! moved a transfer on (`sK`: a segment, a sub-block); `monitor` is signalled once it has
//! printed its first lines.
//!
//! `cargo test --test suite interrupt_commands:: -- --nocapture` prints the table.

use crate::common;

use std::sync::Mutex;

const SIGNALS: [&str; 2] = ["INT", "TERM"];

/// The closing note's table: command, signal, what the report said, device after, exit.
static TABLE: Mutex<Vec<[String; 6]>> = Mutex::new(Vec::new());

fn row(test: &str, command: &str, signal: &str, said: &str, device: &str, code: i32) {
    let signal = format!("SIG{signal}");
    let row = [command, &signal, said, device, &code.to_string(), test].map(|s| s.to_string());
    TABLE.lock().unwrap().push(row);
    // On the real stdout: shown with --nocapture, one row per line as each test ends.
    use std::io::Write;
    let _ = writeln!(std::io::stdout().lock(), "| {} |", TABLE.lock().unwrap().last().unwrap().join(" | "));
}

fn signalled(c: std::process::Command, point: &str, signal: &str) -> common::Run {
    let mut c = common::interrupted(c, &format!("{point}:{signal}"));
    common::finish(c.output().unwrap())
}

/// The line of stderr that starts with `start`.
fn line<'a>(text: &'a str, start: &str) -> &'a str {
    text.lines().find(|l| l.starts_with(start)).unwrap_or_else(|| panic!("no line '{start}…' in\n{text}"))
}

/// `sdo read` of a 64 KiB domain (block upload) stopped after its 5th segment: the
/// transfer is aborted on the bus (0x08000000), no file is written, and the device answers
/// the next transfer at once. The device is a process of its own (`sim --slcan`) that keeps
/// its SDO server's state between invocations, as a real device does.
#[cfg(unix)]
#[test]
fn sdo_read_of_a_domain_interrupted_mid_transfer_is_aborted_and_writes_no_file() {
    let sim = common::Sim::new();
    let dev = common::DeviceSide::start(&sim, "--slcan", &[]);
    let out = sim.path("program.bin");
    std::fs::write(&out, b"previous").unwrap();
    for signal in SIGNALS {
        let c = dev.command(&["-v", "sdo", "read", "1", "1F50:1", "--type", "d", "--out", out.to_str().unwrap()]);
        let run = signalled(c, "s5", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let said = line(&run.stderr, "sdo read interrupted");
        assert!(said.contains("of 65536 bytes read (not kept)"), "{said}");
        assert!(said.contains("program.bin (the old file is unchanged)"), "{said}");
        let state = line(&run.stderr, "nothing was changed on the device");
        assert!(state.contains("aborted (SDO abort 0x08000000), so node 1 is ready for the next one"), "{state}");
        // The abort went out on the bus, after the segments.
        assert!(run.stderr.contains("601   [8]  80 50 1F 01 00 00 00 08"), "no abort frame in\n{}", run.stderr);
        assert!(run.stderr.ends_with("canctl: interrupted\n"), "{}", run.stderr);
        assert_eq!(std::fs::read(&out).unwrap(), b"previous");
        // The device is ready: the next transfer is answered.
        let next = dev.run(&["sdo", "read", "1", "0x1018:1", "--type", "u32"]).ok();
        assert_eq!(next.stdout.trim(), "251");
        row(
            "sdo_read_of_a_domain_interrupted_mid_transfer_is_aborted_and_writes_no_file",
            "sdo read 1 1F50:1 --out (block upload, after segment 5)",
            signal,
            said.trim_start_matches("sdo read interrupted: "),
            "not mid-transfer (abort 0x08000000 sent); next sdo read answered; --out file unchanged",
            run.code,
        );
    }
    // JSON: the same report as a document.
    let c = dev.command(&["sdo", "read", "1", "1F50:1", "--type", "d", "--format", "json"]);
    let run = signalled(c, "s5", "TERM");
    assert_eq!(run.code, 130);
    let report = run.json();
    assert_eq!(report["command"], "sdo read");
    assert_eq!(report["interrupted"], true);
    assert_eq!(report["not_done"], serde_json::json!(["the rest of the read"]));
}

/// `sdo write` of 20000 bytes (block download) stopped after its 3rd sub-block: aborted,
/// so the device takes nothing of it and is not left in the middle of a block download
/// (where it would take the next request for a segment).
#[cfg(unix)]
#[test]
fn sdo_write_of_a_domain_interrupted_mid_transfer_leaves_the_value_and_the_device_ready() {
    let sim = common::Sim::new();
    let dev = common::DeviceSide::start(&sim, "--slcan", &[]);
    let before = dev.run(&["sdo", "read", "1", "1F50:1", "--type", "d", "--format", "json"]).ok().json()["raw"].clone();
    let data = sim.path("new.bin");
    std::fs::write(&data, (0..20000u32).map(|i| (i * 7) as u8).collect::<Vec<u8>>()).unwrap();
    let value = format!("@{}", data.display());
    for signal in SIGNALS {
        let run = signalled(dev.command(&["sdo", "write", "1", "1F50:1", &value, "--type", "d"]), "s3", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let said = line(&run.stderr, "sdo write interrupted");
        assert!(said.contains("of 20000 bytes sent; not done the rest of the write"), "{said}");
        let state = line(&run.stderr, "node 1 0x1F50:1 keeps its previous value");
        assert!(state.contains("SDO abort 0x08000000"), "{state}");
        // Ready for the next transfer, and the value is the old one.
        dev.run(&["sdo", "read", "1", "0x1018:1", "--type", "u32"]).ok();
        let after =
            dev.run(&["sdo", "read", "1", "1F50:1", "--type", "d", "--format", "json"]).ok().json()["raw"].clone();
        assert_eq!(after, before, "the device took part of an aborted download");
        row(
            "sdo_write_of_a_domain_interrupted_mid_transfer_leaves_the_value_and_the_device_ready",
            "sdo write 1 1F50:1 @20000 bytes (block download, after sub-block 3)",
            signal,
            said.trim_start_matches("sdo write interrupted: "),
            "0x1F50:1 unchanged; not mid-transfer: next sdo read answered",
            run.code,
        );
    }
}

/// `sdo write --verify` stopped after the write, before the read-back: written, not
/// verified, and it says so.
#[test]
fn sdo_write_verify_interrupted_before_the_read_back_says_written_not_verified() {
    let sim = common::Sim::new();
    for (signal, value) in SIGNALS.iter().zip(["250", "300"]) {
        let run =
            signalled(sim.command(&["sdo", "write", "5", "1017", value, "--type", "u16", "--verify"]), "1", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let said = format!("node 5 0x1017:0 = {value} (u16): written; not verified: interrupted before the read-back");
        assert_eq!(run.stdout.trim(), said);
        let now = sim.run(&["sdo", "read", "5", "1017"]).ok();
        assert_eq!(now.stdout.trim(), value);
        let c = run.code;
        row(
            "sdo_write_verify_interrupted_before_the_read_back_says_written_not_verified",
            "sdo write 5 1017 --verify (after the write)",
            signal,
            &said,
            &format!("0x1017 = {value}, as written"),
            c,
        );
    }
}

/// `scan` stopped while it probes: the probes in flight are let finish (each is one request
/// and its answer), so every node is found, marked incomplete, with the parts of the scan
/// not done (the probe too: the silent ids were not asked again, and a node whose answer
/// was lost may be there); exit 130. A scan after it is complete.
#[test]
fn scan_interrupted_while_probing_reports_the_nodes_found_and_what_it_did_not_do() {
    let sim = common::Sim::new();
    let all = sim.run(&["scan", "--format", "json"]).ok().json();
    let all: Vec<u64> = all["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect();
    assert!(all.len() >= 4, "{all:?}");
    let nodes = |report: &serde_json::Value| -> Vec<u64> {
        report["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect()
    };
    let identified = |report: &serde_json::Value| {
        report["nodes"].as_array().unwrap().iter().filter(|n| !n["vendor_id"].is_null()).count()
    };
    for signal in SIGNALS {
        let run = signalled(sim.command(&["scan", "--format", "json"]), "r2", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let report = run.json();
        assert_eq!(report["interrupted"], true);
        assert_eq!(nodes(&report), all, "{report}");
        assert_eq!(identified(&report), 0, "{report}");
        let not_done = report["not_done"].as_array().unwrap();
        assert_eq!(
            not_done.iter().map(|s| s.as_str().unwrap()).collect::<Vec<_>>(),
            [
                "probing node-ids 1 to 127 (stopped part-way: nodes not listed may be there)",
                "reading identity, name and heartbeat time",
                "learning NMT states",
                "counting devices without a node-id (LSS)"
            ],
            "{report}"
        );

        let human = signalled(sim.command(&["scan"]), "r2", signal);
        assert_eq!(human.code, 130);
        let said = line(&human.stderr, "scan interrupted, incomplete");
        assert!(said.contains(&format!("{} node(s) found so far", all.len())), "{said}");
        assert!(said.contains("nothing was changed"), "{said}");
        let again = sim.run(&["scan", "--format", "json"]).ok().json();
        assert_eq!(nodes(&again), all);
        assert_eq!(again["interrupted"], false);
        row(
            "scan_interrupted_while_probing_reports_the_nodes_found_and_what_it_did_not_do",
            "scan (after the 2nd probe answered)",
            signal,
            said,
            "unchanged; the next scan is complete",
            human.code,
        );
    }
    // Stopped while reading identities: the probe's batch is 254 reads (0x1000 and then
    // 0x1018:4 of each id, the second skipped for a silent id), then the vendor-IDs: those
    // read are shown.
    let run = signalled(sim.command(&["scan", "--format", "json"]), "r255", "INT");
    assert_eq!(run.code, 130, "{}", run.stderr);
    let report = run.json();
    assert_eq!(nodes(&report), all, "{report}");
    assert!(identified(&report) >= 1, "{report}");
    assert!(report["not_done"][0].as_str().unwrap().starts_with("reading identity"), "{report}");
}

/// `monitor` stopped by Ctrl-C or SIGTERM: its summary, marked interrupted, then exit 130.
#[cfg(unix)]
#[test]
fn monitor_interrupted_prints_its_summary_and_exits_130() {
    use nix::sys::signal::Signal;
    let sim = common::Sim::new();
    for (signal, sig) in [("INT", Signal::SIGINT), ("TERM", Signal::SIGTERM)] {
        let r = common::signal_after_lines(sim.command(&["monitor", "--format", "json"]), 3, sig);
        assert_eq!(r.code, 130, "{}", r.stderr);
        let last: serde_json::Value = serde_json::from_str(r.stdout.lines().last().unwrap()).unwrap();
        assert_eq!(last["summary"]["interrupted"], true, "{last}");
        assert!(last["summary"]["frames"].as_u64().unwrap() >= 3, "{last}");
        let human = common::signal_after_lines(sim.command(&["monitor"]), 3, sig);
        assert_eq!(human.code, 130, "{}", human.stderr);
        let said = line(&human.stderr, "");
        let said = human.stderr.lines().find(|l| l.contains("frame(s) in")).unwrap_or(said);
        assert!(said.ends_with("(interrupted; nothing was sent to the bus)"), "{}", human.stderr);
        row(
            "monitor_interrupted_prints_its_summary_and_exits_130",
            "monitor (after 3 lines)",
            signal,
            said,
            "nothing sent",
            human.code,
        );
    }
    // Ended by its duration, the same monitor exits 0 with a plain summary.
    let r = sim.run(&["monitor", "--duration", "100ms", "--format", "json"]).ok();
    let last: serde_json::Value = serde_json::from_str(r.stdout.lines().last().unwrap()).unwrap();
    assert_eq!(last["summary"].get("interrupted"), None, "{last}");
}

/// `nmt reset` stopped once the reset went out, while it waits for the boot-up: the
/// report says the reset was sent and is unconfirmed; the node is up.
#[test]
fn nmt_reset_interrupted_while_waiting_for_the_boot_up_says_it_was_sent() {
    let sim = common::Sim::new();
    for signal in SIGNALS {
        let run = signalled(sim.command(&["nmt", "reset", "5", "--format", "json"]), "n1", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let report = run.json();
        assert_eq!((report["sent"].as_bool(), report["confirmed"].as_bool()), (Some(true), Some(false)));
        assert_eq!(report["interrupted"], true);
        let human = signalled(sim.command(&["nmt", "reset", "5"]), "n1", signal);
        assert_eq!(human.code, 130);
        let said = human.stdout.trim();
        assert!(
            said.starts_with("NMT reset node sent to node 5; not confirmed: interrupted while waiting for the boot-up"),
            "{said}"
        );
        let state = sim.run(&["nmt", "state", "5"]).ok();
        assert!(state.stdout.contains("pre-operational"), "{}", state.stdout);
        row(
            "nmt_reset_interrupted_while_waiting_for_the_boot_up_says_it_was_sent",
            "nmt reset 5 (after the NMT frame)",
            signal,
            said,
            "node 5 reset, pre-operational",
            human.code,
        );
    }
}

/// `store` stopped before it writes 'save': nothing stored (a reset brings back the
/// values stored before); stopped after it, the store is complete (exit 0).
#[test]
fn store_interrupted_before_save_stores_nothing() {
    let sim = common::Sim::new();
    let heartbeat = || sim.run(&["sdo", "read", "5", "1017"]).ok().stdout.trim().to_string();
    let stored = heartbeat();
    for signal in SIGNALS {
        sim.run(&["sdo", "write", "5", "1017", "777", "--type", "u16"]).ok();
        // Reads: 0x1010:0, then 0x1010:1; stopped after the second, before 'save'.
        let run = signalled(sim.command(&["store", "5"]), "r2", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let said = line(&run.stderr, "store interrupted");
        assert_eq!(said, "store interrupted: done nothing; not done 'save' to 0x1010:1 of node 5");
        assert!(run.stderr.contains("nothing was stored on node 5: its non-volatile memory is as it was"));
        sim.run(&["nmt", "reset", "5"]).ok();
        assert_eq!(heartbeat(), stored, "a reset should bring back what was stored before");
        row(
            "store_interrupted_before_save_stores_nothing",
            "store 5 (before 'save')",
            signal,
            said,
            "nothing stored: after a reset 0x1017 is the old stored value",
            run.code,
        );
    }
    // After 'save' there is nothing left to stop.
    sim.run(&["sdo", "write", "5", "1017", "777", "--type", "u16"]).ok();
    let run = signalled(sim.command(&["store", "5"]), "1", "INT");
    assert_eq!(run.code, 0, "{}", run.stderr);
    sim.run(&["nmt", "reset", "5"]).ok();
    assert_eq!(heartbeat(), "777");
}

/// `store` on several nodes stopped part-way: the nodes done, the one under way and those
/// not begun; the first is stored, the others are not (a reset brings their stored values
/// back).
#[test]
fn store_on_several_nodes_interrupted_says_which_were_done() {
    let sim = common::Sim::new();
    let heartbeat = |node: &str| sim.run(&["sdo", "read", node, "1017"]).ok().stdout.trim().to_string();
    for signal in SIGNALS {
        let stored: Vec<String> = ["1", "5", "10"].iter().map(|n| heartbeat(n)).collect();
        for node in ["1", "5", "10"] {
            sim.run(&["sdo", "write", node, "1017", "321", "--type", "u16"]).ok();
        }
        // Stopped after node 1's 'save', before node 5's.
        let run = signalled(sim.command(&["store", "1,5,10", "--format", "json"]), "1", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let report = run.json();
        assert_eq!(report["done"], serde_json::json!(["node 1: all parameters stored (0x1010:1)"]), "{report}");
        assert_eq!(
            report["not_done"],
            serde_json::json!(["'save' to 0x1010:1 of node 5", "store on node 10"]),
            "{report}"
        );
        sim.run(&["nmt", "reset", "all"]).ok();
        assert_eq!(heartbeat("1"), "321", "node 1 was stored");
        assert_eq!([heartbeat("5"), heartbeat("10")], [stored[1].clone(), stored[2].clone()], "5 and 10 were not");
        let said = format!("done: node 1 stored; not done: {}", report["not_done"]);
        row(
            "store_on_several_nodes_interrupted_says_which_were_done",
            "store 1,5,10 (after node 1's 'save')",
            signal,
            &said,
            "node 1 stored; 5 and 10 not (their old stored values after a reset)",
            run.code,
        );
        // Make node 1's stored value the baseline again for the next signal.
        sim.run(&["store", "1"]).ok();
    }
    // Not interrupted: each node's report, in order.
    let run = sim.run(&["store", "1,5", "--format", "json"]).ok().json();
    assert_eq!(run.as_array().unwrap().len(), 2, "{run}");
}

/// `restore --reset` stopped after 'load', before the reset: the defaults are loaded, not
/// in force; stopped after the reset went out: said so, unconfirmed.
#[test]
fn restore_reset_interrupted_says_how_far_it_got() {
    let sim = common::Sim::new();
    let heartbeat = || sim.run(&["sdo", "read", "5", "1017"]).ok().stdout.trim().to_string();
    let default = heartbeat();
    for signal in SIGNALS {
        sim.run(&["sdo", "write", "5", "1017", "777", "--type", "u16"]).ok();
        let run = signalled(sim.command(&["restore", "5", "--reset"]), "1", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let said = line(&run.stderr, "restore interrupted");
        assert_eq!(said, "restore interrupted: done node 5: 'load' written to 0x1011:1; not done NMT reset of node 5");
        assert!(run.stderr.contains("node 5: the defaults are loaded and apply from its next reset"), "{}", run.stderr);
        assert_eq!(heartbeat(), "777", "not reset: the value in use is unchanged");
        sim.run(&["nmt", "reset", "5"]).ok();
        assert_eq!(heartbeat(), default, "the next reset brings the defaults");
        row(
            "restore_reset_interrupted_says_how_far_it_got",
            "restore 5 --reset (after 'load')",
            signal,
            said,
            "defaults loaded, not in force until a reset",
            run.code,
        );

        sim.run(&["sdo", "write", "5", "1017", "777", "--type", "u16"]).ok();
        let run = signalled(sim.command(&["restore", "5", "--reset", "--format", "json"]), "n1", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let report = run.json();
        assert_eq!(report["done"], serde_json::json!(["node 5: 'load' written to 0x1011:1", "NMT reset of node 5"]));
        assert_eq!(report["not_done"], serde_json::json!(["confirming that node 5 booted"]));
        assert_eq!(heartbeat(), default);
        let said = report["done"].to_string();
        row(
            "restore_reset_interrupted_says_how_far_it_got",
            "restore 5 --reset (after the NMT reset)",
            signal,
            &said,
            "reset with the defaults",
            run.code,
        );
    }
}

/// `config dump` stopped while it reads: no DCF, neither on standard output nor in the
/// --out file (the old one is kept, no temporary file left).
#[test]
fn config_dump_interrupted_writes_no_partial_dcf() {
    let sim = common::Sim::new();
    let out = sim.path("io.dcf");
    std::fs::write(&out, b"[FileInfo]\nFileName=old\n").unwrap();
    for signal in SIGNALS {
        let run = signalled(sim.command(&["config", "dump", "10", "--out", out.to_str().unwrap()]), "r5", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let said = line(&run.stderr, "config dump interrupted");
        assert!(
            said.contains("not done reading the other objects, writing")
                && said.contains("(the old file is unchanged)"),
            "{said}"
        );
        assert!(run.stderr.contains("nothing was changed on the device"));
        assert_eq!(std::fs::read(&out).unwrap(), b"[FileInfo]\nFileName=old\n");
        let left: Vec<_> = std::fs::read_dir(sim.path(""))
            .unwrap()
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().contains("canctl-tmp"))
            .collect();
        assert!(left.is_empty(), "{left:?}");
        let stdout = signalled(sim.command(&["config", "dump", "10"]), "r5", signal);
        assert_eq!(stdout.code, 130);
        assert_eq!(stdout.stdout, "", "a partial DCF was printed");
        row(
            "config_dump_interrupted_writes_no_partial_dcf",
            "config dump 10 --out FILE (after 5 reads)",
            signal,
            said,
            "unchanged; old FILE kept, no temporary file",
            run.code,
        );
    }
}

/// `config eds` stopped in the middle of the upload of the stored EDS: the transfer is
/// aborted, no file written (the old one is kept), and nothing on stdout.
#[test]
fn config_eds_interrupted_mid_upload_writes_no_file() {
    let sim = common::Sim::new();
    let out = sim.path("drive.eds");
    std::fs::write(&out, b"old").unwrap();
    for signal in SIGNALS {
        let run = signalled(sim.command(&["config", "eds", "1", "--out", out.to_str().unwrap()]), "s5", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let said = line(&run.stderr, "config eds interrupted");
        assert!(said.contains("(the old file is unchanged)"), "{said}");
        assert!(run.stderr.contains("nothing was changed on the device"), "{}", run.stderr);
        assert_eq!(std::fs::read(&out).unwrap(), b"old");
        let stdout = signalled(sim.command(&["config", "eds", "1"]), "s5", signal);
        assert_eq!((stdout.code, stdout.stdout.as_str()), (130, ""), "a partial EDS was printed");
        row(
            "config_eds_interrupted_mid_upload_writes_no_file",
            "config eds 1 --out FILE (after 5 segments)",
            signal,
            said,
            "unchanged; old FILE kept",
            run.code,
        );
    }
}

/// `config diff` stopped while it reads: the differences found so far, with how many
/// objects were not compared; exit 130, also with --check.
#[test]
fn config_diff_interrupted_reports_what_it_compared() {
    let sim = common::Sim::new();
    let dcf = sim.path("io.dcf");
    sim.run(&["config", "dump", "10", "--out", dcf.to_str().unwrap()]).ok();
    for signal in SIGNALS {
        let c = sim.command(&["config", "diff", "10", dcf.to_str().unwrap(), "--check", "--format", "json"]);
        let run = signalled(c, "r5", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let report = run.json();
        assert_eq!(report["interrupted"], true);
        assert_eq!(report["same"], 5, "{report}");
        assert!(report["not_compared"].as_u64().unwrap() > 0, "{report}");
        let human = signalled(sim.command(&["config", "diff", "10", dcf.to_str().unwrap()]), "r5", signal);
        assert_eq!(human.code, 130);
        let said = line(&human.stderr, "diff interrupted, incomplete");
        row(
            "config_diff_interrupted_reports_what_it_compared",
            "config diff 10 FILE --check (after 5 reads)",
            signal,
            said,
            "unchanged",
            human.code,
        );
    }
    // Uninterrupted, the same diff is complete and finds nothing.
    sim.run(&["config", "diff", "10", dcf.to_str().unwrap(), "--check"]).ok();
}

/// Through an EPOS2 (its segmented read, 0x14 per segment) the read stops between two
/// segments: the EPOS2 protocol has no abort, so nothing more is sent, and the EPOS2
/// answers the next command.
#[cfg(unix)]
#[test]
fn sdo_read_through_an_epos2_interrupted_stops_between_segments() {
    let sim = common::Sim::new();
    let dev = common::DeviceSide::start(&sim, "--epos2-rs232", &[]);
    for signal in SIGNALS {
        let run = signalled(dev.command(&["sdo", "read", "10", "1008", "--type", "vs"]), "s1", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        let said = line(&run.stderr, "sdo read interrupted");
        assert!(said.starts_with("sdo read interrupted: done 0x1008:0: "), "{said}");
        let state = line(&run.stderr, "nothing was changed on the device");
        assert!(state.contains("the EPOS2 protocol has no command to abort a transfer"), "{state}");
        let next = dev.run(&["sdo", "read", "10", "1008", "--type", "vs"]).ok();
        assert!(!next.stdout.trim().is_empty());
        row(
            "sdo_read_through_an_epos2_interrupted_stops_between_segments",
            "sdo read 10 1008 via epos2-rs232 (after segment 1)",
            signal,
            said.trim_start_matches("sdo read interrupted: "),
            "no abort possible; next sdo read answered",
            run.code,
        );
    }
}

/// `errors --clear` stopped after the clear was written: the history read is shown, the
/// clear is reported as written but not confirmed, and the device holds it. Stopped just
/// before the clear: nothing changed, and the device keeps its history.
#[test]
fn errors_clear_interrupted_says_whether_the_clear_was_written() {
    let sim = common::Sim::new();
    let count = || sim.run(&["sdo", "read", "10", "1003:0", "--type", "u8"]).ok().stdout.trim().to_string();
    assert_eq!(count(), "2");
    for signal in SIGNALS {
        // Reads: six about the node, then its two entries; stopped before the clear.
        let run = signalled(sim.command(&["errors", "10", "--clear"]), "r8", signal);
        assert_eq!(run.code, 130, "{}", run.stderr);
        assert!(run.stdout.contains("2 error(s) logged in 0x1003"), "{}", run.stdout);
        assert!(run.stderr.contains("interrupted before clearing: nothing was changed"), "{}", run.stderr);
        assert_eq!(count(), "2");
        row(
            "errors_clear_interrupted_says_whether_the_clear_was_written",
            "errors 10 --clear (before the clear)",
            signal,
            "the 2 entries; interrupted before clearing: nothing was changed",
            "history kept: 0x1003:0 reads 2",
            run.code,
        );
    }
    let run = signalled(sim.command(&["errors", "10", "--clear"]), "1", "INT");
    assert_eq!(run.code, 130, "{}", run.stderr);
    let said = line(&run.stderr, "node 10 (CAN-2057C): interrupted: 0 written to 0x1003:0, not confirmed");
    assert_eq!(count(), "0");
    row(
        "errors_clear_interrupted_says_whether_the_clear_was_written",
        "errors 10 --clear (after the clear, before its read-back)",
        "INT",
        said,
        "history cleared: 0x1003:0 reads 0",
        run.code,
    );
}

/// `health` and `drive status` only read: stopped, they say so and that nothing changed.
#[test]
fn health_and_drive_status_interrupted_say_nothing_was_changed() {
    let sim = common::Sim::new();
    for (args, said) in [
        (&["health"][..], "health interrupted: done nothing; not done scanning and judging the nodes"),
        (&["drive", "status", "1"][..], "drive status interrupted: done nothing; not done reading node 1's state"),
    ] {
        for signal in SIGNALS {
            let run = signalled(sim.command(args), "r1", signal);
            assert_eq!(run.code, 130, "{}", run.stderr);
            assert_eq!(line(&run.stderr, said.split(':').next().unwrap()), said);
            assert!(run.stderr.contains("nothing was changed on the device"), "{}", run.stderr);
        }
    }
}
