//! Node-ids and bit rates over LSS (CiA 305): ask a device its identity, give it a node-id
//! or a bit rate, find devices without a node-id (fastscan) and number them all (assign).
//! Whatever ends a procedure, every device is sent back to LSS waiting state, where it
//! answers no other master's services by mistake. The request sequences themselves are
//! [`LssMaster`]'s; an interruption is a flag, checked between steps.

use super::progress::Progress;
use crate::bus::lss::LssMaster;
use crate::bus::{Bus, LssWait, SdoOptions};
use crate::cancel::Cancel;
use crate::canopen::lss::{self, Identity, Inquiry, Request, Response, UNCONFIGURED};
use crate::canopen::ObjAddr;
use crate::error::{Error, Result};
use serde::Serialize;
use std::time::Duration;

mod assign;
mod fastscan;
mod identified;
use assign::LISTEN;
pub use assign::*;
pub use fastscan::*;
pub use identified::Identified;

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

    /// The identity of the one device it is, if it is one.
    fn identity(self) -> Option<Identity> {
        match self {
            Target::One(id) => Some(id),
            _ => None,
        }
    }
}

/// Put the devices addressed in configuration state; failing that, all back to waiting (a
/// late acknowledgement may still have put one in configuration state).
fn enter(m: &mut LssMaster, identity: Option<&Identity>) -> Result<()> {
    m.enter(identity).or_else(|e| m.leave().and(Err(e)))
}

/// What the LSS services are refused with on an EPOS2 reached directly.
pub fn no_lss_on_direct_epos2(verb: &str) -> Error {
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
    if target == Target::DirectEpos2 {
        return Err(no_lss_on_direct_epos2("inquire"));
    }
    let identity = target.identity();
    let mut m = LssMaster::new(bus, timeout);
    enter(&mut m, identity.as_ref())?;
    let mut values = Vec::new();
    for q in [Inquiry::Vendor, Inquiry::Product, Inquiry::Revision, Inquiry::Serial, Inquiry::NodeId] {
        let answers = m.ask(Request::Inquire(q), if identity.is_none() { LssWait::All } else { LssWait::First })?;
        let found: Vec<u32> = answers
            .iter()
            .filter_map(|a| match a {
                Response::InquiredValue { inquiry, value } if *inquiry == q => Some(*value),
                _ => None,
            })
            .collect();
        let value = match found.as_slice() {
            [v] => Ok(*v),
            [] => Err(Error::NoLssAnswer { request: "the inquiry".into(), identity: None, waited: timeout }),
            more => Err(Error::InquiryAnsweredByMany { count: more.len() }),
        };
        values.push(value.or_else(|e| m.leave().and(Err(e)))?);
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
        self.failure.map_or(Ok(()), Err)
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
            let identity = target.identity();
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
/// one that some devices refused is remembered (`RefusedRate`) for [`activate_on`] to warn
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
        let Some(path) = super::scan_cache::network_file(super::scan_cache::LSS_SET_BAUD, bus) else { return };
        let _ = match what {
            Some(r) => {
                let _ = std::fs::create_dir_all(path.parent().expect("a directory"));
                std::fs::write(&path, serde_json::to_string(r).expect("serialises"))
            }
            None => std::fs::remove_file(&path),
        };
    }

    pub fn last(bus: &str) -> Option<RefusedRate> {
        let path = super::scan_cache::network_file(super::scan_cache::LSS_SET_BAUD, bus)?;
        serde_json::from_slice(&std::fs::read(path).ok()?).ok()
    }
}

/// `lss set-id`: [`configure`] the node-id, after checking nothing on the bus uses it
/// already (unless `force`): an SDO answer from another device than `target`, or a
/// heartbeat, boot-up or guarding answer heard while listening as `assign` does.
pub fn set_id(
    bus: &mut dyn Bus,
    timeout: Duration,
    target: Target,
    node: u8,
    force: bool,
    interrupted: &Cancel,
) -> Result<Configured> {
    if !force && node != UNCONFIGURED && !interrupted.is_cancelled() {
        if let Some(u) = super::clash::in_use(bus, node, target.identity(), timeout, LISTEN)? {
            return Err(Error::NodeIdInUse { node, identity: u.identity, by: u.by });
        }
    }
    configure(bus, timeout, target, Setting::NodeId(node), interrupted)
}

use crate::epos2::objects::{
    bit_rate_code as epos2_bit_rate_code, CAN_BIT_RATE as EPOS2_CAN_BIT_RATE, NODE_ID as EPOS2_NODE_ID,
};

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
            let name = lss::bit_rate_name(index);
            let none =
                || Error::Usage(format!("the EPOS2 has no {name} setting: use 1M 800k 500k 250k 125k 50k or 20k"));
            let code = epos2_bit_rate_code(index).ok_or_else(none)?;
            bus.sdo_download(0, EPOS2_CAN_BIT_RATE, &code.to_le_bytes(), &opts)
                .map(|_| Took::Epos2BitRate { index, code })
        }
        Setting::Store => bus.sdo_download(0, ObjAddr::STORE_ALL, b"save", &opts).map(|_| Took::Epos2Stored),
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
    if target == Target::DirectEpos2 {
        return Err(Error::Epos2RateOnStore);
    }
    let identity = target.identity();
    let mut m = LssMaster::new(bus, timeout);
    enter(&mut m, identity.as_ref())?;
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
