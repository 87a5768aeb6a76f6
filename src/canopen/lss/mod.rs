//! Layer setting services (CiA 305): node-ids and bit rates for devices that have none or
//! share one. Master requests go on 0x7E5, slave answers on 0x7E4; all frames are 8 bytes.
//! Pure encoding, the fastscan search, and the slave's state machine (for the simulator).

use std::collections::VecDeque;
use std::fmt;
use std::time::Duration;

pub const MASTER_COB: u16 = 0x7E5;
pub const SLAVE_COB: u16 = 0x7E4;
/// The node-id of a device that has none ("not configured").
pub const UNCONFIGURED: u8 = 0xFF;

/// The LSS address: the four entries of the identity object 0x1018.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
pub struct Identity {
    pub vendor: u32,
    pub product: u32,
    pub revision: u32,
    pub serial: u32,
}

impl Identity {
    pub fn part(&self, i: u8) -> u32 {
        match i {
            0 => self.vendor,
            1 => self.product,
            2 => self.revision,
            _ => self.serial,
        }
    }

    fn set_part(&mut self, i: u8, v: u32) {
        match i {
            0 => self.vendor = v,
            1 => self.product = v,
            2 => self.revision = v,
            _ => self.serial = v,
        }
    }
}

/// `0x00000040:0x43787800:0x312E3031:0x09501234`
impl fmt::Display for Identity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "0x{:08X}:0x{:08X}:0x{:08X}:0x{:08X}", self.vendor, self.product, self.revision, self.serial)
    }
}

/// VENDOR:PRODUCT:REVISION:SERIAL, each decimal or 0x hex.
impl std::str::FromStr for Identity {
    type Err = String;

    fn from_str(s: &str) -> Result<Identity, String> {
        let parts: Vec<&str> = s.split(':').collect();
        if parts.len() != 4 {
            return Err(format!("'{s}' is not an LSS identity: use VENDOR:PRODUCT:REVISION:SERIAL, e.g. 0x40:0x43787800:0x312E3031:0x09501234"));
        }
        let mut id = Identity::default();
        for (i, p) in parts.iter().enumerate() {
            let v = match p.strip_prefix("0x").or_else(|| p.strip_prefix("0X")) {
                Some(h) => u32::from_str_radix(h, 16),
                None => p.parse(),
            }
            .map_err(|_| format!("'{p}' in '{s}' is not a 32-bit number (decimal, or hex with 0x)"))?;
            id.set_part(i as u8, v);
        }
        Ok(id)
    }
}

/// CiA 305 table of bit timings (selector 0): index → bit rate in kbit/s.
pub const BIT_TIMINGS: [(u8, Option<u32>); 10] = [
    (0, Some(1000)),
    (1, Some(800)),
    (2, Some(500)),
    (3, Some(250)),
    (4, Some(125)),
    (5, None), // reserved
    (6, Some(50)),
    (7, Some(20)),
    (8, Some(10)),
    (9, None), // automatic bit rate detection
];
pub const AUTO_BIT_RATE: u8 = 9;

/// `500k`, `1M`, `125000`, `auto` → CiA 305 table index.
pub fn parse_bit_rate(text: &str) -> Result<u8, String> {
    let t = text.trim().to_ascii_lowercase();
    if t == "auto" {
        return Ok(AUTO_BIT_RATE);
    }
    let kbit = if let Some(k) = t.strip_suffix('k') {
        k.parse::<f64>().ok()
    } else if let Some(m) = t.strip_suffix('m') {
        m.parse::<f64>().ok().map(|m| m * 1000.0)
    } else {
        t.parse::<f64>().ok().map(|b| b / 1000.0)
    };
    let valid = "1M 800k 500k 250k 125k 50k 20k 10k or auto (CiA 305 has no entry for 100k)";
    let kbit = kbit.ok_or_else(|| format!("'{text}' is not a bit rate: use {valid}"))?;
    BIT_TIMINGS
        .iter()
        .find(|(_, k)| k.is_some_and(|k| k as f64 == kbit))
        .map(|(i, _)| *i)
        .ok_or_else(|| format!("{text} is not in the CiA 305 bit timing table: use {valid}"))
}

pub fn bit_rate_name(index: u8) -> String {
    match BIT_TIMINGS.get(index as usize) {
        Some((_, Some(k))) if *k >= 1000 => format!("{}M", k / 1000),
        Some((_, Some(k))) => format!("{k}k"),
        Some((AUTO_BIT_RATE, None)) => "auto".into(),
        _ => format!("reserved ({index})"),
    }
}

/// Which identity part an inquiry asks for, or the node-id.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Inquiry {
    Vendor,
    Product,
    Revision,
    Serial,
    NodeId,
}

impl Inquiry {
    fn cs(self) -> u8 {
        match self {
            Inquiry::Vendor => 0x5A,
            Inquiry::Product => 0x5B,
            Inquiry::Revision => 0x5C,
            Inquiry::Serial => 0x5D,
            Inquiry::NodeId => 0x5E,
        }
    }
}

/// A master request.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Request {
    SwitchGlobal {
        configuration: bool,
    },
    /// Part 0..3 of the identity: vendor, product, revision, serial.
    SwitchSelective {
        part: u8,
        value: u32,
    },
    ConfigureNodeId(u8),
    ConfigureBitTiming {
        table: u8,
        index: u8,
    },
    ActivateBitTiming {
        delay_ms: u16,
    },
    StoreConfiguration,
    Inquire(Inquiry),
    /// 0x46..0x4B: vendor, product, revision low/high, serial low/high.
    IdentifyRemote {
        field: u8,
        value: u32,
    },
    IdentifyNonConfigured,
    Fastscan {
        id: u32,
        bit_checked: u8,
        sub: u8,
        next: u8,
    },
}

/// Fastscan's "bit checked" value that restarts the search.
pub const FASTSCAN_RESET: u8 = 0x80;

impl Request {
    pub fn encode(&self) -> [u8; 8] {
        let mut f = [0u8; 8];
        let put32 = |f: &mut [u8; 8], v: u32| f[1..5].copy_from_slice(&v.to_le_bytes());
        match *self {
            Request::SwitchGlobal { configuration } => {
                f[0] = 0x04;
                f[1] = configuration as u8;
            }
            Request::SwitchSelective { part, value } => {
                f[0] = 0x40 + part;
                put32(&mut f, value);
            }
            Request::ConfigureNodeId(id) => {
                f[0] = 0x11;
                f[1] = id;
            }
            Request::ConfigureBitTiming { table, index } => {
                f[0] = 0x13;
                f[1] = table;
                f[2] = index;
            }
            Request::ActivateBitTiming { delay_ms } => {
                f[0] = 0x15;
                f[1..3].copy_from_slice(&delay_ms.to_le_bytes());
            }
            Request::StoreConfiguration => f[0] = 0x17,
            Request::Inquire(q) => f[0] = q.cs(),
            Request::IdentifyRemote { field, value } => {
                f[0] = field;
                put32(&mut f, value);
            }
            Request::IdentifyNonConfigured => f[0] = 0x4C,
            Request::Fastscan { id, bit_checked, sub, next } => {
                f[0] = 0x51;
                put32(&mut f, id);
                f[5] = bit_checked;
                f[6] = sub;
                f[7] = next;
            }
        }
        f
    }

    pub fn decode(d: &[u8]) -> Option<Request> {
        if d.len() != 8 {
            return None;
        }
        let v = u32::from_le_bytes([d[1], d[2], d[3], d[4]]);
        Some(match d[0] {
            0x04 if d[1] <= 1 => Request::SwitchGlobal { configuration: d[1] == 1 },
            0x40..=0x43 => Request::SwitchSelective { part: d[0] - 0x40, value: v },
            0x11 => Request::ConfigureNodeId(d[1]),
            0x13 => Request::ConfigureBitTiming { table: d[1], index: d[2] },
            0x15 => Request::ActivateBitTiming { delay_ms: u16::from_le_bytes([d[1], d[2]]) },
            0x17 => Request::StoreConfiguration,
            0x5A => Request::Inquire(Inquiry::Vendor),
            0x5B => Request::Inquire(Inquiry::Product),
            0x5C => Request::Inquire(Inquiry::Revision),
            0x5D => Request::Inquire(Inquiry::Serial),
            0x5E => Request::Inquire(Inquiry::NodeId),
            0x46..=0x4B => Request::IdentifyRemote { field: d[0], value: v },
            0x4C => Request::IdentifyNonConfigured,
            0x51 => Request::Fastscan { id: v, bit_checked: d[5], sub: d[6], next: d[7] },
            _ => return None,
        })
    }
}

