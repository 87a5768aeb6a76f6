//! LSS on the simulated bus at the pace learned from the devices' answers: fastscan of one
//! device, and `assign` of 8 devices without node-ids (a fastscan each), on the `typical`
//! and `slow` profiles, with nothing known and with vendor and product given.
//! `cargo bench --bench lss`.

use canctl::bus::lss::LssMaster;
use canctl::bus::Master;
use canctl::cancel::Cancel;
use canctl::canopen::lss::Pace;
use canctl::ops::lss::number_all;
use canctl::ops::Silent;
use canctl::sim::profiles::position_sensor;
use canctl::sim::{Network, Profile, SimConfig, SimLink};
use std::collections::BTreeSet;
use std::time::{Duration, Instant};

/// The first probe's window: the default --timeout.
const PROBE: Duration = Duration::from_millis(500);

fn unconfigured(n: u32, profile: Profile) -> Master<SimLink> {
    let devices = (0..n).map(|i| (position_sensor(0x0950_2000 + i * 0x1111), None)).collect();
    let net = Network::of_with(devices, SimConfig::default().profile(profile));
    Master::new(SimLink::of(net), "sim".into())
}

fn main() {
    let known = [Some(0x40), Some(0x4378_7800), None, None];
    for profile in [Profile::Typical, Profile::Slow] {
        for (what, given) in [("nothing known", [None; 4]), ("vendor+product given", known)] {
            let runs = if profile == Profile::Slow { 3 } else { 5 };
            let mut times = Vec::new();
            let (mut steps, mut step) = (0, Duration::ZERO);
            for _ in 0..runs {
                let mut bus = unconfigured(1, profile);
                let mut lss = LssMaster::new(&mut bus, PROBE);
                let t = Instant::now();
                let scan =
                    lss.fastscan(Pace::measured(PROBE), given, &Cancel::default(), &mut |_| {}).unwrap().unwrap();
                times.push(t.elapsed());
                scan.found.unwrap();
                steps = scan.steps;
                step = scan.pace.longest_step();
            }
            times.sort();
            println!(
                "{profile:>7}, {what}: fastscan of 1 device: {steps} steps, median {:.2} s (step {} ms, incl. the {} ms first probe)",
                times[runs / 2].as_secs_f64(),
                step.as_millis(),
                PROBE.as_millis()
            );

            let mut bus = unconfigured(8, profile);
            let mut lss = LssMaster::new(&mut bus, PROBE);
            let t = Instant::now();
            let pace = Pace::measured(PROBE);
            let outcome =
                number_all(&mut lss, 20, BTreeSet::new(), pace, given, true, &mut Silent, &Cancel::default()).unwrap();
            let elapsed = t.elapsed();
            assert_eq!(outcome.assigned.len(), 8, "all 8 numbered");
            println!(
                "{profile:>7}, {what}: assign of 8 devices: {} fastscan steps, {:.1} s, {:.2} s a device (step {} ms, {} escalations)",
                outcome.steps,
                elapsed.as_secs_f64(),
                elapsed.as_secs_f64() / 8.0,
                outcome.pace.longest_step().as_millis(),
                outcome.pace.escalations()
            );
        }
    }
}
