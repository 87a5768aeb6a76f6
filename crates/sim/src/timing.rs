//! Time on the simulated bus: how late devices answer (profiles, seeded jitter), how long
//! each frame occupies the bus at its bit rate, and the order frames leave in.
//!
//! Pure: times are nanoseconds on a bus clock the caller keeps (`SimLink` anchors it to
//! the wall clock), so every rule here is a unit test without sleeping.

use crate::frame::Frame;
use std::collections::BTreeMap;
use std::fmt;
use std::str::FromStr;

/// Nanoseconds on the bus clock.
pub(crate) type Nanos = u64;

pub(crate) const US: Nanos = 1_000;
pub(crate) const MS: Nanos = 1_000_000;

/// A small, seeded pseudo-random generator (SplitMix64): the same seed gives the same
/// latencies and faults, so a failing run can be replayed.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator whose draws are fixed by `seed`.
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// A generator for one device: the network's seed mixed with the device's stable key,
    /// so adding a device does not change the others' draws.
    pub(crate) fn for_device(seed: u64, key: &str) -> Rng {
        // FNV-1a over the key.
        let h = key.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3));
        Rng::new(seed ^ h)
    }

    /// The next draw (splitmix64).
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `lo..=hi`.
    pub fn between(&mut self, lo: u64, hi: u64) -> u64 {
        if hi <= lo {
            return lo;
        }
        lo + self.next_u64() % (hi - lo + 1)
    }

    /// True with this probability (0.0..=1.0).
    pub fn chance(&mut self, p: f64) -> bool {
        ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64) < p
    }
}

/// How late the devices answer, and whether frames take time on the bus.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Profile {
    /// Answers at once and frames take no time: a function call, for unit tests of
    /// protocol logic only.
    Instant,
    /// Small, realistic: each device answers 0.5–3 ms after a request; bus timing on.
    /// (Seed 002 measures an EPOS2 SDO round trip at 794 µs at 1 Mbit/s, and 100 round
    /// trips at 159 ms: 0.6–1.4 ms of answer time.)
    #[default]
    Typical,
    /// Slow slaves, as real ones can be: answers 5–80 ms late; bus timing on.
    Slow,
}

impl Profile {
    /// The profiles by name, as `--profile` takes them.
    pub const NAMES: [&'static str; 3] = ["instant", "typical", "slow"];

    /// The range a device's own base latency is drawn from, and the jitter added to each
    /// answer (both in ns).
    fn latency(self) -> ((Nanos, Nanos), Nanos) {
        match self {
            Profile::Instant => ((0, 0), 0),
            Profile::Typical => ((500 * US, 2 * MS), MS),
            Profile::Slow => ((5 * MS, 60 * MS), 20 * MS),
        }
    }

    /// How long a device is silent after an NMT reset before its boot-up: a real device
    /// restarts its firmware (CANopenNode on a small controller: tens of ms; drives longer),
    /// and a master that reads the first answer after the reset as its effect is wrong.
    pub(crate) fn reset_ms(self) -> u64 {
        match self {
            Profile::Instant => 0,
            Profile::Typical => 100,
            Profile::Slow => 300,
        }
    }

    /// The answer time of one device: drawn once per device, from its own generator.
    pub(crate) fn device_latency(self, rng: &mut Rng) -> Latency {
        let ((lo, hi), jitter) = self.latency();
        Latency { base: rng.between(lo, hi), jitter }
    }
}

impl fmt::Display for Profile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(Profile::NAMES[*self as usize])
    }
}

impl FromStr for Profile {
    type Err = String;
    fn from_str(s: &str) -> Result<Profile, String> {
        let all = [Profile::Instant, Profile::Typical, Profile::Slow];
        all.into_iter()
            .find(|p| p.to_string() == s)
            .ok_or_else(|| format!("'{s}' is not a sim profile: use instant, typical or slow"))
    }
}

/// One device's answer time: its base latency plus up to `jitter` on each answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Latency {
    pub base: Nanos,
    pub jitter: Nanos,
}

