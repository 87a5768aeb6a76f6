//! Faults injected into a simulated device's answers: what a misbehaving real device does
//! on the bus (answers lost, late, twice, cut short, garbled, on the wrong id, refused,
//! stopping mid-transfer, flooding the bus).
//!
//! A fault is written `TARGET:KIND[=ARG][@WHEN]`:
//! - TARGET: a node-id (`5`; whichever device has it at the time) or a model key (`drive`,
//!   `sensor-09501301`);
//! - KIND: `drop`, `delay=MS`, `duplicate`, `short-dlc[=N]` (N data bytes, 4 unless
//!   given), `corrupt` (the first data byte, the command specifier, inverted), `babble[=ID]`
//!   (floods frames on ID, its EMCY id unless given), `abort[=CODE]` (SDO answers become
//!   an abort, 0x08000000 unless given), `mute` (stops sending anything, its own frames too),
//!   `wrong-cob[=ID]` (answers on ID, its own id + 1 unless given), `no-heartbeat` (stops
//!   producing heartbeats, though its 0x1017 still says it does: a hung firmware task),
//!   `off` (not powered: sends nothing from the start, where `mute` falls silent at an answer),
//!   `miss` (does not hear a frame on the bus: a receive queue overrun, a lossy path; its
//!   WHEN counts the frames the device hears, not its answers), `endless-segments` (an
//!   upload is answered as segmented of unstated size and never ends), `endless-block` (a
//!   block upload never ends), `ack-zero` (every sub-block of a block download is
//!   acknowledged with sequence 0: nothing received); for these three, WHEN counts the
//!   transfers of that kind the device is asked to start;
//! - `bus:off` (no KIND, no WHEN: the whole fault): the controller canctl talks through is
//!   bus-off and stays so, as a real one with `restart-ms 0` does (the kernel's automatic
//!   restart is not modelled): it sends nothing and says so, as its link would;
//! - WHEN: `*` every answer (the default), `N` the N-th answer only, `N+` the N-th and
//!   every later one, `P%` each answer with probability P (drawn from the seed).
//!
//! Answers are counted per device from 1, one per frame it sends in answer to a request
//! (each segment of a block upload counts), afresh in each invocation.

use super::endless::{Endless, EndlessServer};
use super::timing::{Nanos, Rng, MS};
use crate::canopen::number::parse_number;
use crate::canopen::sdo;
use crate::frame::Frame;
use std::fmt;
use std::str::FromStr;

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Target {
    Node(u8),
    Model(String),
    /// The bus itself (`bus:off`): the controller of the link, not a device.
    Bus,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    Drop,
    Delay(u32),
    Duplicate,
    ShortDlc(u8),
    Corrupt,
    Babble(Option<u16>),
    Abort(u32),
    Mute,
    WrongCob(Option<u16>),
    NoHeartbeat,
    /// The device reboots instead of answering (a power dip, a watchdog): what it was told
    /// and not stored is gone, and it sends its boot-up.
    Reboot,
    /// The device is not powered: it sends nothing, from the start (no heartbeat, no
    /// answer), where `mute` falls silent at an answer.
    Off,
    /// The device does not hear a frame on the bus (its receive queue overran, or the path
    /// to it lost the frame): WHEN counts the frames it hears, not its answers.
    Miss,
    /// An SDO transfer of some kind never finishes (see [`Endless`]).
    Endless(Endless),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum When {
    Always,
    Nth(u32),
    From(u32),
    Chance(f64),
}

/// One fault on one device, as `--fault` gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct FaultSpec {
    /// The device(s) it concerns: by model key, by node-id, or any.
    pub target: Target,
    /// What goes wrong.
    pub kind: Kind,
    /// From which request on, or after how long.
    pub when: When,
}

