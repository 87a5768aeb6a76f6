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
    /// 0x1000: its profile picks the built-in dictionary that completion offers objects
    /// from (a DS406 sensor is not offered a drive's objects). Absent in older caches.
    #[serde(default)]
    pub device_type: Option<u32>,
}

fn dir() -> Option<PathBuf> {
    crate::xdg::cache_dir()
}

/// The network a bus URI reaches, so `can0` and `socketcan:can0` share what was seen, and
/// a different baud rate to the same EPOS2 does not lose it.
fn network(bus: &str) -> String {
    use crate::connect::BusAddr;
    match bus.parse::<BusAddr>() {
        Ok(BusAddr::Epos2 { framing, port, .. }) => format!("{framing:?}:{port}"),
        Ok(addr) => addr.to_string(),
        Err(_) => bus.to_string(),
    }
}

/// One file per network, named after it.
fn file(bus: &str) -> Option<PathBuf> {
    network_file("scan", bus)
}

/// The cache file `KIND-NETWORK.json` for what is remembered of a network.
pub(crate) fn network_file(kind: &str, bus: &str) -> Option<PathBuf> {
    let name: String =
        network(bus).chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '.' { c } else { '_' }).collect();
    Some(dir()?.join(format!("{kind}-{name}.json")))
}

impl SeenNode {
    /// What completion and hints keep of each node a scan found.
    pub fn from_scan(scan: &super::scan::Scan) -> Vec<SeenNode> {
        let seen = |n: &super::scan::Node| SeenNode {
            node: n.node,
            name: n.name.clone(),
            vendor_id: n.vendor_id,
            device_type: n.device_type,
        };
        scan.nodes.iter().map(seen).collect()
    }
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

#[cfg(test)]
mod tests {
    use super::network;

    #[test]
    fn spellings_of_one_network_share_a_cache() {
        assert_eq!(network("can0"), network("socketcan:can0"));
        assert_eq!(network("epos2-rs232:/dev/ttyS0"), network("epos2-rs232:/dev/ttyS0?baud=38400"));
        assert_ne!(network("epos2-rs232:/dev/ttyS0"), network("epos2-usb:/dev/ttyS0"));
        assert_ne!(network("sim"), network("sim:/tmp/a.json"));
        assert_eq!(network("not a bus:"), "not a bus:");
    }
}
