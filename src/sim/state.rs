//! The simulated network's state between invocations: a JSON file, locked while a
//! process uses it, replaced atomically when saved.

use super::device::DeviceState;
use crate::error::{Error, LinkError, Result};
use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

pub const VERSION: u32 = 1;

#[derive(serde::Serialize, serde::Deserialize, Default, Debug)]
pub struct NetworkState {
    pub version: u32,
    /// The bus's bit rate (CiA 305 table index).
    #[serde(default)]
    pub bit_rate: Option<u8>,
    /// Profile, seed, devices and faults chosen by `sim reset`; absent: the defaults.
    #[serde(default)]
    pub config: Option<super::SimConfig>,
    pub devices: BTreeMap<String, DeviceState>,
}

pub struct StateFile {
    path: PathBuf,
    /// Held for the life of this value: one process drives the sim network at a time.
    _lock: File,
}

/// `$XDG_STATE_HOME/canctl/sim.json`, else `~/.local/state/canctl/sim.json`.
pub fn default_path() -> PathBuf {
    crate::xdg::state_dir().unwrap_or_else(|| std::env::temp_dir().join("canctl")).join("sim.json")
}

fn link_err(path: &Path, what: &'static str, e: impl std::fmt::Display) -> Error {
    LinkError::StateFile { path: path.to_path_buf(), what, detail: e.to_string() }.into()
}

impl StateFile {
    /// Lock the state at `path` (waiting for another canctl using it to finish).
    pub fn lock(path: &Path) -> Result<StateFile> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| link_err(path, "cannot create its directory", e))?;
        }
        let lock_path = path.with_extension("lock");
        let lock = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(|e| link_err(&lock_path, "cannot open", e))?;
        if lock.try_lock().is_err() {
            eprintln!("canctl: waiting for another canctl using the sim network ({})", path.display());
            lock.lock().map_err(|e| link_err(&lock_path, "cannot lock", e))?;
        }
        Ok(StateFile { path: path.to_path_buf(), _lock: lock })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn load(&self) -> Result<Option<NetworkState>> {
        let text = match std::fs::read_to_string(&self.path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(link_err(&self.path, "cannot read", e)),
        };
        let state: NetworkState = serde_json::from_str(&text)
            .map_err(|e| link_err(&self.path, "is not a sim state (`canctl sim reset` starts afresh)", e))?;
        if state.version != VERSION {
            return Err(link_err(
                &self.path,
                "has another format version",
                format!("{} (`canctl sim reset` starts afresh)", state.version),
            ));
        }
        Ok(Some(state))
    }

    pub fn save(&self, state: &NetworkState) -> Result<()> {
        let tmp = self.path.with_extension("tmp");
        let text = serde_json::to_string_pretty(state).expect("state serialises");
        std::fs::write(&tmp, text).map_err(|e| link_err(&tmp, "cannot write", e))?;
        std::fs::rename(&tmp, &self.path).map_err(|e| link_err(&self.path, "cannot replace", e))
    }

    /// Start afresh with this configuration: devices as built, nothing else kept.
    pub fn start_fresh(&self, config: &super::SimConfig) -> Result<()> {
        let state =
            NetworkState { version: VERSION, bit_rate: None, config: Some(config.clone()), devices: BTreeMap::new() };
        self.save(&state)
    }

    /// The configuration the saved state was made with (the default one without a state).
    pub fn config(&self) -> Result<super::SimConfig> {
        Ok(self.load()?.and_then(|s| s.config).unwrap_or_default())
    }

    /// Forget the saved state: the next use starts with the demo network as built.
    pub fn reset(&self) -> Result<()> {
        match std::fs::remove_file(&self.path) {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
            Err(e) => Err(link_err(&self.path, "cannot remove", e)),
        }
    }
}
