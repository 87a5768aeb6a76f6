//! The simulated bus: the demo network's devices behind a `FrameLink`, so every command
//! runs through the same client code as on hardware.

pub mod bridge;
pub mod device;
pub mod epos2_device;
pub mod epos2_serve;
pub mod profiles;
pub mod pty;
pub mod slcan_serve;
pub mod state;

use crate::bus::FrameLink;
use crate::canopen::lss;
use crate::error::Result;
use crate::frame::Frame;
use device::Device;
use std::collections::{BTreeMap, VecDeque};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

/// The bit rate of the demo bus: 500 kbit/s (CiA 305 table index 2).
pub const DEFAULT_BIT_RATE: u8 = 2;

/// The devices on one simulated bus.
pub struct Network {
    devices: Vec<Device>,
    /// The bus's bit rate (CiA 305 table index): devices running at another rate neither
    /// hear nor are heard.
    bit_rate: u8,
}

impl Network {
    pub fn demo() -> Network {
        Network::of(profiles::demo_network())
    }

    /// A network of these devices at the default bit rate.
    pub fn of(devices: Vec<(profiles::Model, Option<u8>)>) -> Network {
        let devices = devices.into_iter().map(|(m, id)| Device::new(m, id, DEFAULT_BIT_RATE)).collect();
        Network { devices, bit_rate: DEFAULT_BIT_RATE }
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

    /// Put `frame` on the bus; returns what the devices send in answer, in order.
    pub fn deliver(&mut self, frame: &Frame) -> Vec<Frame> {
        let rate = self.bit_rate;
        let out = self.devices.iter_mut().filter(|d| d.bit_rate() == rate).flat_map(|d| d.on_frame(frame)).collect();
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
    pub fn events(&mut self, after: u64, upto: u64) -> Vec<Frame> {
        let rate = self.bit_rate;
        self.devices.iter_mut().filter(|d| d.bit_rate() == rate).flat_map(|d| d.events(after, upto)).collect()
    }

    /// When the next of those is due after `now` (ms).
    pub fn next_event(&self, now: u64) -> Option<u64> {
        self.devices.iter().filter(|d| d.bit_rate() == self.bit_rate).filter_map(|d| d.next_event(now)).min()
    }

    pub fn snapshot(&self) -> state::NetworkState {
        state::NetworkState {
            version: state::VERSION,
            bit_rate: Some(self.bit_rate),
            devices: self.devices.iter().map(|d| (d.model.clone(), d.snapshot())).collect(),
        }
    }

    pub fn restore(&mut self, s: &state::NetworkState) {
        self.bit_rate = s.bit_rate.unwrap_or(DEFAULT_BIT_RATE);
        for d in &mut self.devices {
            if let Some(ds) = s.devices.get(&d.model) {
                d.restore(ds);
            }
        }
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
pub struct SimLink {
    net: Network,
    rx: VecDeque<Frame>,
    /// Wall-clock ms up to which the devices' own frames have been produced.
    beats_upto: u64,
    file: Option<state::StateFile>,
}

impl SimLink {
    /// A network with no state file: fresh demo devices, nothing kept.
    pub fn ephemeral() -> SimLink {
        SimLink::of(Network::demo())
    }

    /// These devices, with no state file.
    pub fn of(net: Network) -> SimLink {
        SimLink { net, rx: VecDeque::new(), beats_upto: wall_ms(), file: None }
    }

    /// The network as the state file left it.
    pub fn open(file: state::StateFile) -> Result<SimLink> {
        let mut net = Network::demo();
        if let Some(s) = file.load()? {
            net.restore(&s);
        }
        Ok(SimLink { net, rx: VecDeque::new(), beats_upto: wall_ms(), file: Some(file) })
    }

    pub fn network(&self) -> &Network {
        &self.net
    }

    pub fn network_mut(&mut self) -> &mut Network {
        &mut self.net
    }

    /// When a device next sends something by itself, if any will.
    pub fn next_event(&self) -> Option<Instant> {
        let now = wall_ms();
        let next = self.net.next_event(self.beats_upto.max(now))?;
        Some(Instant::now() + Duration::from_millis(next.saturating_sub(now)))
    }

    /// Save the state now if anything changed (a long-running server saves as it goes).
    pub fn save_if_changed(&mut self) -> Result<()> {
        self.close()
    }

    fn produce_events(&mut self) {
        let now = wall_ms();
        if now > self.beats_upto {
            let beats = self.net.events(self.beats_upto, now);
            self.rx.extend(beats);
            self.beats_upto = now;
        }
    }
}

impl FrameLink for SimLink {
    fn send(&mut self, frame: &Frame) -> Result<()> {
        self.produce_events();
        let answers = self.net.deliver(frame);
        self.rx.extend(answers);
        Ok(())
    }

    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        loop {
            if let Some(f) = self.rx.pop_front() {
                return Ok(Some(f));
            }
            self.produce_events();
            if !self.rx.is_empty() {
                continue;
            }
            let now = Instant::now();
            if now >= deadline {
                return Ok(None);
            }
            let mut wake = deadline;
            if let Some(next) = self.net.next_event(self.beats_upto) {
                wake = wake.min(now + Duration::from_millis(next.saturating_sub(wall_ms())));
            }
            std::thread::sleep(wake.saturating_duration_since(now).max(Duration::from_micros(100)));
        }
    }

    fn name(&self) -> String {
        "sim".into()
    }

    fn close(&mut self) -> Result<()> {
        if self.net.take_dirty() {
            if let Some(file) = &self.file {
                file.save(&self.net.snapshot())?;
            }
        }
        Ok(())
    }
}

/// Node-ids on the demo network, for documentation and tests.
pub fn demo_node_ids() -> BTreeMap<u8, String> {
    Network::demo().devices.iter().filter_map(|d| Some((d.node_id()?, d.model.clone()))).collect()
}
