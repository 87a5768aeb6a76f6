//! What the last scan of each bus found, kept under `$XDG_CACHE_HOME/canctl/` (else
//! `~/.cache/canctl/`): error hints ("nodes seen on the last scan") and shell completion of
//! node-ids and objects use it. A cache: a failure to read or write it is never an error.
//!
//! Per node it also keeps what is known of the node's object list, for completion to offer
//! only objects the node has (see `cli::complete::objects`): the EDS/DCF/XDD that described
//! it when it was scanned or that it stores in itself (once `config eds --out` saved it),
//! the objects it answered (the scan's reads, `sdo read` and `sdo write`) and the objects it
//! said it does not have (SDO abort 0x06020000). A new scan keeps what was learned of a node
//! while the node answers with the same identity.

use crate::canopen::ObjAddr;
use crate::error::Error;
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use std::path::PathBuf;

/// A node the last scan found: what completion offers for `--node` and picks dictionaries by.
#[derive(Serialize, Deserialize, Debug, Clone, PartialEq, Default)]
#[non_exhaustive]
pub struct SeenNode {
    /// Its node-id.
    pub node: u8,
    /// Its device name (0x1008), when it gave one.
    pub name: Option<String>,
    /// Its vendor-id (0x1018:1), when it gave one.
    pub vendor_id: Option<u32>,
    /// 0x1000: its profile picks the built-in dictionary that completion offers objects
    /// from (a DS406 sensor is not offered a drive's objects). Absent in older caches.
    #[serde(default)]
    pub device_type: Option<u32>,
    /// Whether the last scan found it; `false` for a node known only from the objects it
    /// answered since (it is no node-id "seen on the last scan").
    #[serde(default = "scanned")]
    pub scanned: bool,
    /// The EDS/DCF/XDD file that describes the node's object list (an absolute path): the
    /// one the scan used for it, or the one it stores in itself, as saved.
    #[serde(default)]
    pub dictionary: Option<PathBuf>,
    /// Objects the node answered, as (index, sub-index).
    #[serde(default)]
    pub answered: BTreeSet<(u16, u8)>,
    /// Indices the node said it does not have (SDO abort 0x06020000).
    #[serde(default)]
    pub refused: BTreeSet<u16>,
}

/// Caches written before `scanned` was kept hold only scanned nodes.
fn scanned() -> bool {
    true
}

/// The network a bus URI reaches, so `can0` and `socketcan:can0` share what was seen, and
/// a different baud rate to the same EPOS2 does not lose it. A sim network is its state
/// file: `sim:s.json` in two folders is two networks.
fn network(bus: &str) -> String {
    use crate::connect::BusAddr;
    match bus.parse::<BusAddr>() {
        Ok(BusAddr::Epos2 { framing, port, .. }) => format!("{framing:?}:{port}"),
        Ok(BusAddr::Sim { state: Some(path) }) => {
            format!("sim:{}", std::path::absolute(&path).unwrap_or(path).display())
        }
        Ok(addr) => addr.to_string(),
        Err(_) => bus.to_string(),
    }
}

const SCAN: &str = "scan";
/// What the last global `lss set-baud` left (`ops::lss::RefusedRate`).
pub(crate) const LSS_SET_BAUD: &str = "lss-set-baud";

/// Forget all that is remembered of the network `bus` reaches: it was started afresh (a
/// sim network reset), so what was seen on it is of another network.
pub fn forget(bus: &str) {
    for kind in [SCAN, LSS_SET_BAUD] {
        if let Some(path) = network_file(kind, bus) {
            let _ = std::fs::remove_file(path);
        }
    }
}

/// The cache file `KIND-NETWORK.json` for what is remembered of a network.
pub(crate) fn network_file(kind: &str, bus: &str) -> Option<PathBuf> {
    let name: String =
        network(bus).chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '.' { c } else { '_' }).collect();
    Some(crate::xdg::cache_dir()?.join(format!("{kind}-{name}.json")))
}

