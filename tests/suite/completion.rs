//! Shell completion at run time: what the shell gets for each kind of argument, through the
//! same entry point the generated scripts call, and through a real bash sourcing our script.

use crate::common;
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
    let by_name = complete(&sim, &["--bus", &bus, "sdo", "write", "5", "ProducerHeart"]);
    assert_eq!(by_name, [("ProducerHeartbeatTime".to_string(), "0x1017:0 (u16 rw)".to_string())]);

    // With the device's EDS, its own objects are offered, under its names; the node is
    // found past the flag and its value.
    let eds =
        format!("5={}", std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("eds/canctl-sim-sensor.eds").display());
    let with_eds = complete(&sim, &["--bus", &bus, "sdo", "read", "--eds", &eds, "5", "0x6005"]);
    let step = with_eds.iter().find(|(v, _)| v == "0x6005:1").expect("the EDS's own object");
    assert!(step.1.contains("Measuring step"), "{step:?}");
    let by_name = complete(&sim, &["--bus", &bus, "sdo", "read", "--eds", &eds, "5", "LinearEnc"]);
    let name = by_name.iter().find(|(v, _)| v == "LinearEncoderMeasuringStep").expect("offered by name");
    assert!(name.1.starts_with("0x6005:1 "), "{name:?}");
    let without = complete(&sim, &["--bus", &bus, "sdo", "read", "5", "0x6005"]);
    assert!(without.iter().all(|(v, _)| v != "0x6005:1"), "{without:?}");
}

#[test]
fn a_refused_eds_is_said_not_silently_replaced_by_the_built_in_dictionary() {
    let sim = Sim::new();
    let broken = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/eds/broken-line.eds");
    let mut c = Command::new(canctl_bin());
    c.env("XDG_CONFIG_HOME", sim.path("")).env("XDG_CACHE_HOME", sim.path("")).env_remove("CANCTL_BUS");
    c.env("COMPLETE", "fish").arg("--").arg("canctl");
    c.args(["--bus", &sim.bus(), "sdo", "read", "--eds", &format!("5={}", broken.display()), "5", "0x1017"]);
    let out = c.output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("broken-line.eds:3:"), "the refusal, with file:line: {stderr}");
    assert!(stderr.contains("built-in dictionary"), "what is offered instead: {stderr}");
    // The built-in objects are still offered.
    assert!(String::from_utf8_lossy(&out.stdout).contains("0x1017:0"));
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

/// What a real shell offers for `canctl --bus SIM nmt state <Tab>` after sourcing the script
/// we ship (flags left out), or None when that shell is not installed and CI did not ask for
/// every shell (`CANCTL_TEST_SHELLS=1`).
fn in_shell(shell: &str, script: &str, sim: &Sim) -> Option<Vec<String>> {
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("completions").join(script);
    let bus = sim.bus();
    let (args, line) = match shell {
        // bash: call the completion function as readline would.
        "bash" => (
            vec!["--norc".to_string(), "-c".to_string()],
            format!(
                "source '{}'; COMP_WORDS=(canctl --bus '{bus}' nmt state ''); COMP_CWORD=5; COMP_TYPE=9; \
                 _clap_complete_canctl canctl '' state; printf '%s\\n' \"${{COMPREPLY[@]}}\"",
                script.display()
            ),
        ),
        // zsh: <Tab> in an interactive zsh on a pseudo-terminal, the script installed in $fpath.
        "zsh" => {
            let driver = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/shells/zsh-complete.zsh");
            let dir = script.parent().unwrap().display().to_string();
            let out = sim.path("zsh-offered").display().to_string();
            let line = format!("canctl --bus {bus} nmt state ");
            (vec!["-f".to_string(), driver.display().to_string(), dir, out], line)
        }
        // fish: ask it what it would complete.
        _ => (
            vec!["--no-config".to_string(), "-c".to_string()],
            format!("source '{}'; complete -C 'canctl --bus {bus} nmt state '", script.display()),
        ),
    };
    let path = format!("{}:{}", canctl_bin().parent().unwrap().display(), std::env::var("PATH").unwrap_or_default());
    let mut c = Command::new(shell);
    c.args(args).arg(line).env("PATH", path).env_remove("CANCTL_BUS");
    c.env("XDG_CONFIG_HOME", sim.path("")).env("XDG_CACHE_HOME", sim.path(""));
    let out = match c.output() {
        Ok(out) => out,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound && std::env::var_os("CANCTL_TEST_SHELLS").is_none() => {
            common::skipped(&format!("{shell} is not installed (CI installs it and sets CANCTL_TEST_SHELLS=1)"));
            return None;
        }
        Err(e) => panic!("cannot run {shell}: {e}"),
    };
    let run = finish(out).ok();
    assert!(run.stderr.is_empty(), "{shell}: {}", run.stderr);
    let offered = match shell {
        "zsh" => std::fs::read_to_string(sim.path("zsh-offered")).unwrap_or_default(),
        _ => run.stdout,
    };
    let mut got: Vec<String> = Vec::new();
    for word in offered.lines().map(|l| l.split('\t').next().unwrap()).filter(|w| !w.starts_with('-')) {
        // zsh's _describe hands the same candidates to compadd more than once.
        if !got.iter().any(|g| g == word) {
            got.push(word.to_string());
        }
    }
    Some(got)
}

