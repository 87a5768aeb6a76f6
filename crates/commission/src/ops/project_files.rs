//! A network project on disk (`nodelist.cpj` and one DCF per node): where it is, whether it
//! can be written, and writing it so that a project file is only there once every file it
//! names is. The procedures that read, make and write projects are in [`super::network`].

use crate::error::{OutsideProject, Result};
use std::path::{Path, PathBuf};

/// The project file canctl writes and looks for in a folder.
pub const PROJECT_FILE: &str = "nodelist.cpj";

/// The project file: `path` itself, or `path/nodelist.cpj` for a folder.
pub fn project_file(path: &Path) -> PathBuf {
    if path.is_dir() {
        path.join(PROJECT_FILE)
    } else {
        path.to_path_buf()
    }
}

/// Refuse a file of the project in `folder` that, symbolic links followed, is outside it (a
/// link inside the folder to a file inside it is fine). A project's file names are bare or
/// below its folder (`od::cpj` refuses `..` and absolute names); a link is the other way out,
/// so every read and write of a project's file asks this first. A file not there yet (one a
/// dump makes) is judged by the folder it would be made in.
pub(crate) fn check_inside(folder: &Path, path: &Path) -> Result<()> {
    let (Some(folder), Some(points_to)) = (resolved(folder), resolved(path)) else {
        // Nothing there to read or write through: the read or write says so itself.
        return Ok(());
    };
    if points_to.starts_with(&folder) {
        return Ok(());
    }
    Err(OutsideProject { link: path.to_path_buf(), points_to, folder }.into())
}

/// `path` with every symbolic link followed; for a file not there yet (or a link to one),
/// where it would be made. None when its folder is not there either.
fn resolved(path: &Path) -> Option<PathBuf> {
    if let Ok(real) = std::fs::canonicalize(path) {
        return Some(real);
    }
    let at = match std::fs::read_link(path) {
        Ok(target) => folder_of(path).join(target),
        Err(_) => path.to_path_buf(),
    };
    Some(std::fs::canonicalize(folder_of(&at)).ok()?.join(at.file_name()?))
}

/// The folder `path` is in (`.` for a bare name).
pub(crate) fn folder_of(path: &Path) -> &Path {
    path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."))
}

/// Whether a project can be written into `dir`, asked before the bus is read: in `dir`
/// when it exists, else where its first missing folder would be made.
pub fn check_folder(dir: &Path) -> Result<()> {
    let mut probe = dir.join(PROJECT_FILE);
    let mut at = dir;
    while !at.exists() {
        probe = at.to_path_buf();
        match at.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => at = parent,
            _ => break,
        }
    }
    crate::atomic::check_writable(&probe)
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use crate::error::Error;
    use std::os::unix::fs::symlink;

    /// Links are judged by where they lead, also to a file not there yet (a dump would make
    /// it) and through a folder.
    #[test]
    fn a_file_is_inside_when_its_links_lead_inside() {
        let root = tempfile::tempdir().unwrap();
        let project = root.path().join("p");
        std::fs::create_dir_all(project.join("dcf")).unwrap();
        std::fs::create_dir_all(root.path().join("elsewhere")).unwrap();
        std::fs::write(project.join("real.dcf"), "").unwrap();
        symlink("real.dcf", project.join("inside.dcf")).unwrap();
        symlink("../new.dcf", project.join("dangling.dcf")).unwrap();
        symlink("../elsewhere", project.join("out")).unwrap();
        let at = |name: &str| check_inside(&project, &project.join(name));
        assert!(at("real.dcf").is_ok() && at("inside.dcf").is_ok() && at("not-yet.dcf").is_ok());
        assert!(at("dcf/node5.dcf").is_ok());
        for name in ["dangling.dcf", "out/node5.dcf"] {
            let Err(Error::OutsideProject(e)) = at(name) else { panic!("{name} taken as inside") };
            assert_eq!(e.link, project.join(name));
            assert!(!e.points_to.starts_with(&e.folder), "{e}");
        }
    }
}
