//! `canctl errors`: a node's error history (0x1003) with each code's meaning.

use super::ctx::Ctx;
use crate::bus::Bus;
use crate::ops::errors;
use crate::output::CommandResult;
use clap::Args;

/// Show a node's logged errors (0x1003), newest first, with their meanings
///
/// Reads the pre-defined error field 0x1003 (sub 0: how many, sub 1: the newest) and the
/// error register 0x1001. Each entry is split into its error code (low 16 bits) and the
/// manufacturer-specific part (high 16 bits), and named: from the device's own manual
/// where canctl knows it (the Temposonics MH sensor, ICP DAS CAN-2000C modules), from
/// CiA 402 for drives, else by its CiA 301 class. --clear then deletes the history (writes
/// 0 to 0x1003:0) and confirms it by reading it back.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim errors 10
  canctl --bus sim errors 10 --clear
  canctl --bus can0 errors 1 --format json")]
pub(crate) struct ErrorsArgs {
    #[command(flatten)]
    pub node: super::ctx::Node,
    /// Then delete the history (0 to 0x1003:0) and confirm it reads back empty
    #[arg(long)]
    pub clear: bool,
}

pub(crate) fn run(ctx: &Ctx, bus: &mut dyn Bus, a: &ErrorsArgs) -> CommandResult {
    let what = format!("reading node {}'s error history", a.node.node);
    let report = ctx.read(bus, "errors", what, |bus| errors::errors(bus, a.node.node, a.clear, ctx.timeout))?;
    ctx.report_then(&report, report.clear_interrupted.is_some())
}
