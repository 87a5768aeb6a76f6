//! The simulated devices on a real CAN interface: every frame from the interface goes to
//! the devices, everything they send goes out on it.

use super::SimLink;
use crate::bus::{FrameLink, FrameLog};
use crate::error::Result;
use crate::trace::{self, Dir};
use std::time::Duration;

/// Serve until the link fails or the process is stopped. Each frame on the interface goes
/// to the frame trace and to `log`: what came in is received, what the devices answer is
/// sent, seen from this side of the interface.
pub fn run(sim: SimLink, can: &mut dyn FrameLink, log: Option<FrameLog>) -> Result<()> {
    let mut sim = sim.devices_only();
    let iface = can.name();
    let seen = |dir: Dir, f: &crate::frame::Frame| {
        trace::frame(&iface, dir, f);
        if let Some(log) = &log {
            log.record(&iface, f);
        }
    };
    loop {
        let wake = sim.next_event().unwrap_or_else(|| sim.now() + Duration::from_secs(1));
        if let Some(f) = can.recv(wake)? {
            seen(Dir::Rx, &f);
            sim.send(&f)?;
        }
        // The answers to that frame, and any heartbeats that fell due: all there is now,
        // sent together (a block upload's segments leave in one write over socketcand).
        let mut out = Vec::new();
        while let Some(f) = sim.recv(sim.now())? {
            seen(Dir::Tx, &f);
            out.push(f);
        }
        can.send_all(&out)?;
        sim.save_if_changed()?;
    }
}
