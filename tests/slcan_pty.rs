//! The slcan link through a real pseudo-terminal, against the simulator's adapter side with
//! the demo devices behind it: the library alone, no command line.

use canctl::bus::{Bus, Master, SdoOptions};
use canctl::canopen::ObjAddr;
use canctl::epos2::transport::SerialIo;
use canctl::sim::slcan_serve::SlcanAdapter;
use canctl::sim::SimLink;
use canctl::slcan::SlcanLink;
use std::time::Duration;

/// An adapter on a new pty, serving the demo network at `bus_kbit` until the test ends.
fn adapter(bus_kbit: u32) -> String {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut adapter = SlcanAdapter::create(bus_kbit, Vec::new()).unwrap();
        tx.send(adapter.path().to_string()).unwrap();
        let _ = canctl::sim::bridge::run(SimLink::ephemeral(), &mut adapter, false);
    });
    rx.recv().unwrap()
}

fn port(path: &str) -> serialport::TTYPort {
    let mut p = serialport::new(path, 115_200).timeout(Duration::from_millis(100)).open_native().unwrap();
    p.set_exclusive(false).unwrap();
    p
}

fn master<P: SerialIo>(port: P, path: &str, kbit: u32) -> Master<SlcanLink<P>> {
    let link = SlcanLink::open(port, format!("slcan:{path}"), kbit).unwrap();
    Master::new(link, format!("slcan:{path}"), false)
}

#[test]
fn sdo_of_every_kind_through_the_adapter() {
    let path = adapter(500);
    let mut bus = master(port(&path), &path, 500);
    let opts = SdoOptions::new(Duration::from_secs(2));
    let vendor = bus.sdo_upload(1, ObjAddr::new(0x1018, 1), &opts).unwrap();
    assert_eq!(vendor, 0xFBu32.to_le_bytes());
    let name = bus.sdo_upload(10, ObjAddr::new(0x1008, 0), &opts).unwrap();
    assert_eq!(name, b"CAN-2057C");
    let block = SdoOptions { block_upload: true, ..opts.clone() };
    let program = bus.sdo_upload(1, ObjAddr::new(0x1F50, 1), &block).unwrap();
    assert_eq!(program.len(), 65536);
    let data: Vec<u8> = (0..1000u32).map(|i| (i * 7) as u8).collect();
    bus.sdo_download(1, ObjAddr::new(0x1F50, 1), &data, &opts).unwrap();
    assert_eq!(bus.sdo_upload(1, ObjAddr::new(0x1F50, 1), &block).unwrap(), data);
    bus.close().unwrap();
}

#[test]
fn at_another_bit_rate_nothing_is_heard() {
    let path = adapter(500);
    let mut bus = master(port(&path), &path, 250);
    let e = bus.sdo_upload(1, ObjAddr::new(0x1000, 0), &SdoOptions::new(Duration::from_millis(200))).unwrap_err();
    assert_eq!(e.exit_code(), 3, "{e}");
}

#[test]
fn a_host_that_left_the_channel_open_is_set_up_again() {
    let path = adapter(500);
    // A program killed mid-command leaves the channel open and half a command in the line.
    {
        let mut p = port(&path);
        SerialIo::write_all(&mut p, b"S6\rO\rt60").unwrap();
    }
    let mut bus = master(port(&path), &path, 500);
    let opts = SdoOptions::new(Duration::from_secs(2));
    assert_eq!(bus.sdo_upload(5, ObjAddr::new(0x1018, 1), &opts).unwrap(), 0x40u32.to_le_bytes());
}
