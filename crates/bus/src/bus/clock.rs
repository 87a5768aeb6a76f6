//! The monotonic clock of the links that talk to hardware (a CAN interface, a serial port,
//! a served simulator). Everything above the links reads time from its bus
//! ([`Bus::now`](super::Bus::now), [`Bus::sleep_until`](super::Bus::sleep_until)), so that
//! the simulator can put its own, virtual, clock there instead.

use std::time::Instant;

/// Now, on the monotonic clock.
pub fn monotonic_now() -> Instant {
    Instant::now()
}

/// Block the thread until `t` on the monotonic clock.
pub fn sleep_until(t: Instant) {
    let left = t.saturating_duration_since(Instant::now());
    if !left.is_zero() {
        std::thread::sleep(left);
    }
}
