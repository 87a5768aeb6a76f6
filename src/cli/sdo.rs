//! `canctl sdo read|write`: one object, any size, any type.

use super::ctx::Ctx;
use crate::bus::Bus;
use crate::canopen::DataType;
use crate::ops::sdo::{self, ReadOptions, WriteOptions};
use crate::output::CommandResult;
use clap::{Args, Subcommand};
use clap_complete::engine::ArgValueCandidates;
use std::path::PathBuf;

#[derive(Subcommand, Debug)]
pub(crate) enum SdoCommand {
    Read(ReadArgs),
    Write(WriteArgs),
}

/// Read an object (SDO upload)
///
/// Expedited, segmented or block transfer is chosen automatically: strings and domains
/// (--type vs, os, d) are read by block transfer where the device offers it.
/// Without --type the dictionary's type decodes it; an object no dictionary knows is shown
/// as raw bytes with the plain unsigned reading for 1, 2, 4 or 8 bytes.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim sdo read 1 0x1018:1 --type u32
  canctl --bus sim sdo read 10 1008 --type vs
  canctl --bus sim sdo read 1 1F50:1 --type d --out program.bin")]
pub(crate) struct ReadArgs {
    #[command(flatten)]
    pub node: super::ctx::SdoNode,
    /// Object: 0x1018:1, 1018:1 or 1018sub1 (index hex; subindex decimal unless 0x), or a
    /// name from the node's EDS or the built-in dictionary (ProducerHeartbeatTime)
    #[arg(add = ArgValueCandidates::new(super::complete::objects))]
    pub object: String,
    #[command(flatten)]
    pub dtype: Type,
    /// Write the raw bytes to this file instead of printing them
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Never use block transfer (segmented instead)
    #[arg(long)]
    pub no_block: bool,
    /// Largest value to accept: an upload that grows past it is aborted, and one announced
    /// larger is refused (bytes, or with k, M, G: 1024, 1024², 1024³); by default 64k, for
    /// a domain (--type d) or a value of unknown type 1M
    #[arg(long, value_name = "SIZE", value_parser = super::ctx::parse_size)]
    pub max_size: Option<usize>,
}

/// Write an object (SDO download)
///
/// VALUE is parsed by --type: integers in decimal or 0x hex (with a sign for signed types),
/// reals as decimals, vs as text, os and d as hex bytes. @FILE reads the bytes from a file
/// (@- from standard input). Block transfer is used for 64 bytes and more where the device
/// offers it.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim sdo write 5 1017 100 --type u16 --verify
  canctl --bus sim sdo write 1 0x607A:0 -2000 --type i32
  canctl --bus sim sdo write 1 1F50:1 @program.bin --type d")]
pub(crate) struct WriteArgs {
    #[command(flatten)]
    pub node: super::ctx::SdoNode,
    /// Object: 0x1018:1, 1018:1 or 1018sub1 (index hex; subindex decimal unless 0x), or a
    /// name from the node's EDS or the built-in dictionary (ProducerHeartbeatTime)
    #[arg(add = ArgValueCandidates::new(super::complete::objects))]
    pub object: String,
    /// The value, or @FILE for its raw bytes
    #[arg(allow_hyphen_values = true)]
    pub value: String,
    #[command(flatten)]
    pub dtype: Type,
    /// Read the object back and compare (exit 6 when it differs)
    #[arg(long)]
    pub verify: bool,
    /// Never use block transfer (segmented instead)
    #[arg(long)]
    pub no_block: bool,
}

// `--type`, the same for reading and writing.
#[derive(Args, Debug)]
pub(crate) struct Type {
    /// Data type: b u8..u64 i8..i64 (also 24, 40, 48, 56 bits) r32 r64 t td vs us os d (default: the dictionary's)
    #[arg(long = "type", short = 't', value_name = "T", value_parser = parse_type, add = ArgValueCandidates::new(super::complete::types))]
    pub dtype: Option<DataType>,
}

fn parse_type(s: &str) -> Result<DataType, String> {
    s.parse()
}

pub(crate) fn run(ctx: &Ctx, bus: &mut dyn Bus, cmd: &SdoCommand) -> CommandResult {
    ctx.stoppable(bus, |bus| match cmd {
        SdoCommand::Read(a) => read(ctx, bus, a),
        SdoCommand::Write(a) => write(ctx, bus, a),
    })
}

fn read(ctx: &Ctx, bus: &mut dyn Bus, a: &ReadArgs) -> CommandResult {
    let (object, _) = ctx.dicts.resolve(a.node.node, &a.object)?;
    if let Some(path) = &a.out {
        crate::atomic::check_writable(path)?;
    }
    let o = ReadOptions { timeout: ctx.timeout, dtype: a.dtype.dtype, block: !a.no_block, max_size: a.max_size };
    let read =
        sdo::read_watched(bus, ctx.dicts.for_node(a.node.node), a.node.node, object, &o, &mut ctx.out.progress());
    // What the transfer showed of the node's objects, for completion.
    crate::ops::scan_cache::note(ctx.bus.as_deref(), a.node.node, object, &read);
    let read = match read {
        Err(e) => return crate::output::stopped::sdo(&ctx.out, (a.node.node, object, false), a.out.as_deref(), e),
        Ok(read) => read,
    };
    match &a.out {
        Some(path) => ctx.out.report(&read.save(path)?)?,
        None => ctx.out.report(&read)?,
    }
    Ok(())
}

fn write(ctx: &Ctx, bus: &mut dyn Bus, a: &WriteArgs) -> CommandResult {
    let (object, _) = ctx.dicts.resolve(a.node.node, &a.object)?;
    let o = WriteOptions { timeout: ctx.timeout, dtype: a.dtype.dtype, block: !a.no_block, verify: a.verify };
    let written = sdo::write(bus, ctx.dicts.for_node(a.node.node), a.node.node, object, &a.value, &o);
    crate::ops::scan_cache::note(ctx.bus.as_deref(), a.node.node, object, &written);
    let written = match written {
        Err(e) => return crate::output::stopped::sdo(&ctx.out, (a.node.node, object, true), None, e),
        Ok(written) => written,
    };
    ctx.report_then(&written, written.interrupted)
}
