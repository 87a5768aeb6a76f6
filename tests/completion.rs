//! Shell completion at run time: what the shell gets for each kind of argument, through the
//! same entry point the generated scripts call, and through a real bash sourcing our script.

mod common;
use common::{canctl_bin, finish, Sim};
use std::process::Command;

/// The candidates (value, help) fish would be given for the partial command line `words`.
fn complete(sim: &Sim, words: &[&str]) -> Vec<(String, String)> {
    let mut c = Command::new(canctl_bin());
    c.env("XDG_CONFIG_HOME", sim.path("")).env("XDG_CACHE_HOME", sim.path("")).env_remove("CANCTL_BUS");
    c.env("COMPLETE", "fish").arg("--").arg("canctl").args(words);
    let run = finish(c.output().unwrap()).ok();
    run.stdout
        .lines()
        .map(|l| {
            let (value, help) = l.split_once('\t').unwrap_or((l, ""));
            (value.to_string(), help.to_string())
        })
        .collect()
}

fn values(candidates: &[(String, String)]) -> Vec<&str> {
    candidates.iter().map(|(v, _)| v.as_str()).filter(|v| !v.starts_with('-')).collect()
}

#[test]
fn node_ids_come_from_the_last_scan_of_that_bus() {
    let sim = Sim::new();
    let bus = sim.bus();
    assert!(values(&complete(&sim, &["--bus", &bus, "sdo", "read", ""])).is_empty(), "nothing scanned yet");
    assert!(!sim.path("sim.json").exists(), "completing must not touch the bus");

    sim.run(&["scan"]).ok();
    let got = complete(&sim, &["--bus", &bus, "sdo", "read", ""]);
    assert_eq!(values(&got), ["1", "5", "10", "32"]);
    let epos = got.iter().find(|(v, _)| v == "1").unwrap();
    assert!(epos.1.contains("EPOS2") && epos.1.contains("0x000000FB"), "{epos:?}");

    // NMT may address every node, which is spelled out.
    let nmt = complete(&sim, &["--bus", &bus, "nmt", "start", ""]);
    assert_eq!(values(&nmt), ["1", "5", "10", "32", "all"]);

    // Another bus has its own (empty) history.
    let other = format!("sim:{}", sim.path("other.json").display());
    assert!(values(&complete(&sim, &["--bus", &other, "sdo", "read", ""])).is_empty());
}

#[test]
fn objects_come_from_the_nodes_dictionary() {
    let sim = Sim::new();
    let bus = sim.bus();
    let got = complete(&sim, &["--bus", &bus, "sdo", "read", "5", "0x10"]);
    let entry = got.iter().find(|(v, _)| v == "0x1017:0").expect("producer heartbeat time offered");
    assert!(entry.1.contains("heartbeat") || entry.1.contains("Heartbeat"), "{entry:?}");
    assert!(got.iter().all(|(v, _)| v.starts_with("0x10")), "only what matches the prefix: {got:?}");

    // With the device's EDS, its own objects are offered, under its names; the node is
    // found past the flag and its value.
    let eds =
        format!("5={}", std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("eds/canctl-sim-sensor.eds").display());
    let with_eds = complete(&sim, &["--bus", &bus, "sdo", "read", "--eds", &eds, "5", "0x6005"]);
    let step = with_eds.iter().find(|(v, _)| v == "0x6005:1").expect("the EDS's own object");
    assert!(step.1.contains("Measuring step"), "{step:?}");
    let without = complete(&sim, &["--bus", &bus, "sdo", "read", "5", "0x6005"]);
    assert!(without.iter().all(|(v, _)| v != "0x6005:1"), "{without:?}");
}

#[test]
fn fixed_sets_and_buses() {
    let sim = Sim::new();
    let types = complete(&sim, &["sdo", "write", "1", "0x1017", "100", "--type", ""]);
    assert!(values(&types).contains(&"u16") && values(&types).contains(&"vs"), "{types:?}");
    let rates = complete(&sim, &["lss", "set-baud", ""]);
    assert!(values(&rates).contains(&"500k") && values(&rates).contains(&"1M"), "{rates:?}");
    let buses = complete(&sim, &["--bus", ""]);
    assert!(values(&buses).contains(&"sim"), "{buses:?}");
}

/// bash itself: source the script we ship, then call its completion function as readline would.
#[test]
fn bash_completes_through_the_shipped_script() {
    let sim = Sim::new();
    sim.run(&["scan"]).ok();
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("completions/canctl.bash");
    let bin_dir = canctl_bin().parent().unwrap().to_path_buf();
    let path = format!("{}:{}", bin_dir.display(), std::env::var("PATH").unwrap_or_default());
    let line = format!(
        "source '{}'; COMP_WORDS=(canctl --bus '{}' nmt state ''); COMP_CWORD=5; COMP_TYPE=9; \
         _clap_complete_canctl canctl '' state; printf '%s\\n' \"${{COMPREPLY[@]}}\"",
        script.display(),
        sim.bus()
    );
    let out = Command::new("bash")
        .arg("--norc")
        .arg("-c")
        .arg(line)
        .env("PATH", path)
        .env("XDG_CONFIG_HOME", sim.path(""))
        .env("XDG_CACHE_HOME", sim.path(""))
        .env_remove("CANCTL_BUS")
        .output()
        .unwrap();
    let run = finish(out).ok();
    let got: Vec<&str> = run.stdout.lines().filter(|w| !w.starts_with('-')).collect();
    assert_eq!(got, ["1", "5", "10", "32"], "stderr: {}", run.stderr);
}