impl Latency {
    pub(crate) fn draw(&self, rng: &mut Rng) -> Nanos {
        self.base + rng.between(0, self.jitter)
    }
}

/// Bits per second of a CiA 305 bit timing table index; `None` for reserved or automatic.
pub fn bits_per_second(index: u8) -> Option<u64> {
    crate::canopen::lss::BIT_TIMINGS.get(index as usize).and_then(|(_, k)| k.map(|k| k as u64 * 1000))
}

/// CRC-15/CAN (polynomial 0x4599) over the bits from SOF to the end of the data field.
fn crc15(bits: &[bool]) -> u16 {
    let mut crc: u16 = 0;
    for &b in bits {
        let divide = b ^ (crc >> 14 & 1 == 1);
        crc = ((crc << 1) & 0x7FFF) ^ if divide { 0x4599 } else { 0 };
    }
    crc
}

/// Stuff bits the transmitter inserts: after five equal bits, one of the other value,
/// which itself starts the next run.
fn stuff_bits(bits: &[bool]) -> u32 {
    let (mut count, mut last, mut run) = (0, None, 0);
    for &b in bits {
        run = if Some(b) == last { run + 1 } else { 1 };
        last = Some(b);
        if run == 5 {
            count += 1;
            last = Some(!b);
            run = 1;
        }
    }
    count
}

/// The bits a CAN 2.0A (11-bit id) frame occupies on the bus, stuff bits counted exactly:
/// SOF, id, RTR, IDE, r0, DLC, data and CRC are stuffed; CRC delimiter, ACK slot and
/// delimiter, EOF (7) and the 3-bit intermission are not.
pub(crate) fn frame_bits(f: &Frame) -> u32 {
    let mut bits = Vec::with_capacity(100);
    bits.push(false); // SOF
    bits.extend((0..11).rev().map(|i| f.id() >> i & 1 == 1));
    bits.push(f.is_remote());
    bits.extend([false, false]); // IDE, r0
    let dlc = f.len() as u8;
    bits.extend((0..4).rev().map(|i| dlc >> i & 1 == 1));
    if !f.is_remote() {
        bits.extend(f.data().iter().flat_map(|b| (0..8).rev().map(move |i| b >> i & 1 == 1)));
    }
    let crc = crc15(&bits);
    bits.extend((0..15).rev().map(|i| crc >> i & 1 == 1));
    bits.len() as u32 + stuff_bits(&bits) + 1 + 2 + 7 + 3
}

/// How long `f` occupies the bus at `bps` bits per second.
pub fn frame_time(f: &Frame, bps: u64) -> Nanos {
    frame_bits(f) as u64 * 1_000_000_000 / bps
}

/// Who put a frame on the bus.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Origin {
    Master,
    Device(usize),
}

#[derive(Clone, Copy, Debug)]
enum Next {
    Queued(Origin, Order),
    Babble(usize),
}

/// A queued frame's place in its sender's queue: when it was ready, then the order it was
/// queued in.
type Order = (Nanos, u64);

#[derive(Debug)]
struct Queued {
    frame: Frame,
    /// `frame_bits(frame)`, counted once: the queue is looked at far more often than it
    /// changes (on virtual time, at every wait).
    bits: u32,
}

/// A device that floods the bus: it always has a frame on this id ready, from `next` on.
#[derive(Debug)]
struct Babbler {
    device: usize,
    id: u16,
    next: Nanos,
    count: u64,
    /// The bits of its next frame (as `Queued::bits`).
    bits: u32,
}

/// A babbling device sends at most one frame per this long even where frames take no time.
const BABBLE_GAP: Nanos = 62_500;

/// Frames that have left the bus, and how long it was busy.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BusStats {
    /// Frames that completed on the bus.
    pub frames: u64,
    /// Time the bus was busy sending them (ns), bit stuffing and interframe space included.
    pub busy: Nanos,
}

