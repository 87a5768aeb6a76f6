//! A device whose SDO server answers on another node's COB-ID (its 0x1200 changed, or a
//! firmware that got it wrong): the probe sends all 127 requests at once, so its answer is
//! taken for that other node's, and a node that is not there is listed. Asking one node at
//! a time, with nothing else in flight, shows where each answer really comes from.
//!
//! Only where there is a reason to look (a node that shows itself, by heartbeat, boot-up or
//! the last scan, but answered no probe): on a bus without one this costs nothing.

use crate::bus::{Bus, SeenBy};
use crate::canopen::sdo::{request_cob, response_cob, SdoClient};
use crate::canopen::ObjAddr;
use crate::error::Result;
use crate::frame::Frame;
use std::collections::BTreeSet;
use std::time::Duration;

/// A node whose SDO server answers on another COB-ID than its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[non_exhaustive]
pub struct AnswersElsewhere {
    /// The node asked.
    pub node: u8,
    /// The COB-ID its answer came on.
    pub cob_id: u16,
}

/// What asking each suspect alone showed: the nodes whose answers come on another node's
/// COB-ID, and the node-ids whose COB-ID that is that give no answer of their own when asked
/// alone: they are not there, whether the probe found them (it took that answer for theirs)
/// or not (the bus's observer saw the suspect's answer on their COB-ID, and nothing else).
#[derive(Debug, Default, PartialEq)]
pub(crate) struct Shown {
    pub elsewhere: Vec<AnswersElsewhere>,
    pub phantoms: Vec<u8>,
}

/// Ask each of `suspects` (nodes that show themselves but answered no probe) alone; where
/// one answers on the COB-ID of a node in `found`, or of a node that shows itself no other
/// way (its COB-ID has that answer on the bus all the same), ask that node alone too:
/// silent, it is not there. Each request waits `window` at most. Where the link shows no
/// traffic (an EPOS2 gateway reads one node after the other) nothing is asked.
pub(crate) fn look(bus: &mut dyn Bus, suspects: &[u8], found: &[u8], window: Duration) -> Result<Shown> {
    let mut shown = Shown::default();
    if suspects.is_empty() || !bus.sees_traffic() {
        return Ok(shown);
    }
    for &node in suspects {
        let Some(cob_id) = ask_alone(bus, node, window)?.filter(|&c| c != response_cob(node)) else { continue };
        shown.elsewhere.push(AnswersElsewhere { node, cob_id });
        let claimed = (cob_id - 0x580) as u8;
        // A node-id not found that shows itself otherwise (heartbeat, boot-up) is there.
        let shows_itself = |how: &BTreeSet<SeenBy>| how.iter().any(|h| matches!(h, SeenBy::Heartbeat | SeenBy::BootUp));
        let beats = bus.observed().nodes.get(&claimed).is_some_and(shows_itself);
        if (found.contains(&claimed) || !beats) && ask_alone(bus, claimed, window)? != Some(response_cob(claimed)) {
            shown.phantoms.push(claimed);
        }
    }
    Ok(shown)
}

/// How many times a node is asked alone before its silence counts: as often as the probe
/// asks an id (a lost or damaged answer is not taken for none).
const TRIES: usize = super::scan::probe::PROBE_ROUNDS;

/// A read of the device type sent to `node` with nothing else in flight, up to [`TRIES`]
/// times: the COB-ID of the first answer to it (on any SDO response id), each try waiting
/// `window` at most.
pub(crate) fn ask_alone(bus: &mut dyn Bus, node: u8, window: Duration) -> Result<Option<u16>> {
    for _ in 0..TRIES {
        bus.send_frame(&Frame::new(request_cob(node), &SdoClient::upload(ObjAddr::DEVICE_TYPE, false).start()))?;
        let end = bus.now() + window;
        while let Some(f) = bus.recv_frame(end)?.filter(|_| bus.now() <= end) {
            let response = (0x581..=0x5FF).contains(&f.id()) && !f.is_remote();
            if response && super::clash::upload_answer(f.data(), ObjAddr::DEVICE_TYPE).is_some() {
                return Ok(Some(f.id()));
            }
        }
    }
    Ok(None)
}

/// Whether an answer comes on `node`'s SDO response COB-ID while every other node-id is
/// asked and `node` is not (a read of the device type each, up to [`TRIES`] rounds, each
/// waiting `window` at most): then that COB-ID is another device's, and `node` is not there.
/// A node that fell silent after answering for itself gets no answer there.
pub(crate) fn answered_by_another(bus: &mut dyn Bus, node: u8, window: Duration) -> Result<bool> {
    let request = SdoClient::upload(ObjAddr::DEVICE_TYPE, false).start();
    for _ in 0..TRIES {
        for other in (1..=127).filter(|&n| n != node) {
            bus.send_frame(&Frame::new(request_cob(other), &request))?;
        }
        let end = bus.now() + window;
        while let Some(f) = bus.recv_frame(end)?.filter(|_| bus.now() <= end) {
            let answer = super::clash::upload_answer(f.data(), ObjAddr::DEVICE_TYPE).is_some();
            if f.id() == response_cob(node) && !f.is_remote() && answer {
                return Ok(true);
            }
        }
    }
    Ok(false)
}

#[cfg(test)]
mod tests {
    use crate::ops::scan::{scan_against, ScanOptions};
    use crate::ops::Silent;
    use crate::sim::{SimConfig, SimLink};
    use std::time::Duration;

    /// Found by the DST (seed 0x1c000b94): node 10's SDO server answers on node 11's COB-ID,
    /// and the device reboots on the probe, so no answer to the probe comes on 0x58B. Its
    /// boot-up makes node 10 a suspect, asked alone: it answers on 0x58B, which the bus's
    /// observer took for node 11 showing itself, and node 11 was listed, where no device has
    /// it. Asked alone, node 11 answers nothing: it is not listed; node 10 is, answering
    /// elsewhere.
    #[test]
    fn an_answer_elsewhere_from_a_suspect_asked_alone_lists_no_node() {
        let mut config = SimConfig::default().seed(1).virtual_time(true);
        for fault in ["10:wrong-cob", "10:reboot@1"] {
            config = config.fault(fault.parse().unwrap());
        }
        let mut bus = crate::bus::Master::new(SimLink::with_config(config).on_virtual_time(0), "sim".into());
        let o = ScanOptions { window: Duration::from_millis(300), timeout: Duration::from_millis(200) };
        let scan = scan_against(&mut bus, &o, &[1, 5, 10, 32], &mut Silent).unwrap();
        let nodes: Vec<u8> = scan.nodes.iter().map(|n| n.node).collect();
        assert_eq!(nodes, [1, 5, 10, 32], "{scan:?}");
        assert_eq!(scan.answers_elsewhere, [super::AnswersElsewhere { node: 10, cob_id: 0x58B }], "{scan:?}");
    }
}
