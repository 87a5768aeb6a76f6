//! CiA 402 drive profile: the power drive system state machine (statusword 0x6041,
//! controlword 0x6040) and the modes of operation (0x6060/0x6061). Pure: the caller reads
//! and writes the objects; this module decodes them and says which command comes next.

use crate::ObjAddr;
use serde::Serialize;
use std::fmt;

/// CiA 402's controlword (0x6040): the commands of the drive state machine.
pub const CONTROLWORD: ObjAddr = ObjAddr::new(0x6040, 0);
/// CiA 402's statusword (0x6041): the drive's state.
pub const STATUSWORD: ObjAddr = ObjAddr::new(0x6041, 0);
/// CiA 402's modes of operation (0x6060): the mode asked for.
pub const MODES_OF_OPERATION: ObjAddr = ObjAddr::new(0x6060, 0);
/// CiA 402's modes of operation display (0x6061): the mode the drive is in.
pub const MODES_OF_OPERATION_DISPLAY: ObjAddr = ObjAddr::new(0x6061, 0);

/// The device profile number 0x1000 (device type) carries in its low 16 bits.
pub fn profile(device_type: u32) -> u16 {
    device_type as u16
}

/// A CiA 402 drive says so in 0x1000: profile number 402.
pub fn is_drive(device_type: u32) -> bool {
    profile(device_type) == 402
}

/// Statusword bits (CiA 402 §6.4.3, object 0x6041).
pub mod sw {
    /// Bit 4: the power stage has voltage.
    pub const VOLTAGE_ENABLED: u16 = 1 << 4;
    /// Bit 7: a warning stands (the drive keeps running).
    pub const WARNING: u16 = 1 << 7;
    /// Bit 9: the drive follows controlword commands (remote).
    pub const REMOTE: u16 = 1 << 9;
}

/// Controlword bits (CiA 402 §6.4.2, object 0x6040).
pub mod cw {
    /// Bit 1: enable voltage.
    pub const ENABLE_VOLTAGE: u16 = 1 << 1;
    /// Active low: 0 commands a quick stop.
    pub const QUICK_STOP: u16 = 1 << 2;
    /// Acts on its rising edge only.
    pub const FAULT_RESET: u16 = 1 << 7;
}

/// Every statusword bit by name; bits 8 and 14–15 are the manufacturer's, 12–13 depend on
/// the mode of operation.
pub(crate) const STATUSWORD_FLAGS: [(u8, &str); 16] = [
    (0, "ready to switch on"),
    (1, "switched on"),
    (2, "operation enabled"),
    (3, "fault"),
    (4, "voltage enabled"),
    (5, "quick stop"),
    (6, "switch on disabled"),
    (7, "warning"),
    (8, "manufacturer-specific (bit 8)"),
    (9, "remote"),
    (10, "target reached"),
    (11, "internal limit active"),
    (12, "operation mode specific (bit 12)"),
    (13, "operation mode specific (bit 13)"),
    (14, "manufacturer-specific (bit 14)"),
    (15, "manufacturer-specific (bit 15)"),
];

/// Each statusword flag with its value.
pub fn flags(statusword: u16) -> impl Iterator<Item = (u8, &'static str, bool)> {
    STATUSWORD_FLAGS.iter().map(move |&(bit, name)| (bit, name, statusword & (1 << bit) != 0))
}

/// The states of the power drive system finite state automaton (CiA 402 §6.4.1).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum State {
    /// Initialising: the drive does not accept commands yet.
    NotReadyToSwitchOn,
    /// Power stage off, waiting for a shutdown command.
    SwitchOnDisabled,
    /// Ready; the power stage may be off.
    ReadyToSwitchOn,
    /// Power stage on, not driving.
    SwitchedOn,
    /// Driving: the drive follows its set points.
    OperationEnabled,
    /// A quick stop is under way.
    QuickStopActive,
    /// A fault was detected; the drive is reacting to it.
    FaultReactionActive,
    /// Stopped on a fault: a fault reset leaves it.
    Fault,
}

