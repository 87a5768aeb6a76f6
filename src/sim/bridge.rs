//! The simulated devices on a real CAN interface: every frame from the interface goes to
//! the devices, everything they send goes out on it.

use super::SimLink;
use crate::bus::FrameLink;
use crate::error::Result;
use std::time::{Duration, Instant};

/// Serve until the link fails or the process is stopped. `trace` prints each frame.
pub fn run(mut sim: SimLink, can: &mut dyn FrameLink, trace: bool) -> Result<()> {
    let iface = can.name();
    loop {
        let wake = sim.next_event().unwrap_or_else(|| Instant::now() + Duration::from_secs(1));
        if let Some(f) = can.recv(wake)? {
            if trace {
                eprintln!("{}", f.candump_line(&iface));
            }
            sim.send(&f)?;
        }
        // The answers to that frame, and any heartbeats that fell due.
        while let Some(out) = sim.recv(Instant::now())? {
            if trace {
                eprintln!("{}", out.candump_line(&iface));
            }
            can.send(&out)?;
        }
        sim.save_if_changed()?;
    }
}
