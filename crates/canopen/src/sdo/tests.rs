use super::shared::block_crc;
use super::*;
use crate::abort;
use crate::sdo::client::MAX_BLOCK_RETRANSMISSIONS;
use crate::ObjAddr;
use std::collections::BTreeMap;

/// A dictionary for the server side of the tests.
#[derive(Default)]
struct Od(BTreeMap<ObjAddr, (Vec<u8>, bool)>);

impl Od {
    fn with(mut self, addr: ObjAddr, data: &[u8], writable: bool) -> Od {
        self.0.insert(addr, (data.to_vec(), writable));
        self
    }
}

impl ObjectAccess for Od {
    fn read(&mut self, addr: ObjAddr) -> Result<Vec<u8>, u32> {
        self.0.get(&addr).map(|(d, _)| d.clone()).ok_or(abort::NO_OBJECT)
    }
    fn write(&mut self, addr: ObjAddr, data: &[u8]) -> Result<(), u32> {
        self.check_write(addr, Some(data.len()))?;
        self.0.get_mut(&addr).unwrap().0 = data.to_vec();
        Ok(())
    }
    fn check_write(&self, addr: ObjAddr, _size: Option<usize>) -> Result<(), u32> {
        match self.0.get(&addr) {
            None => Err(abort::NO_OBJECT),
            Some((_, false)) => Err(abort::READ_ONLY),
            Some(_) => Ok(()),
        }
    }
}

const A: ObjAddr = ObjAddr::new(0x2000, 1);

/// Run a client against a server; `lose(n)` says whether the n-th server→client frame is
/// lost on the way, to exercise block-transfer repeats.
fn run(
    client: &mut SdoClient,
    server: &mut SdoServer,
    od: &mut Od,
    lose: impl Fn(usize) -> bool,
) -> Result<Vec<u8>, SdoError> {
    let mut to_server = vec![client.start()];
    let mut count = 0;
    for _ in 0..100_000 {
        let mut to_client = Vec::new();
        for req in to_server.drain(..) {
            to_client.extend(server.handle(&req, od));
        }
        for resp in to_client {
            count += 1;
            if lose(count) {
                continue;
            }
            let step = client.on_response(&resp)?;
            for f in &step.send {
                to_server.push(*f);
            }
            if let Some(data) = step.done {
                for req in to_server.drain(..) {
                    assert!(server.handle(&req, od).is_empty());
                }
                return Ok(data);
            }
        }
        assert!(!to_server.is_empty(), "transfer stalled");
    }
    panic!("transfer did not end")
}

fn pattern(n: usize) -> Vec<u8> {
    (0..n).map(|i| (i * 7 + i / 251) as u8).collect()
}

#[test]
fn seed_002_expedited_upload_of_device_type() {
    // Steps 2 and 3 of the gateway note: SDO upload of 0x1000:0 from node 2.
    let mut c = SdoClient::upload(ObjAddr::new(0x1000, 0), false);
    assert_eq!(c.start(), [0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]);
    assert_eq!(request_cob(2), 0x602);
    assert_eq!(response_cob(2), 0x582);
    let step = c.on_response(&[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]).unwrap();
    assert_eq!(step.done.unwrap(), vec![0x92, 0x01, 0x02, 0x00]);
}

#[test]
fn seed_001_figures_16_to_18() {
    // Figure 16: download 0x2x, answered with 0x60.
    let addr = ObjAddr::new(0x1017, 0);
    let mut c = SdoClient::download(addr, vec![0xE8, 0x03], false);
    assert_eq!(c.start(), [0x2B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0, 0]);
    assert_eq!(c.on_response(&[0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0]).unwrap().done, Some(vec![]));
    // Figure 17: upload 0x40, answered 0x42 (expedited, size not indicated: four bytes).
    let addr = ObjAddr::new(0x1018, 2);
    let mut c = SdoClient::upload(addr, false);
    assert_eq!(c.start(), [0x40, 0x18, 0x10, 0x02, 0, 0, 0, 0]);
    let done = c.on_response(&[0x42, 0x18, 0x10, 0x02, 0x00, 0x78, 0x78, 0x43]).unwrap().done.unwrap();
    assert_eq!(u32::from_le_bytes(done.try_into().unwrap()), 0x4378_7800);
    // Figure 18: abort 0x80, index, subindex, code.
    let mut c = SdoClient::upload(ObjAddr::new(0x1008, 1), false);
    c.start();
    let err = c.on_response(&[0x80, 0x08, 0x10, 0x01, 0x11, 0x00, 0x09, 0x06]).unwrap_err();
    assert_eq!(err, SdoError::ServerAbort(abort::NO_SUBINDEX));
    assert_eq!(
        abort_frame(ObjAddr::new(0x1008, 1), abort::NO_SUBINDEX),
        [0x80, 0x08, 0x10, 0x01, 0x11, 0x00, 0x09, 0x06]
    );
}

