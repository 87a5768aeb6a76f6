//! `canctl store` and `canctl restore`: CiA 301 objects 0x1010 and 0x1011.

use super::{parse_node, Ctx};
use crate::bus::Bus;
use crate::canopen::nmt::Command;
use crate::ops::nmt::{self, ResetOptions};
use crate::ops::store::{self, Timeouts};
use crate::ops::Stopped;
use crate::output::{sentence, Each, Report};
use clap::Args;
use clap_complete::engine::ArgValueCandidates;
use std::time::Duration;

pub use crate::ops::store::Class;

/// Save parameters to non-volatile memory (writes 'save' to 0x1010)
///
/// Reads 0x1010:0 and the sub-entry first, and says so when the device cannot store that
/// class on command. Several nodes (5,10,20) are done one after the other; interrupted,
/// the report says which were.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim store 5
  canctl --bus sim store 1,5,10
  canctl --bus can0 store 10 comm --store-timeout 10s")]
pub struct StoreArgs {
    /// Node-id, 1 to 127 (0: the EPOS2 on an epos2-rs232/epos2-usb bus), or several: 5,10,20
    #[arg(value_parser = |s: &str| node_list(s, super::parse_sdo_node), value_name = "NODE", add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: Nodes,
    #[arg(value_enum, default_value = "all")]
    pub class: Class,
    /// How long the device may take to store (flash writes take a while)
    #[arg(long, value_name = "DUR", default_value = "5s", value_parser = super::parse_duration)]
    pub store_timeout: Duration,
}

/// Bring back default parameters (writes 'load' to 0x1011)
///
/// The defaults apply from the next reset on; --reset does the reset and waits for the
/// node to boot. Several nodes (5,10,20) are done one after the other; interrupted, the
/// report says which were.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim restore 5 --reset
  canctl --bus sim restore 5,10 --reset
  canctl --bus can0 restore 10 app")]
pub struct RestoreArgs {
    /// Node-id, 1 to 127, or several: 5,10,20
    #[arg(value_parser = |s: &str| node_list(s, parse_node), value_name = "NODE", add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: Nodes,
    #[arg(value_enum, default_value = "all")]
    pub class: Class,
    /// Reset the node afterwards and wait for it to boot with the defaults
    #[arg(long)]
    pub reset: bool,
    /// How long the device may take to restore
    #[arg(long, value_name = "DUR", default_value = "5s", value_parser = super::parse_duration)]
    pub store_timeout: Duration,
}

/// One node-id or several, as one argument: `5` or `5,10,20`.
#[derive(Clone, Debug)]
pub struct Nodes(pub Vec<u8>);

fn node_list(s: &str, one: fn(&str) -> Result<u8, String>) -> Result<Nodes, String> {
    let nodes = s.split(',').map(one).collect::<Result<Vec<u8>, String>>()?;
    for (i, n) in nodes.iter().enumerate() {
        if nodes[..i].contains(n) {
            return Err(format!("node {n} is named twice"));
        }
    }
    Ok(Nodes(nodes))
}

/// How one node's turn ended, when not with its report.
enum Ended {
    /// The user stopped it: what was done on this node, what was not.
    Stopped(Stopped),
    Failed(anyhow::Error),
}

impl From<crate::Error> for Ended {
    fn from(e: crate::Error) -> Ended {
        Ended::Failed(e.into())
    }
}

