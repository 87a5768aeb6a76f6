//! ReadObject round trips through the EPOS2 protocol over a real pseudo-terminal, against
//! the simulator's device side running in this process.
//!
//! `cargo bench --bench epos2`. Without pacing the figure is the host's own cost per
//! round trip (both sides of the pty); with `--baud 115200` pacing it is comparable to the
//! wire time of seed 002 (24 bytes with acknowledges = 2.08 ms on RS232).

use canctl::backend::epos2::Epos2Gateway;
use canctl::bus::{Bus, SdoOptions};
use canctl::canopen::ObjAddr;
use canctl::epos2::transport::SerialTransport;
use canctl::epos2::Framing;
use canctl::sim::epos2_device::Epos2Device;
use canctl::sim::epos2_serve::{serve, ServeOptions};
use canctl::sim::SimLink;
use criterion::{criterion_group, criterion_main, Criterion};
use std::time::Duration;

/// Start a device side on a thread; returns its pty path.
fn device_side(framing: Framing, baud: Option<u32>) -> String {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let device = Epos2Device::new(SimLink::ephemeral(), Duration::from_millis(25));
        let opts = ServeOptions { framing, baud, faults: vec![] };
        serve(device, &opts, |p| {
            tx.send(p.to_string()).unwrap();
            Ok(())
        })
    });
    rx.recv().unwrap()
}

fn open(path: &str, baud: u32) -> serialport::TTYPort {
    let mut p = serialport::new(path, baud).timeout(Duration::from_secs(1)).open_native().unwrap();
    p.set_exclusive(false).unwrap();
    p
}

fn read_object(c: &mut Criterion) {
    let timeout = Duration::from_secs(1);
    let mut opts = SdoOptions::new(timeout);
    opts.size_hint = Some(4);
    let device_type = ObjAddr::new(0x1000, 0);
    let mut g = c.benchmark_group("ReadObject round trip");
    let path = device_side(Framing::Rs232, None);
    let mut rs232 =
        Epos2Gateway::new(SerialTransport::new(open(&path, 115_200), Framing::Rs232, "rs232".into(), timeout));
    g.bench_function("rs232, unpaced, the EPOS2 itself", |b| {
        b.iter(|| rs232.sdo_upload(0, device_type, &opts).unwrap())
    });
    g.bench_function("rs232, unpaced, node 5 via gateway", |b| {
        b.iter(|| rs232.sdo_upload(5, device_type, &opts).unwrap())
    });
    let path = device_side(Framing::Usb, None);
    let mut usb = Epos2Gateway::new(SerialTransport::new(open(&path, 1_000_000), Framing::Usb, "usb".into(), timeout));
    g.bench_function("usb, unpaced, the EPOS2 itself", |b| b.iter(|| usb.sdo_upload(0, device_type, &opts).unwrap()));
    let path = device_side(Framing::Rs232, Some(115_200));
    let mut paced =
        Epos2Gateway::new(SerialTransport::new(open(&path, 115_200), Framing::Rs232, "rs232".into(), timeout));
    g.sample_size(50);
    g.bench_function("rs232 at 115200 bit/s, the EPOS2 itself", |b| {
        b.iter(|| paced.sdo_upload(0, device_type, &opts).unwrap())
    });
    g.finish();
}

criterion_group!(benches, read_object);
criterion_main!(benches);
