//! `canctl nmt`: network management commands and state queries.

use super::{parse_node, Ctx};
use crate::bus::{Bus, ALL_NODES};
use crate::canopen::nmt::{self, Command, ErrorControl};
use crate::error::Error;
use crate::output::Format;
use clap::{Args, Subcommand};
use clap_complete::engine::ArgValueCandidates;
use serde_json::json;
use std::collections::BTreeSet;
use std::time::{Duration, Instant};

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
    /// Node-id 1..127, or `all` to broadcast to every node
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
    /// Node-id, 1..127
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

fn target_json(t: u8) -> serde_json::Value {
    if t == ALL_NODES {
        json!("all")
    } else {
        json!(t)
    }
}

fn target_text(t: u8) -> String {
    if t == ALL_NODES {
        "all nodes".into()
    } else {
        format!("node {t}")
    }
}

pub fn run(ctx: &Ctx, bus: &mut dyn Bus, cmd: &NmtCommand) -> anyhow::Result<()> {
    match cmd {
        NmtCommand::Start(t) => send(ctx, bus, Command::Start, t.target),
        NmtCommand::Stop(t) => send(ctx, bus, Command::Stop, t.target),
        NmtCommand::Preop(t) => send(ctx, bus, Command::PreOperational, t.target),
        NmtCommand::Reset(a) => reset(ctx, bus, Command::ResetNode, a),
        NmtCommand::ResetComm(a) => reset(ctx, bus, Command::ResetCommunication, a),
        NmtCommand::State(a) => state(ctx, bus, a),
    }
}

/// NMT commands are unconfirmed: say that it was sent, not that it took effect.
fn send(ctx: &Ctx, bus: &mut dyn Bus, cmd: Command, target: u8) -> anyhow::Result<()> {
    bus.nmt(cmd, target)?;
    match ctx.out.format {
        Format::Json => ctx.out.json(&json!({ "command": cmd.name(), "target": target_json(target), "sent": true }))?,
        Format::Csv => ctx.out.table(
            &["command", "target", "sent"],
            &[vec![cmd.name().into(), target_json(target).to_string(), "true".into()]],
        )?,
        Format::Human => ctx.out.print(&format!("NMT {} sent to {}", cmd.name(), target_text(target)))?,
    }
    Ok(())
}

fn reset(ctx: &Ctx, bus: &mut dyn Bus, cmd: Command, a: &ResetArgs) -> anyhow::Result<()> {
    let target = a.target.target;
    let Some((nodes, how)) = reset_and_wait(ctx, bus, cmd, target, a.wait)? else {
        // Without the bus's traffic there is no telling which nodes exist and rebooted.
        let msg = format!(
            "NMT {} sent to all nodes; {} shows no boot-up messages, so check the nodes with `canctl scan`",
            cmd.name(),
            bus.describe()
        );
        return match ctx.out.format {
            Format::Json => {
                Ok(ctx.out.json(&json!({ "command": cmd.name(), "target": "all", "sent": true, "booted": null }))?)
            }
            _ => Ok(ctx.out.print(&msg)?),
        };
    };
    let state = nmt::State::PreOperational;
    match ctx.out.format {
        Format::Json => ctx.out.json(&json!({
            "command": cmd.name(), "target": target_json(target), "booted": nodes, "state": state.name(), "seen_by": how
        }))?,
        Format::Csv => ctx.out.table(
            &["node", "state"],
            &nodes.iter().map(|n| vec![n.to_string(), state.name().into()]).collect::<Vec<_>>(),
        )?,
        Format::Human => {
            let list: Vec<String> = nodes.iter().map(|n| n.to_string()).collect();
            ctx.out.print(&format!(
                "booted after NMT {}: node {} (now {state}; seen by {how})",
                cmd.name(),
                list.join(", ")
            ))?
        }
    }
    Ok(())
}

/// Send a reset and wait until the target is back: the nodes that booted, and how that was
/// seen; `None` for all nodes on a link that shows no traffic (nothing to wait for).
pub(super) fn reset_and_wait(
    ctx: &Ctx,
    bus: &mut dyn Bus,
    cmd: Command,
    target: u8,
    wait: Duration,
) -> anyhow::Result<Option<(Vec<u8>, &'static str)>> {
    bus.nmt(cmd, target)?;
    Ok(if bus.sees_traffic() {
        Some((listen_for_boot_ups(ctx, bus, target, wait)?, "boot-up message"))
    } else if target == ALL_NODES {
        None
    } else {
        poll_until_answering(ctx, bus, target, wait)?;
        Some((vec![target], "answer to a remote request"))
    })
}

