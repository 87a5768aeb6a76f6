//! `canctl --version` names the version, the commit and the target, so that a binary handed
//! to a technician can be traced to its source; the commit is found in a git checkout and in
//! a package from crates.io alike (build.rs, whose functions are tested here directly).

use crate::common;

#[allow(dead_code)]
#[path = "../../build.rs"]
mod build_script;

use std::process::Command;

#[test]
fn version_names_version_commit_and_target() {
    let out = common::bare(&["--version"]).ok().stdout;
    let line = out.trim_end();
    let rest = line
        .strip_prefix(&format!("canctl {} (commit ", env!("CARGO_PKG_VERSION")))
        .unwrap_or_else(|| panic!("{line}"));
    let (commit, target) =
        rest.strip_suffix(')').and_then(|r| r.split_once(", target ")).unwrap_or_else(|| panic!("{line}"));
    // The binary under test was built from this checkout: its commit is HEAD's.
    let head = Command::new("git").args(["-C", env!("CARGO_MANIFEST_DIR"), "rev-parse", "HEAD"]).output();
    match head {
        Ok(h) if h.status.success() && std::env::var_os("CANCTL_COMMIT").is_none() => {
            assert_eq!(commit, &String::from_utf8_lossy(&h.stdout)[..12], "{line}")
        }
        _ => assert!(commit == "unknown" || commit.len() >= 12, "{line}"),
    }
    assert!(target.starts_with(std::env::consts::ARCH) && target.contains(std::env::consts::OS), "{line}");
    // -V stays the plain version (the man pages use it; they must not change per commit).
    assert_eq!(common::bare(&["-V"]).ok().stdout, format!("canctl {}\n", env!("CARGO_PKG_VERSION")));
}

const VCS_INFO: &str =
    "{\n  \"git\": {\n    \"sha1\": \"0123456789abcdef0123456789abcdef01234567\"\n  },\n  \"path_in_vcs\": \"\"\n}";

#[test]
fn a_crates_io_package_takes_its_commit_from_cargo_vcs_info() {
    let dir = tempfile::tempdir().unwrap();
    assert_eq!(build_script::commit_from_vcs_info(dir.path()), None, "no file, no commit");
    std::fs::write(dir.path().join(".cargo_vcs_info.json"), VCS_INFO).unwrap();
    assert_eq!(build_script::commit_from_vcs_info(dir.path()).as_deref(), Some("0123456789ab"));
    let dirty = VCS_INFO.replace("\n  },", ",\n    \"dirty\": true\n  },");
    std::fs::write(dir.path().join(".cargo_vcs_info.json"), dirty).unwrap();
    assert_eq!(build_script::commit_from_vcs_info(dir.path()).as_deref(), Some("0123456789ab-dirty"));
    std::fs::write(dir.path().join(".cargo_vcs_info.json"), "{\"git\": {\"sha1\": \"not hex\"}}").unwrap();
    assert_eq!(build_script::commit_from_vcs_info(dir.path()), None);
}

#[test]
fn a_package_unpacked_inside_another_repository_does_not_take_its_commit() {
    // cargo publish builds the package in target/package/, inside this checkout.
    let inside = tempfile::tempdir_in(env!("CARGO_TARGET_TMPDIR")).unwrap();
    assert_eq!(build_script::commit_from_git(inside.path()), None);
    let outside = tempfile::tempdir().unwrap();
    assert_eq!(build_script::commit_from_git(outside.path()), None);
}