/// The kinds that take no argument, by name.
const PLAIN_KINDS: [(&str, Kind); 11] = [
    ("drop", Kind::Drop),
    ("duplicate", Kind::Duplicate),
    ("corrupt", Kind::Corrupt),
    ("mute", Kind::Mute),
    ("no-heartbeat", Kind::NoHeartbeat),
    ("reboot", Kind::Reboot),
    ("off", Kind::Off),
    ("miss", Kind::Miss),
    ("endless-segments", Kind::Endless(Endless::Segments)),
    ("endless-block", Kind::Endless(Endless::Block)),
    ("ack-zero", Kind::Endless(Endless::AckZero)),
];

/// SDO abort "general error", when `abort` names no code.
pub(crate) const DEFAULT_ABORT: u32 = 0x0800_0000;
const DEFAULT_SHORT_DLC: u8 = 4;

fn parse_cob(s: &str) -> Result<u16, String> {
    let id = parse_number::<u32>(s).filter(|v| *v <= 0x7FF);
    id.map(|v| v as u16).ok_or_else(|| format!("'{s}' is not an 11-bit CAN id"))
}

impl FromStr for FaultSpec {
    type Err = String;
    fn from_str(text: &str) -> Result<FaultSpec, String> {
        let usage = "write TARGET:KIND[=ARG][@WHEN], e.g. 5:drop@3, drive:delay=40, 10:abort=0x06020000@2+, 5:mute@4+";
        let (target, rest) = text.split_once(':').ok_or_else(|| format!("'{text}' is not a fault: {usage}"))?;
        let target = match target.parse::<u8>() {
            _ if target == "bus" => Target::Bus,
            Ok(n) if (1..=127).contains(&n) => Target::Node(n),
            Ok(_) => return Err(format!("'{target}' is not a node-id: use 1 to 127 or a model key")),
            Err(_) if !target.is_empty() => Target::Model(target.to_string()),
            Err(_) => return Err(format!("'{text}' names no device: {usage}")),
        };
        let (kind, when) = rest.split_once('@').map_or((rest, None), |(k, w)| (k, Some(w)));
        let (name, arg) = kind.split_once('=').map_or((kind, None), |(n, a)| (n, Some(a)));
        let need = |what: &str| arg.ok_or_else(|| format!("'{name}' needs {what}: {name}=..."));
        let bad = |a: &str| format!("'{a}' is not a valid argument for {name}");
        let kind = match name {
            "delay" => Kind::Delay(need("a delay in ms").and_then(|a| a.parse().map_err(|_| bad(a)))?),
            "short-dlc" => Kind::ShortDlc(match arg {
                None => DEFAULT_SHORT_DLC,
                Some(a) => a.parse().ok().filter(|n| *n < 8).ok_or_else(|| bad(a))?,
            }),
            "babble" => Kind::Babble(arg.map(parse_cob).transpose()?),
            "abort" => Kind::Abort(arg.map_or(Some(DEFAULT_ABORT), parse_number).ok_or_else(|| bad(arg.unwrap_or("")))?),
            "wrong-cob" => Kind::WrongCob(arg.map(parse_cob).transpose()?),
            _ => match PLAIN_KINDS.iter().find(|(n, _)| *n == name) {
                Some(_) if arg.is_some() => return Err(format!("'{name}' takes no argument")),
                Some((_, kind)) => *kind,
                None => return Err(format!(
                    "'{name}' is not a fault kind: use drop, delay=MS, duplicate, short-dlc[=N], corrupt, babble[=ID], abort[=CODE], mute, wrong-cob[=ID], no-heartbeat, reboot, off, miss, endless-segments, endless-block or ack-zero"
                )),
            },
        };
        let when = match when {
            None | Some("*") => When::Always,
            Some(w) => {
                let bad = || format!("'@{w}' is not a time for a fault: use @N, @N+, @P% or @*");
                if let Some(p) = w.strip_suffix('%') {
                    When::Chance(p.parse::<f64>().ok().filter(|p| (0.0..=100.0).contains(p)).ok_or_else(bad)? / 100.0)
                } else if let Some(n) = w.strip_suffix('+') {
                    When::From(n.parse().ok().filter(|n| *n >= 1).ok_or_else(bad)?)
                } else {
                    When::Nth(w.parse().ok().filter(|n| *n >= 1).ok_or_else(bad)?)
                }
            }
        };
        if target == Target::Bus && (kind != Kind::Off || when != When::Always) {
            return Err(format!("'{text}': the bus takes only bus:off (its controller bus-off, from the start)"));
        }
        Ok(FaultSpec { target, kind, when })
    }
}

