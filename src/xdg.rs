//! Where canctl keeps its files, by the platform's convention: the XDG base directories on
//! Linux (`$XDG_CONFIG_HOME/canctl`, else `~/.config/canctl`, and likewise for the cache
//! and state), the Library folders on macOS, the AppData folders on Windows.

use std::path::PathBuf;

fn project() -> Option<directories::ProjectDirs> {
    directories::ProjectDirs::from("", "", "canctl")
}

/// Settings: `config.toml` lives here.
pub(crate) fn config_dir() -> Option<PathBuf> {
    project().map(|p| p.config_dir().to_path_buf())
}

/// What may be thrown away: the scan cache.
pub(crate) fn cache_dir() -> Option<PathBuf> {
    project().map(|p| p.cache_dir().to_path_buf())
}

/// What must outlive a run but is no setting: the simulated network. XDG has a state
/// directory; elsewhere it is the local data directory.
pub(crate) fn state_dir() -> Option<PathBuf> {
    project().map(|p| p.state_dir().unwrap_or_else(|| p.data_local_dir()).to_path_buf())
}
