//! What the user can do about an error, as a typed remedy: the library says *which*
//! remedy fits, a front end says it in its own terms (the command line names its flags and
//! commands, `output/hints.rs`; a program may offer a button). An error's own message says
//! what happened and names no flag.

use crate::canopen::lss::{FastscanError, Identity};
use crate::error::{DriveStop, Error, LinkError, Service};

/// A remedy for an error, for the front end to word.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Hint {
    /// A node-id asked for is in use: choose a free one (a scan lists those in use), or
    /// give it anyway (the command's force option).
    FreeNodeIdOrForce,
    /// The node keeps no description of itself: give one from its vendor (an EDS for the
    /// node).
    GiveEds,
    /// LSS assignment ran out of node-ids from its first one: start lower.
    LowerStart,
    /// A configuration file names another device: apply it anyway (the force option).
    ForceOtherDevice,
    /// A reset node did not answer after it: check the node (a scan), or wait longer.
    CheckOrWaitLonger,
    /// Whether an LSS device took its node-id is unknown: inquire it by its identity.
    InquireNodeId(Identity),
    /// A drive is in fault: reset the fault once its cause is gone.
    FaultReset,
    /// A fault reset left the drive in fault: read its errors (drive status).
    DriveErrors,
    /// A fastscan step went unconfirmed: try again, or with a longer step.
    LongerStep,
    /// What a node holds is not of the data type taken: name another type.
    OtherType,
    /// A TPDO asked for is not there: leave the choice out, and every TPDO there is taken.
    EveryTpdo,
    /// No TPDO is valid: map one for the session.
    MapOne,
    /// Several LSS devices answered what is for one: address one by its identity (a
    /// fastscan finds them).
    AddressOne,
    /// The simulator's network is held by another process: stop that one, or serve the
    /// network on a CAN interface, where several commands share it.
    ShareSimNetwork,
    /// The process holding the sim network serves its devices: the bus it serves them on.
    UseServedBus {
        /// The `--bus` value that reaches them.
        bus: String,
    },
    /// There is no network interface `iface`: the one of a `near` name (the demo network's or
    /// one of the `available` CAN interfaces), set one up (an adapter, a virtual bus), or use
    /// the demo network.
    SetUpInterface {
        /// The interface asked for.
        iface: String,
        /// A name one or two letters from it (`sim` or an available interface), if any.
        near: Option<String>,
        /// The CAN interfaces this machine has.
        available: Vec<String>,
    },
    /// No SocketCAN on this OS: the simulated bus works anywhere.
    TrySim,
    /// A serial CAN adapter (`port`, its bus address) sees frames nobody acknowledges: give
    /// the bus's bit rate in its address.
    AdapterBitRate {
        /// The adapter's bus address, as it names itself (`slcan:/dev/ttyACM0@250k`).
        port: String,
    },
    /// The size of an object to map could not be learnt by reading it: a dictionary gives
    /// its type.
    MapReadsSize,
    /// A value has no type to be encoded with: name one, or give a dictionary.
    NameType,
    /// LSS on an EPOS2 reached directly: its own objects do set-id, set-baud and store,
    /// and LSS reaches the devices behind it.
    Epos2OwnObjects,
    /// An EPOS2 reached directly takes a new bit rate once stored: store it.
    StoreEpos2,
    /// A device's flash stayed busy past the wait: wait longer.
    LongerBusyWait,
    /// A node of a network project did not answer, and its DCF names this LSS identity:
    /// give it its node-id over LSS (the project apply's assign option).
    AssignOverLss(Identity),
    /// A node of a network project did not answer, and its DCF names no LSS serial number:
    /// assigning its node-id over LSS cannot find it.
    NoIdentityToAssign,
    /// An EPOS2 serial command got no fitting answer in time: a slow device may need a
    /// longer timeout.
    SlowDevice,
    /// An SDO transfer did not finish within its deadline, which follows from its size and
    /// this timeout (per request): a longer timeout gives it more.
    DeadlineFromTimeout(std::time::Duration),
    /// An upload was stopped at the limit of bytes taken from a device: raise the limit.
    RaiseUploadLimit,
    /// A device missed the switch back to LSS waiting state: a scan lists the devices left
    /// in configuration state.
    ScanForConfiguring,
    /// A device stays in LSS configuration state: a scan lists it; power-cycle it if it
    /// stays there.
    ScanThenPowerCycle,
    /// A configuration file breaks CiA 306 so that its values are not all read: checking
    /// the file lists its errors.
    CheckFile(String),
    /// An EDS was given where a DCF (an EDS with values) is needed: a dump of the device
    /// makes one.
    DumpDcf,
    /// A node's SDO server is stuck: reset the node and read again.
    ResetNodeAndReadAgain {
        /// The node-id.
        node: u8,
    },
    /// The simulator's state file is unusable as it is: start a fresh network.
    FreshSimNetwork,
    /// A node on the bus answers no SDO, as a Stopped node does: put it in
    /// Pre-operational, where it answers.
    PreOperational {
        /// The node-id.
        node: u8,
    },
    /// A node logged errors in its history (0x1003): read them, with their meanings.
    ReadErrorHistory {
        /// The node-id.
        node: u8,
    },
    /// Whether a reset node booted is not known: its NMT state says.
    ReadNmtState {
        /// The node-id.
        node: u8,
    },
    /// What a node was told to load applies from its next reset: reset it.
    ResetNode {
        /// The node-id.
        node: u8,
    },
    /// A node's parameters were left changed: loading its stored ones (0x1011, a
    /// restore) puts them back.
    RestoreStored {
        /// The node-id.
        node: u8,
    },
}

