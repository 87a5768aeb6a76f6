//! One check's verdict, the same for `health` and `network check`: what was checked,
//! whether it passed, and what was found, typed (the front end words it).

use super::clash::Clash;
use super::config::report::Difference;
use super::nmt::StateFrom;
use super::node::{hex16, IdentityPart};
use crate::canopen::{cia402, nmt};
use crate::ops::failure::Failure;
use crate::ops::values::as_text;
use serde::Serialize;

/// One check of one node: `present`, `identity`, `objects`, `state`, `error register`...
#[derive(Debug, Serialize)]
pub struct Verdict {
    /// What was checked.
    pub check: &'static str,
    /// Whether it passed.
    pub ok: bool,
    /// What was found (a front end words it, in JSON too).
    pub detail: Finding,
    /// What the user can do about it, for the front end to word after the detail (in JSON
    /// too: a front end serialises the detail with it).
    #[serde(skip)]
    pub remedy: Option<Remedy>,
    /// For `objects`: each writable object that differs.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub differences: Vec<Difference>,
}

impl Verdict {
    /// A verdict with no object differences.
    pub fn new(check: &'static str, ok: bool, detail: Finding) -> Verdict {
        Verdict { check, ok, detail, remedy: None, differences: Vec::new() }
    }

    /// This verdict with `remedy` to follow its detail.
    pub fn with_remedy(self, remedy: Option<Remedy>) -> Verdict {
        Verdict { remedy, ..self }
    }
}

/// What the user can do about a check's finding, for the front end to word after it: what
/// the check knew and its finding does not say (the node's state, the history's count).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Remedy {
    /// The node answers no SDO, as a Stopped node does: put it in Pre-operational.
    PreOperational {
        /// The node-id.
        node: u8,
    },
    /// The node logged errors in its history (0x1003): read them, with their meanings.
    ReadErrorHistory {
        /// The node-id.
        node: u8,
    },
}

/// What a check found: the numbers, states and names its sentence needs.
#[derive(Debug, Serialize)]
#[serde(tag = "finding", rename_all = "snake_case")]
pub enum Finding {
    // `health`.
    /// `sdo`: the last scan saw the node; now it shows nothing: no answer to the probe, no
    /// heartbeat, and no answer to node guarding (`from`: or guarding could not be asked).
    Gone {
        /// What was asked and not answered.
        from: StateFrom,
    },
    /// `sdo`: the node answered none of the scan's probes, though the bus shows it is there.
    SilentToSdo {
        /// How the bus showed it.
        from: StateFrom,
    },
    /// `nmt`: no state seen, and none can be asked on this link (no heartbeat, and no
    /// remote frames for node guarding): not a failure of the node.
    StateNotCheckable {
        /// Why not.
        from: StateFrom,
    },
    /// `nmt`: no state seen.
    StateUnknown {
        /// Why not.
        from: StateFrom,
    },
    /// `nmt`: the node's state (the one expected, or none was).
    State {
        /// Its state.
        state: nmt::State,
        /// How it was learned.
        from: StateFrom,
    },
    /// `nmt`: the node is not in the state expected.
    WrongState {
        /// Its state.
        state: nmt::State,
        /// How it was learned.
        from: StateFrom,
        /// The state expected.
        want: nmt::State,
    },
    /// `heartbeat`: the node has no 0x1017.
    NoHeartbeatObject,
    /// `heartbeat`: 0x1017 is 0, no heartbeat produced.
    HeartbeatOff,
    /// `heartbeat`: produced, but not watched (the link shows no traffic).
    HeartbeatUnwatched {
        /// 0x1017, in ms.
        period_ms: u16,
    },
    /// `heartbeat`: produced, but none came during the watch.
    HeartbeatMissing {
        /// 0x1017, in ms.
        period_ms: u16,
        /// How long the bus was watched, in ms.
        watched_ms: u64,
    },
    /// `heartbeat`: beats came, but too far apart.
    HeartbeatLate {
        /// 0x1017, in ms.
        period_ms: u16,
        /// The longest time without a beat, in ms.
        longest_gap_ms: u64,
        /// How many beats came.
        beats: usize,
        /// How long the bus was watched, in ms.
        watched_ms: u64,
    },
    /// `heartbeat`: every beat on time.
    HeartbeatOnTime {
        /// 0x1017, in ms.
        period_ms: u16,
        /// How many beats came.
        beats: usize,
        /// How long the bus was watched, in ms.
        watched_ms: u64,
    },
    /// `error register`: 0x1001 could not be read.
    RegisterUnread {
        /// Why.
        #[serde(serialize_with = "as_text")]
        error: Failure,
    },
    /// `error register`: 0x1001 answered with no data.
    RegisterEmpty,
    /// `error register`: 0x1001 (0: no error), and what 0x1003 says.
    Register {
        /// 0x1001.
        register: u8,
        /// The error history's count.
        logged: Logged,
    },
    /// `emcy`: not watched (the link shows no traffic).
    EmcyUnwatched,
    /// `emcy`: none during the watch.
    NoEmcy {
        /// How long the bus was watched, in ms.
        watched_ms: u64,
    },
    /// `emcy`: the EMCYs seen during the watch.
    Emcys {
        /// Each, in turn.
        seen: Vec<SeenEmcy>,
    },
    /// `drive`: the statusword 0x6041 could not be read.
    StatuswordUnread {
        /// Why.
        #[serde(serialize_with = "as_text")]
        error: Failure,
    },
    /// `drive`: 0x6041 answered with too few bytes.
    StatuswordShort,
    /// `drive`: the statusword codes no CiA 402 state.
    NoDriveState {
        /// 0x6041.
        statusword: u16,
    },
    /// `drive`: the CiA 402 state the statusword codes.
    Drive {
        /// The state.
        state: cia402::State,
        /// 0x6041.
        statusword: u16,
        /// Whether its warning bit is set.
        warning: bool,
    },
    /// `node-id`: more than one device answers to the node-id.
    NodeIdClash {
        /// What showed it.
        clash: Clash,
    },

