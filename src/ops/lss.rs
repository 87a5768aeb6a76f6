//! Node-ids and bit rates over LSS (CiA 305): ask a device its identity, give it a node-id
//! or a bit rate, find devices without a node-id (fastscan) and number them all (assign).
//! Whatever ends a procedure, every device is sent back to LSS waiting state, where it
//! answers no other master's services by mistake. The request sequences themselves are
//! [`LssMaster`]'s; an interruption is a flag, checked between steps.

use super::{sized, Progress};
use crate::bus::lss::{AssignFailure, LssMaster, NotStored};
use crate::bus::{Bus, LssWait, SdoOptions};
use crate::cancel::Cancel;
use crate::canopen::lss::{self, FastscanError, Identity, Inquiry, Pace, Request, Response, UNCONFIGURED};
use crate::canopen::ObjAddr;
use crate::error::{Error, Result};
use crate::ops::Notice;
use serde::ser::SerializeMap;
use serde::Serialize;
use std::collections::BTreeSet;
use std::time::Duration;

/// Which device a service is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Target {
    /// One device, selected by its identity.
    One(Identity),
    /// Every LSS device on the bus at once (a broadcast).
    All,
    /// The EPOS2 a serial link reaches directly (node 0): no LSS, but its own objects.
    DirectEpos2,
}

impl Target {
    /// How reports name it.
    pub fn text(&self) -> String {
        match self {
            Target::One(id) => id.to_string(),
            Target::All => "all LSS devices".into(),
            Target::DirectEpos2 => "the EPOS2 (node 0)".into(),
        }
    }
}

/// An identity in a report: its `V:P:R:S` text (`identity`) and its four numbers (`lss`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Identified(pub Identity);

impl Serialize for Identified {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        let id = &self.0;
        let mut m = s.serialize_map(Some(2))?;
        m.serialize_entry("identity", &id.to_string())?;
        m.serialize_entry("lss", &LssNumbers::from(id))?;
        m.end()
    }
}

/// The four entries of the identity object (0x1018:1..4), named.
#[derive(Clone, Copy, Debug, Serialize)]
pub(crate) struct LssNumbers {
    pub vendor_id: u32,
    pub product_code: u32,
    pub revision: u32,
    pub serial: u32,
}

impl From<&Identity> for LssNumbers {
    fn from(id: &Identity) -> LssNumbers {
        LssNumbers { vendor_id: id.vendor, product_code: id.product, revision: id.revision, serial: id.serial }
    }
}

/// What the LSS services are refused with on an EPOS2 reached directly.
pub(crate) fn no_lss_on_direct_epos2(verb: &str) -> Error {
    Error::NoLssOnDirectEpos2 { verb: verb.to_string() }
}

/// A device's identity and node-id, as it answered the inquiries.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Inquired {
    /// The device's LSS identity (0x1018's four entries).
    #[serde(flatten)]
    pub identity: Identified,
    /// None: the device has no node-id (255).
    pub node: Option<u8>,
}

/// Ask one device (or the only one, with [`Target::All`]) its identity and node-id.
pub fn inquire(bus: &mut dyn Bus, timeout: Duration, target: Target) -> Result<Inquired> {
    let (identity, global) = match target {
        Target::One(id) => (Some(id), false),
        Target::All => (None, true),
        Target::DirectEpos2 => return Err(no_lss_on_direct_epos2("inquire")),
    };
    let mut m = LssMaster::new(bus, timeout);
    if let Err(e) = m.enter(identity.as_ref()) {
        // A late acknowledgement may still have put the device in configuration state.
        m.leave()?;
        return Err(e);
    }
    let mut values = Vec::new();
    for q in [Inquiry::Vendor, Inquiry::Product, Inquiry::Revision, Inquiry::Serial, Inquiry::NodeId] {
        let answers = m.ask(Request::Inquire(q), if global { LssWait::All } else { LssWait::First })?;
        let found: Vec<u32> = answers
            .iter()
            .filter_map(|a| match a {
                Response::InquiredValue { inquiry, value } if *inquiry == q => Some(*value),
                _ => None,
            })
            .collect();
        match found.as_slice() {
            [v] => values.push(*v),
            [] => {
                m.leave()?;
                return Err(Error::NoLssAnswer { request: "the inquiry".into(), identity: None, waited: timeout });
            }
            more => {
                m.leave()?;
                return Err(Error::InquiryAnsweredByMany { count: more.len() });
            }
        }
    }
    m.leave()?;
    let id = Identity { vendor: values[0], product: values[1], revision: values[2], serial: values[3] };
    let node = (values[4] as u8 != UNCONFIGURED).then_some(values[4] as u8);
    Ok(Inquired { identity: Identified(id), node })
}

