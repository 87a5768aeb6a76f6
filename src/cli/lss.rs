//! `canctl lss`: node-ids and bit rates for devices that have none or share one (CiA 305).

use super::interrupt;
use super::{Ctx, SdoOptions};
use crate::bus::lss::{AssignFailure, LssMaster};
use crate::bus::{Bus, LssWait};
use crate::canopen::lss::{self, FastscanError, Identity, Inquiry, Pace, Request, Response, UNCONFIGURED};
use crate::canopen::ObjAddr;
use crate::error::Error;
use crate::output::Format;
use clap::{Args, Subcommand};
use clap_complete::engine::ArgValueCandidates;
use serde_json::json;
use std::collections::BTreeSet;
use std::time::{Duration, Instant};

#[derive(Subcommand, Debug)]
pub enum LssCommand {
    /// Read a device's identity and node-id
    #[command(after_help = "Examples:
  canctl --bus sim lss inquire --identity 0x40:0x43787800:0x312E3031:0x09501234
  canctl --bus can0 lss inquire --global      # only when exactly one LSS device is on the bus")]
    Inquire(Target),
    /// Give a device a node-id (1 to 127; 255 takes it away)
    #[command(after_help = "Examples:
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
come later still; --step fixes it. Ctrl-C sends every device back to LSS waiting state,
reports what was assigned so far and exits 130. The JSON output is a record for
provisioning logs.

Examples:
  canctl --bus sim lss assign --start 20
  canctl --bus can0 lss assign --start 40 --format json > assigned.json")]
    Assign(AssignArgs),
}

/// Which device: one by identity, all (only when asked), or an EPOS2 reached directly.
#[derive(Args, Debug)]
pub struct Target {
    /// The device's LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)
    #[arg(long, value_name = "V:P:R:S", value_parser = parse_identity, conflicts_with_all = ["global", "node"])]
    pub identity: Option<Identity>,
    /// Every LSS device on the bus at once (a broadcast)
    #[arg(long, conflicts_with = "node")]
    pub global: bool,
    /// 0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)
    #[arg(long, value_name = "0", value_parser = clap::value_parser!(u8).range(0..=0))]
    pub node: Option<u8>,
}

#[derive(Args, Debug)]
pub struct SetIdArgs {
    /// The new node-id: 1 to 127, or 255 for none
    #[arg(value_name = "NEW", value_parser = parse_new_id)]
    pub new: u8,
    #[command(flatten)]
    pub target: Target,
}

#[derive(Args, Debug)]
pub struct SetBaudArgs {
    /// 1M 800k 500k 250k 125k 50k 20k 10k, or auto
    #[arg(value_name = "RATE", value_parser = lss::parse_bit_rate, add = ArgValueCandidates::new(super::complete::bit_rates))]
    pub rate: u8,
    #[command(flatten)]
    pub target: Target,
}

#[derive(Args, Debug)]
pub struct ActivateArgs {
    /// Switch delay in ms: the devices wait this long, switch, and wait as long again
    #[arg(long, value_name = "MS", default_value_t = 100)]
    pub delay: u16,
    #[command(flatten)]
    pub target: Target,
}

/// How fastscan paces itself, and what it already knows.
#[derive(Args, Debug)]
pub struct FastscanOptions {
    /// Wait this long for each fastscan answer instead of learning it from the devices
    /// (lengthened only if answers come later still)
    #[arg(long, value_name = "DUR", value_parser = super::parse_duration)]
    pub step: Option<Duration>,
    /// The vendor-id of the device(s) sought, if known: not searched (0x1018:1)
    #[arg(long, value_name = "ID", value_parser = parse_u32)]
    pub vendor: Option<u32>,
    /// The product code, if known: not searched (0x1018:2)
    #[arg(long, value_name = "CODE", value_parser = parse_u32)]
    pub product: Option<u32>,
    /// The revision number, if known: not searched (0x1018:3)
    #[arg(long, value_name = "REV", value_parser = parse_u32)]
    pub revision: Option<u32>,
}

