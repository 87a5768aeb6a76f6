//! A scan's first phase: the SDO probe of every node-id (a read of 0x1000), asked again
//! where an answer may have been lost, with the nodes that answered only then (frames being
//! lost) and, where the probe asks again within its window, a read of each node that
//! answered whose every answer is counted (a second device's too).

use super::window::check_window;
use crate::bus::observer::SeenBy;
use crate::bus::{Bus, SdoJob, SdoOptions};
use crate::canopen::ObjAddr;
use crate::error::{Error, Result};
use crate::ops::event::Warning;
use crate::ops::progress::Progress;
use crate::ops::values::as_u32;
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Duration;

/// Rounds of the SDO probe of node-ids. A node that beats no heartbeat (CANopenNode's
/// default) shows itself only by its answer, and a lost request or answer (2 % of the
/// frames on a loaded adapter or gateway) would make it look absent: one round misses
/// such a node about one time in 25 then, three about one in 16,000. Each round after the
/// first asks again only the ids that have not answered: one more window, not a rescan.
/// That holds where the probes are in flight at once; through a gateway that makes one
/// transfer at a time (an EPOS2) each silent id costs a wait of its own, a round would be a
/// whole scan again, and its link already sends a command again after a lost or damaged
/// frame: one round there.
pub(crate) const PROBE_ROUNDS: usize = 3;

/// How many rounds of the probe this bus gets ([`PROBE_ROUNDS`]).
pub(crate) fn probe_rounds(bus: &dyn Bus) -> usize {
    if bus.sees_traffic() {
        PROBE_ROUNDS
    } else {
        1
    }
}

/// How long after its request has left the bus a silent id is asked again, where the link
/// says when that is ([`Bus::frame_time`]): devices answer within a few ms, so a lost
/// request or answer costs this, not a whole window. A slow device (up to 80 ms) answers
/// every request it gets, and is told from a lost frame by its count of answers.
const ASK_AGAIN_AFTER: Duration = Duration::from_millis(20);

/// Every node that answers an SDO read of 0x1000 within `window`, in up to
/// `PROBE_ROUNDS` rounds, with its device type (`None` when it answered with an abort:
/// the node is there all the same).
pub fn probe(bus: &mut dyn Bus, window: Duration, progress: &mut dyn Progress) -> Result<Found> {
    check_window(window)?;
    let rounds = probe_rounds(bus);
    found_unless_stopped(probe_until_stopped(bus, window, rounds, None, progress)?)
}

/// [`probe`] in one round: who answers at all, for a diagnosis that needs no more (the
/// rounds after it only find nodes whose answers were lost).
pub(crate) fn probe_once(bus: &mut dyn Bus, window: Duration) -> Result<Found> {
    check_window(window)?;
    found_unless_stopped(probe_until_stopped(bus, window, 1, None, &mut crate::ops::progress::Silent)?)
}

fn found_unless_stopped(p: Probed) -> Result<Found> {
    (!p.stopped).then_some(p.found).ok_or(Error::Interrupted)
}

/// Nodes that answered a probe, with their device types.
type Found = Vec<(u8, Option<u32>)>;

/// A node that answered fewer of the probes sent to it than were sent, and did not restart
/// meanwhile (no boot-up heard): frames are being lost (a loaded adapter or gateway, a bus
/// with errors), and a single probe may miss it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Repeat {
    /// The node-id.
    pub node: u8,
    /// The probes sent to it.
    pub probes: usize,
    /// The answers it gave (fewer).
    pub answered: usize,
}

/// What the rounds of the probe found.
#[derive(Debug, Default)]
pub(crate) struct Probed {
    /// By node-id.
    pub found: Found,
    /// How many rounds ran.
    pub rounds: usize,
    /// The nodes that answered only in a later round.
    pub repeats: Vec<Repeat>,
    /// Stopped part-way (with the nodes found until then).
    pub stopped: bool,
    /// The read asked of every node that answered, in the same batch, where the probe asks
    /// again within its window (`probe_until_stopped`'s `also`): by node, its every answer.
    pub also: BTreeMap<u8, crate::bus::Asked>,
}

