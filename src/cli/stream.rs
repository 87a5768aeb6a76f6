//! `canctl stream-pdo`: a node's transmit PDOs, decoded into named, typed fields, as a live
//! table, CSV or JSON lines.

use super::{parse_node, Ctx};
use crate::bus::{Bus, SdoOptions};
use crate::canopen::nmt::{self, Command};
use crate::canopen::pdo::{self, Field, Layout, RecordWriter};
use crate::canopen::{abort, DataType, ObjAddr};
use crate::error::Error;
use crate::frame::Frame;
use crate::output::Format;
use clap::Args;
use clap_complete::engine::ArgValueCandidates;
use std::collections::{BTreeMap, BTreeSet};
use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

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
pub struct StreamArgs {
    /// Node-id, 1..127
    #[arg(value_parser = parse_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: u8,
    /// Which TPDOs (default: every valid one of 1..4)
    #[arg(long, value_delimiter = ',', value_name = "N,...", value_parser = clap::value_parser!(u16).range(1..=512))]
    pub tpdo: Vec<u16>,
    /// Stop after this many records
    #[arg(long, value_name = "N", conflicts_with = "duration")]
    pub count: Option<u64>,
    /// Stop after this long
    #[arg(long, value_name = "DUR", value_parser = super::parse_duration)]
    pub duration: Option<Duration>,
    /// Send SYNC at this period (for synchronous PDOs, transmission types 0..240)
    #[arg(long, value_name = "PERIOD", value_parser = super::parse_duration)]
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
    #[arg(long, value_name = "DUR", default_value = "10ms", value_parser = super::parse_duration)]
    pub interval: Duration,
}

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

extern "C" fn on_sigint(_: nix::libc::c_int) {
    INTERRUPTED.store(true, Ordering::SeqCst);
}

/// Ctrl-C ends the stream (and what it changed is put back) instead of the process.
fn catch_interrupt() {
    use nix::sys::signal::{sigaction, SaFlags, SigAction, SigHandler, SigSet, Signal};
    let action = SigAction::new(SigHandler::Handler(on_sigint), SaFlags::empty(), SigSet::empty());
    // SAFETY: the handler only stores to an atomic.
    let _ = unsafe { sigaction(Signal::SIGINT, &action) };
}

fn read_u32(ctx: &Ctx, bus: &mut dyn Bus, node: u8, addr: ObjAddr) -> crate::Result<u32> {
    let mut o = SdoOptions::new(ctx.timeout);
    o.size_hint = Some(4);
    let v = bus.sdo_upload(node, addr, &o)?;
    Ok(u32::from_le_bytes(v.get(..4).and_then(|b| b.try_into().ok()).unwrap_or([0; 4])))
}

fn read_u8(ctx: &Ctx, bus: &mut dyn Bus, node: u8, addr: ObjAddr) -> crate::Result<u8> {
    let mut o = SdoOptions::new(ctx.timeout);
    o.size_hint = Some(1);
    Ok(bus.sdo_upload(node, addr, &o)?.first().copied().unwrap_or(0))
}

/// Writes in the safe PDO order of `config apply`.
fn write_plan(
    ctx: &Ctx,
    bus: &mut dyn Bus,
    node: u8,
    changes: &BTreeMap<ObjAddr, Vec<u8>>,
    current: &BTreeMap<ObjAddr, Vec<u8>>,
) -> crate::Result<()> {
    for step in super::config::plan(changes, &|a| current.get(&a).cloned()) {
        let mut o = SdoOptions::new(ctx.timeout);
        o.size_hint = Some(step.value.len());
        bus.sdo_download(node, step.addr, &step.value, &o)?;
    }
    Ok(())
}

