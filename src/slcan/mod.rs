//! Serial-line CAN adapters ("slcan", the Lawicel ASCII protocol): CANUSB, CANable, USBtin
//! and their clones, on any OS that has a serial port.

pub mod link;
pub mod wire;

pub use link::SlcanLink;
