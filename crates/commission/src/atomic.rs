//! Files written whole or not at all: a result saved with `--out` either replaces the old
//! file completely or leaves it as it was (exit 7 on failure), never a stump.

use std::io::Write;

/// Write `bytes` to `path` so that the file is either its old self or wholly the new
/// content, never a mix or a stump: into a temporary file beside it, flushed to the disk,
/// then renamed over it. The temporary file is named after this process
/// (`temp_name`): one left by a process killed outright is in nobody's way, and is
/// removed by the next write once its writer is gone. On any failure (disk full, no permission) the old file is left as
/// it was and the temporary file removed: exit 7. A target that is not a regular file (a
/// terminal, `/dev/stdout`, a FIFO) is written directly, as renaming over it would replace
/// the device with a file.
pub fn write_atomic(path: &std::path::Path, bytes: &[u8]) -> crate::Result<()> {
    use crate::Error;
    use std::fs;
    let output = |why: String| Error::Output { path: path.display().to_string(), why };
    let fail = |what: &str, e: std::io::Error| output(format!("{what}{e}"));
    let target = target(path)?;
    let existing = fs::metadata(&target).ok();
    if existing.as_ref().is_some_and(|m| !m.is_file() && !m.is_dir()) {
        let mut f = fs::OpenOptions::new().write(true).truncate(true).open(&target).map_err(|e| fail("", e))?;
        return f.write_all(bytes).and_then(|_| f.flush()).map_err(|e| fail("", e));
    }
    if existing.as_ref().is_some_and(|m| m.is_dir()) {
        return Err(output("it is a directory".into()));
    }
    let Some((dir, name, temp)) = temporary(&target) else { return Err(output("not a file name".into())) };
    remove_stale_temporaries(dir, name);
    let create = || fs::OpenOptions::new().write(true).create_new(true).open(&temp);
    let mut file = match create() {
        Ok(f) => f,
        // This process's name, yet not this process's file (it writes one file at a time):
        // left by an earlier process that had the same pid. Replaced once.
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            let _ = fs::remove_file(&temp);
            create().map_err(|e| {
                output(format!("{} is in the way ({e}); {} is unchanged", temp.display(), path.display()))
            })?
        }
        Err(e) => return Err(fail("", e)),
    };
    let written = (|| {
        file.write_all(bytes)?;
        if let Some(m) = &existing {
            // The new file keeps the old one's permissions.
            file.set_permissions(m.permissions())?;
        }
        file.sync_all()?;
        drop(file);
        fs::rename(&temp, &target)
    })();
    if let Err(e) = written {
        let _ = fs::remove_file(&temp);
        let left = if existing.is_some() { "the file is unchanged" } else { "nothing was written" };
        return Err(output(format!("{e}; {left}")));
    }
    // The rename itself reaches the disk with the directory.
    #[cfg(unix)]
    if let Ok(d) = fs::File::open(dir.unwrap_or(std::path::Path::new("."))) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// The file a write to `path` replaces: through a symbolic link, the file it points to.
fn target(path: &std::path::Path) -> crate::Result<std::path::PathBuf> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => std::fs::canonicalize(path)
            .map_err(|e| crate::Error::Output { path: path.display().to_string(), why: e.to_string() }),
        _ => Ok(path.to_path_buf()),
    }
}

/// Whether [`write_atomic`] can write `path`, asked before the work that makes its content
/// (a dump of 20 s), so that a mistyped folder fails at once rather than after it: the
/// temporary file is made and removed (the folder exists and takes new files), a device
/// opened for writing. Nothing is written to `path` itself; a full disk shows only later.
pub fn check_writable(path: &std::path::Path) -> crate::Result<()> {
    use std::fs;
    let output = |why: String| crate::Error::Output { path: path.display().to_string(), why };
    let target = target(path)?;
    match fs::metadata(&target) {
        Ok(m) if m.is_dir() => return Err(output("it is a directory".into())),
        Ok(m) if !m.is_file() => {
            return fs::OpenOptions::new().write(true).open(&target).map(drop).map_err(|e| output(e.to_string()))
        }
        _ => {}
    }
    let Some((dir, _, temp)) = temporary(&target) else { return Err(output("not a file name".into())) };
    match fs::OpenOptions::new().write(true).create_new(true).open(&temp) {
        Ok(_) => fs::remove_file(&temp).map_err(|e| output(e.to_string())),
        // Ours from an earlier process of the same pid: the folder takes files.
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let folder = dir.unwrap_or(std::path::Path::new("."));
            // Not found in a folder that is there (/proc): the folder makes no files.
            match folder.is_dir() {
                true => Err(output(format!("the folder {} takes no new files ({e})", folder.display()))),
                false => Err(output(format!("there is no folder {}", folder.display()))),
            }
        }
        Err(e) => Err(output(e.to_string())),
    }
}

