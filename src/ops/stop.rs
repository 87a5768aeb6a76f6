//! Ctrl-C and termination (SIGINT and SIGTERM on Unix; Ctrl-C, Ctrl-Break and console close
//! on Windows) as a request to stop, for every command: a procedure that must leave the bus
//! tidy (LSS devices back in waiting state, a PDO mapping put back) checks the flag between
//! steps and finishes cleanly; the others run over a bus that stops at their next call to
//! it ([`stoppable`]), an SDO transfer under way aborted. Either way the command prints a
//! partial report and exits 130.

use crate::bus::stoppable::Stoppable;
use crate::bus::tap::{AfterSdo, Transfer};
use crate::bus::{Bus, TransferHook};
use crate::cancel::Cancel;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, LazyLock};
use std::time::{Duration, Instant};

/// The program's one request to stop, set by the handler [`install`] puts in place.
static REQUESTED: LazyLock<Cancel> = LazyLock::new(Cancel::new);

/// Called first thing in `main`, whatever the command: from then on an interruption sets
/// the program's [`Cancel`] instead of ending the process, so a stop that comes while the
/// bus opens, or before the command's first step, is still seen and reported (exit 130).
/// Installed lazily by each command, a supervisor's SIGTERM in that window killed canctl
/// with no report. A second request ends the process at once: the user asked twice.
pub fn install() -> Cancel {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // Only fails when a handler is already set, which `ONCE` rules out.
        let _ = ctrlc::set_handler(|| {
            if REQUESTED.is_cancelled() {
                eprintln!("canctl: interrupted again: stopped at once, what was under way may be half done");
                std::process::exit(crate::error::ErrorClass::Interrupted.exit_code());
            }
            REQUESTED.cancel();
        });
    });
    REQUESTED.clone()
}

/// The program's request to stop (the one [`install`] put in place).
pub fn requested() -> bool {
    REQUESTED.is_cancelled()
}

/// Run `f` over `bus` so that an interruption stops it at its next call to the bus (an SDO
/// transfer under way aborted), with the test signal of [`TEST_SIGNAL`] when that is set.
pub fn stoppable<T>(bus: &mut dyn Bus, f: impl FnOnce(&mut dyn Bus) -> T) -> T {
    let mut tapped = with_test_signal(bus);
    let mut guarded = Stoppable::new(&mut tapped, REQUESTED.clone());
    f(&mut guarded)
}

/// A read-only command stopped part-way: its report says only that nothing was changed.
pub fn stopped_reading(ctx: &super::Ctx, command: &str, not_done: String) -> anyhow::Result<()> {
    let state = "nothing was changed on the device".to_string();
    ctx.out.report(&crate::ops::Stopped::new(command, Vec::new(), vec![not_done], state))?;
    Err(crate::Error::Interrupted.into())
}

/// The environment variable of the kill-at-every-step tests: `K:SIGNAL` (INT, TERM, KILL)
/// sends that signal to this process right after its K-th SDO write was answered (`rK:`:
/// its K-th SDO read, those of a batch each as it ends; `nK:` its K-th NMT command; `sK:`
/// the K-th answer that moved an SDO transfer on: a segment, a sub-block; `o1:` once the
/// bus is open, before the command's first step). It makes the
/// point of interruption exact without timing; nothing else reads it.
pub const TEST_SIGNAL: &str = "CANCTL_TEST_SIGNAL_AFTER_WRITES";

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
pub fn with_test_signal(bus: &mut dyn Bus) -> AfterSdo<'_, impl FnMut(Transfer, u32)> {
    let plan = test_plan();
    let segment_hook: Option<TransferHook> = match plan.clone() {
        Some((Point::Segment, k, sig)) => {
            let seen = AtomicU32::new(0);
            Some(Arc::new(move |_| {
                if seen.fetch_add(1, Ordering::SeqCst) + 1 == k {
                    raise_and_wait(&sig);
                }
            }))
        }
        _ => None,
    };
    AfterSdo::new(bus, move |transfer, count| {
        if let Some((_, _, sig)) = plan.as_ref().filter(|(p, k, _)| *p == Point::After(transfer) && *k == count) {
            raise_and_wait(sig);
        }
    })
    .with_progress_hook(segment_hook)
}

/// The bus is open: the test signal of [`TEST_SIGNAL`] when it asks for this point.
pub fn opened() {
    if let Some((Point::Opened, _, sig)) = test_plan() {
        raise_and_wait(&sig);
    }
}

fn raise_and_wait(sig: &str) {
    raise(sig);
    // The handler runs on its own thread: the signal counts once it has set the flag.
    let end = Instant::now() + Duration::from_secs(10);
    while !requested() && Instant::now() < end {
        std::thread::yield_now();
    }
}

#[cfg(unix)]
fn raise(sig: &str) {
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
fn raise(_: &str) {
    REQUESTED.cancel();
}
