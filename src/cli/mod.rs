//! The command line: one clap definition from which help, man pages and completions are
//! all generated, and one module per command.
mod buses;
mod complete;
mod config;
mod ctx;
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
use crate::cancel::Cancel;
use crate::output::{CommandResult, FormatArg, Output, UsageError};
use crate::settings::{Given, Settings};
use clap::{CommandFactory, Parser, Subcommand};
use ctx::{with_bus, Ctx, GlobalArgs};

pub use crate::output::docs::completion_scripts;

/// Answer the shell's completion request (`COMPLETE=bash|zsh|fish|...`) and exit; without
/// one, return (`output::completion::complete_from_env`).
pub fn complete_from_env() {
    crate::output::completion::complete_from_env(Cli::command)
}

/// Every man page: `canctl.1`, then `canctl-sdo-read.1` and so on for each subcommand.
pub fn man_pages() -> Vec<(String, Vec<u8>)> {
    crate::output::docs::man_pages(Cli::command())
}

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
        Command::Man(args) => docs::man(&ctx, args, man_pages()),
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
