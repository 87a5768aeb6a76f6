//! CiA 302-3 program download (`canctl firmware`): the sequence field practice calls for,
//! each step confirmed, and a report that says where the device is when it ends, however
//! it ends.
//!
//! The device is the reference: an erase outlasts any SDO timeout (the flash status is
//! polled, bounded), a device may reboot into its bootloader when told to stop and resets
//! before it answers "start" (program control is an action: never repeated blindly, its
//! outcome read back by the bus, then the boot-up decides), and a new program may ask to be
//! confirmed (0x1F51 reads 0x80).

mod download;
mod each;
mod jobs;
mod status;
pub(crate) mod step;
pub use download::{
    download, DownloadOptions, DownloadReport, Failed, FirmwareError, State, StepDone, Transfer, Where,
};
pub use each::{download_each, Batch, NodeDownload, Unfinished};
pub use jobs::download_jobs;
pub use status::{status, ProgramStatus, StatusReport};
pub use step::{DownloadEnd, Step};
