//! `canctl config dump|diff|apply`: a node's configuration as a DCF (CiA 306), compared
//! with a file, and made to match one — writing only what differs, in a safe order;
//! `config check`: a file against CiA 306, without a bus.

use super::ctx::Ctx;
use crate::bus::Bus;
use crate::ops::config::{self, ApplyOptions, Dcf};
use crate::ops::Progress as _;
use crate::output::CommandResult;
use clap::{Args, Subcommand};
use std::path::{Path, PathBuf};
use std::time::Duration;

#[derive(Subcommand, Debug)]
pub(crate) enum ConfigCommand {
    Dump(DumpArgs),
    Diff(DiffArgs),
    Apply(ApplyArgs),
    Eds(EdsArgs),
    Check(CheckArgs),
}

/// Check an EDS or DCF against CiA 306: every deviation, with file:line, the rule, and
/// what canctl does with it
///
/// Warnings are deviations read as the file plainly means them (an inline comment, a
/// missing SubNumber, NodeID=0 as a placeholder); errors are what is not used (an object
/// that cannot be understood is left out) or a file that is not an EDS at all. Exit 6 when
/// there are errors, 0 with warnings only. No bus is needed.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl config check drive.eds
  canctl config check machine/node5.dcf --format json")]
pub(crate) struct CheckArgs {
    /// The EDS or DCF
    pub file: PathBuf,
}

/// `config check` needs no bus.
pub(crate) fn check(ctx: &Ctx, a: &CheckArgs) -> CommandResult {
    let report = crate::ops::check::check(&a.file)?;
    ctx.out.report(&report)?;
    Ok(report.check()?)
}

/// Save the EDS a node stores in itself (0x1021)
///
/// Unpacked by the storage format the node names in 0x1022: 0 plain text, 1 a ZIP
/// archive. The file is then usable with --eds. A node without 0x1021 ends with exit 4.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim config eds 1 --out drive.eds
  canctl --bus can0 config eds 5 > sensor.eds")]
