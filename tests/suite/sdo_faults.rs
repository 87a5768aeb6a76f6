//! SDO transfers against misbehaving devices (issue 12): every hang ends, every false answer
//! is refused, each with its documented exit code.
//!
//! First through the binary against the simulator's injected faults; then, for devices the
//! simulator cannot play (endless objects, block transfers that never get in sequence), the
//! master runs over a scripted link that plays one device on a virtual clock: answers
//! come after virtual delays and frames can come by themselves, so nothing here waits in
//! real time and nothing asserts a timing. A transfer the master does not bound makes the
//! link give up with a panic instead of hanging the test run.

use crate::common;

use canctl::bus::{Bus, FrameLink, Master, SdoOptions};
use canctl::canopen::abort;
use canctl::canopen::sdo::client::{DEFAULT_MAX_UPLOAD, MAX_BLOCK_RETRANSMISSIONS};
use canctl::canopen::ObjAddr;
use canctl::frame::Frame;
use canctl::Error;
use common::Sim;
use std::time::{Duration, Instant};

/// A fresh sim network with these faults.
fn faulty(faults: &[&str]) -> Sim {
    let sim = Sim::new();
    let mut args = vec!["sim", "reset"];
    for f in faults {
        args.extend(["--fault", f]);
    }
    sim.run(&args).ok();
    sim
}

#[test]
fn sim_duplicated_answers_are_set_aside() {
    // Every answer of node 10 sent twice, as CAN double reception does.
    let clean = Sim::new().run(&["sdo", "read", "10", "1008", "--type", "vs", "--no-block"]).ok().stdout;
    let sim = faulty(&["10:duplicate"]);
    assert_eq!(sim.run(&["sdo", "read", "10", "1008", "--type", "vs", "--no-block"]).ok().stdout, clean);
    assert_eq!(sim.run(&["sdo", "read", "10", "1008", "--type", "vs"]).ok().stdout, clean);
    // The second copy of the write's answer reaches the read-back of --verify.
    sim.run(&["sdo", "write", "10", "1017", "100", "--type", "u16", "--verify"]).ok();
}

#[test]
fn sim_short_dlc_answer_is_exit_5_and_no_value() {
    let sim = faulty(&["10:short-dlc=4@1"]);
    let r = sim.run(&["sdo", "read", "10", "1001", "--type", "u8"]);
    assert_eq!(r.code, 5, "{}", r.stderr);
    assert!(r.stdout.is_empty(), "printed data the device did not send: {}", r.stdout);
    assert!(r.stderr.contains("in a 4-byte frame") && r.stderr.contains("needs 5 bytes"), "{}", r.stderr);
    // Five bytes carry all of a one-byte expedited answer (seed 004): legal.
    let clean = Sim::new().run(&["sdo", "read", "10", "1001", "--type", "u8"]).ok().stdout;
    let sim = faulty(&["10:short-dlc=5@1"]);
    assert_eq!(sim.run(&["sdo", "read", "10", "1001", "--type", "u8"]).ok().stdout, clean);
}

