//! Watching the bus: every frame decoded as it happens, and a summary of what was seen.

use crate::bus::Bus;
use crate::canopen::abort;
use crate::canopen::emcy::{self, Emergency};
use crate::canopen::lss;
use crate::canopen::nmt::{Command, ErrorControl};
use crate::canopen::pdo::Layout;
use crate::canopen::sdo::{
    self,
    wire::{Initiate, Request, Response},
};
use crate::error::{Error, Result};
use crate::frame::Frame;
use serde_json::{json, Value as J};
use std::collections::{BTreeMap, BTreeSet};
use std::time::{Duration, Instant};

/// One decoded frame.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Event {
    /// When it was received: Unix time in ms, the time column of every stream.
    pub time_ms: u64,
    /// Its COB-ID.
    pub cob: u16,
    /// The node it comes from or is meant for, when it names one.
    pub node: Option<u8>,
    /// What kind of frame it is, in words (`sync`, `emcy`, `pdo`, `sdo request`, `lss answer`, ...).
    pub kind: &'static str,
    /// What it says, for people.
    pub text: String,
    /// What it says, as JSON fields.
    pub fields: J,
}

fn event(node: Option<u8>, kind: &'static str, text: String, fields: J) -> Event {
    Event { time_ms: 0, cob: 0, node, kind, text, fields }
}

fn sdo_text(d: &[u8], request: bool) -> (String, J) {
    let p = sdo::pad(d);
    let parsed = if request { Request::parse(&p).map(Sdo::Request) } else { Response::parse(&p).map(Sdo::Response) };
    let what = match parsed {
        Some(Sdo::Request(Request::Abort { addr, code }) | Sdo::Response(Response::Abort { addr, code })) => {
            let m = abort::meaning(code);
            return (
                format!("abort {addr}: 0x{code:08X} {m}"),
                json!({ "sdo": "abort", "object": addr.to_string(), "code": format!("0x{code:08X}"), "meaning": m }),
            );
        }
        Some(Sdo::Request(Request::InitiateDownload { addr, init })) => {
            initiate_text(&format!("download {addr}"), init, ", ", "in segments")
        }
        Some(Sdo::Request(Request::InitiateUpload { addr })) => format!("upload {addr}"),
        Some(Sdo::Request(Request::DownloadSegment(_))) => "download segment".to_string(),
        Some(Sdo::Request(Request::UploadSegment { .. })) => "upload segment request".to_string(),
        Some(Sdo::Request(Request::BlockUpload { addr, .. })) => format!("block upload {addr}"),
        Some(Sdo::Request(Request::BlockDownload { addr, .. })) => format!("block download {addr}"),
        Some(Sdo::Response(Response::InitiateUpload { addr, init })) => {
            initiate_text(&addr.to_string(), init, ": ", "follow in segments")
        }
        Some(Sdo::Response(Response::InitiateDownload { addr })) => format!("{addr} written"),
        Some(Sdo::Response(Response::UploadSegment(_))) => "upload segment".to_string(),
        Some(Sdo::Response(Response::DownloadSegment { .. })) => "download segment confirmed".to_string(),
        // The rest of block transfer, and sub-block segments (which only the transfer's
        // state tells from other frames).
        _ => format!("block transfer ({:02X})", p[0]),
    };
    (what.clone(), json!({ "sdo": what }))
}

/// An initiate frame: "`head` = data" when expedited, else what it says of the size.
fn initiate_text(head: &str, init: Initiate, sep: &str, segmented: &str) -> String {
    match (init.expedited_data(), init) {
        (Some(data), _) => format!("{head} = {}", hex_spaced(data)),
        (None, Initiate::Size(size)) => format!("{head}{sep}{size} bytes {segmented}"),
        (None, _) => format!("{head}{sep}data of unannounced size {segmented}"),
    }
}

/// An SDO frame in either direction.
enum Sdo {
    Request(Request),
    Response(Response),
}

fn hex_spaced(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02X}")).collect::<Vec<_>>().join(" ")
}

