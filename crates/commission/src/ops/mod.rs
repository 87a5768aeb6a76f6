//! The commissioning procedures, as functions over a [`Bus`](crate::bus::Bus): each takes
//! what the user asked for, talks to the devices, and returns a typed report (serialisable,
//! so that any front end can render it). Progress and remarks go through [`Progress`]; a
//! procedure never prints and knows nothing of the command line.

pub use event::{Event, Notice, Warning};
pub use progress::{ItemEnd, ItemStatus, Progress, Silent};
pub use stop::{install_interrupt_plan, InterruptPoint};

pub mod answers_elsewhere;
pub(crate) mod back;
pub mod buses;
pub mod check;
pub mod clash;
pub mod completion;
pub mod config;
pub mod counted;
pub mod dictionaries;
pub mod doctor;
pub mod drive;
pub mod errors;
pub(crate) mod event;
pub mod explain;
pub mod failure;
pub mod firmware;
pub mod health;
pub(crate) mod in_parallel;
pub mod lss;
pub mod many_buses;
pub mod monitor;
pub(crate) mod near;
pub mod network;
pub mod nmt;
pub mod node;
pub mod pdo;
pub(crate) mod progress;
pub mod project_files;
pub mod scan;
pub mod scan_cache;
pub mod sdo;
pub(crate) mod sdo_options;
pub mod silence;
pub mod stop;
pub mod store;
pub mod store_all;
pub mod stored_eds;
pub mod stream_setup;
pub(crate) mod unheard;
pub mod unmet;
pub(crate) mod values;
pub mod verdict;
