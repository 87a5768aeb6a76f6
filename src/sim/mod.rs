//! The simulated bus: the demo network's devices behind a `FrameLink`, so every command
//! runs through the same client code as on hardware.

pub mod bridge;
pub mod cia402_drive;
pub mod device;
pub mod epos2_device;
#[cfg(unix)]
pub mod epos2_serve;
pub mod faults;
pub mod profiles;
#[cfg(unix)]
pub mod pty;
pub mod serial_fault;
pub mod serve;
#[cfg(unix)]
pub mod slcan_serve;
pub mod state;
pub mod timing;

use crate::bus::FrameLink;
use crate::canopen::lss;
use crate::error::Result;
use crate::frame::Frame;
use device::Device;
use faults::Conduct;
pub use faults::FaultSpec;
use std::collections::{BTreeMap, VecDeque};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};
use timing::{BusQueue, Latency, Nanos, Origin, Rng};
pub use timing::{BusStats, Profile};

/// The bit rate of the demo bus: 500 kbit/s (CiA 305 table index 2).
pub const DEFAULT_BIT_RATE: u8 = 2;
/// Devices without a node-id on the demo network unless told otherwise.
pub const DEFAULT_UNCONFIGURED: u8 = 3;
/// The most devices without a node-id `sim reset --unconfigured` builds.
pub const MAX_UNCONFIGURED: u8 = 64;
pub const DEFAULT_SEED: u64 = 1;

/// How the simulated network behaves: chosen by `sim reset` (kept in the state file) or
/// by a test.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SimConfig {
    pub profile: Profile,
    /// Seeds every device's latency and fault draws: the same seed replays the same run.
    pub seed: u64,
    /// Position sensors waiting for an LSS node-id.
    pub unconfigured: u8,
    /// The bit rate the bus and every device start at (CiA 305 table index).
    #[serde(default = "default_bit_rate")]
    pub bit_rate: u8,
    /// Faults injected into devices' answers (see `faults`).
    #[serde(default)]
    pub faults: Vec<FaultSpec>,
}

fn default_bit_rate() -> u8 {
    DEFAULT_BIT_RATE
}

impl Default for SimConfig {
    fn default() -> SimConfig {
        SimConfig {
            profile: Profile::default(),
            seed: DEFAULT_SEED,
            unconfigured: DEFAULT_UNCONFIGURED,
            bit_rate: DEFAULT_BIT_RATE,
            faults: vec![],
        }
    }
}

impl SimConfig {
    pub fn profile(mut self, profile: Profile) -> SimConfig {
        self.profile = profile;
        self
    }

    pub fn seed(mut self, seed: u64) -> SimConfig {
        self.seed = seed;
        self
    }

    pub fn unconfigured(mut self, n: u8) -> SimConfig {
        self.unconfigured = n;
        self
    }

    /// The bus and every device at this bit rate (CiA 305 table index: 0 = 1 Mbit/s,
    /// 4 = 125 kbit/s).
    pub fn bit_rate(mut self, index: u8) -> SimConfig {
        self.bit_rate = index;
        self
    }

    pub fn fault(mut self, fault: FaultSpec) -> SimConfig {
        self.faults.push(fault);
        self
    }

    /// The same network as a function call: for unit tests of protocol logic.
    pub fn instant() -> SimConfig {
        SimConfig::default().profile(Profile::Instant)
    }
}

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

/// The devices on one simulated bus.
pub struct Network {
    devices: Vec<Device>,
    paces: Vec<Pace>,
    conducts: Vec<Conduct>,
    config: SimConfig,
    /// The bus's bit rate (CiA 305 table index): devices running at another rate neither
    /// hear nor are heard.
    bit_rate: u8,
}

impl Network {
    /// The demo network with the default configuration (the `typical` profile).
    pub fn demo() -> Network {
        Network::demo_with(SimConfig::default())
    }

