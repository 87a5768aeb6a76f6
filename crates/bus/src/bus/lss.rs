//! The LSS master over any `Bus` (CiA 305): the I/O driving of its services' sequences
//! (switching, configuring, inquiring, fastscan, the confirmed switch back to waiting), with
//! the waiting each step needs; numbering every device (`assign`) is canctl's procedure on it. What the answers mean, and what is done
//! when they go missing or come late, is `canopen::lss` (its `sequences` and `policy`).

use super::api::{Bus, LssWait};
use crate::canopen::lss::{
    self, Configured, Fastscan, FastscanError, FastscanNext, Identity, Inquiry, Pace, Request, Response,
};
use crate::error::{Error, Result};
use std::time::Duration;

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
                    let (request, identity) = ("the selective switch".into(), Some(*id));
                    return Err(Error::NoLssAnswer { request, identity, waited: self.timeout });
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
        self.switched_back(None)?.then_some(()).ok_or(Error::LssLeftInConfiguration { tries: lss::REPEATS + 1 })
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
            let booted = booting.map(|node| self.boots_as(node)).transpose()?.unwrap_or(false);
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
    pub fn sent_back_since_given(&self, identity: Identity) -> u32 {
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

    /// Whether another device is in configuration state beside the one just selected (it
    /// missed its switch back to waiting): more than one answer to "inquire node-id", asked
    /// twice, as a device that missed a switch may miss one inquiry too. A node-id given now
    /// would be taken by both.
    pub fn others_configuring(&mut self) -> Result<bool> {
        for _ in 0..2 {
            if self.node_ids_inquired()?.len() > 1 {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// The node-ids the devices in configuration state answer "inquire node-id" with,
    /// within three times the latest answer seen so far (the timeout before any).
    fn node_ids_inquired(&mut self) -> Result<Vec<u32>> {
        let window =
            if self.slowest.is_zero() { self.timeout } else { (self.slowest * 3).clamp(lss::STEP_FLOOR, self.timeout) };
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
    /// identity parts in `given`. Before each request `cancel` is looked at (cancelled, the
    /// search ends with `None`) and `sent` told how many requests this one makes.
    pub fn fastscan(
        &mut self,
        pace: Pace,
        given: [Option<u32>; 4],
        cancel: &crate::cancel::Cancel,
        sent: &mut dyn FnMut(u64),
    ) -> Result<Option<FastscanOutcome>> {
        let mut scan = Fastscan::new(pace, given);
        // Strays from before this search say nothing of its requests.
        self.bus.observed().take_lss_answers();
        let mut asked = 0;
        loop {
            let found = match scan.next() {
                FastscanNext::Send(ask) => {
                    if cancel.is_cancelled() {
                        return Ok(None);
                    }
                    asked += 1;
                    sent(asked);
                    // The search starts again (a confirmation went unanswered): the device
                    // it was about may have gone into configuration state all the same, its
                    // answer lost. Back to waiting with the others, or it would take the
                    // node-id meant for the next device found.
                    if asked > 1 && matches!(ask.request, Request::Fastscan { bit_checked: lss::FASTSCAN_RESET, .. }) {
                        self.switch_to_waiting()?;
                    }
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
    /// Give the device in configuration state (`identity`) `node`. Setting a value twice
    /// does no harm, so an answer lost on the way is asked for again (a bounded number of
    /// times). Never answered, the request may still have reached it: it may hold `node`.
    pub fn set_id(&mut self, identity: Identity, node: u8) -> Result<usize> {
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
        if self.switched_back(Some(node))? {
            return Ok(());
        }
        Err(Error::LssStillConfiguring { identity, node, tries: self.sent_back_since_given(identity) })
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
}
