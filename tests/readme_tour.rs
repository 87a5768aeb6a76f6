//! The README's first-commissioning walk-through, run as written: every command in it must
//! succeed on a fresh sim network and leave the network as the text says.

mod common;
use common::{canctl_bin, finish, Sim};
use std::process::Command;

#[test]
fn the_readme_tour_runs_as_written() {
    let readme = include_str!("../README.md");
    let start = readme.find("<!-- tour -->\n```\n").expect("the tour block") + "<!-- tour -->\n```\n".len();
    let script = &readme[start..start + readme[start..].find("```").expect("its end")];
    assert!(script.lines().filter(|l| l.starts_with("canctl ")).count() >= 10, "{script}");

    let sim = Sim::new();
    let dir = sim.path("");
    let path = format!("{}:{}", canctl_bin().parent().unwrap().display(), std::env::var("PATH").unwrap_or_default());
    let mut c = Command::new("bash");
    c.arg("-c").arg(format!("set -euo pipefail\n{script}")).env("PATH", path);
    let run = finish(in_dir(&mut c, &dir).output().unwrap());
    assert_eq!(run.code, 0, "the tour stopped\nstdout: {}\nstderr: {}", run.stdout, run.stderr);

    assert!(run.stderr.contains("3 device(s) given a node-id"), "{}", run.stderr);
    assert!(run.stderr.ends_with("7 node(s) on sim\n"), "{}", run.stderr);
    assert_eq!(run.stdout.matches("TPDO1").count(), 5, "{}", run.stdout);
    // Node 20 took node 5's heartbeat time but kept its own TPDO COB-ID.
    let read = |obj: &str, dtype: &str| {
        let mut c = Command::new(canctl_bin());
        c.args(["--bus", "sim", "sdo", "read", "20", obj, "--type", dtype]);
        finish(in_dir(&mut c, &dir).output().unwrap()).ok().stdout.trim().to_string()
    };
    assert_eq!(read("1017", "u16"), "100");
    assert_eq!(read("1800:1", "u32"), 0x194.to_string());
    assert!(dir.join("sensor.dcf").exists());
}

/// Run in `dir`, with settings, scan cache and the default sim network (XDG_STATE_HOME) there.
fn in_dir<'a>(c: &'a mut Command, dir: &std::path::Path) -> &'a mut Command {
    c.current_dir(dir).env_remove("CANCTL_BUS");
    for var in ["XDG_CONFIG_HOME", "XDG_CACHE_HOME", "XDG_STATE_HOME"] {
        c.env(var, dir);
    }
    c
}
