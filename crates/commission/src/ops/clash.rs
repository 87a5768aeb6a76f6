//! Two devices on one node-id. CANopen gives no device a way to say so; canctl sees it in
//! answers that contradict each other: two SDO answers to one request, heartbeats of one
//! node-id in two states at once, an identity that reads differently from one read to the
//! next. [`find`] looks for that on nodes a scan found; `in_use` checks an id is free
//! before LSS gives it to a device.

pub(crate) use crate::bus::reply::{upload_answer, Reply};
use crate::bus::Bus;
use crate::canopen::lss::Identity;
use crate::canopen::nmt::{self, ErrorControl};
use crate::canopen::sdo::SdoClient;
use crate::canopen::ObjAddr;
use crate::error::{Error, Result};
use crate::frame::Frame;
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt;
use std::time::Duration;

/// What showed that two devices answer to one node-id.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "evidence", rename_all = "snake_case")]
pub enum Evidence {
    /// One SDO read of 0x1018:4 got several answers: the values (`None`: an abort).
    SdoAnswers {
        /// Each answer's serial number.
        values: Vec<Option<u32>>,
    },
    /// Heartbeats of the node-id showed these different states in one short listen.
    HeartbeatStates {
        /// The states, in turn.
        states: Vec<nmt::State>,
    },
    /// Reads of 0x1018:4 one after the other gave these different values.
    IdentityChanged {
        /// The values, in turn.
        values: Vec<u32>,
    },
}

/// A node-id that more than one device answers to: a finding of scan and health (and,
/// later, of doctor). Its text says what showed it; the remedy (give one of the devices
/// another node-id, by its identity) is the front end's to word.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Clash {
    /// The node-id.
    pub node: u8,
    /// What showed it.
    #[serde(flatten)]
    pub evidence: Evidence,
}

impl fmt::Display for Clash {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (n, serial) = (self.node, |v: &u32| format!("0x{v:08X}"));
        match &self.evidence {
            Evidence::SdoAnswers { values } => {
                let list: Vec<String> = values.iter().map(|v| v.as_ref().map_or("an abort".into(), serial)).collect();
                let count = values.len();
                write!(
                    f,
                    "node-id {n} is used by {count} devices: one read of 0x1018:4 got {count} answers ({})",
                    list.join(", ")
                )
            }
            Evidence::HeartbeatStates { states } => {
                let list: Vec<&str> = states.iter().map(|s| s.name()).collect();
                write!(
                    f,
                    "node-id {n} is used by more than one device: its heartbeats say {} at once",
                    list.join(" and ")
                )
            }
            Evidence::IdentityChanged { values } => {
                let list: Vec<String> = values.iter().map(serial).collect();
                write!(f, "node-id {n} is used by more than one device: 0x1018:4 reads {} in turn", list.join(", "))
            }
        }
    }
}

/// What the answers heard for one node say: two answers to one read, two states in its
/// heartbeats, or one answer whose serial is not the one read a moment before (`earlier`;
/// two devices whose answers merged on the bus, or one of them lost, show this way).
fn judge(answers: Vec<Option<u32>>, states: Vec<nmt::State>, earlier: Option<u32>) -> Option<Evidence> {
    match answers[..] {
        [_, _, ..] => Some(Evidence::SdoAnswers { values: answers }),
        [Some(now)] if earlier.is_some_and(|e| e != now) => {
            Some(Evidence::IdentityChanged { values: vec![earlier.unwrap_or_default(), now] })
        }
        _ if states.len() > 1 => Some(Evidence::HeartbeatStates { states }),
        _ => None,
    }
}

/// The nodes that more than one device answers to, of `nodes` (each with the serial
/// number 0x1018:4 read from it before, if any). Where the link shows the bus's traffic,
/// one read of 0x1018:4 to each node at once, and every answer and heartbeat heard for
/// `window`; else (through an EPOS2, which passes on one answer) two reads of 0x1018:4
/// each, compared.
pub fn find(bus: &mut dyn Bus, nodes: &[(u8, Option<u32>)], window: Duration, timeout: Duration) -> Result<Vec<Clash>> {
    find_after(bus, nodes, window, timeout, BTreeMap::new())
}

