//! canctl: commission CANopen devices over SocketCAN, slcan adapters, maxon EPOS2 serial
//! links, socketcand, or a simulated bus. This crate is the command line: `cli` (the clap
//! definitions, one file per command: parse the arguments, call one procedure, render its
//! report) and `output` (the one renderer: tables, JSON, CSV, JSON lines, JUnit; every
//! report's human form, every error's words and remedy, progress bars). The procedures are
//! the library `canctl-commission`, re-exported here under the names its modules have
//! there ([`ops`], [`settings`], [`connect`], [`sim`], ...), as are the layers below it.
//!
//! # Layers
//!
//! `cli` over `output` over the library; the library's own order is
//! `canctl_commission::LAYERS`, each crate's under it its own. `tests/suite/layers.rs`
//! holds both, the compiler the order of the crates.
//!
//! # Where things go
//!
//! - **A new command**: its procedure in `crates/commission/src/ops/` (a function over a
//!   `Bus`, a report struct deriving `serde::Serialize`, progress through `ops::Progress`),
//!   its `output::Report` impl (the human and CSV forms) in `src/output/`, then
//!   `src/cli/<name>.rs` with the clap arguments, and one line in `cli::Command` and
//!   `cli::run`.
//! - **A new backend**: a `FrameLink` (raw frames, served by `Master`) or a `Bus` of its
//!   own (as the EPOS2 gateway) in `crates/bus/src/backend/`, a variant of `BusAddr` with its
//!   `FromStr`/`Display` forms (round-trip tested), and its arm in `connect::open`. Nothing
//!   above `connect` changes.
//! - **A new protocol detail**: pure code in `crates/canopen/`, unit-tested with byte vectors.
//!
//! `cargo build --lib --no-default-features` builds this crate as the library's re-exports
//! alone; a program that needs only the procedures depends on `canctl-commission`.

// Every public item says what it is for (issue 28).
#![deny(missing_docs)]

/// The front end's layers, top first, over the library's (`canctl_commission::LAYERS`): a
/// module may use the ones below it, never one above; `tests/suite/layers.rs` holds it.
pub const LAYERS: &[&[&str]] = &[&["cli"], &["output"]];

#[cfg(feature = "cli")]
pub mod cli;
#[cfg(feature = "cli")]
pub mod output;

pub use canctl_commission::{
    atomic, backend, bus, cancel, canopen, connect, epos2, error, frame, input, od, ops, serial, settings, sim, slcan,
    socketcand, trace, Error, Result,
};