impl fmt::Display for FaultSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.target {
            Target::Node(n) => write!(f, "{n}:")?,
            Target::Model(m) => write!(f, "{m}:")?,
            Target::Bus => write!(f, "bus:")?,
        }
        match self.kind {
            Kind::Delay(ms) => write!(f, "delay={ms}")?,
            Kind::ShortDlc(n) => write!(f, "short-dlc={n}")?,
            Kind::Babble(None) => write!(f, "babble")?,
            Kind::Babble(Some(id)) => write!(f, "babble=0x{id:03X}")?,
            Kind::Abort(code) => write!(f, "abort=0x{code:08X}")?,
            Kind::WrongCob(None) => write!(f, "wrong-cob")?,
            Kind::WrongCob(Some(id)) => write!(f, "wrong-cob=0x{id:03X}")?,
            plain => f.write_str(PLAIN_KINDS.iter().find(|(_, k)| *k == plain).map_or("", |(n, _)| n))?,
        }
        match self.when {
            When::Always => Ok(()),
            When::Nth(n) => write!(f, "@{n}"),
            When::From(n) => write!(f, "@{n}+"),
            When::Chance(p) => write!(f, "@{}%", p * 100.0),
        }
    }
}

/// In the state file as `--fault` writes it.
impl serde::Serialize for FaultSpec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> serde::Deserialize<'de> for FaultSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<FaultSpec, D::Error> {
        <String as serde::Deserialize>::deserialize(d)?.parse().map_err(serde::de::Error::custom)
    }
}

/// Why a fault concerns none of `devices` (model key, node-id), if one does not: a fault
/// for node 99 on a network without it would be accepted and never fire.
pub fn unmatched(faults: &[FaultSpec], devices: &[(String, Option<u8>)]) -> Option<String> {
    let mut device_faults = faults.iter().filter(|f| f.target != Target::Bus);
    let fault = device_faults.find(|f| !devices.iter().any(|(key, node)| f.applies_to(key, *node)))?;
    let nodes: Vec<String> = devices.iter().filter_map(|(_, n)| n.map(|n| n.to_string())).collect();
    let keys: Vec<&str> = devices.iter().map(|(k, _)| k.as_str()).collect();
    Some(format!(
        "--fault {fault}: no device on the sim network is {}; node-ids: {}; model keys: {}",
        match &fault.target {
            Target::Node(n) => format!("node {n}"),
            Target::Model(m) => format!("'{m}'"),
            Target::Bus => "the bus".into(),
        },
        nodes.join(", "),
        keys.join(", ")
    ))
}

/// Whether these faults put the bus's controller bus-off (`bus:off`).
pub fn bus_off(faults: &[FaultSpec]) -> bool {
    faults.iter().any(|f| f.target == Target::Bus)
}

impl FaultSpec {
    fn applies_to(&self, model: &str, node: Option<u8>) -> bool {
        match &self.target {
            Target::Node(n) => node == Some(*n),
            Target::Model(m) => m == model,
            Target::Bus => false,
        }
    }
}

impl When {
    /// Whether a fault with this WHEN fires at the `count`-th thing it counts.
    fn fires(self, count: u32, rng: &mut Rng) -> bool {
        match self {
            When::Always => true,
            When::Nth(n) => count == n,
            When::From(n) => count >= n,
            When::Chance(p) => rng.chance(p),
        }
    }
}

