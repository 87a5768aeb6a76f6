//! The simulated network's state between invocations: a JSON file, locked while a
//! process uses it, replaced atomically when saved.

use super::device::DeviceState;
use crate::error::{Error, LinkError, Result, StateRefused};
use std::collections::BTreeMap;
use std::fs::{File, OpenOptions, TryLockError};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

pub(crate) const VERSION: u32 = 1;

/// What the state file holds: the simulated network between invocations.
#[derive(serde::Serialize, serde::Deserialize, Default, Debug)]
pub struct NetworkState {
    /// The file format's version; an unknown one is not read.
    pub version: u32,
    /// The bus's bit rate (CiA 305 table index).
    pub bit_rate: Option<u8>,
    /// Profile, seed, devices and faults chosen by `sim reset`; absent: the defaults.
    pub config: Option<super::SimConfig>,
    /// Each device's state, by model key.
    pub devices: BTreeMap<String, DeviceState>,
    /// The devices' clock (ms) when saved: the next invocation's starts after it.
    pub clock_ms: Option<u64>,
}

/// The state file, locked: one process at a time runs the simulated network.
pub struct StateFile {
    path: PathBuf,
    /// Who holds the lock, for the next process that finds it taken.
    owner_path: PathBuf,
    /// Held for the life of this value: one process drives the sim network at a time.
    _lock: File,
}

/// How long opening the sim network waits for another process using it: long enough for
/// a command that is finishing, short of hanging behind a server (`canctl sim --...`) that
/// runs until stopped.
pub const DEFAULT_LOCK_WAIT: Duration = Duration::from_secs(10);

/// How often a taken lock is tried again.
const LOCK_RETRY: Duration = Duration::from_millis(50);

/// The process holding the sim network, as it recorded itself beside the lock.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, PartialEq, Eq)]
pub(crate) struct Holder {
    pub pid: u32,
    /// Its command line, program name without its directory: `canctl sim --epos2-rs232`.
    pub command: String,
    /// The `--bus` that reaches the devices where it serves them (`canctl sim --...`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub serves: Option<String>,
}

impl Holder {
    fn this_process() -> Holder {
        let mut args = std::env::args_os();
        let program = args.next().map(|a| Path::new(&a).file_name().unwrap_or(&a).to_string_lossy().into_owned());
        let rest = args.map(|a| a.to_string_lossy().into_owned());
        let command = program.into_iter().chain(rest).collect::<Vec<_>>().join(" ");
        Holder { pid: std::process::id(), command, serves: None }
    }

    fn read(owner_path: &Path) -> Option<Holder> {
        serde_json::from_str(&std::fs::read_to_string(owner_path).ok()?).ok()
    }
}

/// `$XDG_STATE_HOME/canctl/sim.json`, else `~/.local/state/canctl/sim.json`: the state
/// directory of canctl by the platform's convention (XDG's on Linux, the local data directory
/// where there is none; canctl's `xdg` places its settings and cache beside it).
pub fn default_path() -> PathBuf {
    let state_dir = directories::ProjectDirs::from("", "", "canctl")
        .map(|p| p.state_dir().unwrap_or_else(|| p.data_local_dir()).to_path_buf());
    state_dir.unwrap_or_else(|| std::env::temp_dir().join("canctl")).join("sim.json")
}

/// Refuse a state path that is not canctl's: a folder, a file holding anything but a sim
/// state (of any format version: an old one is started afresh, not refused), or a file in
/// a folder that is not there. Asked before anything is written, the lock beside it
/// included, so that `sim:/etc/passwd` leaves `/etc` as it was.
fn check_ours(path: &Path) -> std::result::Result<(), StateRefused> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(StateRefused::Folder(path.to_path_buf())),
        Ok(_) if !holds_a_sim_state(path) => Err(StateRefused::NotAState(path.to_path_buf())),
        Ok(_) => Ok(()),
        Err(_) => {
            let folder = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
            let missing = StateRefused::NoFolder { folder: folder.to_path_buf(), path: path.to_path_buf() };
            folder.is_dir().then_some(()).ok_or(missing)
        }
    }
}