/// Boot-up messages after a reset. One node: done at its boot-up. All: boot-ups may come
/// from any node at any time, so listen until a --timeout passes with no new one.
fn listen_for_boot_ups(ctx: &Ctx, bus: &mut dyn Bus, target: u8, wait: Duration) -> anyhow::Result<Vec<u8>> {
    let deadline = Instant::now() + wait;
    let mut booted = BTreeSet::new();
    let mut quiet_until = deadline;
    while let Some(f) = bus.recv_frame(quiet_until.min(deadline))? {
        if let Some((node, ErrorControl::BootUp)) = ErrorControl::parse(&f) {
            if target == ALL_NODES {
                booted.insert(node);
                quiet_until = Instant::now() + ctx.timeout;
            } else if node == target {
                booted.insert(node);
                break;
            }
        }
    }
    if booted.is_empty() {
        return Err(
            Error::Timeout(format!("{}: no boot-up within {} ms", target_text(target), wait.as_millis())).into()
        );
    }
    Ok(booted.into_iter().collect())
}

/// Through a link that shows no traffic, a reset node is back when it answers the
/// error-control remote request again.
fn poll_until_answering(ctx: &Ctx, bus: &mut dyn Bus, node: u8, wait: Duration) -> anyhow::Result<()> {
    let deadline = Instant::now() + wait;
    loop {
        match bus.request_frame(nmt::error_control_cob(node), 1, ctx.timeout) {
            Ok(f) if ErrorControl::parse(&f).is_some() => return Ok(()),
            Ok(_) | Err(Error::Timeout(_)) if Instant::now() < deadline => {
                std::thread::sleep(Duration::from_millis(20))
            }
            Ok(_) | Err(Error::Timeout(_)) => {
                return Err(Error::Timeout(format!(
                    "node {node}: no answer within {} ms after the reset",
                    wait.as_millis()
                ))
                .into())
            }
            Err(e) => return Err(e.into()),
        }
    }
}

/// A node's NMT state: from its heartbeat (listened for `listen`), else by node guarding.
pub(super) fn query_state(
    ctx: &Ctx,
    bus: &mut dyn Bus,
    node: u8,
    listen: Duration,
) -> crate::Result<(nmt::State, &'static str)> {
    if bus.sees_traffic() {
        let listen_end = Instant::now() + listen;
        while let Some(f) = bus.recv_frame(listen_end)? {
            if let Some((n, ErrorControl::State { state, .. })) = ErrorControl::parse(&f) {
                if n == node {
                    return Ok((state, "heartbeat"));
                }
            }
        }
    }
    // Node guarding; through an EPOS2 this is RequestCANFrame, whose answer may also be
    // the node's next heartbeat (same COB-ID).
    let source = if bus.sees_traffic() { "node guarding" } else { "remote request through the EPOS2" };
    let answer = match bus.request_frame(nmt::error_control_cob(node), 1, ctx.timeout) {
        Err(Error::Timeout(_)) => None,
        other => Some(other?),
    };
    match answer.as_ref().and_then(ErrorControl::parse) {
        Some((_, ErrorControl::State { state, .. })) => Ok((state, source)),
        Some((_, ErrorControl::BootUp)) => Ok((nmt::State::PreOperational, source)),
        _ => {
            let listened = if bus.sees_traffic() {
                format!("no heartbeat within {} ms and ", listen.as_millis())
            } else {
                String::new()
            };
            Err(Error::Timeout(format!(
                "node {node}: {listened}no answer to node guarding within {} ms",
                ctx.timeout.as_millis()
            )))
        }
    }
}

fn state(ctx: &Ctx, bus: &mut dyn Bus, a: &StateArgs) -> anyhow::Result<()> {
    let node = a.node;
    let (state, source) = query_state(ctx, bus, node, a.listen)?;
    match ctx.out.format {
        Format::Json => ctx.out.json(&json!({ "node": node, "state": state.name(), "source": source }))?,
        Format::Csv => ctx
            .out
            .table(&["node", "state", "source"], &[vec![node.to_string(), state.name().into(), source.into()]])?,
        Format::Human => ctx.out.print(&format!("node {node}: {state} (from {source})"))?,
    }
    Ok(())
}
