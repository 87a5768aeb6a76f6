//! What a bus shows by itself, gathered from every frame received: which node-ids are in
//! use and how each was seen, NMT states from heartbeats, boot-ups, and LSS answers that
//! came in outside an exchange waiting for them. Commands read it instead of asking the
//! backend for each kind separately.

use crate::canopen::lss;
use crate::canopen::nmt::{self, ErrorControl};
use crate::canopen::ObjAddr;
use crate::frame::Frame;
use std::collections::{BTreeMap, BTreeSet};
use std::time::Instant;

/// How a node-id was seen in use.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SeenBy {
    /// An SDO answer (0x580 + node).
    Sdo,
    /// A heartbeat (0x700 + node, a state byte).
    Heartbeat,
    /// A boot-up message (0x700 + node, data 0x00).
    BootUp,
    /// An answer to a node-guarding request (0x700 + node, after a remote request).
    Guarding,
    /// An LSS device in configuration state answered "inquire node-id" with it.
    LssInquiry,
}

/// Stray LSS answers kept at most: a babbling device must not fill the memory.
const MAX_LSS_ANSWERS: usize = 1024;

/// How often one read of a batch that counts its answers ([`SdoOptions::ask_again_after`](super::SdoOptions::ask_again_after))
/// was sent to a node, and every answer that came to it: fewer answers than requests say a
/// frame was lost, more say that two devices answer to the node-id.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Asked {
    /// The requests sent (the first one included).
    pub requests: u8,
    /// Each answer, in turn: the value of an expedited answer (up to four bytes, little
    /// endian), `None` for an abort or an answer that does not carry the value.
    pub answers: Vec<Option<u32>>,
    /// Until when answers were counted: the last request's window.
    pub counted_until: Instant,
}

impl Asked {
    /// Fewer answers than requests: a request or its answer was lost on the way (a node
    /// that is only slow answers each one).
    pub fn lost_frames(&self) -> bool {
        self.answers.len() < usize::from(self.requests)
    }
}

/// What a bus showed by itself during a session, kept by the bus as frames pass.
#[derive(Clone, Debug, Default)]
pub struct Observed {
    /// The node-ids seen in use, with what showed each one.
    pub nodes: BTreeMap<u8, BTreeSet<SeenBy>>,
    /// The last NMT state each node reported (heartbeat or guarding answer).
    pub states: BTreeMap<u8, nmt::State>,
    /// The nodes whose boot-up message was seen.
    pub boot_ups: BTreeSet<u8>,
    /// How many data frames were received, of any kind: a bus that showed some is not
    /// silent, whoever sent them.
    pub frames: usize,
    /// The reads that were answered in the last batch that counts its answers
    /// ([`SdoOptions::ask_again_after`](super::SdoOptions::ask_again_after)), by node and
    /// object: how many requests went, and every answer that came.
    pub answers_counted: BTreeMap<(u8, ObjAddr), Asked>,
    /// Every NMT state each node's heartbeats and guarding answers showed since it was last
    /// emptied, each once: two at a time are two devices on one node-id (at most four
    /// states a node).
    pub states_heard: BTreeMap<u8, Vec<nmt::State>>,
    /// LSS slave answers (0x7E4, 8 bytes) that came outside an exchange waiting for them,
    /// oldest first; `take_lss_answers` empties it.
    lss_answers: Vec<[u8; 8]>,
}

