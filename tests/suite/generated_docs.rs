//! completions/ and man/ are generated from the clap definition and committed; this fails
//! when they are stale. Regenerate with: CANCTL_REGENERATE=1 cargo test --test suite generated_docs::

use std::path::Path;

fn check(dir: &str, files: Vec<(String, Vec<u8>)>) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
    if std::env::var_os("CANCTL_REGENERATE").is_some() {
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        for (name, data) in &files {
            std::fs::write(dir.join(name), data).unwrap();
        }
        return;
    }
    let mut stale = Vec::new();
    for (name, data) in &files {
        if std::fs::read(dir.join(name)).ok().as_ref() != Some(data) {
            stale.push(name.clone());
        }
    }
    let mut committed: Vec<String> = std::fs::read_dir(&dir)
        .map(|rd| rd.flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect())
        .unwrap_or_default();
    committed.retain(|c| !files.iter().any(|(n, _)| n == c));
    assert!(
        stale.is_empty() && committed.is_empty(),
        "{} is stale (changed: {stale:?}, no longer generated: {committed:?}); \
         regenerate with CANCTL_REGENERATE=1 cargo test --test suite generated_docs::",
        dir.display()
    );
}

#[test]
fn completions_are_fresh() {
    check("completions", canctl::cli::completion_scripts());
}

#[test]
fn man_pages_are_fresh() {
    let pages = canctl::cli::man_pages();
    let names: Vec<&str> = pages.iter().map(|(n, _)| n.as_str()).collect();
    for page in [
        "canctl.1",
        "canctl-scan.1",
        "canctl-sdo-read.1",
        "canctl-sdo-write.1",
        "canctl-nmt-state.1",
        "canctl-nmt-reset-comm.1",
    ] {
        assert!(names.contains(&page), "{page} not generated: {names:?}");
    }
    let top = String::from_utf8_lossy(&pages[0].1);
    assert!(top.contains("verification failed"), "exit codes missing from the man page");
    check("man", pages);
}

#[test]
fn the_binary_prints_the_same_completions() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_canctl")).args(["completions", "bash"]).output().unwrap();
    assert!(out.status.success());
    let committed = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("completions/canctl.bash")).unwrap();
    assert_eq!(out.stdout, committed);
}

/// Every command's help ends with real examples, and each example names the command it
/// is the help of.
#[test]
fn every_command_has_examples() {
    fn walk(cmd: &clap::Command, path: &str, missing: &mut Vec<String>) {
        let path = if path.is_empty() { cmd.get_name().to_string() } else { format!("{path} {}", cmd.get_name()) };
        let help = cmd.get_after_help().map(|h| h.to_string()).unwrap_or_default();
        let command = path.trim_start_matches("canctl ");
        if path != "canctl" && (!help.contains("Examples:\n") || !help.contains(&format!(" {command}"))) {
            missing.push(path.clone());
        }
        for sub in cmd.get_subcommands().filter(|s| s.get_name() != "help") {
            walk(sub, &path, missing);
        }
    }
    let mut missing = Vec::new();
    walk(&<canctl::cli::Cli as clap::CommandFactory>::command(), "", &mut missing);
    assert!(missing.is_empty(), "no examples in the help of: {missing:?}");
}