/// The faults of one device and what they have done so far.
#[derive(Debug, Default)]
pub(crate) struct Conduct {
    faults: Vec<FaultSpec>,
    answers: u32,
    muted: bool,
    /// Floods this id once a babble fault has fired.
    babbling: Option<u16>,
    /// Produces no heartbeat once a no-heartbeat fault has fired.
    heartbeat_stopped: bool,
    /// The multiplexer of the last SDO request heard, for an injected abort.
    last_mux: [u8; 3],
    /// A reboot fault fired: the device reboots instead of answering.
    reboot: bool,
    /// Frames heard so far (what a miss fault's WHEN counts).
    heard: u32,
    /// Transfers an endless fault could take, started so far (what its WHEN counts).
    endless_asked: u32,
    /// The never-ending transfer under way, if an endless fault took one.
    endless: EndlessServer,
}

impl Conduct {
    /// The faults among `all` that can concern this device (by model key or any node-id).
    pub fn new(all: &[FaultSpec], model: &str) -> Conduct {
        let faults = all.iter().filter(|f| !matches!(&f.target, Target::Model(m) if m != model)).cloned().collect();
        Conduct { faults, ..Conduct::default() }
    }

    /// Whether a reboot fault fired since the last call.
    pub(crate) fn take_reboot(&mut self) -> bool {
        std::mem::take(&mut self.reboot)
    }

    /// A frame on the bus reaches the device: whether it hears it (a miss fault), and what
    /// an abort names if it does.
    pub fn hears(&mut self, request: &Frame, model: &str, node: Option<u8>, rng: &mut Rng) -> bool {
        self.heard += 1;
        let n = self.heard;
        let missed =
            |s: &FaultSpec, rng: &mut Rng| s.kind == Kind::Miss && s.applies_to(model, node) && s.when.fires(n, rng);
        if self.faults.iter().any(|s| missed(s, rng)) {
            return false;
        }
        self.heard_request(request, node);
        true
    }

    /// The answers to an SDO request `payload` the device heard, when an endless fault
    /// answers it instead of the device's own server: it starts a never-ending transfer, or
    /// goes on with the one under way.
    pub(crate) fn endless_answer(
        &mut self,
        payload: &[u8],
        model: &str,
        node: Option<u8>,
        rng: &mut Rng,
    ) -> Option<Vec<[u8; 8]>> {
        let (kind, when) = self.faults.iter().find_map(|s| match s.kind {
            Kind::Endless(kind) if s.applies_to(model, node) => Some((kind, s.when)),
            _ => None,
        })?;
        if self.endless.busy() {
            if let Some(answers) = self.endless.answer(kind, payload) {
                return Some(answers);
            }
        }
        if !EndlessServer::starts(kind, payload) {
            return None;
        }
        self.endless_asked += 1;
        when.fires(self.endless_asked, rng).then(|| self.endless.answer(kind, payload)).flatten()
    }

    /// A request reached the device (before it answers): remember what an abort names.
    pub fn heard_request(&mut self, request: &Frame, node: Option<u8>) {
        let p = request.data();
        if node.is_some_and(|n| request.id() == sdo::request_cob(n))
            && p.len() == 8
            && matches!(p[0] >> 5, 1 | 2 | 5 | 6)
        {
            self.last_mux = [p[1], p[2], p[3]];
        }
    }