/// How many devices confirmed an LSS service sent to all of them, and what the others
/// answered (an LSS answer names no device: only counts can be told).
#[derive(Debug, Default, Serialize)]
#[non_exhaustive]
pub struct LssTally {
    /// How many devices confirmed it.
    pub confirmed: usize,
    /// Each refusal, in words ("LSS configure bit timing: error 1: bit timing not supported").
    pub refused: Vec<String>,
    #[serde(skip)]
    pub(crate) first_refusal: Option<Error>,
}

impl LssTally {
    pub(crate) fn of(answers: &[Response], service: &str) -> LssTally {
        let mut tally = LssTally::default();
        for a in answers {
            if let Response::Result { cs, error, specific } = *a {
                if error == 0 {
                    tally.confirmed += 1;
                } else {
                    let e = Error::LssRefused { service: service.into(), cs, error, specific };
                    tally.refused.push(e.to_string());
                    tally.first_refusal.get_or_insert(e);
                }
            }
        }
        tally
    }

    /// For people: "3 confirmed, 1 refused (...)".
    pub fn text(&self) -> String {
        match self.refused.len() {
            0 => format!("{} device(s) confirmed", self.confirmed),
            n => format!("{} device(s) confirmed, {n} refused ({})", self.confirmed, self.refused.join("; ")),
        }
    }
}

/// A configuration service.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Setting {
    /// A node-id, 1 to 127, or 255 (none).
    NodeId(u8),
    /// A bit rate: its index in the CiA 305 table.
    BitRate(u8),
    /// Keep the node-id and bit rate across power cycles.
    Store,
}

impl Setting {
    /// The `lss` verb that asks for it.
    pub fn verb(self) -> &'static str {
        match self {
            Setting::NodeId(_) => "set-id",
            Setting::BitRate(_) => "set-baud",
            Setting::Store => "store",
        }
    }

    fn request(self) -> Request {
        match self {
            Setting::NodeId(id) => Request::ConfigureNodeId(id),
            Setting::BitRate(index) => Request::ConfigureBitTiming { table: 0, index },
            Setting::Store => Request::StoreConfiguration,
        }
    }
}

/// What a configuration service gave the devices (the front end words it, with what makes
/// it take effect).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Took {
    /// A node-id, over LSS.
    NodeId(u8),
    /// No node-id (255), over LSS.
    NoNodeId,
    /// A bit rate (its CiA 305 index), over LSS: active after an activation, or after a
    /// store and a reset.
    BitRate(u8),
    /// The LSS configuration stored.
    Stored,
    /// A node-id written to an EPOS2's object 0x2000: in force only once stored and the
    /// EPOS2 powered off and on.
    Epos2NodeId(u8),
    /// A bit rate (its CiA 305 index) written to an EPOS2's object 0x2001 as its own
    /// `code`: in force only once stored and the EPOS2 powered off and on.
    Epos2BitRate {
        /// The CiA 305 index.
        index: u8,
        /// The EPOS2's code for it.
        code: u16,
    },
    /// An EPOS2's parameters stored (0x1010:1).
    Epos2Stored,
}

