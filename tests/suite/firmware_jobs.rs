//! `firmware download 9,10,11 IMAGE --jobs N` against simulated bootloaders, on virtual
//! time: the nodes' erases overlap, their downloads share the bus, a node that fails does
//! not stop the others, and an interruption leaves each node's report saying where its
//! device is.

use canctl::bus::tap::AfterSdo;
use canctl::bus::{Bus, Master, SdoOptions, TransferHook};
use canctl::cancel::Cancel;
use canctl::canopen::program;
use canctl::error::ErrorClass;
use canctl::ops::firmware::{self, Batch, DownloadOptions, FirmwareError, Step, Unfinished, Where};
use canctl::ops::Silent;
use canctl::output::Report;
use canctl::sim::bootloader::{self, Fault, FAULT_OBJECT};
use canctl::sim::{Network, SimConfig, SimLink};
use std::sync::Arc;
use std::time::{Duration, Instant};

const TIMEOUT: Duration = Duration::from_millis(500);

fn bus_of(nodes: &[u8]) -> Master<SimLink> {
    let devices = nodes.iter().map(|&n| (bootloader::model(true), Some(n))).collect();
    let net = Network::of_with(devices, SimConfig::default());
    Master::new(SimLink::of(net).on_virtual_time(1_700_000_000_000), "sim".into())
}

fn image(len: usize) -> Vec<u8> {
    canctl::sim::profiles::domain_pattern(len)
}

fn at(r: &firmware::DownloadReport, step: Step) -> u64 {
    r.steps.iter().find(|s| s.step == step).unwrap_or_else(|| panic!("{step:?} in {r:?}")).at_ms
}

fn run(bus: &mut dyn Bus, nodes: &[u8], img: &[u8], o: &DownloadOptions, jobs: usize) -> (Batch, Duration) {
    let began: Instant = bus.now();
    let batch = firmware::download_jobs(bus, nodes, img, o, jobs, &mut Silent);
    (batch, bus.now() - began)
}

#[test]
fn three_nodes_at_once_each_get_the_image_their_erases_overlapping() {
    let nodes = [9, 10, 11];
    let img = image(20_000);
    let (batch, _) = run(&mut bus_of(&nodes), &nodes, &img, &DownloadOptions::new(TIMEOUT), 3);
    assert!(!batch.interrupted);
    let reports: Vec<_> = batch.nodes.iter().map(|n| n.report.as_ref().expect("each node reported")).collect();
    for (n, r) in batch.nodes.iter().zip(&reports) {
        assert!(n.error.is_none(), "node {}: {:?}", n.node, n.error);
        assert_eq!((r.device, r.id_after), (Where::RunsImage, Some(program::image_id(&img))), "{r:?}");
        assert!(r.confirmed, "{r:?}");
    }
    // All began together: each erase was under way while the others were.
    let last_clear = reports.iter().map(|r| at(r, Step::Clear)).max().unwrap();
    let first_erased = reports.iter().map(|r| at(r, Step::Erased)).min().unwrap();
    assert!(last_clear < first_erased, "{reports:?}");
    // The program data took turns on the bus, one node after the other.
    let mut windows: Vec<(u64, u64)> =
        reports.iter().map(|r| (at(r, Step::Download) - r.download_ms.unwrap(), at(r, Step::Download))).collect();
    windows.sort_by_key(|w| w.1);
    assert!(windows.windows(2).all(|w| w[0].1 <= w[1].0), "{windows:?}");
}

/// At 125 kbit/s three block downloads at once would starve the highest node-id: CAN
/// arbitration gives the bus to the lowest id, its sub-blocks follow one another, and node
/// 11's answers wait past any timeout. They take turns.
#[test]
fn three_block_downloads_take_turns_on_a_slow_bus() {
    let nodes = [9, 10, 11];
    let devices = nodes.iter().map(|&n| (bootloader::model(true), Some(n))).collect();
    let net = Network::of_with(devices, SimConfig::default().bit_rate(4));
    let mut bus = Master::new(SimLink::of(net).on_virtual_time(1_700_000_000_000), "sim".to_string());
    let img = image(30_000);
    let (batch, _) = run(&mut bus, &nodes, &img, &DownloadOptions::new(TIMEOUT), 3);
    for n in &batch.nodes {
        assert!(n.error.is_none(), "node {}: {:?}", n.node, n.error);
        assert_eq!(n.report.as_ref().unwrap().transfer, Some(firmware::Transfer::Block));
    }
}

