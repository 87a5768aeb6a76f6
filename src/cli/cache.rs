//! What the last scan of each bus found, kept under `$XDG_CACHE_HOME/canctl/` (else
//! `~/.cache/canctl/`): error hints ("nodes seen on the last scan") and, later, shell
//! completion of node-ids use it. A cache: a failure to read or write it is never an error.

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

#[derive(Serialize, Deserialize, Debug, Clone, PartialEq)]
pub struct SeenNode {
    pub node: u8,
    pub name: Option<String>,
    pub vendor_id: Option<u32>,
}

fn dir() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_CACHE_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
    Some(base.join("canctl"))
}

/// One file per bus URI, named after it.
fn file(bus: &str) -> Option<PathBuf> {
    let name: String =
        bus.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '.' { c } else { '_' }).collect();
    Some(dir()?.join(format!("scan-{name}.json")))
}

pub fn save(bus: &str, nodes: &[SeenNode]) {
    if let Some(path) = file(bus) {
        let _ = std::fs::create_dir_all(path.parent().expect("a directory"));
        let _ = std::fs::write(&path, serde_json::to_string(nodes).expect("serialises"));
    }
}

pub fn load(bus: &str) -> Vec<SeenNode> {
    file(bus).and_then(|p| std::fs::read(p).ok()).and_then(|b| serde_json::from_slice(&b).ok()).unwrap_or_default()
}

/// `; nodes seen on the last scan of sim: 1, 5, 10` for a message about a silent node.
pub fn hint(bus: &str) -> String {
    let seen = load(bus);
    if seen.is_empty() {
        return format!("; `canctl scan` lists the nodes on {bus}");
    }
    let list: Vec<String> = seen.iter().map(|n| n.node.to_string()).collect();
    format!("; nodes seen on the last scan of {bus}: {}", list.join(", "))
}
