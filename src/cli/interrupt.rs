//! SIGINT and SIGTERM as a request to stop: a procedure that must leave the bus tidy
//! (LSS devices back in waiting state) checks `requested()` between steps, finishes
//! cleanly and exits 130 after a partial report.

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

extern "C" fn on_signal(_: nix::libc::c_int) {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// From now on Ctrl-C and SIGTERM set the flag instead of ending the process.
pub fn catch() {
    use nix::sys::signal::{sigaction, SaFlags, SigAction, SigHandler, SigSet, Signal};
    let action = SigAction::new(SigHandler::Handler(on_signal), SaFlags::empty(), SigSet::empty());
    for signal in [Signal::SIGINT, Signal::SIGTERM] {
        // SAFETY: the handler only stores to an atomic.
        let _ = unsafe { sigaction(signal, &action) };
    }
}

pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}
