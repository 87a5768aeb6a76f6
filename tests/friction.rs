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

/// What `--bus` echoes is cut to a readable length; a name one letter from `sim` gets
/// "did you mean"; a path that is no serial port is said to be none, not "Not a typewriter".
#[test]
fn bus_mistakes_are_explained() {
    let long = "a".repeat(100_000);
    let run = common::bare(&["--bus", &long, "scan"]);
    assert_eq!(run.code, 2, "{}", &run.stderr[..run.stderr.len().min(300)]);
    assert!(run.stderr.len() < 1000, "{} bytes of message", run.stderr.len());
    assert!(run.stderr.contains("(100000 characters)"), "{}", run.stderr);

    let run = common::bare(&["--bus", "sims", "scan"]);
    assert_eq!(run.code, 5, "{}", run.stderr);
    assert!(run.stderr.contains("did you mean --bus sim?"), "{}", run.stderr);

    let run = common::bare(&["--bus", "epos2-rs232:/dev/null", "scan"]);
    assert_eq!(run.code, 5, "{}", run.stderr);
    assert!(run.stderr.starts_with("canctl: /dev/null is not a serial port"), "{}", run.stderr);
    assert!(!run.stderr.contains("typewriter"), "{}", run.stderr);
}

/// A fault for a device the sim network does not have is refused, naming the ones it has,
/// rather than accepted and never fired.
#[test]
fn a_fault_for_no_device_is_refused() {
    let sim = Sim::new();
    let run = sim.run(&["sim", "reset", "--fault", "99:drop"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("node 99") && run.stderr.contains("1, 5, 10, 32"), "{}", run.stderr);
    let run = sim.run(&["sim", "reset", "--unconfigured", "0", "--fault", "sensor-09501301:drop"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    sim.run(&["sim", "reset", "--fault", "sensor-09501301:drop", "--fault", "5:drop"]).ok();
}