impl FastscanOptions {
    fn given(&self) -> [Option<u32>; 4] {
        [self.vendor, self.product, self.revision, None]
    }

    /// The step given, or one to learn with a first probe as long as the answer timeout.
    fn pace(&self, timeout: Duration) -> Pace {
        match self.step {
            Some(step) => Pace::fixed(step, timeout),
            None => Pace::measured(timeout),
        }
    }
}

#[derive(Args, Debug)]
pub struct FastscanArgs {
    #[command(flatten)]
    pub pace: FastscanOptions,
    /// Refused: an EPOS2 reached directly (node 0) has no LSS
    #[arg(long, value_name = "0", value_parser = clap::value_parser!(u8).range(0..=0))]
    pub node: Option<u8>,
}

#[derive(Args, Debug)]
pub struct AssignArgs {
    /// The first node-id to give
    #[arg(long, value_name = "N", value_parser = super::parse_node)]
    pub start: u8,
    #[command(flatten)]
    pub pace: FastscanOptions,
    /// How long to listen for heartbeats before assigning [default: 1s, or longer for the
    /// longest heartbeat period the nodes report]
    #[arg(long, value_name = "DUR", value_parser = super::parse_duration)]
    pub listen: Option<Duration>,
    /// Do not store the node-ids (they are lost at power-off)
    #[arg(long)]
    pub no_store: bool,
    /// Refused: an EPOS2 reached directly (node 0) has no LSS
    #[arg(long, value_name = "0", value_parser = clap::value_parser!(u8).range(0..=0))]
    pub node: Option<u8>,
}

fn parse_u32(s: &str) -> Result<u32, String> {
    match s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
        Some(h) => u32::from_str_radix(h, 16),
        None => s.parse(),
    }
    .map_err(|_| format!("'{s}' is not a 32-bit number (decimal, or hex with 0x)"))
}

fn parse_identity(s: &str) -> Result<Identity, String> {
    s.parse()
}

fn parse_new_id(s: &str) -> Result<u8, String> {
    match s.parse::<u16>() {
        Ok(n) if (1..=127).contains(&n) || n == UNCONFIGURED as u16 => Ok(n as u8),
        _ => Err(format!("'{s}' is not a node-id for LSS: use 1 to 127, or 255 to leave the device without one")),
    }
}

fn require_target(t: &Target, verb: &str) -> crate::Result<()> {
    if t.identity.is_none() && !t.global && t.node.is_none() {
        return Err(Error::Usage(format!(
            "say which device `lss {verb}` is for: --identity VENDOR:PRODUCT:REVISION:SERIAL for one, or --global \
             for every LSS device on the bus (a broadcast, so only when you mean it)"
        )));
    }
    Ok(())
}

pub(super) fn identity_json(id: &Identity) -> serde_json::Value {
    json!({ "vendor_id": id.vendor, "product_code": id.product, "revision": id.revision, "serial": id.serial })
}

pub fn run(ctx: &Ctx, bus: &mut dyn Bus, cmd: &LssCommand) -> anyhow::Result<()> {
    // An interruption is noted and acted on between steps, so that no device is left in
    // configuration state.
    interrupt::catch();
    let mut m = LssMaster::new(bus, ctx.timeout);
    let result = match cmd {
        LssCommand::Inquire(t) => inquire(ctx, &mut m, t),
        LssCommand::SetId(a) => configure(ctx, &mut m, &a.target, "set-id", Request::ConfigureNodeId(a.new), a.new),
        LssCommand::SetBaud(a) => configure(
            ctx,
            &mut m,
            &a.target,
            "set-baud",
            Request::ConfigureBitTiming { table: 0, index: a.rate },
            a.rate,
        ),
        LssCommand::Store(t) => configure(ctx, &mut m, t, "store", Request::StoreConfiguration, 0),
        LssCommand::Activate(a) => activate(ctx, &mut m, a),
        LssCommand::Fastscan(a) => fastscan(ctx, &mut m, a),
        LssCommand::Assign(a) => assign(ctx, &mut m, a),
    };
    // A command that finished its last step anyway still says it was interrupted.
    if result.is_ok() && interrupt::requested() {
        return Err(Error::Interrupted.into());
    }
    result
}

