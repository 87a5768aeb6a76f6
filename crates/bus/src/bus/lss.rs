//! LSS master procedures over any `Bus` (CiA 305): the I/O driving of the `lss` commands'
//! sequences, with the waiting each step needs. What the answers mean, and what is done
//! when they go missing or come late, is `canopen::lss` (its `sequences` and `policy`).

use super::{Bus, LssWait};
use crate::canopen::lss::{
    self, Configured, Fastscan, FastscanError, FastscanNext, Identity, Inquiry, Pace, Request, Response,
};
use crate::error::{Error, Result};
use std::collections::BTreeSet;
use std::time::Duration;

/// A device `assign` gave a node-id.
pub struct Assigned {
    /// Its LSS address (vendor, product, revision, serial).
    pub identity: Identity,
    /// The node-id it was given.
    pub node: u8,
    /// Whether "store configuration" succeeded; why not when it did not.
    pub stored: std::result::Result<(), NotStored>,
}

/// Why a device `assign` numbered does not keep its node-id across a power cycle, or may not.
#[derive(Debug)]
#[non_exhaustive]
pub enum NotStored {
    /// The store was not asked for.
    NotAsked,
    /// "store configuration" went unanswered: sent once (an action), and LSS has no way to
    /// read it back, so whether `node` keeps its id is unknown; storing again by its
    /// `identity` settles it.
    NoAnswer {
        /// The node-id it was given.
        node: u8,
        /// The device, to address it again.
        identity: Identity,
    },
    /// The device refused the store, or the bus failed.
    Failed(Error),
}

impl std::fmt::Display for NotStored {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NotStored::NotAsked => f.write_str("not asked"),
            NotStored::NoAnswer { node, .. } => {
                write!(f, "no answer to the store: unknown whether node {node} keeps its id across a power cycle")
            }
            NotStored::Failed(e) => write!(f, "{e}"),
        }
    }
}

/// Why `assign` stopped before every device had a node-id.
pub enum AssignFailure {
    /// No device could be found, or a fastscan went wrong.
    Fastscan(FastscanError),
    /// A device refused the node-id, or the bus failed.
    Refused(Error),
}

/// What `assign` did: the devices it gave node-ids, the fastscan steps it took, and why it stopped
/// early, if it did.
pub struct AssignOutcome {
    /// The devices given node-ids, in order.
    pub assigned: Vec<Assigned>,
    /// Fastscan requests sent, in all.
    pub steps: u32,
    /// Why it stopped before every device had a node-id; `None` when none was left.
    pub failure: Option<AssignFailure>,
    /// The pace learned: the step the fastscans used.
    pub pace: Pace,
    /// Stopped early because `keep_going` said so (an interruption).
    pub interrupted: bool,
}

/// A fastscan's result: the identity found (that device is in configuration state now)
/// or why none, the fastscan requests it took, and the pace it learned.
pub struct FastscanOutcome {
    /// The device's identity, or why none was found.
    pub found: std::result::Result<Identity, FastscanError>,
    /// Fastscan requests sent.
    pub steps: u32,
    /// The pace the fastscan ended at, for the next one to start from.
    pub pace: Pace,
    /// Another device answered as being in configuration state too ([`Fastscan::crowded`]).
    pub crowded: bool,
}

/// LSS through a bus: each confirmed step waits for the first answer, at most the timeout.
pub struct LssMaster<'a> {
    bus: &'a mut dyn Bus,
    timeout: Duration,
    /// A device may be in configuration state by this master's doing (it switched one
    /// there, or a fastscan found one): the switch back must then be confirmed.
    configuring: bool,
    /// The latest any device answered so far (a fastscan's step counts as such): how long
    /// the silence that confirms the switch back needs to last.
    slowest: Duration,
    /// Switches back to waiting sent so far.
    switches_back: u32,
    /// Each device given a node-id, with `switches_back` as it was then: how often it has
    /// been sent back since, when it is found in configuration state again.
    given: Vec<(Identity, u32)>,
}

