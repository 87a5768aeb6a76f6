//! The service-level API every command is written against ([`Bus`]), the raw frame link the
//! CAN backends provide ([`FrameLink`]), the CANopen client over such a link ([`Master`]), and
//! the decorators that observe, trace or stop a bus. The backends are in [`crate::backend`];
//! canctl's `connect` opens one from a bus address.

mod api;
pub mod clock;
pub mod controller;
pub(crate) mod frame_log;
pub mod lss;
pub(crate) mod master;
pub mod observer;
pub mod reply;
pub mod stoppable;
pub mod tap;
#[cfg(test)]
pub(crate) mod timeline;

pub use crate::trace;
pub use api::{
    one_by_one, Bus, FrameLink, LssAnswer, LssExchange, LssWait, SdoJob, SdoOptions, TransferHook, ALL_NODES,
};
pub use frame_log::FrameLog;
pub use master::Master;
pub use observer::{Asked, Observed, SeenBy};
