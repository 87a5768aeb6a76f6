//! `canctl monitor`: the bus's traffic as it happens, decoded.

use super::{parse_node, Ctx};
use crate::bus::Bus;
use crate::canopen::emcy::{self, Emergency};
use crate::canopen::lss;
use crate::canopen::nmt::{Command, ErrorControl};
use crate::canopen::pdo::{self, Field, Layout};
use crate::canopen::{abort, ObjAddr};
use crate::error::Error;
use crate::frame::Frame;
use crate::output::Format;
use clap::Args;
use clap_complete::engine::ArgValueCandidates;
use serde_json::{json, Value as J};
use std::collections::{BTreeMap, BTreeSet};
use std::io::Write;
use std::time::{Duration, Instant};

/// Watch the bus: every frame decoded, as it happens
///
/// NMT commands, boot-ups, heartbeats and node guarding with state names, EMCY with the
/// meaning of the code and the error register bits, SDO requests, answers and aborts, SYNC,
/// LSS, and PDOs — decoded into fields when an EDS or DCF (--eds) gives their mapping. A
/// summary ends it: frames per COB-ID, nodes seen, EMCYs.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus can0 monitor
  canctl --bus can0 monitor --node 5 --node 10 --duration 10s --format json > bus.jsonl
  canctl --bus vcan0 --eds 5=mh.dcf monitor --node 5")]
pub struct MonitorArgs {
    /// Only frames of this node (repeatable); NMT, SYNC and LSS are always shown
    #[arg(long, value_parser = parse_node, add = ArgValueCandidates::new(super::complete::nodes))]
    pub node: Vec<u8>,
    /// Stop after this long
    #[arg(long, value_name = "DUR", value_parser = super::parse_duration)]
    pub duration: Option<Duration>,
    /// Stop after this many frames
    #[arg(long, value_name = "N")]
    pub count: Option<u64>,
}

/// One decoded frame.
struct Event {
    node: Option<u8>,
    kind: &'static str,
    text: String,
    fields: J,
}

fn event(node: Option<u8>, kind: &'static str, text: String, fields: J) -> Event {
    Event { node, kind, text, fields }
}

fn sdo_text(d: &[u8], request: bool) -> (String, J) {
    let p = crate::canopen::sdo::pad(d);
    let addr = ObjAddr::from_mux(&p[1..4]);
    if let Some(code) = crate::canopen::sdo::abort_code(&p) {
        let m = abort::meaning(code);
        return (
            format!("abort {addr}: 0x{code:08X} {m}"),
            json!({ "sdo": "abort", "object": addr.to_string(), "code": format!("0x{code:08X}"), "meaning": m }),
        );
    }
    let cs = p[0] >> 5;
    let what = match (request, cs) {
        (true, 1) if p[0] & 2 != 0 => {
            format!("download {addr} = {}", hex_spaced(&p[4..4 + crate::canopen::sdo::expedited_len(p[0])]))
        }
        (true, 1) => format!("download {addr}, {} bytes in segments", u32::from_le_bytes([p[4], p[5], p[6], p[7]])),
        (true, 2) => format!("upload {addr}"),
        (true, 0) => "download segment".to_string(),
        (true, 3) => "upload segment request".to_string(),
        (true, 5) => format!("block upload {addr}"),
        (true, 6) => format!("block download {addr}"),
        (false, 2) if p[0] & 2 != 0 => {
            format!("{addr} = {}", hex_spaced(&p[4..4 + crate::canopen::sdo::expedited_len(p[0])]))
        }
        (false, 2) => format!("{addr}: {} bytes follow in segments", u32::from_le_bytes([p[4], p[5], p[6], p[7]])),
        (false, 3) => format!("{addr} written"),
        (false, 0) => "upload segment".to_string(),
        (false, 1) => "download segment confirmed".to_string(),
        _ => format!("block transfer ({:02X})", p[0]),
    };
    (what.clone(), json!({ "sdo": what }))
}

fn hex_spaced(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02X}")).collect::<Vec<_>>().join(" ")
}

