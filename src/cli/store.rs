//! `canctl store` and `canctl restore`: CiA 301 objects 0x1010 and 0x1011.

use super::ctx::Ctx;
use crate::bus::Bus;
use crate::ops::store::Timeouts;
use crate::ops::store_all::{restore_nodes, store_nodes};
use crate::output::CommandResult;
use clap::Args;
use clap_complete::engine::ArgValueCandidates;
use std::time::Duration;

pub(crate) use crate::ops::store::Class;

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
pub(crate) struct StoreArgs {
    /// Node-id, 1 to 127 (0: the EPOS2 on an epos2-rs232/epos2-usb bus), or several: 5,10,20
    #[arg(value_parser = super::ctx::sdo_node_list, value_name = "NODE", add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: crate::settings::parse::Nodes,
    #[arg(value_enum, default_value = "all")]
    pub class: Class,
    /// How long the device may take to store (flash writes take a while)
    #[arg(long, value_name = "DUR", default_value = "5s", value_parser = super::ctx::parse_duration)]
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
pub(crate) struct RestoreArgs {
    /// Node-id, 1 to 127, or several: 5,10,20
    #[arg(value_parser = super::ctx::node_list, value_name = "NODE", add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: crate::settings::parse::Nodes,
    #[arg(value_enum, default_value = "all")]
    pub class: Class,
    /// Reset the node afterwards and wait for it to boot with the defaults
    #[arg(long)]
    pub reset: bool,
    /// How long the device may take to restore
    #[arg(long, value_name = "DUR", default_value = "5s", value_parser = super::ctx::parse_duration)]
    pub store_timeout: Duration,
}

pub(crate) fn store(ctx: &Ctx, bus: &mut dyn Bus, a: &StoreArgs) -> CommandResult {
    let t = Timeouts { answer: ctx.timeout, write: a.store_timeout };
    let run = ctx.stoppable(bus, |bus| store_nodes(bus, &a.node.0, a.class, t));
    crate::output::stopped::each_node(&ctx.out, "store", &a.node.0, run)
}

pub(crate) fn restore(ctx: &Ctx, bus: &mut dyn Bus, a: &RestoreArgs) -> CommandResult {
    let t = Timeouts { answer: ctx.timeout, write: a.store_timeout };
    let run = ctx.stoppable(bus, |bus| restore_nodes(bus, &a.node.0, a.class, t, a.reset));
    crate::output::stopped::each_node(&ctx.out, "restore", &a.node.0, run)
}
