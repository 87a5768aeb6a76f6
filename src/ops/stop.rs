//! A request to stop, heeded by any procedure: one that must leave the bus tidy (LSS
//! devices back in waiting state, a PDO mapping put back) checks its [`Cancel`] between
//! steps and finishes cleanly; the others run over a bus that stops at their next call to
//! it ([`stoppable`]), an SDO transfer under way aborted. Either way the caller gets a
//! partial report.
//!
//! Also where a command's bus is opened and closed ([`on_bus`]), with the test seam of the
//! kill-at-every-step tests ([`TEST_SIGNAL`]) on it: the seam raises a real
//! signal at an exact point of a procedure, so that those tests need no timing.

use crate::bus::stoppable::Stoppable;
use crate::bus::tap::{AfterSdo, Transfer};
use crate::bus::{Bus, TransferHook};
use crate::cancel::Cancel;
use crate::connect::{BusAddr, OpenOptions};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// Run `f` over `bus` so that a request to stop (`cancel`) ends it at its next call to the
/// bus (an SDO transfer under way aborted).
pub fn stoppable<T>(bus: &mut dyn Bus, cancel: &Cancel, f: impl FnOnce(&mut dyn Bus) -> T) -> T {
    f(&mut Stoppable::new(bus, cancel.clone()))
}

/// Open `addr` and run `f` on it as a command does: with the test signal of [`TEST_SIGNAL`]
/// when that is set (at the point it names, the opening included); `explain` sees `f`'s
/// error while the bus is still open. The bus is closed whatever the outcome (a simulated
/// bus saves its state then); a frame log that could not be written fails the run once `f`
/// is done (a warning said so when it happened).
pub(crate) fn on_bus<E: From<crate::Error>>(
    addr: &BusAddr,
    opts: &OpenOptions,
    cancel: &Cancel,
    f: impl FnOnce(&mut dyn Bus) -> Result<(), E>,
    explain: impl FnOnce(&mut dyn Bus, E) -> E,
) -> Result<(), E> {
    let mut bus = crate::connect::open(addr, opts)?;
    opened(cancel);
    let result = f(&mut with_test_signal(bus.as_mut(), cancel));
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

/// The environment variable of the kill-at-every-step tests: `K:SIGNAL` (INT, TERM, KILL)
/// sends that signal to this process right after its K-th SDO write was answered (`rK:`:
/// its K-th SDO read, those of a batch each as it ends; `nK:` its K-th NMT command; `sK:`
/// the K-th answer that moved an SDO transfer on: a segment, a sub-block; `o1:` once the
/// bus is open, before the command's first step). It makes the point of interruption
/// exact without timing; nothing else reads it. The process must have a handler that
/// turns the signal into the request to stop (canctl's `main` installs one).
pub(crate) const TEST_SIGNAL: &str = "CANCTL_TEST_SIGNAL_AFTER_WRITES";

/// What [`TEST_SIGNAL`] asks for.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Point {
    After(Transfer),
    Segment,
    Opened,
}

fn test_plan() -> Option<(Point, u32, String)> {
    let v = std::env::var(TEST_SIGNAL).ok()?;
    let (k, sig) = v.split_once(':')?;
    let (point, k) = match k.split_at(k.find(|c: char| c.is_ascii_digit()).unwrap_or(0)) {
        ("", k) => (Point::After(Transfer::Download), k),
        ("r", k) => (Point::After(Transfer::Upload), k),
        ("n", k) => (Point::After(Transfer::Nmt), k),
        ("s", k) => (Point::Segment, k),
        ("o", k) => (Point::Opened, k),
        _ => return None,
    };
    Some((point, k.parse().ok()?, sig.to_string()))
}

/// `bus`, with the test signal of [`TEST_SIGNAL`] when that is set; as it is otherwise.
/// `cancel` is the request to stop the signal's handler makes.
pub(crate) fn with_test_signal<'a>(bus: &'a mut dyn Bus, cancel: &Cancel) -> AfterSdo<'a, impl FnMut(Transfer, u32)> {
    let plan = test_plan();
    let (on_segment, on_transfer) = (cancel.clone(), cancel.clone());
    let segment_hook: Option<TransferHook> = match plan.clone() {
        Some((Point::Segment, k, sig)) => {
            let seen = AtomicU32::new(0);
            Some(Arc::new(move |_| {
                if seen.fetch_add(1, Ordering::SeqCst) + 1 == k {
                    raise_and_wait(&sig, &on_segment);
                }
            }))
        }
        _ => None,
    };
    AfterSdo::new(bus, move |transfer, count| {
        if let Some((_, _, sig)) = plan.as_ref().filter(|(p, k, _)| *p == Point::After(transfer) && *k == count) {
            raise_and_wait(sig, &on_transfer);
        }
    })
    .with_progress_hook(segment_hook)
}

/// The bus is open: the test signal of [`TEST_SIGNAL`] when it asks for this point.
pub fn opened(cancel: &Cancel) {
    if let Some((Point::Opened, _, sig)) = test_plan() {
        raise_and_wait(&sig, cancel);
    }
}

fn raise_and_wait(sig: &str, cancel: &Cancel) {
    raise(sig, cancel);
    cancel.wait_for_handler(Duration::from_secs(10));
}

#[cfg(unix)]
fn raise(sig: &str, _: &Cancel) {
    use nix::sys::signal::{self, Signal};
    let sig = match sig {
        "INT" | "SIGINT" => Signal::SIGINT,
        "TERM" | "SIGTERM" => Signal::SIGTERM,
        "KILL" | "SIGKILL" => Signal::SIGKILL,
        _ => return,
    };
    let _ = signal::raise(sig);
}

#[cfg(not(unix))]
fn raise(_: &str, cancel: &Cancel) {
    cancel.cancel();
}
