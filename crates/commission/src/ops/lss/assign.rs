//! Number every device without a node-id: fastscan each, give it the next free id, store it.

use crate::bus::lss::LssMaster;
use crate::bus::Bus;
use crate::cancel::Cancel;
use crate::canopen::lss::{self, FastscanError, Identity, Pace, Request};
use crate::canopen::ObjAddr;
use crate::error::{Error, Result};
use crate::ops::event::Notice;
use crate::ops::progress::Progress;
use crate::ops::sdo_options::sized;
use serde::Serialize;
use std::collections::BTreeSet;
use std::time::Duration;

use super::fastscan::{fastscan_error, fastscan_steps, FastscanOptions, PaceUsed};
use super::identified::Identified;

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

pub(crate) fn error_text<S: serde::Serializer, E: std::fmt::Display>(
    e: &Option<E>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    match e {
        Some(e) => s.collect_str(e),
        None => s.serialize_none(),
    }
}

impl Assignment {
    /// Done when the last "any device without a node-id?" probe went unanswered: every
    /// device numbered, or none there to number (a provisioning script run again).
    pub fn outcome(self) -> Result<()> {
        self.failure.map_or(Ok(()), Err)
    }

    /// Nothing to do: no device without a node-id answered, and nothing stopped the search.
    pub fn nothing_to_assign(&self) -> bool {
        self.assigned.is_empty() && self.failure.is_none() && !self.interrupted
    }
}

/// Default time to listen for heartbeats before assigning: long enough for the common
/// periods (100 ms .. 1 s); longer when a node reports a longer one.
pub(super) const LISTEN: Duration = Duration::from_secs(1);

const LISTEN_CEILING: Duration = Duration::from_secs(10);

