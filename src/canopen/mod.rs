//! Pure CANopen protocol code: no I/O, no clocks.

pub mod abort;
pub mod cia402;
pub(crate) mod emcy;
pub mod lss;
pub mod nmt;
pub mod number;
pub(crate) mod objaddr;
pub mod pdo;
pub mod program;
pub mod sdo;
pub mod types;

pub use objaddr::ObjAddr;
pub use types::DataType;
