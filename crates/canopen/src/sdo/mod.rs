//! SDO (CiA 301 §7.2.4): expedited, segmented and block transfer, as pure state machines.
//!
//! Both sides take a received 8-byte payload and return the payloads to send; the caller
//! owns the link, the clock and the timeouts.

pub mod client;
pub mod retry;
pub mod server;
mod shared;
pub mod wire;

pub use client::{SdoClient, SdoError, Step};
pub use server::{ObjectAccess, SdoServer};
pub use shared::{abort_frame, pad, request_cob, response_cob, MAX_BLOCK_SIZE};
pub use wire::SEGMENT_DATA;

#[cfg(test)]
mod tests;