/// The TPDO's parameters that `--map` touches, as they are now.
fn snapshot(ctx: &Ctx, bus: &mut dyn Bus, node: u8, n: u16) -> crate::Result<BTreeMap<ObjAddr, Vec<u8>>> {
    let (comm, map) = (0x1800 + n - 1, 0x1A00 + n - 1);
    let mut s = BTreeMap::new();
    s.insert(ObjAddr::new(comm, 1), read_u32(ctx, bus, node, ObjAddr::new(comm, 1))?.to_le_bytes().to_vec());
    s.insert(ObjAddr::new(comm, 2), vec![read_u8(ctx, bus, node, ObjAddr::new(comm, 2))?]);
    if let Ok(v) = bus.sdo_upload(node, ObjAddr::new(comm, 5), &{
        let mut o = SdoOptions::new(ctx.timeout);
        o.size_hint = Some(2);
        o
    }) {
        s.insert(ObjAddr::new(comm, 5), v);
    }
    let count = read_u8(ctx, bus, node, ObjAddr::new(map, 0))?;
    s.insert(ObjAddr::new(map, 0), vec![count]);
    for sub in 1..=count {
        s.insert(ObjAddr::new(map, sub), read_u32(ctx, bus, node, ObjAddr::new(map, sub))?.to_le_bytes().to_vec());
    }
    Ok(s)
}

/// Object values by address.
type Values = BTreeMap<ObjAddr, Vec<u8>>;

/// What the session changed, to put back at the end.
#[derive(Default)]
struct Undo {
    /// The TPDO's parameters before and during the session.
    mapping: Option<(Values, Values)>,
    state: Option<nmt::State>,
}

impl Undo {
    fn run(self, ctx: &Ctx, bus: &mut dyn Bus, node: u8) -> crate::Result<()> {
        if let Some((original, now)) = &self.mapping {
            // Entries the session added beyond the original count go back to 0 too.
            let mut back = original.clone();
            for (a, _) in now.iter().filter(|(a, _)| a.sub > 0 && (0x1A00..=0x1BFF).contains(&a.index)) {
                back.entry(*a).or_insert(vec![0; 4]);
            }
            back.retain(|a, v| now.get(a) != Some(v));
            write_plan(ctx, bus, node, &back, now)?;
        }
        match self.state {
            Some(nmt::State::Stopped) => bus.nmt(Command::Stop, node)?,
            Some(nmt::State::PreOperational) => bus.nmt(Command::PreOperational, node)?,
            _ => {}
        }
        Ok(())
    }
}

fn remap(ctx: &Ctx, bus: &mut dyn Bus, a: &StreamArgs, n: u16, undo: &mut Undo) -> anyhow::Result<()> {
    let (comm, map) = (0x1800 + n - 1, 0x1A00 + n - 1);
    let original = snapshot(ctx, bus, a.node, n)?;
    let mut wanted = BTreeMap::new();
    for (i, text) in a.map.iter().enumerate() {
        let (addr, entry) = ctx.dicts.resolve(a.node, text)?;
        let size = entry.and_then(|e| e.dtype.size()).ok_or_else(|| {
            Error::Usage(format!(
                "--map {text}: its size is unknown (no fixed-size type in the dictionary; --eds gives one)"
            ))
        })?;
        wanted.insert(ObjAddr::new(map, i as u8 + 1), pdo::mapping_raw(addr, (size * 8) as u8).to_le_bytes().to_vec());
    }
    wanted.insert(ObjAddr::new(map, 0), vec![a.map.len() as u8]);
    wanted.insert(ObjAddr::new(comm, 2), vec![a.transmission.unwrap_or(255)]);
    if let Some(ms) = a.event {
        wanted.insert(ObjAddr::new(comm, 5), ms.to_le_bytes().to_vec());
    }
    let changes: BTreeMap<ObjAddr, Vec<u8>> = wanted.into_iter().filter(|(k, v)| original.get(k) != Some(v)).collect();
    let mut now = original.clone();
    now.extend(changes.clone());
    undo.mapping = Some((original.clone(), now));
    write_plan(ctx, bus, a.node, &changes, &original)?;
    Ok(())
}

