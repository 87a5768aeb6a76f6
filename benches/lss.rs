//! LSS on the simulated bus: fastscan of one device and `assign` of 8 devices without
//! node-ids, at the pace learned from the devices' answers. `cargo bench --bench lss`.

use canctl::bus::lss::LssMaster;
use canctl::bus::Master;
use canctl::canopen::lss::Pace;
use canctl::sim::profiles::position_sensor;
use canctl::sim::{Network, SimLink};
use std::collections::BTreeSet;
use std::time::{Duration, Instant};

const PROBE: Duration = Duration::from_millis(500);

fn unconfigured(n: u32) -> Master<SimLink> {
    let devices = (0..n).map(|i| (position_sensor(0x0950_2000 + i * 0x1111), None)).collect();
    Master::new(SimLink::of(Network::of(devices)), "sim".into(), false)
}

fn main() {
    for (what, given) in
        [("nothing known", [None; 4]), ("vendor and product known", [Some(0x40), Some(0x4378_7800), None, None])]
    {
        let mut times = Vec::new();
        let mut steps = 0;
        let mut step = Duration::ZERO;
        for _ in 0..5 {
            let mut bus = unconfigured(1);
            let mut lss = LssMaster::new(&mut bus, Duration::from_millis(100));
            let t = Instant::now();
            let scan = lss.fastscan(Pace::measured(PROBE), given, &mut || true).unwrap().unwrap();
            times.push(t.elapsed());
            scan.found.unwrap();
            steps = scan.steps;
            step = scan.pace.longest_step();
        }
        times.sort();
        println!(
            "fastscan of one device, {what}: {steps} steps, median {:.0} ms (step {} ms, incl. {} ms probe)",
            times[2].as_secs_f64() * 1e3,
            step.as_millis(),
            PROBE.as_millis()
        );

        let mut bus = unconfigured(8);
        let mut lss = LssMaster::new(&mut bus, Duration::from_millis(100));
        let t = Instant::now();
        let outcome =
            lss.assign(20, BTreeSet::new(), Pace::measured(PROBE), given, true, &mut || true, &mut |_| {}).unwrap();
        let elapsed = t.elapsed();
        assert_eq!(outcome.assigned.len(), 8);
        println!(
            "assign of 8 devices, {what}: {} fastscan steps, {:.2} s, {:.0} ms a device (step {} ms)",
            outcome.steps,
            elapsed.as_secs_f64(),
            elapsed.as_secs_f64() * 1e3 / 8.0,
            outcome.pace.longest_step().as_millis()
        );
    }
}
