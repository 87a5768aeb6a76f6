//! The slcan link through a real pseudo-terminal, against the simulator's adapter side with
//! the demo devices behind it: the library alone, no command line.

use crate::common;

use canctl::backend::slcan::SlcanLink;
use canctl::bus::{Bus, Master, SdoOptions};
use canctl::canopen::ObjAddr;
use canctl::serial::SerialIo;
use canctl::sim::serial_fault::Fault;
use canctl::sim::slcan_serve::SlcanAdapter;
use canctl::sim::SimLink;
use std::time::Duration;

/// An adapter on a new pty, serving the demo network at `bus_kbit` until the test ends.
fn adapter(bus_kbit: u32) -> String {
    adapter_with(bus_kbit, Vec::new())
}

/// The same, with these faults.
fn adapter_with(bus_kbit: u32, faults: Vec<Fault>) -> String {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut adapter = SlcanAdapter::create(bus_kbit, faults).unwrap();
        tx.send(adapter.path().to_string()).unwrap();
        let _ = canctl::sim::bridge::run(SimLink::ephemeral(), &mut adapter, None);
    });
    rx.recv().unwrap()
}

/// The test's end of the pty, shared: while another test thread starts a program, the
/// child holds a copy of every open descriptor until its exec closes it, and with it the
/// lock of an exclusive open; a second exclusive open in that moment would fail.
fn port(path: &str) -> serialport::TTYPort {
    serialport::new(path, 115_200).timeout(Duration::from_millis(100)).exclusive(false).open_native().unwrap()
}

fn master<P: SerialIo>(port: P, path: &str, kbit: u32) -> Master<SlcanLink<P>> {
    let link = SlcanLink::open(port, format!("slcan:{path}"), kbit).unwrap();
    Master::new(link, format!("slcan:{path}"))
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

/// At another bit rate nothing is heard, and the adapter's status flags say why (its
/// frames went unacknowledged): a link failure naming the bit rate, not a silent node.
#[test]
fn at_another_bit_rate_nothing_is_heard() {
    let path = adapter(500);
    let mut bus = master(port(&path), &path, 250);
    let e = bus.sdo_upload(1, ObjAddr::new(0x1000, 0), &SdoOptions::new(Duration::from_millis(200))).unwrap_err();
    assert_eq!(e.exit_code(), 5, "{e}");
    assert!(e.to_string().contains("error passive") && e.to_string().contains("bit rate"), "{e}");
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

/// A program that ran at the wrong rate leaves the adapter's error flags set as it closes
/// the channel; the next program opens it at the right rate and must not hear of them:
/// opening a channel starts its controller afresh, as a Lawicel adapter's does. (doctor at
/// the right rate after a sweep at the wrong one said "bus errors" one run in a few.)
#[test]
fn errors_at_the_wrong_rate_are_not_said_to_the_next_program() {
    let path = adapter(500);
    let mut wrong = master(port(&path), &path, 125);
    // The sensor's heartbeats (every 40 ms) reach an adapter at the wrong rate: bus errors.
    std::thread::sleep(Duration::from_millis(200));
    wrong.close().unwrap();
    let mut right = master(port(&path), &path, 500);
    right.check_link().unwrap();
    let opts = SdoOptions::new(Duration::from_secs(2));
    assert_eq!(right.sdo_upload(5, ObjAddr::new(0x1018, 1), &opts).unwrap(), 0x40u32.to_le_bytes());
    right.check_link().unwrap();
}

/// An adapter busy with something else answers the empty lines that reset its line parser
/// (refusals, on a closed channel) long after the host stopped waiting for them: they must
/// not be taken for the answers to the set-up commands that follow.
#[test]
fn an_adapter_that_answers_the_line_reset_late_is_set_up() {
    let path = adapter_with(500, vec!["late@1".parse().unwrap()]);
    let mut bus = master(port(&path), &path, 500);
    let opts = SdoOptions::new(Duration::from_secs(2));
    assert_eq!(bus.sdo_upload(5, ObjAddr::new(0x1018, 1), &opts).unwrap(), 0x40u32.to_le_bytes());
}

/// The whole command line over `canctl sim --slcan`: every command as over SocketCAN.
#[test]
fn commands_over_the_simulated_adapter() {
    let sim = common::Sim::new();
    let dev = common::DeviceSide::start(&sim, "--slcan", &[]);
    assert!(dev.uri.starts_with("slcan:/dev/"), "{}", dev.uri);
    let scan = dev.run(&["scan", "--format", "json"]).ok().json();
    let nodes: Vec<u64> = scan["nodes"].as_array().unwrap().iter().map(|n| n["node"].as_u64().unwrap()).collect();
    assert_eq!(nodes, [1, 5, 10, 32], "{scan}");
    assert_eq!(scan["lss_unconfigured"], 3, "{scan}");
    assert_eq!(dev.run(&["sdo", "read", "10", "1008"]).ok().stdout.trim(), "CAN-2057C");
    dev.run(&["sdo", "write", "5", "1017", "150", "--verify"]).ok();
    let assigned = dev.run(&["lss", "assign", "--start", "20", "--format", "json"]).ok().json();
    assert_eq!(assigned["assigned"].as_array().unwrap().len(), 3, "{assigned}");
    let nmt = dev.run(&["nmt", "reset", "20"]).ok();
    assert!(nmt.stdout.contains("node 20"), "{}", nmt.stdout);
}

/// An adapter set to another rate than the bus hears nothing, and its status flags say why
/// (frames nobody acknowledged): `sdo read` and `sdo write` end as `scan` does, with a link
/// failure (exit 5) that names the bit rate and how to give the right one, not "node 1 did
/// not answer" (exit 3); so do the other commands that read over SDO (`errors`, `config
/// dump`), which ended with exit 3.
#[test]
fn a_wrong_bit_rate_in_the_address_is_a_link_failure_naming_it() {
    let sim = common::Sim::new();
    let dev = common::DeviceSide::start(&sim, "--slcan", &[]);
    let wrong = format!("{}@125k", dev.uri);
    let commands = [
        &["sdo", "read", "1", "1000"][..],
        &["sdo", "write", "5", "1017", "150"],
        &["errors", "5"],
        &["config", "dump", "5"],
    ];
    for args in commands {
        let mut c = std::process::Command::new(common::canctl_bin());
        common::isolate(&mut c);
        c.env_remove("CANCTL_BUS").args(["--bus", &wrong, "--timeout", "200ms"]);
        let r = common::finish(c.args(args).output().unwrap());
        assert_eq!(r.code, 5, "{args:?}: {}", r.stderr);
        assert!(r.stderr.contains("the adapter reports") && r.stderr.contains("bit rate"), "{}", r.stderr);
        assert!(r.stderr.contains(&format!("{}@RATE", dev.uri)) && r.stderr.contains("canctl.toml"), "{}", r.stderr);
    }
    // At the right rate the same adapter answers.
    assert_eq!(dev.run(&["sdo", "read", "10", "1008"]).ok().stdout.trim(), "CAN-2057C");
}
