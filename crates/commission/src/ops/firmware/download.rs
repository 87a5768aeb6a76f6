//! One node's download, step by step: its options, its report, how it fails, and the
//! sequence itself.

use crate::bus::{Bus, SdoOptions};
use crate::cancel::Cancel;
use crate::canopen::nmt;
use crate::canopen::program::{self, Control, FlashStatus, FLASH_STATUS, PROGRAM_CONTROL, PROGRAM_DATA, SOFTWARE_ID};
use crate::canopen::ObjAddr;
use crate::error::{Error, ErrorClass};
use crate::ops::progress::Progress;
use serde::Serialize;
use std::time::{Duration, Instant};

use super::step::{DownloadEnd, Step};
use crate::ops::in_parallel::Served;

/// How often the flash status is asked while the device is busy.
pub(crate) const POLL: Duration = Duration::from_millis(100);
/// The longest an erase or a write may keep the flash busy: real erases of a megabyte of
/// flash take tens of seconds.
pub(crate) const BUSY_WAIT: Duration = Duration::from_secs(60);
/// The longest a device may take to boot (into its bootloader or its program).
pub(crate) const BOOT_WAIT: Duration = Duration::from_secs(10);

/// What `firmware download` is asked to do.
#[derive(Clone)]
pub struct DownloadOptions {
    /// The program number (sub-index of 0x1F50..0x1F57), 1 for most devices.
    pub program: u8,
    /// Download even when the device already runs this image.
    pub force: bool,
    /// The identification the device gives this image, when it is not its CRC-32.
    pub expect_id: Option<u32>,
    /// How long to wait for each SDO answer.
    pub timeout: Duration,
    /// How long to wait for the flash to finish erasing or writing (0x1F57 busy).
    pub busy_wait: Duration,
    /// How long to wait for the device to come back after a reset (its boot-up, or an answer).
    pub boot_wait: Duration,
    /// Confirm a program that asks for it (0x1F51 reads 0x80 after the start).
    pub confirm: bool,
    /// Looked at between steps and transfers: set, the download stops where it is safe to.
    pub cancel: Option<Cancel>,
}

impl DownloadOptions {
    /// The defaults: program 1, no force, the image's CRC-32 as its identification, a confirmation when asked for; `timeout` for each SDO answer.
    pub fn new(timeout: Duration) -> DownloadOptions {
        DownloadOptions {
            program: 1,
            force: false,
            expect_id: None,
            timeout,
            busy_wait: BUSY_WAIT,
            boot_wait: BOOT_WAIT,
            confirm: true,
            cancel: None,
        }
    }
}

/// A step done, and when (ms since the command began).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[non_exhaustive]
pub struct StepDone {
    /// The step.
    pub step: Step,
    /// When it was done, in ms since the command began.
    pub at_ms: u64,
}

/// Where the device is when the procedure ends.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Where {
    /// Running the image (downloaded now, or already: skipped).
    RunsImage,
    /// Nothing was changed: it runs what it ran.
    #[default]
    Unchanged,
    /// Stopped in its bootloader; its program is intact.
    BootloaderWithProgram,
    /// In its bootloader with no valid program.
    BootloaderNoProgram,
    /// The new program was written and started, but did not show it runs.
    Unknown,
}

/// Where the device is when the procedure ends, with what to do next: the report's
/// `state`, which the front end words.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum State {
    /// It already ran the image (the same identification): nothing was written; a forced
    /// download writes it all the same.
    AlreadyRuns,
    /// It runs the image on trial: unconfirmed, its bootloader returns to the old program
    /// at the next reset.
    OnTrial,
    /// Where [`Where`] says.
    At(Where),
}

impl Default for State {
    fn default() -> State {
        State::At(Where::default())
    }
}

/// How the program data went to the device.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Transfer {
    /// SDO block transfer (CiA 301 7.2.4.3.9): the fast one.
    Block,
    /// Segmented SDO transfer: the device refused block transfer, or the link has none.
    Segmented,
}

