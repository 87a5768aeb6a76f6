//! `canctl nmt`: network management commands and state queries.

use super::ctx::{parse_node, Ctx};
use crate::bus::{Bus, ALL_NODES};
use crate::canopen::nmt::Command;
use crate::ops::nmt::{self, ResetOptions, StateOptions};
use crate::output::CommandResult;
use clap::{Args, Subcommand};
use clap_complete::engine::ArgValueCandidates;
use std::time::Duration;

#[derive(Subcommand, Debug)]
pub(crate) enum NmtCommand {
    /// Put a node (or all) in Operational
    #[command(after_help = "Examples:\n  canctl --bus sim nmt start 5\n  canctl --bus sim nmt start all")]
    Start(Target),
    /// Put a node (or all) in Stopped
    #[command(after_help = "Examples:\n  canctl --bus sim nmt stop 5\n  canctl --bus sim nmt stop all")]
    Stop(Target),
    /// Put a node (or all) in Pre-operational
    #[command(after_help = "Examples:\n  canctl --bus sim nmt preop 5\n  canctl --bus sim nmt preop all")]
    Preop(Target),
    /// Reset a node's application (or all nodes') and wait for the boot-up
    #[command(after_help = "Examples:\n  canctl --bus sim nmt reset 5\n  canctl --bus sim nmt reset all --wait 5s")]
    Reset(ResetArgs),
    /// Reset a node's communication (or all nodes') and wait for the boot-up
    #[command(after_help = "Examples:\n  canctl --bus sim nmt reset-comm 10\n  canctl --bus sim nmt reset-comm all")]
    ResetComm(ResetArgs),
    /// Report a node's NMT state, from its heartbeat or by node guarding
    #[command(after_help = "Listens for the node's heartbeat first; a node that sends none is asked with one
node-guarding request (RTR on 0x700+node), which toggles its guarding bit.

Examples:
  canctl --bus sim nmt state 5
  canctl --bus sim nmt state 32 --format json")]
    State(StateArgs),
}

#[derive(Args, Debug)]
pub(crate) struct Target {
    /// Node-id 1 to 127, or `all` to broadcast to every node
    #[arg(value_parser = parse_target, value_name = "NODE|all", add = ArgValueCandidates::new(super::complete::nodes_or_all))]
    pub target: u8,
}

#[derive(Args, Debug)]
pub(crate) struct ResetArgs {
    #[command(flatten)]
    pub target: Target,
    /// How long to wait for boot-up messages
    #[arg(long, value_name = "DUR", default_value = "2s", value_parser = super::ctx::parse_duration)]
    pub wait: Duration,
}

#[derive(Args, Debug)]
pub(crate) struct StateArgs {
    #[command(flatten)]
    pub node: super::ctx::Node,
    /// How long to listen for a heartbeat before asking by node guarding
    #[arg(long, value_name = "DUR", default_value = "300ms", value_parser = super::ctx::parse_duration)]
    pub listen: Duration,
}

fn parse_target(s: &str) -> Result<u8, String> {
    if s.eq_ignore_ascii_case("all") {
        return Ok(ALL_NODES);
    }
    parse_node(s).map_err(|e| format!("{e}, or all"))
}

pub(crate) fn run(ctx: &Ctx, bus: &mut dyn Bus, cmd: &NmtCommand) -> CommandResult {
    ctx.stoppable(bus, |bus| run_stoppable(ctx, bus, cmd))
}

fn run_stoppable(ctx: &Ctx, bus: &mut dyn Bus, cmd: &NmtCommand) -> CommandResult {
    let reset = |a: &ResetArgs| (a.target.target, ResetOptions { wait: a.wait, timeout: ctx.timeout });
    let send = |bus: &mut dyn Bus, command: Command, target: u8| -> CommandResult {
        match nmt::send(bus, command, target) {
            Ok(sent) => Ok(ctx.out.report(&sent)?),
            Err(e) => crate::output::stopped::nmt_not_sent(&ctx.out, command.name(), target, e),
        }
    };
    match cmd {
        NmtCommand::Start(t) => send(bus, Command::Start, t.target),
        NmtCommand::Stop(t) => send(bus, Command::Stop, t.target),
        NmtCommand::Preop(t) => send(bus, Command::PreOperational, t.target),
        NmtCommand::Reset(a) | NmtCommand::ResetComm(a) => {
            let command =
                if matches!(cmd, NmtCommand::Reset(_)) { Command::ResetNode } else { Command::ResetCommunication };
            let (target, o) = reset(a);
            let report = match nmt::reset(bus, command, target, &o) {
                Ok(report) => report,
                Err(e) => return crate::output::stopped::nmt_not_sent(&ctx.out, command.name(), target, e),
            };
            ctx.report_then(&report, report.interrupted)
        }
        NmtCommand::State(a) => {
            let o = StateOptions { listen: a.listen, timeout: ctx.timeout };
            let what = format!("learning the NMT state of node {}", a.node.node);
            let state = crate::output::stopped::read(&ctx.out, "nmt state", what, nmt::state(bus, a.node.node, &o))?;
            Ok(ctx.out.report(&state)?)
        }
    }
}
