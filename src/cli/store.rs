//! `canctl store` and `canctl restore`: CiA 301 objects 0x1010 and 0x1011.

use super::{parse_node, Ctx};
use crate::bus::Bus;
use crate::canopen::nmt::Command;
use crate::ops::nmt::{self, ResetOptions};
use crate::ops::store::{self, Timeouts};
use crate::ops::Stopped;
use clap::Args;
use clap_complete::engine::ArgValueCandidates;
use std::time::Duration;

pub use crate::ops::store::Class;

/// Save parameters to non-volatile memory (writes 'save' to 0x1010)
///
/// Reads 0x1010:0 and the sub-entry first, and says so when the device cannot store that
/// class on command.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim store 5
  canctl --bus can0 store 10 comm --store-timeout 10s")]
pub struct StoreArgs {
    /// Node-id, 1 to 127 (0: the EPOS2 on an epos2-rs232/epos2-usb bus)
    #[arg(value_parser = super::parse_sdo_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: u8,
    #[arg(value_enum, default_value = "all")]
    pub class: Class,
    /// How long the device may take to store (flash writes take a while)
    #[arg(long, value_name = "DUR", default_value = "5s", value_parser = super::parse_duration)]
    pub store_timeout: Duration,
}

/// Bring back default parameters (writes 'load' to 0x1011)
///
/// The defaults apply from the next reset on; --reset does the reset and waits for the
/// node to boot.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim restore 5 --reset
  canctl --bus can0 restore 10 app")]
pub struct RestoreArgs {
    /// Node-id, 1 to 127
    #[arg(value_parser = parse_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: u8,
    #[arg(value_enum, default_value = "all")]
    pub class: Class,
    /// Reset the node afterwards and wait for it to boot with the defaults
    #[arg(long)]
    pub reset: bool,
    /// How long the device may take to restore
    #[arg(long, value_name = "DUR", default_value = "5s", value_parser = super::parse_duration)]
    pub store_timeout: Duration,
}

pub fn store(ctx: &Ctx, bus: &mut dyn Bus, a: &StoreArgs) -> anyhow::Result<()> {
    let t = Timeouts { answer: ctx.timeout, write: a.store_timeout };
    match super::interrupt::stoppable(bus, |bus| store::store(bus, a.node, a.class, t)) {
        Ok(report) => Ok(ctx.out.report(&report)?),
        Err(e) if e.is_interrupted() => {
            let not_done = vec![format!("'save' to 0x1010:{} of node {}", a.class as u8 + 1, a.node)];
            let state = format!("nothing was stored: node {}'s non-volatile memory is as it was", a.node);
            stopped(ctx, Stopped::new("store", Vec::new(), not_done, state))
        }
        Err(e) => Err(e.into()),
    }
}

pub fn restore(ctx: &Ctx, bus: &mut dyn Bus, a: &RestoreArgs) -> anyhow::Result<()> {
    let t = Timeouts { answer: ctx.timeout, write: a.store_timeout };
    super::interrupt::stoppable(bus, |bus| {
        let node = a.node;
        let mut report = match store::restore(bus, node, a.class, t) {
            Ok(report) => report,
            Err(e) if e.is_interrupted() => {
                let not_done = vec![format!("'load' to 0x1011:{} of node {node}", a.class as u8 + 1)];
                let state = format!("nothing was changed: node {node} keeps its parameters");
                return stopped(ctx, Stopped::new("restore", Vec::new(), not_done, state));
            }
            Err(e) => return Err(e.into()),
        };
        if a.reset {
            let wait = a.store_timeout.max(Duration::from_secs(2));
            report.reset = true;
            let o = ResetOptions { wait, timeout: ctx.timeout };
            let done = vec![format!("'load' written to {}", report.object)];
            match nmt::reset(bus, Command::ResetNode, node, &o) {
                Ok(r) if r.interrupted => {
                    let not_done = vec![format!("confirming that node {node} booted")];
                    let state = format!(
                        "the defaults are loaded and the reset went out; whether node {node} booted with them is \
                         not known (canctl nmt state {node} says)"
                    );
                    return stopped(
                        ctx,
                        Stopped::new(
                            "restore",
                            [done, vec![format!("NMT reset of node {node}")]].concat(),
                            not_done,
                            state,
                        ),
                    );
                }
                Ok(r) if !r.confirmed => report.reset_unconfirmed = r.why,
                Ok(_) => {}
                Err(e) if e.is_interrupted() => {
                    let not_done = vec![format!("NMT reset of node {node}")];
                    let state = format!(
                        "the defaults are loaded and apply from node {node}'s next reset (canctl nmt reset {node} does it)"
                    );
                    return stopped(ctx, Stopped::new("restore", done, not_done, state));
                }
                Err(e) => return Err(e.into()),
            }
        }
        Ok(ctx.out.report(&report)?)
    })
}

/// The report of a command the user stopped, then exit 130.
fn stopped(ctx: &Ctx, report: Stopped) -> anyhow::Result<()> {
    ctx.out.report(&report)?;
    Err(crate::Error::Interrupted.into())
}