/// [`find`], where a probe already read 0x1018:4 of some of `nodes` and counted every
/// answer (`heard`, `scan::Probed::also`), and the bus's observer kept the
/// states heard since it began: those nodes are not asked again, and the listen lasts only
/// as long as their reads' windows still run. A scan so needs no window of its own.
pub(crate) fn find_after(
    bus: &mut dyn Bus,
    nodes: &[(u8, Option<u32>)],
    window: Duration,
    timeout: Duration,
    heard: BTreeMap<u8, crate::bus::Asked>,
) -> Result<Vec<Clash>> {
    if nodes.is_empty() {
        return Ok(Vec::new());
    }
    if !bus.sees_traffic() {
        let ids: Vec<u8> = nodes.iter().map(|(n, _)| *n).collect();
        return identity_changes(bus, &ids, timeout);
    }
    let wanted: BTreeMap<u8, Option<u32>> = nodes.iter().copied().collect();
    let mut end = bus.now();
    let mut answers: BTreeMap<u8, Vec<Option<u32>>> = BTreeMap::new();
    // The states heard since a probe began; of a node that restarted meanwhile, not: it
    // changed its state by booting, not by being two.
    let observed = bus.observed();
    let kept = |n: &u8| !heard.is_empty() && wanted.contains_key(n) && !observed.boot_ups.contains(n);
    let mut states: BTreeMap<u8, Vec<nmt::State>> =
        observed.states_heard.iter().filter(|(n, _)| kept(n)).map(|(n, shown)| (*n, shown.clone())).collect();
    for n in wanted.keys() {
        // A read that was sent again (its first request timed out) is not one read.
        match heard.get(n).filter(|asked| asked.requests == 1) {
            Some(asked) => {
                end = end.max(asked.counted_until);
                answers.insert(*n, asked.answers.clone());
            }
            None => {
                let read = SdoClient::upload(ObjAddr::SERIAL_NUMBER, false).start();
                bus.send_frame(&Frame::new(0x600 + u16::from(*n), &read))?;
                end = end.max(bus.now() + window);
            }
        }
    }
    while let Some(f) = bus.recv_frame(end)? {
        let id = f.id();
        if (0x581..=0x5FF).contains(&id) && wanted.contains_key(&((id - 0x580) as u8)) {
            if let Some(v) = upload_answer(f.data(), ObjAddr::SERIAL_NUMBER).and_then(Reply::value) {
                answers.entry((id - 0x580) as u8).or_default().push(v);
            }
        } else if let Some((node, ErrorControl::State { state, .. })) = ErrorControl::parse(&f) {
            let seen = states.entry(node).or_default();
            if wanted.contains_key(&node) && !seen.contains(&state) {
                seen.push(state);
            }
        }
    }
    let mut clash = |(node, earlier): (u8, Option<u32>)| {
        let (answers, states) = (answers.remove(&node).unwrap_or_default(), states.remove(&node).unwrap_or_default());
        Some(Clash { node, evidence: judge(answers, states, earlier)? })
    };
    Ok(wanted.into_iter().filter_map(&mut clash).collect())
}

/// Two reads of 0x1018:4 of each node, compared: where each answer is the first one to
/// come, two devices show as a serial number that changes.
fn identity_changes(bus: &mut dyn Bus, nodes: &[u8], timeout: Duration) -> Result<Vec<Clash>> {
    let reads: Vec<(u8, ObjAddr)> =
        nodes.iter().flat_map(|n| [(*n, ObjAddr::SERIAL_NUMBER), (*n, ObjAddr::SERIAL_NUMBER)]).collect();
    let values = bus.sdo_upload_many(
        &reads,
        &super::sdo_options::capped(timeout, super::sdo_options::NUMBER_LIMIT),
        &mut |_| {},
    )?;
    let mut seen: BTreeMap<u8, Vec<u32>> = BTreeMap::new();
    for ((n, _), v) in reads.iter().zip(values) {
        if let Some(s) = v.ok().filter(|b| b.len() >= 4).map(|b| super::values::le_u32(&b)) {
            let values = seen.entry(*n).or_default();
            if !values.contains(&s) {
                values.push(s);
            }
        }
    }
    let clash = |(node, values)| Clash { node, evidence: Evidence::IdentityChanged { values } };
    Ok(seen.into_iter().filter(|(_, v)| v.len() > 1).map(clash).collect())
}