/// (mask, value) of each state in the statusword (CiA 402 table "state coding"), in the
/// order of the state machine, and its name as the standard writes it.
const STATE_CODING: [(u16, u16, State, &str); 8] = [
    (0x004F, 0x0000, State::NotReadyToSwitchOn, "Not ready to switch on"),
    (0x004F, 0x0040, State::SwitchOnDisabled, "Switch on disabled"),
    (0x006F, 0x0021, State::ReadyToSwitchOn, "Ready to switch on"),
    (0x006F, 0x0023, State::SwitchedOn, "Switched on"),
    (0x006F, 0x0027, State::OperationEnabled, "Operation enabled"),
    (0x006F, 0x0007, State::QuickStopActive, "Quick stop active"),
    (0x004F, 0x000F, State::FaultReactionActive, "Fault reaction active"),
    (0x004F, 0x0008, State::Fault, "Fault"),
];

impl State {
    /// The state a statusword codes, or None for a bit pattern CiA 402 gives no state
    /// (e.g. ready to switch on with quick stop low).
    pub fn from_statusword(statusword: u16) -> Option<State> {
        STATE_CODING.iter().find(|(mask, value, ..)| statusword & mask == *value).map(|c| c.2)
    }

    /// The state bits (0–3, 5, 6) a drive in this state shows; the other bits are the
    /// drive's to add (voltage enabled, remote, warning …).
    pub fn statusword_bits(self) -> u16 {
        STATE_CODING.iter().find(|c| c.2 == self).map_or(0, |c| c.1)
    }

    /// Its name as the standard writes it ("operation enabled").
    pub fn name(self) -> &'static str {
        STATE_CODING.iter().find(|c| c.2 == self).map_or("", |c| c.3)
    }

    /// A state the drive leaves on its own (transitions 1 and 14), not by a command.
    pub fn is_transient(self) -> bool {
        matches!(self, State::NotReadyToSwitchOn | State::FaultReactionActive)
    }
}

impl fmt::Display for State {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The device control commands (CiA 402 table "command coding").
#[derive(Clone, Copy, PartialEq, Eq, Debug, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Command {
    /// 0xxx x110: transitions 2, 6, 8.
    Shutdown,
    /// 0xxx 0111: transition 3.
    SwitchOn,
    /// 0xxx 1111: transitions 4, 16 (and 3+4 from ready to switch on).
    EnableOperation,
    /// 0xxx xx0x: transitions 7, 9, 10, 12.
    DisableVoltage,
    /// 0xxx x01x: transitions 7, 10, 11.
    QuickStop,
    /// 0xxx 0111: transition 5 (the same bits as switch on).
    DisableOperation,
    /// Bit 7 rising edge: transition 15.
    FaultReset,
}

/// Each command's controlword (every "x" bit 0, halt clear) and its name as the standard writes it.
const COMMANDS: [(Command, u16, &str); 7] = [
    (Command::Shutdown, 0x0006, "shutdown"),
    (Command::SwitchOn, 0x0007, "switch on"),
    (Command::EnableOperation, 0x000F, "enable operation"),
    (Command::DisableVoltage, 0x0000, "disable voltage"),
    (Command::QuickStop, 0x0002, "quick stop"),
    (Command::DisableOperation, 0x0007, "disable operation"),
    (Command::FaultReset, 0x0080, "fault reset"),
];

impl Command {
    /// The controlword that issues the command, every "x" bit 0 (halt clear).
    pub fn controlword(self) -> u16 {
        COMMANDS.iter().find(|c| c.0 == self).map_or(0, |c| c.1)
    }

    /// Its name as the standard writes it ("enable operation").
    pub fn name(self) -> &'static str {
        COMMANDS.iter().find(|c| c.0 == self).map_or("", |c| c.2)
    }
}

