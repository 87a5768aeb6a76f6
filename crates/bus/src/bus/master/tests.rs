//! Transfers under loss, on virtual time, against one SDO server whose frames (either
//! way) are lost where the test says.

use super::*;
use crate::bus::timeline::Timeline;
use crate::canopen::sdo::{ObjectAccess, SdoServer};

const NODE: u8 = 4;
const CONTROL: ObjAddr = ObjAddr::new(0x1F51, 1);
const SAVE: ObjAddr = ObjAddr::new(0x1010, 1);
const HEARTBEAT: ObjAddr = ObjAddr::new(0x1017, 0);

#[derive(Default)]
struct Objects(BTreeMap<ObjAddr, Vec<u8>>, usize);

impl ObjectAccess for Objects {
    fn read(&mut self, addr: ObjAddr) -> std::result::Result<Vec<u8>, u32> {
        self.0.get(&addr).cloned().ok_or(abort::NO_OBJECT)
    }
    fn write(&mut self, addr: ObjAddr, data: &[u8]) -> std::result::Result<(), u32> {
        self.1 += 1;
        // Program control's state: what was commanded. A save leaves nothing to read.
        if addr != SAVE {
            self.0.insert(addr, data.to_vec());
        }
        Ok(())
    }
    fn check_write(&self, _addr: ObjAddr, _size: Option<usize>) -> std::result::Result<(), u32> {
        Ok(())
    }
}

/// One device; `lose_requests` and `lose_answers` number the frames (from 1) lost on
/// the way to it and from it. Answers take 2 ms.
struct Device {
    server: SdoServer,
    objects: Objects,
    time: Timeline,
    requests: usize,
    answers: usize,
    lose_requests: Vec<usize>,
    lose_answers: Vec<usize>,
    /// Answers that come 150 ms late, and answers that come twice.
    late: Vec<usize>,
    twice: Vec<usize>,
    /// How long the device takes to answer (2 ms unless a test says).
    answer_time: Duration,
    /// What the link says of its frame time (`None`: it does not know).
    frame_time: Option<Duration>,
    /// Whether frames sent wait for the ones before them, a frame time each (a kernel's
    /// transmit queue on a slow bus); else each leaves at once.
    queued: bool,
    /// When the frames sent so far have left, where they are queued.
    busy_until: Instant,
}

impl Device {
    fn new(lose_requests: &[usize], lose_answers: &[usize]) -> Device {
        let time = Timeline::starting_now();
        let mut objects = Objects::default();
        objects.0.insert(CONTROL, vec![0]);
        objects.0.insert(HEARTBEAT, vec![0xE8, 0x03]);
        Device {
            server: SdoServer::new(false),
            objects,
            requests: 0,
            answers: 0,
            lose_requests: lose_requests.to_vec(),
            lose_answers: lose_answers.to_vec(),
            late: Vec::new(),
            twice: Vec::new(),
            answer_time: Duration::from_millis(2),
            frame_time: None,
            queued: false,
            busy_until: time.now,
            time,
        }
    }
}

impl FrameLink for Device {
    fn send(&mut self, frame: &Frame) -> Result<()> {
        self.requests += 1;
        let left = match self.queued {
            true => self.time.now.max(self.busy_until) + self.frame_time.unwrap_or_default(),
            false => self.time.now,
        };
        self.busy_until = left;
        if frame.id() != sdo::request_cob(NODE) || self.lose_requests.contains(&self.requests) {
            return Ok(());
        }
        for answer in self.server.handle(frame.data(), &mut self.objects) {
            self.answers += 1;
            if self.lose_answers.contains(&self.answers) {
                continue;
            }
            let late = if self.late.contains(&self.answers) { 150 } else { 0 };
            let at = left + self.answer_time + Duration::from_millis(late);
            let copies = if self.twice.contains(&self.answers) { 2 } else { 1 };
            for _ in 0..copies {
                self.time.arrive(at, Frame::new(sdo::response_cob(NODE), &answer));
            }
        }
        Ok(())
    }
    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        Ok(self.time.recv(deadline))
    }
    fn name(&self) -> String {
        "test".into()
    }
    fn frame_time(&self) -> Option<Duration> {
        self.frame_time
    }
    fn now(&self) -> Instant {
        self.time.now
    }
    fn sleep_until(&mut self, t: Instant) -> Result<()> {
        self.time.sleep_until(t);
        Ok(())
    }
}

fn master(lose_requests: &[usize], lose_answers: &[usize]) -> Master<Device> {
    Master::new(Device::new(lose_requests, lose_answers), "test".into())
}

fn opts() -> SdoOptions {
    SdoOptions::new(Duration::from_millis(100))
}

