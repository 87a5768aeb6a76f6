//! canctl: commission CANopen devices over SocketCAN, maxon EPOS2 serial links, or a
//! simulated bus. The binary is a thin shell over this library.
//!
//! # Layers
//!
//! Each layer may use the ones below it, never one above:
//!
//! | layer | what | may depend on |
//! |---|---|---|
//! | `cli`, `output` (feature `cli`) | clap definitions, one file per command: parse the arguments, call one operation, render its report; `output` is the one renderer (table, JSON, CSV, JSON lines; each report's human form in `output/`) and turns [`ops::Progress`] into progress bars | everything below; clap, indicatif, comfy-table, anyhow |
//! | [`ops`], [`settings`] | the procedures (scan, SDO read/write, NMT with confirmation, LSS, config dump/diff/apply, store/restore, PDO remap and stream, monitor): functions over `&mut dyn Bus` returning serialisable reports; which dictionary describes a node (`ops::dictionaries`) and the last scan of each bus (`ops::scan_cache`); no printing, no clap. `settings` resolves flags, `CANCTL_BUS` and `canctl.toml` once, each value with its source | `bus`, `canopen`, `od`, `frame`, `error`; `settings` also toml |
//! | [`bus`] | the [`bus::Bus`] service API and the `FrameLink` trait; [`bus::BusAddr`] (`FromStr` + `Display`); `Master` (CANopen client over a `FrameLink`); the one factory [`bus::open`], the only place that names the backends | `canopen`, `frame`, `error`; `open` also `sim` and `epos2` |
//! | [`epos2`] | pure framing and CRC, the two serial transports, the gateway that implements `Bus` | `bus` (the trait), `canopen`, `frame`, `error` |
//! | [`sim`] | the device side: virtual CANopen nodes, the demo network as a `FrameLink`, the EPOS2 serial device; `sim::serve` puts them behind an interface or a pty | `bus` (the trait), `canopen`, `od`, `epos2`, `frame` |
//! | [`od`] | object dictionaries, EDS/DCF read and write, object names | `canopen` |
//! | [`cancel`] | the one request to stop ([`cancel::Cancel`]), taken by every procedure and bus wrapper that heeds it | `error` |
//! | [`canopen`] | pure protocol: SDO state machines, LSS, NMT, PDO mapping, EMCY, data types — no I/O | `frame`, `error` |
//!
//! # Where things go
//!
//! - **A new command**: its procedure in `ops/` (a function over a `Bus`, a report struct
//!   deriving `serde::Serialize`, progress through `ops::Progress`), its `output::Report`
//!   impl (the human and CSV forms) in `src/output/`, then `src/cli/<name>.rs` with the clap
//!   arguments, and one line in `cli::Command` and `cli::run`.
//! - **A new backend**: a `FrameLink` (raw frames, served by `Master`) or a `Bus` of its
//!   own (as the EPOS2 gateway), a variant of `BusAddr` with its `FromStr`/`Display` forms
//!   (round-trip tested), and its arm in `bus::open`. Nothing above `bus` changes.
//! - **A new protocol detail**: pure code in `canopen/`, unit-tested with byte vectors.
//!
//! `cargo build --lib --no-default-features` builds the library without the command line;
//! `examples/provision.rs` applies a DCF through it.

pub mod atomic;
pub mod bus;
pub mod cancel;
pub mod canopen;
#[cfg(feature = "cli")]
pub mod cli;
pub mod error;
pub mod frame;
pub mod hint;
pub mod input;
pub mod od;
pub mod ops;
#[cfg(feature = "cli")]
pub mod output;
pub mod settings;
pub mod sim;
pub mod slcan;
pub mod xdg;

pub use error::{Error, Result};
pub mod epos2;