/// A slave answer.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Response {
    SwitchSelectiveAck,
    /// Answer to configure node-id (0x11), configure bit timing (0x13) or store (0x17):
    /// the command, its error code and the implementation-specific code.
    Result {
        cs: u8,
        error: u8,
        specific: u8,
    },
    InquiredValue {
        inquiry: Inquiry,
        value: u32,
    },
    IdentifySlave,
    IdentifyNonConfiguredSlave,
}

impl Response {
    pub fn encode(&self) -> [u8; 8] {
        let mut f = [0u8; 8];
        match *self {
            Response::SwitchSelectiveAck => f[0] = 0x44,
            Response::Result { cs, error, specific } => {
                f[0] = cs;
                f[1] = error;
                f[2] = specific;
            }
            Response::InquiredValue { inquiry: Inquiry::NodeId, value } => {
                f[0] = 0x5E;
                f[1] = value as u8;
            }
            Response::InquiredValue { inquiry, value } => {
                f[0] = inquiry.cs();
                f[1..5].copy_from_slice(&value.to_le_bytes());
            }
            Response::IdentifySlave => f[0] = 0x4F,
            Response::IdentifyNonConfiguredSlave => f[0] = 0x50,
        }
        f
    }

    pub fn decode(d: &[u8]) -> Option<Response> {
        if d.len() != 8 {
            return None;
        }
        let v = u32::from_le_bytes([d[1], d[2], d[3], d[4]]);
        Some(match d[0] {
            0x44 => Response::SwitchSelectiveAck,
            cs @ (0x11 | 0x13 | 0x17) => Response::Result { cs, error: d[1], specific: d[2] },
            0x5A => Response::InquiredValue { inquiry: Inquiry::Vendor, value: v },
            0x5B => Response::InquiredValue { inquiry: Inquiry::Product, value: v },
            0x5C => Response::InquiredValue { inquiry: Inquiry::Revision, value: v },
            0x5D => Response::InquiredValue { inquiry: Inquiry::Serial, value: v },
            0x5E => Response::InquiredValue { inquiry: Inquiry::NodeId, value: d[1] as u32 },
            0x4F => Response::IdentifySlave,
            0x50 => Response::IdentifyNonConfiguredSlave,
            _ => return None,
        })
    }
}

/// The meaning of an error code in the answer to command `cs` (CiA 305; seed 001 §10.1).
pub fn error_meaning(cs: u8, error: u8) -> &'static str {
    match (cs, error) {
        (_, 0) => "protocol successfully completed",
        (0x11, 1) => "node-id out of range",
        (0x13, 1) => "bit timing not supported",
        (0x17, 1) => "store configuration not supported",
        (0x17, 2) => "storage media access error",
        (_, 255) => "implementation-specific error (see the specific code)",
        _ => "reserved error code",
    }
}

impl Request {
    /// The command specifier of the slave answer this request expects, if it has one:
    /// only a frame with it counts as an answer (a heartbeat or a stray frame on 0x7E4
    /// does not).
    pub fn expected_answer(&self) -> Option<u8> {
        match *self {
            Request::SwitchSelective { part: 3, .. } => Some(0x44),
            Request::ConfigureNodeId(_) => Some(0x11),
            Request::ConfigureBitTiming { .. } => Some(0x13),
            Request::StoreConfiguration => Some(0x17),
            Request::Inquire(q) => Some(q.cs()),
            Request::IdentifyRemote { field: 0x4B, .. } | Request::Fastscan { .. } => Some(0x4F),
            Request::IdentifyNonConfigured => Some(0x50),
            _ => None,
        }
    }
}

/// Whether `data` (a frame on 0x7E4) is a well-formed slave answer with command specifier
/// `expect`: 8 bytes, that specifier, and for the answers that carry nothing but it
/// (0x44, 0x4F, 0x50) the reserved bytes 0, so that a babbling device's counter on 0x7E4
/// does not pass for a device.
pub fn is_answer(data: &[u8], expect: u8) -> bool {
    data.len() == 8 && data[0] == expect && (!matches!(expect, 0x44 | 0x4F | 0x50) || data[1..] == [0; 7])
}

/// The four selective-switch requests for one device; the answer is 0x44 from it alone.
pub fn switch_selective(id: &Identity) -> [Request; 4] {
    [0, 1, 2, 3].map(|part| Request::SwitchSelective { part, value: id.part(part) })
}

/// The shortest fastscan step: enough for slaves on the same machine or a quiet bus.
pub const STEP_FLOOR: Duration = Duration::from_millis(10);
/// The longest: a slave slower than this is broken, not slow.
pub const STEP_CEILING: Duration = Duration::from_secs(2);
/// How many times a search may lengthen its step (or, at a fixed step, retry) before it
/// gives up.
pub const MAX_ESCALATIONS: u32 = 4;
/// How many more times a request whose answer is missing where one is due (a confirmation,
/// a reset, the last "anybody there?") is sent before the silence counts: a frame lost on
/// the way, to or from the slaves, is not a slow slave, and asking again brings the answer
/// back where a longer step cannot.
pub const REPEATS: u32 = 2;
/// How many times one fastscan may search again from a reset (a part not confirmed, a
/// device that answered the last "anybody there?" but not the reset) before it gives up:
/// under heavy loss every search has a fair chance, and none is certain.
pub const MAX_SEARCHES: u32 = 24;
/// How many times a part whose confirmation went unanswered is searched again from the
/// bit that was likely lost, before the whole part is searched again from a reset.
pub const BACKTRACKS: u32 = 4;
/// The bus time one fastscan may spend waiting for answers: one whole search at the
/// longest step. Searches again at a long step run out of this before [`MAX_SEARCHES`].
pub const SEARCH_BUDGET: Duration = Duration::from_secs(2 * 133);
/// How many of the latest answer times the step is learned from.
const RECENT_ANSWERS: usize = 64;

/// How long fastscan waits for answers: learned from the slaves' own answer times (or
/// fixed by the user), lengthened when answers turn out to come later than that.
#[derive(Clone, Debug)]
pub struct Pace {
    fixed: Option<Duration>,
    /// The slowest answer seen so far, timed from its request.
    slowest: Option<Duration>,
    /// The latest answer times: the step follows these, so that one answer held up once
    /// (a busy bus, a busy host) does not slow every later step.
    recent: VecDeque<Duration>,
    escalations: u32,
    /// The window of the first probe, before anything is known.
    probe_window: Duration,
    /// The longest step used so far.
    longest_used: Duration,
    /// Frames were lost on this bus (a request asked again was answered, a part had to be
    /// searched again): from then on a silent bit check is asked once more too.
    loss_seen: bool,
}

impl Pace {
    /// A pace still to be measured; the first probe waits `probe_window`.
    pub fn measured(probe_window: Duration) -> Pace {
        Pace {
            fixed: None,
            slowest: None,
            recent: VecDeque::new(),
            escalations: 0,
            probe_window: probe_window.clamp(STEP_FLOOR, STEP_CEILING),
            longest_used: Duration::ZERO,
            loss_seen: false,
        }
    }

    /// The step the user chose (`--step`): used instead of one learned from the answer
    /// times, and lengthened only when answers come later than it.
    pub fn fixed(step: Duration, probe_window: Duration) -> Pace {
        Pace { fixed: Some(step), ..Pace::measured(probe_window) }
    }

    /// Whether a step can be derived yet.
    pub fn known(&self) -> bool {
        self.fixed.is_some() || self.slowest.is_some()
    }

