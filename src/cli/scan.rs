//! `canctl scan`: every node 1 to 127, with identity, name and NMT state.

use super::ctx::Ctx;
use crate::bus::Bus;
use crate::ops::scan::{self, ScanOptions};
use crate::ops::scan_cache;
use crate::output::CommandResult;
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
pub(crate) struct ScanArgs {
    /// How long the bus must stay quiet after the last answer to the probes: at least
    /// 10ms; under 100ms slow devices may be missed, and the scan cache is not replaced
    #[arg(long, value_name = "DUR", default_value = "100ms", value_parser = super::ctx::parse_duration)]
    pub window: Duration,
}

pub(crate) fn run(ctx: &Ctx, bus: &mut dyn Bus, args: &ScanArgs) -> CommandResult {
    let options = ScanOptions { window: args.window, timeout: ctx.timeout };
    let last_seen = scan_cache::last_seen(ctx.bus.as_deref());
    let report = ctx.stoppable(bus, |bus| scan::scan_against(bus, &options, &last_seen, &mut ctx.out.progress()))?;
    if report.interrupted {
        // The nodes found so far: reported, not remembered as the bus's.
        return ctx.report_then(&report, true);
    }
    if options.may_miss_slow_devices() {
        ctx.out.note(&crate::output::short_window_note());
    }
    if let Some(uri) = &ctx.bus {
        scan_cache::remember(uri, &report, &options, &ctx.dicts);
    }
    Ok(ctx.out.report(&report)?)
}

/// `scan` on several buses at once: a table of every bus's nodes, each bus's scan cache
/// saved as the one-bus scan saves it.
pub(crate) fn on_buses(ctx: &Ctx, g: &super::ctx::GlobalArgs, args: &ScanArgs) -> CommandResult {
    let options = ScanOptions { window: args.window, timeout: ctx.timeout };
    let outcome = |report: &scan::Scan| match report.interrupted {
        true => Err(crate::Error::Interrupted),
        false => Ok(()),
    };
    let run = |uri: &str, bus: &mut dyn Bus, progress: &mut dyn crate::ops::Progress| {
        let report = scan::scan_against(bus, &options, &scan_cache::last_seen(Some(uri)), progress)?;
        scan_cache::remember(uri, &report, &options, &ctx.dicts);
        Ok(report)
    };
    super::ctx::on_each_bus(ctx, g, "canctl scan", run, outcome)
}