/// The node-ids the last scan found, offered by the shell itself.
fn shell_offers_the_scanned_nodes(shell: &str, script: &str) {
    let sim = Sim::new();
    sim.run(&["scan"]).ok();
    if let Some(got) = in_shell(shell, script, &sim) {
        assert_eq!(got, ["1", "5", "10", "32"], "{shell}");
    }
}

#[test]
fn bash_completes_through_the_shipped_script() {
    shell_offers_the_scanned_nodes("bash", "canctl.bash");
}

#[test]
fn fish_completes_through_the_shipped_script() {
    shell_offers_the_scanned_nodes("fish", "canctl.fish");
}

#[test]
fn zsh_completes_through_the_shipped_script() {
    shell_offers_the_scanned_nodes("zsh", "_canctl");
}

/// zsh takes `value:description`, so the colons of `0x1018:1` must reach it escaped.
#[test]
fn zsh_gets_colons_escaped() {
    let sim = Sim::new();
    let mut c = Command::new(canctl_bin());
    c.env("XDG_CONFIG_HOME", sim.path("")).env("XDG_CACHE_HOME", sim.path("")).env_remove("CANCTL_BUS");
    c.env("COMPLETE", "zsh").env("_CLAP_COMPLETE_INDEX", "4").env("_CLAP_IFS", "\n");
    c.args(["--", "canctl", "sdo", "read", "1", "0x1018"]);
    let run = finish(c.output().unwrap()).ok();
    assert!(run.stdout.lines().any(|l| l == "0x1018\\:1:Identity object: Vendor-ID (u32 ro)"), "{}", run.stdout);
}

/// What a real bash offers for `canctl WORDS<Tab>` (the last word is the one being typed)
/// after sourcing the script we ship, flags left out.
fn bash_offers(sim: &Sim, words: &[&str]) -> Vec<String> {
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("completions/canctl.bash");
    let quoted: Vec<String> = words.iter().map(|w| format!("'{w}'")).collect();
    let line = format!(
        "source '{}'; COMP_WORDS=(canctl {}); COMP_CWORD={}; COMP_TYPE=9; \
         _clap_complete_canctl canctl '{}' '{}'; printf '%s\\n' \"${{COMPREPLY[@]}}\"",
        script.display(),
        quoted.join(" "),
        words.len(),
        words[words.len() - 1],
        words.get(words.len().wrapping_sub(2)).unwrap_or(&"canctl"),
    );
    let path = format!("{}:{}", canctl_bin().parent().unwrap().display(), std::env::var("PATH").unwrap_or_default());
    let mut c = Command::new("bash");
    c.args(["--norc", "-c", &line]).env("PATH", path).env_remove("CANCTL_BUS");
    c.env("XDG_CONFIG_HOME", sim.path("")).env("XDG_CACHE_HOME", sim.path(""));
    let run = finish(c.output().unwrap()).ok();
    assert!(run.stderr.is_empty(), "bash: {}", run.stderr);
    run.stdout.lines().filter(|w| !w.is_empty() && !w.starts_with('-')).map(str::to_string).collect()
}

