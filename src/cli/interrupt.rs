//! Ctrl-C and termination (SIGINT and SIGTERM on Unix; Ctrl-C, Ctrl-Break and console close
//! on Windows) as the program's request to stop, for every command. How a procedure heeds
//! it (between steps, or at its next call to the bus) is the library's: `ops::stop`.

use crate::cancel::Cancel;
use std::sync::LazyLock;

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
