//! What a procedure tells a person while it runs, beside its progress: typed events, so
//! that the procedure decides *what* happened and the front end (`output/events.rs` for the
//! command line) decides how to say it. They reach the caller through
//! [`Progress::event`](super::progress::Progress::event), the one observer of a procedure.

use super::nmt::StateFrom;
use crate::canopen::lss::Identity;
use crate::canopen::nmt::State;
use crate::canopen::ObjAddr;
use std::time::Duration;

/// A remark of a procedure under way.
#[derive(Debug)]
pub enum Event {
    /// Something is not as it should be; the procedure went on without it.
    Warning(Warning),
    /// Worth knowing; nothing is wrong.
    Notice(Notice),
}

/// Something not as it should be, passed over so that the rest could be done.
#[derive(Debug)]
pub enum Warning {
    /// A node (or, without one, a device) answered with an error that was not a refusal or
    /// silence; what it had to say is left out.
    Failed {
        /// The node asked, when one was.
        node: Option<u8>,
        /// What went wrong.
        error: crate::Error,
    },
    /// A TPDO came with another length than its mapping makes: not decoded (said once per
    /// TPDO).
    PdoLength {
        /// The node that sent it.
        node: u8,
        /// The TPDO's number (1 to 512).
        pdo: u16,
        /// The COB-ID it came on.
        cob_id: u32,
        /// Bytes it came with.
        got: usize,
        /// Bytes its mapping makes.
        want: usize,
    },
    /// SYNC was asked for, but a TPDO is event-driven: SYNC does not make it send.
    SyncDoesNotDrive {
        /// The node whose TPDO it is.
        node: u8,
        /// The TPDO's number.
        pdo: u16,
        /// Its transmission type (254 or 255).
        transmission: u8,
    },
    /// A deviation from CiA 306/311 in a file that was read (with file:line and the rule).
    File(crate::od::lint::Warning),
    /// A global bit-rate activation is about to switch the devices that took the last global
    /// set-baud while those that refused it stay at the old rate.
    ActivationStrands {
        /// The rate the last global set-baud asked for (`125k`).
        rate: String,
        /// Devices that refused it.
        refused: usize,
        /// Devices that took it.
        confirmed: usize,
    },
}

/// Something worth a person's knowing, while all is well.
#[derive(Debug)]
pub enum Notice {
    /// A TPDO whose COB-ID is marked invalid: left out.
    PdoInvalid {
        /// The node whose TPDO it is.
        node: u8,
        /// The TPDO's number.
        pdo: u16,
        /// Its communication object (0x1800 + pdo - 1).
        comm: u16,
        /// The COB-ID entry as read (bit 31 set).
        cob: u32,
    },
    /// The device refused to show an object (an SDO abort other than "no such object").
    Refused {
        /// The object.
        addr: ObjAddr,
        /// The abort code.
        code: u32,
    },
    /// A value no file of this form can hold was left out of it.
    LeftOut {
        /// The object.
        addr: ObjAddr,
        /// The file's form: "DCF", "XDC".
        file: &'static str,
        /// Why it cannot be written, as the writer says it.
        why: String,
    },
    /// A stream has heard nothing from its node for a while; it goes on listening.
    Silent {
        /// The node listened to.
        node: u8,
        /// How long it has been silent.
        after: Duration,
        /// Why it may be, as the procedure found it.
        why: Vec<Silence>,
    },
    /// A device found over LSS was given a node-id.
    Assigned {
        /// The device.
        identity: Identity,
        /// Its node-id now.
        node: u8,
    },
}

impl From<Warning> for Event {
    fn from(w: Warning) -> Event {
        Event::Warning(w)
    }
}

impl From<Notice> for Event {
    fn from(n: Notice) -> Event {
        Event::Notice(n)
    }
}

/// Why a stream may hear nothing from its node, for the front end to say.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Silence {
    /// The node is not operational (`state`, learned by `source`): it sends no PDO; the
    /// stream can start it.
    NotOperational {
        /// The node-id.
        node: u8,
        /// Its state.
        state: State,
        /// How the state was learned.
        source: StateFrom,
    },
    /// The node's state could not be learned: it may not be operational.
    StateUnknown {
        /// The node-id.
        node: u8,
    },
    /// A synchronous TPDO (transmission type `kind`) and no SYNC sent: it waits for SYNC.
    WaitsForSync {
        /// The TPDO's number (1 for TPDO1).
        pdo: u16,
        /// Its transmission type.
        kind: u8,
    },
    /// A TPDO sent only on request (RTR, transmission type 252 or 253).
    OnRequest {
        /// The TPDO's number (1 for TPDO1).
        pdo: u16,
        /// Its transmission type.
        kind: u8,
    },
    /// An event-driven TPDO (254 or 255) with SYNC sent: SYNC does not make it send.
    SyncDoesNotDrive {
        /// The TPDO's number (1 for TPDO1).
        pdo: u16,
        /// Its transmission type.
        kind: u8,
    },
    /// An event-driven TPDO without an event timer: it sends when its values change.
    NoEventTimer {
        /// The TPDO's number (1 for TPDO1).
        pdo: u16,
    },
    /// Nothing found against it: the node may have nothing to say.
    NothingFound,
}
