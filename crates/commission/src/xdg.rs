//! Where canctl keeps its files, by the platform's convention: the XDG base directories on
//! Linux (`$XDG_CONFIG_HOME/canctl`, else `~/.config/canctl`, and likewise for the cache
//! and state; the simulator's state is `canctl_sim::state::default_path`), the Library folders on macOS, the AppData folders on Windows.

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
