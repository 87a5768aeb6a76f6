//! Settings from files, so that a commissioning folder carries its setup: `canctl.toml` in
//! the current directory or a parent, and `~/.config/canctl/config.toml` (or
//! `$XDG_CONFIG_HOME/canctl/config.toml`). The project file wins over the user's; flags
//! and CANCTL_BUS win over both.
//!
//! ```toml
//! bus = "socketcan:can0"
//! timeout = "1s"
//! [nodes.5]
//! eds = "sensors/mh.eds"     # relative to this file
//! ```

use super::objects::EdsArg;
use super::Ctx;
use crate::error::Error;
use crate::output::{Human, Report};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    bus: Option<String>,
    timeout: Option<String>,
    #[serde(default)]
    nodes: BTreeMap<String, NodeSettings>,
}

#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields)]
struct NodeSettings {
    eds: Option<PathBuf>,
}

/// Where a value came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    Flag,
    Env,
    File(PathBuf),
    Default,
}

impl std::fmt::Display for Source {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Source::Flag => f.write_str("command line"),
            Source::Env => f.write_str("environment (CANCTL_BUS)"),
            Source::File(p) => write!(f, "{}", p.display()),
            Source::Default => f.write_str("default"),
        }
    }
}

/// What the files say, resolved: later files override earlier ones.
#[derive(Default, Debug)]
pub struct FileSettings {
    pub bus: Option<(String, PathBuf)>,
    pub timeout: Option<(Duration, PathBuf)>,
    pub eds: BTreeMap<u8, (PathBuf, PathBuf)>,
    /// The files read, in order.
    pub files: Vec<PathBuf>,
}

fn user_file() -> Option<PathBuf> {
    Some(crate::xdg::config_dir()?.join("config.toml"))
}

fn project_file() -> Option<PathBuf> {
    let cwd = std::env::current_dir().ok()?;
    cwd.ancestors().map(|d| d.join("canctl.toml")).find(|p| p.is_file())
}

/// The line of a byte offset, for messages.
fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

fn read(path: &Path, into: &mut FileSettings) -> Result<(), Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::Usage(format!("{}: {e}", path.display())))?;
    let file: File = toml::from_str(&text).map_err(|e| {
        let line = e.span().map_or(1, |s| line_of(&text, s.start));
        Error::Usage(format!("{}:{line}: {}", path.display(), e.message()))
    })?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let line_with = |needle: &str| text.find(needle).map_or(1, |o| line_of(&text, o));
    if let Some(bus) = file.bus {
        into.bus = Some((bus, path.to_path_buf()));
    }
    if let Some(t) = file.timeout {
        let d = super::parse_duration(&t)
            .map_err(|e| Error::Usage(format!("{}:{}: timeout: {e}", path.display(), line_with("timeout"))))?;
        into.timeout = Some((d, path.to_path_buf()));
    }
    for (node, n) in file.nodes {
        let id = super::parse_node(&node).map_err(|e| {
            Error::Usage(format!("{}:{}: [nodes.{node}]: {e}", path.display(), line_with(&format!("nodes.{node}"))))
        })?;
        if let Some(eds) = n.eds {
            into.eds.insert(id, (dir.join(eds), path.to_path_buf()));
        }
    }
    into.files.push(path.to_path_buf());
    Ok(())
}

/// Read the user's file, then the project's.
pub fn load() -> Result<FileSettings, Error> {
    let mut s = FileSettings::default();
    for path in [user_file(), project_file()].into_iter().flatten() {
        if path.is_file() {
            read(&path, &mut s)?;
        }
    }
    Ok(s)
}

/// The settings in force, each with where it came from.
pub struct Resolved {
    pub bus: Option<(String, Source)>,
    pub timeout: (Duration, Source),
    pub eds: Vec<(EdsArg, Source)>,
    pub files: Vec<PathBuf>,
}

/// Flags (and CANCTL_BUS) over the files over the defaults.
pub fn resolve(
    bus: Option<(String, Source)>,
    timeout: Option<Duration>,
    eds: &[EdsArg],
    files: FileSettings,
) -> Resolved {
    let bus = bus.or_else(|| files.bus.map(|(b, p)| (b, Source::File(p))));
    let timeout = match (timeout, files.timeout) {
        (Some(t), _) => (t, Source::Flag),
        (None, Some((t, p))) => (t, Source::File(p)),
        (None, None) => (super::DEFAULT_TIMEOUT, Source::Default),
    };
    let mut all: Vec<(EdsArg, Source)> = eds.iter().map(|e| (e.clone(), Source::Flag)).collect();
    for (node, (path, from)) in files.eds {
        if !eds.iter().any(|e| e.node == Some(node)) {
            all.push((EdsArg { node: Some(node), path }, Source::File(from)));
        }
    }
    Resolved { bus, timeout, eds: all, files: files.files }
}