fn no_lss_on_direct_epos2(verb: &str) -> Error {
    Error::Usage(format!(
        "an EPOS2 reached directly has no LSS, so `lss {verb} --node 0` cannot be done; \
         set-id, set-baud and store work on it through its own objects, and without --node \
         LSS goes to the devices on the CAN bus behind it"
    ))
}

fn inquire(ctx: &Ctx, m: &mut LssMaster, t: &Target) -> anyhow::Result<()> {
    require_target(t, "inquire")?;
    if t.node.is_some() {
        return Err(no_lss_on_direct_epos2("inquire").into());
    }
    if let Err(e) = m.enter(t.identity.as_ref()) {
        // A late acknowledgement may still have put the device in configuration state.
        m.leave()?;
        return Err(e.into());
    }
    let mut values = Vec::new();
    for q in [Inquiry::Vendor, Inquiry::Product, Inquiry::Revision, Inquiry::Serial, Inquiry::NodeId] {
        let answers = m.ask(Request::Inquire(q), if t.global { LssWait::All } else { LssWait::First })?;
        let found: Vec<u32> = answers
            .iter()
            .filter_map(|a| match a {
                Response::InquiredValue { inquiry, value } if *inquiry == q => Some(*value),
                _ => None,
            })
            .collect();
        match found.as_slice() {
            [v] => values.push(*v),
            [] => {
                m.leave()?;
                return Err(Error::Timeout(format!(
                    "no LSS device answered the inquiry within {} ms",
                    ctx.timeout.as_millis()
                ))
                .into());
            }
            more => {
                m.leave()?;
                return Err(Error::Usage(format!(
                    "{} devices answered the global inquiry: address one with --identity (lss fastscan finds them)",
                    more.len()
                ))
                .into());
            }
        }
    }
    m.leave()?;
    let id = Identity { vendor: values[0], product: values[1], revision: values[2], serial: values[3] };
    let node = (values[4] as u8 != UNCONFIGURED).then_some(values[4] as u8);
    match ctx.out.format {
        Format::Json => {
            ctx.out.json(&json!({ "identity": id.to_string(), "lss": identity_json(&id), "node": node }))?
        }
        Format::Csv => ctx
            .out
            .table(&["identity", "node"], &[vec![id.to_string(), node.map_or(String::new(), |n| n.to_string())]])?,
        Format::Human => {
            ctx.out.print(&format!("{id}  node-id {}", node.map_or("none".to_string(), |n| n.to_string())))?
        }
    }
    Ok(())
}

/// EPOS2 firmware specification, object 0x2001 "CAN Bitrate": 0 = 1 Mbit/s, 1 = 800 k,
/// 2 = 500 k, 3 = 250 k, 4 = 125 k, 5 = 50 k, 6 = 20 k — not the CiA 305 table (there 5 is
/// reserved, 6 = 50 k, 7 = 20 k).
fn epos2_bit_rate_code(cia_index: u8) -> Option<u16> {
    [(0, 0), (1, 1), (2, 2), (3, 3), (4, 4), (6, 5), (7, 6)].iter().find(|(c, _)| *c == cia_index).map(|(_, e)| *e)
}
/// EPOS2 firmware specification: 0x2000 "Node ID", 0x2001 "CAN Bitrate".
const EPOS2_NODE_ID: ObjAddr = ObjAddr::new(0x2000, 0);
const EPOS2_CAN_BIT_RATE: ObjAddr = ObjAddr::new(0x2001, 0);
const STORE_ALL: ObjAddr = ObjAddr::new(0x1010, 1);