    /// A slave answered `after` its request was sent.
    pub fn observe(&mut self, after: Duration) {
        self.slowest = Some(self.slowest.map_or(after, |s| s.max(after)));
        if self.recent.len() == RECENT_ANSWERS {
            self.recent.pop_front();
        }
        self.recent.push_back(after);
    }

    /// The slowest and fastest of the latest answers.
    fn recent_range(&self) -> Option<(Duration, Duration)> {
        Some((*self.recent.iter().max()?, *self.recent.iter().min()?))
    }

    /// How long one fastscan step waits for an answer: half as long again as the slowest
    /// of the latest answers plus a margin, doubled for each escalation.
    pub fn step(&self) -> Duration {
        let base = match self.fixed {
            Some(step) => step,
            None => {
                let slowest = self.recent_range().map_or(self.probe_window, |(s, _)| s);
                (slowest * 3 / 2 + Duration::from_millis(5)).clamp(STEP_FLOOR, STEP_CEILING)
            }
        };
        (base * (1 << self.escalations.min(8))).min(STEP_CEILING.max(base))
    }

    /// After the first answer to a request, how much longer the others may come: the
    /// spread of the answer times seen and a quarter step more, so that a straggler does
    /// not count for the next request.
    pub fn settle(&self) -> Duration {
        let spread = self.recent_range().map_or(Duration::ZERO, |(s, f)| s - f);
        (spread + (self.step() / 4).max(Duration::from_millis(2))).min(self.step())
    }

    pub fn probe_window(&self) -> Duration {
        self.probe_window
    }

    /// The window of the "is anybody still there?" probe before fastscan says nobody is:
    /// several times the slowest answer seen.
    pub fn final_window(&self) -> Duration {
        let several = self.recent_range().map_or(self.probe_window, |(s, _)| s * 4);
        several.max(self.step() * 2).clamp(STEP_FLOOR, STEP_CEILING)
    }

    /// Answers came later than the step allowed: lengthen it. False when no more.
    pub fn escalate(&mut self) -> bool {
        if self.escalations >= MAX_ESCALATIONS || self.step() >= STEP_CEILING {
            return false;
        }
        self.escalations += 1;
        true
    }

    pub fn escalations(&self) -> u32 {
        self.escalations
    }

    /// The slowest answer seen so far.
    pub fn slowest(&self) -> Option<Duration> {
        self.slowest
    }

    /// The longest step a fastscan waited.
    pub fn longest_step(&self) -> Duration {
        self.longest_used
    }
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum FastscanError {
    /// Nobody answered: no non-configured device in waiting state.
    NoDevice,
    /// A part that every bit matched was not confirmed, even with the longest step:
    /// devices changed meanwhile, or frames were lost.
    Unconfirmed(u8),
    /// No device without a node-id has this part (given by the user) of its identity.
    NoMatch { part: u8, value: u32 },
    /// A device answered once, then no more, even with the longest step.
    Lost,
}

/// What the fastscan driver wants done next.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum FastscanNext {
    Send(Ask),
    /// The device found; it is in configuration state now.
    Found(Identity),
    Failed(FastscanError),
}

/// One request and how to wait for its answers.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Ask {
    pub request: Request,
    /// The command specifier an answer must carry.
    pub expect: u8,
    /// How long after sending answers count.
    pub window: Duration,
    /// After the first answer, wait this much longer for others (capped by the window);
    /// `None`: collect every answer within the window.
    pub settle: Option<Duration>,
}

/// One identity part, as far as the search knows it.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Part {
    Unknown,
    /// Given by the user: confirmed in one step, never searched.
    Given(u32),
    /// Found bit by bit and confirmed.
    Found(u32),
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Phase {
    /// "Identify non-configured remote slave" with a generous window: is anybody there,
    /// and how late do they answer?
    Probe,
    /// Fastscan reset: every non-configured device takes part again from part 0.
    Reset,
    /// Asking whether bit `n` of the current part is 0 (the bits above as found).
    Bit(u8),
    /// The current part's whole value, bit-checked 0: the matching devices move on.
    Confirm,
    /// Part `n` of the identity found, asked of the device in configuration state: a
    /// fastscan answer says nothing of the request it answers, so one held up into the
    /// serial's confirmation "confirms" a value nobody has. The device's own answer does.
    Verify(u8),
    /// Nobody answered the reset at the learned pace: ask once more with a long window
    /// before saying nobody is there.
    FinalProbe,
    /// The last part's confirmation went unanswered: the device may have taken it (and
    /// its answer been lost), so it is in configuration state, out of every later search,
    /// and would take the next device's node-id too. Every device back to waiting state
    /// (no answer to this) before the search goes again.
    Waiting,
    Over,
}

/// Fastscan (CiA 305 §8.4.3), the master side, sans I/O: says which request to send and
/// how long to wait; the caller reports the answers with their times. Finds the whole
/// identity of one non-configured device in waiting state (133 fastscan requests when
/// nothing is known), skipping the parts the user gives. A part found bit by bit and not
/// confirmed (an answer lost, or late into another request's window) is searched again,
/// keeping the parts found; the step is lengthened only on evidence of lateness (an answer
/// seen later than the step, or one that came between windows), since a longer step
/// brings no lost answer back. At most [`MAX_SEARCHES`] searches and [`SEARCH_BUDGET`].
#[derive(Clone, Debug)]
pub struct Fastscan {
    pace: Pace,
    parts: [Part; 4],
    sub: u8,
    /// The value of the current part as far as searched.
    value: u32,
    phase: Phase,
    outcome: Option<Result<Identity, FastscanError>>,
    /// Fastscan requests sent.
    steps: u32,
    /// Whether any device answered so far: silence afterwards is lateness or loss.
    seen: bool,
    /// How many times the current request was sent again after a silence ([`REPEATS`]).
    repeats: u32,
    /// How many times the search started again from a reset ([`MAX_SEARCHES`]).
    searches: u32,
    /// The bus time waited for answers so far ([`SEARCH_BUDGET`]).
    waited: Duration,
    /// A fastscan answer came between two windows (late for its own): the driver says so.
    late: bool,
    /// How many times the current part was searched again from a bit ([`BACKTRACKS`]).
    backtracks: u32,
    /// How many times somebody answered "anybody there?" after the reset went unanswered
    /// (three times): more than [`REPEATS`] is no loss, the answers are not the device's.
    unanswered_resets: u32,
}

impl Fastscan {
    /// `given`: identity parts (vendor, product, revision, serial) already known.
    pub fn new(pace: Pace, given: [Option<u32>; 4]) -> Fastscan {
        let phase = if pace.known() { Phase::Reset } else { Phase::Probe };
        Fastscan {
            pace,
            parts: given.map(|g| g.map_or(Part::Unknown, Part::Given)),
            sub: 0,
            value: 0,
            phase,
            outcome: None,
            steps: 0,
            seen: false,
            repeats: 0,
            searches: 0,
            waited: Duration::ZERO,
            late: false,
            unanswered_resets: 0,
            backtracks: 0,
        }
    }

    /// Fastscan requests sent so far.
    pub fn steps(&self) -> u32 {
        self.steps
    }

    pub fn pace(&self) -> &Pace {
        &self.pace
    }

    /// The pace learned, for the next search on the same bus.
    pub fn into_pace(self) -> Pace {
        self.pace
    }

    /// LSS frames that came between two requests' windows (the driver drains them before
    /// each request): a fastscan answer among them came later than its window allowed,
    /// which is evidence of lateness.
    pub fn on_strays(&mut self, frames: &[[u8; 8]]) {
        self.late |= frames.iter().any(|f| is_answer(f, 0x4F));
    }

    /// Whether answers are known to come later than the step: one came between windows,
    /// or the step is the user's and shorter than answers seen in a longer window (a
    /// probe). A learned step follows the answers by itself.
    fn lateness_seen(&self) -> bool {
        self.late || (self.pace.fixed.is_some() && self.pace.slowest.is_some_and(|s| s > self.pace.step()))
    }