/// `canctl settings`: what is in force and where each value came from.
pub fn show(ctx: &Ctx, r: &Resolved) -> anyhow::Result<()> {
    let bus = r.bus.as_ref();
    let report = Shown {
        bus: bus.map(|(b, _)| b.clone()),
        bus_from: bus.map(|(_, s)| s.to_string()),
        timeout_ms: r.timeout.0.as_millis() as u64,
        timeout_from: r.timeout.1.to_string(),
        eds: r
            .eds
            .iter()
            .map(|(e, s)| ShownEds {
                node: e.node.map_or("every node".into(), |n| format!("node {n}")),
                file: e.path.display().to_string(),
                from: s.to_string(),
            })
            .collect(),
        files: r.files.iter().map(|f| f.display().to_string()).collect(),
    };
    Ok(ctx.out.report(&report)?)
}

/// The settings in force, as shown.
#[derive(Serialize)]
struct Shown {
    bus: Option<String>,
    bus_from: Option<String>,
    timeout_ms: u64,
    timeout_from: String,
    eds: Vec<ShownEds>,
    files: Vec<String>,
}

#[derive(Serialize)]
struct ShownEds {
    #[serde(rename = "for")]
    node: String,
    file: String,
    from: String,
}

impl Report for Shown {
    fn human(&self) -> Human {
        let mut rows = vec![
            vec![
                "bus".into(),
                self.bus.clone().unwrap_or("(none)".into()),
                self.bus_from.clone().unwrap_or("-".into()),
            ],
            vec!["timeout".into(), format!("{} ms", self.timeout_ms), self.timeout_from.clone()],
        ];
        rows.extend(self.eds.iter().map(|e| vec![format!("eds ({})", e.node), e.file.clone(), e.from.clone()]));
        Human::Table { headers: vec!["setting", "value", "from"], rows, when_empty: true }
    }

    fn notes(&self) -> Vec<String> {
        if !self.files.is_empty() {
            return Vec::new();
        }
        let user = user_file().map_or("(no home directory)".to_string(), |p| p.display().to_string());
        vec![format!("no settings file: canctl.toml here or in a parent directory, or {user}")]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<FileSettings, Error> {
        let dir = tempfile_dir();
        let path = dir.join("canctl.toml");
        std::fs::write(&path, text).unwrap();
        let mut s = FileSettings::default();
        read(&path, &mut s).map(|_| s)
    }

    fn tempfile_dir() -> PathBuf {
        let d = std::env::temp_dir().join(format!(
            "canctl-settings-{}-{:?}",
            std::process::id(),
            std::thread::current().id()
        ));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_good_file() {
        let s = parse("bus = \"sim\"\ntimeout = \"2s\"\n[nodes.5]\neds = \"mh.eds\"\n").unwrap();
        assert_eq!(s.bus.unwrap().0, "sim");
        assert_eq!(s.timeout.unwrap().0, Duration::from_secs(2));
        assert!(s.eds[&5].0.ends_with("mh.eds"));
    }

    #[test]
    fn broken_files_cite_their_line() {
        let e = parse("bus = \"sim\"\n\ntimeout = 5\n").unwrap_err().to_string();
        assert!(e.contains("canctl.toml:3:"), "{e}");
        let e = parse("bus = \"sim\"\nspeed = 1\n").unwrap_err().to_string();
        assert!(e.contains("canctl.toml:2:") && e.contains("speed"), "{e}");
        let e = parse("timeout = \"soon\"\n").unwrap_err().to_string();
        assert!(e.contains("canctl.toml:1: timeout:"), "{e}");
        let e = parse("[nodes.200]\neds = \"x.eds\"\n").unwrap_err().to_string();
        assert!(e.contains("canctl.toml:1: [nodes.200]"), "{e}");
        let e = parse("bus = \"sim\n").unwrap_err().to_string();
        assert!(e.contains("canctl.toml:1:"), "{e}");
    }
}