#[test]
fn one_nodes_flash_error_does_not_stop_the_others() {
    let nodes = [9, 10, 11];
    let mut bus = bus_of(&nodes);
    bus.sdo_download(10, FAULT_OBJECT, &[Fault::FlashWrite as u8], &SdoOptions::new(TIMEOUT)).unwrap();
    let img = image(8_000);
    let (batch, _) = run(&mut bus, &nodes, &img, &DownloadOptions::new(TIMEOUT), 3);
    assert!(!batch.interrupted);
    for n in [&batch.nodes[0], &batch.nodes[2]] {
        assert!(n.error.is_none(), "node {}: {:?}", n.node, n.error);
        assert_eq!(n.report.as_ref().unwrap().device, Where::RunsImage);
    }
    let failed = &batch.nodes[1];
    assert_eq!(failed.report.as_ref().unwrap().device, Where::BootloaderNoProgram);
    let Some(Unfinished::Failed(FirmwareError::Flash { node: 10, after: "the download", .. })) = &failed.error else {
        panic!("{:?}", failed.error)
    };
    assert_eq!(batch.into_failure().unwrap().class(), ErrorClass::Refused);
}

#[test]
fn interrupted_each_node_says_where_its_device_is_and_none_more_is_begun() {
    // The user stops (Ctrl-C) while 9, 10 and 11 download; 12 waits its turn (--jobs 3).
    let nodes = [9, 10, 11, 12];
    let mut bus = bus_of(&nodes);
    let cancel = Cancel::new();
    let c = cancel.clone();
    let mut o = DownloadOptions::new(TIMEOUT);
    o.cancel = Some(cancel);
    // The user stops it once 3000 bytes of any node's image are through.
    let stop: TransferHook = Arc::new(move |bytes| {
        if bytes > 3000 {
            c.cancel();
        }
    });
    let img = image(20_000);
    let mut watched = AfterSdo::new(&mut bus, |_, _| {}).with_progress_hook(Some(stop));
    let (batch, _) = run(&mut watched, &nodes, &img, &o, 3);
    assert!(batch.interrupted);
    for n in &batch.nodes[..3] {
        let r = n.report.as_ref().unwrap();
        assert!(r.interrupted, "{r:?}");
        assert!(
            matches!(&n.error, Some(Unfinished::Failed(e)) if e.class() == ErrorClass::Interrupted),
            "{:?}",
            n.error
        );
        // Stopped mid-download: no valid program, and the same command finishes the job.
        assert_eq!(r.device, Where::BootloaderNoProgram, "{r:?}");
        assert!(r.steps.iter().any(|s| s.step == Step::Erased), "{r:?}");
    }
    assert!(batch.nodes[3].report.is_none() && matches!(batch.nodes[3].error, Some(Unfinished::NotBegun)));
    let said = batch.json_value();
    assert_eq!(
        said["nodes"][0]["report"]["state"],
        "in its bootloader with no valid program; run the same command again"
    );
    assert_eq!(said["nodes"][3]["error"], "not begun: interrupted");
    // The same command, again, finishes the job on all four.
    let (batch, _) = run(&mut bus, &nodes, &img, &DownloadOptions::new(TIMEOUT), 3);
    assert!(batch.nodes.iter().all(|n| n.report.as_ref().unwrap().device == Where::RunsImage), "{batch:?}");
}

/// Figures for the closing note: three nodes, a 256 KiB image each, on the timing-emulated
/// sim at 1 Mbit/s and 125 kbit/s (virtual time), one after the other and all at once.
/// `cargo test --test suite firmware_jobs::figures -- --ignored --nocapture`
#[test]
#[ignore]
fn figures() {
    let nodes = [9, 10, 11];
    let img = image(256 * 1024);
    for (index, name) in [(0u8, "1 Mbit/s"), (4, "125 kbit/s")] {
        for jobs in [1, 3] {
            let devices = nodes.iter().map(|&n| (bootloader::model(true), Some(n))).collect();
            let net = Network::of_with(devices, SimConfig::default().bit_rate(index));
            let mut bus = Master::new(SimLink::of(net).on_virtual_time(1_700_000_000_000), "sim".to_string());
            let (batch, took) = run(&mut bus, &nodes, &img, &DownloadOptions::new(TIMEOUT), jobs);
            assert!(batch.nodes.iter().all(|n| n.error.is_none()), "{batch:?}");
            let reports: Vec<_> = batch.nodes.iter().map(|n| n.report.as_ref().unwrap()).collect();
            // The program data of all three: bytes over the bus time their transfers took.
            let busy: u64 = reports.iter().map(|r| r.download_ms.unwrap()).sum();
            let rate = (3 * img.len()) as f64 / (busy as f64 / 1000.0);
            println!(
                "{name}, 3 nodes x 256 KiB, --jobs {jobs}: whole command {:.2} s; program data {:.0} B/s on the bus; per node: {}",
                took.as_secs_f64(),
                rate,
                reports
                    .iter()
                    .map(|r| format!("{} B/s, erase {:.2} s", r.bytes_per_second.unwrap(), r.erase_ms.unwrap() as f64 / 1000.0))
                    .collect::<Vec<_>>()
                    .join("; ")
            );
        }
    }
}
