//! `health` judges heartbeats from the moment each was on the bus, not from when canctl
//! read it: a canctl held up by a loaded host (frames wait, then come in a burst) still
//! finds a healthy producer on time. Library level: the stall is played by a link that
//! stops delivering for 300 ms now and then, as a descheduled process would.

use canctl::bus::{Bus, FrameLink, Master};
use canctl::frame::Frame;
use canctl::ops::health::{health, HealthOptions};
use canctl::ops::Silent;
use canctl::sim::SimLink;
use canctl::Result;
use std::time::{Duration, Instant};

const STALL: Duration = Duration::from_millis(300);
/// The demo network's position sensor: it beats every 40 ms (allowed gap 110 ms).
const SENSOR: u8 = 5;

/// The simulated bus, read by a master that is descheduled for 300 ms after every 200 ms
/// of listening. `stamp_on_receipt`: stamps the moment of reading, as before the fix.
struct Stalling {
    sim: SimLink,
    awake_since: Option<Instant>,
    stamp_on_receipt: bool,
}

impl Stalling {
    fn new(stamp_on_receipt: bool) -> Stalling {
        Stalling { sim: SimLink::ephemeral(), awake_since: None, stamp_on_receipt }
    }
}

impl FrameLink for Stalling {
    fn send(&mut self, frame: &Frame) -> Result<()> {
        self.sim.send(frame)
    }
    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        self.sim.recv(deadline)
    }
    // Only the stamped receive stalls: health's watch uses it, the scan and SDO reads
    // before it do not.
    fn recv_stamped(&mut self, deadline: Instant) -> Result<Option<(Frame, Instant)>> {
        let awake = *self.awake_since.get_or_insert_with(Instant::now);
        if awake.elapsed() >= Duration::from_millis(200) {
            std::thread::sleep(STALL);
            self.awake_since = Some(Instant::now());
        }
        let got = self.sim.recv_stamped(deadline)?;
        Ok(if self.stamp_on_receipt { got.map(|(f, _)| (f, Instant::now())) } else { got })
    }
    fn name(&self) -> String {
        self.sim.name()
    }
    fn follows_bit_rate_switch(&self) -> bool {
        true
    }
}

fn sensor_heartbeat(stamp_on_receipt: bool) -> (bool, Option<u64>, usize) {
    let mut bus = Master::new(Stalling::new(stamp_on_receipt), "sim".into());
    let opts = HealthOptions {
        window: Duration::from_millis(100),
        timeout: Duration::from_millis(500),
        watch: Some(Duration::from_millis(1500)),
        state: None,
        last_seen: Vec::new(),
    };
    let report = health(&mut bus, &opts, &mut Silent).unwrap();
    bus.close().unwrap();
    let sensor = report.nodes.iter().find(|n| n.node == SENSOR).expect("the sensor is found");
    let check = sensor.checks.iter().find(|c| c.check == "heartbeat").expect("a heartbeat check");
    (check.ok, sensor.longest_gap_ms, sensor.heartbeats)
}

#[test]
fn a_healthy_producer_is_on_time_however_long_canctl_was_held_up() {
    let (on_time, longest_gap, beats) = sensor_heartbeat(false);
    assert!(on_time, "longest gap {longest_gap:?} ms over {beats} beats");
    // Every beat of the 1.5 s watch was counted, those during the stalls too.
    assert!(beats >= 30, "{beats} beats");
}

#[test]
fn judged_from_the_moment_of_reading_the_same_producer_looks_late() {
    // What `health` did before: this is the failure the stamps prevent.
    let (on_time, longest_gap, _) = sensor_heartbeat(true);
    assert!(!on_time);
    assert!(longest_gap.is_some_and(|g| g >= STALL.as_millis() as u64), "{longest_gap:?}");
}

/// The simulated bus, with a master descheduled for 300 ms, far longer than the
/// transfers' timeout, right after its `at`-th frame (counting down).
struct HeldUpOnce {
    sim: SimLink,
    at: usize,
}

impl FrameLink for HeldUpOnce {
    fn send(&mut self, frame: &Frame) -> Result<()> {
        self.sim.send(frame)?;
        self.at = self.at.saturating_sub(1);
        if self.at == 1 {
            std::thread::sleep(STALL);
        }
        Ok(())
    }
    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        self.sim.recv(deadline)
    }
    fn recv_stamped(&mut self, deadline: Instant) -> Result<Option<(Frame, Instant)>> {
        self.sim.recv_stamped(deadline)
    }
    fn name(&self) -> String {
        self.sim.name()
    }
}

/// Answers that came in time, and waited to be read while canctl was held up, are
/// answers: no node is reported silent because of this program's own scheduling.
#[test]
fn sdo_answers_that_waited_while_canctl_was_held_up_count() {
    use canctl::bus::SdoOptions;
    use canctl::canopen::ObjAddr;
    // Four requests, then the I/O module's first answer (its name is segmented) is
    // answered with a segment request: held up there, with the stepper's answer waiting.
    let mut bus = Master::new(HeldUpOnce { sim: SimLink::ephemeral(), at: 6 }, "sim".into());
    let requests = [(1, 0x1000), (5, 0x1000), (10, 0x1008), (32, 0x1000)].map(|(n, i)| (n, ObjAddr::new(i, 0)));
    let opts = SdoOptions::new(Duration::from_millis(100));
    let answers = bus.sdo_upload_many(&requests, &opts, &mut |_| {}).unwrap();
    for ((node, _), a) in requests.iter().zip(answers) {
        assert!(a.is_ok(), "node {node}: {}", a.unwrap_err());
    }
}
