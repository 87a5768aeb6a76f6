//! Completion however the user wrote the line: the bus (and other global options with a
//! value) before or after the subcommand, with a space or `=`, from the environment or from
//! `canctl.toml` — each driven through a real bash, zsh and fish sourcing the scripts we ship.
//!
//! The bus is the literal `sim`, as in every README example: a value that is also the name
//! of a subcommand is what clap_complete's engine used to mistake for that subcommand.

use crate::common;
use common::{canctl_bin, finish};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A folder with the default sim network scanned once, so its node-ids are in the cache.
struct Scanned {
    dir: tempfile::TempDir,
}

impl Scanned {
    fn new() -> Scanned {
        let s = Scanned { dir: tempfile::tempdir().unwrap() };
        let mut c = Command::new(canctl_bin());
        s.env(&mut c);
        c.args(["--bus", "sim", "scan"]).current_dir(s.dir.path());
        finish(c.output().unwrap()).ok();
        s
    }

    fn env(&self, c: &mut Command) {
        let d = self.dir.path();
        c.env("XDG_CONFIG_HOME", d).env("XDG_CACHE_HOME", d).env("XDG_STATE_HOME", d).env_remove("CANCTL_BUS");
    }

    /// A folder whose `canctl.toml` names the bus.
    fn folder_with_settings(&self) -> PathBuf {
        let folder = self.dir.path().join("cabinet");
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::write(folder.join("canctl.toml"), "bus = \"sim\"\n").unwrap();
        folder
    }
}

/// Where the line's bus comes from besides the line itself.
#[derive(Clone, Copy, Debug)]
enum Context {
    Line,
    Environment,
    SettingsFile,
}

/// The forms of a line that asks for the node-ids of `nmt state`.
const FORMS: &[(&str, &str, Context)] = &[
    ("--bus before the subcommand", "canctl --bus sim nmt state ", Context::Line),
    ("--bus= before the subcommand", "canctl --bus=sim nmt state ", Context::Line),
    ("--bus after the subcommand", "canctl nmt state --bus sim ", Context::Line),
    ("--bus= after the subcommand", "canctl nmt --bus=sim state ", Context::Line),
    ("--timeout and --bus before", "canctl --timeout 2s --bus sim nmt state ", Context::Line),
    ("--format and --bus before", "canctl --format json --bus sim nmt state ", Context::Line),
    ("--bus and -v before", "canctl -v --bus sim nmt state ", Context::Line),
    ("CANCTL_BUS", "canctl nmt state ", Context::Environment),
    ("CANCTL_BUS and --timeout before", "canctl --timeout 2s nmt state ", Context::Environment),
    ("canctl.toml", "canctl nmt state ", Context::SettingsFile),
    ("canctl.toml and --format before", "canctl --format csv nmt state ", Context::SettingsFile),
];

/// What `shell` offers at the end of `line` (flags left out), or None when the shell is not
/// installed and CI did not ask for every shell (`CANCTL_TEST_SHELLS=1`).
fn offered(shell: &str, line: &str, context: Context, scanned: &Scanned) -> Option<Vec<String>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let completions = root.join("completions");
    let out_file = scanned.dir.path().join(format!("{shell}-offered"));
    let _ = std::fs::remove_file(&out_file);
    let mut words: Vec<&str> = line.split_whitespace().collect();
    if line.ends_with(' ') {
        words.push("");
    }
    let mut c = Command::new(shell);
    match shell {
        "bash" => {
            // Call the completion function as readline would.
            let quoted: Vec<String> = words.iter().map(|w| format!("'{w}'")).collect();
            let cword = words.len() - 1;
            let script = format!(
                "source '{}'; COMP_WORDS=({}); COMP_CWORD={cword}; COMP_TYPE=9; \
                 _clap_complete_canctl canctl '{}' '{}'; printf '%s\\n' \"${{COMPREPLY[@]}}\"",
                completions.join("canctl.bash").display(),
                quoted.join(" "),
                words[cword],
                words[cword - 1],
            );
            c.args(["--norc", "-c", &script]);
        }
        "zsh" => {
            let driver = root.join("tests/shells/zsh-complete.zsh");
            c.arg("-f").arg(driver).arg(&completions).arg(&out_file).arg(line);
        }
        _ => {
            let script = format!("source '{}'; complete -C '{line}'", completions.join("canctl.fish").display());
            c.args(["--no-config", "-c", &script]);
        }
    }
    let path = format!("{}:{}", canctl_bin().parent().unwrap().display(), std::env::var("PATH").unwrap_or_default());
    c.env("PATH", path);
    scanned.env(&mut c);
    match context {
        Context::Line => c.current_dir(scanned.dir.path()),
        Context::Environment => c.env("CANCTL_BUS", "sim").current_dir(scanned.dir.path()),
        Context::SettingsFile => c.current_dir(scanned.folder_with_settings()),
    };
    let out = match c.output() {
        Ok(out) => out,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound && std::env::var_os("CANCTL_TEST_SHELLS").is_none() => {
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "skipped: {shell} is not installed (CI sets CANCTL_TEST_SHELLS=1)");
            return None;
        }
        Err(e) => panic!("cannot run {shell}: {e}"),
    };
    let run = finish(out).ok();
    assert!(run.stderr.is_empty(), "{shell}: {}", run.stderr);
    let text = match shell {
        "zsh" => std::fs::read_to_string(&out_file).unwrap_or_default(),
        _ => run.stdout,
    };
    let mut got: Vec<String> = Vec::new();
    for word in text.lines().map(|l| l.split('\t').next().unwrap()).filter(|w| !w.is_empty() && !w.starts_with('-')) {
        // zsh's _describe hands the same candidates to compadd more than once.
        if !got.iter().any(|g| g == word) {
            got.push(word.to_string());
        }
    }
    Some(got)
}

/// Every form in one shell; the failures are listed together, so one run shows the matrix.
fn every_form_offers_the_scanned_nodes(shell: &str) {
    let scanned = Scanned::new();
    let mut wrong = Vec::new();
    for (name, line, context) in FORMS {
        let Some(got) = offered(shell, line, *context, &scanned) else { return };
        if got != ["1", "5", "10", "32"] {
            wrong.push(format!("{name} ({line:?}, {context:?}): offered {got:?}"));
        }
    }
    assert!(wrong.is_empty(), "{shell} does not offer the node-ids for:\n{}", wrong.join("\n"));
}

#[test]
fn bash_completes_node_ids_in_every_form() {
    every_form_offers_the_scanned_nodes("bash");
}

#[test]
fn zsh_completes_node_ids_in_every_form() {
    every_form_offers_the_scanned_nodes("zsh");
}

#[test]
fn fish_completes_node_ids_in_every_form() {
    every_form_offers_the_scanned_nodes("fish");
}

/// Objects by name and bit rates, behind `--bus sim` before the subcommand.
#[test]
fn objects_and_bit_rates_after_a_bus_named_like_a_subcommand() {
    let scanned = Scanned::new();
    for shell in ["bash", "zsh", "fish"] {
        let Some(objects) = offered(shell, "canctl --bus sim sdo read 5 ProducerHeart", Context::Line, &scanned) else {
            continue;
        };
        assert_eq!(objects, ["ProducerHeartbeatTime"], "{shell}");
        let rates = offered(shell, "canctl --bus sim lss set-baud ", Context::Line, &scanned).unwrap();
        assert!(rates.iter().any(|r| r == "500k") && rates.iter().any(|r| r == "1M"), "{shell}: {rates:?}");
    }
}
