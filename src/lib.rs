//! canctl: commission CANopen devices over SocketCAN, maxon EPOS2 serial links, or a
//! simulated bus. The binary is a thin shell over this library.

pub mod bus;
pub mod canopen;
pub mod cli;
pub mod error;
pub mod frame;
pub mod od;
pub mod output;
pub mod sim;
pub mod slcan;
pub mod xdg;

pub use error::{Error, Result};
pub mod epos2;