#[test]
fn seed_004_segmented_upload_and_short_dlc() {
    let mut c = SdoClient::upload(ObjAddr::new(0x1008, 0), false);
    assert_eq!(c.start(), [0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0]);
    let s = c.on_response(&[0x41, 0x08, 0x10, 0x00, 0x09, 0x00, 0x00, 0x00]).unwrap();
    assert_eq!(s.send, vec![[0x60, 0, 0, 0, 0, 0, 0, 0]]);
    let s = c.on_response(&[0x00, 0x43, 0x41, 0x4E, 0x2D, 0x32, 0x30, 0x38]).unwrap();
    assert_eq!(s.send, vec![[0x70, 0, 0, 0, 0, 0, 0, 0]]);
    // t=1, n=5, c=1: two bytes end the nine.
    let s = c.on_response(&[0x1B, 0x37, 0x43, 0, 0, 0, 0, 0]).unwrap();
    assert_eq!(s.done.unwrap(), b"CAN-2087C");
    // The 5-byte expedited answer of seed 004: 4F 00 14 00 02 (n=3, one byte).
    let mut c = SdoClient::upload(ObjAddr::new(0x1400, 0), false);
    c.start();
    assert_eq!(c.on_response(&[0x4F, 0x00, 0x14, 0x00, 0x02]).unwrap().done.unwrap(), vec![0x02]);
}

#[test]
fn toggle_errors_abort() {
    let mut c = SdoClient::upload(ObjAddr::new(0x1008, 0), false);
    c.start();
    c.on_response(&[0x41, 0x08, 0x10, 0x00, 0x20, 0, 0, 0]).unwrap();
    let err = c.on_response(&[0x10, 1, 2, 3, 4, 5, 6, 7]).unwrap_err();
    assert!(matches!(err, SdoError::ClientAbort { code: abort::TOGGLE_BIT, .. }));
}

#[test]
fn oversized_announcement_is_refused() {
    let mut c = SdoClient::upload(A, false).with_max_upload(1000);
    c.start();
    let err = c.on_response(&[0x41, 0x00, 0x20, 0x01, 0xFF, 0xFF, 0xFF, 0xFF]).unwrap_err();
    assert!(matches!(err, SdoError::ClientAbort { code: abort::OUT_OF_MEMORY, .. }));
    // The same by block transfer, and the size is 32-bit unsigned: 0xFFFFFFFF is 4 GiB - 1.
    let mut c = SdoClient::upload(A, true);
    c.start();
    let err = c.on_response(&[0xC2, 0x00, 0x20, 0x01, 0xFF, 0xFF, 0xFF, 0xFF]).unwrap_err();
    let SdoError::ClientAbort { code: abort::OUT_OF_MEMORY, reason } = err else { panic!("{err:?}") };
    assert!(reason.contains("4294967295 bytes") && reason.contains("1048576") && !reason.contains("--"), "{reason}");
}

#[test]
fn every_size_round_trips_by_every_protocol() {
    for size in [0, 1, 3, 4, 5, 7, 8, 13, 14, 21, 22, 63, 64, 100, 889, 890, 1000, 4096] {
        for block in [false, true] {
            let data = pattern(size);
            let mut od = Od::default().with(A, &[], true);
            let mut server = SdoServer::new(true);
            let mut c = SdoClient::download(A, data.clone(), block);
            run(&mut c, &mut server, &mut od, |_| false).unwrap();
            assert_eq!(od.0[&A].0, data, "download {size} block={block}");
            let mut c = SdoClient::upload(A, block);
            assert_eq!(run(&mut c, &mut server, &mut od, |_| false).unwrap(), data, "upload {size} block={block}");
        }
    }
}