/// What a frame says, in CiA 301/305 terms; PDOs decoded with `layouts` (by COB-ID).
pub fn decode(f: &Frame, layouts: &BTreeMap<u16, Layout>) -> Event {
    let id = f.id();
    let node = (id & 0x7F) as u8;
    // The data as the text shows it, and as JSON gives it: made only by the arms that show it
    // (this runs for every frame of a busy bus).
    let spaced = || hex_spaced(f.data());
    let hex = || crate::canopen::types::hex(f.data());
    if let Some((cmd, target)) = Command::parse(f) {
        let to = if target == 0 { "all nodes".to_string() } else { format!("node {target}") };
        let fields = json!({ "command": cmd.name(), "target": target });
        return event((target != 0).then_some(target), "nmt", format!("{} → {to}", cmd.name()), fields);
    }
    match id {
        0x080 => event(None, "sync", "SYNC".into(), json!({})),
        0x7E5 | 0x7E4 => {
            // The decoded message itself, never the text of an Option around it.
            let (kind, decoded) = match id {
                0x7E5 => ("lss request", lss::Request::decode(f.data()).map(|r| format!("{r:?}"))),
                _ => ("lss answer", lss::Response::decode(f.data()).map(|r| format!("{r:?}"))),
            };
            let text = decoded.unwrap_or_else(|| format!("not a CiA 305 message ({})", spaced()));
            event(None, kind, text.clone(), json!({ "lss": text }))
        }
        0x081..=0x0FF => match Emergency::parse(f) {
            Some((n, e)) => {
                let (code, register, vendor) = (e.code, e.register, hex_spaced(&e.vendor));
                let (bits, meaning) = (emcy::register_bits(register), emcy::code_meaning(code));
                let listed = bits.join(", ");
                let text =
                    format!("0x{code:04X} {meaning}; error register 0x{register:02X} [{listed}]; vendor {vendor}");
                let fields = json!({ "code": format!("0x{code:04X}"), "meaning": meaning, "register": register, "register_bits": bits, "vendor": crate::canopen::types::hex(&e.vendor) });
                event(Some(n), "emcy", text, fields)
            }
            None => event(Some(node), "emcy", format!("no data ({} bytes)", f.len()), json!({})),
        },
        0x701..=0x77F if f.is_remote() => event(Some(node), "guard request", "node guarding request".into(), json!({})),
        0x701..=0x77F => match ErrorControl::parse(f) {
            Some((n, ErrorControl::BootUp)) => {
                event(Some(n), "boot-up", "boot-up".into(), json!({ "state": "initialising" }))
            }
            Some((n, ErrorControl::State { state, toggle })) => {
                let text = format!("{state}{}", if toggle { " (toggle 1)" } else { "" });
                event(Some(n), "heartbeat", text, json!({ "state": state.name(), "toggle": toggle }))
            }
            _ => event(Some(node), "error control", spaced(), json!({ "data": hex() })),
        },
        0x581..=0x5FF | 0x601..=0x67F => {
            let request = id >= 0x601;
            let (t, j) = sdo_text(f.data(), request);
            event(Some(node), if request { "sdo request" } else { "sdo answer" }, t, j)
        }
        0x181..=0x57F => {
            let kind = ["tpdo", "rpdo"][((id - 0x180) / 0x80 % 2) as usize];
            let number = (id - 0x180) / 0x100 + 1;
            let label = format!("{}{number}", kind.to_uppercase());
            if f.is_remote() {
                return event(Some(node), "pdo request", format!("{label} remote request"), json!({ "pdo": label }));
            }
            let (text, fields) = match layouts.get(&id).map(|l| (l, l.decode(f.data()))) {
                Some((l, Ok(values))) => {
                    let mut fields = serde_json::Map::new();
                    let mut text = Vec::new();
                    for (fd, v) in l.fields.iter().zip(&values) {
                        fields.insert(fd.name.clone(), v.to_json());
                        text.push(format!("{}={v}", fd.name));
                    }
                    (format!("{label} {}", text.join(" ")), json!({ "pdo": label, "values": fields }))
                }
                Some((l, Err(m))) => {
                    let text = format!("{label} {} (length {} where the mapping makes {})", spaced(), m.got, m.want);
                    (text, json!({ "pdo": label, "data": hex(), "length_mismatch": l.len() }))
                }
                None => (format!("{label} {}", spaced()), json!({ "pdo": label, "data": hex() })),
            };
            event(Some(node), "pdo", text, fields)
        }
        _ => event(None, "frame", spaced(), json!({ "data": hex() })),
    }
}

/// What a monitor saw.
#[derive(Clone, Debug, Default)]
#[non_exhaustive]
pub struct Summary {
    /// Frames seen, per COB-ID.
    pub per_cob_id: BTreeMap<u16, u64>,
    /// The node-ids frames came from or were meant for.
    pub nodes: BTreeSet<u8>,
    /// EMCY frames seen.
    pub emcy: u64,
    /// How long the monitor ran.
    pub elapsed: Duration,
    /// Ended by the user (SIGINT, SIGTERM, Ctrl-C) rather than by its duration or count.
    pub interrupted: bool,
}

impl Summary {
    /// Frames seen in all.
    pub fn frames(&self) -> u64 {
        self.per_cob_id.values().sum()
    }
}

/// The bus's frames, decoded, as they come: pull them with [`Monitor::next`].
pub struct Monitor {
    layouts: BTreeMap<u16, Layout>,
    nodes: Vec<u8>,
    start: Instant,
    /// The bus's time when the monitor last looked: what the summary's elapsed time runs to.
    last: Instant,
    end: Option<Instant>,
    count: Option<u64>,
    seen: Summary,
}