/// A configuration service done and confirmed.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Configured {
    /// The verb: set-id, set-baud or store.
    pub command: &'static str,
    /// Which devices it was sent to, in words: an identity, all LSS devices, or the EPOS2.
    pub target: String,
    /// What the devices now have.
    pub result: Took,
    /// How many devices confirmed it.
    pub answers: usize,
    /// Sent to every device (--global): who confirmed and what the others answered, since
    /// one refusal does not undo the others' acceptance.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub tally: Option<LssTally>,
    /// The user asked to stop while it was under way: it was done all the same (one LSS
    /// service cannot be half done), and nothing after it.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub interrupted: bool,
    /// A device's refusal, when some refused (its exit code is the command's).
    #[serde(skip)]
    pub failure: Option<Error>,
}

impl Configured {
    /// The command's outcome: Ok when no device refused, else the refusal (exit 4).
    pub fn outcome(self) -> Result<()> {
        match self.failure {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

/// Give the target a node-id or a bit rate, or make it store them: over LSS, or through
/// the EPOS2's own objects when it is reached directly.
pub fn configure(
    bus: &mut dyn Bus,
    timeout: Duration,
    target: Target,
    setting: Setting,
    interrupted: &Cancel,
) -> Result<Configured> {
    if interrupted.is_cancelled() {
        return Err(Error::Interrupted);
    }
    let mut tally = None;
    let (result, answers) = match target {
        Target::DirectEpos2 => (configure_direct_epos2(bus, timeout, setting)?, 1),
        Target::One(_) | Target::All => {
            let identity = match target {
                Target::One(id) => Some(id),
                _ => None,
            };
            let mut m = LssMaster::new(bus, timeout);
            let result = m.enter(identity.as_ref()).and_then(|_| match identity {
                Some(_) => m.configure(setting.request(), setting.verb(), false),
                // Every device answers for itself: count who took it and who refused.
                None => {
                    let answers = m.ask(setting.request(), LssWait::All)?;
                    let t = LssTally::of(&answers, setting.verb());
                    if t.confirmed + t.refused.len() == 0 {
                        let request = setting.verb().into();
                        return Err(Error::NoLssAnswer { request, identity: None, waited: timeout });
                    }
                    let n = t.confirmed;
                    tally = Some(t);
                    Ok(n)
                }
            });
            m.leave()?;
            let n = result?;
            let what = match setting {
                Setting::NodeId(UNCONFIGURED) => Took::NoNodeId,
                Setting::NodeId(id) => Took::NodeId(id),
                Setting::BitRate(index) => Took::BitRate(index),
                Setting::Store => Took::Stored,
            };
            (what, n)
        }
    };
    let interrupted = interrupted.is_cancelled();
    let failure = tally.as_mut().and_then(|t: &mut LssTally| t.first_refusal.take());
    Ok(Configured { command: setting.verb(), target: target.text(), result, answers, tally, interrupted, failure })
}

/// `lss set-baud`: [`configure`] the bit rate `index`. On the network at `network`, a global
/// one that some devices refused is remembered ([`RefusedRate`]) for [`activate_on`] to warn
/// of, and one that every device took forgets it.
pub fn set_baud(
    bus: &mut dyn Bus,
    timeout: Duration,
    target: Target,
    index: u8,
    network: Option<&str>,
    interrupted: &Cancel,
) -> Result<Configured> {
    let done = configure(bus, timeout, target, Setting::BitRate(index), interrupted)?;
    if let (Some(network), Some(_)) = (network, &done.tally) {
        RefusedRate::remember(network, RefusedRate::of(&done, index).as_ref());
    }
    Ok(done)
}

/// `lss activate` on the network at `network`: a global one first warns (through
/// `progress`) of the devices the last global set-baud left behind, then, once activated,
/// forgets them.
pub fn activate_on(
    bus: &mut dyn Bus,
    timeout: Duration,
    target: Target,
    delay_ms: u16,
    network: Option<&str>,
    progress: &mut dyn Progress,
) -> Result<Activated> {
    let network = network.filter(|_| target == Target::All);
    if let Some(refused) = network.and_then(RefusedRate::last) {
        let RefusedRate { rate, refused, confirmed } = refused;
        progress.event(super::event::Warning::ActivationStrands { rate, refused, confirmed }.into());
    }
    let done = activate(bus, timeout, target, delay_ms)?;
    if let Some(network) = network {
        RefusedRate::remember(network, None);
    }
    Ok(done)
}

/// A global "configure bit timing" that some devices refused, remembered per network (in
/// the cache, as the last scan is) until the next global set-baud or activation, so that
/// `lss activate` can warn that it would strand them. Like any cache, a failure to read or
/// write it is never an error.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub(crate) struct RefusedRate {
    /// The rate asked for (`125k`).
    pub rate: String,
    pub confirmed: usize,
    pub refused: usize,
}

impl RefusedRate {
    /// What a global configure leaves to remember: a refusal by some, or nothing.
    pub fn of(done: &Configured, index: u8) -> Option<RefusedRate> {
        let t = done.tally.as_ref().filter(|t| !t.refused.is_empty())?;
        Some(RefusedRate { rate: lss::bit_rate_name(index), confirmed: t.confirmed, refused: t.refused.len() })
    }

    /// Keep `what` as the last global configure of `bus` (None: every device took it).
    pub(crate) fn remember(bus: &str, what: Option<&RefusedRate>) {
        let Some(path) = super::scan_cache::network_file("lss-set-baud", bus) else { return };
        match what {
            Some(r) => {
                let _ = std::fs::create_dir_all(path.parent().expect("a directory"));
                let _ = std::fs::write(&path, serde_json::to_string(r).expect("serialises"));
            }
            None => {
                let _ = std::fs::remove_file(&path);
            }
        }
    }

    pub fn last(bus: &str) -> Option<RefusedRate> {
        let path = super::scan_cache::network_file("lss-set-baud", bus)?;
        serde_json::from_slice(&std::fs::read(path).ok()?).ok()
    }
}

/// `lss set-id`: [`configure`] the node-id, after checking nothing on the bus uses it
/// already (unless `force`): an SDO answer from another device than `target`, or a
/// heartbeat, boot-up or guarding answer heard while listening as `assign` does.
pub(crate) fn set_id(
    bus: &mut dyn Bus,
    timeout: Duration,
    target: Target,
    node: u8,
    force: bool,
    interrupted: &Cancel,
) -> Result<Configured> {
    if !force && node != UNCONFIGURED && !interrupted.is_cancelled() {
        let identity = match target {
            Target::One(id) => Some(id),
            _ => None,
        };
        if let Some(u) = super::clash::in_use(bus, node, identity, timeout, LISTEN)? {
            return Err(Error::NodeIdInUse { node, identity: u.identity, by: u.by });
        }
    }
    configure(bus, timeout, target, Setting::NodeId(node), interrupted)
}

/// EPOS2 firmware specification, object 0x2001 "CAN Bitrate": 0 = 1 Mbit/s, 1 = 800 k,
/// 2 = 500 k, 3 = 250 k, 4 = 125 k, 5 = 50 k, 6 = 20 k — not the CiA 305 table (there 5 is
/// reserved, 6 = 50 k, 7 = 20 k).
fn epos2_bit_rate_code(cia_index: u8) -> Option<u16> {
    [(0, 0), (1, 1), (2, 2), (3, 3), (4, 4), (6, 5), (7, 6)].iter().find(|(c, _)| *c == cia_index).map(|(_, e)| *e)
}
/// EPOS2 firmware specification: 0x2000 "Node ID", 0x2001 "CAN Bitrate".
const EPOS2_NODE_ID: ObjAddr = ObjAddr::new(0x2000, 0);
const EPOS2_CAN_BIT_RATE: ObjAddr = ObjAddr::new(0x2001, 0);
const STORE_ALL: ObjAddr = ObjAddr::new(0x1010, 1);

/// set-id, set-baud and store on an EPOS2 reached directly: its own objects.
fn configure_direct_epos2(bus: &mut dyn Bus, timeout: Duration, setting: Setting) -> Result<Took> {
    let opts = SdoOptions::new(timeout);
    match setting {
        Setting::NodeId(UNCONFIGURED) => {
            Err(Error::Usage("an EPOS2 always has a node-id (1 to 127); 255 is for LSS devices".into()))
        }
        Setting::NodeId(id) => {
            // The EPOS2 reads 0x2000 and 0x2001 at power-on only: the new value is a
            // stored parameter, not a change of the running device.
            bus.sdo_download(0, EPOS2_NODE_ID, &[id], &opts).map(|_| Took::Epos2NodeId(id))
        }
        Setting::BitRate(index) => {
            let code = epos2_bit_rate_code(index).ok_or_else(|| {
                Error::Usage(format!(
                    "the EPOS2 has no {} setting: use 1M 800k 500k 250k 125k 50k or 20k",
                    lss::bit_rate_name(index)
                ))
            })?;
            bus.sdo_download(0, EPOS2_CAN_BIT_RATE, &code.to_le_bytes(), &opts)
                .map(|_| Took::Epos2BitRate { index, code })
        }
        Setting::Store => bus.sdo_download(0, STORE_ALL, b"save", &opts).map(|_| Took::Epos2Stored),
    }
}

/// Configured bit rates switched on.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Activated {
    /// Always "activate".
    pub command: &'static str,
    /// How long the devices wait before switching, in ms (the LSS switch delay).
    pub delay_ms: u16,
    /// Whether the link switched with the devices (and so could send them back to waiting).
    pub bus_followed: bool,
    /// Which devices, in words.
    #[serde(skip)]
    pub devices: String,
    /// The link, as it describes itself.
    #[serde(skip)]
    pub bus: String,
}

/// Switch the configured bit rates on: the devices wait `delay_ms`, switch, and wait as
/// long again before talking.
pub fn activate(bus: &mut dyn Bus, timeout: Duration, target: Target, delay_ms: u16) -> Result<Activated> {
    let identity = match target {
        Target::One(id) => Some(id),
        Target::All => None,
        Target::DirectEpos2 => return Err(Error::Epos2RateOnStore),
    };
    let mut m = LssMaster::new(bus, timeout);
    if let Err(e) = m.enter(identity.as_ref()) {
        m.leave()?;
        return Err(e);
    }
    m.send(Request::ActivateBitTiming { delay_ms })?;
    // CiA 305: the devices wait the delay, switch, and wait as long again before talking.
    let link = m.bus();
    link.sleep_until(link.now() + Duration::from_millis(2 * delay_ms as u64))?;
    let devices = identity.map_or("all devices in configuration".to_string(), |i| i.to_string());
    let described = m.bus().describe();
    // The devices are still in configuration state; only a link at the new rate can send
    // them back to waiting.
    let bus_followed = m.bus().follows_bit_rate_switch();
    if bus_followed {
        m.leave()?;
    }
    Ok(Activated { command: "activate", delay_ms, bus_followed, devices, bus: described })
}

/// How fastscan paces itself, and what it already knows.
#[derive(Clone, Debug)]
pub struct FastscanOptions {
    /// The first probe's window, when no step is given.
    pub timeout: Duration,
    /// Wait this long for each answer instead of learning it from the devices (lengthened
    /// only if answers come later still).
    pub step: Option<Duration>,
    /// Identity parts known in advance: not searched.
    pub vendor: Option<u32>,
    /// The product code, when known.
    pub product: Option<u32>,
    /// The revision number, when known.
    pub revision: Option<u32>,
}

impl FastscanOptions {
    /// A search of every identity part, its pace learnt from the devices; `timeout` for the first probe.
    pub fn new(timeout: Duration) -> FastscanOptions {
        FastscanOptions { timeout, step: None, vendor: None, product: None, revision: None }
    }

