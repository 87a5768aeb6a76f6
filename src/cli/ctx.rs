//! What every command's arguments and run share: the global flags, one node or several,
//! the checks' `--format`, the context a command runs in ([`Ctx`]) and the bus it opens.

use super::{complete, objects};
use crate::bus::Bus;
use crate::cancel::Cancel;
use crate::connect::{BusAddr, OpenOptions};
use crate::error::Error;
use crate::output::{CommandError, CommandResult, FormatArg, Output, UsageError};
// The value parsers the commands' arguments name (`ctx::parse_node`).
pub(super) use crate::settings::parse::{
    parse_fixed_bit_rate, parse_kbit, parse_lss_node_id, parse_nodes, parse_sdo_node, parse_size, parse_state,
    parse_u32,
};
pub(super) use crate::settings::{number_in, parse_duration, parse_node, parse_timeout};
use clap::Args;
use clap_complete::engine::ArgValueCandidates;
use std::time::Duration;

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
    pub(super) fn frame_log(&self) -> CommandResult<Option<crate::bus::FrameLog>> {
        self.log_frames.as_deref().map(crate::bus::FrameLog::create).transpose().map_err(CommandError::FrameLog)
    }

    /// How a bus is opened: the answers' timeout, and the frame log asked for.
    pub(super) fn open_options(&self, timeout: Duration) -> CommandResult<OpenOptions> {
        Ok(OpenOptions { frame_log: self.frame_log()?, ..OpenOptions::new(timeout) })
    }
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
pub(super) fn node_list(text: &str) -> Result<crate::settings::parse::Nodes, String> {
    parse_nodes(text, parse_node)
}

/// [`node_list`] where node 0 is the EPOS2 on an epos2-rs232/epos2-usb bus.
pub(super) fn sdo_node_list(text: &str) -> Result<crate::settings::parse::Nodes, String> {
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
    pub(super) fn stoppable<T>(&self, bus: &mut dyn Bus, f: impl FnOnce(&mut dyn Bus) -> T) -> T {
        crate::ops::stop::stoppable(bus, &self.cancel, f)
    }

    /// What a read-only `command` read with `f`, stoppable; stopped part-way (`not_done`:
    /// what it was reading), its report saying so and an interruption.
    pub(super) fn read<R>(
        &self,
        bus: &mut dyn Bus,
        command: &str,
        not_done: String,
        f: impl FnOnce(&mut dyn Bus) -> crate::Result<R>,
    ) -> CommandResult<R> {
        crate::output::stopped::read(&self.out, command, not_done, self.stoppable(bus, f))
    }

    /// `report` rendered; then, `interrupted`, the command ends as an interruption.
    pub(super) fn report_then(&self, report: &impl crate::output::Report, interrupted: bool) -> CommandResult {
        self.out.report(report)?;
        match interrupted {
            true => Err(Error::Interrupted.into()),
            false => Ok(()),
        }
    }
}

/// Run a command that talks to the bus the user named (or say how to name one); the bus
/// is closed whatever the command's outcome, and its error explained ([`explain_failure`]).
pub(super) fn with_bus(ctx: &Ctx, global: &GlobalArgs, f: impl FnOnce(&mut dyn Bus) -> CommandResult) -> CommandResult {
    let opts = global.open_options(ctx.timeout)?;
    let Some(text) = ctx.bus.as_deref().filter(|b| !b.is_empty()) else {
        let (interfaces, ports) = (crate::connect::can_interfaces(), crate::connect::serial_ports());
        return Err(UsageError::NoBus { interfaces, ports }.into());
    };
    let addr: BusAddr = text.parse()?;
    crate::ops::stop::on_bus(&addr, &opts, &ctx.cancel, f, |bus, e| explain_failure(ctx, bus, e))
}

/// Run `procedure` on every bus given, all at once, each opened as [`with_bus`] opens one (a
/// malformed URI a usage error before any is opened); then one report of them all
/// ([`crate::output::many_buses`]). `outcome` says how a bus's report ends (a node
/// unhealthy: exit 6); the run ends as [`crate::ops::many_buses::exit`] says.
pub(super) fn on_each_bus<R: crate::output::Report + Send, V: Into<crate::ops::unmet::Shortfall>>(
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
