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
    let (nodes, how) = match reset_and_wait(ctx, bus, cmd, target, a.wait)? {
        Reset::Confirmed(nodes, how) => (nodes, how),
        Reset::Unconfirmed(why) => {
            let msg = format!("NMT {} sent to {}; not confirmed: {why}", cmd.name(), target_text(target));
            return match ctx.out.format {
                Format::Json => Ok(ctx.out.json(&json!({
                    "command": cmd.name(), "target": target_json(target), "sent": true, "confirmed": false,
                    "booted": null, "why": why
                }))?),
                _ => Ok(ctx.out.print(&msg)?),
            };
        }
    };
    let state = nmt::State::PreOperational;
    match ctx.out.format {
        Format::Json => ctx.out.json(&json!({
            "command": cmd.name(), "target": target_json(target), "sent": true, "confirmed": true, "booted": nodes,
            "state": state.name(), "seen_by": how
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

/// What is known after a reset was sent.
pub(super) enum Reset {
    /// These nodes are back, and how that was seen.
    Confirmed(Vec<u8>, String),
    /// The reset went out but nothing showed that it took effect; why not.
    Unconfirmed(String),
}

/// Send a reset and wait until the target is back. A link that shows the bus's traffic
/// sees boot-up messages; through an EPOS2 only the node's answers to remote requests
/// show anything, and only a boot-up answer or a change of state proves a reset.
pub(super) fn reset_and_wait(
    ctx: &Ctx,
    bus: &mut dyn Bus,
    cmd: Command,
    target: u8,
    wait: Duration,
) -> anyhow::Result<Reset> {
    if bus.sees_traffic() {
        bus.nmt(cmd, target)?;
        let nodes = listen_for_boot_ups(ctx, bus, target, wait)?;
        return Ok(Reset::Confirmed(nodes, "boot-up message".into()));
    }
    let no_traffic = format!("{} passes on no boot-up messages", bus.describe());
    if target == ALL_NODES {
        bus.nmt(cmd, target)?;
        return Ok(Reset::Unconfirmed(format!("{no_traffic}; check the nodes with `canctl scan`")));
    }
    let before = match remote_state(ctx, bus, target) {
        Ok(answer) => answer,
        Err(e) if e.is_timeout() => None,
        Err(e) => return Err(e.into()),
    };
    bus.nmt(cmd, target)?;
    let after = poll_until_answering(ctx, bus, target, wait)?;
    Ok(match (before, after) {
        (_, ErrorControl::BootUp) => {
            Reset::Confirmed(vec![target], "its boot-up, as the answer to a remote request".into())
        }
        (
            Some(ErrorControl::State { state: was, .. }),
            ErrorControl::State { state: nmt::State::PreOperational, .. },
        ) if was != nmt::State::PreOperational => {
            Reset::Confirmed(vec![target], format!("its state: {was} before, pre-operational after (remote requests)"))
        }
        (_, ErrorControl::State { state, .. }) => Reset::Unconfirmed(format!(
            "node {target} answers and is {state}, as before; {no_traffic}, so a reset cannot be told from none. \
             To see one, put the node in another state first (`canctl nmt stop {target}`)"
        )),
        (_, ErrorControl::Unknown(code)) => Reset::Unconfirmed(format!(
            "node {target} answers with state code 0x{code:02X}, which CiA 301 does not define; {no_traffic}"
        )),
    })
}

/// The node's answer to one error-control remote request; `None` for an answer that is
/// no error-control message.
fn remote_state(ctx: &Ctx, bus: &mut dyn Bus, node: u8) -> crate::Result<Option<ErrorControl>> {
    let f = bus.request_frame(nmt::error_control_cob(node), 1, ctx.timeout)?;
    Ok(ErrorControl::parse(&f).map(|(_, ec)| ec))
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
/// error-control remote request again; its answer.
fn poll_until_answering(ctx: &Ctx, bus: &mut dyn Bus, node: u8, wait: Duration) -> anyhow::Result<ErrorControl> {
    let deadline = Instant::now() + wait;
    loop {
        match remote_state(ctx, bus, node) {
            Ok(Some(answer)) => return Ok(answer),
            Err(e) if !e.is_timeout() => return Err(e.into()),
            Ok(None) | Err(_) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(20)),
            Ok(None) | Err(_) => {
                return Err(Error::Timeout(format!(
                    "node {node}: NMT reset sent, but no answer to remote requests within {} ms after it; \
                     not confirmed. Check the node with `canctl scan`, or wait longer (--wait)",
                    wait.as_millis()
                ))
                .into())
            }
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
        Err(e) if e.is_timeout() => None,
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
