//! Where canctl keeps files, by the XDG base directory convention: `$VAR/canctl`, else
//! `$HOME/<default>/canctl` (`~/.config`, `~/.cache`, `~/.local/state`).

use std::path::PathBuf;

/// `canctl`'s directory under `$var`, else under `$HOME/home_default`; None without either.
pub fn canctl_dir(var: &str, home_default: &str) -> Option<PathBuf> {
    let base = std::env::var_os(var)
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(home_default)))?;
    Some(base.join("canctl"))
}
