//! The CiA 402 power drive state machine of a simulated drive: which state a controlword
//! leads to, and which statusword the drive shows in a state. Pure; the device keeps the
//! state in its statusword object (so it persists like any other value).

use crate::canopen::cia402::{self, sw, State};

/// How long a simulated drive stays in "fault reaction active" before "fault".
pub(crate) const FAULT_REACTION_MS: u64 = 20;

/// What bit 4 (voltage enabled) shows on this drive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VoltageBit {
    /// The power stage is on: operation enabled and quick stop active (EPOS2 firmware).
    PowerStage,
    /// The supply is present, whatever the state (seed 003's 0x0250 after power on).
    Supply,
}

/// What bit 9 (remote) shows on this drive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RemoteBit {
    /// Only while NMT operational (seed 000, table 6-15 "Remote flag Bit 9").
    WhenOperational,
    Always,
}

/// A drive model's statusword conventions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DriveProfile {
    /// Bits the drive always shows: the EPOS2's 0x0540 after boot has bit 8 (offset current
    /// measured) and bit 10 (target reached: nothing moves here) besides switch on disabled.
    pub constant_bits: u16,
    pub voltage: VoltageBit,
    pub remote: RemoteBit,
}

/// The drive's situation outside its state machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Drive {
    pub profile: DriveProfile,
    /// The cause of a fault is still there: a fault reset does not clear it.
    pub fault_cause: bool,
    /// The power supply is off (a simulator knob): the drive does not switch on.
    pub supply_off: bool,
    pub operational: bool,
}

impl Drive {
    pub fn new(profile: DriveProfile) -> Drive {
        Drive { profile, fault_cause: false, supply_off: false, operational: false }
    }

    /// The statusword of a drive in `state`.
    pub fn statusword(&self, state: State) -> u16 {
        let voltage = match self.profile.voltage {
            VoltageBit::PowerStage => matches!(state, State::OperationEnabled | State::QuickStopActive),
            VoltageBit::Supply => !self.supply_off,
        };
        let remote = self.profile.remote == RemoteBit::Always || self.operational;
        let flag = |on: bool, bit: u16| if on { bit } else { 0 };
        let always = state.statusword_bits() | self.profile.constant_bits;
        always | flag(voltage, sw::VOLTAGE_ENABLED) | flag(remote, sw::REMOTE)
    }

    /// The state after controlword `controlword` (the one before was `previous`) in `state`.
    pub(crate) fn on_controlword(&self, state: State, previous: u16, controlword: u16) -> State {
        let edge = cia402::fault_reset_edge(previous, controlword);
        let next = cia402::on_controlword(state, controlword, edge);
        let switching_on = matches!(next, State::SwitchedOn | State::OperationEnabled)
            && !matches!(state, State::SwitchedOn | State::OperationEnabled | State::QuickStopActive);
        if (state == State::Fault && self.fault_cause) || (switching_on && self.supply_off) {
            return state;
        }
        next
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const EPOS2: DriveProfile =
        DriveProfile { constant_bits: 0x0500, voltage: VoltageBit::PowerStage, remote: RemoteBit::WhenOperational };
    const SERS: DriveProfile =
        DriveProfile { constant_bits: 0, voltage: VoltageBit::Supply, remote: RemoteBit::Always };

    #[test]
    fn statuswords_match_the_seeds_after_power_on() {
        assert_eq!(Drive::new(EPOS2).statusword(State::SwitchOnDisabled), 0x0540);
        assert_eq!(Drive::new(SERS).statusword(State::SwitchOnDisabled), 0x0250);
    }

    #[test]
    fn the_epos2_shows_remote_while_operational_and_voltage_with_the_power_stage() {
        let d = Drive { operational: true, ..Drive::new(EPOS2) };
        assert_eq!(d.statusword(State::SwitchOnDisabled), 0x0740);
        assert_eq!(d.statusword(State::ReadyToSwitchOn), 0x0721);
        assert_eq!(d.statusword(State::OperationEnabled), 0x0737);
        assert_eq!(d.statusword(State::QuickStopActive), 0x0717);
        assert_eq!(d.statusword(State::Fault), 0x0708);
        assert_eq!(Drive::new(EPOS2).statusword(State::FaultReactionActive), 0x050F);
    }

    #[test]
    fn a_fault_reset_clears_the_fault_only_once_its_cause_is_gone() {
        let mut d = Drive::new(EPOS2);
        d.fault_cause = true;
        assert_eq!(d.on_controlword(State::Fault, 0x0000, 0x0080), State::Fault);
        d.fault_cause = false;
        assert_eq!(d.on_controlword(State::Fault, 0x0080, 0x0080), State::Fault, "no edge");
        assert_eq!(d.on_controlword(State::Fault, 0x0000, 0x0080), State::SwitchOnDisabled);
    }

    #[test]
    fn without_supply_the_drive_does_not_switch_on() {
        let d = Drive { supply_off: true, ..Drive::new(SERS) };
        assert_eq!(d.statusword(State::ReadyToSwitchOn) & sw::VOLTAGE_ENABLED, 0);
        assert_eq!(d.on_controlword(State::SwitchOnDisabled, 0, 0x0006), State::ReadyToSwitchOn);
        assert_eq!(d.on_controlword(State::ReadyToSwitchOn, 0x0006, 0x0007), State::ReadyToSwitchOn);
        assert_eq!(d.on_controlword(State::ReadyToSwitchOn, 0x0006, 0x000F), State::ReadyToSwitchOn);
        // Already on: switching off still works.
        assert_eq!(d.on_controlword(State::OperationEnabled, 0x000F, 0x0007), State::SwitchedOn);
        assert_eq!(d.on_controlword(State::OperationEnabled, 0x000F, 0x0000), State::SwitchOnDisabled);
    }
}