impl Observed {
    /// Note what `f` says. `guarding`: the error-control id a remote request is waiting an
    /// answer on; `in_exchange`: whether an LSS exchange is collecting answers itself.
    pub(crate) fn on_frame(&mut self, f: &Frame, guarding: Option<u16>, in_exchange: bool) {
        if f.is_remote() {
            return;
        }
        self.frames += 1;
        let id = f.id();
        if (0x581..=0x5FF).contains(&id) && f.len() == 8 {
            self.seen((id - 0x580) as u8, SeenBy::Sdo);
        }
        if let Some((node, ec)) = ErrorControl::parse(f) {
            if let Some(state) = ec.state() {
                self.states.insert(node, state);
            }
            match ec {
                ErrorControl::BootUp => {
                    self.boot_ups.insert(node);
                    self.seen(node, SeenBy::BootUp);
                }
                ErrorControl::State { state, .. } => {
                    let how = if guarding == Some(id) { SeenBy::Guarding } else { SeenBy::Heartbeat };
                    self.seen(node, how);
                    let heard = self.states_heard.entry(node).or_default();
                    if !heard.contains(&state) {
                        heard.push(state);
                    }
                }
                ErrorControl::Unknown(_) => {}
            }
        }
        if id == lss::SLAVE_COB && f.len() == 8 {
            let d: [u8; 8] = f.data().try_into().expect("8 bytes");
            if let Some(lss::Response::InquiredValue { inquiry: lss::Inquiry::NodeId, value }) =
                lss::Response::decode(&d)
            {
                if (1..=127).contains(&value) {
                    self.seen(value as u8, SeenBy::LssInquiry);
                }
            }
            if !in_exchange && self.lss_answers.len() < MAX_LSS_ANSWERS {
                self.lss_answers.push(d);
            }
        }
    }

    fn seen(&mut self, node: u8, how: SeenBy) {
        self.nodes.entry(node).or_default().insert(how);
    }

    /// Every node-id seen in use, however.
    pub fn node_ids(&self) -> BTreeSet<u8> {
        self.nodes.keys().copied().collect()
    }

    /// The stray LSS answers since the last call.
    pub fn take_lss_answers(&mut self) -> Vec<[u8; 8]> {
        std::mem::take(&mut self.lss_answers)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_of_frame_names_its_node() {
        let mut o = Observed::default();
        o.on_frame(&Frame::new(0x585, &[0x43, 0, 0x10, 0, 0x92, 1, 0x02, 0]), None, false);
        // A Stopped node's heartbeat (state 4): it answers no SDO, yet its id is taken.
        o.on_frame(&Frame::new(0x707, &[0x04]), None, false);
        o.on_frame(&Frame::new(0x709, &[0x00]), None, false);
        o.on_frame(&Frame::new(0x70A, &[0x85]), Some(0x70A), false);
        o.on_frame(&Frame::new(lss::SLAVE_COB, &[0x5E, 12, 0, 0, 0, 0, 0, 0]), None, true);
        // Not node-ids: an unconfigured device's inquiry answer, a short SDO frame, an RTR.
        o.on_frame(&Frame::new(lss::SLAVE_COB, &[0x5E, 0xFF, 0, 0, 0, 0, 0, 0]), None, true);
        o.on_frame(&Frame::new(0x590, &[0x43, 0]), None, false);
        o.on_frame(&Frame::remote(0x711, 1), None, false);
        assert_eq!(o.node_ids().into_iter().collect::<Vec<_>>(), [5, 7, 9, 10, 12]);
        assert_eq!(o.nodes[&7], BTreeSet::from([SeenBy::Heartbeat]));
        assert_eq!(o.nodes[&9], BTreeSet::from([SeenBy::BootUp]));
        assert_eq!(o.nodes[&10], BTreeSet::from([SeenBy::Guarding]));
        assert_eq!(o.nodes[&12], BTreeSet::from([SeenBy::LssInquiry]));
        assert_eq!(o.states[&7], nmt::State::Stopped);
        assert_eq!(o.states[&10], nmt::State::Operational);
        assert!(o.boot_ups.contains(&9));
        // Answers an exchange collected itself are not strays.
        assert!(o.take_lss_answers().is_empty());
    }

    #[test]
    fn stray_lss_answers_are_kept_bounded() {
        let mut o = Observed::default();
        for _ in 0..5000 {
            o.on_frame(&Frame::new(lss::SLAVE_COB, &[0x50, 0, 0, 0, 0, 0, 0, 0]), None, false);
        }
        o.on_frame(&Frame::new(lss::SLAVE_COB, &[0x50]), None, false);
        assert_eq!(o.take_lss_answers().len(), MAX_LSS_ANSWERS);
        assert!(o.take_lss_answers().is_empty());
    }
}
