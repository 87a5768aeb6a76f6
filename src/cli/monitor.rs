//! `canctl monitor`: the bus's traffic as it happens, decoded.

use super::{parse_node, Ctx};
use crate::bus::Bus;
use crate::canopen::pdo::Layout;
use crate::ops::monitor::{Event, Monitor, Summary};
use crate::output::Line;
use clap::Args;
use clap_complete::engine::ArgValueCandidates;
use serde_json::{json, Value as J};
use std::collections::BTreeMap;
use std::time::Duration;

/// Watch the bus: every frame decoded, as it happens
///
/// NMT commands, boot-ups, heartbeats and node guarding with state names, EMCY with the
/// meaning of the code and the error register bits, SDO requests, answers and aborts, SYNC,
/// LSS, and PDOs — decoded into fields when an EDS or DCF (--eds) gives their mapping. A
/// summary ends it: frames per COB-ID, nodes seen, EMCYs.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus can0 monitor
  canctl --bus can0 monitor --node 5 --node 10 --duration 10s --format json > bus.jsonl
  canctl --bus vcan0 --eds 5=mh.dcf monitor --node 5")]
pub struct MonitorArgs {
    /// Only frames of this node (repeatable); NMT, SYNC and LSS are always shown
    #[arg(long, value_parser = parse_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: Vec<u8>,
    /// Stop after this long
    #[arg(long, value_name = "DUR", value_parser = super::parse_duration)]
    pub duration: Option<Duration>,
    /// Stop after this many frames
    #[arg(long, value_name = "N")]
    pub count: Option<u64>,
}

/// PDO layouts from the EDS/DCF files: their TPDO and RPDO mappings, for their nodes.
fn layouts(ctx: &Ctx, nodes: &[u8]) -> BTreeMap<u16, Layout> {
    let candidates: Vec<u8> = if nodes.is_empty() { (1..=127).collect() } else { nodes.to_vec() };
    let mut out = BTreeMap::new();
    for node in candidates {
        if let Some(eds) = ctx.dicts.eds_for(node) {
            out.extend(crate::ops::pdo::dcf_layouts(eds, node));
        }
    }
    out
}

pub fn run(ctx: &Ctx, bus: &mut dyn Bus, a: &MonitorArgs) -> anyhow::Result<()> {
    let mut monitor = Monitor::new(bus, layouts(ctx, &a.node), &a.node, a.duration, a.count)?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    while let Some(ev) = monitor.next(bus)? {
        ctx.out.line(&mut out, &ev)?;
        std::io::Write::flush(&mut out)?;
    }
    ctx.out.summary(&mut out, &monitor.summary())?;
    Ok(())
}

impl Line for Event {
    fn json(&self) -> J {
        let time = (self.time * 1000.0).round() / 1000.0;
        let mut j = json!({ "time": time, "cob": format!("0x{:03X}", self.cob), "node": self.node, "kind": self.kind });
        if let (Some(o), J::Object(extra)) = (j.as_object_mut(), &self.fields) {
            o.extend(extra.clone());
        }
        j
    }

    fn csv(&self) -> String {
        let node = self.node.map_or(String::new(), |n| n.to_string());
        format!("{:.3},0x{:03X},{node},{},\"{}\"", self.time, self.cob, self.kind, self.text.replace('"', "\"\""))
    }

    fn text(&self) -> String {
        let node = self.node.map_or("       ".to_string(), |n| format!("node {n:<2}"));
        format!("{:9.3}  {:03X}  {node}  {:<13} {}", self.time, self.cob, self.kind, self.text)
    }
}

impl Line for Summary {
    fn json(&self) -> J {
        let per_cob: BTreeMap<String, u64> = self.per_cob_id.iter().map(|(c, n)| (format!("0x{c:03X}"), *n)).collect();
        json!({ "summary": { "frames": self.frames(), "per_cob_id": per_cob, "nodes": self.nodes, "emcy": self.emcy } })
    }

    fn csv(&self) -> String {
        self.text()
    }

    fn text(&self) -> String {
        let cobs: Vec<String> = self.per_cob_id.iter().map(|(c, n)| format!("{c:03X}×{n}")).collect();
        let list: Vec<String> = self.nodes.iter().map(|n| n.to_string()).collect();
        format!(
            "{} frame(s) in {:.1} s; per COB-ID: {}; nodes seen: {}; EMCYs: {}",
            self.frames(),
            self.elapsed.as_secs_f64(),
            if cobs.is_empty() { "-".into() } else { cobs.join(" ") },
            if list.is_empty() { "-".into() } else { list.join(", ") },
            self.emcy
        )
    }
}
