//! The command line: one clap definition from which help, man pages and completions are
//! all generated, and one module per command.

mod buses;
mod complete;
mod config;
mod docs;
mod doctor;
mod drive;
mod errors;
mod firmware;
mod health;
mod lss;
mod monitor;
mod network;
mod nmt;
mod objects;
mod scan;
mod sdo;
mod sim;
mod store;
mod stream;

use crate::bus::Bus;
use crate::cancel::Cancel;
use crate::connect::{BusAddr, OpenOptions};
use crate::error::Error;
use crate::output::{CommandError, CommandResult, FormatArg, Output, UsageError};
// The value parsers the commands' arguments name (`super::parse_node`).
use crate::settings::parse::{
    parse_fixed_bit_rate, parse_kbit, parse_lss_node_id, parse_nodes, parse_sdo_node, parse_size, parse_state,
    parse_u32,
};
use crate::settings::{number_in, parse_duration, parse_node, parse_timeout};
use crate::settings::{Given, Settings};
use clap::{Args, Parser, Subcommand};
use clap_complete::engine::ArgValueCandidates;
use std::time::Duration;

pub use crate::output::docs::completion_scripts;
pub use complete::complete_from_env;
pub use docs::man_pages;

/// `canctl --version`: what a bug report needs to name the binary exactly (build.rs).
/// `-V` and the man pages keep the plain version, so they do not change with every commit.
const LONG_VERSION: &str =
    concat!(env!("CARGO_PKG_VERSION"), " (commit ", env!("CANCTL_COMMIT"), ", target ", env!("CANCTL_TARGET"), ")");

const EXIT_CODES: &str = "\
Exit codes:
  0    ok
  2    usage: bad arguments, malformed object or value, no bus given
  3    no response or timeout
  4    refused by the device (SDO abort, LSS or EPOS2 error; the code and its meaning are printed)
  5    link failure (cannot open, CRC/framing failure, device gone)
  6    verification failed
  7    output could not be written (disk full, no permission); the old --out file is kept
  130  interrupted (SIGINT, SIGTERM, Ctrl-C/Ctrl-Break), after a report of what was done";

/// canctl's command line, as clap parses it: `main` hands it to [`run`]; its
/// `clap::CommandFactory` is what help, man pages and completions are made from.
#[derive(Parser, Debug)]
#[command(
    name = "canctl",
    version,
    long_version = LONG_VERSION,
    about = "Commission CANopen drives and sensors",
    long_about = "Commission CANopen drives and sensors: find every node, read and write objects, \
drive NMT — over SocketCAN, a maxon EPOS2 on RS232 or USB, or the built-in simulated bus.\n\n\
Try it without hardware: canctl --bus sim scan",
    after_help = EXIT_CODES,
    propagate_version = true
)]
pub struct Cli {
    #[command(flatten)]
    pub(crate) global: GlobalArgs,
    #[command(subcommand)]
    pub(crate) command: Command,
}

impl Cli {
    /// The output format in force: the command's own `--format` (the checks take JUnit
    /// too), else the global one.
    pub fn format(&self) -> FormatArg {
        match &self.command {
            Command::Network(network::NetworkCommand::Check(a)) => a.checks.format,
            Command::Health(a) => a.checks.format,
            Command::Doctor(a) => a.checks.format,
            _ => None,
        }
        .unwrap_or(self.global.format)
    }
}

