//! `canctl sim`: run the simulated network's devices behind a real interface, or manage
//! its saved state.

use super::{Ctx, GlobalArgs};
use crate::bus::BusUri;
use crate::epos2::Framing;
use crate::error::Error;
use crate::output::Format;
use crate::sim::serial_fault::Fault;
use crate::sim::state::{default_path, StateFile};
use crate::sim::{FaultSpec, Profile, SimConfig, DEFAULT_SEED, DEFAULT_UNCONFIGURED, MAX_UNCONFIGURED};
use clap::builder::TypedValueParser;
use clap::{Args, Subcommand};
use serde_json::json;
use std::path::PathBuf;
use std::time::Duration;

/// Run the simulated network on a CAN interface or behind a serial link, or manage its state
///
/// With --socketcan IFACE, the devices answer on that interface (a vcan interface makes a
/// test bus for provisioning scripts). With --slcan, creates a pseudo-terminal, prints its
/// path and acts there as a serial-line CAN adapter with the devices on its bus (use
/// --bus slcan:/dev/pts/N, or attach the kernel's slcand to it). With --epos2-rs232 or --epos2-usb, creates a pseudo-terminal, prints its path on stdout
/// and serves it as a maxon EPOS2 (node 1 of the sim network) until stopped: commands for
/// node 0 or 1 run on the EPOS2's own dictionary, the others go on to the simulated CAN bus
/// as SDO, NMT and LSS frames. The network's state is saved after every command. The
/// devices answer as `canctl sim reset` set them up: late by their profile, with their
/// faults (on a CAN interface, frame timing is the interface's own).
#[derive(Args, Debug)]
#[command(
    args_conflicts_with_subcommands = true,
    after_help = "Examples:
  canctl sim --socketcan vcan0 &
  canctl sim --epos2-rs232 &               # prints /dev/pts/N
  canctl --bus epos2-rs232:/dev/pts/N scan
  canctl sim --epos2-usb --baud 1000000 --fault crc@2
  canctl sim --slcan &                     # prints /dev/pts/N: --bus slcan:/dev/pts/N
  canctl sim reset"
)]
pub struct SimArgs {
    #[command(subcommand)]
    pub command: Option<SimCommand>,
    /// Put the devices on this CAN interface (vcan0, can0) and answer there
    #[arg(long, value_name = "IFACE", conflicts_with_all = ["epos2_rs232", "epos2_usb", "slcan"])]
    pub socketcan: Option<String>,
    /// Serve the devices behind a simulated slcan (Lawicel) adapter on a pseudo-terminal
    #[arg(long, conflicts_with_all = ["epos2_rs232", "epos2_usb"])]
    pub slcan: bool,
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
    /// How long the EPOS2 waits for an SDO answer on the CAN bus (the slow profile's
    /// devices answer up to 80 ms late)
    #[arg(long, value_name = "DUR", default_value = "100ms", value_parser = super::parse_duration)]
    pub can_timeout: Duration,
}

#[derive(Subcommand, Debug)]
pub enum SimCommand {
    /// Forget the simulated network's saved state: devices start as built
    ///
    /// The sim network keeps node-ids, written and stored values and NMT states between
    /// invocations in a state file ($XDG_STATE_HOME/canctl/sim.json, or the path in
    /// --bus sim:PATH). This starts it afresh, with the profile, bit rate, seed, faults and
    /// number of devices without a node-id given here (kept in the state file, so that every later
    /// invocation sees the same network).
    ///
    /// Profiles: instant (answers at once, frames take no time: for unit tests), typical
    /// (devices answer 0.5-3 ms late, frames take their time at the bit rate: the default),
    /// slow (answers 5-80 ms late, as slow real slaves do).
    #[command(after_help = "Examples:
  canctl sim reset
  canctl sim reset --profile slow --unconfigured 8
  canctl sim reset --bit-rate 1M
  canctl sim reset --fault 5:drop@2 --fault drive:abort=0x06010000
  canctl --bus sim:/tmp/bench.json sim reset --profile instant --seed 7")]
    Reset(ResetArgs),
}