    fn given(&self) -> [Option<u32>; 4] {
        [self.vendor, self.product, self.revision, None]
    }

    fn pace(&self) -> Pace {
        match self.step {
            Some(step) => Pace::fixed(step, self.timeout),
            None => Pace::measured(self.timeout),
        }
    }
}

/// The pace a fastscan used and what it was learned from.
#[derive(Clone, Debug, Serialize)]
#[non_exhaustive]
pub struct PaceUsed {
    /// The longest step waited.
    pub step_ms: u64,
    /// The slowest answer seen.
    pub slowest_answer_ms: Option<f64>,
    /// How often answers came later than the step and it was lengthened.
    pub escalations: u32,
}

impl From<&Pace> for PaceUsed {
    fn from(p: &Pace) -> PaceUsed {
        PaceUsed {
            step_ms: p.longest_step().as_millis() as u64,
            slowest_answer_ms: p.slowest().map(|s| s.as_secs_f64() * 1e3),
            escalations: p.escalations(),
        }
    }
}

impl PaceUsed {
    /// For people: the step and the slowest answer.
    pub fn text(&self) -> String {
        match self.slowest_answer_ms {
            Some(s) => format!("step {} ms (slowest answer {s:.1} ms)", self.step_ms),
            None => format!("step {} ms", self.step_ms),
        }
    }
}

/// A device without a node-id, found by fastscan.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Found {
    /// The device's LSS identity.
    #[serde(flatten)]
    pub identity: Identified,
    /// Fastscan requests sent.
    pub steps: u32,
    /// The longest step waited, in ms.
    pub step_ms: u64,
    /// The pace used and what it was learnt from.
    pub pace: PaceUsed,
    /// How long the search took, in ms.
    pub elapsed_ms: u64,
}