#[derive(Args, Debug)]
pub(crate) struct GlobalArgs {
    /// The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), slcan:/dev/ttyACM0@500k,
    /// epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0, socketcand:HOST/IFACE or
    /// socketcand:HOST:PORT/IFACE (default: CANCTL_BUS, else the settings file's). Repeat it
    /// for scan, health, network check and firmware status: they work on every bus given,
    /// all at once
    #[arg(long, global = true, env = "CANCTL_BUS", value_name = "URI", action = clap::ArgAction::Append, add = ArgValueCandidates::new(complete::buses))]
    pub bus: Vec<String>,
    /// How long to wait for each answer: 500ms, 2s, 1.5s (a unit is required: us, ms, s, m;
    /// at least 10ms); default 500ms, or the settings file's
    #[arg(long, global = true, value_name = "DUR", value_parser = parse_timeout)]
    pub timeout: Option<Duration>,
    /// Output format
    #[arg(long, global = true, value_enum, default_value = "human")]
    pub format: FormatArg,
    /// An EDS or DCF (or XDD or XDC) describing node NODE, or every node without NODE=
    /// (repeatable): object names, types and ranges come from it
    #[arg(long, global = true, value_name = "[NODE=]FILE", value_parser = objects::parse_eds_arg)]
    pub eds: Vec<crate::settings::EdsFile>,
    /// Trace every frame on stderr in candump notation; -vv also what each procedure does
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    pub verbose: u8,
    /// Tables with every column even on a narrow terminal (they are fitted to its width
    /// otherwise; pipes and files always get every column)
    #[arg(long, global = true)]
    pub wide: bool,
    /// No warnings, diagnostics or progress on stderr (errors still print)
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    pub quiet: bool,
    /// Write every frame sent and received to FILE, in the candump log format of can-utils
    /// (`(1700000000.123456) vcan0 605#4000100000000000`), for support cases
    #[arg(long, global = true, value_name = "FILE")]
    pub log_frames: Option<std::path::PathBuf>,
    /// When a node does not answer, do not look for the likely cause (about a second of
    /// node guarding and a read of every node-id; see canctl doctor)
    #[arg(long, global = true)]
    pub no_diagnose: bool,
}

impl GlobalArgs {
    /// The frame log asked for with --log-frames, created (emptied) now; a failure says the
    /// flag it came from.
    pub(crate) fn frame_log(&self) -> CommandResult<Option<crate::bus::FrameLog>> {
        self.log_frames.as_deref().map(crate::bus::FrameLog::create).transpose().map_err(CommandError::FrameLog)
    }

    /// How a bus is opened: the answers' timeout, and the frame log asked for.
    fn open_options(&self, timeout: Duration) -> CommandResult<OpenOptions> {
        Ok(OpenOptions { frame_log: self.frame_log()?, ..OpenOptions::new(timeout) })
    }
}

#[derive(Subcommand, Debug)]
pub(crate) enum Command {
    Scan(scan::ScanArgs),
    /// Read and write objects (SDO)
    #[command(
        subcommand,
        after_help = "Examples:
  canctl --bus sim sdo read 1 0x1018:1
  canctl --bus sim sdo read 5 ProducerHeartbeatTime
  canctl --bus sim sdo write 5 1017 100 --type u16 --verify"
    )]
    Sdo(sdo::SdoCommand),
    /// Start, stop and reset nodes, or ask their NMT state
    #[command(
        subcommand,
        after_help = "Examples:
  canctl --bus sim nmt state 5
  canctl --bus sim nmt reset 5
  canctl --bus sim nmt start all"
    )]
    Nmt(nmt::NmtCommand),
    /// Node-ids and bit rates over LSS (CiA 305): find, set, store, assign
    #[command(
        subcommand,
        after_help = "Examples:
  canctl --bus sim lss fastscan
  canctl --bus sim lss assign --start 20
  canctl --bus sim lss set-id 7 --identity 0x40:0x43787800:0x312E3031:0x09501234"
    )]
    Lss(lss::LssCommand),
    Store(store::StoreArgs),
    Restore(store::RestoreArgs),
    /// CiA 402 drives: state and flags, enable, disable, quick stop, fault reset
    #[command(
        subcommand,
        after_help = "Examples:
  canctl --bus sim drive status 1
  canctl --bus sim drive enable 1
  canctl --bus sim drive fault-reset 1"
    )]
    Drive(drive::DriveCommand),
    StreamPdo(stream::StreamArgs),
    Monitor(monitor::MonitorArgs),
    /// Configuration files: dump a node to a DCF, compare, apply; check a file (CiA 306)
    #[command(
        subcommand,
        after_help = "Examples:
  canctl --bus sim config dump 5 --out sensor.dcf
  canctl --bus sim config diff 20 sensor.dcf
  canctl --bus sim config apply 20 sensor.dcf --verify --store
  canctl config check sensor.dcf"
    )]
    Config(config::ConfigCommand),
    /// A whole machine from one CiA 306-3 network project (nodelist.cpj + one DCF per node)
    #[command(
        subcommand,
        after_help = "Examples:
  canctl --bus sim network dump machine/
  canctl --bus sim network check machine/ --format junit > check.xml
  canctl --bus sim network apply machine/ --assign"
    )]
    Network(network::NetworkCommand),
    /// CiA 302-3 program download: the state of a device's programs, new firmware onto it
    #[command(
        subcommand,
        after_help = "Examples:\n  canctl --bus sim firmware status 9\n  canctl --bus sim firmware download 9 app.bin"
    )]
    Firmware(firmware::FirmwareCommand),
    Errors(errors::ErrorsArgs),
    Health(health::HealthArgs),
    Doctor(doctor::DoctorArgs),
    Sim(sim::SimArgs),
    Buses(buses::BusesArgs),
    /// Show the settings in force and where each comes from (flags, CANCTL_BUS, canctl.toml)
    #[command(after_help = "Examples:\n  canctl settings\n  canctl --bus sim settings --format json")]
    Settings,
    Completions(docs::CompletionsArgs),
    Man(docs::ManArgs),
}