/// [`probe`] in up to `rounds` rounds, with how many ran, who answered only on a repeat,
/// and whether it was stopped part-way (with the nodes found until then). Where the rounds
/// go in one batch, each node that answers is read `also` right after, in the same batch,
/// and every answer to that read is counted while the probe waits for the silent ids
/// ([`Probed::also`]): a scan's serial number, whose second answers show two devices.
pub(crate) fn probe_until_stopped(
    bus: &mut dyn Bus,
    window: Duration,
    rounds: usize,
    also: Option<ObjAddr>,
    progress: &mut dyn Progress,
) -> Result<Probed> {
    // Where the link says when a request has left the bus, every round goes in one batch:
    // an id silent a typical answer time after its request is asked again at once, while
    // the window of the first request still runs. Elsewhere round after round, each asking
    // the silent ids at once, each one more window: not retried one by one, as most ids
    // have no node behind them and a retry would be one more window for each.
    let at_once = bus.frame_time().is_some();
    let base = crate::ops::sdo_options::capped(window, crate::ops::sdo_options::NUMBER_LIMIT);
    let mut ids: Vec<u8> = (1..=127).collect();
    let mut p = Probed::default();
    // What a node answered that was not an answer (a malformed frame may be a damaged
    // one): said only when no later round brings a good one.
    let mut failed: BTreeMap<u8, Error> = BTreeMap::new();
    while p.rounds < rounds && !ids.is_empty() && !p.stopped {
        let first = p.rounds == 0;
        // A malformed answer ends its id's batch: the next round asks it once more.
        let batch = if at_once && first { rounds } else { 1 };
        let opts = SdoOptions {
            retries: (batch - 1) as u8,
            // Within a short window too: at most half of it.
            ask_again_after: (batch > 1).then_some(ASK_AGAIN_AFTER.min(window / 2)),
            ..base.clone()
        };
        p.rounds += batch;
        let then = also.filter(|_| batch > 1);
        let reads: Vec<(u8, ObjAddr)> =
            ids.iter().flat_map(|n| std::iter::once((*n, ObjAddr::DEVICE_TYPE)).chain(then.map(|a| (*n, a)))).collect();
        // Only the probe is asked again early: a second answer to the other read is news.
        let once = SdoOptions { ask_again_after: None, ..opts.clone() };
        let job = |&(node, addr): &(u8, ObjAddr)| {
            let opts = if addr == ObjAddr::DEVICE_TYPE { opts.clone() } else { once.clone() };
            SdoJob::Upload { node, addr, opts }
        };
        let jobs: Vec<SdoJob> = reads.iter().map(job).collect();
        let count = ids.len() as u64;
        progress.start(if first { "probing" } else { "probing again" }, count);
        bus.observed().answers_counted.clear();
        let answers = bus.sdo_batch(&jobs, &mut |n| progress.advance((n as u64).min(count)));
        progress.finish();
        let mut asked = std::mem::take(&mut bus.observed().answers_counted);
        if let Some(then) = then {
            p.also = ids.iter().filter_map(|n| Some((*n, asked.remove(&(*n, then))?))).collect();
        }
        // Stopped before a repeat went out: what the rounds before found stands.
        let answers = match answers {
            Err(e) if e.is_interrupted() => {
                p.stopped = true;
                break;
            }
            answers => answers?,
        };
        ids.clear();
        let probes = reads.iter().zip(answers).filter(|((_, addr), _)| *addr == ObjAddr::DEVICE_TYPE);
        for ((node, _), answer) in probes {
            let device_type = match answer {
                Ok(bytes) => as_u32(&bytes),
                Err(Error::SdoAbort { .. }) => None,
                Err(e) if e.is_interrupted() => {
                    p.stopped = true;
                    continue;
                }
                Err(e) => {
                    // An id asked every time already in this batch is done with.
                    if !e.is_timeout() {
                        failed.insert(*node, e);
                        ids.push(*node);
                    } else if batch == 1 {
                        ids.push(*node);
                    }
                    continue;
                }
            };
            // Frames were lost only where the rounds before heard nothing of it: an answer
            // that was malformed or without end was an answer. A node whose boot-up was
            // heard restarted meanwhile: it was silent while it booted, nothing was lost.
            let answered_before = failed.remove(node).is_some();
            let restarted = bus.observed().nodes.get(node).is_some_and(|how| how.contains(&SeenBy::BootUp));
            p.found.push((*node, device_type));
            // Asked in one batch, a node that is only slow answers every request; round by
            // round, an answer in a later round is the sign.
            let repeat = match asked.get(&(*node, ObjAddr::DEVICE_TYPE)) {
                Some(a) => Some(Repeat { node: *node, probes: a.requests.into(), answered: a.answers.len() })
                    .filter(|_| a.lost_frames()),
                None => (!first).then_some(Repeat { node: *node, probes: p.rounds, answered: 1 }),
            };
            p.repeats.extend(repeat.filter(|_| !answered_before && !restarted));
        }
    }
    // A node whose every answer was malformed or without end answered all the same: it is
    // there, its device type unknown, and what it sent is its finding.
    for (node, error) in failed {
        progress.event(Warning::Failed { node: Some(node), error }.into());
        p.found.push((node, None));
    }
    p.found.sort_by_key(|(n, _)| *n);
    if p.found.is_empty() && !p.stopped {
        // No node at all: an adapter at the wrong bit rate sees exactly that, and may say so.
        crate::ops::unheard::check(bus)?;
    }
    Ok(p)
}
