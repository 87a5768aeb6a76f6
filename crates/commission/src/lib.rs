//! The commissioning library of canctl: the procedures a technician runs on a CANopen bus
//! (scan, SDO, NMT with confirmation, LSS, config dump/diff/apply, store/restore, PDO remap
//! and stream, monitor, health, doctor, network projects, firmware download), each a
//! function over `&mut dyn Bus` that takes its options and returns a typed, serialisable
//! report; no printing, no command line. canctl's binary is a thin shell over it.
//!
//! The layers below are crates of their own, re-exported here under their names in canctl:
//! `canctl-canopen` ([`canopen`], [`frame`]: the protocol, no I/O), `canctl-od` ([`od`],
//! [`input`]: dictionaries and their files), `canctl-bus` ([`bus`], [`backend`], [`epos2`],
//! [`slcan`], [`socketcand`], [`cancel`], [`error`], [`serial`], [`trace`]: the bus API, its
//! backends and the error type) and `canctl-sim` ([`sim`], but for `sim::serve`: the
//! simulated devices and bus).
//!
//! # Layers
//!
//! Each layer may use the ones below it, never one above nor a sibling; the order is
//! [`LAYERS`], checked by `tests/suite/layers.rs`. Top first:
//!
//! | layer | what |
//! |---|---|
//! | [`ops`] | the procedures: options in, typed reports out; progress through [`ops::Progress`]; verdicts ([`ops::unmet`]) beside the library's [`Error`] |
//! | [`settings`] | flags, `CANCTL_BUS` and `canctl.toml` resolved once, each value with its source |
//! | [`sim::serve`] | the simulated network as a service, behind a CAN interface, a pty or a socketcand server |
//! | [`connect`] | [`connect::BusAddr`] (`FromStr` + `Display`) and [`connect::open`], the only place that names every backend |
//! | [`sim`] (crate `canctl-sim`) | the device side: virtual CANopen nodes, the demo network as a `FrameLink`, the EPOS2 and slcan serial devices |
//! | `atomic` | files written whole or not at all |
//! | crate `canctl-bus` | the links, the [`bus::Bus`] service API, [`bus::Master`], the one request to stop, the library's [`Error`] and exit classes |
//! | [`od`] (crate `canctl-od`) | object dictionaries, EDS/DCF/XDD read and write, object names |
//! | [`canopen`] (crate `canctl-canopen`), [`input`] | pure protocol; bounded reads of input files |
//! | [`frame`], `xdg` | the CAN frame; where state and cache files live |
//!
//! A new procedure goes in `ops/`: a function over a `Bus` and a report struct deriving
//! `serde::Serialize`; the command line words it (`src/output/` of the `canctl` crate).
//! `examples/provision.rs` applies a DCF through this library.

// Every public item says what it is for (issue 28): an item not meant for users of the
// library is `pub(crate)`, the rest have a doc, and an item without one does not build.
#![deny(missing_docs)]

/// The layers of the library, top first. A module may use the modules of the layers below its
/// own, never one above, nor a sibling of its own layer: so there is no cycle. An entry names a
/// module; a longer entry places a submodule apart from its parent. `tests/suite/layers.rs` reads the
/// `crate::` paths of every source file and holds the code to this order (test modules are
/// exempt: they may drive the code under test with a simulator).
pub const LAYERS: &[&[&str]] = &[
    &["ops"],
    &["settings"],
    &["sim::serve"],
    &["connect"],
    &["sim"],
    &["atomic"],
    // The crate canctl-bus, whose own `LAYERS` order these among themselves.
    &["backend", "bus", "cancel", "error", "epos2", "slcan", "socketcand", "serial", "trace"],
    &["od"],
    &["canopen", "input"],
    &["frame", "xdg"],
];

pub mod atomic;
pub use canctl_canopen as canopen;
pub mod connect;
pub use canctl_canopen::frame;
pub use canctl_od as od;
pub use canctl_od::input;
pub mod ops;
pub mod settings;
pub mod sim;
pub(crate) mod xdg;

pub use canctl_bus::{backend, bus, cancel, epos2, error, serial, slcan, socketcand, trace};
pub use error::{Error, Result};
