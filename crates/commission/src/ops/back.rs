//! A node back after a reset: one policy for every command that resets a node and goes on
//! with it (network apply's reset, firmware download's program start, an LSS-given
//! node-id).
//!
//! Where the link shows the bus's traffic, a node is back at its boot-up message (CiA 301:
//! the first thing a node sends once it can communicate). Through a gateway that passes on
//! answers only (an EPOS2), it is back when it answers an SDO read of 0x1000 again, an
//! abort included: it asks nothing of the device, and every CANopen device has 0x1000.

use crate::bus::Bus;
use crate::bus::SdoOptions;
use crate::cancel::Cancel;
use crate::canopen::ObjAddr;
use crate::error::{Error, Result};
use std::collections::BTreeMap;
use std::time::Duration;

/// The pause between two reads of a node that is not back yet, where a read ends at once
/// (a gateway that reports the node's silence without waiting).
const POLL: Duration = Duration::from_millis(20);

/// Forget the boot-ups seen of `nodes`: call it before sending what resets them, so that
/// [`wait_back`] waits for the boot-up that follows, not one from before.
pub(crate) fn forget_boot_ups(bus: &mut dyn Bus, nodes: &[u8]) {
    for n in nodes {
        bus.observed().boot_ups.remove(n);
    }
}

/// Wait until each of `nodes`, reset (its boot-up forgotten first, [`forget_boot_ups`]),
/// is back, for `wait` at most in all: which came back. Through a link without traffic each
/// read waits `answer_wait`. `cancel`, when given, ends the wait with
/// [`Error::Interrupted`].
pub(crate) fn wait_back(
    bus: &mut dyn Bus,
    nodes: &[u8],
    wait: Duration,
    answer_wait: Duration,
    cancel: Option<&Cancel>,
) -> Result<BTreeMap<u8, bool>> {
    if bus.sees_traffic() {
        until_booted(bus, nodes, wait, cancel)
    } else {
        let deadline = bus.now() + wait;
        nodes.iter().map(|&n| Ok((n, until_answering(bus, n, deadline, answer_wait, cancel)?))).collect()
    }
}

/// Each node's boot-up, as the bus's observer notes it, within `wait`.
fn until_booted(
    bus: &mut dyn Bus,
    nodes: &[u8],
    wait: Duration,
    cancel: Option<&Cancel>,
) -> Result<BTreeMap<u8, bool>> {
    let deadline = bus.now() + wait;
    let booted = |bus: &mut dyn Bus| -> BTreeMap<u8, bool> {
        nodes.iter().map(|n| (*n, bus.observed().boot_ups.contains(n))).collect()
    };
    loop {
        let back = booted(bus);
        if back.values().all(|b| *b) {
            return Ok(back);
        }
        check(cancel)?;
        // A boot-up that came with the deadline (seen while the bus was busy) still counts.
        if bus.recv_frame(deadline)?.is_none() && bus.now() >= deadline {
            return Ok(booted(bus));
        }
    }
}

/// Whether `node` answers a read of 0x1000 (an abort too) before `deadline`.
pub(crate) fn until_answering(
    bus: &mut dyn Bus,
    node: u8,
    deadline: std::time::Instant,
    answer_wait: Duration,
    cancel: Option<&Cancel>,
) -> Result<bool> {
    // One request at a time: the next read is the retry.
    let opts = SdoOptions { retries: 0, stop: cancel.cloned(), ..SdoOptions::new(answer_wait) };
    loop {
        check(cancel)?;
        match bus.sdo_upload(node, ObjAddr::DEVICE_TYPE, &opts) {
            Ok(_) | Err(Error::SdoAbort { .. }) => return Ok(true),
            Err(e) if e.is_timeout() => {}
            Err(e) => return Err(e),
        }
        let now = bus.now();
        if now >= deadline {
            return Ok(false);
        }
        bus.sleep_until(deadline.min(now + POLL))?;
    }
}

fn check(cancel: Option<&Cancel>) -> Result<()> {
    cancel.map_or(Ok(()), Cancel::check)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canopen::nmt::Command;
    use crate::sim::test_bus as bus;

    /// A reset node is back at its boot-up; an id nobody holds is not, and the wait for it
    /// ends at its bound.
    #[test]
    fn a_reset_node_is_back_at_its_boot_up_and_an_absent_one_within_the_bound() {
        let mut bus = bus();
        let wait = Duration::from_secs(2);
        forget_boot_ups(&mut bus, &[5, 44]);
        bus.nmt(Command::ResetNode, 5).unwrap();
        bus.nmt(Command::ResetNode, 44).unwrap();
        let start = bus.now();
        let back = wait_back(&mut bus, &[5, 44], wait, Duration::from_millis(100), None).unwrap();
        assert_eq!(back, BTreeMap::from([(5, true), (44, false)]));
        assert!(bus.now() - start <= wait + Duration::from_millis(5), "{:?}", bus.now() - start);
    }

    /// A boot-up seen before the reset does not count: forgotten, the wait is for the next.
    #[test]
    fn a_boot_up_from_before_the_reset_is_not_taken_for_the_node_being_back() {
        let mut bus = bus();
        bus.observed().boot_ups.insert(10);
        forget_boot_ups(&mut bus, &[10]);
        let back = wait_back(&mut bus, &[10], Duration::from_millis(300), Duration::from_millis(100), None).unwrap();
        assert!(!back[&10], "nothing reset it");
    }

    /// Through a link without traffic, the node's answering again: the sim's node answers.
    #[test]
    fn a_node_answering_again_is_back_where_no_boot_up_can_be_seen() {
        let mut bus = bus();
        let deadline = bus.now() + Duration::from_millis(500);
        assert!(until_answering(&mut bus, 5, deadline, Duration::from_millis(100), None).unwrap());
        let deadline = bus.now() + Duration::from_millis(300);
        assert!(!until_answering(&mut bus, 44, deadline, Duration::from_millis(100), None).unwrap());
    }
}
