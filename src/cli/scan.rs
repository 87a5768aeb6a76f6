//! `canctl scan`: every node 1 to 127, with identity, name and NMT state.

use super::Ctx;
use crate::bus::Bus;
use crate::ops::scan::{self, Scan, ScanOptions};
use crate::ops::scan_cache::{self, SeenNode};
use crate::output::{Human, Report};
use clap::Args;
use std::time::Duration;

/// Find every node on the bus
///
/// Sends an SDO read of 0x1000 (device type) to all 127 node-ids at once and waits until
/// no answer has come for one window (slow devices answer up to 80 ms late); then reads
/// identity (0x1018:1..4) and name (0x1008) from each node that answered, all nodes in
/// parallel. The NMT state is what each node shows: its
/// heartbeat, waited for as long as its period (0x1017) needs, else its answer to node
/// guarding, else `unknown` with the reason.
/// Last, it counts the devices without a node-id that answer LSS "identify non-configured
/// remote slave", and lists devices left in LSS configuration state (they answer the LSS
/// inquiry services, and without a node-id no SDO).
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim scan
  canctl --bus can0 scan --window 200ms --format json > nodes.json
  canctl --bus sim scan --format csv | cut -d, -f1,7")]
pub struct ScanArgs {
    /// How long the bus must stay quiet after the last answer to the probes
    #[arg(long, value_name = "DUR", default_value = "100ms", value_parser = super::parse_duration)]
    pub window: Duration,
}

pub fn run(ctx: &Ctx, bus: &mut dyn Bus, args: &ScanArgs) -> anyhow::Result<()> {
    let options = ScanOptions { window: args.window, timeout: ctx.timeout };
    let report = scan::scan(bus, &options, &mut ctx.out.progress())?;
    if let Some(uri) = &ctx.bus {
        scan_cache::save(uri, &SeenNode::from_scan(&report));
    }
    Ok(ctx.out.report(&report)?)
}

impl Scan {
    fn table(&self) -> Human {
        let hex = |v: Option<u32>| v.map_or("-".to_string(), |v| format!("0x{v:08X}"));
        let headers = vec!["node", "device_type", "vendor_id", "product_code", "revision", "serial", "name", "state"];
        let rows = self.nodes.iter().map(|f| {
            let identity = [f.device_type, f.vendor_id, f.product_code, f.revision, f.serial].map(hex);
            let (name, state) = (f.name.clone().unwrap_or_else(|| "-".into()), f.state.map_or("unknown", |s| s.name()));
            [vec![f.node.to_string()], identity.to_vec(), vec![name, state.into()]].concat()
        });
        Human::Table { headers, rows: rows.collect(), when_empty: true }
    }
}

impl Report for Scan {
    fn human(&self) -> Human {
        let mut parts = vec![Human::Note(format!("{} node(s) on {}", self.nodes.len(), self.bus)), self.table()];
        for f in self.nodes.iter().filter(|f| f.state.is_none()) {
            parts.push(Human::Line(format!("node {}: NMT state unknown: {}", f.node, f.state_from)));
        }
        if self.lss_unconfigured > 0 {
            parts.push(Human::Line(format!(
                "{} device(s) without a node-id answered LSS (canctl lss fastscan finds them, lss assign numbers them)",
                self.lss_unconfigured
            )));
        }
        let configuring = &self.lss_configuration;
        if configuring.count > 0 {
            let which = match configuring.one {
                Some((id, None)) => format!(": {id}, no node-id"),
                Some((id, Some(n))) => format!(": {id}, node-id {n}"),
                None if configuring.count > 1 => {
                    " (several answered at once, so their identities cannot be told apart)".to_string()
                }
                None => " (not every identity inquiry was answered, so its identity is incomplete)".to_string(),
            };
            parts.push(Human::Line(format!(
                "{} device(s) waiting in LSS configuration state{which} (canctl lss set-id gives a node-id; \
                 `canctl lss set-id 255 --global` or any LSS command sends them back to waiting)",
                configuring.count
            )));
        }
        Human::Parts(parts)
    }

    fn csv(&self) -> Human {
        self.table()
    }
}
