//! `canctl scan`: every node 1..127, with identity, name and NMT state.

use super::Ctx;
use crate::bus::{Bus, SdoOptions};
use crate::canopen::{DataType, ObjAddr};
use crate::error::Error;
use crate::output::Format;
use clap::Args;
use serde_json::json;
use std::time::Duration;

/// Find every node on the bus
///
/// Sends an SDO read of 0x1000 (device type) to all 127 node-ids at once and waits one
/// quiet window for answers; then reads identity (0x1018:1..4) and name (0x1008) from each
/// node that answered, all nodes in parallel. The NMT state comes from heartbeats seen
/// meanwhile; a node without heartbeat shows none (scan never sends node-guarding requests).
/// Last, it counts the devices without a node-id that answer LSS "identify non-configured
/// remote slave".
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim scan
  canctl --bus can0 scan --window 200ms --format json > nodes.json
  canctl --bus sim scan --format csv | cut -d, -f1,7")]
pub struct ScanArgs {
    /// How long to wait for answers to the probes
    #[arg(long, value_name = "DUR", default_value = "50ms", value_parser = super::parse_duration)]
    pub window: Duration,
}

const IDENTITY: [(&str, ObjAddr); 4] = [
    ("vendor_id", ObjAddr::new(0x1018, 1)),
    ("product_code", ObjAddr::new(0x1018, 2)),
    ("revision", ObjAddr::new(0x1018, 3)),
    ("serial", ObjAddr::new(0x1018, 4)),
];
const NAME: ObjAddr = ObjAddr::new(0x1008, 0);

struct Found {
    node: u8,
    device_type: Option<u32>,
    identity: [Option<u32>; 4],
    name: Option<String>,
    state: Option<crate::canopen::nmt::State>,
}

fn as_u32(bytes: &[u8]) -> Option<u32> {
    bytes.try_into().ok().map(u32::from_le_bytes)
}

/// Every node that answers an SDO read of 0x1000 within `window`, with its device type
/// (`None` when it answered with an abort: the node is there all the same).
pub fn probe(ctx: &Ctx, bus: &mut dyn Bus, window: Duration) -> anyhow::Result<Vec<(u8, Option<u32>)>> {
    let probes: Vec<(u8, ObjAddr)> = (1..=127).map(|n| (n, ObjAddr::new(0x1000, 0))).collect();
    let bar = ctx.out.bar(probes.len() as u64, "probing");
    let answers = bus.sdo_upload_many(&probes, &SdoOptions::new(window), &mut |n| bar.set_position(n as u64))?;
    bar.finish_and_clear();
    let mut found = Vec::new();
    for ((node, _), answer) in probes.iter().zip(answers) {
        match answer {
            Ok(bytes) => found.push((*node, as_u32(&bytes))),
            Err(Error::SdoAbort { .. }) => found.push((*node, None)),
            Err(Error::Timeout(_)) => {}
            Err(e) => ctx.out.note(&format!("warning: node {node}: {e}")),
        }
    }
    Ok(found)
}

pub fn run(ctx: &Ctx, bus: &mut dyn Bus, args: &ScanArgs) -> anyhow::Result<()> {
    // Where the bus's traffic is seen, the LSS question goes out with the probes and its
    // answers come in during the same window.
    let lss_alongside = bus.sees_traffic();
    if lss_alongside {
        let ask = crate::canopen::lss::Request::IdentifyNonConfigured.encode();
        bus.lss_exchange(&ask, Duration::ZERO, crate::bus::LssWait::Nothing)?;
    }
    let mut found: Vec<Found> = probe(ctx, bus, args.window)?
        .into_iter()
        .map(|(node, device_type)| Found { node, device_type, identity: [None; 4], name: None, state: None })
        .collect();

    let reads: Vec<(u8, ObjAddr)> =
        found.iter().flat_map(|f| IDENTITY.iter().map(|(_, a)| (f.node, *a)).chain([(f.node, NAME)])).collect();
    let bar = ctx.out.bar(reads.len() as u64, "identity");
    let values = bus.sdo_upload_many(&reads, &SdoOptions::new(ctx.timeout), &mut |n| bar.set_position(n as u64))?;
    bar.finish_and_clear();
    for ((node, addr), value) in reads.iter().zip(values) {
        let f = found.iter_mut().find(|f| f.node == *node).expect("read for a found node");
        match value {
            Ok(bytes) if *addr == NAME => f.name = DataType::Vs.decode(&bytes).map(|v| v.to_string()),
            Ok(bytes) => {
                let i = IDENTITY.iter().position(|(_, a)| a == addr).expect("identity entry");
                f.identity[i] = as_u32(&bytes);
            }
            Err(Error::SdoAbort { .. }) => {}
            Err(e) => ctx.out.note(&format!("warning: {e}")),
        }
    }
    let states = bus.heartbeats_seen();
    for f in &mut found {
        f.state = states.get(&f.node).copied();
    }
    let unconfigured = if lss_alongside {
        crate::bus::lss::count_non_configured(&bus.lss_answers_seen())
    } else {
        crate::bus::lss::count_unconfigured(bus, args.window)?
    };
    if let Some(uri) = &ctx.bus {
        let seen: Vec<super::cache::SeenNode> = found
            .iter()
            .map(|f| super::cache::SeenNode { node: f.node, name: f.name.clone(), vendor_id: f.identity[0] })
            .collect();
        super::cache::save(uri, &seen);
    }
    report(ctx, bus, &found, unconfigured)
}

fn report(ctx: &Ctx, bus: &dyn Bus, found: &[Found], unconfigured: usize) -> anyhow::Result<()> {
    let hex = |v: Option<u32>| v.map_or("-".to_string(), |v| format!("0x{v:08X}"));
    match ctx.out.format {
        Format::Json => {
            let nodes: Vec<_> = found
                .iter()
                .map(|f| {
                    json!({
                        "node": f.node,
                        "device_type": f.device_type,
                        "vendor_id": f.identity[0],
                        "product_code": f.identity[1],
                        "revision": f.identity[2],
                        "serial": f.identity[3],
                        "name": f.name,
                        "state": f.state.map(|s| s.name()),
                    })
                })
                .collect();
            ctx.out.json(&json!({ "bus": bus.describe(), "nodes": nodes, "lss_unconfigured": unconfigured }))?;
        }
        Format::Human | Format::Csv => {
            let headers = ["node", "device_type", "vendor_id", "product_code", "revision", "serial", "name", "state"];
            let rows: Vec<Vec<String>> = found
                .iter()
                .map(|f| {
                    let mut row = vec![f.node.to_string(), hex(f.device_type)];
                    row.extend(f.identity.iter().map(|v| hex(*v)));
                    row.push(f.name.clone().unwrap_or_else(|| "-".into()));
                    row.push(f.state.map_or("-".into(), |s| s.name().to_string()));
                    row
                })
                .collect();
            if ctx.out.format == Format::Human {
                ctx.out.note(&format!("{} node(s) on {}", found.len(), bus.describe()));
            }
            ctx.out.table(&headers, &rows)?;
            if ctx.out.format == Format::Human && unconfigured > 0 {
                ctx.out.print(&format!(
                    "{unconfigured} device(s) without a node-id answered LSS (canctl lss fastscan finds them, lss assign numbers them)"
                ))?;
            }
        }
    }
    Ok(())
}