fn fastscan_error(error: FastscanError, pace: &Pace) -> Error {
    Error::Fastscan { error, step: pace.longest_step() }
}

/// Fastscan requests for one identity when all goes well: a reset, then 32 bits and a
/// confirmation for each part not given, one request for each part given. A bar's length,
/// not a limit: a search that has to slow down takes more.
fn fastscan_steps(given: [Option<u32>; 4]) -> u64 {
    1 + given.iter().map(|g| if g.is_some() { 1 } else { 33 }).sum::<u64>()
}

/// Find the identity of one device without a node-id, bit by bit. The device found is
/// sent back to waiting state, unchanged.
pub fn fastscan(bus: &mut dyn Bus, o: &FastscanOptions, interrupted: &Cancel) -> Result<Found> {
    fastscan_shown(bus, o, interrupted, &mut super::Silent)
}

/// [`fastscan`], each request a step on `progress` (the search takes 13 s on slow devices).
pub(crate) fn fastscan_shown(
    bus: &mut dyn Bus,
    o: &FastscanOptions,
    interrupted: &Cancel,
    progress: &mut dyn Progress,
) -> Result<Found> {
    let start = bus.now();
    let mut m = LssMaster::new(bus, o.timeout);
    let len = fastscan_steps(o.given());
    progress.start("fastscan", len);
    let mut sent = 0;
    let result = m.fastscan(o.pace(), o.given(), &mut || {
        sent += 1;
        progress.advance(sent.min(len));
        !interrupted.is_cancelled()
    });
    progress.finish();
    // The device found is in configuration state: whatever happened, every device goes
    // back to waiting, unchanged.
    let left = m.leave();
    let elapsed = m.bus().now().saturating_duration_since(start);
    let Some(outcome) = result? else {
        left?;
        return Err(Error::Interrupted);
    };
    left?;
    let id = outcome.found.map_err(|e| fastscan_error(e, &outcome.pace))?;
    let pace = PaceUsed::from(&outcome.pace);
    Ok(Found {
        identity: Identified(id),
        steps: outcome.steps,
        step_ms: pace.step_ms,
        pace,
        elapsed_ms: elapsed.as_millis() as u64,
    })
}

