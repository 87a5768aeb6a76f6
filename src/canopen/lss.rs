//! Layer setting services (CiA 305): node-ids and bit rates for devices that have none or
//! share one. Master requests go on 0x7E5, slave answers on 0x7E4; all frames are 8 bytes.
//! Pure encoding, the fastscan search, and the slave's state machine (for the simulator).

use std::fmt;

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

/// The four selective-switch requests for one device; the answer is 0x44 from it alone.
pub fn switch_selective(id: &Identity) -> [Request; 4] {
    [0, 1, 2, 3].map(|part| Request::SwitchSelective { part, value: id.part(part) })
}

/// Fastscan (CiA 305 §8.4.3), the master side: finds the complete identity of one
/// non-configured device in waiting state, bit by bit, 133 steps for the whole of it.
/// Feed it whether anyone answered each request.
#[derive(Clone, Debug)]
pub struct Fastscan {
    id: Identity,
    sub: u8,
    /// 0x80 before the reset step; 31..0 while searching bits; `None` while confirming.
    bit: Option<u8>,
    done: bool,
    steps: u32,
    /// Searches started; one whose confirmation fails (an answer came too late, so a bit
    /// was taken for 1) starts over, up to `ATTEMPTS` in all.
    attempts: u32,
}

const ATTEMPTS: u32 = 3;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum FastscanError {
    /// Nobody answered the reset: no non-configured device in waiting state.
    NoDevice,
    /// A part that every bit matched was not confirmed: devices changed meanwhile, or
    /// frames were lost.
    Unconfirmed(u8),
}

impl Default for Fastscan {
    fn default() -> Self {
        Fastscan::new()
    }
}

impl Fastscan {
    pub fn new() -> Fastscan {
        Fastscan { id: Identity::default(), sub: 0, bit: Some(FASTSCAN_RESET), done: false, steps: 0, attempts: 1 }
    }

    pub fn steps(&self) -> u32 {
        self.steps
    }

    /// The identity found, once the search is over.
    pub fn found(&self) -> Option<Identity> {
        self.done.then_some(self.id)
    }

    /// The next request to send, or `None` when the search is over.
    pub fn request(&self) -> Option<Request> {
        if self.done {
            return None;
        }
        let sub = self.sub;
        Some(match self.bit {
            Some(FASTSCAN_RESET) => Request::Fastscan { id: 0, bit_checked: FASTSCAN_RESET, sub: 0, next: 0 },
            Some(bit) => Request::Fastscan { id: self.id.part(sub), bit_checked: bit, sub, next: sub },
            None => Request::Fastscan { id: self.id.part(sub), bit_checked: 0, sub, next: (sub + 1) % 4 },
        })
    }

    /// Whether any slave answered the last request.
    pub fn answered(&mut self, answered: bool) -> Result<(), FastscanError> {
        self.steps += 1;
        match self.bit {
            Some(FASTSCAN_RESET) => {
                if !answered {
                    self.done = true;
                    return Err(FastscanError::NoDevice);
                }
                self.bit = Some(31);
            }
            Some(bit) => {
                // Asked "does bit `bit` being 0 (and the bits above as found) match?": no
                // answer means every remaining device has a 1 there.
                if !answered {
                    let v = self.id.part(self.sub) | 1 << bit;
                    self.id.set_part(self.sub, v);
                }
                self.bit = if bit == 0 { None } else { Some(bit - 1) };
            }
            None => {
                if !answered {
                    if self.attempts == ATTEMPTS {
                        self.done = true;
                        return Err(FastscanError::Unconfirmed(self.sub));
                    }
                    self.attempts += 1;
                    self.id = Identity::default();
                    self.sub = 0;
                    self.bit = Some(FASTSCAN_RESET);
                    return Ok(());
                }
                if self.sub == 3 {
                    // The device that matched the serial is now in configuration state.
                    self.done = true;
                } else {
                    self.sub += 1;
                    self.bit = Some(31);
                }
            }
        }
        Ok(())
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

    /// Fastscan against several slaves at once: the master finds the lowest identity.
    #[test]
    fn fastscan_finds_a_whole_identity_in_133_steps() {
        let ids = [
            Identity { vendor: 0x40, product: 0x4378_7800, revision: 0x312E_3031, serial: 0x0950_1302 },
            Identity { vendor: 0x40, product: 0x4378_7800, revision: 0x312E_3031, serial: 0x0950_1301 },
            Identity { vendor: 0x444, product: 0x2057, revision: 1, serial: 7 },
        ];
        let mut slaves: Vec<Slave> =
            ids.iter().map(|i| Slave::new(*i, SlaveCaps { store: true, bit_timing: true })).collect();
        let mut found = vec![];
        for _ in 0..ids.len() {
            let mut scan = Fastscan::new();
            while let Some(req) = scan.request() {
                let answered =
                    slaves.iter_mut().map(|s| s.handle(req, UNCONFIGURED).0.is_some()).fold(false, |a, b| a | b);
                scan.answered(answered).unwrap();
            }
            let id = scan.found().unwrap();
            assert_eq!(scan.steps(), 133);
            // The device found is in configuration state; once it has a node-id it no
            // longer takes part, and the next search finds another.
            let s = slaves.iter().find(|s| s.identity == id).unwrap();
            assert_eq!(s.state, SlaveState::Configuration);
            assert!(slaves.iter().filter(|s| s.identity != id).all(|s| s.state == SlaveState::Waiting));
            found.push(id);
            slaves.retain(|s| s.identity != id);
        }
        let mut want = ids.to_vec();
        want.sort();
        assert_eq!(found, want);
        let mut scan = Fastscan::new();
        assert_eq!(scan.answered(false), Err(FastscanError::NoDevice));
    }

    /// An answer that comes too late makes a bit look like 1; the confirmation then fails
    /// and the search starts over instead of giving up.
    #[test]
    fn fastscan_survives_a_late_answer() {
        let id = Identity { vendor: 0x40, product: 0x4378_7800, revision: 0x312E_3031, serial: 0x0950_1301 };
        let mut slave = Slave::new(id, SlaveCaps { store: true, bit_timing: true });
        let mut scan = Fastscan::new();
        let mut n = 0;
        while let Some(req) = scan.request() {
            n += 1;
            let answered = slave.handle(req, UNCONFIGURED).0.is_some() && n != 40;
            scan.answered(answered).unwrap();
        }
        assert_eq!(scan.found(), Some(id));
        assert!(scan.steps() > 133);
    }
}