/// Whether the file is what [`StateFile::save`] writes: a JSON object with a `version` and
/// `devices`. A file that cannot be read is left to the read that follows to report.
fn holds_a_sim_state(path: &Path) -> bool {
    #[derive(serde::Deserialize)]
    #[allow(dead_code)]
    struct Shape {
        version: serde::de::IgnoredAny,
        devices: serde::de::IgnoredAny,
    }
    File::open(path).map_or(true, |f| serde_json::from_reader::<_, Shape>(std::io::BufReader::new(f)).is_ok())
}

/// A file canctl keeps beside the state file (`sim.json.canctl-lock`): named so that it is
/// nobody else's (`passwd.lock` is the lock the system's own tools take).
fn beside(path: &Path, what: &str) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".canctl-{what}"));
    path.with_file_name(name)
}

fn link_err(path: &Path, what: &'static str, e: impl std::fmt::Display) -> Error {
    LinkError::StateFile { path: path.to_path_buf(), what, detail: e.to_string(), afresh: false }.into()
}

/// A state file that is there but cannot be taken as it is: a fresh network is the remedy.
fn unusable(path: &Path, what: &'static str, e: impl std::fmt::Display) -> Error {
    LinkError::StateFile { path: path.to_path_buf(), what, detail: e.to_string(), afresh: true }.into()
}

/// Best effort: without it the next process is only told "another process". Renamed into
/// place, so that it is never read half written.
fn record(owner_path: &Path, holder: &Holder) {
    let text = serde_json::to_string(holder).expect("holder serialises");
    let tmp =
        owner_path.with_file_name(format!("{}-tmp", owner_path.file_name().unwrap_or_default().to_string_lossy()));
    if let Err(e) = std::fs::write(&tmp, text).and_then(|()| std::fs::rename(&tmp, owner_path)) {
        tracing::trace!(target: "canctl::sim", "cannot record this process in {}: {e}", owner_path.display());
    }
}

/// This process, which holds the sim network saved at `path`, serves its devices on `bus`:
/// recorded for a command that finds the network taken, to say where to reach them.
pub fn announce_serving(path: &Path, bus: &str) {
    let holder = Holder { serves: Some(bus.to_string()), ..Holder::this_process() };
    record(&beside(path, "owner"), &holder);
}

/// Who is using the sim network, in words.
fn holder_text(holder: &Option<Holder>) -> String {
    match holder {
        Some(h) => format!("pid {} ({})", h.pid, h.command),
        None => "another process (it did not record which)".into(),
    }
}

/// `10 s`, `1.5 s`, `250 ms`.
fn duration_text(d: Duration) -> String {
    if d < Duration::from_secs(1) {
        format!("{} ms", d.as_millis())
    } else {
        format!("{} s", d.as_secs_f64())
    }
}

impl StateFile {
    /// Lock the state at `path`, waiting up to `DEFAULT_LOCK_WAIT` for another process
    /// using it.
    pub fn lock(path: &Path) -> Result<StateFile> {
        StateFile::lock_within(path, DEFAULT_LOCK_WAIT)
    }

