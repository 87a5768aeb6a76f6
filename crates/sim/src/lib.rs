//! The simulated bus: the demo network's devices behind a `FrameLink`, so every command
//! runs through the same client code as on hardware; on virtual time, with seeded faults and
//! timing; and the device sides of the serial links (an EPOS2, an slcan adapter, each on a
//! pseudo-terminal) and of a socketcand server.
//!
//! Above `canctl-bus` (whose `FrameLink` it is), below canctl's procedures: serving the
//! network as a command does (`canctl sim`) is canctl's `sim::serve`.

// Every public item says what it is for; an item not meant for users is `pub(crate)`.
#![deny(missing_docs)]

// The layers below, under the names the modules use (`crate::bus::...`).
use canctl_bus::{bus, epos2, error, socketcand, trace};
// The slcan adapter's device side is a pseudo-terminal's (Unix).
#[cfg(unix)]
use canctl_bus::slcan;
use canctl_canopen as canopen;
use canctl_canopen::frame;
use canctl_od as od;

pub mod bootloader;
pub mod bridge;
pub(crate) mod cia402_drive;
mod config;
pub(crate) mod device;
pub(crate) mod endless;
pub mod epos2_device;
#[cfg(unix)]
pub mod epos2_serve;
pub(crate) mod faults;
pub mod profiles;
#[cfg(unix)]
pub(crate) mod pty;
pub mod serial_fault;
#[cfg(unix)]
pub mod slcan_serve;
pub mod socketcand_serve;
pub mod state;
pub mod timing;

use crate::bus::FrameLink;
use crate::canopen::lss;
use crate::error::Result;
use crate::frame::Frame;
pub use config::{SimConfig, DEFAULT_BIT_RATE, DEFAULT_SEED, DEFAULT_UNCONFIGURED, MAX_UNCONFIGURED};
use device::Device;
use faults::Conduct;
pub use faults::{bus_off, unmatched, FaultSpec};
use std::collections::VecDeque;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};
use timing::{BusQueue, Latency, Nanos, Origin, Rng};
pub use timing::{BusStats, Profile};

/// How one device's answers are timed: its latency and its own random draws.
struct Pace {
    latency: Latency,
    rng: Rng,
    /// When its last answer is ready: a device answers its requests in order.
    last_ready: Nanos,
}

impl Pace {
    fn new(config: &SimConfig, key: &str) -> Pace {
        let mut rng = Rng::for_device(config.seed, key);
        let latency = config.profile.device_latency(&mut rng);
        Pace { latency, rng, last_ready: 0 }
    }

    /// When an answer to a request heard at `heard` is ready to go.
    fn answer_at(&mut self, heard: Nanos) -> Nanos {
        let ready = (heard + self.latency.draw(&mut self.rng)).max(self.last_ready);
        self.last_ready = ready;
        ready
    }
}

/// The payload of `frame` when it is an SDO request that `d` would answer (an endless
/// fault may answer it instead).
fn endless_request<'f>(d: &Device, frame: &'f Frame) -> Option<(u8, &'f [u8])> {
    let node = d.node_id()?;
    let request = frame.id() == crate::canopen::sdo::request_cob(node) && !frame.is_remote() && frame.len() == 8;
    (request && d.nmt_state() != crate::canopen::nmt::State::Stopped).then(|| (node, frame.data()))
}

/// The devices on one simulated bus.
pub struct Network {
    devices: Vec<Device>,
    paces: Vec<Pace>,
    conducts: Vec<Conduct>,
    config: SimConfig,
    /// The bus's bit rate (CiA 305 table index): devices running at another rate neither
    /// hear nor are heard.
    bit_rate: u8,
    /// The latest ms the devices were told; saved, so that the next invocation's clock
    /// starts after it (see [`Network::resumes_at`]).
    clock_ms: u64,
}

impl Network {
    /// The demo network as `config` describes it.
    pub(crate) fn demo_with(config: SimConfig) -> Network {
        let mut devices = profiles::demo_network_with(config.unconfigured);
        devices.extend(config.bootloader.map(|node| (bootloader::model(true), Some(node))));
        Network::of_with(devices, config)
    }

    /// A network of these devices at the default bit rate and configuration.
    pub fn of(devices: Vec<(profiles::Model, Option<u8>)>) -> Network {
        Network::of_with(devices, SimConfig::default())
    }

