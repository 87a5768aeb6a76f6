//! `canctl scan`: every node 1 to 127, with identity, name and NMT state.

use super::Ctx;
use crate::bus::{Bus, LssWait, SdoOptions};
use crate::canopen::lss::{Identity, Inquiry, Request, Response, UNCONFIGURED};
use crate::canopen::{DataType, ObjAddr};
use crate::error::Error;
use crate::output::Format;
use clap::Args;
use serde_json::json;
use std::time::{Duration, Instant};

/// Find every node on the bus
///
/// Sends an SDO read of 0x1000 (device type) to all 127 node-ids at once and waits until
/// no answer has come for one window (slow devices answer up to 80 ms late); then reads
/// identity (0x1018:1..4) and name (0x1008) from each node that answered, all nodes in
/// parallel. The NMT state is what each node shows: its
/// heartbeat, waited for as long as its period (0x1017) needs, else its answer to node
/// guarding, else `unknown` with the reason.
/// Last, it counts the devices without a node-id that answer LSS "identify non-configured
/// remote slave", and lists devices left in LSS configuration state (they answer the LSS
/// inquiry services, and without a node-id no SDO).
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl --bus sim scan
  canctl --bus can0 scan --window 200ms --format json > nodes.json
  canctl --bus sim scan --format csv | cut -d, -f1,7")]
pub struct ScanArgs {
    /// How long the bus must stay quiet after the last answer to the probes
    #[arg(long, value_name = "DUR", default_value = "100ms", value_parser = super::parse_duration)]
    pub window: Duration,
}

const IDENTITY: [(&str, ObjAddr); 4] = [
    ("vendor_id", ObjAddr::new(0x1018, 1)),
    ("product_code", ObjAddr::new(0x1018, 2)),
    ("revision", ObjAddr::new(0x1018, 3)),
    ("serial", ObjAddr::new(0x1018, 4)),
];
const NAME: ObjAddr = ObjAddr::new(0x1008, 0);
const HEARTBEAT_TIME: ObjAddr = ObjAddr::new(0x1017, 0);
/// The longest scan waits for heartbeats: a node that beats more slowly is asked by node
/// guarding instead.
const MAX_HEARTBEAT_WAIT: Duration = Duration::from_secs(3);

struct Found {
    node: u8,
    device_type: Option<u32>,
    identity: [Option<u32>; 4],
    name: Option<String>,
    /// The producer heartbeat time the node reports (0x1017), in ms.
    heartbeat_ms: Option<u16>,
    state: Option<crate::canopen::nmt::State>,
    /// How the state was learned, or why it is unknown.
    state_from: &'static str,
}

fn as_u32(bytes: &[u8]) -> Option<u32> {
    bytes.try_into().ok().map(u32::from_le_bytes)
}

/// Every node that answers an SDO read of 0x1000 within `window`, with its device type
/// (`None` when it answered with an abort: the node is there all the same).
pub fn probe(ctx: &Ctx, bus: &mut dyn Bus, window: Duration) -> anyhow::Result<Vec<(u8, Option<u32>)>> {
    let probes: Vec<(u8, ObjAddr)> = (1..=127).map(|n| (n, ObjAddr::new(0x1000, 0))).collect();
    let bar = ctx.out.bar(probes.len() as u64, "probing");
    let answers = bus.sdo_upload_many(&probes, &SdoOptions::new(window), &mut |n| bar.set_position(n as u64))?;
    bar.finish_and_clear();
    let mut found = Vec::new();
    for ((node, _), answer) in probes.iter().zip(answers) {
        match answer {
            Ok(bytes) => found.push((*node, as_u32(&bytes))),
            Err(Error::SdoAbort { .. }) => found.push((*node, None)),
            Err(e) if e.is_timeout() => {}
            Err(e) => ctx.out.note(&format!("warning: node {node}: {e}")),
        }
    }
    Ok(found)
}

