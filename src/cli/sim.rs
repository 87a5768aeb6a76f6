//! `canctl sim`: run the simulated network's devices behind a real interface, or manage
//! its saved state.

use super::ctx::{Ctx, GlobalArgs};
use crate::epos2::Framing;
use crate::error::{Error, LinkError, PtyOp};
use crate::output::sim;
use crate::output::CommandResult;
use crate::sim::serial_fault::Fault;
use crate::sim::serve::{self, Serve, Serving};
use crate::sim::socketcand_serve;
use crate::sim::{FaultSpec, Profile, SimConfig, DEFAULT_SEED, DEFAULT_UNCONFIGURED, MAX_UNCONFIGURED};
use clap::builder::TypedValueParser;
use clap::{Args, Subcommand};
use std::time::Duration;

/// Run the simulated network on a CAN interface or behind a serial link, or manage its state
///
/// With --socketcan IFACE, the devices answer on that interface (a vcan interface makes a
/// test bus for provisioning scripts). With --slcan, creates a pseudo-terminal, prints its
/// path and acts there as a serial-line CAN adapter with the devices on its bus (use
/// --bus slcan:/dev/pts/N, or attach the kernel's slcand to it). With --socketcand, listens
/// on TCP as a socketcand server (raw mode, interface `sim`) and prints the --bus value that
/// reaches it; several programs share that bus at once, as a real one. With --epos2-rs232 or --epos2-usb, creates a pseudo-terminal, prints its path on stdout
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
  canctl sim --socketcand 29536 &          # prints socketcand:127.0.0.1/sim
  canctl sim reset"
)]
pub(crate) struct SimArgs {
    #[command(subcommand)]
    pub command: Option<SimCommand>,
    /// Put the devices on this CAN interface (vcan0, can0) and answer there
    #[arg(long, value_name = "IFACE", conflicts_with_all = ["epos2_rs232", "epos2_usb", "slcan"])]
    pub socketcan: Option<String>,
    /// Serve the devices behind a simulated slcan (Lawicel) adapter on a pseudo-terminal
    #[arg(long, conflicts_with_all = ["epos2_rs232", "epos2_usb"])]
    pub slcan: bool,
    /// Serve the devices behind a socketcand server (raw mode) on this TCP port, on
    /// 127.0.0.1 unless an address is given; prints the --bus value that reaches it
    #[arg(long, value_name = "[ADDR:]PORT", value_parser = parse_listen, conflicts_with_all = ["socketcan", "slcan", "epos2_rs232", "epos2_usb"])]
    pub socketcand: Option<std::net::SocketAddr>,
    /// With --socketcand: send no discovery beacon. Without this, the server announces
    /// itself every 2.5 s as socketcand does (UDP port 42000): to 127.0.0.1 when bound to
    /// loopback, else to the broadcast address; `canctl buses` lists it
    #[arg(long, requires = "socketcand")]
    pub no_beacon: bool,
    /// Serve an EPOS2 speaking the RS232 protocol (with the 'O'/'F' handshake)
    #[arg(long, conflicts_with = "epos2_usb")]
    pub epos2_rs232: bool,
    /// Serve an EPOS2 speaking the USB protocol (DLE/STX framing)
    #[arg(long)]
    pub epos2_usb: bool,
    /// Pace bytes as a serial line at this bit rate would (10 bits a byte)
    #[arg(long, value_name = "BITS/S", value_parser = super::ctx::number_in::<u32>("a serial bit rate", 300, 10_000_000))]
    pub baud: Option<u32>,
    /// Inject a fault: nack, crc, garbage, drop, mute, stale, late, babble, empty-segments,
    /// endless-segments or wrong-object, on frame N (KIND@N) or every frame (KIND@*)
    #[arg(long, value_name = "KIND@N")]
    pub fault: Vec<Fault>,
    /// How long the EPOS2 waits for an SDO answer on the CAN bus (the slow profile's
    /// devices answer up to 80 ms late)
    #[arg(long, value_name = "DUR", default_value = "100ms", value_parser = super::ctx::parse_duration)]
    pub can_timeout: Duration,
}

#[derive(Subcommand, Debug)]
pub(crate) enum SimCommand {
    /// Forget the simulated network's saved state: devices start as built
    ///
    /// The sim network keeps node-ids, written and stored values and NMT states between
    /// invocations in a state file ($XDG_STATE_HOME/canctl/sim.json, or the path in
    /// --bus sim:PATH). This starts it afresh, with the profile, bit rate, seed, faults and
    /// number of devices without a node-id given here (kept in the state file, so that every later
    /// invocation sees the same network).
    ///
    /// Profiles: instant (answers at once, frames take no time: for unit tests), typical
    /// (devices answer 0.5-3 ms late and restart in 100 ms after an NMT reset, frames take
    /// their time at the bit rate: the default), slow (answers 5-80 ms late, restarts in
    /// 300 ms, as slow real slaves do).
    #[command(after_help = "Examples:
  canctl sim reset
  canctl sim reset --profile slow --unconfigured 8
  canctl sim reset --bit-rate 1M
  canctl sim reset --fault 5:drop@2 --fault drive:abort=0x06010000
  canctl --bus sim:/tmp/bench.json sim reset --profile instant --seed 7")]
    Reset(ResetArgs),
}