fn decode(f: &Frame, layouts: &BTreeMap<u16, (u8, Layout)>) -> Event {
    let id = f.id();
    let node = (id & 0x7F) as u8;
    if let Some((cmd, target)) = Command::parse(f) {
        let to = if target == 0 { "all nodes".to_string() } else { format!("node {target}") };
        return event(
            (target != 0).then_some(target),
            "nmt",
            format!("{} → {to}", cmd.name()),
            json!({ "command": cmd.name(), "target": target }),
        );
    }
    match id {
        0x080 => event(None, "sync", "SYNC".into(), json!({})),
        0x7E5 | 0x7E4 => {
            let text = if id == 0x7E5 {
                format!("{:?}", lss::Request::decode(f.data()))
            } else {
                format!("{:?}", lss::Response::decode(f.data()))
            };
            let text = text.trim_start_matches("Some(").trim_end_matches(')').to_string();
            event(None, if id == 0x7E5 { "lss request" } else { "lss answer" }, text.clone(), json!({ "lss": text }))
        }
        0x081..=0x0FF => match Emergency::parse(f) {
            Some((n, e)) => {
                let bits = emcy::register_bits(e.register);
                let meaning = emcy::code_meaning(e.code);
                event(
                    Some(n),
                    "emcy",
                    format!(
                        "0x{:04X} {meaning}; error register 0x{:02X} [{}]; vendor {}",
                        e.code,
                        e.register,
                        bits.join(", "),
                        hex_spaced(&e.vendor)
                    ),
                    json!({ "code": format!("0x{:04X}", e.code), "meaning": meaning, "register": e.register, "register_bits": bits, "vendor": crate::canopen::types::hex(&e.vendor) }),
                )
            }
            None => event(Some(node), "emcy", format!("no data ({} bytes)", f.len()), json!({})),
        },
        0x701..=0x77F if f.is_remote() => event(Some(node), "guard request", "node guarding request".into(), json!({})),
        0x701..=0x77F => match ErrorControl::parse(f) {
            Some((n, ErrorControl::BootUp)) => {
                event(Some(n), "boot-up", "boot-up".into(), json!({ "state": "initialising" }))
            }
            Some((n, ErrorControl::State { state, toggle })) => event(
                Some(n),
                "heartbeat",
                format!("{state}{}", if toggle { " (toggle 1)" } else { "" }),
                json!({ "state": state.name(), "toggle": toggle }),
            ),
            _ => event(
                Some(node),
                "error control",
                hex_spaced(f.data()),
                json!({ "data": crate::canopen::types::hex(f.data()) }),
            ),
        },
        0x581..=0x5FF => {
            let (t, j) = sdo_text(f.data(), false);
            event(Some(node), "sdo answer", t, j)
        }
        0x601..=0x67F => {
            let (t, j) = sdo_text(f.data(), true);
            event(Some(node), "sdo request", t, j)
        }
        0x181..=0x57F => {
            let kind = ["tpdo", "rpdo"][((id - 0x180) / 0x80 % 2) as usize];
            let number = (id - 0x180) / 0x100 + 1;
            let label = format!("{}{number}", kind.to_uppercase());
            if f.is_remote() {
                return event(Some(node), "pdo request", format!("{label} remote request"), json!({ "pdo": label }));
            }
            match layouts.get(&id).map(|(_, l)| (l, l.decode(f.data()))) {
                Some((l, Ok(values))) => {
                    let mut fields = serde_json::Map::new();
                    let text: Vec<String> = l
                        .fields
                        .iter()
                        .zip(&values)
                        .map(|(fd, v)| {
                            fields.insert(fd.name.clone(), v.to_json());
                            format!("{}={v}", fd.name)
                        })
                        .collect();
                    event(
                        Some(node),
                        "pdo",
                        format!("{label} {}", text.join(" ")),
                        json!({ "pdo": label, "values": fields }),
                    )
                }
                Some((l, Err(m))) => event(
                    Some(node),
                    "pdo",
                    format!("{label} {} (length {} where the mapping makes {})", hex_spaced(f.data()), m.got, m.want),
                    json!({ "pdo": label, "data": crate::canopen::types::hex(f.data()), "length_mismatch": l.len() }),
                ),
                None => event(
                    Some(node),
                    "pdo",
                    format!("{label} {}", hex_spaced(f.data())),
                    json!({ "pdo": label, "data": crate::canopen::types::hex(f.data()) }),
                ),
            }
        }
        _ => event(None, "frame", hex_spaced(f.data()), json!({ "data": crate::canopen::types::hex(f.data()) })),
    }
}