/// What `firmware download` did to one node.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct DownloadReport {
    /// The node-id.
    pub node: u8,
    /// The program number (sub-index of 0x1F50..0x1F57).
    pub program: u8,
    /// The image's size, in bytes.
    pub image_bytes: usize,
    /// The identification the image must show in 0x1F56 (its CRC-32 unless given).
    pub image_id: u32,
    /// 0x1F56 before the download; none when the procedure stopped before reading it.
    pub id_before: Option<u32>,
    /// 0x1F56 after it; none when not read (nothing written, or stopped before).
    pub id_after: Option<u32>,
    /// The device already ran the image: nothing was written.
    pub skipped: bool,
    /// Each step done, in order.
    pub steps: Vec<StepDone>,
    /// The last flash status read, by meaning.
    pub flash_status: Option<FlashStatus>,
    /// How many times 0x1F57 was read while busy (erase and write).
    pub busy_polls: u32,
    /// How long the erase took, in ms; none when there was none (skipped, or stopped before).
    pub erase_ms: Option<u64>,
    /// How long the program data took to write, in ms; none when none was written (skipped, or
    /// stopped before).
    pub download_ms: Option<u64>,
    /// Program data bytes per second during the download.
    pub bytes_per_second: Option<u64>,
    /// How the program data went; none when none was written.
    pub transfer: Option<Transfer>,
    /// How long the whole procedure took, in ms.
    pub total_ms: u64,
    /// The new program was confirmed (0x1F51 = 0x80) when it asked for it.
    pub confirmed: bool,
    /// Where the device is now.
    pub device: Where,
    /// Where the device is now, with what to do next (the front end words it).
    pub state: State,
    /// The user asked to stop: the download ended where it was safe to.
    pub interrupted: bool,
}

impl DownloadReport {
    /// The report before the first step: nothing done, the device as it was.
    pub fn begun(node: u8, program: u8, image_bytes: usize, image_id: u32) -> DownloadReport {
        DownloadReport { node, program, image_bytes, image_id, ..DownloadReport::default() }
    }
}

/// Why a download did not finish.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FirmwareError {
    /// The bus or the device failed a step (SDO abort with its object and code, no answer,
    /// link failure, interrupted).
    #[error(transparent)]
    Bus(#[from] Error),
    /// The flash status (0x1F57) reports an error after a step (`after`).
    #[error("node {node}: flash status (0x1F57:{program}) after {after}: 0x{:08X}, {}", status.raw, status.meaning())]
    Flash {
        /// The node-id.
        node: u8,
        /// The program number.
        program: u8,
        /// The step it followed, in words.
        after: &'static str,
        /// The flash status read.
        status: FlashStatus,
    },
    /// The flash stayed busy (0x1F57) past the wait after a step (`after`).
    #[error("node {node}: the flash is still busy (0x1F57:{program}) {} s after {after}, {polls} polls; the device may need longer", waited.as_secs())]
    StillBusy {
        /// The node-id.
        node: u8,
        /// The program number.
        program: u8,
        /// The step it followed, in words.
        after: &'static str,
        /// How many times 0x1F57 was read.
        polls: u32,
        /// How long it was waited for.
        waited: Duration,
    },
    /// After the download, the software identification (0x1F56) is not the image's.
    #[error("node {node}: 0x1F56:{program} reads 0x{got:08X} after the download, the image's identification is 0x{want:08X}{}", if *got == 0 { " (0: the device holds no valid program)" } else { "" })]
    IdMismatch {
        /// The node-id.
        node: u8,
        /// The program number.
        program: u8,
        /// What 0x1F56 reads (0: no valid program).
        got: u32,
        /// The image's identification.
        want: u32,
    },
    /// The device did not come back (no boot-up, no answer) after a reset (`after`).
    #[error("node {node}: not back (no boot-up, no answer) within {} ms after {after}", waited.as_millis())]
    NoBootUp {
        /// The node-id.
        node: u8,
        /// The step it followed, in words.
        after: &'static str,
        /// How long it was waited for.
        waited: Duration,
    },
}

impl FirmwareError {
    /// How the process ends for it (DESIGN.md's exit codes).
    pub fn class(&self) -> ErrorClass {
        match self {
            FirmwareError::Bus(e) => e.class(),
            FirmwareError::Flash { .. } => ErrorClass::Refused,
            FirmwareError::StillBusy { .. } | FirmwareError::NoBootUp { .. } => ErrorClass::Timeout,
            FirmwareError::IdMismatch { .. } => ErrorClass::Verify,
        }
    }
}