/// Run `one` on each node in turn. One node: its report. Several: their reports together;
/// stopped part-way, which nodes were done and which were not; failed, the reports of
/// those done, then the error.
fn each_node<R: Report + serde::Serialize>(
    ctx: &Ctx,
    command: &str,
    nodes: &[u8],
    mut one: impl FnMut(u8) -> Result<R, Ended>,
) -> anyhow::Result<()> {
    let mut done: Vec<R> = Vec::new();
    for (i, &node) in nodes.iter().enumerate() {
        match one(node) {
            Ok(report) => done.push(report),
            Err(Ended::Stopped(mut report)) => {
                if nodes.len() > 1 {
                    let before = done.iter().filter_map(sentence);
                    report.done = before.chain(report.done).collect();
                    report.not_done.extend(nodes[i + 1..].iter().map(|n| format!("{command} on node {n}")));
                }
                ctx.out.report(&report)?;
                return Err(crate::Error::Interrupted.into());
            }
            Err(Ended::Failed(e)) => {
                if !done.is_empty() {
                    ctx.out.report(&Each(done))?;
                    ctx.out.note(&format!("{command} not done on node {}", list(&nodes[i..])));
                }
                return Err(e);
            }
        }
    }
    match done.len() {
        1 => ctx.out.report(&done[0])?,
        _ => ctx.out.report(&Each(done))?,
    }
    Ok(())
}

fn list(nodes: &[u8]) -> String {
    nodes.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(", ")
}

pub fn store(ctx: &Ctx, bus: &mut dyn Bus, a: &StoreArgs) -> anyhow::Result<()> {
    let t = Timeouts { answer: ctx.timeout, write: a.store_timeout };
    crate::ops::stop::stoppable(bus, &ctx.cancel, |bus| {
        each_node(ctx, "store", &a.node.0, |node| match store::store(bus, node, a.class, t) {
            Ok(report) => Ok(report),
            Err(e) if e.is_interrupted() => {
                let not_done = vec![format!("'save' to 0x1010:{} of node {node}", a.class as u8 + 1)];
                let state = format!("nothing was stored on node {node}: its non-volatile memory is as it was");
                Err(Ended::Stopped(Stopped::new("store", Vec::new(), not_done, state)))
            }
            Err(e) => Err(e.into()),
        })
    })
}

pub fn restore(ctx: &Ctx, bus: &mut dyn Bus, a: &RestoreArgs) -> anyhow::Result<()> {
    let t = Timeouts { answer: ctx.timeout, write: a.store_timeout };
    crate::ops::stop::stoppable(bus, &ctx.cancel, |bus| {
        each_node(ctx, "restore", &a.node.0, |node| restore_one(ctx, bus, a, t, node))
    })
}

fn restore_one(ctx: &Ctx, bus: &mut dyn Bus, a: &RestoreArgs, t: Timeouts, node: u8) -> Result<store::Restored, Ended> {
    let stopped = |done: Vec<String>, not_done: Vec<String>, state: String| {
        Err(Ended::Stopped(Stopped::new("restore", done, not_done, state)))
    };
    let mut report = match store::restore(bus, node, a.class, t) {
        Ok(report) => report,
        Err(e) if e.is_interrupted() => {
            let not_done = vec![format!("'load' to 0x1011:{} of node {node}", a.class as u8 + 1)];
            return stopped(Vec::new(), not_done, format!("nothing was changed: node {node} keeps its parameters"));
        }
        Err(e) => return Err(e.into()),
    };
    if a.reset {
        let wait = a.store_timeout.max(Duration::from_secs(2));
        report.reset = true;
        let o = ResetOptions { wait, timeout: ctx.timeout };
        let done = vec![format!("node {node}: 'load' written to {}", report.object)];
        match nmt::reset(bus, Command::ResetNode, node, &o) {
            Ok(r) if r.interrupted => {
                let not_done = vec![format!("confirming that node {node} booted")];
                let state = format!(
                    "node {node}: the defaults are loaded and the reset went out; whether it booted with them is \
                     not known (canctl nmt state {node} says)"
                );
                return stopped([done, vec![format!("NMT reset of node {node}")]].concat(), not_done, state);
            }
            Ok(r) if !r.confirmed => report.reset_unconfirmed = r.why,
            Ok(_) => {}
            Err(e) if e.is_interrupted() => {
                let not_done = vec![format!("NMT reset of node {node}")];
                let state = format!(
                    "node {node}: the defaults are loaded and apply from its next reset (canctl nmt reset {node} does it)"
                );
                return stopped(done, not_done, state);
            }
            Err(e) => return Err(e.into()),
        }
    }
    Ok(report)
}