    /// A network of these devices, timed as `config` says (its device count is not used).
    pub fn of_with(devices: Vec<(profiles::Model, Option<u8>)>, config: SimConfig) -> Network {
        let reset_ms = config.profile.reset_ms();
        let devices: Vec<Device> =
            devices.into_iter().map(|(m, id)| Device::new(m, id, config.bit_rate).with_reset_time(reset_ms)).collect();
        let paces = devices.iter().map(|d| Pace::new(&config, &d.model)).collect();
        let conducts = devices.iter().map(|d| Conduct::new(&config.faults, &d.model)).collect();
        Network { devices, paces, conducts, bit_rate: config.bit_rate, config, clock_ms: 0 }
    }

    /// How the network was set up.
    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    /// The bus's bit rate (CiA 305 table index).
    pub fn bit_rate(&self) -> u8 {
        self.bit_rate
    }

    /// The devices on the network, configured or waiting for a node-id.
    pub fn devices(&self) -> &[Device] {
        &self.devices
    }

    /// The devices, to set a test's starting point (a value already in an object).
    pub fn devices_mut(&mut self) -> &mut [Device] {
        &mut self.devices
    }

    /// The device built from the model with this key (`drive`, `sensor`, ...).
    pub(crate) fn device_mut(&mut self, model: &str) -> Option<&mut Device> {
        self.devices.iter_mut().find(|d| d.model == model)
    }

    /// `frame` has left the bus at `heard`: what the devices send in answer, each with
    /// the time it is ready to go and who sends it.
    pub(crate) fn deliver(&mut self, frame: &Frame, heard: Nanos) -> Vec<(Nanos, usize, Frame)> {
        let rate = self.bit_rate;
        let mut out = Vec::new();
        for (i, d) in self.devices.iter_mut().enumerate().filter(|(_, d)| d.bit_rate() == rate) {
            let (conduct, pace) = (&mut self.conducts[i], &mut self.paces[i]);
            if !conduct.hears(frame, &d.model, d.node_id(), &mut pace.rng) {
                continue;
            }
            let endless = endless_request(d, frame).and_then(|(node, payload)| {
                Some(device::sdo_frames(node, &conduct.endless_answer(payload, &d.model, Some(node), &mut pace.rng)?))
            });
            let answers = endless.unwrap_or_else(|| d.on_frame(frame));
            if answers.is_empty() {
                continue;
            }
            // One answer time for all of them: a device streams what it has to say.
            let ready = pace.answer_at(heard);
            for f in answers {
                let (go, sdo_reset) = conduct.answer(f, &d.model, d.node_id(), &mut pace.rng);
                if sdo_reset {
                    d.reset_sdo();
                }
                out.extend(go.into_iter().map(|(later, f)| (ready + later, i, f)));
            }
            // A reboot fault: the device resets instead (what was not stored is gone) and
            // says so with its boot-up.
            if let (true, Some(id)) = (conduct.take_reboot(), d.node_id()) {
                let boot = d.on_frame(&crate::canopen::nmt::Command::ResetNode.frame(id));
                out.extend(boot.into_iter().map(|f| (ready, i, f)));
            }
        }
        // CiA 305 "activate bit timing": the devices that switched, and the master with
        // them, run at the new rate; a device left at the old rate drops off the bus.
        let activate = matches!(lss::Request::decode(frame.data()), Some(lss::Request::ActivateBitTiming { .. }));
        if let Some(new) = self.devices.iter().map(|d| d.bit_rate()).find(|r| *r != rate).filter(|_| activate) {
            self.bit_rate = new;
        }
        out
    }

    /// What the devices send by themselves in `(after, upto]` (ms of wall-clock time):
    /// heartbeats, timed PDOs, faults, each with the ms it was due and who sends it.
    /// Phases follow the wall clock, so the network seems to run between invocations.
    pub fn events(&mut self, after: u64, upto: u64) -> Vec<(u64, usize, Frame)> {
        let rate = self.bit_rate;
        let mut out = Vec::new();
        for (i, d) in self.devices.iter_mut().enumerate().filter(|(_, d)| d.bit_rate() == rate) {
            let (own, conduct) = (d.events(after, upto), &self.conducts[i]);
            out.extend(own.into_iter().filter_map(|(t, f)| Some((t, i, conduct.own(f, &d.model, d.node_id())?))));
        }
        out
    }

