//! Number every device without a node-id: fastscan each, give it the next free id, store it.

use super::*;

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

pub(super) fn error_text<S: serde::Serializer, E: std::fmt::Display>(
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
