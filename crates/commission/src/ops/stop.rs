//! A request to stop, heeded by any procedure: one that must leave the bus tidy (LSS
//! devices back in waiting state, a PDO mapping put back) checks its [`Cancel`] between
//! steps and finishes cleanly; the others run over a bus that stops at their next call to
//! it ([`stoppable`]), an SDO transfer under way aborted. Either way the caller gets a
//! partial report.
//!
//! Also where a command's bus is opened and closed ([`on_bus`]), with the test seam of the
//! kill-at-every-step tests on it ([`install_interrupt_plan`]): a test build of canctl
//! raises a real signal at an exact point of a procedure, so that those tests need no
//! timing.

use crate::bus::stoppable::Stoppable;
use crate::bus::tap::{AfterSdo, Transfer};
use crate::bus::{Bus, TransferHook};
use crate::cancel::Cancel;
use crate::connect::{BusAddr, OpenOptions};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::Duration;

/// Run `f` over `bus` so that a request to stop (`cancel`) ends it at its next call to the
/// bus (an SDO transfer under way aborted).
pub fn stoppable<T>(bus: &mut dyn Bus, cancel: &Cancel, f: impl FnOnce(&mut dyn Bus) -> T) -> T {
    f(&mut Stoppable::new(bus, cancel.clone()))
}

/// Open `addr` and run `f` on it as a command does: interrupted as the plan of
/// [`install_interrupt_plan`] says when there is one (the opening included); `explain` sees
/// `f`'s error while the bus is still open. The bus is closed whatever the outcome (a
/// simulated bus saves its state then); a frame log that could not be written fails the run
/// once `f` is done (a warning said so when it happened).
pub fn on_bus<E: From<crate::Error>>(
    addr: &BusAddr,
    opts: &OpenOptions,
    cancel: &Cancel,
    f: impl FnOnce(&mut dyn Bus) -> Result<(), E>,
    explain: impl FnOnce(&mut dyn Bus, E) -> E,
) -> Result<(), E> {
    let mut bus = crate::connect::open(addr, opts)?;
    opened(cancel);
    let result = f(&mut with_interrupt_plan(bus.as_mut(), cancel));
    // The explanation heeds the request to stop as the command did.
    let result = result.map_err(|e| explain(&mut Stoppable::new(bus.as_mut(), cancel.clone()), e));
    let closed = bus.close();
    result?;
    closed?;
    if let Some(log) = &opts.frame_log {
        log.finish()?;
    }
    Ok(())
}

/// Where the plan of [`install_interrupt_plan`] interrupts a command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InterruptPoint {
    /// Right after the K-th transfer of that kind ended: `After(Transfer::Download, 3)`
    /// once the 3rd SDO write was confirmed (the reads of a batch count each as it ends).
    After(Transfer, u32),
    /// Right after the K-th answer that moved an SDO transfer on: a segment, a sub-block.
    Segment(u32),
    /// Once the bus is open, before the command's first step.
    Opened,
}

type Interrupt = Box<dyn Fn(&Cancel) + Send + Sync>;

static PLAN: OnceLock<(InterruptPoint, Interrupt)> = OnceLock::new();

/// A test seam, the one of the kill-at-every-step tests: from now on every command this
/// process runs on a bus (each bus counting on its own) calls `interrupt` at `at`, and goes
/// on only once that has requested the stop (the command's [`Cancel`] cancelled, within
/// 10 s), or not at all. It makes the point of interruption exact without timing.
///
/// The test build of canctl (`tests/seams/canctl.rs`, a binary of `cargo test` only) is
/// its one user: it installs a plan that raises a real signal, for the real handler of
/// canctl's `main` to catch. The shipped canctl installs none, and the library never does.
///
/// # Panics
///
/// When a plan is installed already: there is one per process.
pub fn install_interrupt_plan(at: InterruptPoint, interrupt: impl Fn(&Cancel) + Send + Sync + 'static) {
    if PLAN.set((at, Box::new(interrupt))).is_err() {
        panic!("an interrupt plan is installed once per process");
    }
}

/// `bus`, interrupted as the plan of [`install_interrupt_plan`] says when there is one; as
/// it is otherwise. `cancel` is the request to stop that the interruption makes.
pub(crate) fn with_interrupt_plan<'a>(
    bus: &'a mut dyn Bus,
    cancel: &Cancel,
) -> AfterSdo<'a, impl FnMut(Transfer, u32)> {
    let plan = PLAN.get();
    let (on_segment, on_transfer) = (cancel.clone(), cancel.clone());
    let segment_hook: Option<TransferHook> = match plan {
        Some((InterruptPoint::Segment(k), interrupt)) => {
            let (k, seen) = (*k, AtomicU32::new(0));
            Some(Arc::new(move |_| {
                if seen.fetch_add(1, Ordering::SeqCst) + 1 == k {
                    interrupt_and_wait(interrupt, &on_segment);
                }
            }))
        }
        _ => None,
    };
    AfterSdo::new(bus, move |transfer, count| {
        if let Some((_, interrupt)) = plan.filter(|(at, _)| *at == InterruptPoint::After(transfer, count)) {
            interrupt_and_wait(interrupt, &on_transfer);
        }
    })
    .with_progress_hook(segment_hook)
}

/// The bus is open: the interruption of [`install_interrupt_plan`] when its plan names this
/// point.
pub fn opened(cancel: &Cancel) {
    if let Some((InterruptPoint::Opened, interrupt)) = PLAN.get() {
        interrupt_and_wait(interrupt, cancel);
    }
}

fn interrupt_and_wait(interrupt: &Interrupt, cancel: &Cancel) {
    interrupt(cancel);
    cancel.wait_for_handler(Duration::from_secs(10));
}
