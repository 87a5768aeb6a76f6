//! `canctl lss`: node-ids and bit rates for devices that have none or share one (CiA 305).

use super::ctx::Ctx;
use crate::bus::Bus;
use crate::canopen::lss::{parse_bit_rate, Identity};
use crate::error::Error;
use crate::ops::lss::{self, AssignOptions, FastscanOptions, Setting};
use crate::output::CommandResult;
use clap::{Args, Subcommand};
use clap_complete::engine::ArgValueCandidates;
use std::time::Duration;

#[derive(Subcommand, Debug)]
pub(crate) enum LssCommand {
    /// Read a device's identity and node-id
    #[command(after_help = "Examples:
  canctl --bus sim lss inquire --identity 0x40:0x43787800:0x312E3031:0x09501234
  canctl --bus can0 lss inquire --global      # only when exactly one LSS device is on the bus")]
    Inquire(Target),
    /// Give a device a node-id (1 to 127; 255 takes it away)
    #[command(after_help = "Refuses an id something on the bus already answers to (an SDO answer from another
device, a heartbeat, boot-up or guarding answer heard within 1 s); --force gives it anyway.

Examples:
  canctl --bus sim lss set-id 7 --identity 0x40:0x43787800:0x312E3031:0x09501301
  canctl --bus epos2-usb:/dev/ttyUSB0 lss set-id 3 --node 0   # the EPOS2 itself (object 0x2000)")]
    SetId(SetIdArgs),
    /// Configure a device's bit rate (takes effect at `lss activate`, or stored and reset)
    #[command(after_help = "Examples:
  canctl --bus sim lss set-baud 250k --identity 0x40:0x43787800:0x312E3031:0x09501234
  canctl --bus can0 lss set-baud 1M --global")]
    SetBaud(SetBaudArgs),
    /// Switch configured bit rates on (every device in configuration state at once)
    #[command(after_help = "After activation the devices talk at the new rate: switch the interface too,
e.g. sudo ip link set can0 down && sudo ip link set can0 up type can bitrate 250000

Examples:
  canctl --bus can0 lss activate --global --delay 100")]
    Activate(ActivateArgs),
    /// Make a device keep its LSS node-id and bit rate across power cycles
    #[command(after_help = "Examples:
  canctl --bus sim lss store --identity 0x40:0x43787800:0x312E3031:0x09501234
  canctl --bus epos2-rs232:/dev/ttyS0 lss store --node 0")]
    Store(Target),
    /// Find the identity of a device that has no node-id, bit by bit (CiA 305 fastscan)
    #[command(after_help = "Examples:
  canctl --bus sim lss fastscan
  canctl --bus can0 lss fastscan --vendor 0x40 --product 0x43787800
  canctl --bus can0 lss fastscan --step 60ms --format json")]
    Fastscan(FastscanArgs),
    /// Give every device without a node-id the next free one, and store it
    #[command(after_help = "Finds each device without a node-id by fastscan, gives it the next node-id from
--start on that no node on the bus uses, stores it (unless --no-store) and lets it boot.
Node-ids in use are learned from SDO answers, heartbeats, boot-ups, node guarding and LSS
(it listens for heartbeats first, see --listen), so a Stopped node keeps its id to itself.
The fastscan step is learned from how late the devices answer, and lengthened when answers
come later still; --step fixes it. With no device without a node-id it says so and exits
0 (a provisioning script can run again); when the node-ids up to 127 run out it names the
device left without one and exits 2. Ctrl-C sends every device back to LSS waiting state,
reports what was assigned so far and exits 130. The JSON output is a record for
provisioning logs.

Examples:
  canctl --bus sim lss assign --start 20
  canctl --bus can0 lss assign --start 40 --format json > assigned.json")]
    Assign(AssignArgs),
}

/// Which device: one by identity, all (only when asked), or an EPOS2 reached directly.
#[derive(Args, Debug)]
pub(crate) struct Target {
    /// The device's LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)
    #[arg(long, value_name = "V:P:R:S", value_parser = |s: &str| s.parse::<Identity>(), conflicts_with_all = ["global", "node"])]
    pub identity: Option<Identity>,
    /// Every LSS device on the bus at once (a broadcast)
    #[arg(long, conflicts_with = "node")]
    pub global: bool,
    /// 0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)
    #[arg(long, value_name = "0", value_parser = super::ctx::number_in::<u8>("the EPOS2's own node", 0, 0))]
    pub node: Option<u8>,
}

#[derive(Args, Debug)]
pub(crate) struct SetIdArgs {
    /// The new node-id: 1 to 127, or 255 for none
    #[arg(value_name = "NEW", value_parser = super::ctx::parse_lss_node_id)]
    pub new: u8,
    #[command(flatten)]
    pub target: Target,
    /// Give the id even when something on the bus answers to it already (two devices on
    /// one node-id make both unreachable)
    #[arg(long)]
    pub force: bool,
}

#[derive(Args, Debug)]
pub(crate) struct SetBaudArgs {
    /// 1M 800k 500k 250k 125k 50k 20k 10k, or auto
    #[arg(value_name = "RATE", value_parser = parse_bit_rate, add = ArgValueCandidates::new(super::complete::bit_rates))]
    pub rate: u8,
    #[command(flatten)]
    pub target: Target,
}

#[derive(Args, Debug)]
pub(crate) struct ActivateArgs {
    /// Switch delay in ms: the devices wait this long, switch, and wait as long again
    #[arg(long, value_name = "MS", default_value_t = 100)]
    pub delay: u16,
    #[command(flatten)]
    pub target: Target,
}