impl Hint {
    /// The remedy for `error` (looked for under any hint string it carries), if one fits.
    pub fn of(error: &Error) -> Option<Hint> {
        match error {
            Error::Advised { error, .. } => Hint::of(error),
            Error::TpdoNotPutBack { node, .. } => Some(Hint::RestoreStored { node: *node }),
            Error::NodeIdInUse { .. } => Some(Hint::FreeNodeIdOrForce),
            Error::NoStoredEds { .. } => Some(Hint::GiveEds),
            Error::NoFreeNodeId { .. } => Some(Hint::LowerStart),
            Error::OtherDevice { .. } => Some(Hint::ForceOtherDevice),
            Error::NoAnswer { what: Service::AfterReset, .. } => Some(Hint::CheckOrWaitLonger),
            Error::LssSetIdUnknown { identity, .. } | Error::LssStillConfiguring { identity, .. } => {
                Some(Hint::InquireNodeId(*identity))
            }
            Error::DriveStopped { why: DriveStop::FaultPresent, .. } => Some(Hint::FaultReset),
            Error::DriveStopped { why: DriveStop::FaultRemains, .. } => Some(Hint::DriveErrors),
            Error::Fastscan { error: FastscanError::Unconfirmed(_), .. } => Some(Hint::LongerStep),
            Error::NotOfType { .. } => Some(Hint::OtherType),
            Error::NoSuchTpdo { .. } => Some(Hint::EveryTpdo),
            Error::NoValidTpdo { .. } => Some(Hint::MapOne),
            Error::InquiryAnsweredByMany { .. } => Some(Hint::AddressOne),
            Error::Link(LinkError::SimInUse { serving: Some(bus), .. }) => {
                Some(Hint::UseServedBus { bus: bus.clone() })
            }
            Error::Link(LinkError::SimInUse { serving: None, .. }) => Some(Hint::ShareSimNetwork),
            Error::Link(LinkError::NoInterface { iface, available }) => Some(Hint::SetUpInterface {
                iface: iface.clone(),
                near: near_interface(iface, available),
                available: available.clone(),
            }),
            Error::NoSocketCan { .. } => Some(Hint::TrySim),
            Error::NothingAnswered { error } => match error.root() {
                Error::Link(LinkError::AdapterBusError { port, .. }) => {
                    Some(Hint::AdapterBitRate { port: port.clone() })
                }
                e => Hint::of(e),
            },
            Error::MapSizeUnread { .. } => Some(Hint::MapReadsSize),
            Error::TypeNeeded { .. } => Some(Hint::NameType),
            Error::NoLssOnDirectEpos2 { .. } => Some(Hint::Epos2OwnObjects),
            Error::Epos2RateOnStore => Some(Hint::StoreEpos2),
            Error::NoAnswer { what: Service::ProjectNode { lss: Some(id) }, .. } => Some(Hint::AssignOverLss(*id)),
            Error::NoAnswer { what: Service::ProjectNode { lss: None }, .. } => Some(Hint::NoIdentityToAssign),
            Error::Link(LinkError::Epos2(crate::epos2::Epos2Error::Serial { failure, retry, .. }))
                if retry.as_ref().unwrap_or(failure).may_be_slow() =>
            {
                Some(Hint::SlowDevice)
            }
            Error::SdoUnfinished { why: crate::error::Unfinished::Deadline { timeout, .. }, .. } => {
                Some(Hint::DeadlineFromTimeout(*timeout))
            }
            // The SDO client aborts with "out of memory" only at the upload limit.
            Error::Link(LinkError::SdoProtocol { aborted: Some(crate::canopen::abort::OUT_OF_MEMORY), .. })
            | Error::Link(LinkError::UploadOverLimit { .. }) => Some(Hint::RaiseUploadLimit),
            Error::LssCrowded { .. } => Some(Hint::ScanForConfiguring),
            Error::LssLeftInConfiguration { .. } => Some(Hint::ScanThenPowerCycle),
            Error::DcfNotReadWhole { file, .. } => Some(Hint::CheckFile(file.clone())),
            Error::NotADcf { .. } => Some(Hint::DumpDcf),
            Error::Link(LinkError::Epos2(crate::epos2::Epos2Error::Answer {
                problem: crate::epos2::Epos2Problem::EmptySegments { node, .. },
                ..
            })) => Some(Hint::ResetNodeAndReadAgain { node: *node }),
            Error::Link(LinkError::StateFile { afresh: true, .. }) => Some(Hint::FreshSimNetwork),
            _ => None,
        }
    }
}