impl SeenNode {
    /// What completion and hints keep of each node a scan found: its identity, the objects
    /// the scan read from it, and the description `dicts` holds for it (an EDS given for it).
    pub fn from_scan(scan: &super::scan::Scan, dicts: &super::dictionaries::Dictionaries) -> Vec<SeenNode> {
        let seen = |n: &super::scan::Node| {
            let identity = [n.vendor_id, n.product_code, n.revision, n.serial];
            let read = [(0x1000, 0, n.device_type.is_some()), (0x1008, 0, n.name.is_some())]
                .into_iter()
                .chain(ObjAddr::IDENTITY_PARTS.iter().zip(identity).map(|(a, v)| (a.index, a.sub, v.is_some())))
                .chain([(0x1017, 0, n.heartbeat_ms.is_some())]);
            SeenNode {
                node: n.node,
                name: n.name.clone(),
                vendor_id: n.vendor_id,
                device_type: n.device_type,
                scanned: true,
                dictionary: dicts.eds_for(n.node).and_then(|e| std::path::absolute(&e.path).ok()),
                answered: read.filter(|(_, _, ok)| *ok).map(|(index, sub, _)| (index, sub)).collect(),
                ..SeenNode::default()
            }
        };
        scan.nodes.iter().map(seen).collect()
    }

    fn same_device(&self, other: &SeenNode) -> bool {
        !other.scanned || (self.vendor_id, self.device_type) == (other.vendor_id, other.device_type)
    }
}

/// Remember `scan` as the nodes of `bus` when it may stand for the bus: it was not stopped,
/// and it waited for slow devices (a shorter window may have missed some); whether it was.
pub fn remember(
    bus: &str,
    scan: &super::scan::Scan,
    options: &super::scan::ScanOptions,
    dicts: &super::dictionaries::Dictionaries,
) -> bool {
    let whole = !scan.interrupted && !options.may_miss_slow_devices();
    if whole {
        save(bus, &SeenNode::from_scan(scan, dicts));
    }
    whole
}

/// Save what a scan found as the bus's nodes, keeping what was learned before of each
/// node that answered with the same identity.
pub fn save(bus: &str, nodes: &[SeenNode]) {
    write_cache(network_file(SCAN, bus), &merged(load_all(bus), nodes));
}

/// `nodes`, each with what `old` knew of the same device at its id.
fn merged(old: Vec<SeenNode>, nodes: &[SeenNode]) -> Vec<SeenNode> {
    let mut nodes = nodes.to_vec();
    for n in &mut nodes {
        if let Some(o) = old.iter().find(|o| o.node == n.node && n.same_device(o)) {
            n.answered.extend(&o.answered);
            n.refused.extend(&o.refused);
            n.dictionary = n.dictionary.take().or_else(|| o.dictionary.clone());
        }
    }
    nodes
}

/// Every node of the bus the cache knows of, also those known only from what they answered.
pub(crate) fn load_all(bus: &str) -> Vec<SeenNode> {
    read_cache(network_file(SCAN, bus))
}

/// Write `value` as JSON to the cache file `path`. A cache: failing to is no error.
pub(crate) fn write_cache(path: Option<PathBuf>, value: &(impl Serialize + ?Sized)) {
    if let Some(path) = path {
        let _ = std::fs::create_dir_all(path.parent().expect("a directory"));
        let _ = crate::atomic::write_atomic(&path, serde_json::to_string(value).expect("serialises").as_bytes());
    }
}

/// What the cache file `path` holds; nothing (the default) when it cannot be read.
pub(crate) fn read_cache<T: serde::de::DeserializeOwned + Default>(path: Option<PathBuf>) -> T {
    path.and_then(|p| std::fs::read(p).ok()).and_then(|b| serde_json::from_slice(&b).ok()).unwrap_or_default()
}

/// The nodes the last scan of the bus found.
pub fn load(bus: &str) -> Vec<SeenNode> {
    load_all(bus).into_iter().filter(|n| n.scanned).collect()
}

/// The node-ids the last scan of `bus` found (none for a bus never scanned, or without a
/// URI): what a scan or health now expects to hear from ([`super::scan::scan_against`]).
pub fn last_seen(bus: Option<&str>) -> Vec<u8> {
    bus.map(load).unwrap_or_default().iter().map(|n| n.node).collect()
}

/// Remember what an SDO transfer of `addr` with `node` showed of its object list: that it
/// has the object (it answered), or that it has no object at that index (abort
/// 0x06020000). Any other outcome says nothing of it, and nothing is remembered of a bus
/// without a URI.
pub fn note<T>(bus: Option<&str>, node: u8, addr: ObjAddr, outcome: &Result<T, Error>) {
    let Some(bus) = bus else { return };
    let has = match outcome {
        Ok(_) => true,
        Err(e) if super::node::lacks_index(e) => false,
        Err(_) => return,
    };
    let mut nodes = load_all(bus);
    if noted(&mut nodes, node, addr, has) {
        write_cache(network_file(SCAN, bus), &nodes);
    }
}