#[test]
fn a_lost_request_and_a_lost_answer_are_retried() {
    let mut m = master(&[1], &[]);
    assert_eq!(m.sdo_upload(NODE, HEARTBEAT, &opts()).unwrap(), vec![0xE8, 0x03]);
    let mut m = master(&[], &[1]);
    m.sdo_download(NODE, HEARTBEAT, &[0xD0, 0x07], &opts()).unwrap();
    assert_eq!(m.link.objects.0[&HEARTBEAT], vec![0xD0, 0x07]);
    assert_eq!(m.link.objects.1, 2, "written twice, the same value");
}

#[test]
fn retries_are_bounded() {
    let mut m = master(&[1, 3, 5, 6], &[]);
    let e = m.sdo_upload(NODE, HEARTBEAT, &opts()).unwrap_err();
    assert!(matches!(e, Error::NoAnswer { .. }), "{e}");
    // The first request and two retries, each after an abort: no fourth attempt. Then
    // without retries, the one request (the sixth frame) lost ends it.
    assert_eq!(m.link.requests, 5);
    let e = m.sdo_upload(NODE, HEARTBEAT, &SdoOptions { retries: 0, ..opts() }).unwrap_err();
    assert!(matches!(e, Error::NoAnswer { .. }), "{e}");
}

/// A node that never answers costs every retry: the message says what was tried, not
/// the one timeout of the last request.
#[test]
fn an_unreachable_node_is_reported_with_every_request_tried() {
    let mut m = master(&(1..=20).collect::<Vec<_>>(), &[]);
    let e = m.sdo_upload(NODE, HEARTBEAT, &opts()).unwrap_err();
    assert_eq!(e.exit_code(), 3);
    assert_eq!(
        e.to_string(),
        "node 4: did not answer the SDO transfer of 0x1017:0: no answer to 3 requests, 300 ms in all \
         (100 ms each)"
    );
    let e = m.sdo_upload(NODE, HEARTBEAT, &SdoOptions { retries: 0, ..opts() }).unwrap_err();
    assert_eq!(e.to_string(), "node 4: did not answer the SDO transfer of 0x1017:0 (waited 100 ms)");
}

#[test]
fn a_store_whose_answer_is_lost_is_sent_once_and_its_outcome_unknown() {
    let mut m = master(&[], &[1]);
    let e = m.sdo_download(NODE, SAVE, b"save", &opts()).unwrap_err();
    assert!(matches!(e, Error::SdoOutcomeUnknown { obj: SAVE, .. }), "{e}");
    assert_eq!(e.exit_code(), 3);
    assert_eq!(m.link.objects.1, 1, "the save was sent once");
    // Its request lost instead: the device did nothing, which canctl cannot tell either.
    let mut m = master(&[1], &[]);
    let e = m.sdo_download(NODE, SAVE, b"save", &opts()).unwrap_err();
    assert!(matches!(e, Error::SdoOutcomeUnknown { .. }), "{e}");
    assert_eq!(m.link.requests, 1, "nothing sent after it");
}

#[test]
fn program_control_whose_answer_is_lost_is_read_back_not_repeated() {
    // Started, its answer lost: the read-back shows it started.
    let mut m = master(&[], &[1]);
    m.sdo_download(NODE, CONTROL, &[1], &opts()).unwrap();
    assert_eq!(m.link.objects.1, 1, "sent once");
    // The request lost: the read-back shows it did not start, and the outcome stays
    // unknown (the device may still be on its way); nothing is sent again.
    let mut m = master(&[1], &[]);
    let e = m.sdo_download(NODE, CONTROL, &[1], &opts()).unwrap_err();
    assert!(matches!(e, Error::SdoOutcomeUnknown { obj: CONTROL, .. }), "{e}");
    assert_eq!(m.link.objects.1, 0);
}

#[test]
fn a_segment_late_past_the_timeout_is_not_taken_for_the_retrys_answers() {
    let name = ObjAddr::new(0x1008, 0);
    let mut m = master(&[], &[]);
    m.link.objects.0.insert(name, b"a device name of 24 bytes".to_vec());
    // The answer with the second segment comes after the timeout, when the read has
    // started again; the retry's first answer comes twice.
    m.link.late = vec![3];
    m.link.twice = vec![4];
    assert_eq!(m.sdo_upload(NODE, name, &opts()).unwrap(), b"a device name of 24 bytes");
    // Initiation, two segment requests, the abort, then the whole read again (four
    // segments of seven bytes): the late segment moved nothing, the repeat neither.
    assert_eq!(m.link.requests, 3 + 1 + 5);
}

/// A probe's options: two more requests at most, each 20 ms after the one before.
fn asking_again() -> SdoOptions {
    SdoOptions { retries: 2, ask_again_after: Some(Duration::from_millis(20)), ..opts() }
}

