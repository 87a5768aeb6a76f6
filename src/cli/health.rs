//! `canctl health`: every node of the bus, healthy or not, for people and for CI.

use super::ctx::Ctx;
use crate::bus::Bus;
use crate::canopen::nmt::State;
use crate::ops::health::{self, HealthOptions};
use crate::output::CommandResult;
use clap::Args;
use std::time::Duration;

/// Check every node on the bus; exit 6 when any is not healthy
///
/// Scans the bus (as `scan` does), then for each node: its NMT state (heartbeat, else node
/// guarding), its error register 0x1001 (must be 0), how many errors it logged in 0x1003
/// (shown; `canctl errors NODE` names them), and for CiA 402 drives (0x1000) the state
/// the statusword 0x6041 codes (must not be Fault). Then it watches the bus: every node
/// whose 0x1017 says it produces heartbeats must beat on time (no gap longer than 1.5
/// periods + 50 ms), and no node may send an EMCY with an error. A node silent to SDO gets
/// its likely cause as `canctl doctor` names it (stopped, SDO server elsewhere, silent),
/// from what the scan and the watch saw: no request of its own, no time added
/// (--no-diagnose leaves it out). --format junit writes one JUnit test case per node and
/// check, for CI systems.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim health
  canctl --bus can0 health --state operational --format junit > health.xml
  canctl --bus can0 health --watch 5s --format json")]
pub(crate) struct HealthArgs {
    /// Every node must also be in this NMT state: operational, pre-operational or stopped
    #[arg(long, value_name = "STATE", value_parser = super::ctx::parse_state)]
    pub state: Option<State>,
    /// How long to watch heartbeats and EMCYs (default: two periods of the slowest
    /// heartbeat, 300ms to 10s)
    #[arg(long, value_name = "DUR", value_parser = super::ctx::parse_duration)]
    pub watch: Option<Duration>,
    /// How long the bus must stay quiet after the last answer to the scan's probes
    #[arg(long, value_name = "DUR", default_value = "100ms", value_parser = super::ctx::parse_duration)]
    pub window: Duration,
    #[command(flatten)]
    pub checks: super::ctx::CheckFormat,
}

pub(crate) fn run(ctx: &Ctx, bus: &mut dyn Bus, a: &HealthArgs) -> CommandResult {
    let last_seen = crate::ops::scan_cache::last_seen(ctx.bus.as_deref());
    let options = HealthOptions { window: a.window, timeout: ctx.timeout, watch: a.watch, state: a.state, last_seen };
    let what = "scanning and judging the nodes".to_string();
    let report = ctx.read(bus, "health", what, |bus| health::health(bus, &options, &mut ctx.out.progress()))?;
    let report = if ctx.diagnose { report } else { report.without_diagnoses() };
    ctx.out.report(&report)?;
    Ok(report.outcome()?)
}

/// `health` on several buses at once: one table, one JUnit suite per bus, the worst exit.
pub(crate) fn on_buses(ctx: &Ctx, g: &super::ctx::GlobalArgs, a: &HealthArgs) -> CommandResult {
    let run = |uri: &str, bus: &mut dyn Bus, progress: &mut dyn crate::ops::Progress| {
        let last_seen = crate::ops::scan_cache::last_seen(Some(uri));
        let options =
            HealthOptions { window: a.window, timeout: ctx.timeout, watch: a.watch, state: a.state, last_seen };
        health::health(bus, &options, progress)
    };
    super::ctx::on_each_bus(ctx, g, "canctl health", run, |report: &health::Health| report.outcome())
}