/// What `assign` needs to know.
#[derive(Clone, Debug)]
pub struct AssignOptions {
    /// The first node-id to give.
    pub start: u8,
    /// How to find each device (its pace, identity parts known in advance).
    pub fastscan: FastscanOptions,
    /// How long to listen for heartbeats before assigning; by default 1 s, or longer for
    /// the longest heartbeat period the nodes report.
    pub listen: Option<Duration>,
    /// Make each device keep its node-id across power cycles.
    pub store: bool,
}

/// A device given a node-id.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct AssignedNode {
    /// The device's LSS identity.
    #[serde(flatten)]
    pub identity: Identified,
    /// The node-id it was given and answered with.
    pub node: u8,
    /// The node-id was stored in the device (it keeps it across power cycles).
    pub stored: bool,
    /// Why it was not stored (or not asked to be).
    #[serde(serialize_with = "error_text")]
    pub store_error: Option<NotStored>,
}

/// What `assign` did: every device numbered, or how far it got and why it stopped.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Assignment {
    /// Each device given a node-id, in the order found.
    pub assigned: Vec<AssignedNode>,
    /// The node-ids in use before: the new ones do not collide with them.
    pub in_use_before: Vec<u8>,
    /// Fastscan requests sent, all searches together.
    pub fastscan_steps: u32,
    /// The longest step waited, in ms.
    pub step_ms: u64,
    /// The pace used and what it was learnt from.
    pub pace: PaceUsed,
    /// How long the assignment took, in ms.
    pub elapsed_ms: u64,
    /// The user asked to stop: the devices not yet given a node-id keep waiting.
    pub interrupted: bool,
    /// Why it stopped before every device had a node-id.
    #[serde(rename = "error", serialize_with = "error_text")]
    pub failure: Option<Error>,
}

