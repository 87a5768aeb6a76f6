//! Puts the commit and the target into `canctl --version`, so a binary handed around names
//! exactly what it was built from. The commit comes from, in order: `CANCTL_COMMIT` (a build
//! from a source tarball), `.cargo_vcs_info.json` (a package from crates.io: cargo writes it
//! on `cargo package`), git (a checkout), else "unknown". Nothing here may differ between two
//! builds of the same commit: that would break reproducible releases (scripts/dist.sh).
use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    let dir = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    println!("cargo:rerun-if-env-changed=CANCTL_COMMIT");
    let commit = std::env::var("CANCTL_COMMIT")
        .ok()
        .filter(|c| !c.is_empty())
        .or_else(|| commit_from_vcs_info(&dir))
        .or_else(|| commit_from_git(&dir))
        .unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=CANCTL_COMMIT={commit}");
    println!("cargo:rustc-env=CANCTL_TARGET={}", std::env::var("TARGET").expect("set by cargo"));
}

/// The commit a crates.io package was made from (`{"git": {"sha1": "…"}}`). Read by hand:
/// a build script with a JSON dependency would build it for every user of the library.
pub fn commit_from_vcs_info(dir: &Path) -> Option<String> {
    let path = dir.join(".cargo_vcs_info.json");
    let text = std::fs::read_to_string(&path).ok()?;
    println!("cargo:rerun-if-changed={}", path.display());
    let rest = &text[text.find("\"sha1\"")? + "\"sha1\"".len()..];
    let rest = rest.trim_start().strip_prefix(':')?.trim_start().strip_prefix('"')?;
    let sha = &rest[..rest.find('"')?];
    let dirty = text.contains("\"dirty\": true") || text.contains("\"dirty\":true");
    hex_commit(sha).map(|c| if dirty { format!("{c}-dirty") } else { c })
}

/// HEAD of the checkout the crate is the top of; a package unpacked inside some other
/// repository (target/package/, a vendor directory) must not take that repository's commit.
pub fn commit_from_git(dir: &Path) -> Option<String> {
    let top = git(dir, &["rev-parse", "--show-toplevel"])?;
    if Path::new(&top).canonicalize().ok()? != dir.canonicalize().ok()? {
        return None;
    }
    // A new commit moves HEAD or the branch it names (loose or packed) and adds to HEAD's
    // reflog: look again then.
    for name in ["HEAD", "logs/HEAD", "packed-refs"] {
        rerun_if_changed(dir, git(dir, &["rev-parse", "--git-path", name]));
    }
    if let Some(branch) = git(dir, &["symbolic-ref", "-q", "HEAD"]) {
        rerun_if_changed(dir, git(dir, &["rev-parse", "--git-path", &branch]));
    }
    hex_commit(&git(dir, &["rev-parse", "HEAD"])?)
}

fn git(dir: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git").arg("-C").arg(dir).args(args).output().ok()?;
    out.status.success().then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// Only for files that exist: cargo runs the script again on every build for a missing one.
fn rerun_if_changed(dir: &Path, path: Option<String>) {
    if let Some(path) = path.map(|p| dir.join(p)).filter(|p| p.exists()) {
        println!("cargo:rerun-if-changed={}", path.display());
    }
}

/// The first 12 hex digits, as `git log --abbrev=12` shows them.
fn hex_commit(sha: &str) -> Option<String> {
    (sha.len() >= 12 && sha.bytes().all(|b| b.is_ascii_hexdigit())).then(|| sha[..12].to_string())
}