/// Node-ids in use: the SDO probe, then heartbeats, boot-ups and everything else the bus
/// shows while listening. A node in Stopped answers no SDO but still beats.
pub(super) fn ids_in_use(
    bus: &mut dyn Bus,
    timeout: Duration,
    listen: Option<Duration>,
    progress: &mut dyn Progress,
    interrupted: &Cancel,
) -> Result<BTreeSet<u8>> {
    // The probe asks again the ids that do not answer at once: a node beating no heartbeat
    // whose answer is lost would otherwise look free, and its id be given a second time.
    let found: Vec<u8> = crate::ops::scan::probe(bus, timeout.min(Duration::from_millis(100)), progress)?
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    let mut used: BTreeSet<u8> = found.iter().copied().collect();
    if bus.sees_traffic() {
        let listen = match listen {
            Some(l) => l,
            None => {
                let reads: Vec<(u8, ObjAddr)> = found.iter().map(|n| (*n, ObjAddr::HEARTBEAT_TIME)).collect();
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
    let (mut m, pace, given) = (LssMaster::new(bus, timeout), o.fastscan.pace(), o.fastscan.given());
    let outcome = number_all(&mut m, o.start, used, pace, given, o.store, progress, interrupted)?;
    let stopped = outcome.interrupted || interrupted.is_cancelled();
    let failure = if stopped { Some(Error::Interrupted) } else { outcome.failure };
    let pace = PaceUsed::from(&outcome.pace);
    Ok(Assignment {
        assigned: outcome.assigned,
        in_use_before,
        fastscan_steps: outcome.steps,
        step_ms: pace.step_ms,
        pace,
        elapsed_ms: bus.now().saturating_duration_since(start).as_millis() as u64,
        interrupted: outcome.interrupted,
        failure,
    })
}

/// Why a device `assign` numbered does not keep its node-id across a power cycle, or may not.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum NotStored {
    /// The store was not asked for.
    #[error("not asked")]
    NotAsked,
    /// "store configuration" went unanswered: sent once (an action), and LSS has no way to
    /// read it back, so whether `node` keeps its id is unknown; storing again by its
    /// `identity` settles it.
    #[error("no answer to the store: unknown whether node {node} keeps its id across a power cycle")]
    NoAnswer {
        /// The node-id it was given.
        node: u8,
        /// The device, to address it again.
        identity: Identity,
    },
    /// The device refused the store, or the bus failed.
    #[error("{0}")]
    Failed(Error),
}

/// What `assign` did: the devices it gave node-ids, the fastscan steps it took, and why it stopped
/// early, if it did.
pub struct AssignOutcome {
    /// The devices given node-ids, in order.
    pub assigned: Vec<AssignedNode>,
    /// Fastscan requests sent, in all.
    pub steps: u32,
    /// Why it stopped before every device had a node-id (a fastscan that went wrong, a
    /// device that refused its node-id, the bus); `None` when none was left.
    pub failure: Option<Error>,
    /// The pace learned: the step the fastscans used.
    pub pace: Pace,
    /// Stopped early because `keep_going` said so (an interruption).
    pub interrupted: bool,
}

/// Give every device without a node-id the next node-id from `start` on that is not in
/// `used`: fastscan finds one (leaving it in configuration state), it gets its node-id
/// and, with `store`, keeps it; back in waiting state it boots and leaves the search.
/// Each search is a bar of its requests on `progress`, each device numbered a notice;
/// `cancel` stops it before its next request. Whatever ends it, every device is sent back
/// to waiting state.
#[allow(clippy::too_many_arguments)]
pub fn number_all(
    m: &mut LssMaster,
    start: u8,
    used: BTreeSet<u8>,
    pace: Pace,
    given: [Option<u32>; 4],
    store: bool,
    progress: &mut dyn Progress,
    cancel: &Cancel,
) -> Result<AssignOutcome> {
    let mut out =
        AssignOutcome { assigned: Vec::new(), steps: 0, failure: None, pace: pace.clone(), interrupted: false };
    let result = assign_each(m, start, used, given, store, progress, cancel, &mut out);
    progress.finish();
    // A failure, a lost link or an interruption must not leave a device in
    // configuration state, where it would answer the next master's services.
    let left = m.leave();
    match result {
        Err(Stop::Error(e)) => return Err(e),
        Err(Stop::Failure(f)) => out.failure = Some(f),
        Ok(()) => {}
    }
    if let (Err(e), None) = (left, &out.failure) {
        out.failure = Some(e);
    }
    Ok(out)
}

/// What ends a numbering early: a failure its report tells, or an error that ends the
/// command. A device's refusal, or a failure of the bus, is the first.
enum Stop {
    Failure(Error),
    Error(Error),
}

impl From<Error> for Stop {
    fn from(e: Error) -> Stop {
        Stop::Failure(e)
    }
}

#[allow(clippy::too_many_arguments)]
fn assign_each(
    m: &mut LssMaster,
    start: u8,
    mut used: BTreeSet<u8>,
    given: [Option<u32>; 4],
    store: bool,
    progress: &mut dyn Progress,
    cancel: &Cancel,
    out: &mut AssignOutcome,
) -> std::result::Result<(), Stop> {
    let len = fastscan_steps(given);
    // Searches in a row that found nobody: one lost answer must not be taken for "every
    // device has a node-id" (exit 0), so silence is believed only when it repeats.
    let mut silent = 0;
    let (mut found_again, mut crowded) = (0, 0);
    // Requests sent in the search for the device being sought.
    let mut sent = 0;
    loop {
        // One bar per device sought, over its searches (a lost answer searches again).
        if sent == 0 {
            progress.start(&format!("fastscan for device {}", out.assigned.len() + 1), len);
        }
        let mut this_search = 0;
        let scan = m
            .fastscan(out.pace.clone(), given, cancel, &mut |n| {
                this_search = n;
                progress.advance((sent + n).min(len));
            })
            .map_err(Stop::Error)?;
        sent += this_search;
        let Some(scan) = scan else {
            out.interrupted = true;
            return Ok(());
        };
        out.steps += scan.steps;
        out.pace = scan.pace;
        let identity = match scan.found {
            Ok(found) => found,
            Err(FastscanError::NoDevice) => {
                silent += 1;
                if silent < lss::NO_DEVICE_PROBES {
                    continue;
                }
                return Ok(());
            }
            Err(e) => return Err(Stop::Failure(fastscan_error(e, &out.pace))),
        };
        silent = 0;
        // Another device is in configuration state with it (it missed a switch back):
        // a set-id now would give both one node-id. Everyone back, and search again.
        if scan.crowded {
            crowded += 1;
            if crowded > lss::REPEATS {
                return Err(Error::LssCrowded { identity, times: crowded }.into());
            }
            m.leave()?;
            continue;
        }
        // Found again: the device numbered before did not leave configuration state
        // (the switches back were lost, or its answers to the inquiry). It is the same
        // device: it gets its node-id again, is sent back, and is reported once.
        if let Some(first) = out.assigned.iter().find(|d| d.identity.0 == identity).map(|d| d.node) {
            found_again += 1;
            if found_again > lss::REPEATS {
                let tries = m.sent_back_since_given(identity);
                return Err(Error::LssStillConfiguring { identity, node: first, tries }.into());
            }
            m.set_id(identity, first)?;
            m.back_to_waiting(identity, first)?;
            continue;
        }
        // Ids seen meanwhile (a heartbeat, a boot-up) are taken too.
        used.extend(m.bus().observed().node_ids());
        let Some(node) = (start..=127).find(|n| !used.contains(n)) else {
            return Err(Error::NoFreeNodeId { start, identity }.into());
        };
        m.set_id(identity, node)?;
        // An action: never sent twice blindly, and LSS has no way to read it back, so a
        // lost answer leaves it unknown, and the report says so.
        let store_error = match store {
            true => m.configure(Request::StoreConfiguration, "store", false).err().map(|e| match e {
                Error::NoLssAnswer { .. } => NotStored::NoAnswer { node, identity },
                e => NotStored::Failed(e),
            }),
            false => Some(NotStored::NotAsked),
        };
        used.insert(node);
        // The device's bar ends, and its node-id is said as it is given.
        progress.finish();
        progress.event(Notice::Assigned { identity, node }.into());
        sent = 0;
        let stored = store_error.is_none();
        out.assigned.push(AssignedNode { identity: Identified(identity), node, stored, store_error });
        m.back_to_waiting(identity, node)?;
    }
}
