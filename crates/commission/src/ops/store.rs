//! Store and restore parameters: CiA 301 objects 0x1010 ('save') and 0x1011 ('load').

use super::sdo_options::sized;
use super::values::{as_text, le_u32};
use crate::bus::Bus;
use crate::canopen::ObjAddr;
use crate::error::{Advice, Error, ParameterCommand, Result, StoreRefusal};
use serde::Serialize;
use std::time::Duration;

/// Which parameters (the 0x1010/0x1011 subindex).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[non_exhaustive]
pub enum Class {
    /// All parameters (sub 1)
    All,
    /// Communication parameters, 0x1000..0x1FFF (sub 2)
    Comm,
    /// Application parameters, 0x6000..0x9FFF (sub 3)
    App,
    /// Manufacturer parameters, 0x2000..0x5FFF (sub 4)
    Mfr,
}

impl Class {
    fn sub(self) -> u8 {
        self as u8 + 1
    }

    /// The class in words (`all parameters`, ...).
    pub fn text(self) -> &'static str {
        ["all parameters", "communication parameters", "application parameters", "manufacturer parameters"]
            [self as usize]
    }
}

/// How long to wait: `answer` for the checks, `write` for the device to store or restore
/// (flash writes take a while).
#[derive(Clone, Copy, Debug)]
pub struct Timeouts {
    /// For each SDO answer.
    pub answer: Duration,
    /// For the device to store or restore (it writes its flash meanwhile).
    pub write: Duration,
}

/// Parameters saved to non-volatile memory.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Stored {
    /// The node-id.
    pub node: u8,
    /// Which parameters.
    #[serde(rename = "stored", serialize_with = "class_text")]
    pub class: Class,
    /// The sub-index written (0x1010:N).
    #[serde(serialize_with = "as_text")]
    pub object: ObjAddr,
}

/// Defaults brought back; they apply from the next reset on.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Restored {
    /// The node-id.
    pub node: u8,
    /// Which parameters.
    #[serde(rename = "restored", serialize_with = "class_text")]
    pub class: Class,
    /// The sub-index written (0x1011:N).
    #[serde(serialize_with = "as_text")]
    pub object: ObjAddr,
    /// Whether the node was reset afterwards and booted with them (the caller does it).
    pub reset: bool,
    /// The reset was sent but could not be confirmed (through an EPOS2): why not, for the
    /// front end to word (in JSON too).
    #[serde(skip)]
    pub reset_unconfirmed: Option<super::nmt::Unconfirmed>,
}

fn class_text<S: serde::Serializer>(c: &Class, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(c.text())
}

/// Write 'save' to 0x1010, once the device says it can store `class` on command.
pub fn store(bus: &mut dyn Bus, node: u8, class: Class, t: Timeouts) -> Result<Stored> {
    let object = signature(bus, node, ParameterCommand::Store, class, t)?;
    Ok(Stored { node, class, object })
}

/// Write 'load' to 0x1011, once the device says it can restore `class` on command.
pub fn restore(bus: &mut dyn Bus, node: u8, class: Class, t: Timeouts) -> Result<Restored> {
    let object = signature(bus, node, ParameterCommand::Restore, class, t)?;
    Ok(Restored { node, class, object, reset: false, reset_unconfirmed: None })
}

/// Check that the device can do this on command, then write the signature
/// ('save' and 'load' as they travel, CiA 301 7.5.2.13/14).
fn signature(bus: &mut dyn Bus, node: u8, command: ParameterCommand, class: Class, t: Timeouts) -> Result<ObjAddr> {
    let (index, bytes) = match command {
        ParameterCommand::Store => (0x1010, b"save"),
        ParameterCommand::Restore => (0x1011, b"load"),
    };
    let highest = match bus.sdo_upload(node, ObjAddr::new(index, 0), &sized(t.answer, Some(1))) {
        Ok(v) => v.first().copied().unwrap_or(0),
        Err(e) if super::node::lacks_index(&e) => {
            return Err(Error::StoreRefused { node, command, why: StoreRefusal::NoObject { index } });
        }
        Err(e) => return Err(e),
    };
    let addr = ObjAddr::new(index, class.sub());
    if class.sub() > highest {
        let offered = [Class::All, Class::Comm, Class::App, Class::Mfr]
            .iter()
            .filter(|c| c.sub() <= highest)
            .map(|c| c.text())
            .collect();
        let why = StoreRefusal::NotOffered { class: class.text(), index, highest, offered };
        return Err(Error::StoreRefused { node, command, why });
    }
    let caps = le_u32(&bus.sdo_upload(node, addr, &sized(t.answer, Some(4)))?);
    // Bit 0: the device does this on command. (For 0x1010 bit 1 means it saves on its own.)
    if caps & 1 == 0 {
        let saves_itself = command == ParameterCommand::Store && caps & 2 != 0;
        let why = StoreRefusal::NotOnCommand { class: class.text(), obj: addr, caps, saves_itself };
        return Err(Error::StoreRefused { node, command, why });
    }
    // An action, sent once: with its answer lost, whether it was done is unknown.
    bus.sdo_download(node, addr, bytes, &sized(t.write, Some(4))).map_err(|e| match e {
        Error::NoAnswer { .. } | Error::SdoUnfinished { .. } | Error::SdoOutcomeUnknown { .. } => {
            e.advised(Advice::SentOnce { node, command })
        }
        e => e,
    })?;
    Ok(addr)
}
