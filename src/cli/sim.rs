//! `canctl sim`: run the simulated network's devices behind a real interface, or manage
//! its saved state.

use super::{Ctx, GlobalArgs};
use crate::bus::BusUri;
use crate::error::Error;
use crate::output::Format;
use crate::sim::epos2_device::Epos2Device;
use crate::sim::epos2_serve::{self, Fault, Framing, ServeOptions};
use crate::sim::state::{default_path, StateFile};
use crate::sim::SimLink;
use clap::{Args, Subcommand};
use serde_json::json;
use std::path::PathBuf;
use std::time::Duration;

/// Run the simulated network on a CAN interface or behind a serial link, or manage its state
///
/// With --socketcan IFACE, the devices answer on that interface (a vcan interface makes a
/// test bus for provisioning scripts). With --epos2-rs232 or --epos2-usb, creates a pseudo-terminal, prints its path on stdout
/// and serves it as a maxon EPOS2 (node 1 of the sim network) until stopped: commands for
/// node 0 or 1 run on the EPOS2's own dictionary, the others go on to the simulated CAN bus
/// as SDO, NMT and LSS frames. The network's state is saved after every command.
#[derive(Args, Debug)]
#[command(
    args_conflicts_with_subcommands = true,
    after_help = "Examples:
  canctl sim --socketcan vcan0 &
  canctl sim --epos2-rs232 &               # prints /dev/pts/N
  canctl --bus epos2-rs232:/dev/pts/N scan
  canctl sim --epos2-usb --baud 1000000 --fault crc@2
  canctl sim reset"
)]
pub struct SimArgs {
    #[command(subcommand)]
    pub command: Option<SimCommand>,
    /// Put the devices on this CAN interface (vcan0, can0) and answer there
    #[arg(long, value_name = "IFACE", conflicts_with_all = ["epos2_rs232", "epos2_usb"])]
    pub socketcan: Option<String>,
    /// Serve an EPOS2 speaking the RS232 protocol (with the 'O'/'F' handshake)
    #[arg(long, conflicts_with = "epos2_usb")]
    pub epos2_rs232: bool,
    /// Serve an EPOS2 speaking the USB protocol (DLE/STX framing)
    #[arg(long)]
    pub epos2_usb: bool,
    /// Pace bytes as a serial line at this bit rate would (10 bits a byte)
    #[arg(long, value_name = "BITS/S", value_parser = clap::value_parser!(u32).range(300..=10_000_000))]
    pub baud: Option<u32>,
    /// Inject a fault: nack, crc, garbage, drop, mute, stale, late, babble, empty-segments,
    /// endless-segments or wrong-object, on frame N (KIND@N) or every frame (KIND@*)
    #[arg(long, value_name = "KIND@N")]
    pub fault: Vec<Fault>,
    /// How long the EPOS2 waits for an SDO answer on the CAN bus
    #[arg(long, value_name = "DUR", default_value = "25ms", value_parser = super::parse_duration)]
    pub can_timeout: Duration,
}

#[derive(Subcommand, Debug)]
pub enum SimCommand {
    /// Forget the simulated network's saved state: devices start as built
    ///
    /// The sim network keeps node-ids, written and stored values and NMT states between
    /// invocations in a state file ($XDG_STATE_HOME/canctl/sim.json, or the path in
    /// --bus sim:PATH). This removes it.
    #[command(after_help = "Examples:\n  canctl sim reset\n  canctl --bus sim:/tmp/bench.json sim reset")]
    Reset,
}

/// The state file of the sim bus named by --bus (or the default one).
fn state_path(ctx: &Ctx) -> anyhow::Result<PathBuf> {
    Ok(match ctx.bus.as_deref().filter(|b| !b.is_empty()).map(str::parse::<BusUri>).transpose()? {
        None | Some(BusUri::Sim { state: None }) => default_path(),
        Some(BusUri::Sim { state: Some(p) }) => p,
        Some(_) => {
            return Err(Error::Usage(
                "`canctl sim` runs the simulated network: use --bus sim or sim:PATH (or no --bus)".into(),
            )
            .into())
        }
    })
}

pub fn run(ctx: &Ctx, global: &GlobalArgs, args: &SimArgs) -> anyhow::Result<()> {
    let path = state_path(ctx)?;
    if let Some(SimCommand::Reset) = args.command {
        StateFile::lock(&path)?.reset()?;
        return match ctx.out.format {
            Format::Json => Ok(ctx.out.json(&json!({ "reset": true, "state_file": path.display().to_string() }))?),
            _ => Ok(ctx.out.print(&format!("sim network reset ({})", path.display()))?),
        };
    }
    if let Some(iface) = &args.socketcan {
        let mut can = crate::bus::socketcan::SocketCanLink::open(iface)?;
        let sim = SimLink::open(StateFile::lock(&path)?)?;
        ctx.out.note(&format!("the sim network's devices are on {iface} (nodes 1, 5, 10, 32); stop with Ctrl-C"));
        crate::sim::bridge::run(sim, &mut can, global.verbose > 0)?;
        return Ok(());
    }
    let framing = match (args.epos2_rs232, args.epos2_usb) {
        (true, _) => Framing::Rs232,
        (_, true) => Framing::Usb,
        _ => {
            let msg = "say what to serve: --socketcan IFACE, --epos2-rs232 or --epos2-usb (or `canctl sim reset`)";
            return Err(Error::Usage(msg.into()).into());
        }
    };
    let link = SimLink::open(StateFile::lock(&path)?)?;
    let device = Epos2Device::new(link, args.can_timeout, global.verbose > 0);
    let opts = ServeOptions { framing, baud: args.baud, faults: args.fault.clone() };
    epos2_serve::serve(device, &opts, |pty| {
        ctx.out.print(pty).map_err(|e| Error::Link(format!("cannot print the pty path: {e}")))?;
        let kind = if framing == Framing::Rs232 { "epos2-rs232" } else { "epos2-usb" };
        ctx.out.note(&format!(
            "serving the sim network's EPOS2 (node 1) on {pty}: use --bus {kind}:{pty}; stop with Ctrl-C"
        ));
        Ok(())
    })?;
    Ok(())
}