    /// The demo network as `config` describes it.
    pub fn demo_with(config: SimConfig) -> Network {
        Network::of_with(profiles::demo_network_with(config.unconfigured), config)
    }

    /// A network of these devices at the default bit rate and configuration.
    pub fn of(devices: Vec<(profiles::Model, Option<u8>)>) -> Network {
        Network::of_with(devices, SimConfig::default())
    }

    /// A network of these devices, timed as `config` says (its device count is not used).
    pub fn of_with(devices: Vec<(profiles::Model, Option<u8>)>, config: SimConfig) -> Network {
        let devices: Vec<Device> = devices.into_iter().map(|(m, id)| Device::new(m, id, config.bit_rate)).collect();
        let paces = devices.iter().map(|d| Pace::new(&config, &d.model)).collect();
        let conducts = devices.iter().map(|d| Conduct::new(&config.faults, &d.model)).collect();
        let bit_rate = config.bit_rate;
        Network { devices, paces, conducts, config, bit_rate }
    }

    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    pub fn bit_rate(&self) -> u8 {
        self.bit_rate
    }

    pub fn devices(&self) -> &[Device] {
        &self.devices
    }

    /// The device built from the model with this key (`drive`, `sensor`, ...).
    pub fn device_mut(&mut self, model: &str) -> Option<&mut Device> {
        self.devices.iter_mut().find(|d| d.model == model)
    }

    /// The bus's bit rate was changed by a master that knows better (`sim` knobs, tests).
    pub fn set_bit_rate(&mut self, rate: u8) {
        self.bit_rate = rate;
    }

    /// `frame` has left the bus at `heard`: what the devices send in answer, each with
    /// the time it is ready to go and who sends it.
    pub fn deliver(&mut self, frame: &Frame, heard: Nanos) -> Vec<(Nanos, usize, Frame)> {
        let rate = self.bit_rate;
        let mut out = Vec::new();
        for (i, d) in self.devices.iter_mut().enumerate().filter(|(_, d)| d.bit_rate() == rate) {
            let conduct = &mut self.conducts[i];
            conduct.heard(frame, d.node_id());
            let answers = d.on_frame(frame);
            if answers.is_empty() {
                continue;
            }
            // One answer time for all of them: a device streams what it has to say.
            let pace = &mut self.paces[i];
            let ready = pace.answer_at(heard);
            for f in answers {
                let (go, sdo_reset) = conduct.answer(f, &d.model, d.node_id(), &mut pace.rng);
                if sdo_reset {
                    d.reset_sdo();
                }
                out.extend(go.into_iter().map(|(later, f)| (ready + later, i, f)));
            }
        }
        // CiA 305 "activate bit timing": the devices that switched, and the master with
        // them, run at the new rate; a device left at the old rate drops off the bus.
        if let Some(new) = self.devices.iter().map(|d| d.bit_rate()).find(|r| *r != rate) {
            if lss::Request::decode(frame.data()).is_some_and(|r| matches!(r, lss::Request::ActivateBitTiming { .. })) {
                self.bit_rate = new;
            }
        }
        out
    }

    /// What the devices send by themselves in `(after, upto]` (ms of wall-clock time):
    /// heartbeats, timed PDOs, faults. Phases follow the wall clock, so the network seems
    /// to run between invocations.
    pub fn events(&mut self, after: u64, upto: u64) -> Vec<(usize, Frame)> {
        let rate = self.bit_rate;
        let mut out = Vec::new();
        for (i, d) in self.devices.iter_mut().enumerate().filter(|(_, d)| d.bit_rate() == rate) {
            let conduct = &self.conducts[i];
            let own = d.events(after, upto);
            out.extend(own.into_iter().filter_map(|f| conduct.own(f, &d.model, d.node_id())).map(|f| (i, f)));
        }
        out
    }

    /// The devices flooding the bus, and the id each floods it with.
    pub fn babblers(&mut self) -> Vec<(usize, u16)> {
        let mut out = Vec::new();
        for (i, c) in self.conducts.iter_mut().enumerate() {
            let d = &self.devices[i];
            out.extend(c.babbling(&d.model, d.node_id()).map(|id| (i, id)));
        }
        out
    }

