//! Everything `stream-pdo` does before its first record: a TPDO remapped for the stream,
//! the node started, the TPDO layouts read, and why the stream may stay silent. The
//! changes go into a [`Session`], which puts them back however the stream ends.

use super::nmt::{self, StateOptions};
use super::pdo::{self, Remap, Session};
use super::progress::Progress;
use super::silence::{self, Silence};
use crate::bus::Bus;
use crate::canopen::pdo::Layout;
use crate::canopen::ObjAddr;
use crate::error::Result;
use crate::od::{Dictionary, Entry};
use std::time::Duration;

/// What the stream is of.
#[derive(Debug)]
pub struct Setup<'a> {
    /// The node streamed.
    pub node: u8,
    /// The TPDOs asked for; empty: TPDO1 to TPDO4, those the node lacks left out.
    pub tpdo: &'a [u16],
    /// Objects to map into the first TPDO for the stream (none: the mapping as it is),
    /// with their dictionary entries where the dictionary has them.
    pub map: Vec<(ObjAddr, Option<&'a Entry>)>,
    /// The remapped TPDO's event timer, in ms.
    pub event: Option<u16>,
    /// The remapped TPDO's transmission type.
    pub transmission: Option<u8>,
    /// Put the node in Operational for the stream.
    pub start: bool,
    /// The SYNC period the stream will send, if any.
    pub sync: Option<Duration>,
    /// For each answer.
    pub timeout: Duration,
}

/// The stream, ready to run.
#[derive(Debug)]
pub struct Prepared {
    /// Each TPDO streamed, with its layout.
    pub layouts: Vec<(u16, Layout)>,
    /// How long the stream may be silent before it is worth saying, and why it may be.
    pub silence: (Duration, Vec<Silence>),
}

/// Remap, start and read the layouts as `setup` asks, each change kept in `session`.
pub fn prepare(
    bus: &mut dyn Bus,
    dict: &Dictionary,
    setup: &Setup,
    session: &mut Session,
    progress: &mut dyn Progress,
) -> Result<Prepared> {
    let node = setup.node;
    let state_options = StateOptions { listen: Duration::from_millis(300), timeout: setup.timeout };
    let list: Vec<u16> = if setup.tpdo.is_empty() { (1..=4).collect() } else { setup.tpdo.to_vec() };
    if !setup.map.is_empty() {
        let bits = |&(addr, entry)| Ok((addr, pdo::mapped_bits(bus, node, addr, entry, setup.timeout)?));
        let objects = setup.map.iter().map(bits).collect::<Result<Vec<_>>>()?;
        let remap = Remap { tpdo: list[0], objects, event: setup.event, transmission: setup.transmission };
        session.remap(bus, node, &remap, setup.timeout)?;
    }
    if setup.start {
        let state = nmt::state(bus, node, &state_options)?.state;
        session.start(bus, node, state)?;
    }
    let list = if setup.map.is_empty() { &list[..] } else { &list[..1] };
    let layouts = pdo::read_layouts(bus, node, dict, list, setup.tpdo.is_empty(), setup.timeout, progress)?;
    let state = (!setup.start).then(|| nmt::state(bus, node, &state_options));
    let (silence, warnings) = silence::hint(bus, node, &layouts, state, setup.sync, setup.timeout);
    for w in warnings {
        progress.event(w.into());
    }
    Ok(Prepared { layouts, silence })
}