    /// One answer as the faults let it go: the frames that go out, each with how much
    /// later than planned; and whether the SDO server must forget its transfer (an
    /// injected abort ended it).
    pub fn answer(
        &mut self,
        mut f: Frame,
        model: &str,
        node: Option<u8>,
        rng: &mut Rng,
    ) -> (Vec<(Nanos, Frame)>, bool) {
        self.answers += 1;
        let n = self.answers;
        let (mut delay, mut copies, mut sdo_reset) = (0, 1, false);
        // A miss fault is drawn when a frame is heard (`hears`), an endless one when a
        // transfer starts (`endless_answer`), not here.
        let answering = |s: &&FaultSpec| s.applies_to(model, node) && !matches!(s.kind, Kind::Miss | Kind::Endless(_));
        for spec in self.faults.iter().filter(answering) {
            if !spec.when.fires(n, rng) {
                continue;
            }
            match spec.kind {
                Kind::Drop => copies = 0,
                Kind::Mute | Kind::Off => self.muted = true,
                Kind::Delay(ms) => delay += ms as Nanos * MS,
                Kind::Duplicate => copies *= 2,
                Kind::ShortDlc(len) => f = Frame::new(f.id(), &f.data()[..f.len().min(len as usize)]),
                Kind::Corrupt => {
                    let data: Vec<u8> =
                        f.data().iter().enumerate().map(|(i, b)| if i == 0 { !b } else { *b }).collect();
                    f = Frame::new(f.id(), &data);
                }
                Kind::Babble(id) => _ = self.babbling.get_or_insert(id.unwrap_or(own_emcy(node))),
                Kind::Abort(code) => {
                    if node.is_some_and(|n| f.id() == sdo::response_cob(n)) {
                        let [a, b, c] = self.last_mux;
                        let [d0, d1, d2, d3] = code.to_le_bytes();
                        f = Frame::new(f.id(), &[0x80, a, b, c, d0, d1, d2, d3]);
                        sdo_reset = true;
                    }
                }
                Kind::WrongCob(id) => f = Frame::new(id.unwrap_or((f.id() + 1) & 0x7FF), f.data()),
                Kind::NoHeartbeat => self.heartbeat_stopped = true,
                Kind::Reboot => {
                    self.reboot = true;
                    copies = 0;
                }
                Kind::Miss | Kind::Endless(_) => {}
            }
        }
        if self.muted {
            return (vec![], sdo_reset);
        }
        (vec![(delay, f); copies], sdo_reset)
    }

    /// One frame the device sends by itself (heartbeat, timed PDO, EMCY): none once muted,
    /// no heartbeat once stopped (a no-heartbeat fault without WHEN: from the start).
    pub fn own(&self, f: Frame, model: &str, node: Option<u8>) -> Option<Frame> {
        let heartbeat = node.is_some_and(|n| f.id() == crate::canopen::nmt::error_control_cob(n));
        let from_start = |kind| self.standing(model, node).any(|s| s.kind == kind);
        let stopped = self.heartbeat_stopped || from_start(Kind::NoHeartbeat);
        let silenced = self.muted || from_start(Kind::Off) || (heartbeat && stopped);
        (!silenced).then_some(f)
    }

    /// The faults without WHEN that concern the device: in force from the start.
    fn standing<'a>(&'a self, model: &'a str, node: Option<u8>) -> impl Iterator<Item = &'a FaultSpec> {
        self.faults.iter().filter(move |s| s.when == When::Always && s.applies_to(model, node))
    }

    /// The id a babbling device floods the bus with, if it does: a babble fault without
    /// WHEN floods from the start, one with WHEN from that answer on.
    pub fn babbling(&mut self, model: &str, node: Option<u8>) -> Option<u16> {
        if self.babbling.is_none() {
            let from_start = self.standing(model, node).find_map(|s| match s.kind {
                Kind::Babble(id) => Some(id.unwrap_or(own_emcy(node))),
                _ => None,
            });
            self.babbling = from_start;
        }
        self.babbling.filter(|_| !self.muted)
    }
}

/// The EMCY id of this node, which a babble fault floods unless it names one.
fn own_emcy(node: Option<u8>) -> u16 {
    0x80 + node.unwrap_or(0) as u16
}

#[cfg(test)]
mod tests {
    use super::*;

    fn conduct(spec: &str) -> Conduct {
        Conduct::new(&[spec.parse().unwrap()], "sensor")
    }

    fn answer(c: &mut Conduct, f: Frame) -> Vec<(Nanos, Frame)> {
        c.answer(f, "sensor", Some(5), &mut Rng::new(1)).0
    }

    const UPLOAD_ANSWER: [u8; 8] = [0x43, 0x00, 0x10, 0x00, 0x96, 0x01, 0x0A, 0x00];

    fn sdo_answer() -> Frame {
        Frame::new(0x585, &UPLOAD_ANSWER)
    }

