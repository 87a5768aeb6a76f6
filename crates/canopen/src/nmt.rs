//! NMT (CiA 301 §7.2.8): commands from the master, states, and the error-control
//! frames (boot-up, heartbeat, node-guarding) that report them.

use crate::frame::Frame;
use std::fmt;

pub(crate) const NMT_COB: u16 = 0x000;

/// The COB-ID of `node`'s heartbeat, boot-up and node-guarding answers (0x700 + node).
pub fn error_control_cob(node: u8) -> u16 {
    0x700 + node as u16
}

/// An NMT command (CiA 301 §7.2.8.3.1); its value is its command specifier.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum Command {
    /// To Operational.
    Start = 0x01,
    /// To Stopped.
    Stop = 0x02,
    /// To Pre-operational.
    PreOperational = 0x80,
    /// Reset the application (and communication).
    ResetNode = 0x81,
    /// Reset communication only.
    ResetCommunication = 0x82,
}

impl Command {
    /// Its command specifier, byte 0 of the NMT frame.
    pub fn specifier(self) -> u8 {
        self as u8
    }

    /// The command a command specifier (byte 0 of an NMT frame) codes.
    pub fn from_specifier(cs: u8) -> Option<Command> {
        use Command::*;
        [Start, Stop, PreOperational, ResetNode, ResetCommunication].into_iter().find(|c| c.specifier() == cs)
    }

    /// Its name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Command::Start => "start",
            Command::Stop => "stop",
            Command::PreOperational => "enter pre-operational",
            Command::ResetNode => "reset node",
            Command::ResetCommunication => "reset communication",
        }
    }

    /// `node` 0 addresses all nodes.
    pub fn frame(self, node: u8) -> Frame {
        Frame::new(NMT_COB, &[self.specifier(), node])
    }

    /// Command and addressee of an NMT frame.
    pub fn parse(frame: &Frame) -> Option<(Command, u8)> {
        match frame.data() {
            [cs, node] if frame.id() == NMT_COB => Some((Command::from_specifier(*cs)?, *node)),
            _ => None,
        }
    }
}

/// An NMT state, as a heartbeat or a guarding answer reports it; its value is its code.
#[derive(Clone, Copy, PartialEq, Eq, Debug, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u8)]
pub enum State {
    /// Booting (a boot-up message is this state).
    Initialising = 0x00,
    /// Stopped: only NMT and error control.
    Stopped = 0x04,
    /// Operational: PDOs run.
    Operational = 0x05,
    /// Pre-operational: SDO but no PDO.
    PreOperational = 0x7F,
}

impl State {
    /// The state code in heartbeat and guarding frames (boot-up is 0).
    pub fn code(self) -> u8 {
        self as u8
    }

    /// The state a heartbeat or guarding answer codes (its low 7 bits); `None` for others.
    pub fn from_code(code: u8) -> Option<State> {
        use State::*;
        [Initialising, Stopped, Operational, PreOperational].into_iter().find(|s| s.code() == code)
    }

    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            State::Initialising => "initialising",
            State::Stopped => "stopped",
            State::Operational => "operational",
            State::PreOperational => "pre-operational",
        }
    }

    /// The state a node is in after `cmd` (resets pass through boot-up to pre-operational).
    pub fn after(self, cmd: Command) -> State {
        match cmd {
            Command::Start => State::Operational,
            Command::Stop => State::Stopped,
            Command::PreOperational | Command::ResetNode | Command::ResetCommunication => State::PreOperational,
        }
    }
}

impl fmt::Display for State {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One decoded error-control frame (COB-ID 0x700 + node).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ErrorControl {
    /// The boot-up message (state code 0).
    BootUp,
    /// A heartbeat, or an answer to a guarding request (then `toggle` is meaningful).
    State {
        /// The state it reported.
        state: State,
        /// The toggle bit (node guarding alternates it; heartbeats send 0).
        toggle: bool,
    },
    /// A state code that CiA 301 does not define.
    Unknown(u8),
}

impl ErrorControl {
    /// The node and what it said, if `frame` is an error-control data frame.
    pub fn parse(frame: &Frame) -> Option<(u8, ErrorControl)> {
        let node = frame.id().checked_sub(0x700).filter(|n| (1..=127).contains(n))? as u8;
        // A remote frame has no data.
        let &[b] = frame.data() else { return None };
        let toggle = b & 0x80 != 0;
        let ec = match State::from_code(b & 0x7F) {
            Some(State::Initialising) if !toggle => ErrorControl::BootUp,
            Some(state) => ErrorControl::State { state, toggle },
            None => ErrorControl::Unknown(b),
        };
        Some((node, ec))
    }

    /// The NMT state this message shows: a boot-up, pre-operational (the node has just
    /// started, CiA 301 §7.3.2); none for a code CiA 301 does not define. The one place
    /// that mapping is made.
    pub fn state(self) -> Option<State> {
        match self {
            ErrorControl::BootUp => Some(State::PreOperational),
            ErrorControl::State { state, .. } => Some(state),
            ErrorControl::Unknown(_) => None,
        }
    }

    /// The message as `node` sends it on its error-control COB-ID.
    pub fn frame(self, node: u8) -> Frame {
        let b = match self {
            ErrorControl::BootUp => 0,
            ErrorControl::State { state, toggle } => state.code() | (toggle as u8) << 7,
            ErrorControl::Unknown(b) => b,
        };
        Frame::new(error_control_cob(node), &[b])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn command_frames() {
        assert_eq!(Command::Stop.frame(5).to_string(), "000#0205");
        assert_eq!(Command::ResetNode.frame(0).to_string(), "000#8100");
        assert_eq!(Command::parse(&"000#8205".parse().unwrap()), Some((Command::ResetCommunication, 5)));
        assert_eq!(Command::parse(&"000#0305".parse().unwrap()), None);
    }

    #[test]
    fn heartbeat_and_guarding() {
        // Seed 004: heartbeat 0x701 with 7F = pre-operational.
        let (node, ec) = ErrorControl::parse(&"701#7F".parse().unwrap()).unwrap();
        assert_eq!((node, ec), (1, ErrorControl::State { state: State::PreOperational, toggle: false }));
        // Seed 003: SERS guarding answer with the toggle bit set, operational.
        let (_, ec) = ErrorControl::parse(&"720#85".parse().unwrap()).unwrap();
        assert_eq!(ec, ErrorControl::State { state: State::Operational, toggle: true });
        assert_eq!(ErrorControl::parse(&"705#00".parse().unwrap()), Some((5, ErrorControl::BootUp)));
        assert_eq!(ErrorControl::parse(&"705#R1".parse().unwrap()), None);
        assert_eq!(ErrorControl::parse(&"700#00".parse().unwrap()), None);
        assert_eq!(ErrorControl::parse(&"705#33".parse().unwrap()), Some((5, ErrorControl::Unknown(0x33))));
        let state = |f: &str| ErrorControl::parse(&f.parse().unwrap()).and_then(|(_, ec)| ec.state());
        assert_eq!(state("705#00"), Some(State::PreOperational), "a boot-up: just started");
        assert_eq!(state("705#85"), Some(State::Operational));
        assert_eq!(state("705#04"), Some(State::Stopped));
        assert_eq!(state("705#33"), None);
        assert_eq!(ErrorControl::State { state: State::Stopped, toggle: true }.frame(32).to_string(), "720#84");
    }
}