// The one node a command is for (one definition for every command that takes one node of
// 1 to 127, completed from the last scan).
#[derive(Args, Debug)]
pub(crate) struct Node {
    /// Node-id, 1 to 127
    #[arg(value_parser = parse_node, add = ArgValueCandidates::new(complete::nodes))]
    pub node: u8,
}

// [`Node`] where node 0 is the EPOS2 itself, reached directly (the commands that work on
// it as on any node: sdo, drive).
#[derive(Args, Debug)]
pub(crate) struct SdoNode {
    /// Node-id, 1 to 127 (0: the EPOS2 on an epos2-rs232/epos2-usb bus)
    #[arg(value_parser = parse_sdo_node, add = ArgValueCandidates::new(complete::nodes))]
    pub node: u8,
}

/// Node-ids as one argument, 5,10,20, none named twice (`store`, `restore`, `firmware
/// download`); [`sdo_node_list`] takes the EPOS2's own node 0 too.
fn node_list(text: &str) -> Result<crate::settings::parse::Nodes, String> {
    parse_nodes(text, parse_node)
}

/// [`node_list`] where node 0 is the EPOS2 on an epos2-rs232/epos2-usb bus.
fn sdo_node_list(text: &str) -> Result<crate::settings::parse::Nodes, String> {
    parse_nodes(text, parse_sdo_node)
}

/// `--format` of the commands that check things, which also write JUnit XML. Their own
/// argument, so that only their help and completion offer `junit`; the global `--format`
/// (before the command) takes it too, and the other commands refuse it.
#[derive(Args, Debug)]
pub(crate) struct CheckFormat {
    /// Output format: human, json, csv, or junit (one JUnit test case per node and check,
    /// for CI systems) [default: human]
    #[arg(long = "format", id = "format", value_name = "FORMAT", value_parser = check_formats())]
    pub format: Option<FormatArg>,
}

fn check_formats() -> impl clap::builder::TypedValueParser<Value = FormatArg> {
    use clap::{builder::TypedValueParser as _, ValueEnum};
    clap::builder::PossibleValuesParser::new(["human", "json", "csv", "junit"])
        .map(|s| FormatArg::from_str(&s, false).expect("every listed format is a FormatArg"))
}

/// What every command gets: the output policy, the global settings, the dictionaries.
pub(crate) struct Ctx {
    pub out: Output,
    pub timeout: Duration,
    pub dicts: objects::Dictionaries,
    /// The bus URI in force (flag, CANCTL_BUS or settings file): the first when several are.
    pub bus: Option<String>,
    /// Every bus URI in force, in the order given (several for the commands that take them).
    pub buses: Vec<String>,
    /// The program's request to stop, caught from the start (`main` installs it).
    pub cancel: Cancel,
    /// Whether a node that did not answer is diagnosed (not `--no-diagnose`).
    pub diagnose: bool,
}

impl Ctx {
    /// `f` on `bus`, stopped at the program's request to stop ([`crate::ops::stop::stoppable`]).
    fn stoppable<T>(&self, bus: &mut dyn Bus, f: impl FnOnce(&mut dyn Bus) -> T) -> T {
        crate::ops::stop::stoppable(bus, &self.cancel, f)
    }

    /// What a read-only `command` read with `f`, stoppable; stopped part-way (`not_done`:
    /// what it was reading), its report saying so and an interruption.
    fn read<R>(
        &self,
        bus: &mut dyn Bus,
        command: &str,
        not_done: String,
        f: impl FnOnce(&mut dyn Bus) -> crate::Result<R>,
    ) -> CommandResult<R> {
        crate::output::stopped::read(&self.out, command, not_done, self.stoppable(bus, f))
    }

