//! A bus that heeds a request to stop (SIGINT, SIGTERM, Ctrl-C): once it is set, every
//! service ends with [`Error::Interrupted`](crate::Error::Interrupted) before it sends anything, an SDO transfer under
//! way ends with an abort sent to the device ([`SdoOptions::stop`]), and a wait for frames
//! ends early. A procedure run over it stops at its next call to the bus and turns the
//! error into its partial report; one that must still talk to the bus after a stop (to
//! put a PDO mapping back, say) polls the flag itself over the plain bus instead.

use super::api::{Bus, LssAnswer, LssExchange, SdoJob, SdoOptions};
use crate::cancel::Cancel;
use crate::canopen::nmt::Command;
use crate::error::Result;
use crate::frame::Frame;
use std::time::{Duration, Instant};

/// How often a wait for frames looks at the request to stop.
const POLL: Duration = Duration::from_millis(50);

/// `bus`, stopping once `stop` is set.
pub struct Stoppable<'a> {
    bus: &'a mut dyn Bus,
    stop: Cancel,
}

impl<'a> Stoppable<'a> {
    /// `bus`, ending every service with `Error::Interrupted` once `stop` is cancelled.
    pub fn new(bus: &'a mut dyn Bus, stop: Cancel) -> Self {
        Stoppable { bus, stop }
    }

    fn check(&self) -> Result<()> {
        self.stop.check()
    }
}

impl Bus for Stoppable<'_> {
    super::api::pass_on_unchanged!(bus);

    fn sdo_batch(&mut self, jobs: &[SdoJob], progress: &mut dyn FnMut(usize)) -> Result<Vec<Result<Vec<u8>>>> {
        self.check()?;
        let jobs: Vec<SdoJob> =
            jobs.iter().map(|j| j.with_opts(|o| SdoOptions { stop: Some(self.stop.clone()), ..o.clone() })).collect();
        self.bus.sdo_batch(&jobs, progress)
    }
    fn nmt(&mut self, cmd: Command, node: u8) -> Result<()> {
        self.check()?;
        self.bus.nmt(cmd, node)
    }
    fn send_frame(&mut self, frame: &Frame) -> Result<()> {
        self.check()?;
        self.bus.send_frame(frame)
    }
    /// Waits in short slices, so that a stop ends the wait within one of them.
    fn recv_frame_stamped(&mut self, deadline: Instant) -> Result<Option<(Frame, Instant)>> {
        loop {
            self.check()?;
            let slice = deadline.min(self.bus.now() + POLL);
            if let Some(f) = self.bus.recv_frame_stamped(slice)? {
                return Ok(Some(f));
            }
            if self.bus.now() >= deadline {
                return Ok(None);
            }
        }
    }
    fn sleep_until(&mut self, t: Instant) -> Result<()> {
        self.check()?;
        self.bus.sleep_until(t)
    }
    fn request_frame(&mut self, id: u16, len: u8, timeout: Duration) -> Result<Frame> {
        self.check()?;
        self.bus.request_frame(id, len, timeout)
    }
    fn lss(&mut self, exchange: &LssExchange) -> Result<Vec<LssAnswer>> {
        self.check()?;
        self.bus.lss(exchange)
    }
}
