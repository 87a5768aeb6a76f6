//! CANopen as bytes and state: CAN frames, and the CiA 301, 305, 302-3 and 402 protocol units
//! (SDO, LSS, NMT and node guarding, EMCY, PDO mapping, program download, the drive state
//! machine) as pure parse/emit codecs and state machines. No I/O and no clock: time is
//! passed in, so every edge case is a unit test on virtual time. canctl's bus, simulator and
//! procedures are built on it; a library user builds it without serial ports, netlink or
//! settings files.
//!
//! The layer below everything else in canctl: it uses no other canctl crate.

// Every public item says what it is for; an item not meant for users is `pub(crate)`.
#![deny(missing_docs)]

pub mod frame;

pub mod abort;
pub mod cia402;
pub mod emcy;
pub mod lss;
pub mod nmt;
pub mod number;
pub mod objaddr;
pub mod pdo;
pub mod program;
pub mod sdo;
pub mod types;

pub use objaddr::ObjAddr;
pub use types::DataType;
