//! The foundation's promises, shown with the real binary on the simulated network.

use crate::common;

use common::scenarios;

use common::{bare, Sim};

#[test]
fn scan_lists_the_demo_nodes_with_their_identities() {
    scenarios::scan_lists_the_demo_nodes_with_their_identities(&Sim::new());
}

#[test]
fn every_data_type_round_trips() {
    scenarios::every_data_type_round_trips(&Sim::new());
}

#[test]
fn untyped_reads_show_bytes_and_the_plain_reading() {
    scenarios::untyped_reads_show_bytes_and_the_plain_reading(&Sim::new());
}

#[test]
fn a_long_name_comes_back_whole_by_segmented_transfer() {
    scenarios::a_long_name_comes_back_whole_by_segmented_transfer(&Sim::new());
}

#[test]
fn the_64k_domain_moves_byte_exact_by_block_and_by_segmented() {
    scenarios::the_64k_domain_moves_byte_exact_by_block_and_by_segmented(&Sim::new());
}

#[test]
fn a_device_without_block_transfer_is_read_all_the_same() {
    scenarios::a_device_without_block_transfer_is_read_all_the_same(&Sim::new());
}

#[test]
fn refusals_carry_the_abort_code_and_its_meaning() {
    scenarios::refusals_carry_the_abort_code_and_its_meaning(&Sim::new());
}

#[test]
fn an_absent_node_times_out_with_exit_3() {
    scenarios::an_absent_node_times_out_with_exit_3(&Sim::new());
}

#[test]
fn lss_fastscan_and_assign_number_a_fresh_bus() {
    scenarios::lss_fastscan_and_assign_number_a_fresh_bus(&Sim::new());
}

/// Running out of node-ids is not a device refusing (exit 4): it is the range the user
/// gave (exit 2), with who was numbered and who was not, and what to do.
#[test]
fn lss_assign_out_of_node_ids_says_who_was_numbered_and_who_was_not() {
    let sim = Sim::new();
    let r = sim.run(&["lss", "assign", "--start", "126", "--format", "json"]);
    assert_eq!(r.code, 2, "{}\n{}", r.stdout, r.stderr);
    let report = r.json();
    let nodes: Vec<u64> = report["assigned"].as_array().unwrap().iter().map(|a| a["node"].as_u64().unwrap()).collect();
    assert_eq!(nodes, [126, 127], "{report}");
    let error = report["error"].as_str().unwrap();
    assert!(error.starts_with("no free node-id left from 126 to 127 for 0x00000040:"), "{error}");
    assert!(r.stderr.contains("give a lower --start"), "{}", r.stderr);
    // The one left over still waits for a node-id, and a lower start numbers it.
    assert_eq!(sim.run(&["scan", "--format", "json"]).ok().json()["lss_unconfigured"], 1);
    let again = sim.run(&["lss", "assign", "--start", "20", "--format", "json"]).ok().json();
    assert_eq!(again["assigned"].as_array().unwrap().len(), 1, "{again}");
}

/// A global set-baud that some devices took and one refused says both (as network set-baud
/// does), exit 4; the following `lss activate --global` warns that it strands the one that
/// refused, and a set-baud every device took clears the warning.
#[test]
fn lss_set_baud_global_reports_who_accepted_and_activate_warns_of_the_refusal() {
    let sim = Sim::new();
    // The stepper cannot change its rate over LSS; the other six devices (three without a
    // node-id) can.
    let r = sim.run(&["lss", "set-baud", "125k", "--global"]);
    assert_eq!(r.code, 4, "{}\n{}", r.stdout, r.stderr);
    assert!(r.stdout.contains("6 device(s) confirmed, 1 refused"), "{}", r.stdout);
    assert!(r.stdout.contains("bit timing not supported"), "{}", r.stdout);
    let json = sim.run(&["lss", "set-baud", "125k", "--global", "--format", "json"]).json();
    assert_eq!(json["confirmed"], 6, "{json}");
    assert_eq!(json["refused"].as_array().unwrap().len(), 1, "{json}");

    let r = sim.run(&["lss", "activate", "--global", "--delay", "5"]);
    assert!(
        r.stderr.contains("the last `lss set-baud 125k --global` on this bus was refused by 1 device(s)"),
        "{}",
        r.stderr
    );
    // Back to 500k (the six switched to 125k, the sim with them): every device takes it.
    sim.run(&["lss", "set-baud", "500k", "--global"]);
    let r = sim.run(&["lss", "activate", "--global", "--delay", "5"]);
    assert!(!r.stderr.contains("was refused by"), "{}", r.stderr);
}

