//! `canctl firmware`: CiA 302-3 program download and the state of a device's programs.

use super::ctx::Ctx;
use crate::bus::Bus;
use crate::ops::firmware::{self, DownloadOptions};
use crate::output::CommandResult;
use clap::{Args, Subcommand};
use clap_complete::engine::ArgValueCandidates;
use std::path::PathBuf;

/// The largest image read: far beyond any microcontroller's flash, short of a mistake.
const IMAGE: crate::input::Limit = crate::input::Limit { bytes: 64 << 20, what: "a firmware image" };

#[derive(Subcommand, Debug)]
pub(crate) enum FirmwareCommand {
    /// Program control (0x1F51), software identification (0x1F56) and flash status (0x1F57,
    /// by meaning) for each program the device has
    #[command(after_help = "Examples:\n  canctl --bus sim firmware status 9")]
    Status(StatusArgs),
    /// Download an image into a device's program (CiA 302-3) and start it, each step confirmed
    ///
    /// Reads 0x1F56 and stops when the device already runs the image (its CRC-32, or
    /// --expect-id); else NMT pre-operational, stop (0x1F51 = 0; a device that reboots into
    /// its bootloader instead is waited for), clear (3) and the flash status (0x1F57) polled
    /// until the erase is done, the image by SDO block transfer (segmented where the device
    /// refuses blocks) into 0x1F50, 0x1F57 polled again and read by meaning, 0x1F56 compared
    /// with the image, start (1; a reset before the answer is expected), the boot-up and a
    /// heartbeat waited for, and confirm (0x80) when the new program asks for it. Stopped or
    /// failed, the report says where the device is; the same command finishes the job.
    #[command(after_help = "Examples:
  canctl --bus sim firmware download 9 app.bin
  canctl --bus can0 firmware download 5 app.bin --program 2 --force
  canctl --bus can0 --format junit firmware download 5,6,7 app.bin --jobs 3 > firmware.xml")]
    Download(DownloadArgs),
}

#[derive(Args, Debug)]
pub(crate) struct StatusArgs {
    #[command(flatten)]
    pub node: super::ctx::Node,
}

#[derive(Args, Debug)]
pub(crate) struct DownloadArgs {
    /// Node-id, 1 to 127; several separated by commas (5,6,7) are done one after another
    /// (or --jobs at once), with a report (and with --format junit a test case) for each
    #[arg(value_name = "NODE", value_parser = super::ctx::node_list, add = ArgValueCandidates::new(super::complete::nodes))]
    pub nodes: crate::settings::parse::Nodes,
    /// The image: the bytes written to 0x1F50 as they are in the file
    #[arg(value_name = "IMAGE")]
    pub image: PathBuf,
    /// The program number (sub-index of 0x1F50, 0x1F51, 0x1F56, 0x1F57)
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = super::ctx::number_in::<u8>("a program number", 1, 254))]
    pub program: u8,
    /// Download even when the device already runs this image
    #[arg(long)]
    pub force: bool,
    /// The identification the device shows in 0x1F56 for this image, when it is not the
    /// image's CRC-32 (e.g. 0x01020300)
    #[arg(long, value_name = "ID", value_parser = super::ctx::number_in::<u32>("an identification", 0, u32::MAX as u64))]
    pub expect_id: Option<u32>,
    /// How long the device may stay busy erasing or writing its flash (0x1F57 bit 0)
    #[arg(long, value_name = "DUR", default_value = "60s", value_parser = super::ctx::parse_duration)]
    pub busy_wait: std::time::Duration,
    /// Leave a new program that asks for confirmation (0x1F51 reads 0x80) unconfirmed: its
    /// bootloader returns to the old one at the next reset
    #[arg(long)]
    pub no_confirm: bool,
    /// How many of the nodes to do at once: their erases and waits overlap, their program data
    /// takes turns on the bus; 1: one after the other
    #[arg(long, value_name = "N", default_value = "1", value_parser = clap::value_parser!(u8).range(1..=127))]
    pub jobs: u8,
}

pub(crate) fn run(ctx: &Ctx, bus: &mut dyn Bus, cmd: &FirmwareCommand) -> CommandResult {
    match cmd {
        FirmwareCommand::Status(a) => {
            let what = format!("reading node {}'s program objects", a.node.node);
            let status =
                ctx.read(bus, "firmware status", what, |bus| firmware::status(bus, a.node.node, ctx.timeout))?;
            Ok(ctx.out.report(&status)?)
        }
        FirmwareCommand::Download(a) => download(ctx, bus, a),
    }
}

/// `firmware status NODE` on several buses at once: the node's programs on each.
pub(crate) fn status_on_buses(ctx: &Ctx, g: &super::ctx::GlobalArgs, a: &StatusArgs) -> CommandResult {
    let run =
        |_: &str, bus: &mut dyn Bus, _: &mut dyn crate::ops::Progress| firmware::status(bus, a.node.node, ctx.timeout);
    super::ctx::on_each_bus(ctx, g, "canctl firmware status", run, |_| Ok::<(), crate::Error>(()))
}

fn download(ctx: &Ctx, bus: &mut dyn Bus, a: &DownloadArgs) -> CommandResult {
    let image = crate::input::read_regular_file(&a.image, IMAGE).map_err(crate::Error::from)?;
    // Each transfer's bytes are a bar of `steps`, one transfer at a time (several at once,
    // each node's start and end are told instead).
    let mut steps = ctx.out.progress();
    let mut o = DownloadOptions::new(ctx.timeout);
    o.program = a.program;
    o.force = a.force;
    o.expect_id = a.expect_id;
    o.busy_wait = a.busy_wait;
    o.confirm = !a.no_confirm;
    o.cancel = Some(ctx.cancel.clone());
    if let [node] = a.nodes.0[..] {
        if !ctx.out.junit {
            let result = ctx.stoppable(bus, |bus| firmware::download(bus, node, &image, &o, &mut steps));
            crate::ops::Progress::finish(&mut steps);
            return match result {
                Ok(report) => Ok(ctx.out.report(&report)?),
                Err(failed) => {
                    ctx.out.report(failed.report.as_ref())?;
                    Err(failed.error.into())
                }
            };
        }
    }
    let batch =
        ctx.stoppable(bus, |bus| firmware::download_jobs(bus, &a.nodes.0, &image, &o, usize::from(a.jobs), &mut steps));
    crate::ops::Progress::finish(&mut steps);
    ctx.out.report(&batch)?;
    match batch.into_failure() {
        Some(e) => Err(e.into()),
        None => Ok(()),
    }
}