    #[test]
    fn specs_parse_and_print_back() {
        for text in [
            "5:drop",
            "5:drop@3",
            "drive:delay=40@2+",
            "10:duplicate",
            "5:short-dlc=3",
            "5:corrupt@50%",
            "5:babble=0x7E4",
            "5:babble",
            "10:abort=0x06020000@2+",
            "sensor-09501301:mute@4+",
            "5:wrong-cob=0x586",
            "5:wrong-cob",
            "10:no-heartbeat",
            "sensor:no-heartbeat@2+",
            "sensor-09501301:miss@5%",
            "10:endless-segments",
            "1:endless-block@2+",
            "1:ack-zero",
        ] {
            let spec: FaultSpec = text.parse().unwrap_or_else(|e| panic!("{text}: {e}"));
            assert_eq!(spec.to_string(), text);
        }
        assert_eq!("5:short-dlc".parse::<FaultSpec>().unwrap().kind, Kind::ShortDlc(4));
        assert_eq!("5:abort".parse::<FaultSpec>().unwrap().kind, Kind::Abort(DEFAULT_ABORT));
        for bad in [
            "drop",
            "0:drop",
            "5:explode",
            "5:delay",
            "5:drop=3",
            "5:drop@0",
            "5:drop@x",
            "5:babble=0x800",
            ":drop",
            "5:no-heartbeat=1",
            "5:miss=2",
        ] {
            assert!(bad.parse::<FaultSpec>().is_err(), "{bad}");
        }
    }

    #[test]
    fn drop_on_the_nth_answer_only() {
        let mut c = conduct("5:drop@2");
        assert_eq!(answer(&mut c, sdo_answer()).len(), 1);
        assert!(answer(&mut c, sdo_answer()).is_empty());
        assert_eq!(answer(&mut c, sdo_answer()).len(), 1);
    }

    #[test]
    fn a_fault_for_another_node_does_nothing() {
        let mut c = conduct("6:drop");
        assert_eq!(answer(&mut c, sdo_answer()), vec![(0, sdo_answer())]);
    }

    #[test]
    fn delay_and_duplicate() {
        assert_eq!(answer(&mut conduct("5:delay=40"), sdo_answer()), vec![(40 * MS, sdo_answer())]);
        assert_eq!(answer(&mut conduct("5:duplicate"), sdo_answer()), vec![(0, sdo_answer()); 2]);
    }

    #[test]
    fn short_dlc_cuts_the_data() {
        let out = answer(&mut conduct("5:short-dlc=3"), sdo_answer());
        assert_eq!(out[0].1.data(), &UPLOAD_ANSWER[..3]);
    }

    #[test]
    fn corrupt_inverts_the_command_specifier() {
        let out = answer(&mut conduct("5:corrupt"), sdo_answer());
        assert_eq!(out[0].1.data()[0], !0x43);
        assert_eq!(out[0].1.data()[1..], UPLOAD_ANSWER[1..]);
    }

    #[test]
    fn abort_names_the_requested_object_and_resets_the_server() {
        let mut c = conduct("5:abort=0x06020000");
        c.heard_request(&Frame::new(0x605, &[0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0]), Some(5));
        let (out, reset) = c.answer(sdo_answer(), "sensor", Some(5), &mut Rng::new(1));
        assert_eq!(out[0].1.data(), &[0x80, 0x18, 0x10, 0x01, 0x00, 0x00, 0x02, 0x06]);
        assert!(reset);
        // Not an SDO answer: left alone.
        let lss = Frame::new(0x7E4, &[0x4F, 0, 0, 0, 0, 0, 0, 0]);
        assert_eq!(answer(&mut c, lss), vec![(0, lss)]);
    }

    #[test]
    fn mute_from_the_nth_answer_silences_everything_after() {
        let mut c = conduct("5:mute@3+");
        assert_eq!(answer(&mut c, sdo_answer()).len(), 1);
        assert_eq!(answer(&mut c, sdo_answer()).len(), 1);
        assert!(answer(&mut c, sdo_answer()).is_empty());
        assert!(c.own(Frame::new(0x705, &[0x7F]), "sensor", Some(5)).is_none());
        assert!(answer(&mut c, sdo_answer()).is_empty());
    }

