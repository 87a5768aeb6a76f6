//! `canctl config eds NODE`: the EDS a device stores in itself (0x1021), plain or zipped
//! as 0x1022 says, saved and then usable with --eds; a device without one is told apart
//! (exit 4), and a stored EDS larger than the limit is not read on and on.

use crate::common;

use canctl::bus::{FrameLink, Master};
use canctl::canopen::abort;
use canctl::canopen::sdo::{ObjectAccess, SdoServer};
use canctl::canopen::ObjAddr;
use canctl::frame::Frame;
use canctl::ops::stored_eds;
use common::Sim;
use std::path::Path;
use std::time::{Duration, Instant};

fn committed(name: &str) -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("eds").join(name)).unwrap()
}

#[test]
fn the_drives_plain_eds_is_saved_and_names_its_objects() {
    let sim = Sim::new();
    let out = sim.path("drive.eds");
    let run = sim.run(&["config", "eds", "1", "--out", out.to_str().unwrap()]).ok();
    assert!(run.stdout.contains("node 1: its EDS, ") && run.stdout.contains("(plain text)"), "{}", run.stdout);
    assert!(std::fs::read(&out).unwrap() == committed("canctl-sim-drive.eds"), "not eds/canctl-sim-drive.eds");
    let eds = format!("1={}", out.display());
    let json = sim.run(&["--eds", &eds, "--format", "json", "sdo", "read", "1", "CAN bit rate"]).ok().json();
    assert_eq!(json["object"], "0x2001:0", "{json}");
}

#[test]
fn the_io_modules_zipped_eds_is_unpacked() {
    let sim = Sim::new();
    let json = sim
        .run(&["--format", "json", "config", "eds", "10", "--out", sim.path("io.eds").to_str().unwrap()])
        .ok()
        .json();
    assert_eq!((json["format"].as_u64(), json["format_name"].as_str()), (Some(1), Some("ZIP")), "{json}");
    assert!(json["stored_bytes"].as_u64() < json["bytes"].as_u64(), "{json}");
    assert!(std::fs::read(sim.path("io.eds")).unwrap() == committed("canctl-sim-io.eds"), "not eds/canctl-sim-io.eds");
    // Without --out the file is the output, and what it is goes to stderr.
    let run = sim.run(&["config", "eds", "10"]).ok();
    assert!(run.stdout.as_bytes() == committed("canctl-sim-io.eds"), "standard output is not the EDS");
    assert!(run.stderr.contains("saved to standard output"), "{}", run.stderr);
}

#[test]
fn a_device_without_a_stored_eds_is_refused_with_exit_4_and_nothing_saved() {
    let sim = Sim::new();
    let out = sim.path("sensor.eds");
    let run = sim.run(&["config", "eds", "5", "--out", out.to_str().unwrap()]);
    assert_eq!(run.code, 4, "{}", run.stderr);
    assert!(run.stderr.contains("the device does not store its EDS (0x1021)"), "{}", run.stderr);
    assert!(!out.exists());
}

/// A device answering SDO requests from `objects`, through canctl's own SDO server with
/// block transfer: the whole protocol, on a link with no bus.
struct Device<O: ObjectAccess> {
    server: SdoServer,
    objects: O,
    now: Instant,
    pending: Vec<Frame>,
    frames: usize,
}

impl<O: ObjectAccess> FrameLink for Device<O> {
    fn send(&mut self, frame: &Frame) -> canctl::Result<()> {
        if frame.id() == 0x601 {
            let answers = self.server.handle(frame.data(), &mut self.objects);
            self.pending.extend(answers.iter().map(|a| Frame::new(0x581, a)));
        }
        Ok(())
    }

    fn recv(&mut self, deadline: Instant) -> canctl::Result<Option<Frame>> {
        self.frames += 1;
        assert!(self.frames < 100_000, "still reading after 100000 frames: the upload is unbounded");
        if self.pending.is_empty() {
            self.now = self.now.max(deadline);
            return Ok(None);
        }
        Ok(Some(self.pending.remove(0)))
    }

    fn name(&self) -> String {
        "device".into()
    }

    fn now(&self) -> Instant {
        self.now
    }
}

fn device<O: ObjectAccess>(objects: O) -> Master<Device<O>> {
    let link = Device { server: SdoServer::new(true), objects, now: Instant::now(), pending: Vec::new(), frames: 0 };
    Master::new(link, "device".into())
}

/// A read-only device whose objects `read` gives.
struct Objects(fn(ObjAddr) -> Result<Vec<u8>, u32>);

impl ObjectAccess for Objects {
    fn read(&mut self, addr: ObjAddr) -> Result<Vec<u8>, u32> {
        (self.0)(addr)
    }
    fn write(&mut self, _: ObjAddr, _: &[u8]) -> Result<(), u32> {
        Err(abort::READ_ONLY)
    }
    fn check_write(&self, _: ObjAddr, _: Option<usize>) -> Result<(), u32> {
        Err(abort::READ_ONLY)
    }
}

/// A stored EDS of more than 4 GiB: CiA 301's 32-bit size cannot announce it, so the
/// device uploads it without a size, and only the client's limit ends the transfer. (The
/// zeroes are never touched: the allocation costs address space, not memory.)
fn endless(addr: ObjAddr) -> Result<Vec<u8>, u32> {
    match (addr.index, addr.sub) {
        (0x1021, 0) => Ok(vec![0; (1 << 32) + 10]),
        (0x1022, 0) => Ok(vec![0]),
        _ => Err(abort::NO_OBJECT),
    }
}

#[cfg(all(target_os = "linux", target_pointer_width = "64"))]
#[test]
fn an_upload_without_a_size_stops_at_the_limit() {
    let mut bus = device(Objects(endless));
    let err = stored_eds::read(&mut bus, 1, Duration::from_millis(200), 100_000).unwrap_err();
    assert!(err.to_string().contains("100000 bytes"), "{err}");
    assert!(bus.link_mut().frames < 20_000, "read on for {} frames", bus.link_mut().frames);
}

/// A device whose 0x1022 says ZIP, but whose 0x1021 holds plain text.
fn mislabelled(addr: ObjAddr) -> Result<Vec<u8>, u32> {
    match (addr.index, addr.sub) {
        (0x1021, 0) => Ok(b"[FileInfo]\nFileName=x.eds\n".repeat(10)),
        (0x1022, 0) => Ok(vec![1]),
        _ => Err(abort::NO_OBJECT),
    }
}

#[test]
fn a_stored_eds_that_does_not_unpack_is_a_protocol_failure_saving_nothing() {
    let err = stored_eds::read(&mut device(Objects(mislabelled)), 1, Duration::from_millis(200), 100_000).unwrap_err();
    assert_eq!(err.exit_code(), 5, "{err}");
    assert!(
        err.to_string().contains("the ZIP archive is broken") && err.to_string().contains("nothing was saved"),
        "{err}"
    );
}