/// Remember `path` as the description of `node`'s object list: a description the node
/// stores in itself (0x1021), once saved to a file.
pub fn describe(bus: &str, node: u8, path: &std::path::Path) {
    let Ok(path) = std::path::absolute(path) else { return };
    let mut nodes = load_all(bus);
    entry(&mut nodes, node).dictionary = Some(path);
    write_cache(network_file(SCAN, bus), &nodes);
}

/// `node`'s entry in `nodes`, added (as no node the scan saw) when missing.
fn entry(nodes: &mut Vec<SeenNode>, node: u8) -> &mut SeenNode {
    let i = nodes.iter().position(|n| n.node == node).unwrap_or_else(|| {
        nodes.push(SeenNode { node, ..SeenNode::default() });
        nodes.len() - 1
    });
    &mut nodes[i]
}

/// Add to `nodes` that `node` has `addr` (or has nothing at its index); whether that is news.
fn noted(nodes: &mut Vec<SeenNode>, node: u8, addr: ObjAddr, has: bool) -> bool {
    let n = entry(nodes, node);
    if has {
        n.refused.remove(&addr.index) | n.answered.insert((addr.index, addr.sub))
    } else {
        n.answered.retain(|(index, _)| *index != addr.index);
        n.refused.insert(addr.index)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node(vendor: u32) -> SeenNode {
        SeenNode {
            node: 5,
            name: None,
            vendor_id: Some(vendor),
            device_type: Some(0x196),
            scanned: true,
            dictionary: None,
            answered: BTreeSet::new(),
            refused: BTreeSet::new(),
        }
    }

    /// What a node answered and refused outlives a new scan while the same device answers
    /// at that id; another device there starts with nothing known.
    #[test]
    fn a_new_scan_keeps_what_was_learned_of_the_same_device() {
        let mut nodes = vec![node(0x40)];
        assert!(noted(&mut nodes, 5, ObjAddr::new(0x1800, 1), true));
        assert!(!noted(&mut nodes, 5, ObjAddr::new(0x1800, 1), true), "no news");
        assert!(noted(&mut nodes, 5, ObjAddr::new(0x6004, 0), false));
        // Another node, never scanned: remembered, but as no node the scan saw.
        assert!(noted(&mut nodes, 7, ObjAddr::new(0x1000, 0), true));
        assert!(!nodes[1].scanned);

        let kept = merged(nodes.clone(), &[node(0x40)]);
        assert_eq!(kept.len(), 1, "a scan says which nodes there are");
        assert!(kept[0].answered.contains(&(0x1800, 1)) && kept[0].refused.contains(&0x6004), "{kept:?}");
        let other = merged(nodes, &[node(0x41)]);
        assert!(other[0].answered.is_empty() && other[0].refused.is_empty(), "{other:?}");
    }

    /// A node that refused an index and later answered it (its configuration changed)
    /// has it; one that answered and then refused it has it no more.
    #[test]
    fn the_last_word_of_the_node_counts() {
        let mut nodes = vec![node(0x40)];
        noted(&mut nodes, 5, ObjAddr::new(0x1801, 1), false);
        noted(&mut nodes, 5, ObjAddr::new(0x1801, 1), true);
        assert!(nodes[0].refused.is_empty() && nodes[0].answered.contains(&(0x1801, 1)));
        noted(&mut nodes, 5, ObjAddr::new(0x1801, 2), false);
        assert!(nodes[0].answered.is_empty() && nodes[0].refused.contains(&0x1801));
    }

    #[test]
    fn spellings_of_one_network_share_a_cache() {
        assert_eq!(network("can0"), network("socketcan:can0"));
        assert_eq!(network("epos2-rs232:/dev/ttyS0"), network("epos2-rs232:/dev/ttyS0?baud=38400"));
        assert_ne!(network("epos2-rs232:/dev/ttyS0"), network("epos2-usb:/dev/ttyS0"));
        assert_ne!(network("sim"), network("sim:/tmp/a.json"));
        let here = std::env::current_dir().unwrap();
        assert_eq!(network("sim:a.json"), network(&format!("sim:{}", here.join("a.json").display())));
        assert_eq!(network("not a bus:"), "not a bus:");
    }
}