/// The LSS questions scan asks: "any device without a node-id?", then the inquiries only
/// devices in configuration state answer.
const LSS_QUESTIONS: [Request; 6] = [
    Request::IdentifyNonConfigured,
    Request::Inquire(Inquiry::Vendor),
    Request::Inquire(Inquiry::Product),
    Request::Inquire(Inquiry::Revision),
    Request::Inquire(Inquiry::Serial),
    Request::Inquire(Inquiry::NodeId),
];

/// Devices in LSS configuration state, from their answers to the inquiries.
#[derive(Debug, Default, PartialEq)]
struct Configuring {
    /// How many answered (the most answers to any one inquiry).
    count: usize,
    /// The identity and node-id, when exactly one device answered each inquiry.
    one: Option<(Identity, Option<u8>)>,
}

fn configuring(answers: &[[u8; 8]]) -> Configuring {
    let values = |q: Inquiry| -> Vec<u32> {
        answers
            .iter()
            .filter_map(|a| match Response::decode(a) {
                Some(Response::InquiredValue { inquiry, value }) if inquiry == q => Some(value),
                _ => None,
            })
            .collect()
    };
    let all = [Inquiry::Vendor, Inquiry::Product, Inquiry::Revision, Inquiry::Serial, Inquiry::NodeId].map(values);
    let count = all.iter().map(Vec::len).max().unwrap_or(0);
    let one = match all.each_ref().map(|v| v.as_slice()) {
        [[vendor], [product], [revision], [serial], [node]] => Some((
            Identity { vendor: *vendor, product: *product, revision: *revision, serial: *serial },
            (*node as u8 != UNCONFIGURED).then_some(*node as u8),
        )),
        _ => None,
    };
    Configuring { count, one }
}