/// Layouts of the TPDOs to stream.
fn layouts(ctx: &Ctx, bus: &mut dyn Bus, a: &StreamArgs, list: &[u16]) -> anyhow::Result<Vec<(u16, Layout)>> {
    let dict = ctx.dicts.for_node(a.node);
    let mut out = Vec::new();
    for &n in list {
        let (comm, map) = (0x1800 + n - 1, 0x1A00 + n - 1);
        let cob = match read_u32(ctx, bus, a.node, ObjAddr::new(comm, 1)) {
            Ok(c) => c,
            Err(Error::SdoAbort { code: abort::NO_OBJECT | abort::NO_SUBINDEX, .. }) if a.tpdo.is_empty() => continue,
            Err(e) => return Err(e.into()),
        };
        if cob & 0x8000_0000 != 0 {
            ctx.out.note(&format!("TPDO{n} of node {} is not valid (0x{comm:04X}:1 = 0x{cob:08X}); left out", a.node));
            continue;
        }
        let count = read_u8(ctx, bus, a.node, ObjAddr::new(map, 0))?;
        let mut names = BTreeSet::new();
        let mut fields = Vec::new();
        for sub in 1..=count {
            let (addr, bits) = pdo::mapping_entry(read_u32(ctx, bus, a.node, ObjAddr::new(map, sub))?);
            let entry = dict.get(addr);
            let dtype = entry
                .map(|e| e.dtype)
                .filter(|t| t.size().is_some_and(|s| s * 8 == bits as usize) || *t == DataType::Bool && bits == 1);
            let mut name = dict.display_name(addr).unwrap_or_else(|| addr.to_string());
            if !names.insert(name.clone()) {
                name = format!("{name} ({addr})");
            }
            fields.push(Field { addr, bits, dtype: dtype.unwrap_or_else(|| pdo::default_type(bits)), name });
        }
        out.push((n, Layout { cob_id: (cob & 0x7FF) as u16, fields }));
    }
    if out.is_empty() {
        return Err(Error::Usage(format!(
            "node {} has no valid TPDO to stream (--map makes one for the session)",
            a.node
        ))
        .into());
    }
    Ok(out)
}

pub fn run(ctx: &Ctx, bus: &mut dyn Bus, a: &StreamArgs) -> anyhow::Result<()> {
    catch_interrupt();
    let mut undo = Undo::default();
    let result = session(ctx, bus, a, &mut undo);
    // Put back what was changed, whatever ended the stream.
    let restored = undo.run(ctx, bus, a.node);
    let interrupted = INTERRUPTED.load(Ordering::SeqCst);
    result?;
    restored?;
    if interrupted {
        return Err(Error::Interrupted.into());
    }
    Ok(())
}

fn session(ctx: &Ctx, bus: &mut dyn Bus, a: &StreamArgs, undo: &mut Undo) -> anyhow::Result<()> {
    let list: Vec<u16> = if a.tpdo.is_empty() { (1..=4).collect() } else { a.tpdo.clone() };
    if !a.map.is_empty() {
        remap(ctx, bus, a, list[0], undo)?;
    }
    if a.start {
        let (state, _) = super::nmt::query_state(ctx, bus, a.node, Duration::from_millis(300))?;
        if state != nmt::State::Operational {
            undo.state = Some(state);
            bus.nmt(Command::Start, a.node)?;
        }
    }
    let layouts = layouts(ctx, bus, a, if a.map.is_empty() { &list } else { &list[..1] })?;
    stream(ctx, bus, a, &layouts)
}

fn wall_ms() -> u64 {
    std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_millis() as u64)
}

