//! The one request to stop (SIGINT, SIGTERM, Ctrl-C, Ctrl-Break): a cheap token, cloned
//! into every procedure's options and every bus wrapper that must heed it. The command
//! line installs one at the start of the program, whatever the command, so a stop that
//! comes while the bus is still opening is seen by the command's first step; library users
//! make their own and cancel it from wherever they decide to stop.

use crate::error::{Error, Result};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A request to stop, shared by every clone. A new one is not cancelled.
#[derive(Clone, Default, Debug)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A request not yet made: clone it to everything that is to stop together.
    pub fn new() -> Cancel {
        Cancel::default()
    }

    /// Ask everything that holds a clone to stop at its next safe point.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    /// Whether a stop has been asked for.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::SeqCst)
    }

    /// Wait, on the wall clock, up to `within` for the request: an OS signal's handler runs
    /// on a thread of its own, so a signal just raised counts only once it has set the flag.
    /// Wall time, not the bus's: the handler's thread does not run on simulated time.
    pub fn wait_for_handler(&self, within: std::time::Duration) {
        let end = std::time::Instant::now() + within;
        while !self.is_cancelled() && std::time::Instant::now() < end {
            std::thread::yield_now();
        }
    }

    /// [`Error::Interrupted`] once cancelled: for a step that must not begin after a stop.
    pub fn check(&self) -> Result<()> {
        (!self.is_cancelled()).then_some(()).ok_or(Error::Interrupted)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_clone_sees_the_request() {
        let a = Cancel::new();
        let b = a.clone();
        assert!(!b.is_cancelled() && b.check().is_ok());
        a.cancel();
        assert!(b.is_cancelled());
        assert!(matches!(b.check(), Err(Error::Interrupted)));
        assert!(!Cancel::new().is_cancelled(), "a new token is its own");
    }
}