/// A read that may be asked again, answered at once but by segments for longer than the
/// time to ask again (a device that sends a long value, or without end): once heard, its
/// time to ask again is past and no longer applies, and the batch waits for the segments
/// instead of spinning on that time (on virtual time it never ended).
#[test]
fn a_read_heard_and_going_on_past_its_time_to_ask_again_ends() {
    const NAME: ObjAddr = ObjAddr::new(0x1008, 0);
    let long: Vec<u8> = (0..200).map(|i| b'a' + i % 26).collect();
    let mut m = master(&[], &[]);
    m.link.frame_time = Some(Duration::ZERO);
    m.link.objects.0.insert(NAME, long.clone());
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || tx.send(m.sdo_upload(NODE, NAME, &asking_again()).map(|v| (v, m.link.requests))));
    let (value, requests) = rx.recv_timeout(Duration::from_secs(20)).expect("the read ended").unwrap();
    assert_eq!(value, long);
    assert_eq!(requests, 1 + 200usize.div_ceil(7), "one request, then one per segment: none asked again");
}

/// A read whose request was lost is asked again a typical answer time later, not a timeout
/// later, without an abort (nothing was under way); the count of answers tells of the loss.
#[test]
fn a_read_asked_again_early_recovers_a_lost_request_within_the_first_window() {
    let mut m = master(&[1], &[]);
    m.link.frame_time = Some(Duration::ZERO);
    let start = m.link.time.now;
    assert_eq!(m.sdo_upload(NODE, HEARTBEAT, &asking_again()).unwrap(), vec![0xE8, 0x03]);
    assert_eq!(m.link.requests, 2, "the request again, and no abort before it");
    // The answer came 22 ms in; the batch then listened for an answer to the other request
    // until its window closed, to count it (in a probe, the silent ids wait that long anyway).
    assert_eq!(m.link.time.now - start, Duration::from_millis(120));
    let asked = &m.observed.answers_counted[&(NODE, HEARTBEAT)];
    assert_eq!((asked.requests, &asked.answers[..]), (2, &[Some(1000)][..]));
    assert!(asked.lost_frames());
}

/// A node slower than the time to ask again answers every request: it lost nothing, and
/// its count says so. Where the link does not know its frame time, the old retry after a
/// timeout stands.
#[test]
fn a_slow_node_asked_again_answers_every_request_and_is_not_taken_for_a_loss() {
    let mut m = master(&[], &[]);
    m.link.frame_time = Some(Duration::from_micros(270));
    m.link.answer_time = Duration::from_millis(50);
    assert_eq!(m.sdo_upload(NODE, HEARTBEAT, &asking_again()).unwrap(), vec![0xE8, 0x03]);
    assert_eq!(m.link.requests, 3);
    let asked = &m.observed.answers_counted[&(NODE, HEARTBEAT)];
    assert_eq!((asked.requests, &asked.answers[..]), (3, &[Some(1000); 3][..]));
    assert!(!asked.lost_frames());

    let mut m = master(&[1], &[]);
    assert_eq!(m.sdo_upload(NODE, HEARTBEAT, &asking_again()).unwrap(), vec![0xE8, 0x03]);
    assert_eq!(m.link.requests, 3, "the request, an abort after the timeout, the request again");
    assert!(m.observed.answers_counted.is_empty());
}

/// A read by segments in a batch with many other requests (a scan's): the request for the
/// next segment waits behind them on a slow bus, and its answer is waited for from when the
/// request left, not from when it was queued (it was given up, and said lost, before).
#[test]
fn a_segment_request_queued_behind_others_is_waited_for_from_when_it_left() {
    const NAME: ObjAddr = ObjAddr::new(0x1008, 0);
    let mut m = master(&[], &[]);
    (m.link.frame_time, m.link.queued) = (Some(Duration::from_millis(5)), true);
    m.link.objects.0.insert(NAME, b"a long name".to_vec());
    // Asked once: a retry would hide the transfer given up.
    let once = SdoOptions { retries: 0, ..opts() };
    let mut jobs = vec![SdoJob::Upload { node: NODE, addr: NAME, opts: once.clone() }];
    // Sixty nodes that are not there: their requests fill the bus for 300 ms.
    jobs.extend((10..70).map(|node| SdoJob::Upload { node, addr: HEARTBEAT, opts: once.clone() }));
    let read = m.sdo_many(&jobs).unwrap();
    assert_eq!(read[0].as_ref().unwrap(), b"a long name");
    assert_eq!(m.link.requests, 61 + 2, "the requests, and one per segment");
}