impl fmt::Display for Command {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Whether bit 7 rose between two controlwords: a fault reset acts on the edge only.
pub fn fault_reset_edge(previous: u16, controlword: u16) -> bool {
    previous & cw::FAULT_RESET == 0 && controlword & cw::FAULT_RESET != 0
}

/// The state a drive in `state` moves to on controlword `controlword` (as the drive sees
/// it; the fault reset edge comes from [`fault_reset_edge`]). Unrecognised commands and
/// the transient states leave the state; whether a fault's cause is gone is the drive's to
/// judge before it takes transition 15.
pub fn on_controlword(state: State, controlword: u16, fault_reset_edge: bool) -> State {
    use State::*;
    let bits = controlword & 0x000F;
    let disable_voltage = bits & cw::ENABLE_VOLTAGE == 0;
    let quick_stop = !disable_voltage && bits & cw::QUICK_STOP == 0;
    let shutdown = bits & 0x7 == 0x6;
    let switch_on = bits == 0x7;
    let enable_operation = bits == 0xF;
    match state {
        Fault if fault_reset_edge => SwitchOnDisabled,
        Fault | FaultReactionActive | NotReadyToSwitchOn => state,
        SwitchOnDisabled if shutdown => ReadyToSwitchOn,
        SwitchOnDisabled => state,
        ReadyToSwitchOn if disable_voltage || quick_stop => SwitchOnDisabled,
        ReadyToSwitchOn if switch_on => SwitchedOn,
        ReadyToSwitchOn if enable_operation => OperationEnabled,
        ReadyToSwitchOn => state,
        SwitchedOn if disable_voltage || quick_stop => SwitchOnDisabled,
        SwitchedOn if shutdown => ReadyToSwitchOn,
        SwitchedOn if enable_operation => OperationEnabled,
        SwitchedOn => state,
        OperationEnabled if disable_voltage => SwitchOnDisabled,
        OperationEnabled if quick_stop => QuickStopActive,
        OperationEnabled if shutdown => ReadyToSwitchOn,
        OperationEnabled if switch_on => SwitchedOn,
        OperationEnabled => state,
        QuickStopActive if disable_voltage => SwitchOnDisabled,
        QuickStopActive if enable_operation => OperationEnabled,
        QuickStopActive => state,
    }
}

/// What a command line asks of a drive.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Goal {
    /// Operation enabled.
    Enable,
    /// Switch on disabled (power stage off).
    Disable,
    /// Quick stop active from operation enabled; from ready to switch on or switched on
    /// the same command leads to switch on disabled.
    QuickStop,
    /// Out of fault into switch on disabled.
    FaultReset,
}

impl Goal {
    /// Its name in `drive` commands and reports.
    pub fn name(self) -> &'static str {
        match self {
            Goal::Enable => "enable",
            Goal::Disable => "disable",
            Goal::QuickStop => "quick-stop",
            Goal::FaultReset => "fault-reset",
        }
    }
}

/// Why the walk cannot go on from a state.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Blocker {
    /// The drive is in fault; only a fault reset leaves it.
    FaultPresent,
}

/// The next thing to do to reach a goal from a state.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Step {
    /// The goal is reached.
    Done,
    /// Issue the command and expect the drive to reach the state.
    Send(Command, State),
    /// The drive leaves this state on its own: read the statusword again.
    Wait,
    /// The goal cannot be reached from here without the user (why).
    Blocked(Blocker),
}

