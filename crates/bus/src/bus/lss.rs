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
    /// flooding the LSS answer id with a counter does not. Silence after an answer confirms
    /// nothing: nothing sent since the answer sends a device back, so the one that answered
    /// is still in configuration state, missing the inquiries now (the switch is sent again).
    fn nobody_configuring(&mut self) -> Result<bool> {
        let (mut heard, mut silences) = (Vec::new(), 0);
        for _ in 0..4 {
            let ids = self.node_ids_inquired()?;
            if ids.is_empty() {
                if !heard.is_empty() {
                    return Ok(false);
                }
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

#[cfg(test)]
mod tests {
    //! The confirmed switch back to waiting, on virtual time, against one device that misses
    //! the LSS requests the test numbers (a receive queue overrun): a device really can.

    use super::*;
    use crate::bus::timeline::Timeline;
    use crate::bus::{FrameLink, Master};
    use crate::canopen::lss::{Slave, SlaveCaps, SlaveState, MASTER_COB, SLAVE_COB};
    use crate::frame::Frame;
    use std::time::Instant;

    /// One LSS slave with node-id 10 that does not hear the requests numbered (from 1) in
    /// `missed`; it answers 1 ms after a request.
    struct Device {
        slave: Slave,
        missed: Vec<usize>,
        heard: usize,
        time: Timeline,
    }

    impl FrameLink for Device {
        fn send(&mut self, frame: &Frame) -> Result<()> {
            let Some(req) = Request::decode(frame.data()).filter(|_| frame.id() == MASTER_COB) else { return Ok(()) };
            self.heard += 1;
            if self.missed.contains(&self.heard) {
                return Ok(());
            }
            if let (Some(answer), _) = self.slave.handle(req, 10) {
                self.time.arrive(self.time.now + Duration::from_millis(1), Frame::new(SLAVE_COB, &answer.encode()));
            }
            Ok(())
        }
        fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
            Ok(self.time.recv(deadline))
        }
        fn name(&self) -> String {
            "test".into()
        }
        fn now(&self) -> Instant {
            self.time.now
        }
        fn sleep_until(&mut self, t: Instant) -> Result<()> {
            self.time.sleep_until(t);
            Ok(())
        }
    }

    fn device(missed: &[usize]) -> Master<Device> {
        let identity = Identity { vendor: 0x444, product: 0x2057, revision: 0x10000, serial: 0x1F4A };
        let caps = SlaveCaps { store: true, bit_timing: true, fastscan_in_configuration: false };
        let slave = Slave::new(identity, caps);
        let link = Device { slave, missed: missed.to_vec(), heard: 0, time: Timeline::starting_now() };
        Master::new(link, "test".into())
    }

    /// Every device into configuration state (request 1), then back: whether `leave` said
    /// so, and the device's state after it.
    fn enter_and_leave(missed: &[usize]) -> (Result<()>, SlaveState) {
        let mut bus = device(missed);
        let mut m = LssMaster::new(&mut bus, Duration::from_millis(100));
        m.enter(None).unwrap();
        let left = m.leave();
        (left, bus.link_mut().slave.state)
    }

    /// Found by the DST (network set-baud, a device missing one frame in ten): the device
    /// missed the switch back (request 2), answered the first inquiry (3), missed the next
    /// two (4, 5). That silence came after its answer, when nothing sent could have sent it
    /// back: it was taken for the switch confirmed, and the device stayed in configuration
    /// state under a success. The switch goes again until silence follows it.
    #[test]
    fn silence_after_an_answer_does_not_confirm_the_switch_back() {
        let (left, state) = enter_and_leave(&[2, 4, 5]);
        left.unwrap();
        assert_eq!(state, SlaveState::Waiting);
    }

    /// Silence before any answer is the switch heard: one missed inquiry is allowed.
    #[test]
    fn two_unanswered_inquiries_confirm_the_switch_back() {
        let (left, state) = enter_and_leave(&[3]);
        left.unwrap();
        assert_eq!(state, SlaveState::Waiting);
    }

    /// A device that misses every switch back, answering some inquiries and missing others,
    /// is never reported gone: the error says it stayed.
    #[test]
    fn a_device_missing_every_switch_back_is_said_to_stay() {
        // Each try: the switch, an answer, then silence (the old rule's confirmation).
        let (left, state) = enter_and_leave(&[2, 4, 5, 6, 8, 9, 10, 12, 13]);
        assert!(matches!(left, Err(Error::LssLeftInConfiguration { tries: 3 })), "{left:?}");
        assert_eq!(state, SlaveState::Configuration);
    }
}
