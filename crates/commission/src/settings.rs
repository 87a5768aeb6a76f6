//! The settings in force, resolved once: flags and `CANCTL_BUS` over settings files over
//! the defaults, each value with where it came from.
//!
//! Settings files let a commissioning folder carry its setup: `canctl.toml` in the current
//! directory or a parent, and `~/.config/canctl/config.toml` (or
//! `$XDG_CONFIG_HOME/canctl/config.toml`). The project file wins over the user's.
//!
//! ```toml
//! bus = "socketcan:can0"
//! timeout = "1s"
//! [nodes.5]
//! eds = "sensors/mh.eds"     # relative to this file
//! ```

pub mod parse;

use crate::error::Error;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The answer timeout when neither a flag nor a settings file gives one.
pub const DEFAULT_TIMEOUT: Duration = Duration::from_millis(500);

/// The shortest answer timeout canctl accepts: an SDO request and its answer are two
/// frames on the bus (0.5 ms at 500 kbit/s, 27 ms at 10 kbit/s), and a device takes its
/// own time to answer (1 to 80 ms on real slaves); a shorter wait only ever reports silence.
pub(crate) const MIN_TIMEOUT: Duration = Duration::from_millis(10);

/// Parse `500ms`, `2s`, `1.5s`, `1m` or `200us`. A number without a unit is refused: was
/// `--timeout 5` meant as 5 ms or 5 s? (it used to be taken as ms, `1.5` as 1 ms).
pub fn parse_duration(text: &str) -> Result<Duration, String> {
    let t = text.trim();
    let split = t.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let n: f64 = num.parse().map_err(|_| format!("'{text}' is not a duration: use 500ms, 2s, 1.5s or 1m"))?;
    let secs = match unit.trim() {
        "" => return Err(format!("'{text}' has no unit: write {t}ms or {t}s (units: us, ms, s, m)")),
        "ms" => n / 1000.0,
        "s" => n,
        "m" | "min" => n * 60.0,
        "us" | "µs" => n / 1e6,
        u => return Err(format!("'{u}' is not a time unit: use ms, s or m")),
    };
    if !secs.is_finite() || !(0.0..=86_400.0).contains(&secs) {
        return Err(format!("'{text}' is out of range (0 to 24 h)"));
    }
    Ok(Duration::from_secs_f64(secs))
}

/// An answer timeout: a duration no shorter than `MIN_TIMEOUT`.
pub fn parse_timeout(text: &str) -> Result<Duration, String> {
    let d = parse_duration(text)?;
    if d < MIN_TIMEOUT {
        return Err(format!(
            "'{text}' is shorter than any device can answer in: a request and its answer are two frames on the bus, and devices take 1 to 80 ms to answer; use at least {}ms",
            MIN_TIMEOUT.as_millis()
        ));
    }
    Ok(d)
}

/// Parse a node-id: 1 to 127, decimal or 0x hex.
pub fn parse_node(text: &str) -> Result<u8, String> {
    number_in("a node-id", 1, 127)(text)
}

/// A whole number from `lo` to `hi` (decimal or 0x hex), refused in the words every range
/// uses ("use 1 to 512"), not clap's `1..=512`.
pub fn number_in<T>(what: &'static str, lo: u64, hi: u64) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync
where
    T: TryFrom<u64>,
{
    move |text: &str| {
        let t = text.trim();
        let n = crate::canopen::number::parse_number::<u64>(t);
        let range = if lo == hi { lo.to_string() } else { format!("{lo} to {hi}") };
        n.filter(|n| (lo..=hi).contains(n))
            .and_then(|n| T::try_from(n).ok())
            .ok_or_else(|| format!("'{text}' is not {what}: use {range}"))
    }
}

/// Where a value came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// A command-line flag.
    Flag,
    /// An environment variable (`CANCTL_BUS`, ...).
    Env,
    /// The project file at this path (`canctl.toml`).
    File(PathBuf),
    /// A line of a settings file (`canctl.toml:4`).
    Line {
        /// The settings file.
        file: PathBuf,
        /// The line.
        line: usize,
    },
    /// canctl's own default: nothing chose it.
    Default,
}

