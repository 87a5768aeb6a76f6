//! `firmware status`: what a node's CiA 302-3 program-download objects say of each program.

use super::download::le;
use crate::bus::Bus;
use crate::canopen::abort;
use crate::canopen::program::{self, Control, FlashStatus, FLASH_STATUS, PROGRAM_CONTROL, SOFTWARE_ID};
use crate::canopen::ObjAddr;
use crate::error::Error;
use serde::Serialize;
use std::time::Duration;

/// One program's objects, as `firmware status` shows them.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[non_exhaustive]
pub struct ProgramStatus {
    /// The program number (sub-index).
    pub program: u8,
    /// Its program control (0x1F51); none when it could not be read.
    pub control: Option<Control>,
    /// What that control value says of the program, in words.
    pub control_meaning: Option<&'static str>,
    /// Its software identification (0x1F56); none when it could not be read.
    pub software_id: Option<u32>,
    /// Its flash status (0x1F57); none when it could not be read.
    pub flash_status: Option<FlashStatus>,
}

/// `firmware status NODE`: per program number the device has.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[non_exhaustive]
pub struct StatusReport {
    /// The node-id.
    pub node: u8,
    /// One entry per program the device has (0x1F51:0 of them).
    pub programs: Vec<ProgramStatus>,
}

/// Read 0x1F51, 0x1F56 and 0x1F57 for each program the device has (0x1F51:0 says how
/// many; a device without it has no program download).
pub fn status(bus: &mut dyn Bus, node: u8, timeout: Duration) -> crate::Result<StatusReport> {
    let opts = crate::ops::sdo_options::sized(timeout, Some(1));
    let count = match bus.sdo_upload(node, ObjAddr::new(PROGRAM_CONTROL, 0), &opts) {
        Ok(v) => v.first().copied().unwrap_or(0),
        Err(Error::SdoAbort { code: abort::NO_OBJECT, .. }) => return Err(Error::NoBootloader { node }),
        Err(e) => return Err(e),
    };
    let mut programs = Vec::new();
    for p in 1..=count {
        let read = |bus: &mut dyn Bus, index: u16, size: usize| -> crate::Result<Option<u32>> {
            match bus.sdo_upload(node, program::object(index, p), &crate::ops::sdo_options::sized(timeout, Some(size)))
            {
                Ok(v) => Ok(Some(le(&v))),
                Err(Error::SdoAbort { .. }) => Ok(None),
                Err(e) => Err(e),
            }
        };
        let control = read(bus, PROGRAM_CONTROL, 1)?.map(|v| Control::from_code(v as u8));
        programs.push(ProgramStatus {
            program: p,
            control,
            control_meaning: control.map(Control::state_meaning),
            software_id: read(bus, SOFTWARE_ID, 4)?,
            flash_status: read(bus, FLASH_STATUS, 4)?.map(FlashStatus::decode),
        });
    }
    Ok(StatusReport { node, programs })
}
