//! What a new user meets in the first hour (issue 25, "Friction"): messages that say what
//! is wrong once and name the path, output paths checked before the work, tables that fit
//! the terminal, progress while slow work runs, suggestions from the node's own dictionary.

mod common;

use common::Sim;

fn reset(sim: &Sim, profile: &str) {
    sim.run(&["sim", "reset", "--profile", profile]).ok();
}

/// An EDS or DCF that cannot be read is said once: "cannot read FILE: why", not
/// "cannot use EDS cannot read FILE" nor "cannot use cannot read FILE".
#[test]
fn an_unreadable_dictionary_is_said_once() {
    let sim = Sim::new();
    reset(&sim, "instant");
    for args in [
        &["--eds", "/nonexistent.eds", "scan"][..],
        &["--eds", "5=/nonexistent.eds", "scan"],
        &["config", "diff", "5", "/nonexistent.dcf"],
        &["config", "apply", "5", "/nonexistent.dcf"],
    ] {
        let run = sim.run(args);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        let name = if args.contains(&"scan") { "/nonexistent.eds" } else { "/nonexistent.dcf" };
        assert!(run.stderr.starts_with(&format!("canctl: cannot read {name}: ")), "{args:?}: {}", run.stderr);
        assert!(!run.stderr.contains("cannot use"), "{args:?}: {}", run.stderr);
    }
}

/// `man --out` into a folder that cannot be made names the path it could not make.
#[test]
fn man_out_names_the_path_it_cannot_write() {
    let run = common::bare(&["man", "--out", "/proc/x"]);
    assert_eq!(run.code, 7, "{}", run.stderr);
    assert!(run.stderr.contains("/proc/x"), "{}", run.stderr);
}

/// `--out` is checked before the work, as `--log-frames` is: a path in a folder that does
/// not exist fails before a single frame is sent, and says which folder is missing.
#[test]
fn out_paths_are_checked_before_the_work() {
    let sim = Sim::new();
    reset(&sim, "instant");
    let log = sim.path("frames.log");
    let log = log.to_str().unwrap();
    let missing = sim.path("no-such-folder/x.dcf");
    let missing = missing.to_str().unwrap();
    for args in [
        &["--log-frames", log, "config", "dump", "1", "--out", missing][..],
        &["--log-frames", log, "sdo", "read", "1", "1008", "--out", missing],
    ] {
        let run = sim.run(args);
        assert_eq!(run.code, 7, "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains("there is no folder") && run.stderr.contains("no-such-folder"), "{}", run.stderr);
        let frames = std::fs::read_to_string(log).unwrap();
        assert!(frames.is_empty(), "{args:?} talked to the bus before checking --out:\n{frames}");
    }
    // A folder given where a file is meant is refused at once too.
    let run = sim.run(&["--log-frames", log, "config", "dump", "1", "--out", sim.path("").to_str().unwrap()]);
    assert_eq!(run.code, 7, "{}", run.stderr);
    assert!(run.stderr.contains("it is a directory"), "{}", run.stderr);
    assert!(std::fs::read_to_string(log).unwrap().is_empty());
    // And a good path still gets its file.
    let good = sim.path("node1.dcf");
    sim.run(&["config", "dump", "1", "--out", good.to_str().unwrap()]).ok();
    assert!(std::fs::read_to_string(&good).unwrap().contains("[DeviceInfo]"));
}