impl std::fmt::Display for Source {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Source::Flag => f.write_str("command line"),
            Source::Env => f.write_str("environment (CANCTL_BUS)"),
            Source::File(p) => write!(f, "{}", p.display()),
            Source::Line { file, line } => write!(f, "{}:{line}", file.display()),
            Source::Default => f.write_str("default"),
        }
    }
}

/// A value and where it came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sourced<T> {
    /// The value.
    pub value: T,
    /// Where it came from.
    pub from: Source,
}

/// An EDS or DCF file, for one node or (`node: None`) for every node.
#[derive(Clone, Debug)]
pub struct EdsFile {
    /// The node it describes; `None`: every node without a file of its own.
    pub node: Option<u8>,
    /// The EDS, DCF, XDD or XDC.
    pub path: PathBuf,
}

/// `NODE=PATH` (a node's file) or `PATH` (every node's): `--eds` and canctl.toml's `eds`.
impl std::str::FromStr for EdsFile {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<EdsFile, String> {
        match s.split_once('=') {
            Some((node, path)) if !node.is_empty() && node.chars().all(|c| c.is_ascii_digit()) => {
                let node = parse_node(node)?;
                Ok(EdsFile { node: Some(node), path: PathBuf::from(path) })
            }
            _ => Ok(EdsFile { node: None, path: PathBuf::from(s) }),
        }
    }
}

#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    bus: Option<BusSetting>,
    timeout: Option<String>,
    #[serde(default)]
    nodes: BTreeMap<String, NodeSettings>,
}

/// `bus = "can0"`, or several buses for the commands that check many at once:
/// `bus = ["socketcand:bench1/can0", "socketcand:bench2/can0"]`.
#[derive(Deserialize, Debug)]
#[serde(untagged)]
enum BusSetting {
    One(String),
    Many(Vec<String>),
}

#[derive(Deserialize, Default, Debug)]
#[serde(deny_unknown_fields)]
struct NodeSettings {
    eds: Option<PathBuf>,
}

/// What the files say, resolved: later files override earlier ones.
#[derive(Default, Debug)]
pub struct FileSettings {
    /// The bus, and the file that names it.
    pub bus: Option<(String, PathBuf)>,
    /// The buses after the first when the file lists several (scan, health, network check
    /// and firmware status work on them all).
    pub more_buses: Vec<String>,
    /// The answer timeout, and the file that sets it.
    pub timeout: Option<(Duration, PathBuf)>,
    /// Per node: the EDS (relative paths resolved against its file), and where it is named.
    pub eds: BTreeMap<u8, (PathBuf, Source)>,
    /// The files read, in order.
    pub files: Vec<PathBuf>,
}