    /// The bus's time, in ms, for the devices (which never read a clock themselves).
    pub(crate) fn set_clock(&mut self, ms: u64) {
        self.clock_ms = self.clock_ms.max(ms);
        for d in &mut self.devices {
            d.set_clock(ms);
        }
    }

    /// The devices flooding the bus, and the id each floods it with.
    pub(crate) fn babblers(&mut self) -> Vec<(usize, u16)> {
        let conducts = self.conducts.iter_mut().zip(&self.devices).enumerate();
        conducts.filter_map(|(i, (c, d))| Some((i, c.babbling(&d.model, d.node_id())?))).collect()
    }

    /// When the next of those is due after `now` (ms).
    pub(crate) fn next_event(&self, now: u64) -> Option<u64> {
        self.devices.iter().filter(|d| d.bit_rate() == self.bit_rate).filter_map(|d| d.next_event(now)).min()
    }

    /// The network's state to save: what the next invocation restores.
    pub fn snapshot(&self) -> state::NetworkState {
        state::NetworkState {
            version: state::VERSION,
            bit_rate: Some(self.bit_rate),
            config: Some(self.config.clone()),
            devices: self.devices.iter().map(|d| (d.model.clone(), d.snapshot())).collect(),
            clock_ms: Some(self.clock_ms).filter(|ms| *ms > 0),
        }
    }

    /// Returns the network to a saved state (devices missing from it keep theirs).
    pub fn restore(&mut self, s: &state::NetworkState) {
        self.bit_rate = s.bit_rate.unwrap_or(self.config.bit_rate);
        self.clock_ms = s.clock_ms.unwrap_or(0);
        for d in &mut self.devices {
            if let Some(ds) = s.devices.get(&d.model) {
                d.restore(ds);
            }
        }
    }

    /// The network a state file describes: its configuration, then its devices' state.
    pub fn from_state(s: &state::NetworkState) -> Network {
        let mut net = Network::demo_with(s.config.clone().unwrap_or_default());
        net.restore(s);
        net
    }

    /// The earliest ms the devices' clock may start at: after the last ms the previous
    /// invocation ran them, whatever the wall clock says (it may step back, and a virtual
    /// clock runs ahead of it). Two commands in a row are so at least a ms apart, and a
    /// fault armed 1 ms ahead has struck when the next one opens the network.
    pub(crate) fn resumes_at(&self) -> u64 {
        match self.clock_ms {
            0 => 0,
            ms => ms + 1,
        }
    }

    /// Whether anything persistent changed since the last call.
    pub(crate) fn take_dirty(&mut self) -> bool {
        self.devices.iter_mut().fold(false, |acc, d| d.take_dirty() | acc)
    }
}

/// The latest beat time at or before `now` for a producer with this period; beats are
/// offset by the node-id so that devices do not all beat in the same millisecond.
pub(crate) fn last_beat(period: u64, node: u64, now: u64) -> u64 {
    now.checked_sub(node % period).map_or(0, |since_offset| now - since_offset % period)
}

/// Wall-clock time, ms since the Unix epoch (0 if the clock is before it).
pub fn wall_ms() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map(|d| d.as_millis() as u64).unwrap_or(0)
}

/// What the simulated bus's clock is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Clock {
    /// The monotonic clock since the link was made: for a bus others share (served on an
    /// interface or a pty) and for a person watching.
    Real,
    /// Time passes only when the master waits: a wait with nothing due before its end
    /// jumps there at once. Whole procedures run in a moment of wall time with the same
    /// bus-time figures, and the same seed gives the same frames.
    Virtual { at: Nanos },
}

