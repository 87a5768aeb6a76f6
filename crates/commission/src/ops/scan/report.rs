//! What a scan found: the nodes and their identities, the devices without a node-id, the
//! clashes, and what the scan did not get to.

use super::probe::Repeat;
use crate::canopen::lss::Identity;
use crate::canopen::nmt;
use crate::ops::nmt::StateFrom;
use serde::Serialize;

/// What a scan found.
#[derive(Debug, Default, Serialize)]
pub struct Scan {
    /// The bus, as it describes itself.
    pub bus: String,
    /// Each node that answered, by node-id.
    pub nodes: Vec<Node>,
    /// How many devices without a node-id answered LSS.
    pub lss_unconfigured: usize,
    /// Devices in LSS configuration state, from their answers to the inquiries.
    pub lss_configuration: Configuring,
    /// Node-ids more than one device answers to.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub clashes: Vec<crate::ops::clash::Clash>,
    /// How many rounds of the probe of node-ids ran (see `PROBE_ROUNDS`).
    pub probe_rounds: usize,
    /// The nodes that answered the probe only when asked again: the bus is losing frames.
    pub answered_on_repeat: Vec<Repeat>,
    /// The user stopped the scan (SIGINT, SIGTERM): the nodes are those found so far.
    pub interrupted: bool,
    /// When interrupted: the parts of the scan not done, the one it stopped in first
    /// (canctl's JSON words them as `not_done`).
    #[serde(skip)]
    pub not_done: Vec<Phase>,
    /// Nodes the last scan of this bus saw that showed nothing now: no answer to the probe,
    /// no heartbeat, no answer to node guarding (see [`scan_against`](super::scan_against)).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub gone: Vec<Gone>,
    /// Nodes whose SDO server answers on another node's COB-ID: asked alone, where a node
    /// that showed itself answered no probe ([`crate::ops::answers_elsewhere`]). The node whose
    /// COB-ID it took is not listed unless it answers on its own.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub answers_elsewhere: Vec<crate::ops::answers_elsewhere::AnswersElsewhere>,
    /// Node-ids an answer to the probe came for, that then answered nothing, not even asked
    /// alone: the answer was another device's, on their COB-ID (an SDO server on another
    /// node's COB-ID that showed itself no other way). Not listed in `nodes`.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub not_there: Vec<u8>,
}

/// A node the last scan saw that showed nothing in this one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Gone {
    /// The node-id.
    pub node: u8,
    /// What was asked and not answered: node guarding, or nothing more where the link
    /// carries no remote frames (then it may be a Stopped node).
    #[serde(rename = "state_from")]
    pub from: StateFrom,
}

/// A part of a scan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Probing node-ids 1 to 127 (stopped in it: nodes not listed may be there).
    Probe,
    /// Reading each node's identity, name and heartbeat time.
    Identities,
    /// Learning the nodes' NMT states.
    States,
    /// Counting the devices without a node-id (LSS).
    Unconfigured,
}

impl Phase {
    /// The parts of a scan, in order.
    pub const ALL: [Phase; 4] = [Phase::Probe, Phase::Identities, Phase::States, Phase::Unconfigured];
}

/// A node that answered the probe, with what it told about itself (`None`: not said).
#[derive(Debug, Default, Serialize)]
pub struct Node {
    /// The node-id.
    pub node: u8,
    /// 0x1000; `None` when the probe was answered with an abort (the node is there all the same).
    pub device_type: Option<u32>,
    /// The vendor-ID (0x1018:1).
    pub vendor_id: Option<u32>,
    /// The product code (0x1018:2).
    pub product_code: Option<u32>,
    /// The revision number (0x1018:3).
    pub revision: Option<u32>,
    /// The serial number (0x1018:4).
    pub serial: Option<u32>,
    /// The device name (0x1008).
    pub name: Option<String>,
    /// The NMT state the node shows, never a guess.
    pub state: Option<nmt::State>,
    /// How the state was learned, or why it is unknown.
    pub state_from: StateFrom,
    /// The producer heartbeat time the node reports (0x1017), in ms.
    pub heartbeat_ms: Option<u16>,
    /// Whether it answered the probe. A node that did not (a Stopped node answers no SDO)
    /// but showed itself otherwise (heartbeat, boot-up, an answer after the window) is
    /// listed all the same, without what only SDO tells.
    pub answers_sdo: bool,
}

/// Devices in LSS configuration state, from their answers to the inquiries.
#[derive(Debug, Default, PartialEq, Serialize)]
#[non_exhaustive]
pub struct Configuring {
    /// How many answered (the most answers to any one inquiry).
    pub count: usize,
    /// The identity and node-id, when exactly one device answered each inquiry.
    #[serde(rename = "devices", serialize_with = "devices")]
    pub one: Option<(Identity, Option<u8>)>,
}

/// The device in configuration state as a list of none or one:
/// `{"identity": "0x...:...", "lss": {"vendor_id": ..}, "node": ..}`.
fn devices<S: serde::Serializer>(one: &Option<(Identity, Option<u8>)>, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_seq(one.iter().map(|(id, node)| {
        let lss = serde_json::json!({
            "vendor_id": id.vendor, "product_code": id.product, "revision": id.revision, "serial": id.serial,
        });
        serde_json::json!({ "identity": id.to_string(), "lss": lss, "node": node })
    }))
}