/// The user's settings file (whether it exists or not).
pub fn user_file() -> Option<PathBuf> {
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
    // A refusal at the line that has `needle`.
    let at = |needle: &str, what: String| Error::Usage(format!("{}:{}: {what}", path.display(), line_with(needle)));
    let buses = match file.bus {
        Some(BusSetting::One(bus)) => vec![bus],
        Some(BusSetting::Many(buses)) if buses.is_empty() => return Err(at("bus", "bus: the list is empty".into())),
        Some(BusSetting::Many(buses)) => buses,
        None => Vec::new(),
    };
    if let Some((first, more)) = buses.split_first() {
        into.bus = Some((first.clone(), path.to_path_buf()));
        into.more_buses = more.to_vec();
    }
    if let Some(t) = file.timeout {
        let d = parse_timeout(&t).map_err(|e| at("timeout", format!("timeout: {e}")))?;
        into.timeout = Some((d, path.to_path_buf()));
    }
    for (node, n) in file.nodes {
        let id = parse_node(&node).map_err(|e| at(&format!("nodes.{node}"), format!("[nodes.{node}]: {e}")))?;
        if let Some(eds) = n.eds {
            // The `eds` line after the node's heading: what a message about the file cites.
            let heading = text.find(&format!("nodes.{node}")).unwrap_or(0);
            let line = text[heading..]
                .find("eds")
                .map_or(line_with(&format!("nodes.{node}")), |o| line_of(&text, heading + o));
            into.eds.insert(id, (dir.join(eds), Source::Line { file: path.to_path_buf(), line }));
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

/// What the command line gives (nothing where it is silent).
#[derive(Clone, Debug, Default)]
pub struct Given {
    /// The bus URI, from `--bus` or `CANCTL_BUS` (empty counts as none)...
    pub bus: Option<String>,
    /// ...and whether it came from `CANCTL_BUS`.
    pub bus_from_env: bool,
    /// The buses after the first when `--bus` is given several times.
    pub more_buses: Vec<String>,
    /// The answer timeout from `--timeout`.
    pub timeout: Option<Duration>,
    /// The `--eds` files.
    pub eds: Vec<EdsFile>,
}

/// The settings in force, each with where it came from.
#[derive(Clone, Debug)]
pub struct Settings {
    /// The bus URI, if any source named one.
    pub bus: Option<Sourced<String>>,
    /// The buses after the first, from the same source, when it names several.
    pub more_buses: Vec<String>,
    /// The answer timeout (the default when nothing sets it).
    pub timeout: Sourced<Duration>,
    /// The command line's files first, then the settings files' for the nodes it leaves.
    pub eds: Vec<Sourced<EdsFile>>,
    /// The settings files read.
    pub files: Vec<PathBuf>,
}

impl Settings {
    /// The command line over the files over the defaults.
    pub fn resolve(given: Given, files: FileSettings) -> Settings {
        let from_command_line = if given.bus_from_env { Source::Env } else { Source::Flag };
        let (bus, more_buses) = match given.bus.filter(|b| !b.is_empty()) {
            Some(value) => (Some(Sourced { value, from: from_command_line }), given.more_buses),
            None => (files.bus.map(|(value, p)| Sourced { value, from: Source::File(p) }), files.more_buses),
        };
        let timeout = match (given.timeout, files.timeout) {
            (Some(value), _) => Sourced { value, from: Source::Flag },
            (None, Some((value, p))) => Sourced { value, from: Source::File(p) },
            (None, None) => Sourced { value: DEFAULT_TIMEOUT, from: Source::Default },
        };
        let mut eds: Vec<Sourced<EdsFile>> =
            given.eds.iter().map(|e| Sourced { value: e.clone(), from: Source::Flag }).collect();
        for (node, (path, from)) in files.eds {
            if !given.eds.iter().any(|e| e.node == Some(node)) {
                eds.push(Sourced { value: EdsFile { node: Some(node), path }, from });
            }
        }
        Settings { bus, more_buses, timeout, eds, files: files.files }
    }

    /// The settings as `canctl settings` shows them.
    pub fn report(&self) -> SettingsReport {
        SettingsReport {
            bus: self.bus.as_ref().map(|b| [std::slice::from_ref(&b.value), &self.more_buses[..]].concat().join(", ")),
            bus_from: self.bus.as_ref().map(|b| b.from.to_string()),
            timeout_ms: self.timeout.value.as_millis() as u64,
            timeout_from: self.timeout.from.to_string(),
            eds: self
                .eds
                .iter()
                .map(|e| EdsReport {
                    node: e.value.node.map_or("every node".into(), |n| format!("node {n}")),
                    file: e.value.path.display().to_string(),
                    from: e.from.to_string(),
                })
                .collect(),
            files: self.files.iter().map(|f| f.display().to_string()).collect(),
        }
    }
}

/// The settings in force, as shown.
#[derive(Debug, Serialize)]
pub struct SettingsReport {
    /// The bus URI (several separated by ", ").
    pub bus: Option<String>,
    /// Where the bus came from.
    pub bus_from: Option<String>,
    /// The answer timeout in milliseconds.
    pub timeout_ms: u64,
    /// Where the timeout came from.
    pub timeout_from: String,
    /// The EDS files in force.
    pub eds: Vec<EdsReport>,
    /// The settings files read.
    pub files: Vec<String>,
}

/// One EDS in force, as shown.
#[derive(Debug, Serialize)]
pub struct EdsReport {
    /// "node N" or "every node".
    #[serde(rename = "for")]
    pub node: String,
    /// The file.
    pub file: String,
    /// Where it was given.
    pub from: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations() {
        assert_eq!(parse_duration("500ms").unwrap(), Duration::from_millis(500));
        assert_eq!(parse_duration("2s").unwrap(), Duration::from_secs(2));
        assert_eq!(parse_duration("1.5s").unwrap(), Duration::from_millis(1500));
        // A number without a unit is refused, naming the units, whatever flag it is for.
        for bare in ["250", "1.5", "0"] {
            let e = parse_duration(bare).unwrap_err();
            assert!(e.contains("has no unit") && e.contains("ms, s"), "{e}");
        }
        assert!(parse_duration("fast").is_err());
        assert!(parse_duration("5h").is_err());
        assert!(parse_duration("-1s").is_err());
    }

    #[test]
    fn nodes() {
        assert_eq!(parse_node("5"), Ok(5));
        assert_eq!(parse_node("0x7F"), Ok(127));
        assert!(parse_node("0").is_err());
        assert!(parse_node("128").is_err());
        assert!(parse_node("all").is_err());
        let tpdo = number_in::<u16>("a TPDO number", 1, 512);
        assert_eq!(tpdo("0x200"), Ok(512));
        assert_eq!(tpdo("513").unwrap_err(), "'513' is not a TPDO number: use 1 to 512");
        assert_eq!(number_in::<u8>("the EPOS2", 0, 0)("3").unwrap_err(), "'3' is not the EPOS2: use 0");
    }

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
    fn a_file_may_list_several_buses() {
        let s = parse("bus = [\"sim:/tmp/a.json\", \"socketcand:bench2/can0\"]\n").unwrap();
        assert_eq!(s.bus.unwrap().0, "sim:/tmp/a.json");
        assert_eq!(s.more_buses, vec!["socketcand:bench2/can0".to_string()]);
        let e = parse("timeout = \"1s\"\nbus = []\n").unwrap_err().to_string();
        assert!(e.contains("canctl.toml:2: bus: the list is empty"), "{e}");
        // The command line's buses replace the file's list whole.
        let files = FileSettings {
            bus: Some(("sim:/a".into(), "f".into())),
            more_buses: vec!["sim:/b".into()],
            ..FileSettings::default()
        };
        let given = Given { bus: Some("can0".into()), ..Given::default() };
        let s = Settings::resolve(given, files);
        assert_eq!((s.bus.unwrap().value, s.more_buses), ("can0".to_string(), Vec::new()));
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

    #[test]
    fn the_command_line_wins_and_each_value_says_where_it_came_from() {
        let file = PathBuf::from("/p/canctl.toml");
        let files = FileSettings {
            bus: Some(("socketcan:can0".into(), file.clone())),
            timeout: Some((Duration::from_secs(2), file.clone())),
            eds: BTreeMap::from([
                (5, ("/p/mh.eds".into(), Source::Line { file: file.clone(), line: 4 })),
                (7, ("/p/x.eds".into(), Source::Line { file: file.clone(), line: 7 })),
            ]),
            files: vec![file.clone()],
            more_buses: Vec::new(),
        };
        let given = Given {
            bus: Some("sim".into()),
            bus_from_env: true,
            more_buses: Vec::new(),
            timeout: None,
            eds: vec![EdsFile { node: Some(7), path: "mine.eds".into() }],
        };
        let s = Settings::resolve(given, files);
        assert_eq!(s.bus, Some(Sourced { value: "sim".into(), from: Source::Env }));
        assert_eq!(s.timeout, Sourced { value: Duration::from_secs(2), from: Source::File(file.clone()) });
        let eds: Vec<(Option<u8>, &Path, &Source)> =
            s.eds.iter().map(|e| (e.value.node, e.value.path.as_path(), &e.from)).collect();
        assert_eq!(
            eds,
            [
                (Some(7), Path::new("mine.eds"), &Source::Flag),
                (Some(5), Path::new("/p/mh.eds"), &Source::Line { file, line: 4 })
            ]
        );
        let defaults =
            Settings::resolve(Given { bus: Some(String::new()), ..Given::default() }, FileSettings::default());
        assert_eq!(defaults.bus, None);
        assert_eq!(defaults.timeout, Sourced { value: DEFAULT_TIMEOUT, from: Source::Default });
    }
}