    pub fn next(&self) -> FastscanNext {
        if let Some(outcome) = self.outcome {
            return match outcome {
                Ok(id) => FastscanNext::Found(id),
                Err(e) => FastscanNext::Failed(e),
            };
        }
        let fastscan = |request: Request| Ask {
            request,
            expect: 0x4F,
            window: self.pace.step(),
            settle: Some(self.pace.settle()),
        };
        let sub = self.sub;
        FastscanNext::Send(match self.phase {
            Phase::Probe => Ask {
                request: Request::IdentifyNonConfigured,
                expect: 0x50,
                window: self.pace.probe_window(),
                settle: None,
            },
            Phase::FinalProbe => Ask {
                request: Request::IdentifyNonConfigured,
                expect: 0x50,
                window: self.pace.final_window(),
                settle: None,
            },
            Phase::Reset if !self.pace.known() => Ask {
                window: self.pace.probe_window(),
                ..fastscan(Request::Fastscan { id: 0, bit_checked: FASTSCAN_RESET, sub: 0, next: 0 })
            },
            Phase::Reset => fastscan(Request::Fastscan { id: 0, bit_checked: FASTSCAN_RESET, sub: 0, next: 0 }),
            Phase::Bit(bit) => fastscan(Request::Fastscan { id: self.value, bit_checked: bit, sub, next: sub }),
            Phase::Waiting => Ask {
                request: Request::SwitchGlobal { configuration: false },
                expect: 0,
                window: STEP_FLOOR,
                settle: None,
            },
            Phase::Verify(part) => {
                let inquiry = [Inquiry::Vendor, Inquiry::Product, Inquiry::Revision, Inquiry::Serial][part as usize];
                Ask { expect: inquiry.cs(), ..fastscan(Request::Inquire(inquiry)) }
            }
            Phase::Confirm | Phase::Over => {
                fastscan(Request::Fastscan { id: self.value, bit_checked: 0, sub, next: (sub + 1) % 4 })
            }
        })
    }

    /// The answers to the request `next` asked for: each with the time it came after the
    /// request was sent. Frames with another command specifier are not answers; answers
    /// after the window are late: they lengthen the step and the request is asked again.
    pub fn on_answers(&mut self, answers: &[(Duration, [u8; 8])]) {
        let FastscanNext::Send(ask) = self.next() else { return };
        let valid: Vec<Duration> = answers.iter().filter(|(_, d)| is_answer(d, ask.expect)).map(|(t, _)| *t).collect();
        for t in &valid {
            self.pace.observe(*t);
        }
        if matches!(ask.request, Request::Fastscan { .. }) {
            self.steps += 1;
            self.pace.longest_used = self.pace.longest_used.max(ask.window);
        }
        // What the driver waited: the window, or up to the settle after the first answer.
        let first = valid.iter().filter(|t| **t <= ask.window).min();
        self.waited += match (ask.settle, first) {
            (Some(settle), Some(first)) => (*first + settle).min(ask.window),
            _ => ask.window,
        };
        let in_time = valid.iter().any(|t| *t <= ask.window);
        if !in_time && !valid.is_empty() {
            // Only late answers: what silence would mean is not true. Ask again, slower.
            self.repeats = 0;
            if !self.pace.escalate() {
                self.fail(FastscanError::Lost);
            }
            return;
        }
        self.seen |= in_time;
        if let Phase::Verify(part) = self.phase {
            let found = self.found().part(part);
            let held: Vec<u32> = answers
                .iter()
                .filter(|(t, d)| *t <= ask.window && is_answer(d, ask.expect))
                .map(|(_, d)| u32::from_le_bytes([d[1], d[2], d[3], d[4]]))
                .collect();
            // Devices an earlier search left in configuration state answer too.
            let verified = held.contains(&found);
            if !verified && self.repeats < REPEATS {
                self.repeats += 1;
                return;
            }
            if verified && self.repeats > 0 {
                self.pace.loss_seen = true;
            }
            self.repeats = 0;
            match verified {
                true if part == 3 => {
                    self.outcome = Some(Ok(self.found()));
                    self.phase = Phase::Over;
                }
                true => self.phase = Phase::Verify(part + 1),
                // Nobody in configuration state has it: the serial was not the device's.
                false => self.unconfirmed(3),
            }
            return;
        }
        // Silence where an answer is due: first ask again, at the same step (a lost frame).
        // Silence to a bit check means a 1, or, once this bus has lost frames, perhaps a
        // lost answer: asked once more then.
        let repeats = match self.phase {
            Phase::Confirm | Phase::FinalProbe => REPEATS,
            Phase::Reset if self.seen => REPEATS,
            Phase::Bit(_) if self.pace.loss_seen => 1,
            _ => 0,
        };
        if !in_time && self.repeats < repeats {
            self.repeats += 1;
            return;
        }
        if in_time && self.repeats > 0 {
            self.pace.loss_seen = true;
        }
        self.repeats = 0;
        match self.phase {
            Phase::Probe | Phase::Waiting => self.phase = Phase::Reset,
            // Somebody is there, and did not answer the reset (lost three times, or late).
            Phase::FinalProbe if in_time => {
                // Late answers explain it (and lengthen the step); else it must not go on.
                self.unanswered_resets += u32::from(!self.lateness_seen());
                match self.unanswered_resets > REPEATS {
                    true => self.fail(FastscanError::Lost),
                    false => self.search_again_or(FastscanError::Lost),
                }
            }
            // A device answered earlier in this search and no more: it left.
            Phase::FinalProbe if self.seen => self.fail(FastscanError::Lost),
            Phase::FinalProbe => self.fail(FastscanError::NoDevice),
            Phase::Reset if in_time => {
                self.sub = 0;
                self.start_part();
            }
            Phase::Reset if !self.seen && !self.pace.known() => self.fail(FastscanError::NoDevice),
            Phase::Reset => self.phase = Phase::FinalProbe,
            Phase::Bit(bit) => {
                // No answer to "is bit `bit` 0?": every device still in the search has a 1.
                if !in_time {
                    self.value |= 1 << bit;
                }
                self.phase = if bit == 0 { Phase::Confirm } else { Phase::Bit(bit - 1) };
            }
            Phase::Confirm if in_time => {
                self.backtracks = 0;
                if self.parts[self.sub as usize] == Part::Unknown {
                    self.parts[self.sub as usize] = Part::Found(self.value);
                }
                if self.sub == 3 {
                    // The device that matched the serial is in configuration state now,
                    // if the answer was to this request.
                    self.phase = Phase::Verify(0);
                } else {
                    self.sub += 1;
                    self.start_part();
                }
            }
            Phase::Confirm => self.backtrack(),
            Phase::Verify(_) | Phase::Over => {}
        }
    }

    /// The identity as searched and confirmed.
    fn found(&self) -> Identity {
        let v = |p: Part| match p {
            Part::Given(v) | Part::Found(v) => v,
            Part::Unknown => unreachable!("every part confirmed"),
        };
        let [vendor, product, revision, serial] = self.parts.map(v);
        Identity { vendor, product, revision, serial }
    }

    /// The confirmation of a part searched bit by bit went unanswered. When a bit check's
    /// answer is lost, that bit reads 1, and every check below it, matching nobody now,
    /// reads 1 too: the lost one is in the trailing run of ones. An answer late into
    /// another check's window makes a bit read 0, and every bit below it 1: it is the 0
    /// just above that run. Those bits are checked again (the bits above kept; a slave
    /// keeps its place in the search between checks), a few times before the whole part
    /// is searched again from a reset. Not the serial: its confirmation may have put the
    /// device in configuration state, its answer lost, and only a reset takes it back
    /// before another device is found.
    fn backtrack(&mut self) {
        if self.sub == 3 || self.parts[self.sub as usize] != Part::Unknown || self.backtracks >= BACKTRACKS {
            return self.unconfirmed(self.sub);
        }
        self.backtracks += 1;
        self.pace.loss_seen = true;
        let top = self.value.trailing_ones().min(31);
        self.value &= !((2u64 << top) - 1) as u32;
        self.phase = Phase::Bit(top as u8);
    }