    #[test]
    fn wrong_cob_moves_the_answer() {
        assert_eq!(answer(&mut conduct("5:wrong-cob"), sdo_answer())[0].1.id(), 0x586);
        assert_eq!(answer(&mut conduct("5:wrong-cob=0x123"), sdo_answer())[0].1.id(), 0x123);
    }

    #[test]
    fn the_bus_takes_only_off() {
        let f: FaultSpec = "bus:off".parse().unwrap();
        assert_eq!((f.target.clone(), f.to_string()), (Target::Bus, "bus:off".to_string()));
        assert!(bus_off(std::slice::from_ref(&f)));
        assert!(!bus_off(&["5:off".parse().unwrap()]));
        for bad in ["bus:drop", "bus:off@2", "bus:mute"] {
            assert!(bad.parse::<FaultSpec>().is_err(), "{bad}");
        }
        // It concerns no device, and is not reported as one that matches none.
        assert_eq!(unmatched(&[f], &[("sensor".into(), Some(5))]), None);
    }

    #[test]
    fn babble_starts_when_it_fires() {
        let mut c = conduct("5:babble=0x7E4@2");
        assert_eq!(c.babbling("sensor", Some(5)), None);
        answer(&mut c, sdo_answer());
        assert_eq!(c.babbling("sensor", Some(5)), None);
        answer(&mut c, sdo_answer());
        assert_eq!(c.babbling("sensor", Some(5)), Some(0x7E4));
        // Without WHEN: from the start, on its EMCY id; its answers still go.
        let mut c = conduct("5:babble");
        assert_eq!(c.babbling("sensor", Some(5)), Some(0x85));
        assert_eq!(answer(&mut c, sdo_answer()).len(), 1);
    }

    #[test]
    fn chance_replays_from_the_seed() {
        let draws = |seed| {
            let mut c = conduct("5:drop@50%");
            let mut rng = Rng::new(seed);
            (0..64).map(|_| c.answer(sdo_answer(), "sensor", Some(5), &mut rng).0.is_empty()).collect::<Vec<_>>()
        };
        let a = draws(9);
        assert_eq!(a, draws(9));
        let dropped = a.iter().filter(|d| **d).count();
        assert!((16..=48).contains(&dropped), "{dropped} of 64");
    }

    #[test]
    fn no_heartbeat_silences_only_the_heartbeat() {
        let beat = Frame::new(0x705, &[0x7F]);
        let emcy = Frame::new(0x85, &[0, 0x50, 0x81, 0, 0, 0, 0, 0]);
        let c = conduct("5:no-heartbeat");
        assert_eq!(c.own(beat, "sensor", Some(5)), None);
        assert_eq!(c.own(emcy, "sensor", Some(5)), Some(emcy));
        // Another node's fault: this one keeps beating.
        assert_eq!(conduct("6:no-heartbeat").own(beat, "sensor", Some(5)), Some(beat));
        // From the 2nd answer on: beats until then, and its answers still go.
        let mut c = conduct("5:no-heartbeat@2+");
        assert_eq!(c.own(beat, "sensor", Some(5)), Some(beat));
        assert_eq!(answer(&mut c, sdo_answer()).len(), 1);
        assert_eq!(answer(&mut c, sdo_answer()).len(), 1);
        assert_eq!(c.own(beat, "sensor", Some(5)), None);
    }

    #[test]
    fn a_device_that_is_off_sends_nothing_from_the_start() {
        let beat = Frame::new(0x705, &[0x7F]);
        let mut c = conduct("sensor:off");
        assert_eq!("sensor:off".parse::<FaultSpec>().unwrap().to_string(), "sensor:off");
        assert_eq!(c.own(beat, "sensor", Some(5)), None, "no heartbeat before any request");
        assert!(answer(&mut c, sdo_answer()).is_empty());
        assert_eq!(conduct("drive:off").own(beat, "sensor", Some(5)), Some(beat), "another device is powered");
    }
}