/// set-id, set-baud and store on an EPOS2 reached directly: its own objects.
fn configure_direct_epos2(ctx: &Ctx, bus: &mut dyn Bus, verb: &str, value: u8) -> crate::Result<String> {
    let opts = SdoOptions::new(ctx.timeout);
    match verb {
        "set-id" if value == UNCONFIGURED => {
            Err(Error::Usage("an EPOS2 always has a node-id (1 to 127); 255 is for LSS devices".into()))
        }
        "set-id" => {
            bus.sdo_download(0, EPOS2_NODE_ID, &[value], &opts).map(|_| format!("node-id {value} (object 0x2000)"))
        }
        "set-baud" => {
            let code = epos2_bit_rate_code(value).ok_or_else(|| {
                Error::Usage(format!(
                    "the EPOS2 has no {} setting: use 1M 800k 500k 250k 125k 50k or 20k",
                    lss::bit_rate_name(value)
                ))
            })?;
            bus.sdo_download(0, EPOS2_CAN_BIT_RATE, &code.to_le_bytes(), &opts)
                .map(|_| format!("CAN bit rate {} (object 0x2001 = {code})", lss::bit_rate_name(value)))
        }
        _ => bus.sdo_download(0, STORE_ALL, b"save", &opts).map(|_| "parameters stored (0x1010:1)".to_string()),
    }
}

fn configure(ctx: &Ctx, m: &mut LssMaster, t: &Target, verb: &str, req: Request, value: u8) -> anyhow::Result<()> {
    require_target(t, verb)?;
    let (what, devices) = if t.node.is_some() {
        (configure_direct_epos2(ctx, m.bus(), verb, value)?, 1)
    } else {
        let result = m.enter(t.identity.as_ref()).and_then(|_| m.configure(req, verb, t.global));
        m.leave()?;
        let n = result?;
        if interrupt::requested() {
            return Err(Error::Interrupted.into());
        }
        let what = match req {
            Request::ConfigureNodeId(UNCONFIGURED) => "node-id removed (255)".to_string(),
            Request::ConfigureNodeId(id) => format!("node-id {id}"),
            Request::ConfigureBitTiming { index, .. } => {
                format!(
                    "bit rate {} (active after `lss activate`, or after store and a reset)",
                    lss::bit_rate_name(index)
                )
            }
            _ => "LSS configuration stored".to_string(),
        };
        (what, n)
    };
    let target = match (&t.identity, t.node) {
        (Some(id), _) => id.to_string(),
        (None, Some(_)) => "the EPOS2 (node 0)".to_string(),
        (None, None) => "all LSS devices".to_string(),
    };
    match ctx.out.format {
        Format::Json => {
            ctx.out.json(&json!({ "command": verb, "target": target, "result": what, "answers": devices }))?
        }
        Format::Csv => ctx.out.table(&["command", "target", "result"], &[vec![verb.into(), target, what]])?,
        Format::Human => ctx.out.print(&format!("{target}: {what}"))?,
    }
    Ok(())
}

fn activate(ctx: &Ctx, m: &mut LssMaster, a: &ActivateArgs) -> anyhow::Result<()> {
    require_target(&a.target, "activate")?;
    if a.target.node.is_some() {
        return Err(Error::Usage(
            "an EPOS2 reached directly takes its new bit rate when it is stored and reset: use `lss store --node 0`"
                .into(),
        )
        .into());
    }
    if let Err(e) = m.enter(a.target.identity.as_ref()) {
        m.leave()?;
        return Err(e.into());
    }
    m.send(Request::ActivateBitTiming { delay_ms: a.delay })?;
    // CiA 305: the devices wait the delay, switch, and wait as long again before talking.
    std::thread::sleep(Duration::from_millis(2 * a.delay as u64));
    let who = a.target.identity.map_or("all devices in configuration".to_string(), |i| i.to_string());
    let bus = m.bus().describe();
    // The devices are still in configuration state; only a link at the new rate can send
    // them back to waiting.
    let followed = m.bus().follows_bit_rate_switch();
    let msg = if followed {
        m.leave()?;
        format!(
            "configured bit rates activated on {who}; {bus} switched with them, and they are back in LSS waiting state"
        )
    } else {
        format!(
            "configured bit rates activated on {who}. Switch {bus} to the new rate too (e.g. sudo ip link set can0 \
             down && sudo ip link set can0 up type can bitrate 250000); until an LSS command reaches them at the new \
             rate the devices stay in LSS configuration state (every `canctl lss` command ends by sending them \
             back to waiting)"
        )
    };
    match ctx.out.format {
        Format::Json => {
            ctx.out.json(&json!({ "command": "activate", "delay_ms": a.delay, "bus_followed": followed }))?
        }
        _ => ctx.out.print(&msg)?,
    }
    Ok(())
}