/// Each node's NMT state as the node really shows it, never a guess that changes from run to
/// run: a node that produces heartbeats is listened to for as long as its period (read from
/// 0x1017) needs; the others are asked by node guarding; what neither answers is unknown.
fn nmt_states(ctx: &Ctx, bus: &mut dyn Bus, found: &mut [Found], window: Duration) -> crate::Result<()> {
    use crate::canopen::nmt::{self, ErrorControl};
    let beating = |f: &Found| f.heartbeat_ms.is_some_and(|ms| ms > 0);
    if bus.sees_traffic() {
        let longest = found.iter().filter(|f| beating(f)).filter_map(|f| f.heartbeat_ms).max().unwrap_or(0);
        // Twice the period: one beat may have gone just before the listening began.
        let end = Instant::now() + (Duration::from_millis(2 * longest as u64) + window).min(MAX_HEARTBEAT_WAIT);
        let missing = |bus: &mut dyn Bus, found: &[Found]| {
            found.iter().any(|f| beating(f) && !bus.observed().states.contains_key(&f.node))
        };
        while missing(bus, found) && bus.recv_frame(end)?.is_some() {}
        let states = bus.observed().states.clone();
        for f in found.iter_mut() {
            if let Some(s) = states.get(&f.node) {
                (f.state, f.state_from) = (Some(*s), "heartbeat");
            }
        }
    }
    // Guarding answers come at once; a node that has none is not waited for long.
    let guard_wait = (2 * window).max(Duration::from_millis(200)).min(ctx.timeout.max(Duration::from_millis(200)));
    let source = if bus.sees_traffic() { "node guarding" } else { "remote request through the EPOS2" };
    for f in found.iter_mut().filter(|f| f.state.is_none()) {
        match bus.request_frame(nmt::error_control_cob(f.node), 1, guard_wait) {
            Ok(frame) => match ErrorControl::parse(&frame) {
                Some((_, ErrorControl::State { state, .. })) => (f.state, f.state_from) = (Some(state), source),
                Some((_, ErrorControl::BootUp)) => {
                    (f.state, f.state_from) = (Some(nmt::State::PreOperational), "boot-up")
                }
                _ => f.state_from = "its error-control answer was not a state",
            },
            Err(e) if e.is_timeout() => {
                f.state_from = if beating(f) {
                    "no heartbeat within the wait, and no answer to node guarding"
                } else {
                    "no heartbeat configured, and no answer to node guarding"
                }
            }
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

pub fn run(ctx: &Ctx, bus: &mut dyn Bus, args: &ScanArgs) -> anyhow::Result<()> {
    // Where the bus's traffic is seen, "any device without a node-id?" goes out with the
    // probes and its answers come in during the same window. The inquiries wait until the
    // probes are answered: a device in configuration state with a node-id would otherwise
    // queue its SDO answer behind its LSS answers, which lose arbitration to the probes.
    let lss_alongside = bus.sees_traffic();
    if lss_alongside {
        bus.observed().take_lss_answers();
        bus.lss_exchange(&LSS_QUESTIONS[0].encode(), 0, Duration::ZERO, LssWait::Nothing)?;
    }
    let mut found: Vec<Found> = probe(ctx, bus, args.window)?
        .into_iter()
        .map(|(node, device_type)| Found {
            node,
            device_type,
            identity: [None; 4],
            name: None,
            heartbeat_ms: None,
            state: None,
            state_from: "",
        })
        .collect();

    let reads: Vec<(u8, ObjAddr)> = found
        .iter()
        .flat_map(|f| IDENTITY.iter().map(|(_, a)| (f.node, *a)).chain([(f.node, NAME), (f.node, HEARTBEAT_TIME)]))
        .collect();
    let bar = ctx.out.bar(reads.len() as u64, "identity");
    let values = bus.sdo_upload_many(&reads, &SdoOptions::new(ctx.timeout), &mut |n| bar.set_position(n as u64))?;
    bar.finish_and_clear();
    for ((node, addr), value) in reads.iter().zip(values) {
        let f = found.iter_mut().find(|f| f.node == *node).expect("read for a found node");
        match value {
            Ok(bytes) if *addr == NAME => f.name = DataType::Vs.decode(&bytes).map(|v| v.to_string()),
            Ok(bytes) if *addr == HEARTBEAT_TIME => {
                f.heartbeat_ms = bytes.get(..2).map(|b| u16::from_le_bytes([b[0], b[1]]))
            }
            Ok(bytes) => {
                let i = IDENTITY.iter().position(|(_, a)| a == addr).expect("identity entry");
                f.identity[i] = as_u32(&bytes);
            }
            Err(Error::SdoAbort { .. }) => {}
            Err(e) => ctx.out.note(&format!("warning: {e}")),
        }
    }
    nmt_states(ctx, bus, &mut found, args.window)?;
    let answers = if lss_alongside {
        for q in &LSS_QUESTIONS[1..] {
            bus.lss_exchange(&q.encode(), 0, Duration::ZERO, LssWait::Nothing)?;
        }
        let end = std::time::Instant::now() + args.window;
        while bus.recv_frame(end)?.is_some() {}
        bus.observed().take_lss_answers()
    } else {
        let mut answers = Vec::new();
        for q in LSS_QUESTIONS {
            let expect = q.expected_answer().expect("answered");
            answers.extend(bus.lss_exchange(&q.encode(), expect, args.window, LssWait::All)?.iter().map(|a| a.data));
        }
        answers
    };
    let unconfigured = crate::bus::lss::count_non_configured(&answers);
    let configuring = configuring(&answers);
    if let Some(uri) = &ctx.bus {
        let seen: Vec<super::cache::SeenNode> = found
            .iter()
            .map(|f| super::cache::SeenNode { node: f.node, name: f.name.clone(), vendor_id: f.identity[0] })
            .collect();
        super::cache::save(uri, &seen);
    }
    report(ctx, bus, &found, unconfigured, &configuring)
}

fn report(
    ctx: &Ctx,
    bus: &dyn Bus,
    found: &[Found],
    unconfigured: usize,
    configuring: &Configuring,
) -> anyhow::Result<()> {
    let hex = |v: Option<u32>| v.map_or("-".to_string(), |v| format!("0x{v:08X}"));
    match ctx.out.format {
        Format::Json => {
            let nodes: Vec<_> = found
                .iter()
                .map(|f| {
                    json!({
                        "node": f.node,
                        "device_type": f.device_type,
                        "vendor_id": f.identity[0],
                        "product_code": f.identity[1],
                        "revision": f.identity[2],
                        "serial": f.identity[3],
                        "name": f.name,
                        "state": f.state.map(|s| s.name()),
                        "state_from": f.state_from,
                        "heartbeat_ms": f.heartbeat_ms,
                    })
                })
                .collect();
            let one = configuring.one.map(
                |(id, node)| json!({ "identity": id.to_string(), "lss": super::lss::identity_json(&id), "node": node }),
            );
            ctx.out.json(&json!({
                "bus": bus.describe(),
                "nodes": nodes,
                "lss_unconfigured": unconfigured,
                "lss_configuration": { "count": configuring.count, "devices": one.into_iter().collect::<Vec<_>>() },
            }))?;
        }
        Format::Human | Format::Csv => {
            let headers = ["node", "device_type", "vendor_id", "product_code", "revision", "serial", "name", "state"];
            let rows: Vec<Vec<String>> = found
                .iter()
                .map(|f| {
                    let mut row = vec![f.node.to_string(), hex(f.device_type)];
                    row.extend(f.identity.iter().map(|v| hex(*v)));
                    row.push(f.name.clone().unwrap_or_else(|| "-".into()));
                    row.push(f.state.map_or("unknown".into(), |s| s.name().to_string()));
                    row
                })
                .collect();
            if ctx.out.format == Format::Human {
                ctx.out.note(&format!("{} node(s) on {}", found.len(), bus.describe()));
            }
            ctx.out.table(&headers, &rows)?;
            if ctx.out.format == Format::Human {
                for f in found.iter().filter(|f| f.state.is_none()) {
                    ctx.out.print(&format!("node {}: NMT state unknown: {}", f.node, f.state_from))?;
                }
            }
            if ctx.out.format == Format::Human && unconfigured > 0 {
                ctx.out.print(&format!(
                    "{unconfigured} device(s) without a node-id answered LSS (canctl lss fastscan finds them, lss assign numbers them)"
                ))?;
            }
            if ctx.out.format == Format::Human && configuring.count > 0 {
                let which = match configuring.one {
                    Some((id, None)) => format!(": {id}, no node-id"),
                    Some((id, Some(n))) => format!(": {id}, node-id {n}"),
                    None if configuring.count > 1 => {
                        " (several answered at once, so their identities cannot be told apart)".to_string()
                    }
                    None => " (not every identity inquiry was answered, so its identity is incomplete)".to_string(),
                };
                ctx.out.print(&format!(
                    "{} device(s) waiting in LSS configuration state{which} (canctl lss set-id gives a node-id; \
                     `canctl lss set-id 255 --global` or any LSS command sends them back to waiting)",
                    configuring.count
                ))?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inquired(q: Inquiry, value: u32) -> [u8; 8] {
        Response::InquiredValue { inquiry: q, value }.encode()
    }

    #[test]
    fn one_device_in_configuration_state_is_named() {
        let mut answers = vec![Response::IdentifyNonConfiguredSlave.encode(), [0x7F, 0, 0, 0, 0, 0, 0, 0]];
        for (q, v) in [(Inquiry::Vendor, 0x40), (Inquiry::Product, 2), (Inquiry::Revision, 3), (Inquiry::Serial, 4)] {
            answers.push(inquired(q, v));
        }
        answers.push(inquired(Inquiry::NodeId, 0xFF));
        let c = configuring(&answers);
        assert_eq!(c.count, 1);
        assert_eq!(c.one, Some((Identity { vendor: 0x40, product: 2, revision: 3, serial: 4 }, None)));
        // Two at once: counted, not paired up.
        answers.push(inquired(Inquiry::Serial, 5));
        assert_eq!(configuring(&answers), Configuring { count: 2, one: None });
        assert_eq!(configuring(&[Response::IdentifyNonConfiguredSlave.encode()]), Configuring::default());
    }
}
