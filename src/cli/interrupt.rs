//! Ctrl-C and termination (SIGINT and SIGTERM on Unix; Ctrl-C, Ctrl-Break and console close
//! on Windows) as a request to stop: a procedure that must leave the bus tidy (LSS devices
//! back in waiting state, a PDO mapping put back) checks the flag between steps, finishes
//! cleanly and exits 130 after a partial report.

use crate::bus::{Bus, LssAnswer, LssWait, Observed, SdoOptions};
use crate::canopen::nmt::Command;
use crate::canopen::ObjAddr;
use crate::frame::Frame;
use crate::Result;
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
pub fn with_test_signal(bus: &mut dyn Bus) -> SignalAfterWrites<'_> {
    let plan = std::env::var(TEST_SIGNAL).ok().and_then(|v| {
        let (k, sig) = v.split_once(':')?;
        let (reads, k) = k.strip_prefix('r').map_or((false, k), |k| (true, k));
        Some((reads, k.parse().ok()?, sig.to_string()))
    });
    SignalAfterWrites { bus, plan, count: 0 }
}

/// A bus that signals its own process after a given number of SDO writes (see
/// [`TEST_SIGNAL`]).
pub struct SignalAfterWrites<'a> {
    bus: &'a mut dyn Bus,
    /// Whether reads count (else writes), after how many, which signal.
    plan: Option<(bool, u32, String)>,
    count: u32,
}

impl SignalAfterWrites<'_> {
    fn after(&mut self, read: bool) {
        if self.plan.as_ref().is_none_or(|(reads, _, _)| *reads != read) {
            return;
        }
        self.count += 1;
        let Some((_, _, sig)) = self.plan.take_if(|(_, k, _)| *k == self.count) else { return };
        raise(&sig);
        // The handler runs on its own thread: the signal counts once it has set the flag.
        let end = Instant::now() + Duration::from_secs(10);
        while !requested() && Instant::now() < end {
            std::thread::yield_now();
        }
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
    REQUESTED.store(true, Ordering::SeqCst);
}

impl Bus for SignalAfterWrites<'_> {
    fn describe(&self) -> String {
        self.bus.describe()
    }
    fn sdo_upload(&mut self, node: u8, addr: ObjAddr, opts: &SdoOptions) -> Result<Vec<u8>> {
        let answer = self.bus.sdo_upload(node, addr, opts);
        self.after(true);
        answer
    }
    fn sdo_download(&mut self, node: u8, addr: ObjAddr, data: &[u8], opts: &SdoOptions) -> Result<()> {
        self.bus.sdo_download(node, addr, data, opts)?;
        self.after(false);
        Ok(())
    }
    fn sdo_upload_many(
        &mut self,
        requests: &[(u8, ObjAddr)],
        opts: &SdoOptions,
        progress: &mut dyn FnMut(usize),
    ) -> Result<Vec<Result<Vec<u8>>>> {
        self.bus.sdo_upload_many(requests, opts, progress)
    }
    fn nmt(&mut self, cmd: Command, node: u8) -> Result<()> {
        self.bus.nmt(cmd, node)
    }
    fn send_frame(&mut self, frame: &Frame) -> Result<()> {
        self.bus.send_frame(frame)
    }
    fn sees_traffic(&self) -> bool {
        self.bus.sees_traffic()
    }
    fn follows_bit_rate_switch(&self) -> bool {
        self.bus.follows_bit_rate_switch()
    }
    fn recv_frame(&mut self, deadline: Instant) -> Result<Option<Frame>> {
        self.bus.recv_frame(deadline)
    }
    fn request_frame(&mut self, id: u16, len: u8, timeout: Duration) -> Result<Frame> {
        self.bus.request_frame(id, len, timeout)
    }
    fn lss_exchange(
        &mut self,
        request: &[u8; 8],
        expect: u8,
        wait: Duration,
        collect: LssWait,
    ) -> Result<Vec<LssAnswer>> {
        self.bus.lss_exchange(request, expect, wait, collect)
    }
    fn observed(&mut self) -> &mut Observed {
        self.bus.observed()
    }
    fn close(&mut self) -> Result<()> {
        self.bus.close()
    }
}