/// An error kept in a report row (a write that failed, a node that did not answer): its
/// message and its remedy, typed, for the front end to word after the message.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub struct Failure {
    /// The error's message, without the advice added to it.
    pub message: String,
    /// Its remedy, if one fits.
    pub hint: Option<Hint>,
    /// Advice the library added to the error, which follows the remedy (`; did you mean ...`).
    pub then: String,
}

impl From<&Error> for Failure {
    fn from(error: &Error) -> Failure {
        match error {
            // As `output::library_error_text` words it: the remedy before the advice.
            Error::Advised { error, advice } => {
                let mut f = Failure::from(&**error);
                f.then.push_str(&advice.to_string());
                f
            }
            e => Failure { message: e.to_string(), hint: Hint::of(e), then: String::new() },
        }
    }
}

/// The error's own message (as it displays), without the remedy.
impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}{}", self.message, self.then)
    }
}

/// The name one or two letters from `iface` (`sims`, `cna0`): `sim` or an interface that
/// exists, the nearest first.
fn near_interface(iface: &str, available: &[String]) -> Option<String> {
    std::iter::once("sim")
        .chain(available.iter().map(String::as_str))
        .map(|c| (crate::od::names::distance(iface, c), c))
        .filter(|(d, c)| *d <= 2 && *d < c.len())
        .min()
        .map(|(_, c)| c.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sim network held by another command: the remedy is to serve it where several share it.
    #[test]
    fn a_sim_network_in_use_is_answered_with_the_way_to_share_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sim.json");
        let _held = crate::sim::state::StateFile::lock_within(&path, std::time::Duration::ZERO).unwrap();
        let err = crate::sim::state::StateFile::lock_within(&path, std::time::Duration::from_millis(50)).err().unwrap();
        assert_eq!(Hint::of(&err), Some(Hint::ShareSimNetwork), "{err}");
    }

    #[test]
    fn the_remedy_is_found_under_a_hint_string() {
        let e = Error::NoStoredEds { node: 5 };
        assert_eq!(Hint::of(&e), Some(Hint::GiveEds));
        assert_eq!(Hint::of(&e.advised(crate::error::Advice::PortTaken)), Some(Hint::GiveEds));
        assert_eq!(Hint::of(&Error::Interrupted), None);
        // The message itself names no flag: the front end adds that.
        assert!(!Error::NoStoredEds { node: 5 }.to_string().contains("--"));
    }
}
