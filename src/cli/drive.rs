//! `canctl drive`: CiA 402 drives' state, and their power state changed with the
//! controlword.

use super::ctx::Ctx;
use crate::bus::Bus;
use crate::canopen::cia402::Goal;
use crate::error::Error;
use crate::ops::drive::{self, Options, Watch};
use crate::output::CommandResult;
use clap::{Args, Subcommand};
use std::time::Duration;

#[derive(Subcommand, Debug)]
pub(crate) enum DriveCommand {
    /// The CiA 402 state, every statusword flag, the mode of operation and the errors
    #[command(after_help = "Reads 0x1000 (refused unless the device type says profile 402), the statusword
0x6041, the mode of operation 0x6061, the error register 0x1001 and the error history
0x1003. --watch then prints each change of the statusword until Ctrl-C (exit 130): from
the TPDO that carries it when one is mapped and the node is operational, by SDO otherwise.

Examples:
  canctl --bus sim drive status 1
  canctl --bus sim drive status 32 --format json
  canctl --bus can0 drive status 1 --watch")]
    Status(StatusArgs),
    /// Walk the drive to Operation enabled (shutdown, switch on, enable operation)
    #[command(after_help = "Each transition is confirmed in the statusword before the next; the report says
where the drive stopped and why (fault present, voltage missing, transition refused).
Power state only: no target is set and nothing is told to move.

Examples:
  canctl --bus sim drive enable 1
  canctl --bus can0 drive enable 1 --wait 5s")]
    Enable(WalkArgs),
    /// Walk the drive to Switch on disabled (disable voltage): the power stage off
    #[command(after_help = "Examples:\n  canctl --bus sim drive disable 1")]
    Disable(WalkArgs),
    /// Quick stop: from Operation enabled to Quick stop active (elsewhere to Switch on disabled)
    #[command(after_help = "Examples:\n  canctl --bus sim drive quick-stop 1")]
    QuickStop(WalkArgs),
    /// Reset a fault (controlword bit 7 rising edge): Fault to Switch on disabled
    #[command(after_help = "The drive leaves Fault only once the fault's cause is gone; canctl drive status
shows the error register and the logged errors.

Examples:
  canctl --bus sim drive fault-reset 1")]
    FaultReset(WalkArgs),
}

#[derive(Args, Debug)]
pub(crate) struct StatusArgs {
    #[command(flatten)]
    pub node: super::ctx::SdoNode,
    /// Print each change of the statusword until interrupted
    #[arg(long)]
    pub watch: bool,
    /// With --watch by SDO: how often to read the statusword
    #[arg(long, value_name = "DUR", default_value = "100ms", value_parser = super::ctx::parse_duration)]
    pub interval: Duration,
}

#[derive(Args, Debug)]
pub(crate) struct WalkArgs {
    #[command(flatten)]
    pub node: super::ctx::SdoNode,
    /// How long each transition may take to show in the statusword
    #[arg(long, value_name = "DUR", default_value = "2s", value_parser = super::ctx::parse_duration)]
    pub wait: Duration,
}

pub(crate) fn run(ctx: &Ctx, bus: &mut dyn Bus, cmd: &DriveCommand) -> CommandResult {
    let (args, goal) = match cmd {
        DriveCommand::Status(a) => return status(ctx, bus, a),
        DriveCommand::Enable(a) => (a, Goal::Enable),
        DriveCommand::Disable(a) => (a, Goal::Disable),
        DriveCommand::QuickStop(a) => (a, Goal::QuickStop),
        DriveCommand::FaultReset(a) => (a, Goal::FaultReset),
    };
    let o = Options { timeout: ctx.timeout, wait: args.wait };
    let walk = drive::walk(bus, args.node.node, goal, &o, &ctx.cancel)?;
    ctx.out.report(&walk)?;
    Ok(walk.outcome()?)
}

fn status(ctx: &Ctx, bus: &mut dyn Bus, a: &StatusArgs) -> CommandResult {
    let what = format!("reading node {}'s state", a.node.node);
    let report = ctx.read(bus, "drive status", what, |bus| drive::status(bus, a.node.node, ctx.timeout))?;
    ctx.out.report(&report)?;
    if !a.watch {
        return Ok(());
    }
    let mut watch = Watch::new(bus, a.node.node, a.interval, ctx.timeout)?;
    ctx.out.note(&crate::output::watching_text(a.node.node, watch.source()));
    if let Some(last) = ctx.out.stream(|| watch.next_until(bus, &ctx.cancel))? {
        ctx.out.note(&crate::output::last_seen_text(a.node.node, &last));
    }
    Err(Error::Interrupted.into())
}
