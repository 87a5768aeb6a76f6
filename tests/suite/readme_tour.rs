//! The README's first-commissioning walk-through, run as written, one line at a time on a
//! fresh sim network: every command must succeed, and what each line's comment claims is
//! checked against what that command printed and what the network then holds.

use crate::common;
use common::{canctl_bin, finish, Run};
use std::path::Path;
use std::process::Command;

/// What a tour line's comment claims, checked against its run. Every commented line of
/// the tour must have an entry (keyed by the start of the command), so a new claim in the
/// README cannot go unchecked.
type Check = fn(&Run, &Path);

fn claims() -> Vec<(&'static str, Check)> {
    vec![
        // Checked at the end: the sim network's state file is where the tour ran.
        ("export CANCTL_BUS=sim", |_, _| {}),
        ("canctl sim reset", |r, _| assert!(r.stdout.contains("sim network reset"), "{}", r.stdout)),
        ("canctl scan", |r, _| {
            let nodes = r.stderr.contains("4 node(s) on sim") || r.stderr.contains("7 node(s) on sim");
            assert!(nodes, "{}", r.stderr);
        }),
        ("canctl lss assign --start 20", |r, dir| {
            assert!(r.stderr.contains("3 device(s) given a node-id"), "{}", r.stderr);
            // The three sensors fresh from the box: serials 0x09501301 to 0x09501303.
            let mut serials: Vec<u32> =
                ["20", "21", "22"].iter().map(|n| read(dir, n, "1018:4", "u32").parse().unwrap()).collect();
            serials.sort();
            assert_eq!(serials, [0x0950_1301, 0x0950_1302, 0x0950_1303]);
            assert!(!r.stdout.contains("not stored") && !r.stderr.contains("not stored"), "{}", r.stdout);
        }),
        ("canctl sdo read 20 IdentityObjectSerialNumber", |r, dir| {
            assert_eq!(r.stdout.trim(), read(dir, "20", "0x1018:4", "u32"), "by name, or 0x1018:4");
        }),
        ("canctl config dump 5 --out sensor.dcf", |_, dir| {
            let dcf = std::fs::read_to_string(dir.join("sensor.dcf")).unwrap();
            let heartbeat = &dcf[dcf.find("[1017]").expect("0x1017 in the DCF")..];
            let value = heartbeat.lines().find_map(|l| l.strip_prefix("ParameterValue=")).unwrap();
            assert_eq!(value, "0x64", "the heartbeat time as set up (100 ms):\n{heartbeat}");
        }),
        ("canctl config diff 20 sensor.dcf", |r, _| assert!(r.stdout.contains("0x1017:0"), "{}", r.stdout)),
        ("canctl config apply 20 sensor.dcf --verify --store", |r, dir| {
            assert!(r.stdout.contains("verified") && r.stderr.contains("stored"), "{}{}", r.stdout, r.stderr);
            // Its own COB-IDs: the DCF says $NODEID+0x180, which is 0x194 for node 20.
            assert_eq!(read(dir, "20", "1800:1", "u32"), 0x194.to_string());
            assert_eq!(read(dir, "20", "1017", "u16"), "100");
        }),
        ("canctl nmt reset 20", |r, dir| {
            assert!(r.stdout.contains("node 20"), "{}", r.stdout);
            assert_eq!(read(dir, "20", "1017", "u16"), "100", "booted with what it stored");
        }),
        ("canctl stream-pdo 20 --start --count 5", |r, _| {
            assert_eq!(r.stdout.matches("TPDO1").count(), 5, "{}", r.stdout);
            assert!(r.stdout.contains("Position value") && r.stdout.contains("Speed value"), "{}", r.stdout);
        }),
    ]
}

#[test]
fn the_readme_tour_runs_as_written() {
    let readme = include_str!("../../README.md");
    let start = readme.find("<!-- tour -->\n```\n").expect("the tour block") + "<!-- tour -->\n```\n".len();
    let script = &readme[start..start + readme[start..].find("```").expect("its end")];
    let lines: Vec<&str> = script.lines().filter(|l| !l.trim().is_empty()).collect();
    assert!(lines.iter().filter(|l| l.starts_with("canctl ")).count() >= 10, "{script}");

    let dir = tempfile::tempdir().unwrap();
    let claims = claims();
    let mut scans = Vec::new();
    for line in &lines {
        let command = line.split('#').next().unwrap().trim();
        let run = run_line(dir.path(), &lines, line);
        assert_eq!(run.code, 0, "`{command}` failed\nstdout: {}\nstderr: {}", run.stdout, run.stderr);
        if command == "canctl scan" {
            scans.push(format!("{}{}", run.stderr, run.stdout));
        }
        let claim = claims.iter().find(|(prefix, _)| command.starts_with(prefix));
        match claim {
            Some((_, check)) => check(&run, dir.path()),
            None => assert!(!line.contains('#'), "the tour claims something no check covers: {line}"),
        }
    }
    assert!(scans[0].contains("4 node(s) on sim"), "{}", scans[0]);
    assert!(scans[0].contains("3 device(s) without a node-id"), "{}", scans[0]);
    assert!(scans.last().unwrap().contains("7 node(s) on sim"), "{}", scans.last().unwrap());
    assert!(dir.path().join("canctl/sim.json").exists(), "every command talked to the sim network");
}

/// One tour line, in a shell that has run the `export` lines before it (as a reader's would).
fn run_line(dir: &Path, lines: &[&str], line: &str) -> Run {
    let exports: Vec<&str> = lines.iter().copied().filter(|l| l.starts_with("export ")).collect();
    let path = format!("{}:{}", canctl_bin().parent().unwrap().display(), std::env::var("PATH").unwrap_or_default());
    let mut c = Command::new("bash");
    c.arg("-c").arg(format!("set -euo pipefail\n{}\n{line}", exports.join("\n"))).env("PATH", path);
    finish(in_dir(&mut c, dir).output().unwrap())
}

/// `canctl --bus sim sdo read NODE OBJ --type T` in the tour's folder.
fn read(dir: &Path, node: &str, obj: &str, dtype: &str) -> String {
    let mut c = Command::new(canctl_bin());
    c.args(["--bus", "sim", "sdo", "read", node, obj, "--type", dtype]);
    finish(in_dir(&mut c, dir).output().unwrap()).ok().stdout.trim().to_string()
}

/// Run in `dir`, with settings, scan cache and the default sim network (XDG_STATE_HOME) there.
fn in_dir<'a>(c: &'a mut Command, dir: &Path) -> &'a mut Command {
    c.current_dir(dir).env_remove("CANCTL_BUS");
    for var in ["XDG_CONFIG_HOME", "XDG_CACHE_HOME", "XDG_STATE_HOME"] {
        c.env(var, dir);
    }
    c
}