#[derive(Args, Debug)]
pub(crate) struct ResetArgs {
    /// How late devices answer and whether frames take time on the bus
    #[arg(long, value_name = "PROFILE", default_value = "typical", value_parser = clap::builder::PossibleValuesParser::new(Profile::NAMES).map(|s| s.parse::<Profile>().expect("listed")))]
    pub profile: Profile,
    /// Devices waiting for a node-id over LSS
    #[arg(long, value_name = "N", default_value_t = DEFAULT_UNCONFIGURED, value_parser = super::ctx::number_in::<u8>("a number of devices", 0, MAX_UNCONFIGURED as u64))]
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
    /// wrong-cob[=ID] (answers on another id), reboot (resets instead of
    /// answering: values not stored are lost, a boot-up follows), off (not powered: sends
    /// nothing from the start), no-heartbeat (stops its heartbeat, though 0x1017 still says
    /// it beats), miss (does not hear a frame: WHEN counts the frames it hears instead),
    /// endless-segments (an upload answered by segments that never end), endless-block (a
    /// block upload that never ends), ack-zero (every sub-block of a block download
    /// acknowledged as nothing received); for these three WHEN counts the transfers of that
    /// kind. WHEN counts the device's answers from 1: N
    /// (that one only), N+ (from that one on), P% (each with that probability), * (all,
    /// the default). bus:off puts the controller canctl talks through bus-off, for good
    /// (as with restart-ms 0): it sends nothing and reports so.
    #[arg(long, value_name = "SPEC")]
    pub fault: Vec<FaultSpec>,
    /// Run commands on virtual time: a wait with nothing due ends at once, so slow devices,
    /// long delays and long watches take no wall time; every figure stays in bus time
    ///
    /// For tests and scripts that nothing else watches: a network served with --socketcan,
    /// --slcan or --epos2-* (shared with other programs) runs on real time all the same.
    #[arg(long)]
    pub virtual_time: bool,
    /// Add a device with a CiA 302-3 bootloader on this node-id (for canctl firmware)
    ///
    /// As Zephyr's and CANopenNode's, it answers "start" (0x1F51 = 1) and then resets, and
    /// its boot-up comes after 500 ms of booting. Its simulator objects change that:
    /// 0x5F52 the boot time in ms (u16), 0x5F53 = 0 a reset before the answer (u8),
    /// 0x5F51 a fault (1 power lost mid-download, 2 flash write error, 3 reboot on stop).
    #[arg(long, value_name = "NODE", value_parser = super::ctx::parse_node)]
    pub bootloader: Option<u8>,
}

/// `29536` (on 127.0.0.1), `0.0.0.0:29536`, `[::1]:29536`.
fn parse_listen(text: &str) -> Result<std::net::SocketAddr, String> {
    match text.parse::<u16>() {
        Ok(port) => Ok(std::net::SocketAddr::from(([127, 0, 0, 1], port))),
        Err(_) => text.parse().map_err(|_| format!("'{text}' is not PORT or ADDR:PORT (0.0.0.0:29536, [::1]:29536)")),
    }
}

fn parse_rate(text: &str) -> Result<u8, String> {
    let index = crate::canopen::lss::parse_bit_rate(text)?;
    crate::sim::timing::bits_per_second(index)
        .map(|_| index)
        .ok_or_else(|| format!("the sim bus needs a fixed bit rate, not {text}"))
}

pub(crate) fn run(ctx: &Ctx, global: &GlobalArgs, args: &SimArgs) -> CommandResult {
    let path = serve::state_path(ctx.bus.as_deref())?.ok_or(crate::output::UsageError::NotASimBus)?;
    if let Some(SimCommand::Reset(r)) = &args.command {
        let mut config =
            SimConfig::default().profile(r.profile).seed(r.seed).unconfigured(r.unconfigured).bit_rate(r.bit_rate);
        config.faults = r.fault.clone();
        config.virtual_time = r.virtual_time;
        config.bootloader = r.bootloader;
        let reset = serve::reset(&path, &config)?;
        // The nodes seen on the old network are not this one's.
        crate::ops::scan_cache::forget(ctx.bus.as_deref().unwrap_or("sim"));
        return Ok(ctx.out.report(&reset)?);
    }
    let (faults, baud, can_timeout) = (args.fault.clone(), args.baud, args.can_timeout);
    let how = match (&args.socketcan, args.slcan, args.epos2_rs232, args.epos2_usb) {
        _ if args.socketcand.is_some() => Serve::Socketcand { addr: args.socketcand.expect("just checked") },
        (Some(iface), ..) => Serve::SocketCan { iface: iface.clone() },
        (_, true, ..) => Serve::Slcan { faults },
        (_, _, true, _) => Serve::Epos2 { framing: Framing::Rs232, baud, faults, can_timeout },
        (_, _, _, true) => Serve::Epos2 { framing: Framing::Usb, baud, faults, can_timeout },
        _ => return Err(crate::output::UsageError::NothingToServe.into()),
    };
    // Serving has no step to stop at: a request to stop ends it, as the signal itself did
    // before it was caught for every command, with the exit code of an interruption.
    let cancel = ctx.cancel.clone();
    std::thread::spawn(move || {
        while !cancel.is_cancelled() {
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        std::process::exit(Error::Interrupted.exit_code());
    });
    let served = serve::serve(&path, &how, global.frame_log()?, |serving| {
        if let Some(pty) = serving.pty().or(serving.bus()) {
            ctx.out
                .print(pty)
                .map_err(|e| Error::Link(LinkError::Pty { op: PtyOp::PrintPath, detail: e.to_string() }))?;
        }
        ctx.out.note(&sim::serving(serving));
        if let (Serving::Socketcand { bound, .. }, false) = (serving, args.no_beacon) {
            let target = socketcand_serve::beacon_target(*bound, socketcand_serve::beacon_port());
            socketcand_serve::start_beacon(*bound, target)?;
        }
        Ok(())
    });
    Ok(served?)
}
