//! Files written whole or not at all: a result saved with `--out` either replaces the old
//! file completely or leaves it as it was (exit 7 on failure), never a stump.

use std::io::Write;

/// Write `bytes` to `path` so that the file is either its old self or wholly the new
/// content, never a mix or a stump: into a temporary file beside it, flushed to the disk,
/// then renamed over it. On any failure (disk full, no permission) the old file is left as
/// it was and the temporary file removed: exit 7. A target that is not a regular file (a
/// terminal, `/dev/stdout`, a FIFO) is written directly, as renaming over it would replace
/// the device with a file.
pub fn write_atomic(path: &std::path::Path, bytes: &[u8]) -> crate::Result<()> {
    use crate::Error;
    use std::fs;
    let output = |why: String| Error::Output { path: path.display().to_string(), why };
    let fail = |what: &str, e: std::io::Error| output(format!("{what}{e}"));
    // Through a symbolic link, the file it points to is the one replaced.
    let target = match fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => fs::canonicalize(path).map_err(|e| fail("", e))?,
        _ => path.to_path_buf(),
    };
    let existing = fs::metadata(&target).ok();
    if existing.as_ref().is_some_and(|m| !m.is_file() && !m.is_dir()) {
        let mut f = fs::OpenOptions::new().write(true).truncate(true).open(&target).map_err(|e| fail("", e))?;
        return f.write_all(bytes).and_then(|_| f.flush()).map_err(|e| fail("", e));
    }
    if existing.as_ref().is_some_and(|m| m.is_dir()) {
        return Err(output("it is a directory".into()));
    }
    let Some(name) = target.file_name() else {
        return Err(output("not a file name".into()));
    };
    let dir = target.parent().filter(|d| !d.as_os_str().is_empty());
    let temp = dir.map_or_else(|| temp_name(name).into(), |d| d.join(temp_name(name)));
    let mut file = match fs::OpenOptions::new().write(true).create_new(true).open(&temp) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            return Err(output(format!(
                "{} is in the way (left by an interrupted canctl, or another one is writing the file now); \
                 {} is unchanged. Remove it and try again",
                temp.display(),
                path.display()
            )))
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
        return Err(output(format!(
            "{e}; {}",
            if existing.is_some() { "the file is unchanged" } else { "nothing was written" }
        )));
    }
    // The rename itself reaches the disk with the directory.
    #[cfg(unix)]
    if let Ok(d) = fs::File::open(dir.unwrap_or(std::path::Path::new("."))) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// The temporary file `write_atomic` writes beside `name`: hidden, and named after it.
pub fn temp_name(name: &std::ffi::OsStr) -> std::ffi::OsString {
    let mut temp = std::ffi::OsString::from(".");
    temp.push(name);
    temp.push(".canctl-tmp");
    temp
}
