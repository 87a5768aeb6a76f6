//! canctl.toml and ~/.config/canctl/config.toml: precedence (flag > CANCTL_BUS > project
//! file > user file > default), files found from a subdirectory, broken files.

use crate::common;

use std::path::Path;
use std::process::Command;

/// canctl run in `dir`, with `config_home` as XDG_CONFIG_HOME and no CANCTL_BUS unless given.
fn canctl(dir: &Path, config_home: &Path, env_bus: Option<&str>, args: &[&str]) -> common::Run {
    let mut c = Command::new(common::canctl_bin());
    c.current_dir(dir).env_remove("CANCTL_BUS").env("XDG_CONFIG_HOME", config_home).args(args);
    if let Some(b) = env_bus {
        c.env("CANCTL_BUS", b);
    }
    common::finish(c.output().unwrap())
}

#[test]
fn flags_over_environment_over_project_file_over_user_file() {
    let root = tempfile::tempdir().unwrap();
    let (project, home) = (root.path().join("cell3"), root.path().join("home"));
    std::fs::create_dir_all(project.join("drives")).unwrap();
    std::fs::create_dir_all(home.join("canctl")).unwrap();
    let bus = |name: &str| format!("sim:{}", root.path().join(name).display());
    std::fs::write(home.join("canctl/config.toml"), format!("bus = \"{}\"\ntimeout = \"2s\"\n", bus("user.json")))
        .unwrap();
    let settings = |dir: &Path, env: Option<&str>, args: &[&str]| {
        let mut a = args.to_vec();
        a.extend(["settings", "--format", "json"]);
        canctl(dir, &home, env, &a).ok().json()
    };
    // The user file alone.
    let s = settings(root.path(), None, &[]);
    assert_eq!((s["bus"].as_str(), s["timeout_ms"].as_u64()), (Some(bus("user.json").as_str()), Some(2000)));
    assert!(s["bus_from"].as_str().unwrap().ends_with("config.toml"));
    // A project file, found from a subdirectory, wins over it.
    let drive_eds = format!("{}/eds/canctl-sim-drive.eds", env!("CARGO_MANIFEST_DIR"));
    std::fs::write(
        project.join("canctl.toml"),
        format!("bus = \"{}\"\n\n[nodes.1]\neds = \"{}\"\n", bus("project.json"), drive_eds),
    )
    .unwrap();
    let s = settings(&project.join("drives"), None, &[]);
    assert_eq!(s["bus"], bus("project.json"));
    assert!(s["bus_from"].as_str().unwrap().ends_with("cell3/canctl.toml"));
    assert_eq!(s["timeout_ms"], 2000, "what the project file does not say still comes from the user file");
    assert_eq!(s["eds"][0]["for"], "node 1");
    // CANCTL_BUS over the files, the flag over all.
    let s = settings(&project, Some(&bus("env.json")), &[]);
    assert_eq!(
        (s["bus"].as_str(), s["bus_from"].as_str()),
        (Some(bus("env.json").as_str()), Some("environment (CANCTL_BUS)"))
    );
    let s = settings(&project, Some(&bus("env.json")), &["--bus", &bus("flag.json"), "--timeout", "750ms"]);
    assert_eq!((s["bus"].as_str(), s["bus_from"].as_str()), (Some(bus("flag.json").as_str()), Some("command line")));
    assert_eq!((s["timeout_ms"].as_u64(), s["timeout_from"].as_str()), (Some(750), Some("command line")));
    // The settings are used: the bus from the file, and names from its EDS for node 1.
    let r = canctl(&project, &home, None, &["sdo", "read", "1", "Simulator data types: unsigned16"]).ok();
    assert_eq!(r.stdout.trim(), "4660");
}

#[test]
fn a_broken_file_is_a_usage_error_with_file_and_line() {
    let root = tempfile::tempdir().unwrap();
    let home = root.path().join("home");
    std::fs::write(root.path().join("canctl.toml"), "bus = \"sim\"\n\ntimeout = \"soon\"\n").unwrap();
    let r = canctl(root.path(), &home, None, &["scan"]);
    assert_eq!(r.code, 2);
    assert!(r.stderr.contains("canctl.toml:3: timeout:"), "{}", r.stderr);
    std::fs::write(root.path().join("canctl.toml"), "bus = \"sim\"\nbaud = 500\n").unwrap();
    let r = canctl(root.path(), &home, None, &["settings"]);
    assert_eq!(r.code, 2);
    assert!(r.stderr.contains("canctl.toml:2:") && r.stderr.contains("baud"), "{}", r.stderr);
}

/// An EDS the project file names that is not there: a command that reads it says which
/// settings file and line name it (it said neither), and `canctl settings` still shows the
/// settings, the way to find what to fix (it exited 2 as well).
#[test]
fn a_missing_eds_in_the_file_is_cited_at_its_line_and_settings_still_shows() {
    let root = tempfile::tempdir().unwrap();
    let home = root.path().join("home");
    let bus = format!("sim:{}", root.path().join("sim.json").display());
    std::fs::write(root.path().join("canctl.toml"), format!("bus = \"{bus}\"\n\n[nodes.5]\neds = \"missing.eds\"\n"))
        .unwrap();
    let r = canctl(root.path(), &home, None, &["sdo", "read", "1", "1000"]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    assert!(r.stderr.contains("canctl.toml:4: cannot read ") && r.stderr.contains("missing.eds"), "{}", r.stderr);
    let s = canctl(root.path(), &home, None, &["settings", "--format", "json"]).ok().json();
    assert!(s["eds"][0]["file"].as_str().unwrap().ends_with("missing.eds"), "{s}");
    assert!(s["eds"][0]["from"].as_str().unwrap().ends_with("canctl.toml:4"), "{s}");
}