/// Objects are offered only where the node is known to have them. After a scan without a
/// description of node 5: the CiA 301 mandatory objects and its profile's, not the built-in
/// dictionary's guesses at its communication objects (node 5 has no TPDO2, no 0x1006);
/// then what it answered is offered too, and what it refused (abort 0x06020000) never again.
#[test]
fn objects_are_offered_only_where_the_node_is_known_to_have_them() {
    let sim = Sim::new();
    let bus = sim.bus();
    sim.run(&["scan"]).ok();
    let comm = bash_offers(&sim, &["--bus", &bus, "sdo", "read", "5", "0x10"]);
    for mandatory in ["0x1000:0", "0x1001:0", "0x1017:0", "0x1018:1"] {
        assert!(comm.iter().any(|o| o == mandatory), "{mandatory}: {comm:?}");
    }
    assert!(!comm.iter().any(|o| o.starts_with("0x1006")), "node 5 has no 0x1006: {comm:?}");
    assert_eq!(bash_offers(&sim, &["--bus", &bus, "sdo", "read", "5", "0x18"]), Vec::<String>::new());

    // What it answered is known.
    sim.run(&["sdo", "read", "5", "0x1800:1"]).ok();
    assert_eq!(bash_offers(&sim, &["--bus", &bus, "sdo", "read", "5", "0x18"]), ["0x1800:1"]);

    // A profile object it refused is not offered again.
    let profile = bash_offers(&sim, &["--bus", &bus, "sdo", "read", "5", "0x600"]);
    assert!(profile.iter().any(|o| o == "0x6004:0") && profile.iter().any(|o| o == "0x6000:0"), "{profile:?}");
    assert_eq!(sim.run(&["sdo", "read", "5", "0x6004"]).code, 4);
    let profile = bash_offers(&sim, &["--bus", &bus, "sdo", "read", "5", "0x600"]);
    assert!(!profile.iter().any(|o| o.starts_with("0x6004")), "{profile:?}");
    assert!(profile.iter().any(|o| o == "0x6000:0"), "{profile:?}");

    // Another node's refusals are its own.
    let other = bash_offers(&sim, &["--bus", &bus, "sdo", "read", "10", "0x100"]);
    assert!(other.iter().any(|o| o == "0x1000:0"), "{other:?}");
}

/// A scan given the node's EDS remembers it: later lines without `--eds` are offered the
/// node's own objects (and only those: its EDS lists TPDO1, not TPDO2), by address, named
/// by it; by name only with `--eds`, where the command finds them by name.
#[test]
fn the_description_a_scan_used_is_remembered_for_completion() {
    let sim = Sim::new();
    let bus = sim.bus();
    let eds = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("eds/canctl-sim-sensor.eds");
    sim.run(&["--eds", &format!("5={}", eds.display()), "scan"]).ok();
    let own = bash_offers(&sim, &["--bus", &bus, "sdo", "read", "5", "0x6005"]);
    assert!(own.iter().any(|o| o == "0x6005:1"), "{own:?}");
    let by_name = bash_offers(&sim, &["--bus", &bus, "sdo", "read", "5", "LinearEnc"]);
    assert!(!by_name.iter().any(|o| o == "LinearEncoderMeasuringStep"), "sdo read would refuse it: {by_name:?}");
    let with_eds = format!("5={}", eds.display());
    let by_name = bash_offers(&sim, &["--bus", &bus, "sdo", "read", "--eds", &with_eds, "5", "LinearEnc"]);
    assert!(by_name.iter().any(|o| o == "LinearEncoderMeasuringStep"), "{by_name:?}");
    let tpdos = bash_offers(&sim, &["--bus", &bus, "sdo", "read", "5", "0x180"]);
    assert!(tpdos.iter().any(|o| o == "0x1800:1"), "{tpdos:?}");
    assert!(!tpdos.iter().any(|o| o.starts_with("0x1801")), "{tpdos:?}");
}

/// The description a node stores in itself (0x1021), once `config eds --out` saved it, is
/// what completion offers from: node 10's lists TPDO1 and no analogue inputs (0x6401),
/// which the built-in CiA 401 dictionary would have guessed.
#[test]
fn the_description_a_node_stores_is_remembered_once_saved() {
    let sim = Sim::new();
    let bus = sim.bus();
    sim.run(&["scan"]).ok();
    let guessed = bash_offers(&sim, &["--bus", &bus, "sdo", "read", "10", "0x64"]);
    assert!(guessed.iter().any(|o| o.starts_with("0x6401")), "the built-in profile, before: {guessed:?}");
    let saved = sim.path("node10.eds");
    sim.run(&["config", "eds", "10", "--out", saved.to_str().unwrap()]).ok();
    assert_eq!(bash_offers(&sim, &["--bus", &bus, "sdo", "read", "10", "0x64"]), Vec::<String>::new());
    let tpdo = bash_offers(&sim, &["--bus", &bus, "sdo", "read", "10", "0x180"]);
    assert!(tpdo.iter().any(|o| o == "0x1800:1"), "{tpdo:?}");
}

/// A name completion offers is one the command accepts: node 5's profile (CiA 406) names
/// 0x6000 "Operating parameters", but `sdo read` looks names up in the dictionary it uses
/// for the node, where that name is not; offering it led to "no object named".
#[test]
fn every_name_offered_is_one_the_command_accepts() {
    let sim = Sim::new();
    let bus = sim.bus();
    sim.run(&["scan"]).ok();
    let offered = bash_offers(&sim, &["--bus", &bus, "sdo", "read", "5", "Operat"]);
    assert!(!offered.is_empty(), "Operating status is known by name");
    for name in &offered {
        let run = sim.run(&["sdo", "read", "5", name]);
        assert_ne!(run.code, 2, "{name} offered, then refused: {}", run.stderr);
    }
}