pub(crate) struct EdsArgs {
    #[command(flatten)]
    pub node: super::ctx::Node,
    /// Write the EDS here instead of standard output
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Read every readable object of a node into a DCF (or an XDC)
///
/// The objects come from the node's EDS (--eds), else from the built-in dictionary for its
/// profile (0x1000), probed: what the node does not have is left out. DOMAINs are not read.
/// --format xdc, or --out FILE.xdc, writes the CiA 311 XML form (an XDC) instead.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim config dump 10 > io.dcf
  canctl --bus can0 --eds 5=mh.eds config dump 5 --out sensor.dcf
  canctl --bus sim config dump 10 --out io.xdc")]
pub(crate) struct DumpArgs {
    #[command(flatten)]
    pub node: super::ctx::Node,
    /// Write the DCF here instead of standard output (an XDC when FILE ends in .xdc)
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Show where a node differs from a DCF's ParameterValues
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim config diff 10 io.dcf
  canctl --bus can0 config diff 10 io.dcf --check --format json   # exit 6 when they differ")]
pub(crate) struct DiffArgs {
    #[command(flatten)]
    pub node: super::ctx::Node,
    /// The DCF (or XDC, CiA 311)
    pub file: PathBuf,
    /// Exit 6 when anything differs
    #[arg(long)]
    pub check: bool,
}

/// Make a node match a DCF: write only what differs, safely, and prove it
///
/// Values are checked against the file's ranges before anything is written. PDOs are
/// changed the CiA 301 way: COB-ID made invalid, mapping count 0, entries, count, COB-ID
/// back. Each object is reported with its old and new value and what happened; a failure
/// part-way says what was written and what was not.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim config apply 10 io.dcf --dry-run
  canctl --bus can0 config apply 10 io.dcf --verify --store --format json")]
pub(crate) struct ApplyArgs {
    #[command(flatten)]
    pub node: super::ctx::Node,
    /// The DCF (or XDC, CiA 311)
    pub file: PathBuf,
    /// Show what would be written, write nothing
    #[arg(long)]
    pub dry_run: bool,
    /// Store the parameters (0x1010:1) when everything is written
    #[arg(long)]
    pub store: bool,
    /// Read every written object back (exit 6 when one differs)
    #[arg(long)]
    pub verify: bool,
    /// How long the device may take to store
    #[arg(long, value_name = "DUR", default_value = "5s", value_parser = super::ctx::parse_duration)]
    pub store_timeout: Duration,
    /// Apply even when the device's vendor-ID or product code differs from the file's
    #[arg(long)]
    pub force: bool,
}

pub(crate) fn run(ctx: &Ctx, bus: &mut dyn Bus, cmd: &ConfigCommand) -> CommandResult {
    match cmd {
        ConfigCommand::Dump(a) => dump(ctx, bus, a),
        ConfigCommand::Diff(a) => diff(ctx, bus, a),
        ConfigCommand::Apply(a) => apply(ctx, bus, a),
        ConfigCommand::Eds(a) => stored_eds(ctx, bus, a),
        ConfigCommand::Check(a) => check(ctx, a),
    }
}

fn stored_eds(ctx: &Ctx, bus: &mut dyn Bus, a: &EdsArgs) -> CommandResult {
    let limit = crate::input::MAX_EDS_BYTES as usize;
    let read = ctx.stoppable(bus, |bus| crate::ops::stored_eds::read(bus, a.node.node, ctx.timeout, limit));
    crate::output::config::stored_eds(&ctx.out, a.node.node, a.out.as_deref(), ctx.bus.as_deref(), read)
}

fn dump(ctx: &Ctx, bus: &mut dyn Bus, a: &DumpArgs) -> CommandResult {
    if let Some(path) = &a.out {
        crate::atomic::check_writable(path)?;
    }
    let file_name =
        a.out.as_ref().map_or(String::new(), |p| p.file_name().unwrap_or_default().to_string_lossy().into_owned());
    let dictionary = ctx.dicts.eds_for(a.node.node).map(|e| (&e.dict, e.path.as_str()));
    let xdc_named = a.out.as_ref().and_then(|p| p.extension()).is_some_and(|x| x.eq_ignore_ascii_case("xdc"));
    let form = if ctx.out.xdc || xdc_named { config::FileForm::Xdc } else { config::FileForm::Dcf };
    let dump = ctx.stoppable(bus, |bus| {
        config::dump_as(bus, a.node.node, dictionary, &file_name, ctx.timeout, &mut ctx.out.progress(), form)
    });
    crate::output::config::dumped(&ctx.out, a.node.node, a.out.as_deref(), dump)
}

/// The DCF, its warnings said on stderr.
fn read_dcf(path: &Path) -> crate::Result<Dcf> {
    let dcf = Dcf::read(path)?;
    crate::output::say_deviations(dcf.warnings().iter());
    Ok(dcf)
}

fn diff(ctx: &Ctx, bus: &mut dyn Bus, a: &DiffArgs) -> CommandResult {
    let dcf = read_dcf(&a.file)?;
    // Interrupted, the report holds what was compared so far.
    let report = ctx.stoppable(bus, |bus| config::diff(bus, a.node.node, &dcf, ctx.timeout))?;
    ctx.out.report(&report)?;
    if a.check || report.interrupted {
        report.check()?;
    }
    Ok(())
}

fn apply(ctx: &Ctx, bus: &mut dyn Bus, a: &ApplyArgs) -> CommandResult {
    let options = ApplyOptions {
        interrupted: ctx.cancel.clone(),
        timeout: ctx.timeout,
        dry_run: a.dry_run,
        verify: a.verify,
        store: a.store,
        store_timeout: a.store_timeout,
        force: a.force,
        dictionary: ctx.dicts.eds_for(a.node.node).map(|e| (e.dict.clone(), e.path.clone())),
    };
    let dcf = read_dcf(&a.file)?;
    // Seconds of reads and writes on a slow device: counted on the terminal meanwhile.
    let label = format!("node {}: applying {}", a.node.node, a.file.display());
    let mut bars = ctx.out.progress();
    bars.item(&label, crate::ops::ItemStatus::Begun);
    let report = config::apply(&mut crate::ops::counted::counted(bus, &label, &mut bars), a.node.node, &dcf, &options);
    bars.finish();
    let report = report?;
    ctx.out.report(&report)?;
    if let Some(note) = crate::output::applied_failure_note(&report) {
        ctx.out.note(&note);
    }
    Ok(report.outcome()?)
}
