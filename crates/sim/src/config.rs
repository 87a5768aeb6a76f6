//! How the simulated network behaves: its configuration, chosen by `sim reset` or a test.

use super::{FaultSpec, Profile};

/// The bit rate of the demo bus: 500 kbit/s (CiA 305 table index 2).
pub const DEFAULT_BIT_RATE: u8 = 2;
/// Devices without a node-id on the demo network unless told otherwise.
pub const DEFAULT_UNCONFIGURED: u8 = 3;
/// The most devices without a node-id `sim reset --unconfigured` builds.
pub const MAX_UNCONFIGURED: u8 = 64;
/// The seed of the demo network's draws unless told otherwise.
pub const DEFAULT_SEED: u64 = 1;

/// How the simulated network behaves: chosen by `sim reset` (kept in the state file) or
/// by a test.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SimConfig {
    /// How fast and how variably the devices answer.
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
    /// Run on virtual time when a command opens the network (`--bus sim`): waits with
    /// nothing due end at once, figures stay in bus time. A served network (on an interface
    /// or a pty, shared with other programs) always runs on real time.
    #[serde(default)]
    pub virtual_time: bool,
    /// A CiA 302-3 bootloader device on this node-id (`sim::bootloader`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bootloader: Option<u8>,
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
            virtual_time: false,
            bootloader: None,
        }
    }
}

impl SimConfig {
    /// With this timing profile.
    pub fn profile(mut self, profile: Profile) -> SimConfig {
        self.profile = profile;
        self
    }

    /// With this seed for every random draw.
    pub fn seed(mut self, seed: u64) -> SimConfig {
        self.seed = seed;
        self
    }

    /// With `n` devices waiting for an LSS node-id.
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

    /// On virtual time (tests: waits take no real time), or on the wall clock.
    pub fn virtual_time(mut self, on: bool) -> SimConfig {
        self.virtual_time = on;
        self
    }

    /// With this fault injected too.
    pub fn fault(mut self, fault: FaultSpec) -> SimConfig {
        self.faults.push(fault);
        self
    }

    /// The same network as a function call: for unit tests of protocol logic.
    pub fn instant() -> SimConfig {
        SimConfig::default().profile(Profile::Instant)
    }
}
