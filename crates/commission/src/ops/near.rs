//! What to suggest for an object a node does not have: the dictionary's objects near it
//! that the node has.

use super::dictionaries::Dictionaries;
use crate::bus::{Bus, SdoOptions};
use crate::canopen::abort::{NO_OBJECT, NO_SUBINDEX};
use crate::canopen::ObjAddr;
use crate::error::Error;
use std::time::Duration;

/// The objects of `node`'s dictionary nearest to `obj` that the node has: other objects
/// when the object itself is missing (`object_missing`), else its other sub-indices. Each
/// is asked for once, whether the node has it, not its value (a large one is not read
/// whole), for the dictionary may list objects this node lacks (a TPDO2, say).
pub(crate) fn present_near(
    bus: &mut dyn Bus,
    dicts: &Dictionaries,
    node: u8,
    obj: ObjAddr,
    object_missing: bool,
    timeout: Duration,
) -> Vec<ObjAddr> {
    let opts = SdoOptions { max_upload: 64, ..SdoOptions::new(timeout) };
    let lacks = |r: crate::Result<Vec<u8>>| {
        matches!(r, Err(Error::SdoAbort { code: NO_OBJECT | NO_SUBINDEX, .. } | Error::NoAnswer { .. }))
    };
    dicts.near(node, obj, object_missing).into_iter().filter(|a| !lacks(bus.sdo_upload(node, *a, &opts))).collect()
}
