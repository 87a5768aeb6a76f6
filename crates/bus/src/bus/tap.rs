//! A bus that tells its caller after each confirmed SDO transfer and NMT command: the n-th
//! upload, download or command, counted per kind (the uploads of a batch one by one, as
//! each ends); and, when asked, after each answer that moves a transfer on. A test harness uses it to act at an exact step of a
//! procedure (the kill-at-every-step tests send a signal there); it changes nothing on the
//! bus.

use super::api::{Bus, LssAnswer, LssExchange, SdoJob, SdoOptions, TransferHook};
use crate::canopen::nmt::Command;
use crate::frame::Frame;
use crate::Result;
use std::time::{Duration, Instant};

/// Which kind of SDO transfer just ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Transfer {
    /// A read, answered (or aborted: the device did answer).
    Upload,
    /// A write the device confirmed.
    Download,
    /// An NMT command sent.
    Nmt,
}

/// `bus`, calling `after(kind, n)` once the n-th transfer of that kind has ended.
pub struct AfterSdo<'a, F: FnMut(Transfer, u32)> {
    bus: &'a mut dyn Bus,
    after: F,
    uploads: u32,
    downloads: u32,
    commands: u32,
    on_progress: Option<TransferHook>,
}

impl<'a, F: FnMut(Transfer, u32)> AfterSdo<'a, F> {
    /// `bus`, calling `after` with the kind and count of each confirmed SDO transfer and NMT
    /// command as it ends.
    pub fn new(bus: &'a mut dyn Bus, after: F) -> Self {
        AfterSdo { bus, after, uploads: 0, downloads: 0, commands: 0, on_progress: None }
    }

    /// Also call `hook` after each answer that moves a transfer on (as
    /// [`SdoOptions::on_progress`], where the caller set none).
    pub fn with_progress_hook(mut self, hook: Option<TransferHook>) -> Self {
        self.on_progress = hook;
        self
    }
}

impl<F: FnMut(Transfer, u32)> Bus for AfterSdo<'_, F> {
    super::api::pass_on_unchanged!(bus);

    /// A batch of uploads only is counted as each ends; one with downloads, in the jobs'
    /// order once they have all ended (a download counts once confirmed).
    fn sdo_batch(&mut self, jobs: &[SdoJob], progress: &mut dyn FnMut(usize)) -> Result<Vec<Result<Vec<u8>>>> {
        let hooked = |o: &SdoOptions| SdoOptions {
            on_progress: o.on_progress.clone().or_else(|| self.on_progress.clone()),
            ..o.clone()
        };
        let jobs: Vec<SdoJob> = jobs.iter().map(|j| j.with_opts(hooked)).collect();
        let uploads_only = jobs.iter().all(|j| matches!(j, SdoJob::Upload { .. }));
        let AfterSdo { bus, after, uploads, .. } = self;
        let mut counted = 0;
        let results = bus.sdo_batch(&jobs, &mut |done| {
            while uploads_only && counted < done {
                counted += 1;
                *uploads += 1;
                after(Transfer::Upload, *uploads);
            }
            progress(done)
        })?;
        for (job, result) in jobs.iter().zip(&results).filter(|_| !uploads_only) {
            match job {
                SdoJob::Upload { .. } => {
                    self.uploads += 1;
                    (self.after)(Transfer::Upload, self.uploads);
                }
                SdoJob::Download { .. } if result.is_ok() => {
                    self.downloads += 1;
                    (self.after)(Transfer::Download, self.downloads);
                }
                SdoJob::Download { .. } => {}
            }
        }
        Ok(results)
    }
    fn nmt(&mut self, cmd: Command, node: u8) -> Result<()> {
        self.bus.nmt(cmd, node)?;
        self.commands += 1;
        (self.after)(Transfer::Nmt, self.commands);
        Ok(())
    }
    fn send_frame(&mut self, frame: &Frame) -> Result<()> {
        self.bus.send_frame(frame)
    }
    fn recv_frame_stamped(&mut self, deadline: Instant) -> Result<Option<(Frame, Instant)>> {
        self.bus.recv_frame_stamped(deadline)
    }
    fn sleep_until(&mut self, t: Instant) -> Result<()> {
        self.bus.sleep_until(t)
    }
    fn request_frame(&mut self, id: u16, len: u8, timeout: Duration) -> Result<Frame> {
        self.bus.request_frame(id, len, timeout)
    }
    fn lss(&mut self, exchange: &LssExchange) -> Result<Vec<LssAnswer>> {
        self.bus.lss(exchange)
    }
}