fn error_text<S: serde::Serializer, E: std::fmt::Display>(e: &Option<E>, s: S) -> std::result::Result<S::Ok, S::Error> {
    match e {
        Some(e) => s.collect_str(e),
        None => s.serialize_none(),
    }
}

impl Assignment {
    /// Done when the last "any device without a node-id?" probe went unanswered: every
    /// device numbered, or none there to number (a provisioning script run again).
    pub fn outcome(self) -> Result<()> {
        match self.failure {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    /// Nothing to do: no device without a node-id answered, and nothing stopped the search.
    pub fn nothing_to_assign(&self) -> bool {
        self.assigned.is_empty() && self.failure.is_none() && !self.interrupted
    }
}

/// Default time to listen for heartbeats before assigning: long enough for the common
/// periods (100 ms .. 1 s); longer when a node reports a longer one.
const LISTEN: Duration = Duration::from_secs(1);
const LISTEN_CEILING: Duration = Duration::from_secs(10);
const HEARTBEAT_TIME: ObjAddr = ObjAddr::new(0x1017, 0);

/// Node-ids in use: the SDO probe, then heartbeats, boot-ups and everything else the bus
/// shows while listening. A node in Stopped answers no SDO but still beats.
fn ids_in_use(
    bus: &mut dyn Bus,
    timeout: Duration,
    listen: Option<Duration>,
    progress: &mut dyn Progress,
    interrupted: &Cancel,
) -> Result<BTreeSet<u8>> {
    // The probe asks again the ids that do not answer at once: a node beating no heartbeat
    // whose answer is lost would otherwise look free, and its id be given a second time.
    let found: Vec<u8> = super::scan::probe(bus, timeout.min(Duration::from_millis(100)), progress)?
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    let mut used: BTreeSet<u8> = found.iter().copied().collect();
    if bus.sees_traffic() {
        let listen = match listen {
            Some(l) => l,
            None => {
                let reads: Vec<(u8, ObjAddr)> = found.iter().map(|n| (*n, HEARTBEAT_TIME)).collect();
                let periods = bus.sdo_upload_many(&reads, &sized(timeout, Some(2)), &mut |_| {})?;
                let longest = periods
                    .iter()
                    .filter_map(|r| r.as_ref().ok()?.get(..2).map(|b| u16::from_le_bytes([b[0], b[1]])))
                    .max()
                    .unwrap_or(0);
                (Duration::from_millis(longest as u64) * 3 / 2).clamp(LISTEN, LISTEN_CEILING)
            }
        };
        let (begun, end) = (bus.now(), bus.now() + listen);
        progress.start("listening for node-ids in use", listen.as_millis() as u64);
        while bus.recv_frame(end)?.is_some() && !interrupted.is_cancelled() {
            progress.advance(bus.now().saturating_duration_since(begun).as_millis() as u64);
        }
        progress.finish();
    }
    used.extend(bus.observed().node_ids());
    Ok(used)
}

/// Give every device without a node-id the next free one from `start` on, and (with
/// `store`) make it keep it. Each device numbered is a note on `progress`.
pub fn assign(
    bus: &mut dyn Bus,
    o: &AssignOptions,
    progress: &mut dyn Progress,
    interrupted: &Cancel,
) -> Result<Assignment> {
    let start = bus.now();
    let timeout = o.fastscan.timeout;
    // Node-ids already in use: new ones must not collide.
    let used = ids_in_use(bus, timeout, o.listen, progress, interrupted)?;
    let in_use_before: Vec<u8> = used.iter().copied().collect();
    // Each device sought is a bar of fastscan requests (14 s each on slow devices).
    let len = fastscan_steps(o.fastscan.given());
    let (shown, sent, found) = (std::cell::RefCell::new(progress), std::cell::Cell::new(0), std::cell::Cell::new(0));
    let outcome = LssMaster::new(bus, timeout).assign(
        o.start,
        used,
        o.fastscan.pace(),
        o.fastscan.given(),
        o.store,
        &mut || {
            let mut progress = shown.borrow_mut();
            if sent.get() == 0 {
                progress.start(&format!("fastscan for device {}", found.get() + 1), len);
            }
            sent.set(sent.get() + 1);
            progress.advance(sent.get().min(len));
            !interrupted.is_cancelled()
        },
        &mut |d| {
            let mut progress = shown.borrow_mut();
            progress.finish();
            sent.set(0);
            found.set(found.get() + 1);
            progress.event(Notice::Assigned { identity: d.identity, node: d.node }.into());
        },
    );
    shown.borrow_mut().finish();
    let outcome = outcome?;
    let failure = if outcome.interrupted || interrupted.is_cancelled() {
        Some(Error::Interrupted)
    } else {
        outcome.failure.map(|e| match e {
            AssignFailure::Fastscan(f) => fastscan_error(f, &outcome.pace),
            AssignFailure::Refused(e) => e,
        })
    };
    let pace = PaceUsed::from(&outcome.pace);
    Ok(Assignment {
        assigned: outcome
            .assigned
            .into_iter()
            .map(|d| AssignedNode {
                identity: Identified(d.identity),
                node: d.node,
                stored: d.stored.is_ok(),
                store_error: d.stored.err(),
            })
            .collect(),
        in_use_before,
        fastscan_steps: outcome.steps,
        step_ms: pace.step_ms,
        pace,
        elapsed_ms: bus.now().saturating_duration_since(start).as_millis() as u64,
        interrupted: outcome.interrupted,
        failure,
    })
}