/// One step of the path from `state` towards `goal`.
pub fn next_step(state: State, goal: Goal) -> Step {
    use Command as C;
    use State::*;
    if state.is_transient() {
        return Step::Wait;
    }
    match (goal, state) {
        (Goal::FaultReset, Fault) => Step::Send(C::FaultReset, SwitchOnDisabled),
        (Goal::FaultReset, _) => Step::Done,
        (_, Fault) => Step::Blocked(Blocker::FaultPresent),

        (Goal::Enable, OperationEnabled) => Step::Done,
        (Goal::Enable, SwitchOnDisabled) => Step::Send(C::Shutdown, ReadyToSwitchOn),
        (Goal::Enable, ReadyToSwitchOn) => Step::Send(C::SwitchOn, SwitchedOn),
        (Goal::Enable, SwitchedOn) => Step::Send(C::EnableOperation, OperationEnabled),
        // Transition 16 is optional (quick stop option codes 5–8): go round by switch on
        // disabled, which every drive supports.
        (Goal::Enable, QuickStopActive) => Step::Send(C::DisableVoltage, SwitchOnDisabled),

        (Goal::Disable, SwitchOnDisabled) => Step::Done,
        (Goal::Disable, _) => Step::Send(C::DisableVoltage, SwitchOnDisabled),

        (Goal::QuickStop, SwitchOnDisabled | QuickStopActive) => Step::Done,
        (Goal::QuickStop, OperationEnabled) => Step::Send(C::QuickStop, QuickStopActive),
        (Goal::QuickStop, _) => Step::Send(C::QuickStop, SwitchOnDisabled),

        (_, NotReadyToSwitchOn | FaultReactionActive) => Step::Wait,
    }
}