    /// Part `sub` was not confirmed: a late answer made a bit look like 1 (or a device
    /// left). Search this part again, from a reset, keeping the parts before it.
    fn unconfirmed(&mut self, sub: u8) {
        self.backtracks = 0;
        let error = match self.parts[sub as usize] {
            Part::Given(value) => FastscanError::NoMatch { part: sub, value },
            _ => FastscanError::Unconfirmed(sub),
        };
        if let Part::Found(_) = self.parts[sub as usize] {
            self.parts[sub as usize] = Part::Unknown;
        }
        // Confirmations repeated in vain: a bit check's answer was lost (or came late).
        self.pace.loss_seen = true;
        self.search_again_or(error);
        if sub == 3 && self.phase == Phase::Reset {
            self.phase = Phase::Waiting;
        }
    }

    fn start_part(&mut self) {
        match self.parts[self.sub as usize] {
            Part::Given(v) | Part::Found(v) => {
                self.value = v;
                self.phase = Phase::Confirm;
            }
            Part::Unknown => {
                self.value = 0;
                self.phase = Phase::Bit(31);
            }
        }
    }

    /// Start over from a reset, with a longer step if answers are known to come late; or
    /// fail with `error` when the searches or the time are used up, or the step can grow
    /// no more.
    fn search_again_or(&mut self, error: FastscanError) {
        self.searches += 1;
        if self.searches > MAX_SEARCHES || self.waited >= SEARCH_BUDGET {
            return self.fail(error);
        }
        if self.lateness_seen() {
            self.late = false;
            if !self.pace.escalate() {
                return self.fail(error);
            }
        }
        self.phase = Phase::Reset;
    }

    fn fail(&mut self, error: FastscanError) {
        self.outcome = Some(Err(error));
        self.phase = Phase::Over;
    }
}

/// LSS state of a slave.
#[derive(Clone, Copy, PartialEq, Eq, Debug, serde::Serialize, serde::Deserialize)]
pub enum SlaveState {
    Waiting,
    Configuration,
}

/// What the device behind a slave must do after a request.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum SlaveEvent {
    NodeId(u8),
    BitTiming(u8),
    Activate {
        delay_ms: u16,
    },
    Store,
    /// Left configuration state (a device given a node-id boots with it then).
    BackToWaiting,
}

/// What a slave device supports and holds, as its firmware decides.
#[derive(Clone, Copy, Debug)]
pub struct SlaveCaps {
    pub store: bool,
    pub bit_timing: bool,
}

/// The slave side (CiA 305), for the simulated devices.
#[derive(Clone, Debug)]
pub struct Slave {
    pub identity: Identity,
    pub state: SlaveState,
    caps: SlaveCaps,
    /// Selective switch: how many identity parts have matched in sequence.
    selective: u8,
    /// Identify remote slave: which of the six range checks have passed.
    identify: u8,
    fastscan_pos: u8,
}

impl Slave {
    pub fn new(identity: Identity, caps: SlaveCaps) -> Slave {
        Slave { identity, state: SlaveState::Waiting, caps, selective: 0, identify: 0, fastscan_pos: 0 }
    }

    /// One request; `node_id` is the device's current one (`UNCONFIGURED` for none).
    pub fn handle(&mut self, req: Request, node_id: u8) -> (Option<Response>, Option<SlaveEvent>) {
        let configuring = self.state == SlaveState::Configuration;
        match req {
            Request::SwitchGlobal { configuration } => {
                self.selective = 0;
                let was = self.state;
                self.state = if configuration { SlaveState::Configuration } else { SlaveState::Waiting };
                let event = (was == SlaveState::Configuration && !configuration).then_some(SlaveEvent::BackToWaiting);
                (None, event)
            }
            Request::SwitchSelective { part, value } => {
                if part == self.selective && value == self.identity.part(part) {
                    self.selective += 1;
                    if self.selective == 4 {
                        self.selective = 0;
                        self.state = SlaveState::Configuration;
                        return (Some(Response::SwitchSelectiveAck), None);
                    }
                } else {
                    self.selective = if part == 0 && value == self.identity.vendor { 1 } else { 0 };
                }
                (None, None)
            }
            Request::ConfigureNodeId(id) if configuring => {
                let ok = (1..=127).contains(&id) || id == UNCONFIGURED;
                let error = if ok { 0 } else { 1 };
                (Some(Response::Result { cs: 0x11, error, specific: 0 }), ok.then_some(SlaveEvent::NodeId(id)))
            }
            Request::ConfigureBitTiming { table, index } if configuring => {
                let ok = self.caps.bit_timing
                    && table == 0
                    && BIT_TIMINGS.get(index as usize).is_some_and(|(_, k)| k.is_some());
                let error = if ok { 0 } else { 1 };
                (Some(Response::Result { cs: 0x13, error, specific: 0 }), ok.then_some(SlaveEvent::BitTiming(index)))
            }
            Request::ActivateBitTiming { delay_ms } if configuring => (None, Some(SlaveEvent::Activate { delay_ms })),
            Request::StoreConfiguration if configuring => {
                let error = if self.caps.store { 0 } else { 1 };
                (Some(Response::Result { cs: 0x17, error, specific: 0 }), self.caps.store.then_some(SlaveEvent::Store))
            }
            Request::Inquire(q) if configuring => {
                let value = match q {
                    Inquiry::Vendor => self.identity.vendor,
                    Inquiry::Product => self.identity.product,
                    Inquiry::Revision => self.identity.revision,
                    Inquiry::Serial => self.identity.serial,
                    Inquiry::NodeId => node_id as u32,
                };
                (Some(Response::InquiredValue { inquiry: q, value }), None)
            }
            Request::IdentifyRemote { field, value } => {
                let ok = match field {
                    0x46 => value == self.identity.vendor,
                    0x47 => value == self.identity.product,
                    0x48 => self.identity.revision >= value,
                    0x49 => self.identity.revision <= value,
                    0x4A => self.identity.serial >= value,
                    _ => self.identity.serial <= value,
                };
                let step = field - 0x46;
                self.identify = if ok && self.identify == step { step + 1 } else { 0 };
                if self.identify == 6 {
                    self.identify = 0;
                    return (Some(Response::IdentifySlave), None);
                }
                (None, None)
            }
            Request::IdentifyNonConfigured => (
                (node_id == UNCONFIGURED && self.state == SlaveState::Waiting)
                    .then_some(Response::IdentifyNonConfiguredSlave),
                None,
            ),
            Request::Fastscan { id, bit_checked, sub, next } => self.fastscan(id, bit_checked, sub, next, node_id),
            // Configuration services outside configuration state are ignored (CiA 305).
            _ => (None, None),
        }
    }