    /// When the next of those is due after `now` (ms).
    pub fn next_event(&self, now: u64) -> Option<u64> {
        self.devices.iter().filter(|d| d.bit_rate() == self.bit_rate).filter_map(|d| d.next_event(now)).min()
    }

    pub fn snapshot(&self) -> state::NetworkState {
        state::NetworkState {
            version: state::VERSION,
            bit_rate: Some(self.bit_rate),
            config: Some(self.config.clone()),
            devices: self.devices.iter().map(|d| (d.model.clone(), d.snapshot())).collect(),
        }
    }

    pub fn restore(&mut self, s: &state::NetworkState) {
        self.bit_rate = s.bit_rate.unwrap_or(self.config.bit_rate);
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

    /// Whether anything persistent changed since the last call.
    pub fn take_dirty(&mut self) -> bool {
        self.devices.iter_mut().fold(false, |acc, d| d.take_dirty() | acc)
    }
}

/// The latest beat time at or before `now` for a producer with this period; beats are
/// offset by the node-id so that devices do not all beat in the same millisecond.
pub(crate) fn last_beat(period: u64, node: u64, now: u64) -> u64 {
    let offset = node % period;
    if now < offset {
        return 0;
    }
    now - (now - offset) % period
}

pub fn wall_ms() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map(|d| d.as_millis() as u64).unwrap_or(0)
}

/// The simulated network as a frame link, with its state kept in a locked file.
///
/// Frames go through a model of the bus (`timing::BusQueue`) whose clock is the wall
/// clock since the link was made: a frame sent by the master queues and leaves when the
/// bus is free (as SocketCAN's `send` queues it); devices hear it when it has left, answer
/// after their latency, and their answers are received when they have left the bus.
pub struct SimLink {
    net: Network,
    bus: BusQueue,
    rx: VecDeque<Frame>,
    /// Wall-clock ms up to which the devices' own frames have been produced.
    beats_upto: u64,
    /// The bus clock's zero.
    epoch: Instant,
    /// A bridge to a real bus: frames take no time here.
    bus_timing_off: bool,
    file: Option<state::StateFile>,
}

impl SimLink {
    /// A network with no state file: fresh demo devices, default configuration, nothing kept.
    pub fn ephemeral() -> SimLink {
        SimLink::of(Network::demo())
    }

    /// The demo network as `config` describes it, with no state file.
    pub fn with_config(config: SimConfig) -> SimLink {
        SimLink::of(Network::demo_with(config))
    }

    /// These devices, with no state file.
    pub fn of(net: Network) -> SimLink {
        let bus = BusQueue::new(Self::bps_of(&net));
        SimLink {
            net,
            bus,
            rx: VecDeque::new(),
            beats_upto: wall_ms(),
            epoch: Instant::now(),
            bus_timing_off: false,
            file: None,
        }
    }

    /// The network as the state file left it (the default configuration without one).
    pub fn open(file: state::StateFile) -> Result<SimLink> {
        let net = match file.load()? {
            Some(s) => Network::from_state(&s),
            None => Network::demo(),
        };
        Ok(SimLink { file: Some(file), ..SimLink::of(net) })
    }

    fn bps_of(net: &Network) -> Option<u64> {
        // An automatic or reserved rate is timed as the default one.
        let bps = timing::bits_per_second(net.bit_rate).or(timing::bits_per_second(DEFAULT_BIT_RATE));
        bps.filter(|_| net.config.profile.bus_timing())
    }

    pub fn network(&self) -> &Network {
        &self.net
    }

    pub fn network_mut(&mut self) -> &mut Network {
        &mut self.net
    }

    /// Frames that have left the bus so far and how long it was busy with them.
    pub fn bus_stats(&self) -> BusStats {
        self.bus.stats()
    }

