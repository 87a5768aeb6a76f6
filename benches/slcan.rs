//! slcan: the host's cost per frame through the encoder and decoder, and 100 kB moved by
//! SDO block transfer through the simulated adapter on a real pseudo-terminal.
//!
//! `cargo bench --bench slcan`. The pty run is timed whole (3 runs), like benches/sim_bus.rs:
//! the devices behind the adapter answer as the `typical` profile does and frames take
//! their time at 500 kbit/s on the simulated bus, so the figure is what a host gets from a
//! 500 kbit/s adapter, not a CPU figure.

use canctl::backend::slcan::SlcanLink;
use canctl::bus::{Bus, Master, SdoOptions};
use canctl::canopen::ObjAddr;
use canctl::frame::Frame;
use canctl::sim::profiles::domain_pattern;
use canctl::sim::SimLink;
use canctl::slcan::wire::{Command, Decoder, Message};
use std::time::{Duration, Instant};

const FRAMES: usize = 100_000;
const SIZE: usize = 100_000;
const DOMAIN: ObjAddr = ObjAddr::new(0x1F50, 1);

fn codec() {
    let frames: Vec<Frame> = (0..FRAMES as u32)
        .map(|i| Frame::new(0x580 + (i % 127) as u16 + 1, &(i.wrapping_mul(2_654_435_761)).to_le_bytes().repeat(2)))
        .collect();
    // What an adapter sends: every frame as its text line.
    let stream: Vec<u8> = frames.iter().flat_map(|f| Message::Frame(*f).encode()).collect();
    let mut best_encode = Duration::MAX;
    let mut best_decode = Duration::MAX;
    for _ in 0..5 {
        let start = Instant::now();
        let mut bytes = 0usize;
        for f in &frames {
            bytes += std::hint::black_box(Command::Transmit(*f).encode()).len();
        }
        best_encode = best_encode.min(start.elapsed());
        std::hint::black_box(bytes);

        let start = Instant::now();
        let mut decoder = Decoder::new();
        let mut got = 0usize;
        for chunk in stream.chunks(256) {
            got += decoder.push(chunk).len();
        }
        best_decode = best_decode.min(start.elapsed());
        assert_eq!(got, FRAMES);
    }
    let per = |d: Duration| d.as_nanos() as f64 / FRAMES as f64;
    println!("slcan encode (host -> adapter)        {:>7.1} ns per frame", per(best_encode));
    println!("slcan decode (adapter -> host)        {:>7.1} ns per frame", per(best_decode));
}

/// The simulated adapter on a new pty, with the demo devices behind it.
fn adapter() -> String {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut adapter = canctl::sim::slcan_serve::SlcanAdapter::create(500, Vec::new()).unwrap();
        tx.send(adapter.path().to_string()).unwrap();
        let _ = canctl::sim::bridge::run(SimLink::ephemeral(), &mut adapter, None);
    });
    rx.recv().unwrap()
}

fn pty_transfers() {
    let path = adapter();
    let mut port = serialport::new(&path, 115_200).timeout(Duration::from_millis(100)).open_native().unwrap();
    port.set_exclusive(false).unwrap();
    let link = SlcanLink::open(port, format!("slcan:{path}"), 500).unwrap();
    let mut bus = Master::new(link, format!("slcan:{path}"));
    let opts = SdoOptions { block_upload: true, ..SdoOptions::new(Duration::from_secs(2)) };
    let data = domain_pattern(SIZE);
    // 100 kB in 7-byte segments, plus the initiate, the block acknowledgements and the end.
    let frames = (SIZE.div_ceil(7) + SIZE.div_ceil(7 * 127) + 4) as f64;
    for run in 1..=3 {
        let start = Instant::now();
        bus.sdo_download(1, DOMAIN, &data, &opts).unwrap();
        let down = start.elapsed();
        let start = Instant::now();
        let back = bus.sdo_upload(1, DOMAIN, &opts).unwrap();
        let up = start.elapsed();
        assert_eq!(back, data);
        println!(
            "100 kB over sim --slcan, run {run}: block download {:>7.1} ms ({:>6.0} frames/s), upload {:>7.1} ms ({:>6.0} frames/s)",
            down.as_secs_f64() * 1000.0,
            frames / down.as_secs_f64(),
            up.as_secs_f64() * 1000.0,
            frames / up.as_secs_f64()
        );
    }
    bus.close().unwrap();
}

fn main() {
    // `cargo test --benches` runs benches with --bench absent: nothing to measure then.
    if std::env::args().any(|a| a == "--bench") {
        codec();
        pty_transfers();
    }
}
