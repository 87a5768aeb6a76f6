//! Ctrl-C and termination (SIGINT and SIGTERM on Unix; Ctrl-C, Ctrl-Break and console close
//! on Windows) as a request to stop: a procedure that must leave the bus tidy (LSS devices
//! back in waiting state, a PDO mapping put back) checks the flag between steps, finishes
//! cleanly and exits 130 after a partial report.

use crate::bus::tap::{AfterSdo, Transfer};
use crate::bus::Bus;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, LazyLock};
use std::time::{Duration, Instant};

static REQUESTED: LazyLock<Arc<AtomicBool>> = LazyLock::new(|| Arc::new(AtomicBool::new(false)));

/// From now on an interruption sets the flag instead of ending the process.
pub fn catch() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // Only fails when a handler is already set, which `ONCE` rules out.
        let _ = ctrlc::set_handler(|| REQUESTED.store(true, Ordering::SeqCst));
    });
}

pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// The flag itself, for library procedures that poll it.
pub fn flag() -> &'static AtomicBool {
    &REQUESTED
}

/// The flag, shared, for library options that keep it.
pub fn shared() -> Arc<AtomicBool> {
    Arc::clone(&REQUESTED)
}

/// The environment variable of the kill-at-every-step tests: `K:SIGNAL` (INT, TERM, KILL)
/// sends that signal to this process right after its K-th SDO write was answered (`rK:`:
/// its K-th SDO read). It makes the point of interruption exact without timing; nothing
/// else reads it.
pub const TEST_SIGNAL: &str = "CANCTL_TEST_SIGNAL_AFTER_WRITES";

/// `bus`, with the test signal of [`TEST_SIGNAL`] when that is set; as it is otherwise.
pub fn with_test_signal(bus: &mut dyn Bus) -> AfterSdo<'_, impl FnMut(Transfer, u32)> {
    let plan = std::env::var(TEST_SIGNAL).ok().and_then(|v| {
        let (k, sig) = v.split_once(':')?;
        let (reads, k) = k.strip_prefix('r').map_or((false, k), |k| (true, k));
        Some((if reads { Transfer::Upload } else { Transfer::Download }, k.parse::<u32>().ok()?, sig.to_string()))
    });
    AfterSdo::new(bus, move |transfer, count| {
        let Some((_, _, sig)) = plan.as_ref().filter(|(t, k, _)| *t == transfer && *k == count) else { return };
        raise(sig);
        // The handler runs on its own thread: the signal counts once it has set the flag.
        let end = Instant::now() + Duration::from_secs(10);
        while !requested() && Instant::now() < end {
            std::thread::yield_now();
        }
    })
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
    REQUESTED.store(true, Ordering::SeqCst);
}