/// The simulated network as a frame link, with its state kept in a locked file.
///
/// Frames go through a model of the bus (`timing::BusQueue`) whose clock is the link's
/// own (real or virtual, see [`SimLink::on_virtual_time`]): a frame sent by the master
/// queues and leaves when the bus is free (as SocketCAN's `send` queues it); devices hear
/// it when it has left, answer after their latency, and their answers are received when
/// they have left the bus.
pub struct SimLink {
    net: Network,
    bus: BusQueue,
    /// Frames from the devices, each with the bus time it left the bus.
    rx: VecDeque<(Frame, Nanos)>,
    /// The devices' ms up to which their own frames have been produced: at the start the
    /// one before `start_ms`, so that the first look at the devices runs their start ms
    /// too, and what fell due while no invocation ran them (a fault armed by the last one)
    /// happens before the first request is answered, not at the first ms tick after it.
    beats_upto: u64,
    /// The bus clock's zero.
    epoch: Instant,
    /// The devices' clock (ms) at the bus clock's zero: wall-clock ms, so that devices'
    /// timed state (a fault armed to strike later) carries over between invocations.
    start_ms: u64,
    clock: Clock,
    /// A bridge to a real bus: frames take no time here.
    bus_timing_off: bool,
    /// The master's controller is bus-off (`--fault bus:off`): what it is asked to send
    /// never reaches the bus, and it reports so. It stays off, as a SocketCAN interface
    /// with `restart-ms 0` does: the kernel's automatic restart is not modelled.
    bus_off: bool,
    file: Option<state::StateFile>,
}

impl SimLink {
    /// A network with no state file: fresh demo devices, default configuration, nothing kept.
    pub fn ephemeral() -> SimLink {
        SimLink::with_config(SimConfig::default())
    }

    /// The demo network as `config` describes it, with no state file.
    pub fn with_config(config: SimConfig) -> SimLink {
        SimLink::of(Network::demo_with(config))
    }

    /// These devices, with no state file.
    pub fn of(net: Network) -> SimLink {
        let bus = BusQueue::new(Self::bps_of(&net));
        let start_ms = wall_ms().max(net.resumes_at());
        SimLink {
            bus,
            rx: VecDeque::new(),
            beats_upto: start_ms.saturating_sub(1),
            epoch: crate::bus::clock::monotonic_now(),
            start_ms,
            clock: Clock::Real,
            bus_timing_off: false,
            bus_off: faults::bus_off(&net.config.faults),
            net,
            file: None,
        }
    }

    /// The network as the state file left it (the default configuration without one).
    pub fn open(file: state::StateFile) -> Result<SimLink> {
        let net = Network::from_state(&file.load()?.unwrap_or_default());
        Ok(SimLink { file: Some(file), ..SimLink::of(net) })
    }

    fn bps_of(net: &Network) -> Option<u64> {
        // An automatic or reserved rate is timed as the default one; on the instant profile
        // frames take no time.
        let bps = timing::bits_per_second(net.bit_rate).or(timing::bits_per_second(DEFAULT_BIT_RATE));
        bps.filter(|_| net.config.profile != Profile::Instant)
    }

    /// The devices only, behind another link (an adapter, an interface): a `bus:off` fault
    /// is that link's controller's to show, not this side's.
    pub(crate) fn devices_only(mut self) -> SimLink {
        self.bus_off = false;
        self
    }

    /// The error a bus-off controller's link gives, as the SocketCAN backend's on the
    /// kernel's bus-off error frame.
    fn bus_off_error(&self) -> crate::error::Error {
        let detail = "simulated: the fault bus:off; it stays bus-off, as with restart-ms 0, until the sim network is reset without it".into();
        crate::error::LinkError::BusOff { iface: self.name(), detail }.into()
    }

    /// The simulated network this link is attached to.
    pub fn network(&self) -> &Network {
        &self.net
    }

    /// The simulated network, to change (tests inject faults and reboot devices).
    pub fn network_mut(&mut self) -> &mut Network {
        &mut self.net
    }

    /// Frames that have left the bus so far and how long it was busy with them.
    pub fn bus_stats(&self) -> BusStats {
        self.bus.stats
    }

    /// Frames take no time on this bus (the devices still answer late): for a bridge to
    /// a real bus, which has its own timing.
    pub fn without_bus_timing(mut self) -> SimLink {
        self.bus_timing_off = true;
        self.bus.bps = None;
        self
    }

    /// Run on virtual time from now on, the devices' clock starting at `start_ms`: a
    /// test gives a fixed one, so that the same seed gives the same frames byte for byte
    /// (heartbeat phases follow the devices' clock).
    pub fn on_virtual_time(mut self, start_ms: u64) -> SimLink {
        self.clock = Clock::Virtual { at: 0 };
        self.start_ms = start_ms.max(self.net.resumes_at());
        self.beats_upto = start_ms.saturating_sub(1);
        self
    }

