//! `canctl sdo read|write`: one object, any size, any type.

use super::{parse_sdo_node, Ctx};
use crate::bus::{Bus, SdoOptions};
use crate::canopen::types::{hex, obvious_unsigned, Value};
use crate::canopen::{DataType, ObjAddr};
use crate::error::Error;
use crate::output::Format;
use clap::{Args, Subcommand};
use clap_complete::engine::ArgValueCandidates;
use serde_json::json;
use std::path::PathBuf;

#[derive(Subcommand, Debug)]
pub enum SdoCommand {
    Read(ReadArgs),
    Write(WriteArgs),
}

/// Read an object (SDO upload)
///
/// Expedited, segmented or block transfer is chosen automatically: strings and domains
/// (--type vs, os, d) are read by block transfer where the device offers it.
/// Without --type the raw bytes are shown with the plain unsigned reading for 1, 2, 4 or
/// 8 bytes.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim sdo read 1 0x1018:1 --type u32
  canctl --bus sim sdo read 10 1008 --type vs
  canctl --bus sim sdo read 1 1F50:1 --type d --out program.bin")]
pub struct ReadArgs {
    /// Node-id, 1 to 127 (0: the EPOS2 on an epos2-rs232/epos2-usb bus)
    #[arg(value_parser = parse_sdo_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: u8,
    /// Object: 0x1018:1, 1018:1 or 1018sub1 (index hex; subindex decimal unless 0x), or a
    /// name from the node's EDS or the built-in dictionary (ProducerHeartbeatTime)
    #[arg(add = ArgValueCandidates::new(super::complete::objects))]
    pub object: String,
    /// Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d (default: the dictionary's)
    #[arg(long = "type", short = 't', value_name = "T", value_parser = parse_type, add = ArgValueCandidates::new(super::complete::types))]
    pub dtype: Option<DataType>,
    /// Write the raw bytes to this file instead of printing them
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Never use block transfer (segmented instead)
    #[arg(long)]
    pub no_block: bool,
    /// Largest value to accept: an upload that grows past it is aborted, and one announced
    /// larger is refused (bytes, or with k, M, G: 1024, 1024², 1024³)
    #[arg(long, value_name = "SIZE", default_value = "1M", value_parser = parse_size)]
    pub max_size: usize,
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
pub struct WriteArgs {
    /// Node-id, 1 to 127 (0: the EPOS2 on an epos2-rs232/epos2-usb bus)
    #[arg(value_parser = parse_sdo_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: u8,
    /// Object: 0x1018:1, 1018:1 or 1018sub1 (index hex; subindex decimal unless 0x), or a
    /// name from the node's EDS or the built-in dictionary (ProducerHeartbeatTime)
    #[arg(add = ArgValueCandidates::new(super::complete::objects))]
    pub object: String,
    /// The value, or @FILE for its raw bytes
    #[arg(allow_hyphen_values = true)]
    pub value: String,
    /// Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d (default: the dictionary's)
    #[arg(long = "type", short = 't', value_name = "T", value_parser = parse_type, add = ArgValueCandidates::new(super::complete::types))]
    pub dtype: Option<DataType>,
    /// Read the object back and compare (exit 6 when it differs)
    #[arg(long)]
    pub verify: bool,
    /// Never use block transfer (segmented instead)
    #[arg(long)]
    pub no_block: bool,
}

fn parse_type(s: &str) -> Result<DataType, String> {
    s.parse()
}

/// A byte count: `4096`, `64k`, `16M`, `1G` (binary multiples; `KiB`, `MB` and the like
/// read the same). At most 4 GiB - 1: CiA 301 sizes are 32-bit.
fn parse_size(s: &str) -> Result<usize, String> {
    let t = s.trim();
    let digits = t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
    let (number, unit) = t.split_at(digits);
    let number: u64 =
        number.parse().map_err(|_| format!("'{s}' is not a size: a number of bytes, e.g. 4096, 64k, 16M"))?;
    let shift = match unit.trim().to_ascii_lowercase().trim_end_matches('b').trim_end_matches('i') {
        "" => 0,
        "k" => 10,
        "m" => 20,
        "g" => 30,
        _ => return Err(format!("'{s}': unknown unit '{unit}' (k, M or G)")),
    };
    let bytes = number.checked_shl(shift).filter(|b| *b <= u64::from(u32::MAX) && b >> shift == number);
    bytes
        .and_then(|b| usize::try_from(b).ok())
        .ok_or_else(|| format!("'{s}' is over 4G - 1 bytes, the largest size CiA 301 can carry"))
}

pub fn run(ctx: &Ctx, bus: &mut dyn Bus, cmd: &SdoCommand) -> anyhow::Result<()> {
    match cmd {
        SdoCommand::Read(a) => read(ctx, bus, a),
        SdoCommand::Write(a) => write(ctx, bus, a),
    }
}

fn is_large(t: Option<DataType>) -> bool {
    matches!(t, Some(DataType::Vs | DataType::Os | DataType::D))
}

fn options(ctx: &Ctx, dtype: Option<DataType>, no_block: bool) -> SdoOptions {
    let mut o = SdoOptions::new(ctx.timeout);
    o.block_upload = !no_block && is_large(dtype);
    o.block_download = !no_block;
    o.size_hint = dtype.and_then(DataType::size);
    o
}

/// The object, its type (given, else the dictionary's) and its name, if known.
fn target(
    ctx: &Ctx,
    node: u8,
    text: &str,
    given: Option<DataType>,
) -> Result<(ObjAddr, Option<DataType>, Option<String>), Error> {
    let (addr, entry) = ctx.dicts.resolve(node, text)?;
    let name = entry.and_then(|_| ctx.dicts.for_node(node).display_name(addr));
    Ok((addr, given.or(entry.map(|e| e.dtype)), name))
}

fn read(ctx: &Ctx, bus: &mut dyn Bus, a: &ReadArgs) -> anyhow::Result<()> {
    let (object, dtype, name) = target(ctx, a.node, &a.object, a.dtype)?;
    let mut opts = options(ctx, dtype, a.no_block);
    opts.max_upload = a.max_size;
    let a = &Resolved { node: a.node, object, dtype, name, out: a.out.clone() };
    let bytes = bus.sdo_upload(a.node, a.object, &opts)?;
    let value = match a.dtype {
        Some(t) => Some(t.decode(&bytes).ok_or_else(|| {
            Error::Usage(format!(
                "node {}: {} holds {} byte(s) ({}), which is not a {t} ({} bytes); try another --type",
                a.node,
                a.object,
                bytes.len(),
                hex(&bytes),
                t.size().unwrap_or(0)
            ))
        })?),
        None => None,
    };
    if let Some(path) = &a.out {
        crate::output::write_atomic(path, &bytes)?;
        return match ctx.out.format {
            Format::Json => Ok(ctx.out.json(&json!({
                "node": a.node, "object": a.object.to_string(), "size": bytes.len(), "file": path.display().to_string()
            }))?),
            Format::Csv => Ok(ctx.out.table(
                &["node", "object", "size", "file"],
                &[vec![a.node.to_string(), a.object.to_string(), bytes.len().to_string(), path.display().to_string()]],
            )?),
            Format::Human => Ok(ctx.out.print(&format!(
                "{} bytes from node {} {} written to {}",
                bytes.len(),
                a.node,
                a.object,
                path.display()
            ))?),
        };
    }
    let plain = obvious_unsigned(&bytes);
    match ctx.out.format {
        Format::Json => ctx.out.json(&json!({
            "node": a.node,
            "object": a.object.to_string(),
            "name": a.name,
            "type": a.dtype.map(|t| t.name()),
            "size": bytes.len(),
            "raw": hex(&bytes),
            "value": match &value { Some(v) => v.to_json(), None => json!(plain) },
        }))?,
        Format::Csv => ctx.out.table(
            &["node", "object", "type", "size", "raw", "value"],
            &[vec![
                a.node.to_string(),
                a.object.to_string(),
                a.dtype.map_or(String::new(), |t| t.name().to_string()),
                bytes.len().to_string(),
                hex(&bytes),
                match &value {
                    Some(v) => v.to_string(),
                    None => plain.map_or(String::new(), |p| p.to_string()),
                },
            ]],
        )?,
        Format::Human => ctx.out.print_value(&match value {
            Some(v) => v.to_string(),
            None => untyped(&bytes),
        })?,
    }
    Ok(())
}

/// Raw bytes, then what they obviously are: `92 01 02 00  (u32 131474 = 0x00020192)`.
fn untyped(bytes: &[u8]) -> String {
    let spaced: Vec<String> = bytes.iter().map(|b| format!("{b:02X}")).collect();
    let mut s = spaced.join(" ");
    if let Some(v) = obvious_unsigned(bytes) {
        let width = bytes.len() * 2;
        s += &format!("  (u{} {v} = 0x{v:0width$X})", bytes.len() * 8);
    } else if !bytes.is_empty() && bytes.iter().all(|b| (0x20..0x7F).contains(b)) {
        s += &format!("  \"{}\"", String::from_utf8_lossy(bytes));
    } else if bytes.is_empty() {
        s = "(empty)".into();
    }
    s
}

fn write(ctx: &Ctx, bus: &mut dyn Bus, args: &WriteArgs) -> anyhow::Result<()> {
    let (object, dtype, _) = target(ctx, args.node, &args.object, args.dtype)?;
    let Some(dtype) = dtype else {
        return Err(Error::Usage(format!(
            "--type is needed to encode '{}' for {object} (no dictionary entry; --eds gives one): \
             one of b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d",
            args.value
        ))
        .into());
    };
    let a = &WriteTarget { node: args.node, object, verify: args.verify };
    let bytes = value_bytes(dtype, &args.value)?;
    if let Some(entry) = ctx.dicts.for_node(a.node).get(object).filter(|e| e.dtype == dtype) {
        check_range(entry, &bytes)?;
    }
    let mut opts = options(ctx, Some(dtype), args.no_block);
    // The read-back of --verify takes back as much as was written.
    opts.max_upload = opts.max_upload.max(bytes.len());
    bus.sdo_download(a.node, a.object, &bytes, &opts)?;
    if a.verify {
        let back = bus.sdo_upload(a.node, a.object, &opts)?;
        if back != bytes {
            return Err(Error::Verify(format!(
                "node {}: {} reads back {} after writing {}",
                a.node,
                a.object,
                shown(dtype, &back),
                shown(dtype, &bytes)
            ))
            .into());
        }
    }
    let value = shown(dtype, &bytes);
    match ctx.out.format {
        Format::Json => ctx.out.json(&json!({
            "node": a.node, "object": a.object.to_string(), "type": dtype.name(), "size": bytes.len(),
            "value": dtype.decode(&bytes).map(|v| v.to_json()), "verified": a.verify,
        }))?,
        Format::Csv => ctx.out.table(
            &["node", "object", "type", "size", "value", "verified"],
            &[vec![
                a.node.to_string(),
                a.object.to_string(),
                dtype.name().to_string(),
                bytes.len().to_string(),
                value,
                a.verify.to_string(),
            ]],
        )?,
        Format::Human => {
            let what = if a.verify { "written and verified" } else { "written" };
            let shown = if bytes.len() > 32 { format!("{} bytes", bytes.len()) } else { value };
            ctx.out.print(&format!("node {} {} = {shown} ({dtype}): {what}", a.node, a.object))?
        }
    }
    Ok(())
}

struct Resolved {
    node: u8,
    object: ObjAddr,
    dtype: Option<DataType>,
    name: Option<String>,
    out: Option<PathBuf>,
}

struct WriteTarget {
    node: u8,
    object: ObjAddr,
    verify: bool,
}

use crate::ops::check_range;

fn shown(dtype: DataType, bytes: &[u8]) -> String {
    dtype.decode(bytes).map_or_else(|| hex(bytes), |v: Value| v.to_string())
}

/// The bytes VALUE stands for: `@FILE` (`@-` for stdin) or text parsed by type.
fn value_bytes(dtype: DataType, value: &str) -> Result<Vec<u8>, Error> {
    if let Some(path) = value.strip_prefix('@') {
        let data = crate::input::read_value_file(path, crate::input::VALUE, crate::input::VALUE_IDLE_LIMIT)?;
        if let Some(size) = dtype.size() {
            if data.len() != size {
                return Err(Error::Usage(format!("{path} holds {} bytes; a {dtype} is {size}", data.len())));
            }
        }
        return Ok(data);
    }
    dtype.parse(value).map_err(|e| Error::Usage(e.0))
}

#[cfg(test)]
mod tests {
    use super::parse_size;

    #[test]
    fn sizes_parse_in_binary_multiples_up_to_32_bits() {
        assert_eq!(parse_size("4096"), Ok(4096));
        assert_eq!(parse_size("64k"), Ok(64 << 10));
        assert_eq!(parse_size("16M"), Ok(16 << 20));
        assert_eq!(parse_size("16MiB"), Ok(16 << 20));
        assert_eq!(parse_size("1G"), Ok(1 << 30));
        assert_eq!(parse_size("4294967295"), Ok(u32::MAX as usize));
        assert!(parse_size("4G").unwrap_err().contains("over 4G - 1"));
        assert!(parse_size("2x").unwrap_err().contains("unknown unit"));
        assert!(parse_size("M").is_err());
        assert!(parse_size("99999999999999999999999").is_err());
    }
}