    /// Frames take no time on this bus (the devices still answer late): for a bridge to
    /// a real bus, which has its own timing.
    pub fn without_bus_timing(mut self) -> SimLink {
        self.bus_timing_off = true;
        self.bus.set_bps(None);
        self
    }

    fn now(&self) -> Nanos {
        self.epoch.elapsed().as_nanos() as Nanos
    }

    fn at(&self, t: Nanos) -> Instant {
        self.epoch + Duration::from_nanos(t)
    }

    /// When something next happens on the bus by itself: a frame leaves, or a device
    /// sends on its own.
    pub fn next_event(&self) -> Option<Instant> {
        let now = wall_ms();
        let own = self
            .net
            .next_event(self.beats_upto.max(now))
            .map(|next| Instant::now() + Duration::from_millis(next.saturating_sub(now)));
        let bus = self.bus.next_done().map(|t| self.at(t));
        own.into_iter().chain(bus).min()
    }

    /// Save the state now if anything changed (a long-running server saves as it goes).
    pub fn save_if_changed(&mut self) -> Result<()> {
        if self.net.take_dirty() {
            if let Some(file) = &self.file {
                file.save(&self.net.snapshot())?;
            }
        }
        Ok(())
    }

    /// Let the devices do what they do by themselves up to now (a fault strikes, a drive's
    /// fault reaction ends), for a master that reads a device's objects directly.
    pub fn run_until_now(&mut self) {
        self.advance();
    }

    /// Run the bus up to now: the devices' own frames queue, frames that have left are
    /// heard by the devices (master's) or received (devices').
    fn advance(&mut self) {
        let now = self.now();
        // What left the bus before now was decided without the frames queued now.
        self.pop_done(now);
        let ms = wall_ms();
        if ms > self.beats_upto {
            for (i, f) in self.net.events(self.beats_upto, ms) {
                self.bus.queue(now, Origin::Device(i), f);
            }
            self.beats_upto = ms;
        }
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
        let mut left = 100_000;
        while self.bus.waiting_from(Origin::Master) > 0 && left > 0 {
            let Some(next) = self.bus.next_done() else { break };
            self.pop_done(next);
            left -= 1;
        }
    }

    fn pop_done(&mut self, now: Nanos) {
        while let Some((end, origin, frame)) = self.bus.pop_done(now) {
            match origin {
                Origin::Master => {
                    for (ready, i, f) in self.net.deliver(&frame, end) {
                        self.bus.queue(ready, Origin::Device(i), f);
                    }
                    if !self.bus_timing_off {
                        self.bus.set_bps(Self::bps_of(&self.net));
                    }
                }
                Origin::Device(_) => self.rx.push_back(frame),
            }
        }
    }
}

impl FrameLink for SimLink {
    fn send(&mut self, frame: &Frame) -> Result<()> {
        self.advance();
        let now = self.now();
        self.bus.queue(now, Origin::Master, *frame);
        Ok(())
    }

    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        loop {
            if let Some(f) = self.rx.pop_front() {
                return Ok(Some(f));
            }
            self.advance();
            if !self.rx.is_empty() {
                continue;
            }
            let now = Instant::now();
            if now >= deadline {
                return Ok(None);
            }
            let wake = self.next_event().map_or(deadline, |t| t.min(deadline));
            std::thread::sleep(wake.saturating_duration_since(now).max(Duration::from_micros(20)));
        }
    }

    fn follows_bit_rate_switch(&self) -> bool {
        true
    }

    fn name(&self) -> String {
        "sim".into()
    }

    fn close(&mut self) -> Result<()> {
        self.flush();
        self.save_if_changed()
    }
}