    /// Whether the network was set up to run on virtual time when a command opens it
    /// (`sim reset --virtual-time`).
    pub fn wants_virtual_time(&self) -> bool {
        self.net.config.virtual_time
    }

    /// The bus clock: ns since its zero.
    fn bus_time(&self) -> Nanos {
        match self.clock {
            Clock::Real => self.epoch.elapsed().as_nanos() as Nanos,
            Clock::Virtual { at } => at,
        }
    }

    /// The devices' clock (ms) at bus time `t`.
    fn ms_at(&self, t: Nanos) -> u64 {
        self.start_ms + t / timing::MS
    }

    /// Let virtual time pass up to `t` (never back); real time passes by itself.
    fn pass_to(&mut self, t: Nanos) {
        if let Clock::Virtual { at } = &mut self.clock {
            *at = (*at).max(t);
        }
    }

    fn at(&self, t: Nanos) -> Instant {
        self.epoch + Duration::from_nanos(t)
    }

    /// When something next happens on the bus by itself: a frame leaves, or a device
    /// sends on its own.
    pub(crate) fn next_event(&self) -> Option<Instant> {
        self.next_event_at().map(|t| self.at(t))
    }

    fn next_event_at(&self) -> Option<Nanos> {
        let now = self.bus_time();
        let ms = self.ms_at(now);
        let next_own = self.net.next_event(self.beats_upto.max(ms));
        let own = next_own.map(|next| (next.saturating_sub(self.start_ms) * timing::MS).max(now));
        own.into_iter().chain(self.bus.next_done()).min()
    }

    /// Save the state now if anything changed (a long-running server saves as it goes).
    pub(crate) fn save_if_changed(&mut self) -> Result<()> {
        if self.net.take_dirty() {
            if let Some(file) = &self.file {
                file.save(&self.net.snapshot())?;
            }
        }
        Ok(())
    }

    /// Run the bus up to now: the devices' own frames queue, frames that have left are
    /// heard by the devices (master's) or received (devices'). Also for a master that reads
    /// a device's objects directly: a fault strikes, a drive's fault reaction ends.
    pub(crate) fn advance(&mut self) {
        let now = self.bus_time();
        let ms = self.ms_at(now);
        // In the order things happened, however late the master polls: a device hears a
        // frame that left the bus before its next own frame fell due (a stop before the
        // next beat, which then says stopped), and what it sent by itself competes for
        // the bus from the time it was ready.
        loop {
            let next_end = self.bus.next_done().filter(|end| *end <= now);
            let due_by = next_end.map_or(ms, |end| ms.saturating_sub((now - end).div_ceil(timing::MS)));
            self.queue_own_frames(due_by, now, ms);
            let Some((end, origin, frame)) = self.bus.pop_done(now) else { break };
            self.hand_over(end, origin, frame);
        }
        self.net.set_clock(ms);
        let babblers = self.net.babblers();
        self.bus.keep_babblers(&babblers.iter().map(|(i, _)| *i).collect::<Vec<_>>());
        for (i, id) in babblers {
            self.bus.babble(i, id, now);
        }
        self.pop_done(now);
    }

    /// Frames the master queued leave even if it goes away now (as the kernel still
    /// sends what a closed socket queued): the devices hear them before their state is
    /// saved. Bounded, for a bus a babbling device keeps busy.
    fn flush(&mut self) {
        for _ in 0..100_000 {
            let Some(next) = self.bus.next_done().filter(|_| self.bus.waiting_from(Origin::Master) > 0) else { break };
            self.pop_done(next);
        }
    }

    /// What the devices sent by themselves, due up to `due_by` (ms), onto the bus: each
    /// ready when it was due (`now` is bus time at ms `ms`).
    fn queue_own_frames(&mut self, due_by: u64, now: Nanos, ms: u64) {
        if due_by <= self.beats_upto {
            return;
        }
        self.net.set_clock(due_by);
        for (due, i, f) in self.net.events(self.beats_upto, due_by) {
            let ready = now.saturating_sub((ms - due) * timing::MS);
            self.bus.queue(ready, Origin::Device(i), f);
        }
        self.beats_upto = due_by;
    }

