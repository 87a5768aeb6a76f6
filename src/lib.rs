//! canctl: commission CANopen devices over SocketCAN, maxon EPOS2 serial links, or a
//! simulated bus. The binary is a thin shell over this library.
//!
//! The layers at the bottom are crates of their own (`crates/`), re-exported here under their
//! old names: `canctl-canopen` ([`canopen`], [`frame`]: the protocol, no I/O) and `canctl-od`
//! ([`od`], [`input`]: dictionaries and their files). The compiler holds their order; a
//! library user who needs only them depends on them alone.
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
//! | [`sim`] | the device side: virtual CANopen nodes, the demo network as a `FrameLink`, the EPOS2 and slcan serial devices |
//! | [`backend`] | the links: SocketCAN, slcan, socketcand (`FrameLink`s served by [`bus::Master`]), the EPOS2 gateway (a `Bus` of its own) |
//! | [`bus`] | the [`bus::Bus`] service API, the [`bus::FrameLink`] trait, [`bus::Master`] (CANopen client over a `FrameLink`), clock, and the decorators (observer, tap, stop, frame log) |
//! | [`cancel`], `atomic` | the one request to stop ([`cancel::Cancel`]); files written whole or not at all |
//! | [`error`] | the library's [`Error`], wrapping the lower layers' errors; exit codes |
//! | [`epos2`], [`slcan`], [`socketcand`] | the serial and network protocols: pure framing, CRC, commands; EPOS2's two transports |
//! | [`od`] (crate `canctl-od`) | object dictionaries, EDS/DCF read and write, object names |
//! | [`canopen`] (crate `canctl-canopen`), [`input`] (in `canctl-od`), `trace` | pure protocol: SDO state machines, LSS, NMT, PDO mapping, EMCY, data types — no I/O; bounded reads of input files; diagnostics as `tracing` events |
//! | [`frame`] (in `canctl-canopen`), [`serial`], `xdg` | the CAN frame; the serial port the serial backends use; where state and cache files live |
//!
//! # Where things go
//!
//! - **A new command**: its procedure in `ops/` (a function over a `Bus`, a report struct
//!   deriving `serde::Serialize`, progress through `ops::Progress`), its `output::Report`
//!   impl (the human and CSV forms) in `src/output/`, then `src/cli/<name>.rs` with the clap
//!   arguments, and one line in `cli::Command` and `cli::run`.
//! - **A new backend**: a `FrameLink` (raw frames, served by `Master`) or a `Bus` of its
//!   own (as the EPOS2 gateway) in `backend/`, a variant of `BusAddr` with its
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
    &["backend"],
    &["bus"],
    &["cancel", "atomic", "hint"],
    &["error"],
    &["epos2", "slcan", "socketcand"],
    &["od"],
    &["canopen", "input", "trace"],
    &["frame", "serial", "xdg"],
];

pub(crate) mod atomic;
pub mod backend;
pub mod bus;
pub mod cancel;
pub use canctl_canopen as canopen;
#[cfg(feature = "cli")]
pub mod cli;
pub mod connect;
pub mod error;
pub use canctl_canopen::frame;
pub(crate) mod hint;
pub use canctl_od as od;
pub use canctl_od::input;
pub mod ops;
#[cfg(feature = "cli")]
pub mod output;
pub mod serial;
pub mod settings;
pub mod sim;
pub mod slcan;
pub mod socketcand;
pub(crate) mod trace;
pub(crate) mod xdg;

pub use error::{Error, Result};
pub mod epos2;
