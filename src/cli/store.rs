//! `canctl store` and `canctl restore`: CiA 301 objects 0x1010 and 0x1011.

use super::{parse_node, Ctx};
use crate::bus::Bus;
use crate::canopen::nmt::Command;
use crate::ops::nmt::{self, Confirmation, ResetOptions};
use crate::ops::store::{self, Timeouts};
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
    let report = store::store(bus, a.node, a.class, Timeouts { answer: ctx.timeout, write: a.store_timeout })?;
    Ok(ctx.out.report(&report)?)
}

pub fn restore(ctx: &Ctx, bus: &mut dyn Bus, a: &RestoreArgs) -> anyhow::Result<()> {
    let mut report = store::restore(bus, a.node, a.class, Timeouts { answer: ctx.timeout, write: a.store_timeout })?;
    if a.reset {
        let wait = a.store_timeout.max(Duration::from_secs(2));
        report.reset = true;
        let o = ResetOptions { wait, timeout: ctx.timeout };
        if let Confirmation::Unconfirmed(why) = nmt::reset_and_wait(bus, Command::ResetNode, a.node, &o)? {
            report.reset_unconfirmed = Some(why);
        }
    }
    Ok(ctx.out.report(&report)?)
}