fn stream(ctx: &Ctx, bus: &mut dyn Bus, a: &StreamArgs, layouts: &[(u16, Layout)]) -> anyhow::Result<()> {
    let polling = !bus.sees_traffic();
    for (n, l) in layouts {
        let names: Vec<&str> = l.fields.iter().map(|f| f.name.as_str()).collect();
        let how = if polling {
            format!(", polled by remote frame every {} ms", a.interval.as_millis())
        } else {
            String::new()
        };
        ctx.out.note(&format!(
            "node {} TPDO{n} (0x{:03X}, {} bytes{how}): {}",
            a.node,
            l.cob_id,
            l.len(),
            names.join(", ")
        ));
    }
    let writers: Vec<RecordWriter> = layouts.iter().map(|(_, l)| RecordWriter::new(l)).collect();
    let stdout = std::io::stdout();
    let live = stdout.is_terminal();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let mut line = String::new();
    if ctx.out.format == Format::Csv {
        // One header; with several TPDOs the columns are those of the first.
        let fields: Vec<&str> = layouts[0].1.fields.iter().map(|f| f.name.as_str()).collect();
        writeln!(out, "{}", crate::output::csv(&[&["time", "pdo"][..], &fields[..]].concat(), &[]).trim_end())?;
    }
    let end = a.duration.map(|d| Instant::now() + d);
    let sync_cob = 0x080;
    let mut next_sync = a.sync.map(|_| Instant::now());
    let mut next_poll = Instant::now();
    let mut records = 0u64;
    let mut warned = BTreeSet::new();
    let mut last_flush = Instant::now();
    while !INTERRUPTED.load(Ordering::SeqCst)
        && a.count.is_none_or(|c| records < c)
        && end.is_none_or(|e| Instant::now() < e)
    {
        if let (Some(period), Some(due)) = (a.sync, next_sync) {
            if Instant::now() >= due {
                bus.send_frame(&Frame::new(sync_cob, &[]))?;
                next_sync = Some(due + period);
            }
        }
        let mut wake = Instant::now() + Duration::from_millis(100);
        for t in [end, next_sync, polling.then_some(next_poll)].into_iter().flatten() {
            wake = wake.min(t);
        }
        let frames: Vec<Frame> = if polling {
            std::thread::sleep(next_poll.saturating_duration_since(Instant::now()));
            next_poll += a.interval;
            let mut got = Vec::new();
            for (_, l) in layouts {
                match bus.request_frame(l.cob_id, l.len() as u8, ctx.timeout) {
                    Ok(f) => got.push(f),
                    Err(Error::Timeout(_)) => {}
                    Err(e) => return Err(e.into()),
                }
            }
            got
        } else {
            bus.recv_frame(wake)?.into_iter().filter(|f| !f.is_remote()).collect()
        };
        for f in frames {
            let Some(i) = layouts.iter().position(|(_, l)| l.cob_id == f.id()) else { continue };
            let (n, l) = &layouts[i];
            let values = match l.decode(f.data()) {
                Ok(v) => v,
                Err(m) => {
                    if warned.insert(*n) {
                        ctx.out.note(&format!(
                            "warning: node {} TPDO{n} (0x{:03X}) came with {} bytes, its mapping makes {}: not decoded (this is said once)",
                            a.node, l.cob_id, m.got, m.want
                        ));
                    }
                    continue;
                }
            };
            let t = wall_ms();
            line.clear();
            match ctx.out.format {
                Format::Csv => writers[i].csv(&mut line, t, *n as u8, &values),
                Format::Json => writers[i].json(&mut line, t, a.node, *n as u8, &values),
                Format::Human => human(&mut line, t, *n, l, &values, records == 0),
            }
            out.write_all(line.as_bytes())?;
            // A reader at the other end of a pipe gets the stream as it goes, in batches.
            if live || last_flush.elapsed() >= Duration::from_millis(100) {
                out.flush()?;
                last_flush = Instant::now();
            }
            records += 1;
            if a.count.is_some_and(|c| records >= c) {
                break;
            }
        }
    }
    out.flush()?;
    ctx.out.note(&format!("{records} record(s)"));
    Ok(())
}

fn human(line: &mut String, t: u64, n: u16, l: &Layout, values: &[crate::canopen::types::Value], first: bool) {
    use std::fmt::Write as _;
    if first {
        let _ = write!(line, "{:<14}  {:<5}", "time", "pdo");
        for f in &l.fields {
            let _ = write!(line, "  {:>14}", f.name);
        }
        line.push('\n');
    }
    let secs = t / 1000;
    let _ =
        write!(line, "{:02}:{:02}:{:02}.{:03}    TPDO{n:<1}", secs / 3600 % 24, secs / 60 % 60, secs % 60, t % 1000);
    for v in values {
        let _ = write!(line, "  {:>14}", v.to_string());
    }
    line.push('\n');
}
