//! maxon EPOS2 serial protocol (seeds 000 and 002): frames, commands, transports, and the
//! gateway that offers the `Bus` services through them.

pub mod command;
pub mod frame;
pub mod gateway;
pub mod transport;
