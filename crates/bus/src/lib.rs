//! A CANopen bus, one API over every link: the [`bus::Bus`] trait (SDO, NMT, LSS, PDO,
//! EMCY, guarding and heartbeats as services), [`bus::Master`] (the CANopen client over a
//! [`bus::FrameLink`] of raw frames), the links ([`backend`]: SocketCAN, slcan adapters,
//! socketcand, and the maxon EPOS2 gateway, a `Bus` of its own), their wire protocols
//! ([`epos2`], [`slcan`], [`socketcand`]), the frame log and the decorators of a bus, the one
//! request to stop ([`cancel::Cancel`]), and canctl's [`Error`] with its exit classes.
//!
//! Above `canctl-canopen` (the protocol) and `canctl-od` (dictionaries), below canctl's
//! simulator and procedures: nothing here knows the simulator, a settings file or a
//! command.

// Every public item says what it is for; an item not meant for users is `pub(crate)`.
#![deny(missing_docs)]

/// The layers of this crate, top first, as `canctl::LAYERS` orders the library's: a module
/// may use the modules of the layers below its own, never one above nor a sibling (checked
/// by canctl's `tests/suite/layers.rs`). The last rows are the crates below, by the names
/// the modules use.
pub const LAYERS: &[&[&str]] = &[
    &["backend"],
    &["bus"],
    &["cancel"],
    &["error"],
    &["epos2", "slcan", "socketcand"],
    &["od"],
    &["canopen", "input", "trace"],
    &["frame", "serial"],
];

// The layers below, under the names the modules use (`crate::canopen::...`).
use canctl_canopen as canopen;
use canctl_canopen::frame;
use canctl_od as od;
use canctl_od::input;

pub mod backend;
pub mod bus;
pub mod cancel;
pub mod epos2;
pub mod error;
pub mod serial;
pub mod slcan;
pub mod socketcand;
pub mod trace;

pub use error::{Error, Result};
