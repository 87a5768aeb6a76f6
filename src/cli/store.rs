//! `canctl store` and `canctl restore`: CiA 301 objects 0x1010 and 0x1011.

use super::{parse_node, Ctx};
use crate::bus::{Bus, SdoOptions};
use crate::canopen::nmt::Command;
use crate::canopen::ObjAddr;
use crate::error::Error;
use crate::output::Format;
use clap::{Args, ValueEnum};
use clap_complete::engine::ArgValueCandidates;
use serde_json::json;
use std::time::Duration;

/// Which parameters (the 0x1010/0x1011 subindex).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Class {
    /// All parameters (sub 1)
    All,
    /// Communication parameters, 0x1000..0x1FFF (sub 2)
    Comm,
    /// Application parameters, 0x6000..0x9FFF (sub 3)
    App,
    /// Manufacturer parameters, 0x2000..0x5FFF (sub 4)
    Mfr,
}

impl Class {
    fn sub(self) -> u8 {
        self as u8 + 1
    }
    fn text(self) -> &'static str {
        ["all parameters", "communication parameters", "application parameters", "manufacturer parameters"]
            [self as usize]
    }
}

/// Save parameters to non-volatile memory (writes 'save' to 0x1010)
///
/// Reads 0x1010:0 and the sub-entry first, and says so when the device cannot store that
/// class on command.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim store 5
  canctl --bus can0 store 10 comm --store-timeout 10s")]
pub struct StoreArgs {
    /// Node-id, 1..127 (0: the EPOS2 on an epos2-rs232/epos2-usb bus)
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
    /// Node-id, 1..127
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

/// 'save' and 'load' as they travel (CiA 301 7.5.2.13/14).
const SAVE: &[u8; 4] = b"save";
const LOAD: &[u8; 4] = b"load";

/// Check that the device can do this on command, then write the signature.
pub fn signature(
    ctx: &Ctx,
    bus: &mut dyn Bus,
    node: u8,
    restore: bool,
    class: Class,
    wait: Duration,
) -> crate::Result<ObjAddr> {
    let (index, verb, sig) = if restore { (0x1011, "restore", LOAD) } else { (0x1010, "store", SAVE) };
    let mut opts = SdoOptions::new(ctx.timeout);
    opts.size_hint = Some(1);
    let highest = match bus.sdo_upload(node, ObjAddr::new(index, 0), &opts) {
        Ok(v) => v.first().copied().unwrap_or(0),
        Err(Error::SdoAbort { code: crate::canopen::abort::NO_OBJECT, .. }) => {
            return Err(Error::Refused(format!(
                "node {node} has no object 0x{index:04X}: it cannot {verb} parameters"
            )));
        }
        Err(e) => return Err(e),
    };
    let addr = ObjAddr::new(index, class.sub());
    if class.sub() > highest {
        let offered: Vec<&str> = [Class::All, Class::Comm, Class::App, Class::Mfr]
            .iter()
            .filter(|c| c.sub() <= highest)
            .map(|c| c.text())
            .collect();
        return Err(Error::Refused(format!(
            "node {node} cannot {verb} {} (0x{index:04X}:0 = {highest}; it offers: {})",
            class.text(),
            if offered.is_empty() { "nothing".to_string() } else { offered.join(", ") }
        )));
    }
    opts.size_hint = Some(4);
    let caps = bus.sdo_upload(node, addr, &opts)?;
    let caps = u32::from_le_bytes(caps.get(..4).and_then(|c| c.try_into().ok()).unwrap_or([0; 4]));
    // Bit 0: the device does this on command. (For 0x1010 bit 1 means it saves on its own.)
    if caps & 1 == 0 {
        let own = if !restore && caps & 2 != 0 { ": it saves them by itself" } else { "" };
        return Err(Error::Refused(format!(
            "node {node} does not {verb} {} on command ({addr} = 0x{caps:08X}){own}",
            class.text()
        )));
    }
    let mut slow = SdoOptions::new(wait);
    slow.size_hint = Some(4);
    bus.sdo_download(node, addr, sig, &slow)?;
    Ok(addr)
}

pub fn store(ctx: &Ctx, bus: &mut dyn Bus, a: &StoreArgs) -> anyhow::Result<()> {
    let addr = signature(ctx, bus, a.node, false, a.class, a.store_timeout)?;
    match ctx.out.format {
        Format::Json => {
            ctx.out.json(&json!({ "node": a.node, "stored": a.class.text(), "object": addr.to_string() }))?
        }
        _ => ctx.out.print(&format!("node {}: {} stored ({addr})", a.node, a.class.text()))?,
    }
    Ok(())
}

pub fn restore(ctx: &Ctx, bus: &mut dyn Bus, a: &RestoreArgs) -> anyhow::Result<()> {
    let addr = signature(ctx, bus, a.node, true, a.class, a.store_timeout)?;
    let mut unconfirmed = None;
    let rebooted = if a.reset {
        let wait = a.store_timeout.max(Duration::from_secs(2));
        if let super::nmt::Reset::Unconfirmed(why) =
            super::nmt::reset_and_wait(ctx, bus, Command::ResetNode, a.node, wait)?
        {
            unconfirmed = Some(why);
        }
        true
    } else {
        false
    };
    let text = if let Some(why) = &unconfirmed {
        format!("node {}: {} back to defaults ({addr}); NMT reset sent, not confirmed: {why}", a.node, a.class.text())
    } else if rebooted {
        format!(
            "node {}: {} back to defaults ({addr}); the node was reset and booted with them",
            a.node,
            a.class.text()
        )
    } else {
        format!(
            "node {}: {} will be back to defaults after the next reset ({addr}; --reset does it)",
            a.node,
            a.class.text()
        )
    };
    match ctx.out.format {
        Format::Json => ctx.out.json(
            &json!({ "node": a.node, "restored": a.class.text(), "object": addr.to_string(), "reset": rebooted,
                    "reset_confirmed": rebooted && unconfirmed.is_none() }),
        )?,
        _ => ctx.out.print(&text)?,
    }
    Ok(())
}