impl Monitor {
    /// Frames of `nodes` (all when empty; NMT, SYNC and LSS always) until `duration` or
    /// `count` frames. Needs a link that shows the bus's traffic.
    pub fn new(
        bus: &dyn Bus,
        layouts: BTreeMap<u16, Layout>,
        nodes: &[u8],
        duration: Option<Duration>,
        count: Option<u64>,
    ) -> Result<Monitor> {
        if !bus.sees_traffic() {
            return Err(Error::Usage(format!(
                "{} shows no bus traffic (an EPOS2 answers commands only): monitor needs SocketCAN or sim",
                bus.describe()
            )));
        }
        let start = bus.now();
        let (nodes, end) = (nodes.to_vec(), duration.map(|d| start + d));
        Ok(Monitor { layouts, nodes, start, last: start, end, count, seen: Summary::default() })
    }

    /// The next frame, decoded, or `None` when the monitor is over: its duration or count
    /// reached, or stopped by the user (over a [`Stoppable`](crate::bus::stoppable::Stoppable)
    /// bus; the summary says so).
    pub fn next(&mut self, bus: &mut dyn Bus) -> Result<Option<Event>> {
        while self.end.is_none_or(|e| bus.now() < e) && self.count.is_none_or(|c| self.seen.frames() < c) {
            let wake = self.end.unwrap_or_else(|| bus.now() + Duration::from_millis(200));
            let f = match bus.recv_frame(wake) {
                Err(e) if e.is_interrupted() => {
                    self.seen.interrupted = true;
                    return Ok(None);
                }
                other => other?,
            };
            self.last = bus.now();
            let Some(f) = f else { continue };
            let mut ev = decode(&f, &self.layouts);
            if !self.nodes.is_empty() && ev.node.is_some_and(|n| !self.nodes.contains(&n)) {
                continue;
            }
            *self.seen.per_cob_id.entry(f.id()).or_default() += 1;
            self.seen.nodes.extend(ev.node);
            self.seen.emcy += (ev.kind == "emcy") as u64;
            ev.time_ms = super::pdo::wall_ms();
            ev.cob = f.id();
            return Ok(Some(ev));
        }
        Ok(None)
    }

    /// What was seen so far.
    pub fn summary(&self) -> Summary {
        Summary { elapsed: self.last.saturating_duration_since(self.start), ..self.seen.clone() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(request: bool, bytes: &[u8]) -> String {
        sdo_text(bytes, request).0
    }

    #[test]
    fn an_lss_message_reads_whole_and_an_undecodable_one_says_so() {
        let none = BTreeMap::new();
        // CiA 305 configure node-id 5, and its answer (error code 0): nested parentheses kept.
        let request = decode(&Frame::new(0x7E5, &[0x11, 5, 0, 0, 0, 0, 0, 0]), &none);
        assert_eq!(request.text, format!("{:?}", lss::Request::ConfigureNodeId(5)));
        assert_eq!(request.fields["lss"], request.text);
        let unknown = decode(&Frame::new(0x7E4, &[0xEE, 0, 0, 0, 0, 0, 0, 0]), &none);
        assert_eq!(unknown.text, "not a CiA 305 message (EE 00 00 00 00 00 00 00)");
    }

    #[test]
    fn sdo_frames_read_as_cia_301_says() {
        // Seed 004: expedited download of 0x1801:5 = 1000, and its confirmation (DLC 4).
        assert_eq!(text(true, &[0x2B, 0x01, 0x18, 0x05, 0xE8, 0x03, 0, 0]), "download 0x1801:5 = E8 03");
        assert_eq!(text(false, &[0x60, 0x01, 0x18, 0x05]), "0x1801:5 written");
        // Seed 004: 0x1400:0 read, answered in a DLC-5 frame; 0x1008 announced as 9 bytes.
        assert_eq!(text(true, &[0x40, 0x00, 0x14, 0x00, 0, 0, 0, 0]), "upload 0x1400:0");
        assert_eq!(text(false, &[0x4F, 0x00, 0x14, 0x00, 0x02]), "0x1400:0 = 02");
        assert_eq!(text(false, &[0x41, 0x08, 0x10, 0x00, 0x09, 0, 0, 0]), "0x1008:0: 9 bytes follow in segments");
        // The size is 32-bit unsigned.
        assert_eq!(
            text(false, &[0x41, 0x08, 0x10, 0x00, 0xFF, 0xFF, 0xFF, 0xFF]),
            "0x1008:0: 4294967295 bytes follow in segments"
        );
        assert_eq!(text(true, &[0x60, 0, 0, 0, 0, 0, 0, 0]), "upload segment request");
        assert_eq!(text(false, &[0x00, 0x43, 0x41, 0x4E, 0x2D, 0x32, 0x30, 0x38]), "upload segment");
        assert_eq!(
            text(false, &[0x80, 0x08, 0x10, 0x01, 0x11, 0x00, 0x09, 0x06]),
            format!("abort 0x1008:1: 0x06090011 {}", abort::meaning(0x0609_0011))
        );
        assert_eq!(text(true, &[0xA4, 0x50, 0x1F, 0x01, 0x7F, 0x15, 0, 0]), "block upload 0x1F50:1");
        assert_eq!(text(true, &[0xA2, 0x05, 0x7F, 0, 0, 0, 0, 0]), "block transfer (A2)");
    }
}
