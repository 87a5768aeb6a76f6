//! Scan a bus and read every node's identity (0x1018) through the library:
//! `cargo run --example identities` on a fresh simulated demo network, or
//! `cargo run --example identities -- socketcan:can0` on another bus.

use canctl::bus::Bus;
use canctl::connect::{self, BusAddr, OpenOptions};
use canctl::ops::node::{Identity, Node};
use canctl::ops::{scan, Silent};
use std::time::Duration;

/// Every node that answers on `bus`, with its identity (`None`: the node has no 0x1018).
pub fn identities(bus: &mut dyn Bus, timeout: Duration) -> canctl::Result<Vec<(u8, Option<Identity>)>> {
    let found = scan::probe(bus, timeout, &mut Silent)?;
    found.iter().map(|&(id, _)| Ok((id, Node::new(bus, id, timeout).identity()?))).collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let addr: BusAddr = std::env::args().nth(1).as_deref().unwrap_or("sim").parse()?;
    let mut opts = OpenOptions::new(Duration::from_millis(500));
    opts.ephemeral = true; // the simulator starts afresh and keeps no state file
    let mut bus = connect::open(&addr, &opts)?;
    let result = identities(bus.as_mut(), opts.timeout);
    bus.close()?;
    let hex = |v: Option<u32>| v.map_or("-".to_string(), |v| format!("0x{v:08X}"));
    for (node, id) in result? {
        match id {
            Some(id) => println!(
                "node {node:3}: vendor 0x{:08X} product {} revision {} serial {}",
                id.vendor,
                hex(id.product),
                hex(id.revision),
                hex(id.serial)
            ),
            None => println!("node {node:3}: no identity object (0x1018)"),
        }
    }
    Ok(())
}
