//! Serial-line CAN adapters ("slcan", the Lawicel ASCII protocol): CANUSB, CANable, USBtin
//! and their clones, on any OS that has a serial port: the line protocol. The link that
//! speaks it is [`crate::backend::slcan::SlcanLink`].

pub mod wire;