/// How a node-id showed it is in use.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct InUse {
    pub node: u8,
    /// The identity the node answered with, when it gave all of it.
    pub identity: Option<Identity>,
    /// What showed it: "an SDO answer", "its heartbeat", ...
    pub by: &'static str,
}

/// Whether something on the bus already uses `node`, before a device `target` (if known)
/// is given it: an SDO answer to the identity reads (from another device than `target`),
/// else, where the link shows traffic, a heartbeat, boot-up or guarding answer within
/// `listen` (a Stopped node answers no SDO but still beats).
pub(crate) fn in_use(
    bus: &mut dyn Bus,
    node: u8,
    target: Option<Identity>,
    timeout: Duration,
    listen: Duration,
) -> Result<Option<InUse>> {
    // The identity is the node's 0x1018 (the LSS address is that object, CiA 305), read as
    // every command reads it (`Node::identity`), but its vendor-ID first on its own: any
    // answer to it, an abort too, says the id is in use, and a free id costs one timeout.
    let mut n = super::node::Node::new(bus, node, timeout);
    let (answered, identity) = match n.read::<u32>(ObjAddr::VENDOR_ID) {
        Ok(vendor) => match n.identity_of(vendor) {
            Ok(identity) => (true, identity.lss()),
            // It answered: whatever else it refuses or leaves unanswered, the id is in use.
            Err(e) if e.is_timeout() || matches!(e, Error::SdoAbort { .. }) => (true, None),
            Err(e) => return Err(e),
        },
        Err(Error::SdoAbort { .. }) => (true, None),
        Err(e) if e.is_timeout() => (false, None),
        Err(e) => return Err(e),
    };
    if answered {
        // The device itself, already on that id: nothing changes.
        if identity.is_some() && identity == target {
            return Ok(None);
        }
        return Ok(Some(InUse { node, identity, by: "an SDO answer" }));
    }
    if bus.sees_traffic() {
        let end = bus.now() + listen;
        while !bus.observed().nodes.contains_key(&node) && bus.recv_frame(end)?.is_some() {}
    }
    use crate::bus::SeenBy;
    let by = match bus.observed().nodes.get(&node).and_then(|s| s.iter().next()) {
        None => return Ok(None),
        Some(SeenBy::Heartbeat) => "its heartbeat",
        Some(SeenBy::BootUp) => "its boot-up",
        Some(SeenBy::Guarding) => "its node-guarding answer",
        Some(SeenBy::Sdo) => "an SDO answer",
        Some(SeenBy::LssInquiry) => "an LSS device's answer to 'inquire node-id'",
    };
    Ok(Some(InUse { node, identity: None, by }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contradicting_answers_are_a_clash_and_one_device_is_none() {
        use nmt::State::{Operational, PreOperational};
        let (a, b) = (0x0950_1234, 0x0950_1301);
        assert_eq!(judge(vec![Some(a)], vec![PreOperational], Some(a)), None);
        assert_eq!(judge(vec![], vec![], Some(a)), None, "no answer this time: not a clash");
        assert_eq!(judge(vec![Some(a)], vec![], None), None, "nothing read before to compare");
        assert_eq!(
            judge(vec![Some(a), Some(b)], vec![], Some(a)),
            Some(Evidence::SdoAnswers { values: vec![Some(a), Some(b)] })
        );
        // Two answers alike (merged on the bus they would be one): still two devices.
        assert!(matches!(judge(vec![Some(a), None], vec![], None), Some(Evidence::SdoAnswers { .. })));
        assert_eq!(judge(vec![Some(b)], vec![], Some(a)), Some(Evidence::IdentityChanged { values: vec![a, b] }));
        assert_eq!(
            judge(vec![Some(a)], vec![PreOperational, Operational], Some(a)),
            Some(Evidence::HeartbeatStates { states: vec![PreOperational, Operational] })
        );
    }

    #[test]
    fn a_clash_says_what_showed_it() {
        let c =
            Clash { node: 5, evidence: Evidence::SdoAnswers { values: vec![Some(0x0950_1234), Some(0x0950_1301)] } };
        let text = c.to_string();
        assert!(text.contains("node-id 5 is used by 2 devices") && text.contains("0x09501234, 0x09501301"), "{text}");
        let json = serde_json::to_value(&c).unwrap();
        assert_eq!(json["evidence"], "sdo_answers");
        assert_eq!(json["node"], 5);
    }
}
