//! Layer setting services (CiA 305): node-ids and bit rates for devices that have none or
//! share one. Pure, by concern: `wire` (frames, with byte vectors), `sequences` (the
//! services made of several requests), `fastscan` (the search's state machine), `policy`
//! (what is done when answers go missing or come late, in one place) and `slave` (the
//! device side, for the simulator). The I/O driving is `bus::lss`.

mod fastscan;
mod policy;
mod sequences;
mod slave;
mod wire;

pub use fastscan::*;
pub use policy::*;
pub use sequences::*;
pub use slave::*;
pub use wire::*;