/// The folder of `target` (none: the current one), its file name, and the temporary file
/// this process writes it through; none when `target` names no file.
fn temporary(target: &std::path::Path) -> Option<(Option<&std::path::Path>, &std::ffi::OsStr, std::path::PathBuf)> {
    let name = target.file_name()?;
    let dir = target.parent().filter(|d| !d.as_os_str().is_empty());
    Some((dir, name, dir.unwrap_or(std::path::Path::new("")).join(temp_name(name, std::process::id()))))
}

/// The temporary file process `pid` writes beside `name`: hidden, named after it and after
/// its writer, so that two processes, or one killed half-way and the next, never collide.
pub(crate) fn temp_name(name: &std::ffi::OsStr, pid: u32) -> std::ffi::OsString {
    let mut temp = std::ffi::OsString::from(".");
    temp.push(name);
    temp.push(format!(".{pid}{TEMP_SUFFIX}"));
    temp
}

const TEMP_SUFFIX: &str = ".canctl-tmp";

/// The writer's pid, when `file` is a temporary file of `name`.
fn temp_owner(file: &std::ffi::OsStr, name: &std::ffi::OsStr) -> Option<u32> {
    let rest = file.to_str()?.strip_prefix('.')?.strip_prefix(name.to_str()?)?;
    rest.strip_prefix('.')?.strip_suffix(TEMP_SUFFIX)?.parse().ok()
}

/// Remove the temporary files of `name` whose writer is gone (killed outright: SIGKILL, a
/// power cut). A writer still running keeps its file. Best effort: what cannot be removed
/// is left, and is in nobody's way.
fn remove_stale_temporaries(dir: Option<&std::path::Path>, name: &std::ffi::OsStr) {
    let Ok(entries) = std::fs::read_dir(dir.unwrap_or(std::path::Path::new("."))) else { return };
    for entry in entries.flatten() {
        let Some(pid) = temp_owner(&entry.file_name(), name) else { continue };
        if pid != std::process::id() && !running(pid) && entry.file_type().is_ok_and(|t| t.is_file()) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Whether process `pid` exists (Unix: signal 0 reaches it, or it exists under another
/// user). Elsewhere it is taken to run: its file stays, which is safe.
fn running(pid: u32) -> bool {
    #[cfg(unix)]
    {
        use nix::errno::Errno;
        let Ok(pid) = i32::try_from(pid) else { return false };
        !matches!(nix::sys::signal::kill(nix::unistd::Pid::from_raw(pid), None), Err(Errno::ESRCH))
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::OsStr;

    #[test]
    fn temporary_names_carry_their_writer() {
        let name = OsStr::new("sensor.dcf");
        assert_eq!(temp_name(name, 42), ".sensor.dcf.42.canctl-tmp");
        assert_eq!(temp_owner(OsStr::new(".sensor.dcf.42.canctl-tmp"), name), Some(42));
        assert_eq!(temp_owner(OsStr::new(".sensor.dcf.canctl-tmp"), name), None);
        assert_eq!(temp_owner(OsStr::new(".other.dcf.42.canctl-tmp"), name), None);
        assert_eq!(temp_owner(OsStr::new(".sensor.dcf.x.canctl-tmp"), name), None);
        assert_eq!(temp_owner(OsStr::new("sensor.dcf"), name), None);
    }

    #[cfg(unix)]
    #[test]
    fn a_temporary_file_of_a_dead_writer_is_removed_and_a_live_ones_kept() {
        let dir = std::env::temp_dir().join(format!("canctl-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("out.bin");
        std::fs::write(&target, b"old").unwrap();
        // A writer that is gone: a child that has ended (and been reaped).
        let mut child = std::process::Command::new(std::env::current_exe().unwrap())
            .arg("--list")
            .stdout(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let dead = child.id();
        child.wait().unwrap();
        let stale = dir.join(temp_name(OsStr::new("out.bin"), dead));
        std::fs::write(&stale, b"half").unwrap();
        // Our own parent runs: its file stays.
        let live = dir.join(temp_name(OsStr::new("out.bin"), std::os::unix::process::parent_id()));
        std::fs::write(&live, b"busy").unwrap();
        write_atomic(&target, b"new").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        assert!(!stale.exists(), "stale temporary file kept");
        assert!(live.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
