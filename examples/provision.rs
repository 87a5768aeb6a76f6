//! Provision a node from a DCF, the way a CI script or a production-line tool would use
//! the library: open the bus, apply the file (writing only what differs, PDOs in the safe
//! order), read every written value back, store the parameters, print the report.
//!
//! `cargo run --example provision` runs it against a fresh simulated demo network (in
//! memory: no state file is read or kept). Pass a bus address to use another bus:
//! `cargo run --example provision -- socketcan:can0`.

use canctl::connect::{self, BusAddr, OpenOptions};
use canctl::ops::config::{self, ApplyOptions, Dcf};
use canctl::ops::node::Node;
use std::time::Duration;

/// The demo network's position sensor.
const NODE: u8 = 5;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let addr: BusAddr = std::env::args().nth(1).as_deref().unwrap_or("sim").parse()?;
    let mut opts = OpenOptions::new(Duration::from_millis(500));
    opts.ephemeral = true;
    let dcf = Dcf::parse(include_bytes!("sensor.dcf"), "examples/sensor.dcf")?;

    let mut bus = connect::open(&addr, &opts)?;
    // The device before anything is written (apply itself refuses a DCF for another kind).
    match Node::new(bus.as_mut(), NODE, opts.timeout).identity()? {
        Some(id) => {
            let product = id.product.map_or("none".to_string(), |p| format!("0x{p:08X}"));
            println!("node {NODE}: vendor-ID 0x{:08X}, product code {product}", id.vendor)
        }
        None => println!("node {NODE}: no identity object (0x1018)"),
    }
    let mut apply = ApplyOptions::new(opts.timeout);
    apply.verify = true;
    apply.store = true;
    let result = config::apply(bus.as_mut(), NODE, &dcf, &apply);
    bus.close()?;
    let report = result?;

    println!("node {} on {addr}, from {}:", report.node, report.file);
    for change in &report.objects {
        println!(
            "  {:<9} {:<50} {:>6} -> {:<6} {}",
            change.object.to_string(),
            change.name,
            change.old,
            change.new,
            change.result // a typed Outcome, shown as its sentence
        );
    }
    println!("stored: {}", report.stored);
    println!("{}", serde_json::to_string_pretty(&report)?);
    // A write that failed, or a value that read back otherwise, ends here with its error.
    report.outcome()?;
    Ok(())
}
