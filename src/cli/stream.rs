//! `canctl stream-pdo`: a node's transmit PDOs, decoded into named, typed fields, as a live
//! table, CSV or JSON lines.

use super::ctx::Ctx;
use crate::bus::Bus;
use crate::error::Error;
use crate::ops::pdo::{Session, Stream, StreamOptions};
use crate::ops::stream_setup::{prepare, Prepared, Setup};
use crate::output::CommandResult;
use clap::Args;
use std::time::Duration;

/// Stream a node's transmit PDOs, decoded
///
/// Reads the TPDOs' communication (0x1800+) and mapping (0x1A00+) parameters, builds a
/// decoder for each (names and types from the EDS or the built-in dictionary) and streams
/// the records: a table in a terminal, CSV or JSON lines with a timestamp each. Through an
/// EPOS2, which passes on no traffic, the PDOs are polled with remote frames. Whatever the
/// command changed (--start, --map) is put back when it ends, Ctrl-C included.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim stream-pdo 5 --start --count 100 --format csv > position.csv
  canctl --bus can0 stream-pdo 5 --start --sync 10ms --duration 5s --format json
  canctl --bus sim stream-pdo 1 --start --map 6064:0,606C:0 --event 20")]
pub(crate) struct StreamArgs {
    #[command(flatten)]
    pub node: super::ctx::Node,
    /// Which TPDOs (default: every valid one of 1..4)
    #[arg(long, value_delimiter = ',', value_name = "N,...", value_parser = super::ctx::number_in::<u16>("a TPDO number", 1, 512))]
    pub tpdo: Vec<u16>,
    /// Stop after this many records
    #[arg(long, value_name = "N", conflicts_with = "duration")]
    pub count: Option<u64>,
    /// Stop after this long
    #[arg(long, value_name = "DUR", value_parser = super::ctx::parse_duration)]
    pub duration: Option<Duration>,
    /// Send SYNC at this period (for synchronous PDOs, transmission types 0..240)
    #[arg(long, value_name = "PERIOD", value_parser = super::ctx::parse_duration)]
    pub sync: Option<Duration>,
    /// Put the node in Operational, and back in its former state at the end
    #[arg(long)]
    pub start: bool,
    /// Map these objects into the (first) TPDO for this session: 6064:0,606C:0
    #[arg(long, value_delimiter = ',', value_name = "OBJ,...")]
    pub map: Vec<String>,
    /// With --map: event timer in ms
    #[arg(long, value_name = "MS", requires = "map")]
    pub event: Option<u16>,
    /// With --map: transmission type (1..240 on SYNC, 254/255 by event)
    #[arg(long = "type", value_name = "T", requires = "map")]
    pub transmission: Option<u8>,
    /// Through an EPOS2: how often to poll each PDO
    #[arg(long, value_name = "DUR", default_value = "10ms", value_parser = super::ctx::parse_duration)]
    pub interval: Duration,
}

/// `--map`'s objects, by address or name, with their sizes: from the dictionary, else
/// read once from the node.
pub(crate) fn run(ctx: &Ctx, bus: &mut dyn Bus, a: &StreamArgs) -> CommandResult {
    let mut session = Session::default();
    let result = stream(ctx, bus, a, &mut session);
    // Put back what was changed, whatever ended the stream.
    let restored = session.restore(bus, a.node.node, ctx.timeout);
    ctx.out.notes(restored.as_ref().map_or(Vec::new(), |r| crate::output::records::restored_lines(a.node.node, r)));
    let interrupted = ctx.cancel.is_cancelled();
    result?;
    restored?;
    if interrupted {
        return Err(Error::Interrupted.into());
    }
    Ok(())
}

fn stream(ctx: &Ctx, bus: &mut dyn Bus, a: &StreamArgs, session: &mut Session) -> CommandResult {
    let map = a.map.iter().map(|text| ctx.dicts.resolve(a.node.node, text)).collect::<crate::Result<Vec<_>>>()?;
    let setup = Setup {
        node: a.node.node,
        tpdo: &a.tpdo,
        map,
        event: a.event,
        transmission: a.transmission,
        start: a.start,
        sync: a.sync,
        timeout: ctx.timeout,
    };
    let dict = ctx.dicts.for_node(a.node.node);
    let Prepared { layouts, silence } = prepare(bus, dict, &setup, session, &mut ctx.out.progress())?;
    let opts = StreamOptions {
        count: a.count,
        duration: a.duration,
        sync: a.sync,
        interval: a.interval,
        timeout: ctx.timeout,
        silence: Some(silence),
    };
    let mut stream = Stream::new(bus, a.node.node, &layouts, opts, &ctx.cancel);
    let polled = stream.polling().then_some(a.interval);
    ctx.out.notes(crate::output::records::tpdo_lines(a.node.node, &layouts, polled));
    let mut records = ctx.out.records(a.node.node, &layouts)?;
    let mut progress = ctx.out.progress();
    while let Some(r) = stream.next(bus, &mut progress)? {
        records.write(&r, stream.records() == 1)?;
    }
    records.finish()?;
    ctx.out.note(&format!("{} record(s)", stream.records()));
    Ok(())
}
