//! canctl: commission CANopen devices over SocketCAN, maxon EPOS2 serial links, or a
//! simulated bus. The binary is a thin shell over this library.
//!
//! The layers at the bottom are crates of their own (`crates/`), re-exported here under their
//! old names: `canctl-canopen` ([`canopen`], [`frame`]: the protocol, no I/O), `canctl-od`
//! ([`od`], [`input`]: dictionaries and their files), `canctl-bus` ([`bus`], [`backend`],
//! [`epos2`], [`slcan`], [`socketcand`], [`cancel`], [`error`], [`serial`], [`trace`]: the bus
//! API, its backends and the error type) and `canctl-sim` ([`sim`], but for `sim::serve`:
//! the simulated devices and bus). The compiler holds their order; a library user who needs
//! only them depends on them alone.
//!
//! # Layers
//!
//! Each layer may use the ones below it, never one above nor a sibling; the order is
//! [`LAYERS`], checked by `tests/suite/layers.rs`. Top first (a row may group layers that
//! [`LAYERS`] keeps apart: `cli` over `output`, `ops` over `settings`):
//!
//! | layer | what |
//! |---|---|
//! | `cli`, `output` (feature `cli`) | clap definitions, one file per command: parse the arguments, call one operation, render its report; `output` is the one renderer (table, JSON, CSV, JSON lines; each report's human form in `output/`) and turns [`ops::Progress`] into progress bars |
//! | [`ops`], [`settings`] | the procedures (scan, SDO read/write, NMT with confirmation, LSS, config dump/diff/apply, store/restore, PDO remap and stream, monitor): functions over `&mut dyn Bus` returning serialisable reports; no printing, no clap. `settings` resolves flags, `CANCTL_BUS` and `canctl.toml` once, each value with its source |
//! | `sim::serve` | the simulated network as a service, behind a CAN interface, a pty or a socketcand server |
//! | [`connect`] | [`connect::BusAddr`] (`FromStr` + `Display`) and [`connect::open`], the only place that names every backend |
//! | [`sim`] (crate `canctl-sim`) | the device side: virtual CANopen nodes, the demo network as a `FrameLink`, the EPOS2 and slcan serial devices |
//! | `atomic`, `hint` | files written whole or not at all; the remedies the front end words |
//! | crate `canctl-bus`: [`backend`], [`bus`], [`cancel`], [`error`], [`epos2`], [`slcan`], [`socketcand`], [`serial`], [`trace`] | the links (SocketCAN, slcan, socketcand, the EPOS2 gateway); the [`bus::Bus`] service API, [`bus::Master`] over a [`bus::FrameLink`], clock and decorators; the one request to stop; the library's [`Error`] and exit codes; the serial and network protocols; diagnostics as `tracing` events. Its own `LAYERS` order them |
//! | [`od`] (crate `canctl-od`) | object dictionaries, EDS/DCF read and write, object names |
//! | [`canopen`] (crate `canctl-canopen`), [`input`] (in `canctl-od`) | pure protocol: SDO state machines, LSS, NMT, PDO mapping, EMCY, data types — no I/O; bounded reads of input files |
//! | [`frame`] (in `canctl-canopen`), `xdg` | the CAN frame; where state and cache files live |
//!
//! # Where things go
//!
//! - **A new command**: its procedure in `ops/` (a function over a `Bus`, a report struct
//!   deriving `serde::Serialize`, progress through `ops::Progress`), its `output::Report`
//!   impl (the human and CSV forms) in `src/output/`, then `src/cli/<name>.rs` with the clap
//!   arguments, and one line in `cli::Command` and `cli::run`.
//! - **A new backend**: a `FrameLink` (raw frames, served by `Master`) or a `Bus` of its
//!   own (as the EPOS2 gateway) in `crates/bus/src/backend/`, a variant of `BusAddr` with its
//!   `FromStr`/`Display` forms (round-trip tested), and its arm in `connect::open`. Nothing
//!   above `connect` changes.
//! - **A new protocol detail**: pure code in `crates/canopen/`, unit-tested with byte vectors.
//!
//! `cargo build --lib --no-default-features` builds the library without the command line;
//! `examples/provision.rs` applies a DCF through it.

// Without the command line (`--no-default-features`), the crate-private helpers that only
// the commands call have no caller: that is not dead code.
#![cfg_attr(not(feature = "cli"), allow(dead_code))]
// Every public item says what it is for (issue 28): an item not meant for users of the
// library is `pub(crate)`, the rest have a doc, and an item without one does not build.
#![deny(missing_docs)]

/// The layers of the library, top first. A module may use the modules of the layers below its
/// own, never one above, nor a sibling of its own layer: so there is no cycle. An entry names a
/// module; a longer entry places a submodule apart from its parent. `tests/suite/layers.rs` reads the
/// `crate::` paths of every source file and holds the code to this order (test modules are
/// exempt: they may drive the code under test with a simulator).
pub const LAYERS: &[&[&str]] = &[
    &["cli"],
    &["output"],
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

pub(crate) mod atomic;
pub use canctl_canopen as canopen;
#[cfg(feature = "cli")]
pub mod cli;
pub mod connect;
pub use canctl_canopen::frame;
pub use canctl_od as od;
pub use canctl_od::input;
pub mod ops;
#[cfg(feature = "cli")]
pub mod output;
pub mod settings;
pub mod sim;
pub(crate) mod xdg;

pub use canctl_bus::{backend, bus, cancel, epos2, error, serial, slcan, socketcand, trace};
pub use error::{Error, Result};