#[derive(Args, Debug)]
pub struct ResetArgs {
    /// How late devices answer and whether frames take time on the bus
    #[arg(long, value_name = "PROFILE", default_value = "typical", value_parser = clap::builder::PossibleValuesParser::new(Profile::NAMES).map(|s| s.parse::<Profile>().expect("listed")))]
    pub profile: Profile,
    /// Devices waiting for a node-id over LSS
    #[arg(long, value_name = "N", default_value_t = DEFAULT_UNCONFIGURED, value_parser = clap::value_parser!(u8).range(0..=MAX_UNCONFIGURED as i64))]
    pub unconfigured: u8,
    /// The bit rate the bus and every device start at (1M 800k 500k 250k 125k 50k 20k 10k)
    #[arg(long, value_name = "RATE", default_value = "500k", value_parser = parse_rate)]
    pub bit_rate: u8,
    /// Seed of the devices' latency jitter and random faults: the same seed replays a run
    #[arg(long, value_name = "N", default_value_t = DEFAULT_SEED)]
    pub seed: u64,
    /// Make a device misbehave: TARGET:KIND[=ARG][@WHEN], e.g. 5:drop@3, drive:delay=40, 10:abort@2+
    ///
    /// TARGET is a node-id or a model key (drive, sensor, io, stepper, sensor-09501301).
    /// KIND: drop, delay=MS, duplicate, short-dlc[=N], corrupt (first data byte inverted),
    /// babble[=ID] (floods frames), abort[=CODE] (SDO answers refused), mute (falls silent),
    /// wrong-cob[=ID] (answers on another id). WHEN counts the device's answers from 1: N
    /// (that one only), N+ (from that one on), P% (each with that probability), * (all,
    /// the default).
    #[arg(long, value_name = "SPEC")]
    pub fault: Vec<FaultSpec>,
}

fn parse_rate(text: &str) -> Result<u8, String> {
    let index = crate::canopen::lss::parse_bit_rate(text)?;
    crate::sim::timing::bits_per_second(index)
        .map(|_| index)
        .ok_or_else(|| format!("the sim bus needs a fixed bit rate, not {text}"))
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
    if let Some(SimCommand::Reset(reset)) = &args.command {
        let mut config = SimConfig::default()
            .profile(reset.profile)
            .seed(reset.seed)
            .unconfigured(reset.unconfigured)
            .bit_rate(reset.bit_rate);
        config.faults = reset.fault.clone();
        StateFile::lock(&path)?.start_fresh(&config)?;
        return match ctx.out.format {
            Format::Json => Ok(ctx.out.json(&json!({
                "reset": true,
                "state_file": path.display().to_string(),
                "profile": config.profile.to_string(),
                "seed": config.seed,
                "unconfigured": config.unconfigured,
                "bit_rate": crate::canopen::lss::bit_rate_name(config.bit_rate),
                "faults": config.faults.iter().map(|f| f.to_string()).collect::<Vec<_>>(),
            }))?),
            _ => {
                let faults: Vec<String> = config.faults.iter().map(|f| f.to_string()).collect();
                let faults = if faults.is_empty() { String::new() } else { format!(", faults {}", faults.join(" ")) };
                Ok(ctx.out.print(&format!(
                    "sim network reset ({}): profile {}, {}bit/s, {} device(s) without a node-id, seed {}{faults}",
                    path.display(),
                    config.profile,
                    crate::canopen::lss::bit_rate_name(config.bit_rate),
                    config.unconfigured,
                    config.seed
                ))?)
            }
        };
    }
    if let Some(iface) = &args.socketcan {
        return serve_socketcan(ctx, global, iface, &path);
    }
    if args.slcan {
        return serve_slcan(ctx, global, args, &path);
    }
    let framing = match (args.epos2_rs232, args.epos2_usb) {
        (true, _) => Framing::Rs232,
        (_, true) => Framing::Usb,
        _ => {
            let msg =
                "say what to serve: --socketcan IFACE, --slcan, --epos2-rs232 or --epos2-usb (or `canctl sim reset`)";
            return Err(Error::Usage(msg.into()).into());
        }
    };
    serve_epos2(ctx, global, args, framing, &path)
}

#[cfg(target_os = "linux")]
fn serve_socketcan(ctx: &Ctx, global: &GlobalArgs, iface: &str, path: &std::path::Path) -> anyhow::Result<()> {
    let mut can = crate::bus::socketcan::SocketCanLink::open(iface)?;
    // The interface is a bus with its own timing: the devices only answer late.
    let sim = crate::sim::SimLink::open(StateFile::lock(path)?)?.without_bus_timing();
    ctx.out.note(&format!("the sim network's devices are on {iface} (nodes 1, 5, 10, 32); stop with Ctrl-C"));
    crate::sim::bridge::run(sim, &mut can, global.verbose > 0)?;
    Ok(())
}