/// A download that did not finish: the error, and the report of what was done and where
/// the device is (its `device` and `state`).
#[derive(Debug, thiserror::Error)]
#[error("{error}")]
#[non_exhaustive]
pub struct Failed {
    /// Why it did not finish.
    pub error: FirmwareError,
    /// What was done, and where the device is.
    pub report: Box<DownloadReport>,
}

/// A little-endian value of up to 4 bytes (0x1F51 has one, 0x1F56 and 0x1F57 four).
pub(super) fn le(bytes: &[u8]) -> u32 {
    bytes.iter().take(4).rev().fold(0, |acc, b| acc << 8 | u32::from(*b))
}

/// A flash status that shows an error after a step (`after`) is the step's failure.
fn flash_ok(node: u8, program: u8, after: &'static str, status: FlashStatus) -> Result<(), FirmwareError> {
    match status.is_error() {
        true => Err(FirmwareError::Flash { node, program, after, status }),
        false => Ok(()),
    }
}

/// The procedure's state: the report as it grows, and the bus's clock at the start.
struct Run<'a> {
    bus: &'a mut dyn Bus,
    o: &'a DownloadOptions,
    node: u8,
    began: Instant,
    report: DownloadReport,
}

impl Run<'_> {
    fn ms(&self) -> u64 {
        self.bus.now().saturating_duration_since(self.began).as_millis() as u64
    }

    fn done(&mut self, step: Step) {
        let at_ms = self.ms();
        self.report.steps.push(StepDone { step, at_ms });
        tracing::debug!(target: "canctl::firmware", "node {}: {} at {at_ms} ms", self.node, step.describe());
    }

    fn opts(&self) -> SdoOptions {
        SdoOptions { stop: self.o.cancel.clone(), ..SdoOptions::new(self.o.timeout) }
    }

    fn addr(&self, index: u16) -> ObjAddr {
        program::object(index, self.o.program)
    }

    fn read_u32(&mut self, index: u16) -> Result<u32, Error> {
        let opts = SdoOptions { size_hint: Some(4), ..self.opts() };
        Ok(le(&self.bus.sdo_upload(self.node, self.addr(index), &opts)?))
    }

    fn control(&mut self, c: Control) -> Result<(), Error> {
        let opts = self.opts();
        self.bus.sdo_download(self.node, self.addr(PROGRAM_CONTROL), &[c.code()], &opts)
    }

    fn check_cancel(&self) -> Result<(), Error> {
        self.o.cancel.as_ref().map_or(Ok(()), Cancel::check)
    }

    /// Poll 0x1F57 until it is not busy, bounded; the status it ends with.
    fn wait_not_busy(&mut self, after: &'static str) -> Result<FlashStatus, FirmwareError> {
        let end = self.bus.now() + self.o.busy_wait;
        loop {
            let status = FlashStatus::decode(self.read_u32(FLASH_STATUS)?);
            self.report.flash_status = Some(status);
            if !status.busy {
                return Ok(status);
            }
            self.report.busy_polls += 1;
            self.check_cancel()?;
            let now = self.bus.now();
            if now >= end {
                return Err(FirmwareError::StillBusy {
                    node: self.node,
                    program: self.o.program,
                    after,
                    polls: self.report.busy_polls,
                    waited: self.o.busy_wait,
                });
            }
            self.bus.sleep_until(end.min(now + POLL))?;
        }
    }

    /// The device is back after a reset it may have done instead of answering (`ops::back`;
    /// its boot-up forgotten before the step that causes it).
    fn wait_back(&mut self) -> Result<bool, Error> {
        let (node, wait) = (self.node, self.o.boot_wait);
        let back = crate::ops::back::wait_back(self.bus, &[node], wait, self.o.timeout, self.o.cancel.as_ref())?;
        Ok(back.get(&node).copied().unwrap_or(false))
    }

    /// Wait (bounded) for a heartbeat (or a guarding answer) after the boot-up.
    fn wait_heartbeat(&mut self) -> Result<bool, Error> {
        let end = self.bus.now() + self.o.boot_wait;
        while let Some(f) = self.bus.recv_frame(end)? {
            self.check_cancel()?;
            if matches!(nmt::ErrorControl::parse(&f), Some((n, nmt::ErrorControl::State { .. })) if n == self.node) {
                return Ok(true);
            }
        }
        Ok(false)
    }

    fn fail(mut self, error: impl Into<FirmwareError>, at: Where) -> Box<Failed> {
        let error = error.into();
        self.report.total_ms = self.ms();
        self.report.interrupted = matches!(&error, FirmwareError::Bus(e) if e.is_interrupted());
        self.report.device = at;
        self.report.state = State::At(at);
        Box::new(Failed { error, report: Box::new(self.report) })
    }
}