/// Node-ids on the demo network, for documentation and tests.
pub fn demo_node_ids() -> BTreeMap<u8, String> {
    Network::demo().devices.iter().filter_map(|d| Some((d.node_id()?, d.model.clone()))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canopen::nmt;
    use timing::MS;

    const READ_DEVICE_TYPE: [u8; 8] = [0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0];

    #[test]
    fn a_slow_device_answers_5_to_80_ms_after_it_heard_the_request_and_in_order() {
        let mut net = Network::demo_with(SimConfig::default().profile(Profile::Slow));
        let mut last = 0;
        for i in 0..50u64 {
            let heard = i * MS;
            let out = net.deliver(&Frame::new(0x605, &READ_DEVICE_TYPE), heard);
            assert_eq!(out.len(), 1);
            let (ready, _, f) = out[0];
            assert_eq!(f.id(), 0x585);
            assert!(ready >= heard + 5 * MS && ready <= heard + 80 * MS, "{ready} after {heard}");
            assert!(ready >= last, "answers keep their order");
            last = ready;
        }
    }

    #[test]
    fn the_same_seed_gives_the_same_answer_times() {
        let times = |seed| {
            let mut net = Network::demo_with(SimConfig::default().seed(seed));
            (0..20).map(|i| net.deliver(&Frame::new(0x601, &READ_DEVICE_TYPE), i * MS)[0].0).collect::<Vec<_>>()
        };
        assert_eq!(times(3), times(3));
        assert_ne!(times(3), times(4));
    }

    #[test]
    fn faults_apply_to_the_device_they_name() {
        let config = SimConfig::instant().fault("5:drop".parse().unwrap()).fault("10:duplicate".parse().unwrap());
        let mut net = Network::demo_with(config);
        assert!(net.deliver(&Frame::new(0x605, &READ_DEVICE_TYPE), 0).is_empty());
        assert_eq!(net.deliver(&Frame::new(0x60A, &READ_DEVICE_TYPE), 0).len(), 2);
        assert_eq!(net.deliver(&Frame::new(0x601, &READ_DEVICE_TYPE), 0).len(), 1);
    }

    #[test]
    fn the_unconfigured_count_builds_that_many_lss_devices() {
        let net = Network::demo_with(SimConfig::instant().unconfigured(8));
        assert_eq!(net.devices().iter().filter(|d| d.node_id().is_none()).count(), 8);
        let serials: std::collections::BTreeSet<u32> = net.devices().iter().map(|d| d.identity().serial).collect();
        assert_eq!(serials.len(), net.devices().len(), "distinct serials");
    }

    #[test]
    fn a_command_the_master_queued_reaches_the_devices_before_the_link_closes() {
        let mut link = SimLink::with_config(SimConfig::default().profile(Profile::Slow));
        link.send(&nmt::Command::Stop.frame(5)).unwrap();
        link.close().unwrap();
        let sensor = link.network().devices().iter().find(|d| d.node_id() == Some(5)).unwrap();
        assert_eq!(sensor.nmt_state(), nmt::State::Stopped);
    }

    #[test]
    fn the_configured_bit_rate_times_the_frames() {
        let link = SimLink::with_config(SimConfig::default().bit_rate(0));
        assert_eq!(link.network().bit_rate(), 0);
        assert!(link.network().devices().iter().all(|d| d.bit_rate() == 0));
        assert_eq!(SimLink::bps_of(link.network()), Some(1_000_000));
        assert_eq!(SimLink::bps_of(&Network::demo_with(SimConfig::instant().bit_rate(4))), None);
    }

    #[test]
    fn answers_arrive_through_the_link_whatever_the_profile() {
        for profile in [Profile::Instant, Profile::Typical, Profile::Slow] {
            let mut link = SimLink::with_config(SimConfig::default().profile(profile).bit_rate(4));
            link.send(&Frame::new(0x601, &READ_DEVICE_TYPE)).unwrap();
            let deadline = Instant::now() + Duration::from_secs(5);
            let answer = std::iter::from_fn(|| link.recv(deadline).unwrap()).find(|f| f.id() == 0x581);
            assert_eq!(answer.map(|f| f.data()[0]), Some(0x43), "{profile}");
            assert!(link.bus_stats().frames >= 2, "request and answer went over the bus");
        }
    }
}