    fn fastscan(&mut self, id: u32, bit: u8, sub: u8, next: u8, node_id: u8) -> (Option<Response>, Option<SlaveEvent>) {
        // Only non-configured devices in waiting state take part.
        if node_id != UNCONFIGURED || self.state != SlaveState::Waiting {
            return (None, None);
        }
        if bit == FASTSCAN_RESET {
            self.fastscan_pos = 0;
            return (Some(Response::IdentifySlave), None);
        }
        if bit > 31 || sub > 3 || sub != self.fastscan_pos {
            return (None, None);
        }
        // The bits from 31 down to the one checked must match.
        if (id ^ self.identity.part(sub)) & (u32::MAX << bit) != 0 {
            return (None, None);
        }
        self.fastscan_pos = next;
        // A complete match of the last part, pointing back to the first: this is the
        // device found, and it goes into configuration state.
        if bit == 0 && next < sub {
            self.state = SlaveState::Configuration;
        }
        (Some(Response::IdentifySlave), None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sensor() -> Identity {
        // Seed 001 table 5, with the serial of figure 10's example.
        Identity { vendor: 0x40, product: 0x4378_7800, revision: 0x312E_3031, serial: 0x0950_1234 }
    }

    #[test]
    fn seed_001_figure_10_selective_switch() {
        let frames: Vec<[u8; 8]> = switch_selective(&sensor()).iter().map(Request::encode).collect();
        assert_eq!(
            frames,
            [
                [0x40, 0x40, 0x00, 0x00, 0x00, 0, 0, 0],
                [0x41, 0x00, 0x78, 0x78, 0x43, 0, 0, 0],
                [0x42, 0x31, 0x30, 0x2E, 0x31, 0, 0, 0],
                [0x43, 0x34, 0x12, 0x50, 0x09, 0, 0, 0],
            ]
        );
        let mut slave = Slave::new(sensor(), SlaveCaps { store: true, bit_timing: true });
        let mut answers = vec![];
        for f in &frames {
            answers.push(slave.handle(Request::decode(f).unwrap(), 5).0);
        }
        assert_eq!(answers, [None, None, None, Some(Response::SwitchSelectiveAck)]);
        assert_eq!(Response::SwitchSelectiveAck.encode()[0], 0x44);
        assert_eq!(slave.state, SlaveState::Configuration);
    }

    #[test]
    fn seed_001_figures_11_to_15() {
        assert_eq!(Request::SwitchGlobal { configuration: true }.encode(), [0x04, 0x01, 0, 0, 0, 0, 0, 0]);
        assert_eq!(Request::ConfigureNodeId(5).encode(), [0x11, 5, 0, 0, 0, 0, 0, 0]);
        assert_eq!(Request::ConfigureBitTiming { table: 0, index: 2 }.encode(), [0x13, 0, 2, 0, 0, 0, 0, 0]);
        assert_eq!(Request::ActivateBitTiming { delay_ms: 100 }.encode(), [0x15, 100, 0, 0, 0, 0, 0, 0]);
        assert_eq!(Request::StoreConfiguration.encode(), [0x17, 0, 0, 0, 0, 0, 0, 0]);
        assert_eq!(
            Response::decode(&[0x17, 2, 0, 0, 0, 0, 0, 0]),
            Some(Response::Result { cs: 0x17, error: 2, specific: 0 })
        );
        assert_eq!(error_meaning(0x17, 2), "storage media access error");
        assert_eq!(error_meaning(0x11, 1), "node-id out of range");
        assert_eq!(error_meaning(0x13, 1), "bit timing not supported");
    }

    #[test]
    fn every_request_round_trips() {
        let all = [
            Request::SwitchGlobal { configuration: false },
            Request::SwitchSelective { part: 3, value: 7 },
            Request::ConfigureNodeId(255),
            Request::ConfigureBitTiming { table: 0, index: 8 },
            Request::ActivateBitTiming { delay_ms: 1000 },
            Request::StoreConfiguration,
            Request::Inquire(Inquiry::Vendor),
            Request::Inquire(Inquiry::NodeId),
            Request::IdentifyRemote { field: 0x4B, value: 9 },
            Request::IdentifyNonConfigured,
            Request::Fastscan { id: 0x1234, bit_checked: 7, sub: 2, next: 3 },
        ];
        for r in all {
            assert_eq!(Request::decode(&r.encode()), Some(r));
        }
        let answers = [
            Response::SwitchSelectiveAck,
            Response::Result { cs: 0x13, error: 1, specific: 0 },
            Response::InquiredValue { inquiry: Inquiry::Serial, value: 0xDEAD_BEEF },
            Response::InquiredValue { inquiry: Inquiry::NodeId, value: 5 },
            Response::IdentifySlave,
            Response::IdentifyNonConfiguredSlave,
        ];
        for a in answers {
            assert_eq!(Response::decode(&a.encode()), Some(a));
        }
    }

    #[test]
    fn bit_rates() {
        assert_eq!(parse_bit_rate("500k"), Ok(2));
        assert_eq!(parse_bit_rate("1M"), Ok(0));
        assert_eq!(parse_bit_rate("125000"), Ok(4));
        assert_eq!(parse_bit_rate("auto"), Ok(9));
        assert!(parse_bit_rate("100k").unwrap_err().contains("no entry for 100k"));
        assert!(parse_bit_rate("fast").is_err());
        assert_eq!(bit_rate_name(0), "1M");
        assert_eq!(bit_rate_name(3), "250k");
        assert_eq!(bit_rate_name(5), "reserved (5)");
    }

    #[test]
    fn identities_parse() {
        let id: Identity = "0x40:0x43787800:0x312E3031:0x09501234".parse().unwrap();
        assert_eq!(id, sensor());
        assert_eq!(id.to_string(), "0x00000040:0x43787800:0x312E3031:0x09501234");
        assert_eq!("64:1:2:3".parse::<Identity>().unwrap().vendor, 64);
        assert!("1:2:3".parse::<Identity>().is_err());
        assert!("1:2:3:x".parse::<Identity>().is_err());
    }

    const MS: Duration = Duration::from_millis(1);
    const CAPS: SlaveCaps = SlaveCaps { store: true, bit_timing: true };

    fn three() -> [Identity; 3] {
        [
            Identity { vendor: 0x40, product: 0x4378_7800, revision: 0x312E_3031, serial: 0x0950_1302 },
            Identity { vendor: 0x40, product: 0x4378_7800, revision: 0x312E_3031, serial: 0x0950_1301 },
            Identity { vendor: 0x444, product: 0x2057, revision: 1, serial: 7 },
        ]
    }

    type Latency = Box<dyn FnMut(usize, u32) -> Option<Duration>>;
    type Extra = Box<dyn FnMut(u32) -> Vec<(Duration, [u8; 8])>>;

    /// A bus in virtual time, as a real one behaves: slaves take each request at once and
    /// answer `latency` later (`None`: the answer is lost); an answer counts for whichever
    /// request's window it arrives in, and one that arrives between windows is drained.
    struct VirtualBus {
        slaves: Vec<Slave>,
        now: Duration,
        in_flight: Vec<(Duration, [u8; 8])>,
        /// (slave, request number) → answer latency.
        latency: Latency,
        /// Other frames on 0x7E4 after request number n, timed from it.
        extra: Extra,
        sent: u32,
    }

    impl VirtualBus {
        fn new(ids: &[Identity], latency: Latency) -> VirtualBus {
            VirtualBus {
                slaves: ids.iter().map(|i| Slave::new(*i, CAPS)).collect(),
                now: Duration::ZERO,
                in_flight: vec![],
                latency,
                extra: Box::new(|_| vec![]),
                sent: 0,
            }
        }

        fn exchange(&mut self, ask: &Ask) -> Vec<(Duration, [u8; 8])> {
            let t0 = self.now;
            self.in_flight.retain(|(t, _)| *t >= t0);
            self.sent += 1;
            for i in 0..self.slaves.len() {
                if let (Some(a), _) = self.slaves[i].handle(ask.request, UNCONFIGURED) {
                    if let Some(lat) = (self.latency)(i, self.sent) {
                        self.in_flight.push((t0 + lat, a.encode()));
                    }
                }
            }
            for (t, f) in (self.extra)(self.sent) {
                self.in_flight.push((t0 + t, f));
            }
            self.in_flight.sort_by_key(|(t, _)| *t);
            let mut end = t0 + ask.window;
            let mut got = vec![];
            let mut answered = false;
            for (t, f) in &self.in_flight {
                if *t > end {
                    break;
                }
                got.push((*t - t0, *f));
                if f[0] == ask.expect && !answered {
                    answered = true;
                    if let Some(settle) = ask.settle {
                        end = end.min(*t + settle);
                    }
                }
            }
            self.now = end;
            self.in_flight.retain(|(t, _)| *t > end);
            got
        }

        fn run(&mut self, scan: &mut Fastscan) -> Result<Identity, FastscanError> {
            for _ in 0..5000 {
                match scan.next() {
                    FastscanNext::Send(ask) => {
                        let answers = self.exchange(&ask);
                        scan.on_answers(&answers);
                    }
                    FastscanNext::Found(id) => return Ok(id),
                    FastscanNext::Failed(e) => return Err(e),
                }
            }
            panic!("fastscan did not end");
        }
    }

    fn fixed_latency(ms: u64) -> Latency {
        Box::new(move |_, _| Some(MS * ms as u32))
    }

    fn fresh() -> Fastscan {
        Fastscan::new(Pace::measured(MS * 500), [None; 4])
    }

    /// Against several slaves at once the master finds the lowest identity, 133 fastscan
    /// requests for a whole one; the found device is in configuration state and the next
    /// search (with the pace already learned) finds the next.
    #[test]
    fn fastscan_finds_every_identity_in_133_steps() {
        let mut bus = VirtualBus::new(&three(), fixed_latency(0));
        let mut pace = Pace::measured(MS * 500);
        let mut found = vec![];
        for _ in 0..3 {
            let mut scan = Fastscan::new(pace, [None; 4]);
            let id = bus.run(&mut scan).unwrap();
            assert_eq!(scan.steps(), 133);
            let s = bus.slaves.iter().find(|s| s.identity == id).unwrap();
            assert_eq!(s.state, SlaveState::Configuration);
            found.push(id);
            pace = scan.into_pace();
            assert_eq!(pace.step(), STEP_FLOOR);
        }
        let mut want = three().to_vec();
        want.sort();
        assert_eq!(found, want);
        // Every device is configured: the reset is silent, and so is the last probe.
        let mut scan = Fastscan::new(pace, [None; 4]);
        assert_eq!(bus.run(&mut scan), Err(FastscanError::NoDevice));
        assert!(matches!(scan.next(), FastscanNext::Failed(FastscanError::NoDevice)));
    }

    #[test]
    fn nobody_there_is_no_device_after_two_generous_probes() {
        let mut bus = VirtualBus::new(&[], fixed_latency(0));
        let mut scan = fresh();
        assert_eq!(bus.run(&mut scan), Err(FastscanError::NoDevice));
        assert_eq!(bus.sent, 2, "the probe and one reset");
        assert_eq!(bus.now, MS * 1000);
    }

    /// Slaves that answer 60 ms late (as real ones do): the probe measures it and every
    /// step waits long enough, with no escalation.
    #[test]
    fn the_pace_is_learned_from_the_first_probe() {
        let mut bus = VirtualBus::new(&three(), fixed_latency(60));
        let mut scan = fresh();
        let id = bus.run(&mut scan).unwrap();
        assert_eq!(id, three()[1]);
        assert_eq!(scan.steps(), 133);
        assert_eq!(scan.pace().escalations(), 0);
        assert_eq!(scan.pace().step(), MS * 95);
        assert_eq!(scan.pace().longest_step(), MS * 95);
    }

    /// `--step 10ms` (the old default) against 60 ms slaves: every answer comes in the
    /// next window, parts are not confirmed, and the step doubles until answers fit.
    /// Slaves slower than the step can ever become: a bounded failure.
    #[test]
    fn a_fixed_step_too_short_is_lengthened_or_fails_bounded() {
        let mut bus = VirtualBus::new(&three(), fixed_latency(60));
        let mut scan = Fastscan::new(Pace::fixed(MS * 10, MS * 500), [None; 4]);
        assert_eq!(bus.run(&mut scan), Ok(three()[1]));
        assert_eq!(scan.pace().longest_step(), MS * 80);
        let mut bus = VirtualBus::new(&three(), fixed_latency(300));
        let mut scan = Fastscan::new(Pace::fixed(MS * 10, MS * 500), [None; 4]);
        let r = bus.run(&mut scan);
        assert!(matches!(r, Err(FastscanError::Unconfirmed(_) | FastscanError::Lost)), "{r:?}");
        assert_eq!(scan.pace().escalations(), MAX_ESCALATIONS);
        assert!(bus.sent < 1000);
    }

    /// One answer held up once (a busy host) lengthens the step for a while, not for ever.
    #[test]
    fn the_step_follows_the_latest_answers() {
        let mut pace = Pace::measured(MS * 500);
        pace.observe(MS * 170);
        assert_eq!(pace.step(), MS * 260);
        for _ in 0..RECENT_ANSWERS {
            pace.observe(MS * 20);
        }
        assert_eq!(pace.step(), MS * 35);
        assert_eq!(pace.slowest(), Some(MS * 170), "reported as seen");
    }

    /// One answer far later than the probe showed, once (it is lost to its window, as a
    /// lost answer is): the bit looks like 1, the part is not confirmed, the confirmation
    /// is asked twice more, then that part alone is searched again at the same step.
    /// Lateness that goes on lengthens the step ([`a_fixed_step_too_short_is_lengthened_or_fails_bounded`]).
    #[test]
    fn a_late_answer_once_searches_that_part_again_at_the_same_step() {
        let id = three()[1];
        let latency: Latency = Box::new(|_, n| Some(if n == 60 { MS * 45 } else { MS * 5 }));
        let mut bus = VirtualBus::new(&[id], latency);
        let mut scan = fresh();
        assert_eq!(bus.run(&mut scan), Ok(id));
        assert_eq!(scan.pace().escalations(), 0);
        // Request 60 is in part 1 (the product): its confirmation three times, a reset,
        // part 0 confirmed in one step, part 1 searched again (33 steps, and its silent
        // bits asked twice now that a loss was seen); parts 2 and 3 likewise.
        assert!(scan.steps() > 133 + 2 + 1 + 1 + 33, "{}", scan.steps());
        assert!(scan.steps() < 2 * (133 + 2 + 1 + 1 + 33), "{}", scan.steps());
    }

    /// Seed 0x109bc6 of tests/dst.rs: an answer to a bit check of the serial held up
    /// 45 ms (four short steps) made that bit look like 1, and arrived in the window of
    /// the serial's confirmation, so a value no device has was "confirmed". Fastscan
    /// answers carry nothing to tell which request they answer: the identity found is
    /// asked of the device in configuration state before it is trusted, and searched
    /// again when no device there has it.
    #[test]
    fn an_answer_late_into_a_confirmation_does_not_find_an_identity_nobody_has() {
        let id = three()[1];
        // Request 131 is the check of the serial's bit 2 (a 0 in 0x09501301): probe,
        // reset, three parts of 33, then bits 31 down to 3.
        let latency: Latency = Box::new(|_, n| Some(if n == 131 { MS * 45 } else { MS * 5 }));
        let mut bus = VirtualBus::new(&[id], latency);
        let mut scan = fresh();
        assert_eq!(bus.run(&mut scan), Ok(id));
        assert_eq!(bus.slaves[0].state, SlaveState::Configuration);
    }

    /// A lost answer makes a bit 1 as well: the same recovery.
    #[test]
    fn a_lost_answer_is_recovered() {
        let id = three()[0];
        let latency: Latency = Box::new(|_, n| (n != 110).then_some(MS * 3));
        let mut bus = VirtualBus::new(&[id], latency);
        let mut scan = fresh();
        assert_eq!(bus.run(&mut scan), Ok(id));
        assert!(scan.steps() > 133);
        assert_eq!(scan.pace().escalations(), 0, "a loss is not lateness");
    }

    /// Every answer twice (a device, or a gateway, repeating itself): still one answer.
    #[test]
    fn duplicated_answers_count_once() {
        let mut dup_bus = VirtualBus::new(&three(), Box::new(|_, _| Some(MS * 2)));
        let mut scan = fresh();
        let mut sent = 0;
        let id = loop {
            match scan.next() {
                FastscanNext::Send(ask) => {
                    sent += 1;
                    let mut answers = dup_bus.exchange(&ask);
                    let copies = answers.clone();
                    answers.extend(copies.iter().map(|(t, f)| (*t + MS, *f)));
                    scan.on_answers(&answers);
                }
                FastscanNext::Found(id) => break id,
                FastscanNext::Failed(e) => panic!("{e:?}"),
            }
        };
        assert!(sent < 200);
        assert_eq!(id, three()[1]);
        assert_eq!(scan.steps(), 133);
    }

    /// Frames on 0x7E4 that are not fastscan answers (another command specifier: a
    /// heartbeat-like byte, a stray "non-configured" answer, garbage) never count, however
    /// many: with nobody there it is still "no device", in bounded time.
    #[test]
    fn bogus_frames_on_the_slave_id_never_count() {
        let flood = |_: u32| -> Vec<(Duration, [u8; 8])> {
            (0..200)
                .map(|i| (MS * (i % 10) / 2, [[0x7F, 0x05, 0x50, 0x44][i as usize % 4], 0, 0, 0, 0, 0, 0, 0]))
                .collect()
        };
        let mut bus = VirtualBus::new(&[], fixed_latency(0));
        bus.extra = Box::new(flood);
        let mut scan = fresh();
        // 0x50 is the answer the probe expects: the flood includes it, so the probe
        // "sees" devices, yet no fastscan reset is ever answered.
        let r = bus.run(&mut scan);
        assert!(matches!(r, Err(FastscanError::NoDevice | FastscanError::Lost)), "{r:?}");
        assert!(bus.sent < 20, "bounded: {} requests", bus.sent);
        // With real devices among the flood, the right one is found in 133 steps.
        let mut bus = VirtualBus::new(&three(), fixed_latency(1));
        bus.extra = Box::new(|_| (0..50).map(|i| (MS * i / 10, [0x7F, 5, 0, 0, 0, 0, 0, 0])).collect());
        let mut scan = fresh();
        assert_eq!(bus.run(&mut scan), Ok(three()[1]));
        assert_eq!(scan.steps(), 133);
    }

    /// Known vendor and product: those parts are confirmed in one step each.
    #[test]
    fn given_parts_are_confirmed_not_searched() {
        let mut bus = VirtualBus::new(&three(), fixed_latency(1));
        let mut scan = Fastscan::new(Pace::measured(MS * 500), [Some(0x444), Some(0x2057), None, None]);
        assert_eq!(bus.run(&mut scan), Ok(three()[2]));
        assert_eq!(scan.steps(), 1 + 1 + 1 + 33 + 33);
        // A vendor nobody has: refused after the bounded searches, by name. Nothing came
        // late: the step stays.
        let mut bus = VirtualBus::new(&three(), fixed_latency(1));
        let mut scan = Fastscan::new(Pace::measured(MS * 500), [Some(0x99), None, None, None]);
        assert_eq!(bus.run(&mut scan), Err(FastscanError::NoMatch { part: 0, value: 0x99 }));
        assert_eq!(scan.pace().escalations(), 0);
        assert!(bus.sent <= 2 + 4 * (MAX_SEARCHES + 1), "bounded: {} requests", bus.sent);
    }

    #[test]
    fn every_answer_late_by_a_lot_stops_at_the_ceiling() {
        let mut bus = VirtualBus::new(&three(), Box::new(|_, n| Some(if n < 3 { MS } else { MS * 3000 })));
        let mut scan = fresh();
        let r = bus.run(&mut scan);
        assert!(r.is_err());
        assert!(scan.pace().longest_step() <= STEP_CEILING);
        assert!(bus.sent < 500);
    }

    /// Frames lost as an overloaded adapter or gateway loses them: each request (2 %) and
    /// each answer (2 %) independently, drawn from `seed`; answers 15 ms late with a few
    /// ms of jitter. Deterministic for a seed.
    fn lossy(seed: u64) -> Latency {
        let draw = move |a: u64, b: u64| {
            // splitmix64 of (seed, a, b): a fixed, well-spread draw per frame.
            let mut z = seed ^ a.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ b.wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        };
        Box::new(move |slave, n| {
            let request_lost = draw(n as u64, 1000) % 100 < 2;
            let answer_lost = draw(n as u64, slave as u64) % 100 < 2;
            let jitter = draw(n as u64, 2000 + slave as u64) % 4;
            (!request_lost && !answer_lost).then_some(MS * (15 + jitter as u32))
        })
    }

    /// `lss assign`'s search under 2 % frame loss (the field report: three slaves behind a
    /// 15 ms path, one numbered, then "part 0 found but not confirmed, even with a 1013 ms
    /// step"): a lost answer is not a late one, so the search repeats what was lost instead
    /// of lengthening the step, and finds all three devices, then nobody, on every seed.
    #[test]
    fn fastscan_finds_every_device_under_two_percent_loss() {
        let mut failed = vec![];
        for seed in 0..200u64 {
            let mut bus = VirtualBus::new(&three(), lossy(seed));
            let mut pace = Pace::measured(MS * 500);
            let mut found = vec![];
            let outcome = loop {
                let mut scan = Fastscan::new(pace.clone(), [None; 4]);
                let r = bus.run(&mut scan);
                pace = scan.into_pace();
                match r {
                    // Numbered, as assign does next: no longer one without a node-id.
                    Ok(id) => {
                        bus.slaves.retain(|s| s.identity != id);
                        found.push(id)
                    }
                    Err(e) => break e,
                }
            };
            found.sort();
            let mut want = three().to_vec();
            want.sort();
            if outcome != FastscanError::NoDevice || found != want {
                failed.push((seed, found.len(), outcome, pace.longest_step()));
            }
        }
        assert!(failed.is_empty(), "{} of 200 seeds failed: {failed:?}", failed.len());
    }

    /// Seeds 0xfb02c and 0xf7686 of tests/dst.rs: one slave losing 20 % of its answers.
    /// Parts went unconfirmed again and again, were taken for lateness, and the step
    /// doubled four times (786–2,272 s of bus time): a longer step brings no lost answer
    /// back. The step stays, and the search ends, found or failed, within its bound.
    #[test]
    fn heavy_loss_never_lengthens_the_step_and_the_search_is_bounded() {
        let id = three()[1];
        let mut found = 0;
        for seed in 0..40u64 {
            // The 2 % of `lossy`, and 20 % of the answers more: a fixed, well-spread draw each.
            let mut draws = lossy(seed);
            let mut n = 0u64;
            let latency: Latency = Box::new(move |slave, req| {
                n += 1;
                let draw = (n.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ seed.wrapping_mul(0xBF58_476D_1CE4_E5B9)) >> 32;
                draws(slave, req).filter(|_| !draw.is_multiple_of(5))
            });
            let mut bus = VirtualBus::new(&[id], latency);
            let mut scan = fresh();
            let r = bus.run(&mut scan);
            assert_eq!(scan.pace().escalations(), 0, "seed {seed}: {r:?}, a loss is not lateness");
            assert!(bus.now <= STEP_CEILING * 133, "seed {seed}: {:?} of bus time", bus.now);
            match r {
                Ok(got) => {
                    assert_eq!(got, id, "seed {seed}");
                    found += 1;
                }
                // Two first answers lost: nobody seen (assign asks three times before it
                // believes that).
                Err(e) => assert!(
                    matches!(e, FastscanError::Unconfirmed(_) | FastscanError::Lost | FastscanError::NoDevice),
                    "seed {seed}: {e:?}"
                ),
            }
        }
        eprintln!("found on {found} of 40 seeds");
        assert!(found >= 36, "found on {found} of 40 seeds");
    }

    #[test]
    fn only_well_formed_answers_count() {
        assert!(is_answer(&[0x4F, 0, 0, 0, 0, 0, 0, 0], 0x4F));
        assert!(!is_answer(&[0x4F, 0, 0, 0, 0, 0, 0], 0x4F), "7 bytes");
        assert!(!is_answer(&[0x4F, 1, 1, 0, 0, 0, 0, 0], 0x4F), "a babbler's counter");
        assert!(!is_answer(&[0x50, 0, 0, 0, 0, 0, 0, 0], 0x4F), "another service's answer");
        assert!(!is_answer(&[0x7F], 0x4F), "a heartbeat-like frame");
        assert!(is_answer(&[0x5A, 0x40, 0, 0, 0, 0, 0, 0], 0x5A), "inquiry answers carry a value");
        assert!(is_answer(&[0x11, 1, 0, 0, 0, 0, 0, 0], 0x11), "results carry an error code");
    }

    #[test]
    fn expected_answers() {
        assert_eq!(Request::Fastscan { id: 0, bit_checked: 0x80, sub: 0, next: 0 }.expected_answer(), Some(0x4F));
        assert_eq!(Request::IdentifyNonConfigured.expected_answer(), Some(0x50));
        assert_eq!(Request::SwitchSelective { part: 3, value: 1 }.expected_answer(), Some(0x44));
        assert_eq!(Request::SwitchSelective { part: 2, value: 1 }.expected_answer(), None);
        assert_eq!(Request::Inquire(Inquiry::NodeId).expected_answer(), Some(0x5E));
        assert_eq!(Request::SwitchGlobal { configuration: false }.expected_answer(), None);
    }
}
