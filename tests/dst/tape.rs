//! The tape: the simulated network behind a recorder of every frame, and a loaded host.

use super::*;

/// What every frame on the tape is: sent by canctl or received, when, and its bytes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Taped {
    pub sent: bool,
    pub at: Duration,
    pub id: u16,
    pub data: Vec<u8>,
}

/// The simulated network behind a recorder of every frame.
pub struct Tape {
    pub sim: SimLink,
    pub zero: Instant,
    pub frames: Vec<Taped>,
    /// A loaded host: now and then canctl polls the link late; the bus and the devices
    /// go on meanwhile.
    pub stalls: Option<Stalls>,
    /// Polls of the link in a row with no bus time passing, and when: a procedure that
    /// waits on a deadline already past spins (on hardware it burns a core; here it would
    /// never end), which is caught here and reported with its seed.
    pub polls_standing: (u32, Instant),
}

/// More polls than any frames one instant of bus time can hold.
const SPINNING: u32 = 100_000;

/// When a loaded host holds canctl up: now and then right after it sent a frame (the
/// moment a system call hands the CPU to another task), for 1 ms to `longest`, drawn from
/// the generator, before it polls for the answer.
pub struct Stalls {
    pub rng: Rng,
    pub longest: u64,
    pub after_send: bool,
}

impl Stalls {
    pub fn sent(&mut self) {
        self.after_send = self.rng.chance(0.25);
    }

    /// How long canctl is held up before this poll, if it is.
    pub fn polling(&mut self) -> Option<Duration> {
        std::mem::take(&mut self.after_send).then(|| Duration::from_millis(self.rng.between(1, self.longest)))
    }
}

impl Tape {
    /// `sim` recorded from now on, on a host that may hold canctl up.
    pub fn new(sim: SimLink, stalls: Option<Stalls>) -> Tape {
        let zero = sim.now();
        Tape { sim, zero, frames: Vec::new(), stalls, polls_standing: (0, zero) }
    }

    pub fn record(&mut self, sent: bool, at: Instant, f: &Frame) {
        let at = at.saturating_duration_since(self.zero);
        self.frames.push(Taped { sent, at, id: f.id(), data: f.data().to_vec() });
    }
}

impl FrameLink for Tape {
    fn send(&mut self, frame: &Frame) -> Result<()> {
        let now = self.sim.now();
        self.record(true, now, frame);
        if let Some(s) = &mut self.stalls {
            s.sent();
        }
        self.sim.send(frame)
    }
    fn recv(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        Ok(self.recv_stamped(deadline)?.map(|(f, _)| f))
    }
    fn recv_stamped(&mut self, deadline: Instant) -> Result<Option<(Frame, Instant)>> {
        if let Some(late) = self.stalls.as_mut().and_then(Stalls::polling) {
            self.sim.sleep_until(self.sim.now() + late)?;
        }
        let now = self.sim.now();
        self.polls_standing = match self.polls_standing {
            (n, at) if at == now => (n + 1, at),
            _ => (1, now),
        };
        let (polls, at) = self.polls_standing;
        assert!(polls < SPINNING, "the procedure spins: {polls} polls of the link at {:?} of bus time", at - self.zero);
        let got = self.sim.recv_stamped(deadline)?;
        if let Some((f, at)) = &got {
            self.record(false, *at, f);
        }
        Ok(got)
    }
    fn name(&self) -> String {
        "sim".into()
    }
    fn now(&self) -> Instant {
        self.sim.now()
    }
    fn sleep_until(&mut self, t: Instant) -> Result<()> {
        self.sim.sleep_until(t)
    }
    fn follows_bit_rate_switch(&self) -> bool {
        self.sim.follows_bit_rate_switch()
    }
    // What the link knows of the bus: passed on, as the procedures see it on hardware.
    fn frame_time(&self) -> Option<Duration> {
        self.sim.frame_time()
    }
    fn report(&mut self) -> Option<canctl::bus::controller::LinkReport> {
        self.sim.report()
    }
    fn close(&mut self) -> Result<()> {
        self.sim.close()
    }
}

/// With `CANCTL_DST_TRACE` set: every frame of a run, as canctl's `-v` trace shows them.
pub fn trace(frames: &[Taped]) {
    if std::env::var("CANCTL_DST_TRACE").is_err() {
        return;
    }
    for f in frames {
        eprintln!("{:>12.3?} {} {:03X} {:02X?}", f.at, if f.sent { "tx" } else { "rx" }, f.id, f.data);
    }
}