#[test]
fn block_requests_fall_back_on_servers_without_block() {
    let data = pattern(300);
    let mut od = Od::default().with(A, &[], true);
    let mut server = SdoServer::new(false);
    let mut c = SdoClient::download(A, data.clone(), true);
    run(&mut c, &mut server, &mut od, |_| false).unwrap();
    assert!(c.fell_back());
    let mut c = SdoClient::upload(A, true);
    assert_eq!(run(&mut c, &mut server, &mut od, |_| false).unwrap(), data);
    assert!(c.fell_back());
}

#[test]
fn block_upload_repeats_lost_segments() {
    let data = pattern(5000);
    let mut od = Od::default().with(A, &data, true);
    let mut server = SdoServer::new(true);
    // Lose a few server frames mid-block (never the very first answer).
    let mut c = SdoClient::upload(A, true);
    let got = run(&mut c, &mut server, &mut od, |n| n == 5 || n == 90 || n == 300).unwrap();
    assert_eq!(got, data);
}

#[test]
fn block_download_crc_is_checked() {
    let data = pattern(200);
    let mut od = Od::default().with(A, &[], true);
    let mut server = SdoServer::new(true);
    let mut c = SdoClient::download(A, data, true);
    let mut to_server = vec![c.start()];
    loop {
        let mut replies = Vec::new();
        for mut req in to_server.drain(..) {
            if req[0] & 0xE3 == 0xC1 {
                req[1] ^= 0xFF; // corrupt the CRC in the end frame
            }
            replies.extend(server.handle(&req, &mut od));
        }
        let r = replies.pop().unwrap();
        match c.on_response(&r) {
            Ok(step) => to_server = step.send,
            Err(e) => {
                assert_eq!(e, SdoError::ServerAbort(abort::CRC_ERROR));
                break;
            }
        }
    }
    assert!(od.0[&A].0.is_empty(), "nothing written on CRC failure");
}

#[test]
fn server_refusals_reach_the_client() {
    let mut od = Od::default().with(A, &[1, 2, 3, 4], false);
    let mut server = SdoServer::new(true);
    let mut c = SdoClient::download(A, vec![1, 2], false);
    assert_eq!(run(&mut c, &mut server, &mut od, |_| false), Err(SdoError::ServerAbort(abort::READ_ONLY)));
    let mut c = SdoClient::download(A, pattern(100), true);
    assert_eq!(run(&mut c, &mut server, &mut od, |_| false), Err(SdoError::ServerAbort(abort::READ_ONLY)));
    let mut c = SdoClient::upload(ObjAddr::new(0x3000, 0), false);
    assert_eq!(run(&mut c, &mut server, &mut od, |_| false), Err(SdoError::ServerAbort(abort::NO_OBJECT)));
}

#[test]
fn crc_matches_xmodem_check_value() {
    assert_eq!(block_crc(b"123456789"), 0x31C3);
}

/// Arbitrary bytes from a misbehaving peer never panic either side, in any state.
#[test]
fn random_frames_never_panic() {
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut rand = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    for round in 0..2000 {
        let block = round % 2 == 0;
        let mut c = if round % 4 < 2 {
            SdoClient::upload(A, block)
        } else {
            SdoClient::download(A, pattern((round % 300) as usize), block)
        };
        c.start();
        let mut server = SdoServer::new(block);
        let mut od = Od::default().with(A, &pattern(round as usize % 200), true);
        for _ in 0..50 {
            let len = (rand() % 9) as usize;
            let bytes = rand().to_le_bytes();
            let mut f = bytes[..len].to_vec();
            // Often keep the multiplexer right so that deeper states are reached.
            if len >= 4 && rand() % 2 == 0 {
                f[1..4].copy_from_slice(&A.to_mux());
            }
            let _ = server.handle(&f, &mut od);
            if c.on_response(&f).is_err() {
                break;
            }
        }
    }
}

mod misbehaving;