    // `network check`.
    /// `present`: the listed node answered a probe.
    Answered {
        /// The node-id.
        node: u8,
    },
    /// `present`: the listed node beats its heartbeat but answered no SDO probe.
    SilentListed {
        /// The node-id.
        node: u8,
        /// The state its heartbeat shows.
        state: nmt::State,
        /// How many rounds of probes went out.
        rounds: usize,
        /// How long each waited, in ms.
        window_ms: u64,
    },
    /// `present`: the listed node answered none of the probes.
    Absent {
        /// The node-id.
        node: u8,
        /// How many rounds of probes went out.
        rounds: usize,
        /// How long each waited, in ms.
        window_ms: u64,
    },
    /// `identity`: the device's identity matches the parts its DCF names.
    IdentityMatches {
        /// The parts compared.
        parts: Vec<IdentityPart>,
    },
    /// `identity`: the DCF names no vendor-ID or product code.
    IdentityUnnamed {
        /// The DCF, as the project names it.
        file: String,
    },
    /// `identity`: another device than the DCF's.
    IdentityDiffers {
        /// The parts that differ.
        differ: Vec<IdentityPart>,
        /// The DCF, as the project names it.
        file: String,
    },
    /// `objects`: every writable object as in the DCF.
    ObjectsMatch {
        /// The DCF, as the project names it.
        file: String,
    },
    /// `objects`: the writable objects in the verdict's `differences` differ from the DCF.
    ObjectsDiffer {
        /// The DCF, as the project names it.
        file: String,
    },
    /// `state`: the node's NMT state, against the one expected.
    NetworkState {
        /// Its state.
        state: nmt::State,
        /// How it was learned.
        #[serde(serialize_with = "as_text")]
        from: super::nmt::StateFrom,
        /// The state expected.
        want: nmt::State,
    },
    /// `state`: no heartbeat seen and no answer to node guarding.
    NoNetworkState {
        /// The state expected.
        want: nmt::State,
    },
}

/// What the error history (0x1003:0) says, alongside the error register.
#[derive(Debug, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Logged {
    /// 0x1003:0 answered with no data.
    Unsaid,
    /// No errors logged.
    Nothing,
    /// This many errors logged.
    Count(u8),
    /// The node keeps no error history (no 0x1003).
    NoHistory,
    /// 0x1003:0 could not be read.
    Unread(#[serde(serialize_with = "as_text")] Failure),
}

/// One EMCY the node sent during the watch.
#[derive(Clone, Debug, Serialize)]
pub struct SeenEmcy {
    /// Its error code (CiA 301).
    #[serde(serialize_with = "hex16")]
    pub code: u16,
    /// Its error register byte.
    pub register: u8,
    /// What the error code means, in words.
    pub meaning: &'static str,
}
