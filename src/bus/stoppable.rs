//! A bus that heeds a request to stop (SIGINT, SIGTERM, Ctrl-C): once it is set, every
//! service ends with [`Error::Interrupted`](crate::Error::Interrupted) before it sends anything, an SDO transfer under
//! way ends with an abort sent to the device ([`SdoOptions::stop`]), and a wait for frames
//! ends early. A procedure run over it stops at its next call to the bus and turns the
//! error into its partial report; one that must still talk to the bus after a stop (to
//! put a PDO mapping back, say) polls the flag itself over the plain bus instead.

use super::{Bus, LssAnswer, LssExchange, SdoJob, SdoOptions};
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

    fn heeding(&self, opts: &SdoOptions) -> SdoOptions {
        SdoOptions { stop: Some(self.stop.clone()), ..opts.clone() }
    }
}

impl Bus for Stoppable<'_> {
    super::pass_on_unchanged!(bus);

    fn sdo_batch(&mut self, jobs: &[SdoJob], progress: &mut dyn FnMut(usize)) -> Result<Vec<Result<Vec<u8>>>> {
        self.check()?;
        let jobs: Vec<SdoJob> = jobs.iter().map(|j| j.with_opts(|o| self.heeding(o))).collect();
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canopen::ObjAddr;
    use crate::sim::SimLink;
    use crate::Error;

    #[test]
    fn once_stopped_nothing_more_is_sent() {
        let mut bus = crate::bus::Master::new(SimLink::ephemeral(), "sim".into());
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
        let mut bus = crate::bus::Master::new(SimLink::ephemeral(), "sim".into());
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
        let mut bus = crate::bus::Master::new(SimLink::ephemeral(), "sim".into());
        let stop = Cancel::new();
        let domain = ObjAddr::new(0x1F50, 1);
        let opts = SdoOptions::new(Duration::from_secs(1));
        let before = bus.sdo_upload(1, domain, &SdoOptions { block_upload: true, ..opts.clone() }).unwrap();
        let mut s = Stoppable::new(&mut bus, stop.clone());
        let at_second_block: crate::bus::TransferHook = std::sync::Arc::new(move |moved| {
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
}
