//! Ctrl-C and termination (SIGINT and SIGTERM on Unix; Ctrl-C, Ctrl-Break and console close
//! on Windows) as a request to stop: a procedure that must leave the bus tidy (LSS devices
//! back in waiting state, a PDO mapping put back) checks the flag between steps, finishes
//! cleanly and exits 130 after a partial report.

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

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