/// Download `image` into program `o.program` of `node` and start it: the CiA 302-3
/// sequence, each step confirmed. Skipped (and reported so) when the device already runs
/// it, unless `o.force`.
pub fn download(
    bus: &mut dyn Bus,
    node: u8,
    image: &[u8],
    o: &DownloadOptions,
    progress: &mut dyn Progress,
) -> Result<DownloadReport, Box<Failed>> {
    download_timed(bus, node, image, o, progress, &Served::default())
}

/// [`download`], where the program data's transfer may wait its turn (`served` says when
/// it began on the bus; unset, it began when asked).
pub(super) fn download_timed(
    bus: &mut dyn Bus,
    node: u8,
    image: &[u8],
    o: &DownloadOptions,
    progress: &mut dyn Progress,
    served: &Served,
) -> Result<DownloadReport, Box<Failed>> {
    let image_id = o.expect_id.unwrap_or_else(|| program::image_id(image));
    let began = bus.now();
    let report = DownloadReport::begun(node, o.program, image.len(), image_id);
    let mut r = Run { bus, o, node, began, report };
    // Each step done is told as it happens: an erase or a boot can take seconds.
    macro_rules! did {
        ($step:expr) => {{
            let step = $step;
            r.done(step);
            progress.item(&format!("node {node}"), crate::ops::progress::ItemStatus::Firmware(step));
        }};
    }
    macro_rules! step {
        ($e:expr, $at:expr) => {
            match $e {
                Ok(v) => v,
                Err(e) => return Err(r.fail(e, $at)),
            }
        };
    }

    let before = step!(r.read_u32(SOFTWARE_ID), Where::Unchanged);
    r.report.id_before = Some(before);
    did!(Step::ReadId);
    if before == image_id && !o.force {
        let (id_after, device, state, total_ms) = (Some(before), Where::RunsImage, State::AlreadyRuns, r.ms());
        return Ok(DownloadReport { skipped: true, id_after, device, state, total_ms, ..r.report });
    }
    step!(r.check_cancel(), Where::Unchanged);
    step!(r.bus.nmt(nmt::Command::PreOperational, node), Where::Unchanged);
    did!(Step::PreOperational);

    // Stop. A device whose bootloader is another image reboots into it instead of
    // answering: its boot-up says the stop was done.
    r.bus.observed().boot_ups.remove(&node);
    let rebooted = match r.control(Control::Stop) {
        Ok(()) => r.bus.observed().boot_ups.contains(&node),
        // No answer in time, however the bus puts it (a gateway reports its own timeout).
        Err(e) if e.is_timeout() => {
            let after = "stop (0x1F51 = 0), which it did not answer";
            let e = FirmwareError::NoBootUp { node, after, waited: o.boot_wait };
            step!(r.wait_back(), Where::Unknown) || return Err(r.fail(e, Where::Unknown))
        }
        Err(e) => return Err(r.fail(e, Where::Unchanged)),
    };
    did!(Step::Stop);
    if rebooted {
        did!(Step::BootedBootloader);
    }
    // Stopped: in its bootloader, with the program it had, if any.
    let stopped_at = if before == 0 { Where::BootloaderNoProgram } else { Where::BootloaderWithProgram };
    step!(r.check_cancel(), stopped_at);
    // A device may still be busy with an erase an earlier run left (it refuses a clear
    // then): wait that out first. An error code it shows is the earlier run's; the clear
    // starts afresh.
    step!(r.wait_not_busy("an earlier erase or write"), stopped_at);

    // Clear, then wait out the erase.
    step!(r.control(Control::Clear), stopped_at);
    let erase_began = r.bus.now();
    did!(Step::Clear);
    progress.start(&format!("node {node}: erasing"), 0);
    let erased = r.wait_not_busy("clear (0x1F51 = 3)");
    progress.finish();
    let status = step!(erased, Where::BootloaderNoProgram);
    r.report.erase_ms = Some(r.bus.now().saturating_duration_since(erase_began).as_millis() as u64);
    step!(flash_ok(node, o.program, "clear", status), Where::BootloaderNoProgram);
    did!(Step::Erased);

    // The program data: block transfer (the bus falls back to segmented when the device
    // refuses it), its bytes a phase of `progress`, stopped between frames when asked.
    let on_progress = progress.transfer(&format!("0x1F50:{}", o.program), Some(image.len() as u64));
    let opts = SdoOptions { block_download: true, on_progress, ..r.opts() };
    let download_began = r.bus.now();
    let written = r.bus.sdo_download(node, r.addr(PROGRAM_DATA), image, &opts);
    progress.finish();
    step!(written, Where::BootloaderNoProgram);
    let took = r.bus.now().saturating_duration_since(served.since().unwrap_or(download_began));
    r.report.download_ms = Some(took.as_millis() as u64);
    r.report.bytes_per_second =
        (took.as_micros() > 0).then(|| (image.len() as u128 * 1_000_000 / took.as_micros()) as u64);
    // The bus knows whether the device took the block transfer or it fell back.
    r.report.transfer = Some(if r.bus.block_transfer_to(node) { Transfer::Block } else { Transfer::Segmented });
    did!(Step::Download);
    let status = step!(r.wait_not_busy("the download"), Where::BootloaderNoProgram);
    step!(flash_ok(node, o.program, "the download", status), Where::BootloaderNoProgram);
    did!(Step::Written);
    let after = step!(r.read_u32(SOFTWARE_ID), Where::BootloaderNoProgram);
    r.report.id_after = Some(after);
    if after != image_id {
        let e = FirmwareError::IdMismatch { node, program: o.program, got: after, want: image_id };
        return Err(r.fail(e, Where::BootloaderNoProgram));
    }
    did!(Step::IdChecked);
    step!(r.check_cancel(), Where::BootloaderWithProgram);

    // Start: the device may reset before its answer; the bus reads the state back, and
    // the boot-up decides either way.
    r.bus.observed().boot_ups.remove(&node);
    match r.control(Control::Start) {
        Err(e) if !e.is_timeout() => return Err(r.fail(e, Where::BootloaderWithProgram)),
        _ => {}
    }
    did!(Step::Start);
    let sees_traffic = r.bus.sees_traffic();
    // The device resets after its answer (or before it): it is back with its boot-up, or
    // through a gateway, which shows no boot-up, once it answers again.
    if !step!(r.wait_back(), Where::Unknown) {
        let e = FirmwareError::NoBootUp { node, after: "start (0x1F51 = 1)", waited: o.boot_wait };
        return Err(r.fail(e, Where::Unknown));
    }
    did!(if sees_traffic { Step::BootUp } else { Step::Answers });
    if sees_traffic && step!(r.wait_heartbeat(), Where::Unknown) {
        did!(Step::Heartbeat);
    }
    let state = Control::from_code(step!(r.read_u32(PROGRAM_CONTROL), Where::Unknown) as u8);
    if state == Control::Confirm && o.confirm {
        step!(r.control(Control::Confirm), Where::Unknown);
        r.report.confirmed = true;
        did!(Step::Confirm);
    }
    let id_after = Some(step!(r.read_u32(SOFTWARE_ID), Where::Unknown));
    let state = if state == Control::Confirm && !o.confirm { State::OnTrial } else { State::At(Where::RunsImage) };
    Ok(DownloadReport { id_after, device: Where::RunsImage, state, total_ms: r.ms(), ..r.report })
}

/// A node's download: its report, or how it failed.
pub(super) type Outcome = std::result::Result<DownloadReport, Box<Failed>>;

/// How a node's download ended (as [`super::download_each`] tells it).
pub(super) fn ended(outcome: &Outcome) -> DownloadEnd {
    match outcome {
        Ok(r) if r.skipped => DownloadEnd::Skipped,
        Ok(_) => DownloadEnd::Done,
        Err(f) if f.report.interrupted => DownloadEnd::Interrupted,
        Err(_) => DownloadEnd::Failed,
    }
}