#[test]
fn sim_flooded_bus_ends_with_exit_3() {
    // The drive floods its EMCY id, which wins arbitration over every SDO answer.
    let sim = faulty(&["drive:babble"]);
    let r = sim.run(&["--timeout", "200ms", "sdo", "read", "10", "1008", "--type", "vs"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    assert!(r.stderr.contains("node 10: did not answer"), "{}", r.stderr);
}

#[test]
fn sim_device_falling_silent_mid_transfer_ends_with_exit_3() {
    // Node 10 answers the upload and its first segment, then nothing.
    let sim = faulty(&["10:mute@3+"]);
    let r = sim.run(&["--timeout", "200ms", "sdo", "read", "10", "1008", "--type", "vs", "--no-block"]);
    assert_eq!(r.code, 3, "{}", r.stderr);
    assert!(r.stderr.contains("stopped answering") && r.stderr.contains("7 of 9 bytes moved"), "{}", r.stderr);
    assert!(r.stdout.is_empty());
}

#[test]
fn sim_corrupted_segment_is_exit_5() {
    let sim = faulty(&["10:corrupt@2"]);
    let r = sim.run(&["sdo", "read", "10", "1008", "--type", "vs", "--no-block"]);
    assert_eq!(r.code, 5, "{}", r.stderr);
    assert!(r.stdout.is_empty());
}

#[test]
fn sim_upload_over_max_size_is_refused_with_the_limit_named() {
    let sim = Sim::new();
    let r = sim.run(&["sdo", "read", "10", "1008", "--type", "vs", "--max-size", "8"]);
    assert_eq!(r.code, 5, "{}", r.stderr);
    assert!(r.stderr.contains("upload limit of 8 bytes") && r.stderr.contains("--max-size"), "{}", r.stderr);
    assert!(r.stderr.contains("0x05040005"), "{}", r.stderr);
    sim.run(&["sdo", "read", "10", "1008", "--type", "vs", "--max-size", "1k"]).ok();
}

const NODE: u8 = 5;
const OBJ: ObjAddr = ObjAddr::new(0x2000, 1);
const TIMEOUT: Duration = Duration::from_millis(500);
/// Frames the link delivers before it declares the transfer unbounded.
const GIVE_UP: usize = 2_000_000;

/// What the device sends in answer to one request: (virtual delay, payload) pairs.
type Answers = Vec<(Duration, Vec<u8>)>;
/// The device: its answers to each request it receives.
type Device = Box<dyn FnMut(&[u8]) -> Answers>;

struct ScriptedLink {
    now: Instant,
    /// Frames on their way to the master, with the virtual time they arrive.
    pending: Vec<(Instant, Frame)>,
    device: Device,
    /// A frame that keeps coming by itself, every `period`.
    babble: Option<(Duration, Frame, Instant)>,
    /// Virtual time the host spends per frame received: with frames coming faster than
    /// that, they queue up and `recv` never finds the line quiet (a saturated bus).
    cost_per_frame: Duration,
    sent: Vec<Frame>,
    delivered: usize,
}

impl ScriptedLink {
    fn new(device: impl FnMut(&[u8]) -> Answers + 'static) -> ScriptedLink {
        ScriptedLink {
            now: Instant::now(),
            pending: Vec::new(),
            device: Box::new(device),
            babble: None,
            cost_per_frame: Duration::ZERO,
            sent: Vec::new(),
            delivered: 0,
        }
    }

    fn babbling(mut self, period: Duration, frame: Frame) -> ScriptedLink {
        self.babble = Some((period, frame, self.now + period));
        self
    }

    fn costing(mut self, per_frame: Duration) -> ScriptedLink {
        self.cost_per_frame = per_frame;
        self
    }
}

impl FrameLink for ScriptedLink {
    fn send(&mut self, frame: &Frame) -> canctl::Result<()> {
        self.sent.push(*frame);
        if frame.id() == 0x600 + NODE as u16 {
            for (delay, payload) in (self.device)(frame.data()) {
                self.pending.push((self.now + delay, Frame::new(0x580 + NODE as u16, &payload)));
            }
            self.pending.sort_by_key(|(at, _)| *at);
        }
        Ok(())
    }

    fn recv(&mut self, deadline: Instant) -> canctl::Result<Option<Frame>> {
        self.delivered += 1;
        assert!(
            self.delivered < GIVE_UP,
            "the master is still waiting after {GIVE_UP} frames: this transfer is unbounded"
        );
        self.now += self.cost_per_frame;
        let answer_at = self.pending.first().map(|(at, _)| *at);
        let babble_at = self.babble.as_ref().map(|(_, _, at)| *at);
        let next = [answer_at, babble_at].into_iter().flatten().min();
        match next {
            // Already queued frames are delivered even when the deadline has passed, as a
            // socket does; others only if they arrive before it.
            Some(at) if at <= self.now.max(deadline) => {
                self.now = self.now.max(at);
                if Some(at) == answer_at {
                    return Ok(Some(self.pending.remove(0).1));
                }
                let (period, frame, at) = self.babble.as_mut().expect("babble");
                *at += *period;
                Ok(Some(*frame))
            }
            _ => {
                self.now = self.now.max(deadline);
                Ok(None)
            }
        }
    }

    fn name(&self) -> String {
        "scripted".into()
    }

    fn now(&self) -> Instant {
        self.now
    }
}

fn master(link: ScriptedLink) -> Master<ScriptedLink> {
    Master::new(link, "scripted".into())
}

/// One attempt: these tests are about how a single transfer ends (its deadlines, what is
/// progress); repeating it after a timeout is `bus::master`'s tests and tests/dst/.
fn opts() -> SdoOptions {
    SdoOptions { retries: 0, ..SdoOptions::new(TIMEOUT) }
}

/// An SDO answer with OBJ's multiplexer.
fn answer(cmd: u8, data: &[u8]) -> Vec<u8> {
    let mut f = vec![cmd, 0x00, 0x20, 0x01];
    f.extend_from_slice(data);
    f
}

fn at_once(payload: Vec<u8>) -> Answers {
    vec![(Duration::from_millis(2), payload)]
}

/// The abort codes the master sent to the device.
fn aborts_sent(m: &mut Master<ScriptedLink>) -> Vec<u32> {
    m.link_mut()
        .sent
        .iter()
        .filter(|f| f.id() == 0x600 + NODE as u16 && f.data()[0] == 0x80)
        .map(|f| u32::from_le_bytes(f.data()[4..8].try_into().unwrap()))
        .collect()
}

fn exit_code(r: Result<impl std::fmt::Debug, Error>) -> (i32, String) {
    let e = r.expect_err("the transfer must fail");
    // What canctl prints: the message, then the remedy it words.
    (e.exit_code(), canctl::output::library_error_text(&e))
}

#[test]
fn same_node_frames_that_are_no_progress_do_not_restart_the_deadline() {
    // The device never answers the upload, but every 100 ms repeats an answer for another
    // object (a stale answer stuck in its queue). Each used to restart the wait.
    let stale = Frame::new(0x580 + NODE as u16, &[0x43, 0x00, 0x20, 0x02, 1, 2, 3, 4]);
    let link = ScriptedLink::new(|_| vec![]).babbling(Duration::from_millis(100), stale);
    let mut m = master(link);
    let (code, msg) = exit_code(m.sdo_upload(NODE, OBJ, &opts()));
    assert_eq!(code, 3, "{msg}");
    assert!(msg.contains("made no progress for 500 ms") && msg.contains("did not advance it"), "{msg}");
    assert!(msg.contains("43 00 20 02 01 02 03 04"), "{msg}");
    assert_eq!(aborts_sent(&mut m), vec![abort::TIMED_OUT]);
}

#[test]
fn repeated_segment_does_not_keep_a_stalled_upload_alive() {
    // Segmented upload; after two segments the device repeats the second forever.
    let seg2 = {
        let mut f = vec![0x10];
        f.extend_from_slice(&[7; 7]);
        f
    };
    let mut requests = 0;
    let link = ScriptedLink::new(move |req| {
        requests += 1;
        match (requests, req[0]) {
            (1, 0x40) => at_once(answer(0x41, &[100, 0, 0, 0])),
            (2, 0x60) => at_once(vec![0x00, 1, 2, 3, 4, 5, 6, 7]),
            (3, 0x70) => (1..=10_000).map(|i| (Duration::from_millis(50 * i), seg2.clone())).collect(),
            _ => vec![],
        }
    });
    let mut m = master(link);
    let (code, msg) = exit_code(m.sdo_upload(NODE, OBJ, &opts()));
    assert_eq!(code, 3, "{msg}");
    assert!(msg.contains("14 of 100 bytes moved") && msg.contains("a repeat of its previous answer"), "{msg}");
}

#[test]
fn saturated_bus_does_not_keep_a_silent_node_waiting() {
    // Node 9 floods the bus faster than the host reads it: the receive queue is never
    // empty, so a wait that only checks its deadline when the line is quiet never ends.
    let flood = Frame::new(0x709, &[0x05]);
    let link =
        ScriptedLink::new(|_| vec![]).babbling(Duration::from_micros(130), flood).costing(Duration::from_micros(200));
    let mut m = master(link);
    let (code, msg) = exit_code(m.sdo_upload(NODE, OBJ, &opts()));
    assert_eq!(code, 3, "{msg}");
    assert!(msg.contains("node 5: did not answer"), "{msg}");
    assert!(aborts_sent(&mut m).is_empty(), "no abort to a node that never answered");
}

/// Listening for traffic (heartbeats before an LSS assign, a scan's LSS answers) on a bus
/// that is never quiet: the frames keep coming, the wait still ends at its deadline.
#[test]
fn listening_on_a_saturated_bus_ends_at_the_deadline() {
    let flood = Frame::new(0x7F0, &[0x55; 8]);
    let link =
        ScriptedLink::new(|_| vec![]).babbling(Duration::from_micros(130), flood).costing(Duration::from_micros(200));
    let mut m = master(link);
    let end = m.link_mut().now() + Duration::from_secs(1);
    let mut heard = 0;
    while m.recv_frame(end).unwrap().is_some() {
        heard += 1;
    }
    assert!(heard > 1000, "the flood was heard: {heard} frames");
}

/// A block download server that acknowledges each sub-block with `ackseq`.
fn acking_device(ackseq: u8) -> impl FnMut(&[u8]) -> Answers {
    move |req| match req[0] {
        0xC6 => at_once(answer(0xA4, &[127, 0, 0, 0])),
        0x80 => vec![],
        c if c & 0x7F == 127 || c & 0x80 != 0 => at_once(vec![0xA2, ackseq, 127, 0, 0, 0, 0, 0]),
        _ => vec![],
    }
}

#[test]
fn block_download_acknowledged_zero_forever_ends_with_exit_5() {
    let mut m = master(ScriptedLink::new(acking_device(0)));
    let (code, msg) = exit_code(m.sdo_download(NODE, OBJ, &[0x5A; 2000], &opts()));
    assert_eq!(code, 5, "{msg}");
    assert!(msg.contains("acknowledged none of the segments") && msg.contains("0x05040003"), "{msg}");
    assert_eq!(aborts_sent(&mut m), vec![abort::INVALID_SEQUENCE]);
    // The first sub-block and MAX_BLOCK_RETRANSMISSIONS repeats of it, no more.
    let first_segments = m.link_mut().sent.iter().filter(|f| f.data()[0] == 0x01).count();
    assert_eq!(first_segments, 1 + MAX_BLOCK_RETRANSMISSIONS as usize);
}

#[test]
fn block_upload_never_in_sequence_ends_with_exit_5() {
    // The device numbers every sub-block from 2, whatever the client acknowledges.
    let link = ScriptedLink::new(|req| match req[0] {
        0xA4 => at_once(answer(0xC2, &[0x10, 0x27, 0, 0])),
        0xA3 | 0xA2 => {
            (2..=127u8).map(|seq| (Duration::from_micros(130 * seq as u64), vec![seq, 1, 2, 3, 4, 5, 6, 7])).collect()
        }
        _ => vec![],
    });
    let mut m = master(link);
    let mut o = opts();
    o.block_upload = true;
    let (code, msg) = exit_code(m.sdo_upload(NODE, OBJ, &o));
    assert_eq!(code, 5, "{msg}");
    assert!(msg.contains("without segment 1 in sequence"), "{msg}");
    assert_eq!(aborts_sent(&mut m), vec![abort::INVALID_SEQUENCE]);
}

/// A segmented upload server whose object never ends: full segments, never the last.
fn endless_device(initiate: Vec<u8>) -> impl FnMut(&[u8]) -> Answers {
    move |req| match req[0] {
        0x40 => at_once(initiate.clone()),
        t @ (0x60 | 0x70) => at_once(vec![t & 0x10, 0x41, 0x42, 0x43, 0x44, 0x45, 0x46, 0x47]),
        _ => vec![],
    }
}

#[test]
fn endless_upload_stops_at_the_limit_with_exit_5() {
    let mut m = master(ScriptedLink::new(endless_device(answer(0x40, &[]))));
    let mut o = opts();
    o.max_upload = 4096;
    let (code, msg) = exit_code(m.sdo_upload(NODE, OBJ, &o));
    assert_eq!(code, 5, "{msg}");
    assert!(msg.contains("limit of 4096 bytes") && msg.contains("--max-size"), "{msg}");
    assert_eq!(aborts_sent(&mut m), vec![abort::OUT_OF_MEMORY]);
}

#[test]
fn endless_upload_stops_at_the_default_limit() {
    const { assert!(DEFAULT_MAX_UPLOAD < 64 << 20) };
    let mut m = master(ScriptedLink::new(endless_device(answer(0x40, &[]))));
    let (code, msg) = exit_code(m.sdo_upload(NODE, OBJ, &opts()));
    assert_eq!(code, 5, "{msg}");
    assert!(msg.contains(&format!("limit of {DEFAULT_MAX_UPLOAD} bytes")), "{msg}");
}

#[test]
fn announced_size_over_the_limit_is_refused_at_initiation() {
    // 0x80000000 as CiA 301 carries it: 32-bit unsigned, 2 GiB.
    let mut m = master(ScriptedLink::new(endless_device(answer(0x41, &[0, 0, 0, 0x80]))));
    let (code, msg) = exit_code(m.sdo_upload(NODE, OBJ, &opts()));
    assert_eq!(code, 5, "{msg}");
    assert!(msg.contains("announces 2147483648 bytes") && msg.contains("--max-size"), "{msg}");
    assert_eq!(aborts_sent(&mut m), vec![abort::OUT_OF_MEMORY]);
    assert_eq!(m.link_mut().sent.len(), 2, "the request and the abort, no segment request");
}

#[test]
fn short_dlc_answer_is_exit_5_never_data() {
    // Expedited, four bytes indicated, in a DLC-5 frame.
    let mut m = master(ScriptedLink::new(|_| at_once(answer(0x43, &[0x11]))));
    let (code, msg) = exit_code(m.sdo_upload(NODE, OBJ, &opts()));
    assert_eq!(code, 5, "{msg}");
    assert!(msg.contains("5-byte frame"), "{msg}");
    // A segment claiming seven bytes in a DLC-3 frame.
    let mut m = master(ScriptedLink::new(|req| match req[0] {
        0x40 => at_once(answer(0x41, &[20, 0, 0, 0])),
        _ => at_once(vec![0x00, 0xAA, 0xBB]),
    }));
    let (code, msg) = exit_code(m.sdo_upload(NODE, OBJ, &opts()));
    assert_eq!(code, 5, "{msg}");
    // Seed 004: one byte, size indicated, DLC 5: legal.
    let mut m = master(ScriptedLink::new(|_| at_once(answer(0x4F, &[0x02]))));
    assert_eq!(m.sdo_upload(NODE, OBJ, &opts()).unwrap(), vec![0x02]);
}

#[test]
fn expedited_without_size_is_read_by_the_requested_type() {
    let mut m = master(ScriptedLink::new(|_| at_once(answer(0x42, &[0xE8, 0x03, 0x00, 0x00]))));
    let mut o = opts();
    o.size_hint = Some(2);
    assert_eq!(m.sdo_upload(NODE, OBJ, &o).unwrap(), vec![0xE8, 0x03]);
    assert_eq!(m.sdo_upload(NODE, OBJ, &opts()).unwrap(), vec![0xE8, 0x03, 0x00, 0x00]);
}

/// A segmented upload server that answers every request after `delay`; `size` announced
/// or not; the object is `len` bytes.
fn slow_device(delay: Duration, len: usize, announce: bool) -> impl FnMut(&[u8]) -> Answers {
    let mut sent = 0;
    move |req| match req[0] {
        0x40 if announce => vec![(delay, answer(0x41, &(len as u32).to_le_bytes()))],
        0x40 => vec![(delay, answer(0x40, &[]))],
        t @ (0x60 | 0x70) => {
            let n = (len - sent).min(7);
            sent += n;
            let last = (sent == len) as u8;
            let mut seg = vec![(t & 0x10) | ((7 - n as u8) << 1) | last];
            seg.extend(std::iter::repeat_n(0x33, n));
            vec![(delay, seg)]
        }
        _ => vec![],
    }
}

#[test]
fn slow_but_steady_device_finishes() {
    // Every answer at 40% of the timeout: slow, but each in time and the pace (at most
    // half the timeout per segment on average) holds.
    let mut m = master(ScriptedLink::new(slow_device(TIMEOUT * 2 / 5, 700, true)));
    assert_eq!(m.sdo_upload(NODE, OBJ, &opts()).unwrap(), vec![0x33; 700]);
}

#[test]
fn trickling_upload_ends_at_its_total_deadline() {
    // Each segment just inside the timeout, size never announced: the per-answer wait is
    // always met, but the pace is not (the deadline allows half the timeout per segment of
    // the limit): it ends at 4 × 0.5 s + 1000 × 0.25 s, not after 1000 × 0.475 s.
    let mut m = master(ScriptedLink::new(slow_device(TIMEOUT * 19 / 20, 7000, false)));
    let mut o = opts();
    o.max_upload = 7000;
    let (code, msg) = exit_code(m.sdo_upload(NODE, OBJ, &o));
    assert_eq!(code, 3, "{msg}");
    assert!(msg.contains("did not finish within its deadline of 252.0 s"), "{msg}");
    assert_eq!(aborts_sent(&mut m), vec![abort::TIMED_OUT]);
}

#[test]
fn silent_node_times_out_with_exit_3() {
    let mut m = master(ScriptedLink::new(|_| vec![]));
    let (code, msg) = exit_code(m.sdo_download(NODE, OBJ, &[1, 2], &opts()));
    assert_eq!(code, 3, "{msg}");
    assert!(msg.contains("did not answer"), "{msg}");
}
