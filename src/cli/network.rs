//! `canctl network dump|check|apply`: a whole machine from one CiA 306-3 network project
//! (`nodelist.cpj` plus one DCF per node).

use super::ctx::Ctx;
use crate::bus::Bus;
use crate::canopen::nmt::State;
use crate::ops::config;
use crate::ops::network::{self, PROJECT_FILE};
use crate::ops::project_files;
use crate::output::network::{DumpReport, SetBaudReport};
use crate::output::CommandResult;
use crate::output::NodeBars;
use crate::output::UsageError;
use clap::{Args, Subcommand};
use std::path::{Path, PathBuf};
use std::time::Duration;

#[derive(Subcommand, Debug)]
pub(crate) enum NetworkCommand {
    Dump(DumpArgs),
    Check(CheckArgs),
    Apply(ApplyArgs),
    SetBaud(SetBaudArgs),
}

/// Read every node of the bus into a network project: nodelist.cpj and one DCF per node
///
/// Each node's readable objects go into DIR/nodeN.dcf (as `config dump` reads them), with
/// its [DeviceComissioning]: node-id, name, bit rate (--bit-rate) and LSS serial number
/// (0x1018:4). DIR/nodelist.cpj lists them (CiA 306-3 [Topology]). A known-good machine so
/// becomes the reference the next one is checked against and provisioned from.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim network dump machine/
  canctl --bus can0 network dump machine/ --net-name 'Cabinet A' --bit-rate 500k")]
pub(crate) struct DumpArgs {
    /// The folder to write into (made if missing)
    pub dir: PathBuf,
    /// The network's name in the project (NetName)
    #[arg(long, value_name = "NAME", default_value = "canctl network")]
    pub net_name: String,
    /// The bus's bit rate, written as each DCF's Baudrate (1M 800k 500k 250k 125k 50k 20k 10k)
    #[arg(long, value_name = "RATE", value_parser = super::ctx::parse_kbit)]
    pub bit_rate: Option<u32>,
    #[command(flatten)]
    pub probes: Probes,
    /// Replace a project already in DIR
    #[arg(long)]
    pub force: bool,
}

/// Check the bus against a network project; exit 6 when anything differs
///
/// For each node the project lists: it answers, its vendor-ID and product code (0x1018)
/// are the ones its DCF names, every writable object holds the DCF's value, and (with
/// --state) it is in that NMT state. Then: no
/// node answers that the project does not list, and no device waits for a node-id over LSS.
/// --format junit writes one JUnit test case per node and check, for CI systems.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim network check machine/nodelist.cpj
  canctl --bus can0 network check machine/ --format junit > network-check.xml")]
pub(crate) struct CheckArgs {
    /// The project: a nodelist.cpj, or the folder holding one
    pub project: PathBuf,
    /// Every listed node must also be in this NMT state (from its heartbeat, else node
    /// guarding): operational, pre-operational or stopped
    #[arg(long, value_name = "STATE", value_parser = super::ctx::parse_state)]
    pub state: Option<State>,
    /// How many nodes to check at once, their SDO transfers in flight together (1: one after
    /// the other)
    #[arg(long, value_name = "N", default_value = "8", value_parser = clap::value_parser!(u8).range(1..=127))]
    pub jobs: u8,
    #[command(flatten)]
    pub probes: Probes,
    #[command(flatten)]
    pub checks: super::ctx::CheckFormat,
}

/// Make the bus as a network project says: only what differs is written, verified, stored
///
/// Node by node, as `config apply --verify` does it: values checked against the files'
/// ranges first, a DCF for another device refused, PDOs changed the CiA 301 way. A node
/// written to is then stored (0x1010:1). With --assign, a listed node that does not answer
/// is looked for over LSS by the identity its DCF names (vendor-ID, product code, revision,
/// and [DeviceComissioning] LSS_SerialNumber) and given its node-id, which it stores. A
/// second run writes nothing and says so. Up to --jobs nodes are configured at once (node-ids
/// over LSS first, one device at a time). One node's failure does not stop the others; the
/// first failure decides the exit code.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim network apply machine/nodelist.cpj --assign
  canctl --bus can0 network apply machine/ --dry-run
  canctl --bus can0 network apply machine/ --assign --format json > applied.json")]