    /// `report` rendered; then, `interrupted`, the command ends as an interruption.
    fn report_then(&self, report: &impl crate::output::Report, interrupted: bool) -> CommandResult {
        self.out.report(report)?;
        match interrupted {
            true => Err(Error::Interrupted.into()),
            false => Ok(()),
        }
    }
}

/// Run a command that talks to the bus the user named (or say how to name one); the bus
/// is closed whatever the command's outcome, and its error explained ([`explain_failure`]).
fn with_bus(ctx: &Ctx, global: &GlobalArgs, f: impl FnOnce(&mut dyn Bus) -> CommandResult) -> CommandResult {
    let opts = global.open_options(ctx.timeout)?;
    let Some(text) = ctx.bus.as_deref().filter(|b| !b.is_empty()) else {
        let (interfaces, ports) = (crate::connect::can_interfaces(), crate::connect::serial_ports());
        return Err(UsageError::NoBus { interfaces, ports }.into());
    };
    let addr: BusAddr = text.parse()?;
    crate::ops::stop::on_bus(&addr, &opts, &ctx.cancel, f, |bus, e| explain_failure(ctx, bus, e))
}

/// A command given several buses: run on all of them when it is one that works on several, a
/// usage error when it uses a bus otherwise; `None` for the commands that use none.
fn on_buses(ctx: &Ctx, g: &GlobalArgs, command: &Command) -> Option<CommandResult> {
    let run = match command {
        Command::Scan(a) => scan::on_buses(ctx, g, a),
        Command::Health(a) => health::on_buses(ctx, g, a),
        Command::Network(network::NetworkCommand::Check(a)) => network::check_on_buses(ctx, g, a),
        Command::Firmware(firmware::FirmwareCommand::Status(a)) => firmware::status_on_buses(ctx, g, a),
        Command::Config(config::ConfigCommand::Check(_))
        | Command::Buses(_)
        | Command::Settings
        | Command::Completions(_)
        | Command::Man(_) => return None,
        _ => Err(UsageError::SeveralBuses(ctx.buses.clone()).into()),
    };
    Some(run)
}

/// Run `procedure` on every bus given, all at once, each opened as [`with_bus`] opens one (a
/// malformed URI a usage error before any is opened); then one report of them all
/// ([`crate::output::many_buses`]). `outcome` says how a bus's report ends (a node
/// unhealthy: exit 6); the run ends as [`crate::ops::many_buses::exit`] says.
fn on_each_bus<R: crate::output::Report + Send, V: Into<crate::ops::unmet::Shortfall>>(
    ctx: &Ctx,
    g: &GlobalArgs,
    command: &'static str,
    procedure: impl Fn(&str, &mut dyn Bus, &mut dyn crate::ops::Progress) -> Result<R, Error> + Sync,
    outcome: impl Fn(&R) -> Result<(), V>,
) -> CommandResult {
    use crate::output::many_buses::{BusNotes, OnBuses};
    let opts = g.open_options(ctx.timeout)?;
    let addrs = ctx.buses.iter().map(|b| b.parse()).collect::<Result<Vec<BusAddr>, Error>>()?;
    let runs = crate::ops::many_buses::each(&addrs, &opts, &ctx.cancel, |addr, bus| {
        let uri = addr.to_string();
        procedure(&uri, bus, &mut BusNotes { out: &ctx.out, bus: uri.clone() })
    });
    let ended = crate::ops::many_buses::judged(runs, outcome);
    ctx.out.report(&OnBuses { command, runs: &ended })?;
    Ok(crate::ops::many_buses::exit(ended)?)
}

/// The error explained ([`crate::ops::explain`]): the link's failure, a silent node's likely
/// cause and the nodes the last scan saw, or the objects near a missing one.
fn explain_failure(ctx: &Ctx, bus: &mut dyn Bus, e: CommandError) -> CommandError {
    let CommandError::Library(error) = e else { return e };
    let o = crate::ops::explain::ExplainOptions {
        bus: ctx.bus.as_deref(),
        dicts: &ctx.dicts,
        diagnose: ctx.diagnose,
        timeout: ctx.timeout,
    };
    match crate::ops::explain::explain(bus, &error, &o) {
        Some(x) => crate::output::explained(error, x, &ctx.dicts),
        None => error.into(),
    }
}