/// The bus as one transmitter at a time: frames wait until they are ready and the bus is
/// free; each sender's frames leave in the order it queued them, and of the senders'
/// first frames waiting when the bus frees, the lowest id wins arbitration.
#[derive(Debug, Default)]
pub(crate) struct BusQueue {
    /// The bus's bit rate; `None`: frames take no time.
    pub(crate) bps: Option<u64>,
    free_at: Nanos,
    /// Each sender's frames in the order they leave. Per sender, so that choosing the next
    /// frame looks at each sender's first frame only: a device that floods the bus keeps
    /// hundreds of frames waiting (the master's probe of every node-id), and the simulated
    /// bus is asked for its next frame twice for every frame.
    queued: BTreeMap<Origin, BTreeMap<Order, Queued>>,
    babblers: Vec<Babbler>,
    seq: u64,
    pub(crate) stats: BusStats,
}

impl BusQueue {
    pub fn new(bps: Option<u64>) -> BusQueue {
        BusQueue { bps, ..BusQueue::default() }
    }

    /// How many frames from this origin are waiting.
    pub(crate) fn waiting_from(&self, origin: Origin) -> usize {
        self.queued.get(&origin).map_or(0, BTreeMap::len)
    }

    /// A frame ready to go at `ready`.
    pub fn queue(&mut self, ready: Nanos, origin: Origin, frame: Frame) {
        self.seq += 1;
        let queued = Queued { frame, bits: frame_bits(&frame) };
        self.queued.entry(origin).or_default().insert((ready, self.seq), queued);
    }

    /// This device floods the bus with frames on `id` from `since` on (once told).
    pub fn babble(&mut self, device: usize, id: u16, since: Nanos) {
        if !self.babblers.iter().any(|b| b.device == device) {
            let bits = frame_bits(&Frame::new(id, &0u64.to_le_bytes()));
            self.babblers.push(Babbler { device, id, next: since, count: 0, bits });
        }
    }

    /// Only these devices babble any more (the others fell silent).
    pub(crate) fn keep_babblers(&mut self, devices: &[usize]) {
        self.babblers.retain(|b| devices.contains(&b.device));
    }

    fn babble_frame(b: &Babbler) -> Frame {
        Frame::new(b.id, &b.count.to_le_bytes())
    }

    /// The next frame to go, as things stand: (queued index or babbler, start, end).
    fn next(&self) -> Option<(Next, Nanos, Nanos)> {
        // Each sender's frames leave in the order it queued them (a FIFO per controller,
        // as SocketCAN's queue discipline gives the master), a frame entering its
        // controller's queue when it is ready; the senders' first frames compete in
        // arbitration.
        let heads = self.queued.iter().filter_map(|(origin, frames)| {
            let (order, q) = frames.first_key_value()?;
            Some((*origin, *order, q))
        });
        let first_ready =
            heads.clone().map(|(_, (ready, _), _)| ready).chain(self.babblers.iter().map(|b| b.next)).min()?;
        let start = self.free_at.max(first_ready);
        let queued = heads
            .filter(|(_, (ready, _), _)| *ready <= start)
            .map(|(origin, order, q)| ((q.frame.id(), 0, order.1), Next::Queued(origin, order), q.bits));
        let ready_babblers = self.babblers.iter().enumerate().filter(|(_, b)| b.next <= start);
        let babbling = ready_babblers.map(|(i, b)| ((b.id, 1, 0), Next::Babble(i), b.bits));
        let (_, next, bits) = queued.chain(babbling).min_by_key(|(key, _, _)| *key).expect("a ready frame");
        let end = start + self.bps.map_or(0, |bps| bits as u64 * 1_000_000_000 / bps);
        Some((next, start, end))
    }

    /// When the next frame will have left the bus, if any is queued.
    pub(crate) fn next_done(&self) -> Option<Nanos> {
        self.next().map(|(_, _, end)| end)
    }