#[cfg(not(target_os = "linux"))]
fn serve_socketcan(_: &Ctx, _: &GlobalArgs, _: &str, _: &std::path::Path) -> anyhow::Result<()> {
    Err(Error::Usage("SocketCAN is Linux's: `sim --socketcan` runs on Linux only; try `sim --slcan`".into()).into())
}

/// The simulated EPOS2 on a pseudo-terminal.
#[cfg(unix)]
fn serve_epos2(
    ctx: &Ctx,
    global: &GlobalArgs,
    args: &SimArgs,
    framing: Framing,
    path: &std::path::Path,
) -> anyhow::Result<()> {
    use crate::sim::epos2_serve::{self, ServeOptions};
    let link = crate::sim::SimLink::open(StateFile::lock(path)?)?;
    let device = crate::sim::epos2_device::Epos2Device::new(link, args.can_timeout, global.verbose > 0);
    let opts = ServeOptions { framing, baud: args.baud, faults: args.fault.clone() };
    epos2_serve::serve(device, &opts, |pty| {
        ctx.out.print(pty).map_err(|e| {
            Error::Link(crate::error::LinkError::Pty { op: crate::error::PtyOp::PrintPath, detail: e.to_string() })
        })?;
        let kind = if framing == Framing::Rs232 { "epos2-rs232" } else { "epos2-usb" };
        ctx.out.note(&format!(
            "serving the sim network's EPOS2 (node 1) on {pty}: use --bus {kind}:{pty}; stop with Ctrl-C"
        ));
        Ok(())
    })?;
    Ok(())
}

#[cfg(not(unix))]
fn serve_epos2(_: &Ctx, _: &GlobalArgs, _: &SimArgs, _: Framing, _: &std::path::Path) -> anyhow::Result<()> {
    Err(no_pty().into())
}

#[cfg(not(unix))]
fn no_pty() -> Error {
    Error::Usage(
        "the simulated serial devices (--epos2-rs232, --epos2-usb, --slcan) sit on a pseudo-terminal, which \
         this OS lacks; use --bus sim directly, or run them on Linux or macOS"
            .into(),
    )
}

#[cfg(not(unix))]
fn serve_slcan(_: &Ctx, _: &GlobalArgs, _: &SimArgs, _: &std::path::Path) -> anyhow::Result<()> {
    Err(no_pty().into())
}

/// The devices behind a simulated slcan adapter: the adapter is a frame link, bridged to
/// the sim network as a CAN interface is.
#[cfg(unix)]
fn serve_slcan(ctx: &Ctx, global: &GlobalArgs, args: &SimArgs, path: &std::path::Path) -> anyhow::Result<()> {
    use crate::sim::serial_fault::FaultKind;
    let adapter_faults = [FaultKind::Nack, FaultKind::Crc, FaultKind::Garbage, FaultKind::Drop, FaultKind::Mute];
    if let Some(f) = args.fault.iter().find(|f| !adapter_faults.contains(&f.kind)) {
        let msg = format!(
            "the slcan adapter takes the faults nack (a bell), crc, garbage, drop and mute, not {:?}; device faults \
             go to `canctl sim reset --fault`",
            f.kind
        );
        return Err(Error::Usage(msg).into());
    }
    let sim = crate::sim::SimLink::open(StateFile::lock(path)?)?;
    let rate = sim.network().bit_rate();
    let kbit = crate::canopen::lss::BIT_TIMINGS.get(rate as usize).and_then(|(_, k)| *k).unwrap_or(500);
    let mut adapter = crate::sim::slcan_serve::SlcanAdapter::create(kbit, args.fault.clone())?;
    let pty = adapter.path().to_string();
    ctx.out.print(&pty)?;
    let rate = crate::canopen::lss::bit_rate_name(rate);
    ctx.out.note(&format!("the sim network's devices are behind an slcan adapter on {pty} ({rate}): use --bus slcan:{pty}@{rate}; stop with Ctrl-C"));
    crate::sim::bridge::run(sim, &mut adapter, global.verbose > 0)?;
    Ok(())
}