impl<'a> LssMaster<'a> {
    /// An LSS master on `bus` that waits at most `timeout` for each confirmed step's answer.
    pub fn new(bus: &'a mut dyn Bus, timeout: Duration) -> LssMaster<'a> {
        LssMaster { bus, timeout, configuring: false, slowest: Duration::ZERO, switches_back: 0, given: Vec::new() }
    }

    /// The bus underneath, for the frames LSS does not cover.
    pub fn bus(&mut self) -> &mut dyn Bus {
        self.bus
    }

    /// Sends `req` without waiting for an answer (an unconfirmed service).
    pub fn send(&mut self, req: Request) -> Result<()> {
        self.bus.lss_exchange(&req.encode(), 0, Duration::ZERO, LssWait::Nothing).map(|_| ())
    }

    /// A request and the answers with the command specifier it expects.
    pub fn ask(&mut self, req: Request, collect: LssWait) -> Result<Vec<Response>> {
        self.ask_within(req, collect, self.timeout)
    }

    /// [`ask`](Self::ask), waiting `window` for the answers.
    fn ask_within(&mut self, req: Request, collect: LssWait, window: Duration) -> Result<Vec<Response>> {
        let expect = req.expected_answer().expect("a confirmed LSS service");
        let answers = self.bus.lss_exchange(&req.encode(), expect, window, collect)?;
        self.slowest = answers.iter().map(|a| a.after).fold(self.slowest, Duration::max);
        Ok(answers.iter().filter_map(|a| Response::decode(&a.data)).collect())
    }

    /// Put one device (by identity) or every device (`None`) into configuration state.
    pub fn enter(&mut self, identity: Option<&Identity>) -> Result<()> {
        self.configuring = true;
        match identity {
            Some(id) => {
                let [a, b, c, d] = lss::switch_selective(id);
                for r in [a, b, c] {
                    self.send(r)?;
                }
                if !self.ask(d, LssWait::First)?.contains(&Response::SwitchSelectiveAck) {
                    return Err(Error::NoLssAnswer {
                        request: "the selective switch".into(),
                        identity: Some(*id),
                        waited: self.timeout,
                    });
                }
                Ok(())
            }
            None => self.send(Request::SwitchGlobal { configuration: true }),
        }
    }

    /// Switches every device back to waiting state, and makes sure they went. The switch is
    /// unconfirmed (no device answers it) and may be missed; a device left in
    /// configuration state answers the next master's services, and takes the next node-id
    /// given. Sent again until nobody answers "inquire node-id" (only devices in
    /// configuration state do), a bounded number of times.
    /// When this master put no device there, the switch is sent once: there is nothing
    /// to confirm (and a device flooding the LSS answer id must not stop the command).
    pub fn leave(&mut self) -> Result<()> {
        if !self.configuring {
            return self.switch_to_waiting();
        }
        match self.switched_back(None)? {
            true => Ok(()),
            false => Err(Error::LssLeftInConfiguration { tries: lss::REPEATS + 1 }),
        }
    }

    /// Send the switch back to waiting until it is confirmed, at most [`lss::REPEATS`] + 1
    /// times: nobody answers "inquire node-id" ([`Self::nobody_configuring`]), or, sooner,
    /// the boot-up of `booting` is heard (a device just given that node-id). Whether it was.
    fn switched_back(&mut self, booting: Option<u8>) -> Result<bool> {
        for _ in 0..=lss::REPEATS {
            if let Some(node) = booting {
                self.bus.observed().boot_ups.remove(&node);
            }
            self.switch_to_waiting()?;
            let booted = match booting {
                Some(node) => self.boots_as(node)?,
                None => false,
            };
            if booted || self.nobody_configuring()? {
                self.configuring = false;
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// "switch state global: waiting", once.
    fn switch_to_waiting(&mut self) -> Result<()> {
        self.switches_back += 1;
        self.send(Request::SwitchGlobal { configuration: false })
    }

    /// How many switches back to waiting went out since `identity` was first given a
    /// node-id (all of them when it never was).
    fn sent_back_since_given(&self, identity: Identity) -> u32 {
        let given = self.given.iter().find(|(id, _)| *id == identity).map_or(0, |(_, at)| *at);
        self.switches_back - given
    }

    /// Whether no device is in configuration state: two inquiries in a row go unanswered
    /// ("inquire node-id"; a device that missed the switch may miss one inquiry too), or the
    /// answers are not a device's: a device answers with the same node-id again, a device
    /// flooding the LSS answer id with a counter does not.
    fn nobody_configuring(&mut self) -> Result<bool> {
        let (mut heard, mut silences) = (Vec::new(), 0);
        for _ in 0..4 {
            let ids = self.node_ids_inquired()?;
            if ids.is_empty() {
                silences += 1;
                if silences == 2 {
                    return Ok(true);
                }
                continue;
            }
            if ids.iter().any(|n| heard.contains(n)) {
                return Ok(false);
            }
            heard.extend(ids);
            silences = 0;
        }
        Ok(true)
    }

    /// The node-ids the devices in configuration state answer "inquire node-id" with,
    /// within three times the latest answer seen so far (the timeout before any).
    fn node_ids_inquired(&mut self) -> Result<Vec<u32>> {
        let window = match self.slowest.is_zero() {
            true => self.timeout,
            false => (self.slowest * 3).clamp(lss::STEP_FLOOR, self.timeout),
        };
        let answers = self.ask_within(Request::Inquire(Inquiry::NodeId), LssWait::All, window)?;
        Ok(answers
            .iter()
            .filter_map(|a| match a {
                Response::InquiredValue { inquiry: Inquiry::NodeId, value } => Some(*value),
                _ => None,
            })
            .collect())
    }

    /// A confirmed configuration service; every answer must report success.
    pub fn configure(&mut self, req: Request, what: &str, global: bool) -> Result<usize> {
        let answers = self.ask(req, if global { LssWait::All } else { LssWait::First })?;
        match lss::configured(&answers) {
            Configured::Done(n) => Ok(n),
            Configured::Refused { cs, error, specific } => {
                Err(Error::LssRefused { service: what.into(), cs, error, specific })
            }
            Configured::Unanswered => {
                Err(Error::NoLssAnswer { request: what.into(), identity: None, waited: self.timeout })
            }
        }
    }

    /// Find one device without a node-id, at `pace` (learned as it goes), skipping the
    /// identity parts in `given`. `keep_going` is asked before each request: when it says
    /// no, the search ends with `None`.
    pub fn fastscan(
        &mut self,
        pace: Pace,
        given: [Option<u32>; 4],
        keep_going: &mut dyn FnMut() -> bool,
    ) -> Result<Option<FastscanOutcome>> {
        let mut scan = Fastscan::new(pace, given);
        // Strays from before this search say nothing of its requests.
        self.bus.observed().take_lss_answers();
        let mut asked = false;
        loop {
            let found = match scan.next() {
                FastscanNext::Send(ask) => {
                    if !keep_going() {
                        return Ok(None);
                    }
                    // The search starts again (a confirmation went unanswered): the device
                    // it was about may have gone into configuration state all the same, its
                    // answer lost. Back to waiting with the others, or it would take the
                    // node-id meant for the next device found.
                    if asked && matches!(ask.request, Request::Fastscan { bit_checked: lss::FASTSCAN_RESET, .. }) {
                        self.switch_to_waiting()?;
                    }
                    asked = true;
                    let collect = ask.settle.map_or(LssWait::All, LssWait::Settle);
                    let answers = self.bus.lss_exchange(&ask.request.encode(), ask.expect, ask.window, collect)?;
                    let answers: Vec<(Duration, [u8; 8])> = answers.iter().map(|a| (a.after, a.data)).collect();
                    // Drained before this request went out: answers to the one before, late.
                    scan.on_strays(&self.bus.observed().take_lss_answers());
                    scan.on_answers(&answers);
                    continue;
                }
                FastscanNext::Found(id) => Ok(id),
                FastscanNext::Failed(e) => Err(e),
            };
            // Unless nobody took part, a device may be in configuration state now.
            self.configuring |= !matches!(found, Err(FastscanError::NoDevice));
            self.slowest = self.slowest.max(scan.pace().step());
            let (steps, crowded) = (scan.steps(), scan.crowded());
            return Ok(Some(FastscanOutcome { found, steps, pace: scan.into_pace(), crowded }));
        }
    }
}

/// How many devices without a node-id answer "identify non-configured remote slave".
pub fn count_unconfigured(bus: &mut dyn Bus, wait: Duration) -> Result<usize> {
    let answers = bus.lss_exchange(&Request::IdentifyNonConfigured.encode(), 0x50, wait, LssWait::All)?;
    Ok(answers.len())
}

/// Answers "I have no node-id" among these.
pub fn count_non_configured(answers: &[[u8; 8]]) -> usize {
    answers.iter().filter(|a| Response::decode(*a) == Some(Response::IdentifyNonConfiguredSlave)).count()
}

impl LssMaster<'_> {
    /// Give every device without a node-id the next node-id from `start` on that is not in
    /// `used`: fastscan finds one (leaving it in configuration state), it gets its node-id
    /// and, with `store`, keeps it; back in waiting state it boots and leaves the search.
    /// Whatever ends it, every device is sent back to waiting state.
    #[allow(clippy::too_many_arguments)]
    pub fn assign(
        &mut self,
        start: u8,
        used: BTreeSet<u8>,
        pace: Pace,
        given: [Option<u32>; 4],
        store: bool,
        keep_going: &mut dyn FnMut() -> bool,
        each: &mut dyn FnMut(&Assigned),
    ) -> Result<AssignOutcome> {
        let mut out =
            AssignOutcome { assigned: Vec::new(), steps: 0, failure: None, pace: pace.clone(), interrupted: false };
        let result = self.assign_each(start, used, given, store, keep_going, each, &mut out);
        // A failure, a lost link or an interruption must not leave a device in
        // configuration state, where it would answer the next master's services.
        let left = self.leave();
        result?;
        if let (Err(e), None) = (left, &out.failure) {
            out.failure = Some(AssignFailure::Refused(e));
        }
        Ok(out)
    }

    /// Give the device in configuration state (`identity`) `node`. Setting a value twice
    /// does no harm, so an answer lost on the way is asked for again (a bounded number of
    /// times). Never answered, the request may still have reached it: it may hold `node`.
    fn set_id(&mut self, identity: Identity, node: u8) -> Result<usize> {
        let mut tries = 0;
        loop {
            match self.configure(Request::ConfigureNodeId(node), "set-id", false) {
                Err(Error::NoLssAnswer { .. }) if tries < lss::REPEATS => tries += 1,
                Err(Error::NoLssAnswer { waited, .. }) => {
                    return Err(Error::LssSetIdUnknown { identity, node, tries: tries + 1, waited })
                }
                done => return done,
            }
        }
    }

    /// [`leave`](Self::leave) after `node` was given to `identity`: a device left in
    /// configuration state would take the node-id meant for the next device found (two
    /// devices on one id), or, where it takes part in fastscan there (durand), be found and
    /// numbered again. Its boot-up with `node` says it went, sooner than the silence.
    pub fn back_to_waiting(&mut self, identity: Identity, node: u8) -> Result<()> {
        if !self.given.iter().any(|(id, _)| *id == identity) {
            self.given.push((identity, self.switches_back));
        }
        match self.switched_back(Some(node))? {
            true => Ok(()),
            false => Err(Error::LssStillConfiguring { identity, node, tries: self.sent_back_since_given(identity) }),
        }
    }

    /// Whether the boot-up of `node` is heard within the timeout (a device may beat its
    /// heartbeat with the new node-id before it has left configuration state). A bus that
    /// passes on only answers (an EPOS2 gateway) shows no boot-up.
    fn boots_as(&mut self, node: u8) -> Result<bool> {
        if !self.bus.sees_traffic() {
            return Ok(false);
        }
        let end = self.bus.now() + self.timeout;
        loop {
            if self.bus.observed().boot_ups.contains(&node) {
                return Ok(true);
            }
            if self.bus.recv_frame(end)?.is_none() {
                return Ok(false);
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn assign_each(
        &mut self,
        start: u8,
        mut used: BTreeSet<u8>,
        given: [Option<u32>; 4],
        store: bool,
        keep_going: &mut dyn FnMut() -> bool,
        each: &mut dyn FnMut(&Assigned),
        out: &mut AssignOutcome,
    ) -> Result<()> {
        // Searches in a row that found nobody: one lost answer must not be taken for "every
        // device has a node-id" (exit 0), so silence is believed only when it repeats.
        let mut silent = 0;
        let (mut found_again, mut crowded) = (0, 0);
        loop {
            let Some(scan) = self.fastscan(out.pace.clone(), given, keep_going)? else {
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
                Err(e) => {
                    out.failure = Some(AssignFailure::Fastscan(e));
                    return Ok(());
                }
            };
            silent = 0;
            // Another device is in configuration state with it (it missed a switch back):
            // a set-id now would give both one node-id. Everyone back, and search again.
            if scan.crowded {
                crowded += 1;
                if crowded > lss::REPEATS {
                    out.failure = Some(AssignFailure::Refused(Error::LssCrowded { identity, times: crowded }));
                    return Ok(());
                }
                if let Err(e) = self.leave() {
                    out.failure = Some(AssignFailure::Refused(e));
                    return Ok(());
                }
                continue;
            }
            // Found again: the device numbered before did not leave configuration state
            // (the switches back were lost, or its answers to the inquiry). It is the same
            // device: it gets its node-id again, is sent back, and is reported once.
            if let Some(first) = out.assigned.iter().find(|d| d.identity == identity).map(|d| d.node) {
                found_again += 1;
                let again = match found_again > lss::REPEATS {
                    true => {
                        let tries = self.sent_back_since_given(identity);
                        Err(Error::LssStillConfiguring { identity, node: first, tries })
                    }
                    false => self.set_id(identity, first).and_then(|_| self.back_to_waiting(identity, first)),
                };
                if let Err(e) = again {
                    out.failure = Some(AssignFailure::Refused(e));
                    return Ok(());
                }
                continue;
            }
            // Ids seen meanwhile (a heartbeat, a boot-up) are taken too.
            used.extend(self.bus.observed().node_ids());
            let Some(node) = (start..=127).find(|n| !used.contains(n)) else {
                let e = Error::NoFreeNodeId { start, identity };
                out.failure = Some(AssignFailure::Refused(e));
                return Ok(());
            };
            if let Err(e) = self.set_id(identity, node) {
                out.failure = Some(AssignFailure::Refused(e));
                return Ok(());
            }
            // An action: never sent twice blindly, and LSS has no way to read it back, so a
            // lost answer leaves it unknown, and the report says so.
            let stored = if store {
                self.configure(Request::StoreConfiguration, "store", false).map(|_| ()).map_err(|e| match e {
                    Error::NoLssAnswer { .. } => NotStored::NoAnswer { node, identity },
                    e => NotStored::Failed(e),
                })
            } else {
                Err(NotStored::NotAsked)
            };
            used.insert(node);
            let done = Assigned { identity, node, stored };
            if let Err(e) = self.back_to_waiting(identity, node) {
                each(&done);
                out.assigned.push(done);
                out.failure = Some(AssignFailure::Refused(e));
                return Ok(());
            }
            each(&done);
            out.assigned.push(done);
        }
    }
}