    /// The next frame that has completely left the bus by `now`, with the time it did.
    pub(crate) fn pop_done(&mut self, now: Nanos) -> Option<(Nanos, Origin, Frame)> {
        let (next, start, end) = self.next()?;
        if end > now {
            return None;
        }
        self.free_at = end;
        self.stats.frames += 1;
        self.stats.busy += end - start;
        match next {
            Next::Queued(origin, order) => {
                let frames = self.queued.get_mut(&origin).expect("a sender with frames");
                let q = frames.remove(&order).expect("its first frame");
                if frames.is_empty() {
                    self.queued.remove(&origin);
                }
                Some((end, origin, q.frame))
            }
            Next::Babble(i) => {
                let b = &mut self.babblers[i];
                let frame = Self::babble_frame(b);
                b.count += 1;
                b.bits = frame_bits(&Self::babble_frame(b));
                b.next = b.next.max(start + BABBLE_GAP);
                Some((end, Origin::Device(b.device), frame))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::worst_case_bits;

    #[test]
    fn crc15_of_a_single_one_bit_is_the_polynomial() {
        assert_eq!(crc15(&[true]), 0x4599);
        assert_eq!(crc15(&[false; 20]), 0);
    }

    #[test]
    fn stuffing_counts_runs_of_five_including_the_stuffed_bit() {
        assert_eq!(stuff_bits(&[false; 4]), 0);
        assert_eq!(stuff_bits(&[false; 5]), 1);
        // 00000 [1] 0000: the stuffed 1 ends the zeros; four more zeros make no run of five.
        assert_eq!(stuff_bits(&[false; 9]), 1);
        assert_eq!(stuff_bits(&[false; 10]), 2);
        // 11111 [0] 0000 → the stuffed 0 and four zeros are five equal bits: stuffed again.
        let mut bits = vec![true; 5];
        bits.extend([false; 4]);
        assert_eq!(stuff_bits(&bits), 2);
    }

    #[test]
    fn all_zero_frame_time() {
        // 34 stuffed-region bits, all zero (the CRC of zeros is zero): 6 stuff bits, plus
        // 13 fixed-form bits.
        assert_eq!(frame_bits(&Frame::new(0, &[])), 34 + 6 + 13);
        // 1 µs a bit at 1 Mbit/s.
        assert_eq!(frame_time(&Frame::new(0, &[]), 1_000_000), 53 * US);
    }

    #[test]
    fn frame_bits_lie_between_unstuffed_and_the_worst_case() {
        let mut rng = Rng::new(7);
        for n in 0..=8 {
            for _ in 0..200 {
                let data: Vec<u8> = (0..n).map(|_| rng.next_u64() as u8).collect();
                let f = Frame::new((rng.next_u64() & 0x7FF) as u16, &data);
                let bits = frame_bits(&f);
                assert!(bits >= 47 + 8 * n as u32, "{f:?}: {bits}");
                assert!(bits <= worst_case_bits(n), "{f:?}: {bits}");
            }
        }
        assert_eq!(worst_case_bits(8), 135);
        assert_eq!(worst_case_bits(0), 55);
    }

    #[test]
    fn a_remote_frame_carries_no_data_bits() {
        let remote = frame_bits(&Frame::remote(0x701, 1));
        assert!((47..=worst_case_bits(0)).contains(&remote), "{remote}");
    }

    #[test]
    fn frames_ready_together_leave_lowest_id_first() {
        let mut bus = BusQueue::new(Some(1_000_000));
        bus.queue(0, Origin::Master, Frame::new(0x605, &[0x40; 8]));
        bus.queue(0, Origin::Device(1), Frame::new(0x585, &[0x43; 8]));
        bus.queue(0, Origin::Device(0), Frame::new(0x181, &[1]));
        let order: Vec<u16> = std::iter::from_fn(|| bus.pop_done(u64::MAX)).map(|(_, _, f)| f.id()).collect();
        assert_eq!(order, [0x181, 0x585, 0x605]);
    }

    #[test]
    fn a_frame_that_arrives_while_the_bus_is_busy_waits_then_wins_over_higher_ids() {
        let mut bus = BusQueue::new(Some(1_000_000));
        bus.queue(0, Origin::Master, Frame::new(0x600, &[0; 8]));
        bus.queue(0, Origin::Master, Frame::new(0x601, &[0; 8]));
        // Ready while 0x600 is on the bus: takes part in the next arbitration.
        bus.queue(10 * US, Origin::Device(0), Frame::new(0x080, &[]));
        let (end1, _, f1) = bus.pop_done(u64::MAX).unwrap();
        assert_eq!(f1.id(), 0x600);
        let (end2, _, f2) = bus.pop_done(u64::MAX).unwrap();
        assert_eq!(f2.id(), 0x080);
        assert_eq!(end2, end1 + frame_time(&f2, 1_000_000), "back to back");
        assert_eq!(bus.pop_done(u64::MAX).unwrap().2.id(), 0x601);
    }

    #[test]
    fn one_senders_frames_leave_in_its_order_and_others_win_arbitration_between_them() {
        let mut bus = BusQueue::new(Some(125_000));
        bus.queue(0, Origin::Master, Frame::new(0x67F, &[0x40; 8]));
        bus.queue(0, Origin::Master, Frame::new(0x000, &[0x02, 0x00]));
        bus.queue(0, Origin::Device(3), Frame::new(0x7E4, &[0x50; 8]));
        bus.queue(0, Origin::Device(2), Frame::new(0x182, &[1]));
        let order: Vec<u16> = std::iter::from_fn(|| bus.pop_done(u64::MAX)).map(|(_, _, f)| f.id()).collect();
        assert_eq!(order, [0x182, 0x67F, 0x000, 0x7E4]);
    }

    /// A frame that became ready earlier than one queued before it leaves first (its
    /// controller had it first); a sender's hundreds of waiting frames (a probe of every
    /// node-id) keep their order beside a device flooding the bus with a higher id, and
    /// behind one with a lower id none gets out.
    #[test]
    fn a_senders_queue_is_in_ready_order_and_keeps_it_beside_a_flood() {
        let mut bus = BusQueue::new(Some(500_000));
        bus.queue(50 * US, Origin::Device(1), Frame::new(0x701, &[0x7F]));
        bus.queue(10 * US, Origin::Device(1), Frame::new(0x581, &[0x43; 8]));
        let order: Vec<u16> = std::iter::from_fn(|| bus.pop_done(u64::MAX)).map(|(_, _, f)| f.id()).collect();
        assert_eq!(order, [0x581, 0x701]);
        for (flood, out) in [(0x7FF, 127), (0x001, 0)] {
            let mut bus = BusQueue::new(Some(500_000));
            bus.babble(0, flood, 0);
            for node in 1..=127u16 {
                bus.queue(0, Origin::Master, Frame::new(0x600 + node, &[0x40, 0, 0x10, 0, 0, 0, 0, 0]));
            }
            let sent: Vec<u16> = std::iter::from_fn(|| bus.pop_done(u64::MAX))
                .take(2_000)
                .filter(|(_, origin, _)| *origin == Origin::Master)
                .map(|(_, _, f)| f.id() - 0x600)
                .collect();
            assert_eq!(sent, (1..).take(out).collect::<Vec<u16>>(), "flood on {flood:03X}");
            assert_eq!(bus.waiting_from(Origin::Master), 127 - out);
        }
    }

    #[test]
    fn equal_ids_keep_queue_order_and_a_frame_is_not_done_before_its_end() {
        let mut bus = BusQueue::new(Some(125_000));
        for i in 0..3u8 {
            bus.queue(0, Origin::Device(0), Frame::new(0x581, &[i; 8]));
        }
        let end = bus.next_done().unwrap();
        assert!(bus.pop_done(end - 1).is_none());
        let firsts: Vec<u8> = std::iter::from_fn(|| bus.pop_done(u64::MAX)).map(|(_, _, f)| f.data()[0]).collect();
        assert_eq!(firsts, [0, 1, 2]);
        assert!(bus.stats.busy >= 3 * 111 * 8 * US);
    }

    #[test]
    fn a_babbler_with_a_low_id_starves_higher_ids_and_one_with_a_high_id_yields() {
        let mut bus = BusQueue::new(Some(1_000_000));
        bus.babble(0, 0x001, 0);
        bus.queue(0, Origin::Master, Frame::new(0x605, &[0x40; 8]));
        for _ in 0..100 {
            assert_eq!(bus.pop_done(u64::MAX).unwrap().2.id(), 0x001);
        }
        let mut bus = BusQueue::new(Some(1_000_000));
        bus.babble(0, 0x700, 0);
        bus.queue(10 * MS, Origin::Master, Frame::new(0x605, &[0x40; 8]));
        let ids: Vec<u16> = (0..200).map(|_| bus.pop_done(u64::MAX).unwrap().2.id()).collect();
        assert_eq!(ids.iter().filter(|id| **id == 0x605).count(), 1);
        // The bus never idles: frames back to back.
        assert!(bus.stats.busy > 200 * 100 * US);
        // Untimed, a babbler still sends one frame per gap, not infinitely many.
        let mut untimed = BusQueue::new(None);
        untimed.babble(0, 0x080, 0);
        assert_eq!(std::iter::from_fn(|| untimed.pop_done(MS)).count(), 17);
    }

    #[test]
    fn an_idle_bus_sends_a_late_frame_when_it_is_ready() {
        let mut bus = BusQueue::new(Some(1_000_000));
        bus.queue(5 * MS, Origin::Master, Frame::new(0x000, &[]));
        assert_eq!(bus.next_done(), Some(5 * MS + 53 * US));
        let mut untimed = BusQueue::new(None);
        untimed.queue(5 * MS, Origin::Master, Frame::new(0x000, &[]));
        assert_eq!(untimed.pop_done(5 * MS).map(|(t, _, _)| t), Some(5 * MS));
    }

    #[test]
    fn profile_latencies_stay_in_their_ranges_and_replay_from_the_seed() {
        for (p, lo, hi) in
            [(Profile::Instant, 0, 0), (Profile::Typical, 500 * US, 3 * MS), (Profile::Slow, 5 * MS, 80 * MS)]
        {
            let mut rng = Rng::for_device(42, "drive");
            let lat = p.device_latency(&mut rng);
            let draws: Vec<Nanos> = (0..500).map(|_| lat.draw(&mut rng)).collect();
            assert!(draws.iter().all(|d| (lo..=hi).contains(d)), "{p}: {draws:?}");
            let mut again = Rng::for_device(42, "drive");
            let lat2 = p.device_latency(&mut again);
            assert_eq!(draws, (0..500).map(|_| lat2.draw(&mut again)).collect::<Vec<_>>());
        }
        assert_ne!(Rng::for_device(1, "drive").next_u64(), Rng::for_device(1, "sensor").next_u64());
    }

    #[test]
    fn profile_names_round_trip() {
        for name in Profile::NAMES {
            assert_eq!(name.parse::<Profile>().unwrap().to_string(), name);
        }
        assert!("fast".parse::<Profile>().is_err());
    }

    #[test]
    fn frames_ready_in_the_past_start_once_the_bus_is_free_in_their_order() {
        let mut bus = BusQueue::new(Some(1_000_000));
        bus.queue(10 * MS, Origin::Master, Frame::new(0x605, &[0x40; 8]));
        let (first_end, _, _) = bus.pop_done(20 * MS).unwrap();
        // Queued late with earlier ready times: never before the bus was free, each
        // sender's in its order, and at their own times once the bus is idle.
        bus.queue(5 * MS, Origin::Device(0), Frame::new(0x705, &[0x7F]));
        bus.queue(12 * MS, Origin::Device(0), Frame::new(0x705, &[0x7F]));
        bus.queue(12 * MS, Origin::Device(1), Frame::new(0x701, &[0x7F]));
        let done: Vec<(Nanos, u16)> =
            std::iter::from_fn(|| bus.pop_done(20 * MS)).map(|(t, _, f)| (t, f.id())).collect();
        let beat = frame_time(&Frame::new(0x705, &[0x7F]), 1_000_000);
        assert_eq!(done[0], (first_end + beat, 0x705), "waited for the bus");
        assert_eq!(done[1].1, 0x701, "lower id wins when both are ready");
        assert_eq!(done[1].0, 12 * MS + frame_time(&Frame::new(0x701, &[0x7F]), 1_000_000));
        assert_eq!(done[2], (done[1].0 + beat, 0x705));
        assert!(done.windows(2).all(|w| w[0].0 < w[1].0));
    }
}