fn no_device_error() -> Error {
    Error::Timeout("no device without a node-id answered the fastscan".into())
}

fn fastscan_error(e: FastscanError, pace: &Pace) -> Error {
    let step = pace.longest_step().as_millis();
    match e {
        FastscanError::NoDevice => no_device_error(),
        FastscanError::Unconfirmed(_) => Error::Fastscan { error: e, step: pace.longest_step() },
        FastscanError::NoMatch { part, value } => Error::Timeout(format!(
            "no device without a node-id has {} 0x{value:08X} (waited up to {step} ms a step)",
            ["vendor-id", "product code", "revision", "serial"][part as usize]
        )),
        FastscanError::Lost => Error::Timeout(format!(
            "fastscan: a device without a node-id answered, then stopped answering, even with a {step} ms step"
        )),
    }
}

/// The step used and what it was learned from, for humans.
fn pace_text(pace: &Pace) -> String {
    let step = pace.longest_step().as_millis();
    match pace.slowest() {
        Some(s) => format!("step {step} ms (slowest answer {:.1} ms)", s.as_secs_f64() * 1e3),
        None => format!("step {step} ms"),
    }
}

fn pace_json(pace: &Pace) -> serde_json::Value {
    json!({
        "step_ms": pace.longest_step().as_millis() as u64,
        "slowest_answer_ms": pace.slowest().map(|s| s.as_secs_f64() * 1e3),
        "escalations": pace.escalations(),
    })
}

fn fastscan(ctx: &Ctx, m: &mut LssMaster, a: &FastscanArgs) -> anyhow::Result<()> {
    if a.node.is_some() {
        return Err(no_lss_on_direct_epos2("fastscan").into());
    }
    let start = Instant::now();
    let result = m.fastscan(a.pace.pace(ctx.timeout), a.pace.given(), &mut || !interrupt::requested());
    // The device found is in configuration state: whatever happened, every device goes
    // back to waiting, unchanged.
    let left = m.leave();
    let Some(outcome) = result? else {
        left?;
        return Err(Error::Interrupted.into());
    };
    left?;
    let id = outcome.found.map_err(|e| fastscan_error(e, &outcome.pace))?;
    let steps = outcome.steps;
    let ms = start.elapsed().as_millis();
    let step_ms = outcome.pace.longest_step().as_millis() as u64;
    match ctx.out.format {
        Format::Json => ctx.out.json(&json!({
            "identity": id.to_string(),
            "lss": identity_json(&id),
            "steps": steps,
            "step_ms": step_ms,
            "pace": pace_json(&outcome.pace),
            "elapsed_ms": ms,
        }))?,
        Format::Csv => ctx.out.table(
            &["identity", "steps", "step_ms", "elapsed_ms"],
            &[vec![id.to_string(), steps.to_string(), step_ms.to_string(), ms.to_string()]],
        )?,
        Format::Human => {
            ctx.out.print(&id.to_string())?;
            ctx.out.note(&format!("found in {steps} steps, {ms} ms; {}", pace_text(&outcome.pace)));
        }
    }
    Ok(())
}

/// Default time to listen for heartbeats before assigning: long enough for the common
/// periods (100 ms .. 1 s); longer when a node reports a longer one.
const LISTEN: Duration = Duration::from_secs(1);
const LISTEN_CEILING: Duration = Duration::from_secs(10);
const HEARTBEAT_TIME: ObjAddr = ObjAddr::new(0x1017, 0);