pub(crate) struct ApplyArgs {
    /// The project: a nodelist.cpj, or the folder holding one
    pub project: PathBuf,
    /// Give node-ids over LSS to listed nodes that do not answer, found by their DCF's identity
    #[arg(long)]
    pub assign: bool,
    /// Show what would be written, write nothing
    #[arg(long)]
    pub dry_run: bool,
    /// Do not store the parameters of the nodes written to
    #[arg(long)]
    pub no_store: bool,
    /// Apply DCFs even to devices whose vendor-ID or product code differs from the file's
    #[arg(long)]
    pub force: bool,
    /// How long a device may take to store
    #[arg(long, value_name = "DUR", default_value = "5s", value_parser = super::ctx::parse_duration)]
    pub store_timeout: Duration,
    /// Reset the nodes written to (NMT reset node) and wait until each has booted
    #[arg(long)]
    pub reset: bool,
    /// How many nodes to configure at once, their SDO transfers in flight together (1: one
    /// after the other)
    #[arg(long, value_name = "N", default_value = "8", value_parser = clap::value_parser!(u8).range(1..=127))]
    pub jobs: u8,
    /// How long a device given a node-id over LSS, or reset, may take to be back
    #[arg(long, value_name = "DUR", default_value = "3s", value_parser = super::ctx::parse_duration)]
    pub boot_wait: Duration,
    #[command(flatten)]
    pub probes: Probes,
}

/// Switch every device on the bus to a new bit rate (LSS global), then look for each node
///
/// CiA 305, to every LSS device at once: switch to configuration state, configure bit
/// timing, store configuration (--store), activate bit timing with the switch delay (the
/// devices go quiet, switch after the delay and wait as long again before they talk). Then
/// the bus is probed at the new rate and every node that does not answer is named (exit 6):
/// the project's nodes when PROJECT is given, else the nodes found before the switch. A
/// device that refuses the rate stops the switch before anything is activated (exit 4),
/// unless --force. An LSS answer names no device, so refusals are counted; the probe says
/// which node was left behind.
///
/// A CAN interface or an EPOS2 does not change its own bit rate: canctl says what to switch,
/// and cannot look for the nodes at the new rate until it is done.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim network set-baud 250k --global
  canctl --bus sim network set-baud 250k machine/ --global --store --update-project
  canctl --bus can0 network set-baud 1M --global --store --delay 200
    (then: sudo ip link set can0 down && sudo ip link set can0 up type can bitrate 1000000)")]
pub(crate) struct SetBaudArgs {
    /// The new bit rate: 1M 800k 500k 250k 125k 50k 20k 10k
    #[arg(value_name = "RATE", value_parser = super::ctx::parse_fixed_bit_rate, add = clap_complete::engine::ArgValueCandidates::new(super::complete::bit_rates))]
    pub rate: u8,
    /// The project whose nodes must follow: a nodelist.cpj, or the folder holding one
    /// (without it: the nodes that answer before the switch)
    pub project: Option<PathBuf>,
    /// Required: the switch is an LSS broadcast to every device on the bus
    #[arg(long)]
    pub global: bool,
    /// Make the devices keep the new rate across power cycles (LSS store configuration)
    #[arg(long)]
    pub store: bool,
    /// Switch delay in ms: the devices wait this long, switch, and wait as long again
    #[arg(long, value_name = "MS", default_value_t = 100)]
    pub delay: u16,
    /// Activate even when some device refuses the new rate (it is left at the old one)
    #[arg(long)]
    pub force: bool,
    /// Write the new rate into each DCF of PROJECT ([DeviceComissioning] Baudrate) once the
    /// devices switched
    #[arg(long, requires = "project")]
    pub update_project: bool,
    #[command(flatten)]
    pub probes: Probes,
}

// How long the bus must stay quiet after the probes: the same for every network command.
#[derive(Args, Debug)]
pub(crate) struct Probes {
    /// How long the bus must stay quiet after the last answer to the probes
    #[arg(long, value_name = "DUR", default_value = "100ms", value_parser = super::ctx::parse_duration)]
    pub window: Duration,
}

pub(crate) fn run(ctx: &Ctx, bus: &mut dyn Bus, cmd: &NetworkCommand) -> CommandResult {
    match cmd {
        NetworkCommand::Dump(a) => dump(ctx, bus, a),
        NetworkCommand::Check(a) => check(ctx, bus, a),
        NetworkCommand::Apply(a) => apply(ctx, bus, a),
        NetworkCommand::SetBaud(a) => set_baud(ctx, bus, a),
    }
}

fn load(ctx: &Ctx, path: &Path) -> crate::Result<network::Loaded> {
    let loaded = network::load(&project_files::project_file(path))?;
    ctx.out.notes(crate::output::network::load_warning_lines(&loaded));
    Ok(loaded)
}

