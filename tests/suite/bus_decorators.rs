//! The decorators of a bus over the simulator: a bus that heeds a stop ([`Stoppable`]) and
//! one that tells its caller after each confirmed transfer ([`AfterSdo`]).

use canctl::bus::stoppable::Stoppable;
use canctl::bus::tap::{AfterSdo, Transfer};
use canctl::bus::{Bus, SdoJob, SdoOptions};
use canctl::cancel::Cancel;
use canctl::canopen::nmt::Command;
use canctl::canopen::ObjAddr;
use canctl::sim::SimLink;
use canctl::Error;
use std::time::{Duration, Instant};

#[test]
fn once_stopped_nothing_more_is_sent() {
    let mut bus = canctl::bus::Master::new(SimLink::ephemeral(), "sim".into());
    let stop = Cancel::new();
    let mut s = Stoppable::new(&mut bus, stop.clone());
    let opts = SdoOptions::new(Duration::from_secs(1));
    s.sdo_upload(5, ObjAddr::new(0x1017, 0), &opts).unwrap();
    stop.cancel();
    assert!(matches!(s.sdo_upload(5, ObjAddr::new(0x1017, 0), &opts), Err(Error::Interrupted)));
    assert!(matches!(s.nmt(Command::Start, 5), Err(Error::Interrupted)));
    let far = Instant::now() + Duration::from_secs(3600);
    assert!(matches!(s.recv_frame(far), Err(Error::Interrupted)));
}

/// Frames that waited to be read keep the moment they were on the bus, as the bus under
/// it stamped them: a device's timing is judged from it (heartbeat periods, answer times).
#[test]
fn frames_keep_the_stamp_of_the_bus_under_it() {
    let mut bus = canctl::bus::Master::new(SimLink::ephemeral(), "sim".into());
    bus.nmt(Command::ResetNode, 5).unwrap();
    // The boot-up and heartbeats that come meanwhile wait to be read.
    let later = bus.now() + Duration::from_secs(1);
    bus.sleep_until(later).unwrap();
    let mut s = Stoppable::new(&mut bus, Cancel::new());
    let (_, on_bus) = s.recv_frame_stamped(later + Duration::from_secs(1)).unwrap().expect("a frame");
    assert!(on_bus < later, "stamped at receipt, not when it was on the bus");
}

/// Stopped in the middle of a block download: the transfer ends with an abort, the
/// error says how far it got, and the device (which would otherwise take the next
/// request for a segment of the block) answers the next transfer.
#[test]
fn a_transfer_under_way_is_aborted_and_the_device_is_ready_for_the_next() {
    let mut bus = canctl::bus::Master::new(SimLink::ephemeral(), "sim".into());
    let stop = Cancel::new();
    let domain = ObjAddr::new(0x1F50, 1);
    let opts = SdoOptions::new(Duration::from_secs(1));
    let before = bus.sdo_upload(1, domain, &SdoOptions { block_upload: true, ..opts.clone() }).unwrap();
    let mut s = Stoppable::new(&mut bus, stop.clone());
    let at_second_block: canctl::bus::TransferHook = std::sync::Arc::new(move |moved| {
        if moved > 7 * 127 {
            stop.cancel()
        }
    });
    let hooked = SdoOptions { on_progress: Some(at_second_block), ..opts.clone() };
    let err = s.sdo_download(1, domain, &vec![0x55; 5000], &hooked).unwrap_err();
    match err {
        Error::SdoInterrupted { node: 1, obj, upload: false, moved, aborted: Some(0x0800_0000) } => {
            assert_eq!(obj, domain);
            assert_eq!(moved.total, Some(5000));
            assert!(moved.bytes > 7 * 127 && moved.bytes < 5000, "{moved:?}");
        }
        other => panic!("{other:?}"),
    }
    // Over the plain bus (the stop is the command's, not the device's): ready, unchanged.
    drop(s);
    assert_eq!(bus.sdo_upload(1, domain, &SdoOptions { block_upload: true, ..opts }).unwrap(), before);
}

#[test]
fn each_kind_is_counted_on_its_own_after_the_transfer() {
    let mut bus = canctl::bus::Master::new(SimLink::ephemeral(), "sim".into());
    let mut seen = Vec::new();
    let mut tapped = AfterSdo::new(&mut bus, |t, n| seen.push((t, n)));
    let opts = SdoOptions::new(Duration::from_secs(1));
    tapped.sdo_upload(5, ObjAddr::new(0x1017, 0), &opts).unwrap();
    tapped.sdo_download(5, ObjAddr::new(0x1017, 0), &[100, 0], &opts).unwrap();
    tapped.sdo_upload(5, ObjAddr::new(0x1017, 0), &opts).unwrap();
    // A refused write is not a confirmed one.
    assert!(tapped.sdo_download(5, ObjAddr::new(0x1018, 1), &[1, 0, 0, 0], &opts).is_err());
    assert_eq!(seen, [(Transfer::Upload, 1), (Transfer::Download, 1), (Transfer::Upload, 2)]);
}

#[test]
fn transfers_run_together_are_counted_in_the_order_of_the_jobs() {
    let mut bus = canctl::bus::Master::new(SimLink::ephemeral(), "sim".into());
    let mut seen = Vec::new();
    let mut tapped = AfterSdo::new(&mut bus, |t, n| seen.push((t, n)));
    let opts = SdoOptions::new(Duration::from_secs(1));
    let jobs = [
        SdoJob::Download { node: 5, addr: ObjAddr::new(0x1017, 0), data: vec![100, 0], opts: opts.clone() },
        SdoJob::Upload { node: 10, addr: ObjAddr::new(0x1017, 0), opts: opts.clone() },
        // Refused: not a confirmed write.
        SdoJob::Download { node: 1, addr: ObjAddr::new(0x1018, 1), data: vec![1, 0, 0, 0], opts: opts.clone() },
    ];
    let results = tapped.sdo_many(&jobs).unwrap();
    assert!(results[0].is_ok() && results[1].is_ok() && results[2].is_err());
    assert_eq!(seen, [(Transfer::Download, 1), (Transfer::Upload, 1)]);
}