/// Node-ids in use: the SDO probe, then heartbeats, boot-ups and everything else the bus
/// shows while listening. A node in Stopped answers no SDO but still beats.
fn ids_in_use(ctx: &Ctx, bus: &mut dyn Bus, listen: Option<Duration>) -> anyhow::Result<BTreeSet<u8>> {
    let found = super::scan::probe(ctx, bus, ctx.timeout.min(Duration::from_millis(100)))?;
    let mut used: BTreeSet<u8> = found.iter().map(|(n, _)| *n).collect();
    if bus.sees_traffic() {
        let listen = match listen {
            Some(l) => l,
            None => {
                let reads: Vec<(u8, ObjAddr)> = found.iter().map(|(n, _)| (*n, HEARTBEAT_TIME)).collect();
                let mut opts = SdoOptions::new(ctx.timeout);
                opts.size_hint = Some(2);
                let periods = bus.sdo_upload_many(&reads, &opts, &mut |_| {})?;
                let longest = periods
                    .iter()
                    .filter_map(|r| r.as_ref().ok()?.get(..2).map(|b| u16::from_le_bytes([b[0], b[1]])))
                    .max()
                    .unwrap_or(0);
                (Duration::from_millis(longest as u64) * 3 / 2).clamp(LISTEN, LISTEN_CEILING)
            }
        };
        let end = Instant::now() + listen;
        while bus.recv_frame(end)?.is_some() && !interrupt::requested() {}
    }
    used.extend(bus.observed().node_ids());
    Ok(used)
}

fn assign(ctx: &Ctx, m: &mut LssMaster, a: &AssignArgs) -> anyhow::Result<()> {
    if a.node.is_some() {
        return Err(no_lss_on_direct_epos2("assign").into());
    }
    let start = Instant::now();
    // Node-ids already in use: new ones must not collide.
    let used = ids_in_use(ctx, m.bus(), a.listen)?;
    let in_use: Vec<u8> = used.iter().copied().collect();
    let outcome = m.assign(
        a.start,
        used,
        a.pace.pace(ctx.timeout),
        a.pace.given(),
        !a.no_store,
        &mut || !interrupt::requested(),
        &mut |d| ctx.out.note(&format!("{} -> node {}", d.identity, d.node)),
    )?;
    let (done, steps) = (&outcome.assigned, outcome.steps);
    let failure = if outcome.interrupted || interrupt::requested() {
        Some(Error::Interrupted)
    } else {
        outcome.failure.map(|e| match e {
            AssignFailure::Fastscan(f) => fastscan_error(f, &outcome.pace),
            AssignFailure::Refused(e) => e,
        })
    };
    let ms = start.elapsed().as_millis();
    let stored_text = |r: &Result<(), String>| match r {
        Ok(()) => "yes".to_string(),
        Err(e) => e.clone(),
    };
    match ctx.out.format {
        Format::Json => ctx.out.json(&json!({
            "assigned": done.iter().map(|d| json!({
                "identity": d.identity.to_string(),
                "lss": identity_json(&d.identity),
                "node": d.node,
                "stored": d.stored.is_ok(),
                "store_error": d.stored.as_ref().err(),
            })).collect::<Vec<_>>(),
            "in_use_before": in_use,
            "fastscan_steps": steps,
            "step_ms": outcome.pace.longest_step().as_millis() as u64,
            "pace": pace_json(&outcome.pace),
            "elapsed_ms": ms,
            "interrupted": outcome.interrupted,
            "error": failure.as_ref().map(|e| e.to_string()),
        }))?,
        _ => {
            let rows: Vec<Vec<String>> =
                done.iter().map(|d| vec![d.identity.to_string(), d.node.to_string(), stored_text(&d.stored)]).collect();
            ctx.out.table(&["identity", "node", "stored"], &rows)?;
            ctx.out.note(&format!(
                "{} device(s) given a node-id in {ms} ms ({steps} fastscan steps, {})",
                done.len(),
                pace_text(&outcome.pace)
            ));
            if outcome.interrupted {
                ctx.out.note("interrupted: every LSS device was sent back to waiting state");
            }
        }
    }
    if let Some(e) = failure {
        return Err(e.into());
    }
    if done.is_empty() {
        return Err(no_device_error().into());
    }
    Ok(())
}