/// PDO layouts from the EDS/DCF files: their TPDO and RPDO mappings, for their nodes.
fn layouts(ctx: &Ctx, nodes: &[u8]) -> BTreeMap<u16, (u8, Layout)> {
    let mut out = BTreeMap::new();
    let candidates: Vec<u8> = if nodes.is_empty() { (1..=127).collect() } else { nodes.to_vec() };
    for node in candidates {
        let Some(eds) = ctx.dicts.eds_for(node) else { continue };
        let value = |addr: ObjAddr| -> Option<Vec<u8>> {
            let e = eds.dict.get(addr)?;
            let init = eds.values.get(&addr).cloned().unwrap_or_else(|| e.default.clone());
            Some(crate::od::Entry { default: init, ..e.clone() }.default_for(node))
        };
        let u32_at = |addr| value(addr).and_then(|v| v.get(..4).map(|b| u32::from_le_bytes(b.try_into().unwrap())));
        for (comm, map) in (0..4u16).flat_map(|n| [(0x1400 + n, 0x1600 + n), (0x1800 + n, 0x1A00 + n)]) {
            let Some(cob) = u32_at(ObjAddr::new(comm, 1)).filter(|c| c & 0x8000_0000 == 0) else { continue };
            let count = value(ObjAddr::new(map, 0)).and_then(|v| v.first().copied()).unwrap_or(0);
            let fields = (1..=count)
                .filter_map(|s| u32_at(ObjAddr::new(map, s)))
                .map(|raw| {
                    let (addr, bits) = pdo::mapping_entry(raw);
                    let dtype = eds
                        .dict
                        .get(addr)
                        .map(|e| e.dtype)
                        .filter(|t| t.size() == Some(bits as usize / 8))
                        .unwrap_or_else(|| pdo::default_type(bits));
                    Field { addr, bits, dtype, name: eds.dict.display_name(addr).unwrap_or_else(|| addr.to_string()) }
                })
                .collect();
            out.insert((cob & 0x7FF) as u16, (node, Layout { cob_id: (cob & 0x7FF) as u16, fields }));
        }
    }
    out
}

pub fn run(ctx: &Ctx, bus: &mut dyn Bus, a: &MonitorArgs) -> anyhow::Result<()> {
    if !bus.sees_traffic() {
        return Err(Error::Usage(format!(
            "{} shows no bus traffic (an EPOS2 answers commands only): monitor needs SocketCAN or sim",
            bus.describe()
        ))
        .into());
    }
    let layouts = layouts(ctx, &a.node);
    let start = Instant::now();
    let end = a.duration.map(|d| start + d);
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let mut per_cob: BTreeMap<u16, u64> = BTreeMap::new();
    let mut nodes: BTreeSet<u8> = BTreeSet::new();
    let (mut emcys, mut shown) = (0u64, 0u64);
    while end.is_none_or(|e| Instant::now() < e) && a.count.is_none_or(|c| shown < c) {
        let wake = end.unwrap_or_else(|| Instant::now() + Duration::from_millis(200));
        let Some(f) = bus.recv_frame(wake)? else { continue };
        let ev = decode(&f, &layouts);
        if !a.node.is_empty() && ev.node.is_some_and(|n| !a.node.contains(&n)) {
            continue;
        }
        *per_cob.entry(f.id()).or_default() += 1;
        nodes.extend(ev.node);
        emcys += (ev.kind == "emcy") as u64;
        shown += 1;
        let t = start.elapsed().as_secs_f64();
        match ctx.out.format {
            Format::Json => {
                let mut j = json!({ "time": (t * 1000.0).round() / 1000.0, "cob": format!("0x{:03X}", f.id()), "node": ev.node, "kind": ev.kind });
                if let (Some(o), J::Object(extra)) = (j.as_object_mut(), ev.fields) {
                    o.extend(extra);
                }
                writeln!(out, "{j}")?;
            }
            Format::Csv => writeln!(
                out,
                "{t:.3},0x{:03X},{},{},\"{}\"",
                f.id(),
                ev.node.map_or(String::new(), |n| n.to_string()),
                ev.kind,
                ev.text.replace('"', "\"\"")
            )?,
            Format::Human => {
                let node = ev.node.map_or("       ".to_string(), |n| format!("node {n:<2}"));
                writeln!(out, "{t:9.3}  {:03X}  {node}  {:<13} {}", f.id(), ev.kind, ev.text)?
            }
        }
        out.flush()?;
    }
    let summary_nodes: Vec<u8> = nodes.into_iter().collect();
    match ctx.out.format {
        Format::Json => writeln!(
            out,
            "{}",
            json!({ "summary": { "frames": per_cob.values().sum::<u64>(), "per_cob_id": per_cob.iter().map(|(c, n)| (format!("0x{c:03X}"), *n)).collect::<BTreeMap<_, _>>(), "nodes": summary_nodes, "emcy": emcys } })
        )?,
        _ => {
            out.flush()?;
            let cobs: Vec<String> = per_cob.iter().map(|(c, n)| format!("{c:03X}×{n}")).collect();
            let list: Vec<String> = summary_nodes.iter().map(|n| n.to_string()).collect();
            ctx.out.note(&format!(
                "{} frame(s) in {:.1} s; per COB-ID: {}; nodes seen: {}; EMCYs: {emcys}",
                per_cob.values().sum::<u64>(),
                start.elapsed().as_secs_f64(),
                if cobs.is_empty() { "-".into() } else { cobs.join(" ") },
                if list.is_empty() { "-".into() } else { list.join(", ") }
            ));
        }
    }
    out.flush()?;
    Ok(())
}
