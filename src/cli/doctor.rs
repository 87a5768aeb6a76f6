//! `canctl doctor`: why a node, or the bus, is silent.

use super::ctx::{parse_node, Ctx, GlobalArgs};
use crate::error::Error;
use crate::ops::doctor::{self, DoctorOptions};
use crate::output::CommandResult;
use clap::Args;
use clap_complete::engine::ArgValueCandidates;
use std::time::Duration;

/// Say why a node or the bus is silent: ranked causes, the frames that show each, the fix
///
/// Listens to the bus for --window (heartbeats, boot-ups, any traffic); then, given NODE,
/// reads its vendor-ID 0x1018:1 by SDO (2 requests, each waiting --timeout), asks its state
/// by node guarding when no heartbeat said it (one remote request, --timeout), and, when it
/// is silent, reads 0x1000 of every node-id at once (one --timeout) to find the device the
/// last scan saw on NODE on another id; when it answers, reads its serial number twice to
/// tell two devices on one id apart. Without NODE: the listen and the read of every node-id.
/// Through an EPOS2, which shows no traffic, nothing is listened to and the ids are read
/// one after the other (up to 127 --timeout).
/// Failures of the link (interface down, no permission, transmit queue full, bus-off, an
/// adapter's bus errors) are findings too. Doctor only reads and listens: it writes nothing
/// to any device and sends no NMT or LSS command, except with --lss the one LSS inquiry
/// for devices without a node-id (a broadcast, answered only by those). Exit 0 when nothing is wrong, 6 when it
/// found a problem (the findings say which, most likely first).
/// With --sweep, an slcan adapter then listens, listen-only (sending and acknowledging
/// nothing), at each CiA 301 bit rate (1M 800k 500k 250k 125k 50k 20k 10k) for
/// --sweep-window each, and names the rate the bus's traffic decodes at; a CAN interface is
/// not reconfigured: doctor prints the ip link commands to try the rates by hand.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim doctor 5
  canctl --bus can0 doctor
  canctl --bus can0 doctor 7 --window 3s --format json
  canctl --bus can0 doctor 7 --lss
  canctl --bus slcan:/dev/ttyACM0@250k doctor --sweep")]
pub struct DoctorArgs {
    /// The node to examine, 1 to 127 (without it: the bus only)
    #[arg(value_parser = parse_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: Option<u8>,
    /// How long to listen to the bus first (a heartbeat slower than this may be missed)
    #[arg(long, value_name = "DUR", default_value = "1s", value_parser = super::ctx::parse_duration)]
    pub window: Duration,
    /// Also ask for devices waiting without a node-id: one LSS "identify non-configured
    /// remote slave" broadcast (CiA 305), answers waited for --timeout
    #[arg(long)]
    pub lss: bool,
    /// Find the bus's bit rate: listen-only at each CiA 301 rate (slcan adapters; 8 windows)
    // Only when asked, never on its own after bit errors: it takes the adapter off the bus
    // for seconds, which on a running machine is the user's call.
    #[arg(long)]
    pub sweep: bool,
    /// How long the sweep listens at each rate (a bus quieter than this shows nothing)
    #[arg(long, value_name = "DUR", default_value = "500ms", value_parser = super::ctx::parse_duration)]
    pub sweep_window: Duration,
    #[command(flatten)]
    pub checks: super::ctx::CheckFormat,
}

/// Run `canctl doctor`: the diagnosis rendered, exit 6 when it found a problem.
pub fn run(ctx: &Ctx, global: &GlobalArgs, a: &DoctorArgs) -> CommandResult {
    let last_scan = ctx.bus.as_deref().map(crate::ops::scan_cache::load).unwrap_or_default();
    // Scan's rule: a shorter listen hears nothing, and would not say so.
    crate::ops::scan::check_window(a.window)?;
    crate::ops::scan::check_window(a.sweep_window)?;
    let options = DoctorOptions { node: a.node, listen: a.window, timeout: ctx.timeout, last_scan, lss: a.lss };
    let mut opened = false;
    let result = super::ctx::with_bus(ctx, global, |bus| {
        opened = true;
        let sweep = a.sweep.then_some(a.sweep_window);
        let working = ctx.out.working(&crate::output::doctor::working(a.node));
        let diagnosed = ctx.stoppable(bus, |bus| doctor::doctor_swept(bus, &options, ctx.bus.as_deref(), sweep));
        working.finish_and_clear();
        let report = crate::output::stopped::read(&ctx.out, "doctor", "listening and asking".into(), diagnosed)?;
        ctx.out.report(&report)?;
        Ok(report.outcome()?)
    });
    // A link that cannot be opened is a diagnosis of its own (an interface down, no
    // permission), not only an error.
    match result {
        Err(e) if !opened => match e.library().map(Error::root) {
            Some(Error::Link(link)) => {
                let report = doctor::unopened(ctx.bus.as_deref().unwrap_or_default(), a.node, link);
                ctx.out.report(&report)?;
                Ok(report.outcome()?)
            }
            _ => Err(e),
        },
        result => result,
    }
}
