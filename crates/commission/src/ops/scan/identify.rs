//! A scan's second phase: each node found is asked who it is (identity, name, heartbeat
//! period), and a node that answered the probe but not that is asked alone, to tell a node
//! that fell silent from another device's answer on its COB-ID.

use super::report::{Node, Scan};
use crate::bus::Bus;
use crate::canopen::sdo::response_cob;
use crate::canopen::{DataType, ObjAddr};
use crate::error::{Error, Result};
use crate::ops::answers_elsewhere::{self, AnswersElsewhere};
use crate::ops::event::Warning;
use crate::ops::progress::Progress;
use crate::ops::values::as_u32;
use std::time::Duration;

/// Read each node's identity, name and heartbeat period. The vendor-ID first, of every node
/// at once: a node that answers not even that (it timed out) is asked nothing more, and is
/// returned with its error for [`confirm_silent`], unsaid.
pub(super) fn identify(
    bus: &mut dyn Bus,
    nodes: &mut [Node],
    timeout: Duration,
    progress: &mut dyn Progress,
) -> Result<Vec<(u8, Error)>> {
    progress.start("identity", (nodes.len() * 6) as u64);
    // The name is a string: one that never ends stops at the name's limit, not after 1 MiB.
    let opts = crate::ops::sdo_options::capped(timeout, crate::ops::sdo_options::NAME_LIMIT);
    let first: Vec<(u8, ObjAddr)> = nodes.iter().map(|f| (f.node, ObjAddr::VENDOR_ID)).collect();
    let answers = bus.sdo_upload_many(&first, &opts, &mut |n| progress.advance(n as u64))?;
    let mut silent = Vec::new();
    let mut stopped = false;
    let mut answered = Vec::new();
    for (read, answer) in first.iter().zip(answers) {
        match answer {
            Err(e) if e.is_timeout() => silent.push((read.0, e)),
            answer => {
                answered.push(read.0);
                stopped |= record(nodes, read, answer, progress);
            }
        }
    }
    if !stopped {
        let parts = ObjAddr::IDENTITY_PARTS[1..].iter().copied().chain([ObjAddr::DEVICE_NAME, ObjAddr::HEARTBEAT_TIME]);
        let rest: Vec<(u8, ObjAddr)> =
            answered.iter().flat_map(|&node| parts.clone().map(move |a| (node, a))).collect();
        let done = first.len() as u64;
        let answers = bus.sdo_upload_many(&rest, &opts, &mut |n| progress.advance(done + n as u64))?;
        for (read, answer) in rest.iter().zip(answers) {
            stopped |= record(nodes, read, answer, progress);
        }
    }
    progress.finish();
    (!stopped).then_some(silent).ok_or(Error::Interrupted)
}

/// One identity read's answer, into its node; whether it says the user asked to stop.
fn record(
    nodes: &mut [Node],
    (node, addr): &(u8, ObjAddr),
    value: Result<Vec<u8>>,
    progress: &mut dyn Progress,
) -> bool {
    let f = nodes.iter_mut().find(|f| f.node == *node).expect("read for a found node");
    match value {
        Ok(bytes) if *addr == ObjAddr::DEVICE_NAME => f.name = DataType::Vs.decode(&bytes).map(|v| v.to_string()),
        Ok(bytes) if *addr == ObjAddr::HEARTBEAT_TIME => {
            f.heartbeat_ms = bytes.get(..2).map(|b| u16::from_le_bytes([b[0], b[1]]))
        }
        Ok(bytes) => {
            *match *addr {
                ObjAddr::VENDOR_ID => &mut f.vendor_id,
                ObjAddr::PRODUCT_CODE => &mut f.product_code,
                ObjAddr::REVISION_NUMBER => &mut f.revision,
                _ => &mut f.serial,
            } = as_u32(&bytes)
        }
        Err(Error::SdoAbort { .. }) => {}
        Err(e) if e.is_interrupted() => return true,
        Err(error) => progress.event(Warning::Failed { node: None, error }.into()),
    }
    false
}

/// The nodes that answered the probe but not their identity (`silent`, with the read's
/// error), each asked alone: an answer on its own COB-ID keeps it (the error is said), on
/// another keeps it as answering elsewhere. Silent alone, the other node-ids are asked
/// without it: an answer on its COB-ID then is another device's, and it is not there; none
/// means it answered for itself and fell silent since (kept, the error said). Where the
/// link shows no traffic the probe asked one node at a time: its answers were the nodes' own.
pub(super) fn confirm_silent(
    bus: &mut dyn Bus,
    report: &mut Scan,
    silent: Vec<(u8, Error)>,
    window: Duration,
    progress: &mut dyn Progress,
) -> Result<()> {
    for (node, error) in silent {
        let own = response_cob(node);
        let alone = match bus.sees_traffic() {
            true => answers_elsewhere::ask_alone(bus, node, window)?,
            false => Some(own),
        };
        match alone {
            Some(cob_id) if cob_id != own => report.answers_elsewhere.push(AnswersElsewhere { node, cob_id }),
            None if answers_elsewhere::answered_by_another(bus, node, window)? => {
                report.nodes.retain(|n| n.node != node);
                report.not_there.push(node);
            }
            _ => progress.event(Warning::Failed { node: None, error }.into()),
        }
    }
    Ok(())
}
