//! LSS on the simulated bus: a fastscan of one device, and `assign` of 8 devices without
//! node-ids, with the default 10 ms step. `cargo bench --bench lss`.

use canctl::bus::lss::LssMaster;
use canctl::bus::Master;
use canctl::sim::profiles::position_sensor;
use canctl::sim::{Network, SimLink};
use std::collections::BTreeSet;
use std::time::{Duration, Instant};

const STEP: Duration = Duration::from_millis(10);

fn unconfigured(n: u32) -> Master<SimLink> {
    let devices = (0..n).map(|i| (position_sensor(0x0950_2000 + i * 0x1111), None)).collect();
    Master::new(SimLink::of(Network::of(devices)), "sim".into(), false)
}

fn main() {
    let mut times = Vec::new();
    let mut steps = 0;
    for _ in 0..5 {
        let mut bus = unconfigured(1);
        let mut lss = LssMaster::new(&mut bus, Duration::from_millis(100));
        let t = Instant::now();
        let (_, n) = lss.fastscan(STEP).unwrap().unwrap();
        times.push(t.elapsed());
        steps = n;
    }
    times.sort();
    println!(
        "fastscan of one device: {steps} steps, median {:.0} ms (step {} ms)",
        times[2].as_secs_f64() * 1e3,
        STEP.as_millis()
    );

    let mut bus = unconfigured(8);
    let mut lss = LssMaster::new(&mut bus, Duration::from_millis(100));
    let t = Instant::now();
    let outcome = lss.assign(20, BTreeSet::new(), STEP, true, &mut |_| {}).unwrap();
    let elapsed = t.elapsed();
    assert_eq!(outcome.assigned.len(), 8);
    println!(
        "assign of 8 devices: {} fastscan steps, {:.2} s, {:.0} ms a device",
        outcome.steps,
        elapsed.as_secs_f64(),
        elapsed.as_secs_f64() * 1e3 / 8.0
    );
}