/// How fastscan paces itself, and what it already knows.
#[derive(Args, Debug)]
pub(crate) struct FastscanFlags {
    /// Wait this long for each fastscan answer instead of learning it from the devices
    /// (lengthened only if answers come later still)
    #[arg(long, value_name = "DUR", value_parser = super::ctx::parse_duration)]
    pub step: Option<Duration>,
    /// The vendor-id of the device(s) sought, if known: not searched (0x1018:1)
    #[arg(long, value_name = "ID", value_parser = super::ctx::parse_u32)]
    pub vendor: Option<u32>,
    /// The product code, if known: not searched (0x1018:2)
    #[arg(long, value_name = "CODE", value_parser = super::ctx::parse_u32)]
    pub product: Option<u32>,
    /// The revision number, if known: not searched (0x1018:3)
    #[arg(long, value_name = "REV", value_parser = super::ctx::parse_u32)]
    pub revision: Option<u32>,
}

impl FastscanFlags {
    fn options(&self, timeout: Duration) -> FastscanOptions {
        FastscanOptions {
            timeout,
            step: self.step,
            vendor: self.vendor,
            product: self.product,
            revision: self.revision,
        }
    }
}

#[derive(Args, Debug)]
pub(crate) struct FastscanArgs {
    #[command(flatten)]
    pub pace: FastscanFlags,
    /// Refused: an EPOS2 reached directly (node 0) has no LSS
    #[arg(long, value_name = "0", value_parser = super::ctx::number_in::<u8>("the EPOS2's own node", 0, 0))]
    pub node: Option<u8>,
}

#[derive(Args, Debug)]
pub(crate) struct AssignArgs {
    /// The first node-id to give
    #[arg(long, value_name = "N", value_parser = super::ctx::parse_node)]
    pub start: u8,
    #[command(flatten)]
    pub pace: FastscanFlags,
    /// How long to listen for heartbeats before assigning [default: 1s, or longer for the
    /// longest heartbeat period the nodes report]
    #[arg(long, value_name = "DUR", value_parser = super::ctx::parse_duration)]
    pub listen: Option<Duration>,
    /// Do not store the node-ids (they are lost at power-off)
    #[arg(long)]
    pub no_store: bool,
    /// Refused: an EPOS2 reached directly (node 0) has no LSS
    #[arg(long, value_name = "0", value_parser = super::ctx::number_in::<u8>("the EPOS2's own node", 0, 0))]
    pub node: Option<u8>,
}

impl Target {
    /// The device asked for; one must be named, a broadcast only when asked.
    fn get(&self, verb: &str) -> CommandResult<lss::Target> {
        match (self.identity, self.global, self.node) {
            (Some(id), _, _) => Ok(lss::Target::One(id)),
            (None, true, _) => Ok(lss::Target::All),
            (None, false, Some(_)) => Ok(lss::Target::DirectEpos2),
            (None, false, None) => Err(crate::output::UsageError::LssUnnamed(verb.to_string()).into()),
        }
    }
}

/// Refuse `--node 0` where it has no meaning.
fn no_node(node: Option<u8>, verb: &str) -> crate::Result<()> {
    node.map_or(Ok(()), |_| Err(lss::no_lss_on_direct_epos2(verb)))
}

pub(crate) fn run(ctx: &Ctx, bus: &mut dyn Bus, cmd: &LssCommand) -> CommandResult {
    // An interruption is noted and acted on between steps, so that no device is left in
    // configuration state.
    let (t, stop) = (ctx.timeout, &ctx.cancel);
    let set = |bus: &mut dyn Bus, target: &Target, setting: Setting| -> CommandResult {
        let target = target.get(setting.verb())?;
        let done = match setting {
            Setting::BitRate(index) => lss::set_baud(bus, t, target, index, ctx.bus.as_deref(), stop)?,
            _ => lss::configure(bus, t, target, setting, stop)?,
        };
        ctx.report_then(&done, done.interrupted)?;
        Ok(done.outcome()?)
    };
    match cmd {
        LssCommand::Inquire(a) => ctx.out.report(&lss::inquire(bus, t, a.get("inquire")?)?)?,
        LssCommand::SetId(a) => {
            let done = lss::set_id(bus, t, a.target.get("set-id")?, a.new, a.force, stop)?;
            ctx.report_then(&done, done.interrupted)?
        }
        LssCommand::SetBaud(a) => set(bus, &a.target, Setting::BitRate(a.rate))?,
        LssCommand::Store(a) => set(bus, a, Setting::Store)?,
        LssCommand::Activate(a) => {
            let target = a.target.get("activate")?;
            let network = ctx.bus.as_deref();
            ctx.out.report(&lss::activate_on(bus, t, target, a.delay, network, &mut ctx.out.progress())?)?
        }
        LssCommand::Fastscan(a) => {
            no_node(a.node, "fastscan")?;
            ctx.out.report(&lss::fastscan_shown(bus, &a.pace.options(t), stop, &mut ctx.out.progress())?)?
        }
        LssCommand::Assign(a) => {
            no_node(a.node, "assign")?;
            let fastscan = a.pace.options(t);
            let o = AssignOptions { start: a.start, fastscan, listen: a.listen, store: !a.no_store };
            let report = lss::assign(bus, &o, &mut ctx.out.progress(), stop)?;
            ctx.out.report(&report)?;
            report.outcome()?
        }
    }
    // A command that finished its last step anyway still says it was interrupted.
    if ctx.cancel.is_cancelled() {
        return Err(Error::Interrupted.into());
    }
    Ok(())
}
