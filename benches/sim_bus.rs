//! SDO block transfer and scan on the timing-emulated sim bus (`typical` profile: devices
//! answer 0.5–3 ms late, frames take their time at the bit rate).
//!
//! `cargo bench --bench sim_bus` (SIM_BUS_RUNS=N for more runs than 3). A transfer of 100 kB
//! takes about 1.5 s at 1 Mbit/s and 13 s at 125 kbit/s, so this is a plain harness that
//! times whole runs, not criterion's many iterations.
//!
//! "% of bus limit": the time the transfer's frames (segments, initiate, acknowledgements)
//! would take back to back at the bit rate, over the time the transfer took. The
//! difference is the time the bus was idle: each block waits for the receiver's
//! acknowledgement (its latency) before the next one starts.

use canctl::bus::{Bus, Master, SdoOptions};
use canctl::canopen::ObjAddr;
use canctl::sim::profiles::domain_pattern;
use canctl::sim::{BusStats, SimConfig, SimLink};
use std::process::Command;
use std::time::{Duration, Instant};

const SIZE: usize = 100_000;
const DOMAIN: ObjAddr = ObjAddr::new(0x1F50, 1);

struct Measured {
    elapsed: Duration,
    bus: BusStats,
}

impl Measured {
    fn percent_of_limit(&self) -> f64 {
        self.bus.busy as f64 / self.elapsed.as_nanos() as f64 * 100.0
    }
}

fn measure(bus: &mut Master<SimLink>, f: impl FnOnce(&mut Master<SimLink>)) -> Measured {
    let before = bus.link_mut().bus_stats();
    let start = Instant::now();
    f(bus);
    let elapsed = start.elapsed();
    let after = bus.link_mut().bus_stats();
    Measured { elapsed, bus: BusStats { frames: after.frames - before.frames, busy: after.busy - before.busy } }
}

fn report(what: &str, runs: &[Measured]) {
    let mut pct: Vec<f64> = runs.iter().map(Measured::percent_of_limit).collect();
    pct.sort_by(f64::total_cmp);
    let mut ms: Vec<f64> = runs.iter().map(|m| m.elapsed.as_secs_f64() * 1000.0).collect();
    ms.sort_by(f64::total_cmp);
    let m = &runs[0];
    println!(
        "{what:<40} {:>9.1} ms (min {:.1}, max {:.1})  {:>5.1}% of bus limit (min {:.1}, max {:.1})  {} frames, {:.1} ms on the bus",
        ms[ms.len() / 2],
        ms[0],
        ms[ms.len() - 1],
        pct[pct.len() / 2],
        pct[0],
        pct[pct.len() - 1],
        m.bus.frames,
        m.bus.busy as f64 / 1e6
    );
}

fn block_transfers(runs: usize) {
    let data = domain_pattern(SIZE);
    let mut opts = SdoOptions::new(Duration::from_secs(1));
    opts.block_upload = true;
    opts.block_download = true;
    for (name, rate) in [("1 Mbit/s", 0u8), ("125 kbit/s", 4)] {
        let mut bus = Master::new(SimLink::with_config(SimConfig::default().bit_rate(rate)), "sim".into());
        let mut down = Vec::new();
        let mut up = Vec::new();
        for _ in 0..runs {
            down.push(measure(&mut bus, |b| b.sdo_download(1, DOMAIN, &data, &opts).expect("block download")));
            up.push(measure(&mut bus, |b| {
                assert_eq!(b.sdo_upload(1, DOMAIN, &opts).expect("block upload"), data, "read back what was written")
            }));
        }
        report(&format!("block download 100 kB at {name}"), &down);
        report(&format!("block upload 100 kB at {name}"), &up);
    }
}

fn scan_probes(runs: usize) {
    // What `canctl scan` sends first: 0x1000 of every node at once, its default 50 ms window.
    let probes: Vec<(u8, ObjAddr)> = (1..=127).map(|n| (n, ObjAddr::new(0x1000, 0))).collect();
    let opts = SdoOptions::new(Duration::from_millis(50));
    let mut bus = Master::new(SimLink::with_config(SimConfig::default().bit_rate(0)), "sim".into());
    let runs: Vec<Measured> = (0..runs)
        .map(|_| {
            measure(&mut bus, |b| {
                let answers = b.sdo_upload_many(&probes, &opts, &mut |_| {}).expect("probes");
                assert_eq!(answers.iter().filter(|a| a.is_ok()).count(), 4, "the four demo nodes answer");
            })
        })
        .collect();
    report("scan probes 1..127 at 1 Mbit/s", &runs);
}

/// The whole `canctl scan` (probes, identities, names, LSS count) through the binary.
fn scan_command(runs: usize) {
    let dir = tempfile::tempdir().expect("temp dir");
    let bus = format!("sim:{}", dir.path().join("sim.json").display());
    let canctl = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_canctl"))
            .env("XDG_CONFIG_HOME", dir.path())
            .env("XDG_CACHE_HOME", dir.path())
            .arg("--bus")
            .arg(&bus)
            .args(args)
            .output()
            .expect("canctl runs");
        assert!(out.status.success(), "canctl {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    };
    canctl(&["sim", "reset", "--bit-rate", "1M"]);
    let mut ms: Vec<f64> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            canctl(&["scan"]);
            start.elapsed().as_secs_f64() * 1000.0
        })
        .collect();
    ms.sort_by(f64::total_cmp);
    println!(
        "{:<40} {:>9.1} ms (min {:.1}, max {:.1}), process start included",
        "canctl scan at 1 Mbit/s",
        ms[ms.len() / 2],
        ms[0],
        ms[ms.len() - 1]
    );
}

fn main() {
    // `cargo test --benches` runs this with no --bench flag: build-check only.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let runs = std::env::var("SIM_BUS_RUNS").ok().and_then(|r| r.parse().ok()).unwrap_or(3).max(1);
    println!("sim bus, profile typical, {runs} run(s) each: median (min, max)");
    block_transfers(runs);
    scan_probes(runs);
    scan_command(runs);
}
