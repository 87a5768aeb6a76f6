//! `canctl nmt`: network management commands and state queries.

use super::{parse_node, Ctx};
use crate::bus::{Bus, ALL_NODES};
use crate::canopen::nmt::Command;
use crate::ops::nmt::{self, target_text, NodeState, ResetOptions, Sent, StateOptions};
use crate::output::{Human, Report};
use clap::{Args, Subcommand};
use clap_complete::engine::ArgValueCandidates;
use std::time::Duration;

#[derive(Subcommand, Debug)]
pub enum NmtCommand {
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
pub struct Target {
    /// Node-id 1 to 127, or `all` to broadcast to every node
    #[arg(value_parser = parse_target, value_name = "NODE|all", add = ArgValueCandidates::new(super::complete::nodes_or_all))]
    pub target: u8,
}

#[derive(Args, Debug)]
pub struct ResetArgs {
    #[command(flatten)]
    pub target: Target,
    /// How long to wait for boot-up messages
    #[arg(long, value_name = "DUR", default_value = "2s", value_parser = super::parse_duration)]
    pub wait: Duration,
}

#[derive(Args, Debug)]
pub struct StateArgs {
    /// Node-id, 1 to 127
    #[arg(value_parser = parse_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: u8,
    /// How long to listen for a heartbeat before asking by node guarding
    #[arg(long, value_name = "DUR", default_value = "300ms", value_parser = super::parse_duration)]
    pub listen: Duration,
}

fn parse_target(s: &str) -> Result<u8, String> {
    if s.eq_ignore_ascii_case("all") {
        return Ok(ALL_NODES);
    }
    parse_node(s).map_err(|e| format!("{e}, or all"))
}

pub fn run(ctx: &Ctx, bus: &mut dyn Bus, cmd: &NmtCommand) -> anyhow::Result<()> {
    let reset = |a: &ResetArgs| (a.target.target, ResetOptions { wait: a.wait, timeout: ctx.timeout });
    match cmd {
        NmtCommand::Start(t) => ctx.out.report(&nmt::send(bus, Command::Start, t.target)?)?,
        NmtCommand::Stop(t) => ctx.out.report(&nmt::send(bus, Command::Stop, t.target)?)?,
        NmtCommand::Preop(t) => ctx.out.report(&nmt::send(bus, Command::PreOperational, t.target)?)?,
        NmtCommand::Reset(a) => {
            let (target, o) = reset(a);
            ctx.out.report(&nmt::reset(bus, Command::ResetNode, target, &o)?)?
        }
        NmtCommand::ResetComm(a) => {
            let (target, o) = reset(a);
            ctx.out.report(&nmt::reset(bus, Command::ResetCommunication, target, &o)?)?
        }
        NmtCommand::State(a) => {
            let o = StateOptions { listen: a.listen, timeout: ctx.timeout };
            ctx.out.report(&nmt::state(bus, a.node, &o)?)?
        }
    }
    Ok(())
}

impl Report for Sent {
    fn human(&self) -> Human {
        Human::Line(format!("NMT {} sent to {}", self.command.name(), target_text(self.target)))
    }

    fn csv(&self) -> Human {
        // The target as in JSON: 5, or "all" with its quotes.
        let target = if self.target == ALL_NODES { "\"all\"".into() } else { self.target.to_string() };
        let rows = vec![vec![self.command.name().into(), target, "true".into()]];
        Human::Table { headers: vec!["command", "target", "sent"], rows, when_empty: true }
    }
}

impl Report for nmt::Reset {
    fn human(&self) -> Human {
        let (command, target) = (self.command.name(), target_text(self.target));
        Human::Line(match (&self.booted, &self.why) {
            (Some(nodes), _) => {
                let list: Vec<String> = nodes.iter().map(|n| n.to_string()).collect();
                let (state, how) = (self.state.map_or("", |s| s.name()), self.seen_by.as_deref().unwrap_or(""));
                format!("booted after NMT {command}: node {} (now {state}; seen by {how})", list.join(", "))
            }
            (None, why) => format!("NMT {command} sent to {target}; not confirmed: {}", why.as_deref().unwrap_or("")),
        })
    }

    fn csv(&self) -> Human {
        let Some(nodes) = &self.booted else { return self.human() };
        let state = self.state.map_or("", |s| s.name());
        let rows = nodes.iter().map(|n| vec![n.to_string(), state.into()]).collect();
        Human::Table { headers: vec!["node", "state"], rows, when_empty: true }
    }
}

impl Report for NodeState {
    fn human(&self) -> Human {
        Human::Line(format!("node {}: {} (from {})", self.node, self.state, self.source))
    }

    fn csv(&self) -> Human {
        let rows = vec![vec![self.node.to_string(), self.state.name().into(), self.source.into()]];
        Human::Table { headers: vec!["node", "state", "source"], rows, when_empty: true }
    }
}