    fn pop_done(&mut self, now: Nanos) {
        while let Some((end, origin, frame)) = self.bus.pop_done(now) {
            self.hand_over(end, origin, frame);
        }
    }

    /// A frame that left the bus at `end`: the devices hear the master's (and may answer),
    /// the master receives the devices'.
    fn hand_over(&mut self, end: Nanos, origin: Origin, frame: Frame) {
        match origin {
            Origin::Master => {
                self.net.set_clock(self.ms_at(end));
                for (ready, i, f) in self.net.deliver(&frame, end) {
                    self.bus.queue(ready, Origin::Device(i), f);
                }
                if !self.bus_timing_off {
                    self.bus.bps = Self::bps_of(&self.net);
                }
            }
            Origin::Device(_) => self.rx.push_back((frame, end)),
        }
    }
}

impl FrameLink for SimLink {
    fn send(&mut self, frame: &Frame) -> Result<()> {
        // A bus-off controller sends nothing.
        if self.bus_off {
            return Err(self.bus_off_error());
        }
        self.advance();
        let now = self.bus_time();
        self.bus.queue(now, Origin::Master, *frame);
        Ok(())
    }

    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        Ok(self.recv_stamped(deadline)?.map(|(f, _)| f))
    }

    /// Stamped with the time the frame left the simulated bus.
    fn recv_stamped(&mut self, deadline: Instant) -> Result<Option<(Frame, Instant)>> {
        if self.bus_off {
            return Err(self.bus_off_error());
        }
        loop {
            if let Some((f, end)) = self.rx.pop_front() {
                return Ok(Some((f, self.at(end))));
            }
            self.advance();
            if !self.rx.is_empty() {
                continue;
            }
            let now = self.bus_time();
            let until = deadline.saturating_duration_since(self.epoch).as_nanos() as Nanos;
            if now >= until {
                return Ok(None);
            }
            // Nothing to hand over before the next event on the bus, or the deadline.
            let wake = self.next_event_at().map_or(until, |t| t.min(until)).max(now + MIN_WAIT);
            match self.clock {
                Clock::Virtual { .. } => self.pass_to(wake),
                Clock::Real => crate::bus::clock::sleep_until(self.at(wake)),
            }
        }
    }

    fn now(&self) -> Instant {
        self.at(self.bus_time())
    }

    fn sleep_until(&mut self, t: Instant) -> Result<()> {
        match self.clock {
            Clock::Virtual { .. } => {
                self.pass_to(t.saturating_duration_since(self.epoch).as_nanos() as Nanos);
                self.advance();
            }
            Clock::Real => crate::bus::clock::sleep_until(t),
        }
        Ok(())
    }

    fn follows_bit_rate_switch(&self) -> bool {
        true
    }

    fn frame_time(&self) -> Option<Duration> {
        Some(self.bus.bps.map_or(Duration::ZERO, crate::frame::longest_frame_time))
    }

    fn name(&self) -> String {
        "sim".into()
    }

    /// A bus-off controller reports itself as a SocketCAN one does (netlink state bus-off,
    /// one bus-off error frame); otherwise the simulated bus has no controller to report
    /// on. No restart-ms is reported: there is no `ip link` setting to change here (the
    /// error's text says how it comes back), and no error counters are made up.
    fn report(&mut self) -> Option<crate::bus::controller::LinkReport> {
        use crate::bus::controller::{CanState, Controller, ErrorFrameCounts, LinkReport};
        let bitrate = timing::bits_per_second(self.net.bit_rate).map(|b| b as u32);
        let controller = Controller::Can {
            state: Some(CanState::BusOff),
            tx_errors: None,
            rx_errors: None,
            restart_ms: None,
            bitrate,
        };
        let error_frames = ErrorFrameCounts { frames: 1, bus_off: 1, ..ErrorFrameCounts::default() };
        let report = LinkReport { iface: self.name(), controller: Some(controller), error_frames, queue_full: 0 };
        self.bus_off.then_some(report)
    }

    fn close(&mut self) -> Result<()> {
        self.flush();
        self.save_if_changed()
    }
}

/// The shortest wait of a receive with nothing due: on real time, what a sleep costs anyway.
const MIN_WAIT: Nanos = 20_000;

#[cfg(test)]
mod tests;