fn dump(ctx: &Ctx, bus: &mut dyn Bus, a: &DumpArgs) -> CommandResult {
    let project = a.dir.join(PROJECT_FILE);
    if project.exists() && !a.force {
        return Err(UsageError::ProjectExists(project).into());
    }
    let options = network::DumpOptions {
        timeout: ctx.timeout,
        window: a.probes.window,
        net_name: a.net_name.clone(),
        baudrate_kbit: a.bit_rate,
    };
    project_files::check_folder(&a.dir)?;
    let dumped = network::dump(bus, &options, &mut ctx.out.progress())?;
    network::write_project(&a.dir, &dumped)?;
    ctx.out.report(&DumpReport { dumped: &dumped, dir: &a.dir })?;
    Ok(())
}

fn check(ctx: &Ctx, bus: &mut dyn Bus, a: &CheckArgs) -> CommandResult {
    let loaded = load(ctx, &a.project)?;
    let options =
        network::CheckOptions { timeout: ctx.timeout, window: a.probes.window, jobs: a.jobs.into(), state: a.state };
    let report = network::check(bus, &loaded, &options, &mut NodeBars::new(&ctx.out))?;
    ctx.out.report(&report)?;
    Ok(report.outcome()?)
}

/// `network check` on several buses at once (each against the same project): one table,
/// one JUnit suite per bus, the worst exit.
pub(crate) fn check_on_buses(ctx: &Ctx, g: &super::ctx::GlobalArgs, a: &CheckArgs) -> CommandResult {
    let loaded = load(ctx, &a.project)?;
    let options =
        network::CheckOptions { timeout: ctx.timeout, window: a.probes.window, jobs: a.jobs.into(), state: a.state };
    let run = |_: &str, bus: &mut dyn Bus, progress: &mut dyn crate::ops::Progress| {
        network::check(bus, &loaded, &options, progress)
    };
    super::ctx::on_each_bus(ctx, g, "canctl network check", run, |report: &network::Checked| report.outcome())
}

fn apply(ctx: &Ctx, bus: &mut dyn Bus, a: &ApplyArgs) -> CommandResult {
    let loaded = load(ctx, &a.project)?;
    let mut c = config::ApplyOptions::new(ctx.timeout);
    c.dry_run = a.dry_run;
    c.verify = true;
    c.store = !a.no_store;
    c.store_timeout = a.store_timeout;
    c.force = a.force;
    // Each node stops at its next safe point: between two SDO transfers, a PDO change under
    // way rolled back.
    c.interrupted = ctx.cancel.clone();
    let options = network::ApplyOptions {
        config: c,
        assign: a.assign,
        window: a.probes.window,
        boot_wait: a.boot_wait,
        jobs: a.jobs.into(),
        reset: a.reset,
        interrupted: ctx.cancel.clone(),
    };
    // Ctrl-C: no node is begun after it, the nodes under way stop at their next safe point,
    // and the report says for each what was done and the state it is left in.
    let report = network::apply(bus, &loaded, &options, &mut NodeBars::new(&ctx.out))?;
    ctx.out.report(&report)?;
    Ok(report.outcome()?)
}

fn set_baud(ctx: &Ctx, bus: &mut dyn Bus, a: &SetBaudArgs) -> CommandResult {
    if !a.global {
        return Err(UsageError::SetBaudNotGlobal.into());
    }
    let loaded = a.project.as_deref().map(|p| load(ctx, p)).transpose()?;
    let options = network::SetBaudOptions {
        timeout: ctx.timeout,
        window: a.probes.window,
        index: a.rate,
        delay_ms: a.delay,
        store: a.store,
        force: a.force,
        interrupted: ctx.cancel.clone(),
    };
    // Ctrl-C before the activation: every device back to waiting, nothing switched; after
    // it, the switch is finished and reported.
    let report = network::set_baud(bus, loaded.as_ref(), &options, &mut ctx.out.progress())?;
    let followed = match (a.update_project, &loaded) {
        (true, Some(loaded)) => network::follow_switch(loaded, &report, a.rate)?,
        _ => Default::default(),
    };
    let hint = crate::output::switch_hint(ctx.bus.as_deref(), a.rate);
    ctx.out.report(&SetBaudReport { switched: &report, updated: &followed.updated, left: &followed.left, hint })?;
    Ok(report.outcome()?)
}