/// A slow node asked again answers every request, and the read goes on by segments: the
/// answers to the other requests come while it does, taken for repeats; its count shows
/// nothing, and no lost frame is said.
#[test]
fn a_slow_node_asked_again_whose_read_goes_on_by_segments_is_not_taken_for_a_loss() {
    const NAME: ObjAddr = ObjAddr::new(0x1008, 0);
    let mut m = master(&[], &[]);
    m.link.frame_time = Some(Duration::from_micros(270));
    m.link.answer_time = Duration::from_millis(50);
    m.link.objects.0.insert(NAME, b"a long name".to_vec());
    assert_eq!(m.sdo_upload(NODE, NAME, &asking_again()).unwrap(), b"a long name");
    let lost = m.observed.answers_counted.values().any(|a| a.lost_frames());
    assert!(!lost, "{:?}", m.observed.answers_counted);
}

/// A segment of a transfer before, late, comes first into a read that counts its answers,
/// then the read's own answer, while the batch waits for a silent node: the read is not
/// counted (the segment answers something else), so the answer after it is not taken for a
/// second device's.
#[test]
fn a_late_segment_of_the_transfer_before_is_not_counted_as_an_answer() {
    let mut m = master(&[], &[]);
    m.link.frame_time = Some(Duration::ZERO);
    let late_segment = Frame::new(sdo::response_cob(NODE), &[0x00, b'E', b'N', b'D', b'L', b'E', b'S', b'S']);
    m.link.time.arrive(m.link.time.now + Duration::from_millis(1), late_segment);
    let read = |node| SdoJob::Upload { node, addr: HEARTBEAT, opts: asking_again() };
    m.sdo_many(&[read(NODE), read(NODE + 1)]).unwrap();
    let doubled = m.observed.answers_counted.values().any(|a| a.answers.len() > usize::from(a.requests));
    assert!(!doubled, "{:?}", m.observed.answers_counted);
}

/// A slow node asked again answers the first request; the user stops the batch then, before
/// the answer to the second request could come: the count, cut short, shows no lost frame.
#[test]
fn a_count_of_answers_cut_short_by_a_stop_shows_no_loss() {
    let mut m = master(&[], &[]);
    m.link.frame_time = Some(Duration::from_micros(270));
    m.link.answer_time = Duration::from_millis(30);
    let stop = Cancel::new();
    let opts = SdoOptions { stop: Some(stop.clone()), ..asking_again() };
    let job = SdoJob::Upload { node: NODE, addr: HEARTBEAT, opts };
    let read = m.sdo_batch(&[job], &mut |_| stop.cancel()).unwrap();
    assert_eq!(read[0].as_ref().unwrap(), &vec![0xE8, 0x03]);
    assert_eq!(m.link.requests, 2, "asked again once before the first answer");
    let lost = m.observed.answers_counted.values().any(|a| a.lost_frames());
    assert!(!lost, "{:?}", m.observed.answers_counted);
}

/// A second device on the node-id answers the same read: in a batch that counts answers, an
/// answer after the first that comes while the batch runs (it waits for a silent node
/// here) is kept with its value, for the clash check.
#[test]
fn a_second_answer_to_one_read_is_counted_with_its_value() {
    let mut m = master(&[], &[]);
    m.link.frame_time = Some(Duration::ZERO);
    m.link.twice = vec![1];
    let once = SdoOptions { ask_again_after: None, ..asking_again() };
    let jobs = [
        SdoJob::Upload { node: NODE, addr: HEARTBEAT, opts: once },
        SdoJob::Upload { node: NODE + 1, addr: HEARTBEAT, opts: asking_again() },
    ];
    let results = m.sdo_batch(&jobs, &mut |_| {}).unwrap();
    assert_eq!(results[0].as_ref().unwrap(), &vec![0xE8, 0x03]);
    let asked = &m.observed.answers_counted[&(NODE, HEARTBEAT)];
    assert_eq!((asked.requests, &asked.answers[..]), (1, &[Some(1000), Some(1000)][..]));
}

/// A node that answers none of its first read's requests is not asked its other reads in a
/// batch that counts answers: each would be one more window of silence.
#[test]
fn a_silent_node_is_not_asked_the_rest_of_its_reads_where_the_batch_counts_answers() {
    let mut m = master(&(1..=20).collect::<Vec<_>>(), &[]);
    m.link.frame_time = Some(Duration::ZERO);
    let o = asking_again();
    let jobs = [HEARTBEAT, CONTROL].map(|addr| SdoJob::Upload { node: NODE, addr, opts: o.clone() });
    let start = m.link.time.now;
    let results = m.sdo_batch(&jobs, &mut |_| {}).unwrap();
    assert!(results.iter().all(|r| matches!(r, Err(Error::NoAnswer { .. }))), "{results:?}");
    assert_eq!(m.link.requests, 3, "the first read asked three times, the second not at all");
    assert_eq!(m.link.time.now - start, Duration::from_millis(140), "20 + 20 + one window");
}