/// Run a parsed command line; `bus_from_env` says whether `--bus` came from CANCTL_BUS,
/// `cancel` is the program's request to stop (caught from its start).
pub fn run(cli: Cli, bus_from_env: bool, cancel: Cancel) -> CommandResult {
    let g = &cli.global;
    // The library reports through `tracing`; -v/-q choose what reaches stderr.
    crate::output::diagnostics::install(g.verbose, g.quiet);
    let (bus, more_buses) = (g.bus.first().cloned(), g.bus.iter().skip(1).cloned().collect());
    let given = Given { bus, bus_from_env, more_buses, timeout: g.timeout, eds: g.eds.clone() };
    let settings = Settings::resolve(given, crate::settings::load()?);
    let format = cli.format();
    let mut out = Output::for_arg(format, g.quiet);
    if g.wide {
        out.fit = None;
    }
    // `settings` reads no EDS: it is what a user looks at to fix one that cannot be read.
    let dicts = match cli.command {
        Command::Settings => objects::Dictionaries::default(),
        _ => objects::load(&settings.eds)?,
    };
    let ctx = Ctx {
        out,
        timeout: settings.timeout.value,
        dicts,
        bus: settings.bus.as_ref().map(|b| b.value.clone()),
        buses: settings.bus.iter().map(|b| b.value.clone()).chain(settings.more_buses.iter().cloned()).collect(),
        cancel,
        diagnose: !g.no_diagnose,
    };
    let checks = matches!(
        cli.command,
        Command::Network(network::NetworkCommand::Check(_))
            | Command::Health(_)
            | Command::Doctor(_)
            | Command::Firmware(firmware::FirmwareCommand::Download(_))
    );
    if format == FormatArg::Junit && !checks {
        return Err(UsageError::JunitElsewhere.into());
    }
    let dumps = matches!(cli.command, Command::Config(config::ConfigCommand::Dump(_)));
    if g.format == FormatArg::Xdc && !dumps {
        return Err(UsageError::XdcElsewhere.into());
    }
    if ctx.buses.len() > 1 {
        if let Some(done) = on_buses(&ctx, g, &cli.command) {
            return done;
        }
    }
    match &cli.command {
        Command::Scan(args) => with_bus(&ctx, g, |bus| scan::run(&ctx, bus, args)),
        Command::Sdo(cmd) => with_bus(&ctx, g, |bus| sdo::run(&ctx, bus, cmd)),
        Command::Nmt(cmd) => with_bus(&ctx, g, |bus| nmt::run(&ctx, bus, cmd)),
        Command::Lss(cmd) => with_bus(&ctx, g, |bus| lss::run(&ctx, bus, cmd)),
        Command::Store(a) => with_bus(&ctx, g, |bus| store::store(&ctx, bus, a)),
        Command::Restore(a) => with_bus(&ctx, g, |bus| store::restore(&ctx, bus, a)),
        Command::Drive(cmd) => with_bus(&ctx, g, |bus| drive::run(&ctx, bus, cmd)),
        Command::Config(config::ConfigCommand::Check(a)) => config::check(&ctx, a),
        Command::Config(cmd) => with_bus(&ctx, g, |bus| config::run(&ctx, bus, cmd)),
        Command::StreamPdo(a) => with_bus(&ctx, g, |bus| stream::run(&ctx, bus, a)),
        Command::Monitor(a) => with_bus(&ctx, g, |bus| monitor::run(&ctx, bus, a)),
        Command::Network(cmd) => with_bus(&ctx, g, |bus| network::run(&ctx, bus, cmd)),
        Command::Firmware(cmd) => with_bus(&ctx, g, |bus| firmware::run(&ctx, bus, cmd)),
        Command::Errors(a) => with_bus(&ctx, g, |bus| errors::run(&ctx, bus, a)),
        Command::Health(a) => with_bus(&ctx, g, |bus| health::run(&ctx, bus, a)),
        Command::Doctor(a) => doctor::run(&ctx, g, a),
        Command::Sim(args) => sim::run(&ctx, g, args),
        Command::Buses(a) => buses::run(&ctx, a),
        Command::Settings => Ok(ctx.out.report(&settings.report())?),
        Command::Completions(args) => docs::completions(args),
        Command::Man(args) => docs::man(&ctx, args),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clap_definition_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