    /// Lock the state at `path`, waiting up to `wait` for another process using it; then a
    /// link error (exit 5) that names that process and how to proceed.
    pub fn lock_within(path: &Path, wait: Duration) -> Result<StateFile> {
        // The default state's folder is canctl's own to make; a path the user named is
        // written only where it stands.
        if path == default_path() {
            if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir).map_err(|e| link_err(path, "cannot create its directory", e))?;
            }
        }
        check_ours(path)?;
        let lock_path = beside(path, "lock");
        let owner_path = beside(path, "owner");
        let lock = OpenOptions::new().create(true).truncate(false).write(true).open(&lock_path);
        let lock = lock.map_err(|e| link_err(&lock_path, "cannot open", e))?;
        let give_up = Instant::now() + wait;
        let mut told = false;
        loop {
            match lock.try_lock() {
                Ok(()) => break,
                Err(TryLockError::Error(e)) => return Err(link_err(&lock_path, "cannot lock", e)),
                Err(TryLockError::WouldBlock) => {}
            }
            let holder = Holder::read(&owner_path);
            if Instant::now() >= give_up {
                let serving = holder.as_ref().and_then(|h| h.serves.clone());
                return Err(LinkError::SimInUse { holder: holder_text(&holder), waited: wait, serving }.into());
            }
            if !told {
                tracing::warn!(
                    target: "canctl::sim",
                    pid = holder.as_ref().map(|h| h.pid),
                    "the sim network ({}) is in use by {}: waiting up to {}",
                    path.display(),
                    holder_text(&holder),
                    duration_text(wait)
                );
                told = true;
            }
            std::thread::sleep(LOCK_RETRY.min(give_up.saturating_duration_since(Instant::now())));
        }
        tracing::trace!(target: "canctl::sim", "locked the sim network ({})", path.display());
        record(&owner_path, &Holder::this_process());
        Ok(StateFile { path: path.to_path_buf(), owner_path, _lock: lock })
    }

    /// Where the file is.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The saved state; `None` when there is no file yet.
    pub fn load(&self) -> Result<Option<NetworkState>> {
        let text = match std::fs::read_to_string(&self.path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(link_err(&self.path, "cannot read", e)),
        };
        let state: NetworkState =
            serde_json::from_str(&text).map_err(|e| unusable(&self.path, "is not a sim state", e))?;
        if state.version != VERSION {
            return Err(unusable(&self.path, "has another format version", state.version));
        }
        Ok(Some(state))
    }

    /// Saves `state`, replacing the file whole (never half-written).
    pub fn save(&self, state: &NetworkState) -> Result<()> {
        let tmp = beside(&self.path, "tmp");
        let text = serde_json::to_string_pretty(state).expect("state serialises");
        std::fs::write(&tmp, text).map_err(|e| link_err(&tmp, "cannot write", e))?;
        std::fs::rename(&tmp, &self.path).map_err(|e| link_err(&self.path, "cannot replace", e))
    }

    /// Start afresh with this configuration: devices as built, nothing else kept.
    pub fn start_fresh(&self, config: &super::SimConfig) -> Result<()> {
        self.save(&NetworkState { version: VERSION, config: Some(config.clone()), ..NetworkState::default() })
    }

    /// The configuration the saved state was made with (the default one without a state).
    pub fn config(&self) -> Result<super::SimConfig> {
        Ok(self.load()?.and_then(|s| s.config).unwrap_or_default())
    }

    /// Forget the saved state: the next use starts with the demo network as built.
    pub fn reset(&self) -> Result<()> {
        match std::fs::remove_file(&self.path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(link_err(&self.path, "cannot remove", e)),
            _ => Ok(()),
        }
    }
}

impl Drop for StateFile {
    /// The record goes before the lock does (fields drop after this), so that it never
    /// names a process that no longer holds the lock.
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.owner_path);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A second lock on the same file waits its bounded time and names the holder; once
    /// the holder is gone the lock is free again.
    #[test]
    fn a_taken_lock_is_waited_for_a_bounded_time_and_names_its_holder() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sim.json");
        let held = StateFile::lock(&path).unwrap();
        let recorded = Holder::read(&beside(&path, "owner")).expect("the holder is recorded");
        assert_eq!(recorded.pid, std::process::id());
        // flock locks belong to each open file: a second open in this process is refused
        // as another process's would be.
        let err = StateFile::lock_within(&path, Duration::from_millis(100)).err().expect("the lock is taken");
        assert_eq!(err.exit_code(), 5);
        let msg = err.to_string();
        assert!(msg.contains(&format!("in use by pid {} ({})", recorded.pid, recorded.command)), "{msg}");
        assert!(msg.contains("(waited 100 ms): it serves one command at a time"), "{msg}");
        // The way to share it is the front end's to word (canctl's hint tests).
        drop(held);
        assert!(!beside(&path, "owner").exists(), "the record goes with the lock");
        StateFile::lock_within(&path, Duration::ZERO).expect("free again");
    }

    #[test]
    fn a_holder_that_recorded_nothing_is_still_told() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sim.json");
        let _held = StateFile::lock(&path).unwrap();
        std::fs::remove_file(beside(&path, "owner")).unwrap();
        let msg = StateFile::lock_within(&path, Duration::ZERO).err().unwrap().to_string();
        assert!(msg.contains("in use by another process"), "{msg}");
    }
}