/// A mode of operation (0x6060/0x6061) by name: CiA 402 values 0–10; negative values are
/// the manufacturer's.
pub fn mode_name(mode: i8) -> Option<&'static str> {
    Some(match mode {
        0 => "no mode",
        1 => "profile position",
        2 => "velocity",
        3 => "profile velocity",
        4 => "profile torque",
        6 => "homing",
        7 => "interpolated position",
        8 => "cyclic synchronous position",
        9 => "cyclic synchronous velocity",
        10 => "cyclic synchronous torque",
        m if m < 0 => "manufacturer-specific",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn states_decode_from_the_coding_table() {
        // Values seen on drives: EPOS2 after boot 0x0540 (switch on disabled, remote,
        // target reached), SERS 0x0250, operation enabled 0x0637 …
        assert_eq!(State::from_statusword(0x0540), Some(State::SwitchOnDisabled));
        assert_eq!(State::from_statusword(0x0250), Some(State::SwitchOnDisabled));
        assert_eq!(State::from_statusword(0x0000), Some(State::NotReadyToSwitchOn));
        assert_eq!(State::from_statusword(0x0221), Some(State::ReadyToSwitchOn));
        assert_eq!(State::from_statusword(0x0231), Some(State::ReadyToSwitchOn));
        assert_eq!(State::from_statusword(0x0233), Some(State::SwitchedOn));
        assert_eq!(State::from_statusword(0x0637), Some(State::OperationEnabled));
        assert_eq!(State::from_statusword(0x0217), Some(State::QuickStopActive));
        assert_eq!(State::from_statusword(0x001F), Some(State::FaultReactionActive));
        assert_eq!(State::from_statusword(0x003F), Some(State::FaultReactionActive));
        assert_eq!(State::from_statusword(0x0208), Some(State::Fault));
        assert_eq!(State::from_statusword(0x0238), Some(State::Fault));
        // Bits above 6 never change the state.
        assert_eq!(State::from_statusword(0xFFA7), Some(State::OperationEnabled));
    }

    #[test]
    fn patterns_with_no_state_decode_to_none() {
        // Ready to switch on with quick stop low; switch on disabled plus ready bit.
        assert_eq!(State::from_statusword(0x0001), None);
        assert_eq!(State::from_statusword(0x0041), None);
        assert_eq!(State::from_statusword(0x0003), None);
        assert_eq!(State::from_statusword(0x0048), None);
    }

    #[test]
    fn each_state_codes_back_to_itself() {
        for state in STATE_CODING.map(|c| c.2) {
            assert_eq!(State::from_statusword(state.statusword_bits()), Some(state));
            // The drive's own bits (voltage enabled, remote, warning, target reached) do
            // not change it.
            assert_eq!(State::from_statusword(state.statusword_bits() | 0x0690), Some(state));
        }
    }

    #[test]
    fn every_statusword_bit_has_a_name() {
        let named: Vec<_> = flags(0x0637).filter(|f| f.2).map(|f| f.1).collect();
        assert_eq!(
            named,
            [
                "ready to switch on",
                "switched on",
                "operation enabled",
                "voltage enabled",
                "quick stop",
                "remote",
                "target reached"
            ]
        );
        assert_eq!(flags(0).count(), 16);
        assert!(flags(0x0808).any(|f| f.1 == "internal limit active" && f.2));
        assert!(flags(0x0080).any(|f| f.1 == "warning" && f.2));
    }

    #[test]
    fn command_bit_patterns_follow_the_command_coding() {
        assert_eq!(Command::Shutdown.controlword(), 0x0006);
        assert_eq!(Command::SwitchOn.controlword(), 0x0007);
        assert_eq!(Command::EnableOperation.controlword(), 0x000F);
        assert_eq!(Command::DisableVoltage.controlword(), 0x0000);
        assert_eq!(Command::QuickStop.controlword(), 0x0002);
        assert_eq!(Command::DisableOperation.controlword(), 0x0007);
        assert_eq!(Command::FaultReset.controlword(), 0x0080);
    }

    #[test]
    fn each_command_takes_its_transitions() {
        use State::*;
        let t = |s, c: Command| on_controlword(s, c.controlword(), false);
        assert_eq!(t(SwitchOnDisabled, Command::Shutdown), ReadyToSwitchOn); // 2
        assert_eq!(t(ReadyToSwitchOn, Command::SwitchOn), SwitchedOn); // 3
        assert_eq!(t(SwitchedOn, Command::EnableOperation), OperationEnabled); // 4
        assert_eq!(t(OperationEnabled, Command::DisableOperation), SwitchedOn); // 5
        assert_eq!(t(SwitchedOn, Command::Shutdown), ReadyToSwitchOn); // 6
        assert_eq!(t(ReadyToSwitchOn, Command::DisableVoltage), SwitchOnDisabled); // 7
        assert_eq!(t(ReadyToSwitchOn, Command::QuickStop), SwitchOnDisabled); // 7
        assert_eq!(t(OperationEnabled, Command::Shutdown), ReadyToSwitchOn); // 8
        assert_eq!(t(OperationEnabled, Command::DisableVoltage), SwitchOnDisabled); // 9
        assert_eq!(t(SwitchedOn, Command::DisableVoltage), SwitchOnDisabled); // 10
        assert_eq!(t(SwitchedOn, Command::QuickStop), SwitchOnDisabled); // 10
        assert_eq!(t(OperationEnabled, Command::QuickStop), QuickStopActive); // 11
        assert_eq!(t(QuickStopActive, Command::DisableVoltage), SwitchOnDisabled); // 12
        assert_eq!(t(QuickStopActive, Command::EnableOperation), OperationEnabled); // 16
        assert_eq!(t(ReadyToSwitchOn, Command::EnableOperation), OperationEnabled); // 3+4
        assert_eq!(on_controlword(Fault, 0x0080, true), SwitchOnDisabled); // 15
    }

    #[test]
    fn refused_commands_leave_the_state() {
        use State::*;
        let t = |s, c: Command| on_controlword(s, c.controlword(), false);
        assert_eq!(t(SwitchOnDisabled, Command::SwitchOn), SwitchOnDisabled);
        assert_eq!(t(SwitchOnDisabled, Command::EnableOperation), SwitchOnDisabled);
        assert_eq!(t(SwitchOnDisabled, Command::QuickStop), SwitchOnDisabled);
        assert_eq!(t(QuickStopActive, Command::Shutdown), QuickStopActive);
        assert_eq!(t(QuickStopActive, Command::SwitchOn), QuickStopActive);
        for c in [Command::Shutdown, Command::SwitchOn, Command::EnableOperation] {
            assert_eq!(t(Fault, c), Fault);
            assert_eq!(t(FaultReactionActive, c), FaultReactionActive);
            assert_eq!(t(NotReadyToSwitchOn, c), NotReadyToSwitchOn);
        }
        // Bit 7 held high is no edge: the fault stays.
        assert_eq!(on_controlword(Fault, 0x0080, false), Fault);
    }

    #[test]
    fn fault_reset_acts_on_the_rising_edge_only() {
        assert!(fault_reset_edge(0x0000, 0x0080));
        assert!(fault_reset_edge(0x000F, 0x0086));
        assert!(!fault_reset_edge(0x0080, 0x0080));
        assert!(!fault_reset_edge(0x0080, 0x0000));
    }

    /// Follows the path of `goal` from `from` on a drive that takes every transition.
    fn walk(from: State, goal: Goal) -> (Vec<Command>, State) {
        let (mut state, mut commands) = (from, Vec::new());
        loop {
            match next_step(state, goal) {
                Step::Send(c, expect) => {
                    let edge = c == Command::FaultReset;
                    state = on_controlword(state, c.controlword(), edge);
                    assert_eq!(state, expect, "{c} from {from}");
                    commands.push(c);
                }
                Step::Done | Step::Blocked(_) | Step::Wait => return (commands, state),
            }
            assert!(commands.len() < 8, "no end from {from} to {goal:?}");
        }
    }

    #[test]
    fn enable_walks_through_each_state() {
        use Command::*;
        use State::*;
        assert_eq!(walk(SwitchOnDisabled, Goal::Enable), (vec![Shutdown, SwitchOn, EnableOperation], OperationEnabled));
        assert_eq!(walk(SwitchedOn, Goal::Enable), (vec![EnableOperation], OperationEnabled));
        assert_eq!(
            walk(QuickStopActive, Goal::Enable),
            (vec![DisableVoltage, Shutdown, SwitchOn, EnableOperation], OperationEnabled)
        );
        assert_eq!(walk(OperationEnabled, Goal::Enable), (vec![], OperationEnabled));
    }

    #[test]
    fn other_goals_walk_to_their_state() {
        use Command::*;
        use State::*;
        assert_eq!(walk(OperationEnabled, Goal::Disable), (vec![DisableVoltage], SwitchOnDisabled));
        assert_eq!(walk(SwitchOnDisabled, Goal::Disable), (vec![], SwitchOnDisabled));
        assert_eq!(walk(OperationEnabled, Goal::QuickStop), (vec![QuickStop], QuickStopActive));
        assert_eq!(walk(SwitchedOn, Goal::QuickStop), (vec![QuickStop], SwitchOnDisabled));
        assert_eq!(walk(Fault, Goal::FaultReset), (vec![FaultReset], SwitchOnDisabled));
        assert_eq!(walk(OperationEnabled, Goal::FaultReset), (vec![], OperationEnabled));
    }

    #[test]
    fn a_fault_blocks_every_goal_but_fault_reset_and_transients_wait() {
        for goal in [Goal::Enable, Goal::Disable, Goal::QuickStop] {
            assert_eq!(next_step(State::Fault, goal), Step::Blocked(Blocker::FaultPresent));
        }
        for goal in [Goal::Enable, Goal::Disable, Goal::QuickStop, Goal::FaultReset] {
            assert_eq!(next_step(State::FaultReactionActive, goal), Step::Wait);
            assert_eq!(next_step(State::NotReadyToSwitchOn, goal), Step::Wait);
        }
    }

    #[test]
    fn drives_are_profile_402() {
        assert!(is_drive(0x0002_0192)); // EPOS2: 402, servo drive
        assert!(is_drive(0x0000_0192));
        assert!(!is_drive(0x000F_0191)); // I/O module, 401
        assert!(!is_drive(0x0000_0196)); // encoder, 406
        assert!(!is_drive(0x0192_0000));
        assert_eq!(profile(0x0002_0192), 402);
    }

    #[test]
    fn modes_have_names() {
        assert_eq!(mode_name(1), Some("profile position"));
        assert_eq!(mode_name(6), Some("homing"));
        assert_eq!(mode_name(3), Some("profile velocity"));
        assert_eq!(mode_name(-1), Some("manufacturer-specific"));
        assert_eq!(mode_name(5), None);
        assert_eq!(mode_name(0), Some("no mode"));
    }
}
