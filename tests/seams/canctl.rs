//! canctl as the kill-at-every-step tests run it: the real `main` (src/main.rs, its signal
//! handler and all), plus an interrupt plan ([`canctl::ops::install_interrupt_plan`]) taken
//! from `CANCTL_TEST_SIGNAL_AFTER_WRITES`, so that the point of interruption is exact
//! without timing. A binary of `cargo test` only (Cargo.toml, `test-seams`), outside the
//! published package: the canctl that is installed and shipped reads no such variable.
//!
//! `K:SIGNAL` (INT, TERM, KILL) sends that signal to this process right after its K-th SDO
//! write was confirmed; `rK:` after its K-th SDO read (those of a batch each as it ends);
//! `nK:` after its K-th NMT command; `sK:` after the K-th answer that moved an SDO transfer
//! on (a segment, a sub-block); `o1:` once the bus is open, before the command's first step.

#[path = "../../src/main.rs"]
mod canctl_main;

use canctl::bus::tap::Transfer;
use canctl::cancel::Cancel;
use canctl::ops::InterruptPoint;

const PLAN: &str = "CANCTL_TEST_SIGNAL_AFTER_WRITES";

fn main() {
    if let Some(plan) = std::env::var_os(PLAN) {
        let plan = plan.to_string_lossy();
        // A mistyped plan would run the command uninterrupted: the test says so instead.
        let (at, signal) = parse(&plan).unwrap_or_else(|| panic!("{PLAN}={plan}: not a point:SIGNAL"));
        canctl::ops::install_interrupt_plan(at, interrupt(signal));
    }
    canctl_main::main()
}

fn parse(plan: &str) -> Option<(InterruptPoint, &str)> {
    let (point, signal) = plan.split_once(':')?;
    let (kind, k) = point.split_at(point.find(|c: char| c.is_ascii_digit())?);
    let k = k.parse().ok()?;
    let at = match kind {
        "" => InterruptPoint::After(Transfer::Download, k),
        "r" => InterruptPoint::After(Transfer::Upload, k),
        "n" => InterruptPoint::After(Transfer::Nmt, k),
        "s" => InterruptPoint::Segment(k),
        "o" => InterruptPoint::Opened,
        _ => return None,
    };
    Some((at, signal))
}

/// The signal, raised at this process for `main`'s handler to turn into the request to stop.
#[cfg(unix)]
fn interrupt(signal: &str) -> impl Fn(&Cancel) + Send + Sync + 'static {
    use nix::sys::signal::{raise, Signal};
    let signal = match signal {
        "INT" | "SIGINT" => Signal::SIGINT,
        "TERM" | "SIGTERM" => Signal::SIGTERM,
        "KILL" | "SIGKILL" => Signal::SIGKILL,
        _ => panic!("{PLAN}: no signal {signal} (INT, TERM, KILL)"),
    };
    move |_: &Cancel| {
        let _ = raise(signal);
    }
}

/// No signals to raise: the request to stop as the Ctrl-C handler makes it.
#[cfg(not(unix))]
fn interrupt(_: &str) -> impl Fn(&Cancel) + Send + Sync + 'static {
    |cancel: &Cancel| cancel.cancel()
}