#[test]
fn lss_selective_services() {
    scenarios::lss_selective_services(&Sim::new());
}

#[test]
fn lss_refusals() {
    scenarios::lss_refusals(&Sim::new());
}

#[test]
fn lss_activate_switches_the_bit_rate() {
    let sim = Sim::new();
    let io = "0x444:0x2057:0x10000:0x1F4A";
    sim.run(&["lss", "set-baud", "250k", "--identity", io]).ok();
    // Configured, not yet active: everything still answers.
    assert_eq!(sim.run(&["scan", "--format", "json"]).ok().json()["nodes"].as_array().unwrap().len(), 4);
    let r = sim.run(&["lss", "activate", "--identity", io, "--delay", "5"]).ok();
    assert!(r.stdout.contains("sim switched with them, and they are back in LSS waiting state"), "{}", r.stdout);
    // The bus (and this master) followed the I/O module to 250k: the others are left behind.
    let nodes = sim.run(&["scan", "--format", "json"]).ok().json()["nodes"].clone();
    assert_eq!(nodes.as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect::<Vec<_>>(), [10]);
}

#[test]
fn malformed_input_is_a_usage_error_with_a_pointed_message() {
    let sim = Sim::new();
    let cases: &[(&[&str], &str)] = &[
        (&["sdo", "read", "1", "10180:1"], "1 to 4 hex digits"),
        (&["sdo", "read", "1", "1018:300"], "0..255"),
        (&["sdo", "read", "0", "1000"], "0 is only for an EPOS2"),
        (&["sdo", "read", "128", "1000"], "not a node-id"),
        (&["sdo", "read", "1", "1000", "--type", "u12"], "not a data type"),
        (&["sdo", "write", "1", "5FF0:2", "300", "--type", "u8"], "out of range for u8: use 0 to 255"),
        (&["sdo", "write", "1", "5FF0:3", "12abc", "--type", "u16"], "not a valid u16"),
        (&["sdo", "write", "1", "5FF0:13", "abc", "--type", "os"], "odd number of hex digits"),
        (&["sdo", "write", "1", "5FF0:3", "12"], "--type is needed"),
        (&["sdo", "write", "1", "5FF0:13", "@/nonexistent/file", "--type", "os"], "cannot read /nonexistent/file"),
        (&["sdo", "read", "1", "1000", "--type", "u16"], "not a u16"),
        (&["nmt", "stop", "200"], "1 to 127, or all"),
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
    scenarios::verify_catches_a_device_that_ignores_the_write(&Sim::new());
}

#[test]
fn nmt_stop_state_and_reset() {
    scenarios::nmt_stop_state_and_reset(&Sim::new());
}

#[test]
fn nmt_state_falls_back_to_node_guarding_with_toggle() {
    scenarios::nmt_state_falls_back_to_node_guarding_with_toggle(&Sim::new());
}

#[test]
fn nmt_all_is_the_only_broadcast() {
    scenarios::nmt_all_is_the_only_broadcast(&Sim::new());
}

#[test]
fn store_and_restore_survive_resets_as_on_hardware() {
    scenarios::store_and_restore_survive_resets_as_on_hardware(&Sim::new());
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
        ("socketcan:vcan9", "no network interface 'vcan9'"),
        ("can9", "no network interface 'can9'"),
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
    let mut c = std::process::Command::new(common::canctl_bin());
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

#[test]
fn a_silent_node_gets_the_nodes_of_the_last_scan_as_a_hint() {
    let sim = Sim::new();
    let r = sim.run(&["--timeout", "100ms", "sdo", "read", "7", "1000"]);
    assert_eq!(r.code, 3);
    assert!(r.stderr.contains("`canctl scan` lists the nodes on"), "{}", r.stderr);
    sim.run(&["scan"]).ok();
    let r = sim.run(&["--timeout", "100ms", "sdo", "read", "7", "1000"]);
    assert_eq!(r.code, 3);
    assert!(
        r.stderr.contains("node 7: did not answer") && r.stderr.contains("nodes seen on the last scan of sim:"),
        "{}",
        r.stderr
    );
    assert!(r.stderr.trim_end().ends_with(": 1, 5, 10, 32"), "{}", r.stderr);
}

#[test]
fn an_object_the_node_lacks_gets_the_nearest_ones_suggested() {
    let sim = Sim::new();
    let run = sim.run(&["sdo", "read", "1", "0x1081:1"]);
    assert_eq!(run.code, 4);
    assert!(run.stderr.contains("Object does not exist") && run.stderr.contains("did you mean"), "{}", run.stderr);
    assert!(run.stderr.contains("0x1018:1 (Identity object: Vendor-ID)"), "{}", run.stderr);
    let run = sim.run(&["sdo", "read", "1", "0x1018:9"]);
    assert!(run.stderr.contains("did you mean 0x1018:0"), "{}", run.stderr);
}

/// The built-in dictionary knows CiA 402's modes: a reserved one is refused before anything
/// is sent, with no EDS given.
#[test]
fn a_reserved_mode_of_operation_is_refused_before_sending() {
    let sim = Sim::new();
    let r = sim.run(&["-v", "sdo", "write", "1", "6060", "99"]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    assert!(r.stderr.contains("use -128 to 10"), "{}", r.stderr);
    assert!(!r.stderr.contains(" 601 "), "nothing sent: {}", r.stderr);
}

/// Node 0 (refused by the bus) and node 128 (refused by the argument parser) are told the
/// same way, in canctl's voice.
#[test]
fn bad_node_ids_are_told_in_one_voice() {
    let sim = Sim::new();
    for node in ["0", "128"] {
        let r = sim.run(&["sdo", "read", node, "1000"]);
        assert_eq!(r.code, 2, "{}", r.stderr);
        assert!(r.stderr.starts_with("canctl: "), "{}", r.stderr);
        assert!(r.stderr.contains("use 1 to 127"), "{}", r.stderr);
        assert!(!r.stderr.contains("..="), "{}", r.stderr);
    }
    // Every other bounded number says its range the same way.
    for (args, words) in [
        (&["stream-pdo", "5", "--tpdo", "600"][..], "use 1 to 512"),
        (&["sim", "reset", "--unconfigured", "300"][..], "use 0 to 64"),
        (&["sim", "--epos2-rs232", "--baud", "5"][..], "use 300 to 10000000"),
        (&["lss", "store", "--node", "3"][..], "use 0"),
    ] {
        let r = sim.run(args);
        assert_eq!(r.code, 2, "{args:?}: {}", r.stderr);
        assert!(r.stderr.contains(words) && !r.stderr.contains("..="), "{args:?}: {}", r.stderr);
    }
}

/// The state column shows what each node really shows: a 100 ms heartbeat is waited for
/// (0x1017 says how long), nodes without one are asked by guarding; run after run, the
/// same column on an unchanged bus.
#[test]
fn the_scan_state_column_does_not_flicker() {
    let sim = Sim::new();
    sim.run(&["sdo", "write", "5", "1017", "100"]).ok();
    sim.run(&["nmt", "start", "10"]).ok();
    let column = |sim: &Sim| -> Vec<(u64, String, String)> {
        let scan = sim.run(&["scan", "--format", "json"]).ok().json();
        scan["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| (n["node"].as_u64().unwrap(), n["state"].to_string(), n["state_from"].to_string()))
            .collect()
    };
    let first = column(&sim);
    let state = |node: u64| first.iter().find(|(n, _, _)| *n == node).map(|(_, s, f)| (s.clone(), f.clone()));
    assert_eq!(state(5), Some(("\"pre-operational\"".into(), "\"heartbeat\"".into())), "{first:?}");
    assert_eq!(state(10), Some(("\"operational\"".into(), "\"node guarding\"".into())), "{first:?}");
    for _ in 0..5 {
        assert_eq!(column(&sim), first);
    }
}

/// `--timeout 0` and `--timeout 1.5` were taken (0 ms and 1 ms): every identity "-" and
/// exit 0. A number without a unit is refused, naming the units, and a timeout shorter than
/// a device can answer in is refused with the reason; canctl.toml's timeout the same.
#[test]
fn timeouts_without_a_unit_or_too_short_are_refused() {
    let sim = Sim::new();
    for (t, words) in [("1.5", "has no unit"), ("5", "has no unit"), ("0ms", "shorter than"), ("2ms", "shorter than")] {
        let r = sim.run(&["--timeout", t, "scan"]);
        assert_eq!(r.code, 2, "--timeout {t}: {}", r.stderr);
        assert!(r.stderr.contains(words), "--timeout {t}: {}", r.stderr);
        assert!(r.stdout.is_empty(), "--timeout {t}: nothing scanned: {}", r.stdout);
    }
    let r = sim.run(&["scan", "--window", "100"]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    assert!(r.stderr.contains("has no unit") && r.stderr.contains("ms"), "{}", r.stderr);
    let ok = sim.run(&["--timeout", "1.5s", "sdo", "read", "5", "1018:4"]);
    assert_eq!(ok.code, 0, "{}", ok.stderr);
    std::fs::write(sim.path("canctl.toml"), "timeout = \"0ms\"\n").unwrap();
    let mut c = sim.command(&["sdo", "read", "5", "1018:4"]);
    c.current_dir(sim.path(""));
    let r = common::finish(c.output().unwrap());
    assert_eq!(r.code, 2, "{}", r.stderr);
    assert!(r.stderr.contains("canctl.toml:1: timeout:") && r.stderr.contains("shorter than"), "{}", r.stderr);
}

/// `scan --window 0` (or 5ms) lost nodes silently, exit 0, and replaced the scan cache with
/// what little it found: a window shorter than devices answer in is refused (exit 2, the
/// reason), and a scan that may have missed slow devices does not replace the cache.
#[test]
fn a_scan_window_too_short_to_trust_is_refused_and_never_cached() {
    let sim = Sim::new();
    let cache = sim.path("cache");
    let scan = |window: &str| {
        let mut c = sim.command(&["scan", "--window", window, "--format", "csv"]);
        c.env("XDG_CACHE_HOME", &cache);
        common::finish(c.output().unwrap())
    };
    let cached = || -> String {
        let dir = cache.join("canctl");
        std::fs::read_dir(&dir)
            .map(|d| d.map(|e| std::fs::read_to_string(e.unwrap().path()).unwrap()).collect())
            .unwrap_or_default()
    };
    let full = scan("100ms").ok();
    assert_eq!(full.stdout.lines().count(), 5, "{}", full.stdout);
    let before = cached();
    assert!(before.contains("\"node\":32"), "{before}");
    for w in ["0ms", "5ms"] {
        let r = scan(w);
        assert_eq!(r.code, 2, "--window {w}: {}", r.stderr);
        assert!(r.stderr.contains("shorter than") && r.stderr.contains("use at least"), "{}", r.stderr);
        assert!(r.stdout.is_empty(), "{}", r.stdout);
    }
    // Long enough for these devices, too short for slow ones: reported, said, not cached.
    let short = scan("20ms").ok();
    assert!(short.stderr.contains("the scan cache is kept"), "{}", short.stderr);
    assert_eq!(cached(), before);
}

// ---------------------------------------------------------------------------------------
// `sim:PATH`: the state file is canctl's or nothing is touched; what was learned of a sim
// network goes with it.

mod state_file {
    use super::common::{self, Run};
    use std::path::Path;

    /// canctl in `cwd` on `bus`, with its config, cache and state homes in `home`.
    fn canctl_on(home: &Path, cwd: &Path, bus: &str, args: &[&str]) -> Run {
        let mut c = std::process::Command::new(common::canctl_bin());
        c.current_dir(cwd)
            .env("XDG_CONFIG_HOME", home)
            .env("XDG_CACHE_HOME", home)
            .env("XDG_STATE_HOME", home)
            .env_remove("CANCTL_BUS")
            .arg("--bus")
            .arg(bus)
            .args(args)
            .stdin(std::process::Stdio::null());
        common::finish(c.output().unwrap())
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        names
    }

    /// A file that is not a sim state (`sim:/etc/passwd`), a folder (`sim:/etc`) or a path
    /// whose folder is missing is refused with exit 2, and nothing is written: no lock file
    /// beside it (`passwd.lock` is the lock the system's own tools take), no folder made.
    #[test]
    fn a_state_path_that_is_not_canctls_is_refused_and_nothing_written() {
        let root = tempfile::tempdir().unwrap();
        let home = root.path().join("home");
        let etc = root.path().join("etc");
        std::fs::create_dir_all(&etc).unwrap();
        common::generous_timeout(&home);
        let passwd = etc.join("passwd");
        std::fs::write(&passwd, "root:x:0:0:root:/root:/bin/bash\n").unwrap();
        let missing = etc.join("nonexistent/dir/x.json");
        let cases = [
            (format!("sim:{}", passwd.display()), "is not a sim network's state"),
            (format!("sim:{}", etc.display()), "is a folder"),
            (format!("sim:{}", missing.display()), "there is no folder"),
        ];
        for (bus, said) in &cases {
            for args in [&["scan"][..], &["sim", "reset"]] {
                let run = canctl_on(&home, root.path(), bus, args);
                assert_eq!(run.code, 2, "{bus} {args:?}\n{}\n{}", run.stdout, run.stderr);
                assert!(run.stderr.contains(said), "{bus} {args:?}: {}", run.stderr);
                assert_eq!(listing(root.path()), ["etc", "home"], "{bus} {args:?}");
                assert_eq!(listing(&etc), ["passwd"], "{bus} {args:?}");
            }
        }
        assert_eq!(std::fs::read_to_string(&passwd).unwrap(), "root:x:0:0:root:/root:/bin/bash\n");
        // A new file in a folder that is there is the sim's from then on.
        let fresh = format!("sim:{}", etc.join("sim.json").display());
        canctl_on(&home, root.path(), &fresh, &["scan"]).ok();
        canctl_on(&home, root.path(), &fresh, &["sim", "reset"]).ok();
        canctl_on(&home, root.path(), &fresh, &["scan"]).ok();
    }

    /// The nodes a scan saw belong to the network scanned: `sim reset` forgets them, and
    /// `sim:s.json` in another folder is another network.
    #[test]
    fn a_sim_reset_forgets_the_last_scan_and_relative_paths_are_separate_networks() {
        let root = tempfile::tempdir().unwrap();
        let home = root.path().join("home");
        common::generous_timeout(&home);
        let (a, b) = (root.path().join("a"), root.path().join("b"));
        std::fs::create_dir_all(&a).unwrap();
        std::fs::create_dir_all(&b).unwrap();
        let run = |cwd: &Path, args: &[&str]| canctl_on(&home, cwd, "sim:s.json", args);
        run(&a, &["sim", "reset", "--profile", "instant", "--unconfigured", "3"]).ok();
        run(&a, &["lss", "assign", "--start", "20"]).ok();
        run(&a, &["scan"]).ok();
        let silent = |cwd: &Path, node: &str| {
            let r = run(cwd, &["--timeout", "100ms", "sdo", "read", node, "0x1000"]);
            assert_eq!(r.code, 3, "{}\n{}", r.stdout, r.stderr);
            r.stderr
        };
        assert!(silent(&a, "40").contains("nodes seen on the last scan of sim:s.json: 1, 5, 10, 20, 21, 22, 32"));
        // Another folder's s.json has not been scanned.
        let other = silent(&b, "21");
        assert!(!other.contains("nodes seen on the last scan"), "{other}");
        run(&a, &["sim", "reset", "--profile", "instant", "--unconfigured", "0"]).ok();
        let after = silent(&a, "20");
        assert!(!after.contains("nodes seen on the last scan"), "{after}");
    }
}
