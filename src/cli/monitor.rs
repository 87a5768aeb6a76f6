//! `canctl monitor`: the bus's traffic as it happens, decoded.

use super::ctx::{parse_node, Ctx};
use crate::bus::Bus;
use crate::ops::monitor::Monitor;
use crate::output::CommandResult;
use clap::Args;
use clap_complete::engine::ArgValueCandidates;
use std::time::Duration;

/// Watch the bus: every frame decoded, as it happens
///
/// NMT commands, boot-ups, heartbeats and node guarding with state names, EMCY with the
/// meaning of the code and the error register bits, SDO requests, answers and aborts, SYNC,
/// LSS, and PDOs — decoded into fields when an EDS or DCF (--eds) gives their mapping. A
/// summary ends it: frames per COB-ID, nodes seen, EMCYs. --duration or --count end it
/// with exit 0; Ctrl-C or SIGTERM with the summary marked interrupted, and exit 130.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus can0 monitor
  canctl --bus can0 monitor --node 5 --node 10 --duration 10s --format json > bus.jsonl
  canctl --bus vcan0 --eds 5=mh.dcf monitor --node 5")]
pub(crate) struct MonitorArgs {
    /// Only frames of this node (repeatable); NMT, SYNC and LSS are always shown
    #[arg(long, value_parser = parse_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: Vec<u8>,
    /// Stop after this long
    #[arg(long, value_name = "DUR", value_parser = super::ctx::parse_duration)]
    pub duration: Option<Duration>,
    /// Stop after this many frames
    #[arg(long, value_name = "N")]
    pub count: Option<u64>,
}

/// Ctrl-C or SIGTERM ends the monitor as its duration would, with the summary; the exit
/// code is 130 all the same (as for every command the user stops), 0 only when --duration
/// or --count ended it.
pub(crate) fn run(ctx: &Ctx, bus: &mut dyn Bus, a: &MonitorArgs) -> CommandResult {
    ctx.stoppable(bus, |bus| {
        let mut monitor = Monitor::new(bus, ctx.dicts.pdo_layouts(&a.node), &a.node, a.duration, a.count)?;
        ctx.out.stream(|| monitor.next(bus))?;
        let summary = monitor.summary();
        ctx.out.summary(&mut std::io::stdout().lock(), &summary)?;
        if summary.interrupted {
            return Err(crate::Error::Interrupted.into());
        }
        Ok(())
    })
}
