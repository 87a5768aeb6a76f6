//! What a CAN controller tells about the bus, beyond the frames: its state and error
//! counters (SocketCAN's netlink details) and the error frames it reported. Pure: the
//! backends fill a [`LinkReport`], doctor reads it.
//!
//! Error frames follow the kernel's `linux/can/error.h` layout: the class bits in the CAN
//! id (with `CAN_ERR_FLAG`), details in the data bytes.

// Only the SocketCAN backend (Linux) reads error frames and netlink states; the decoding
// stays portable, so that its byte-vector tests run on every platform.
#![cfg_attr(not(target_os = "linux"), allow(dead_code))]

use serde::Serialize;

/// The flag that marks an error frame in a SocketCAN CAN id.
pub const CAN_ERR_FLAG: u32 = 0x2000_0000;
/// Class: a controller problem, details in data[1].
const ERR_CRTL: u32 = 0x0004;
/// Class: a protocol violation, its type in data[2], its location in data[3].
const ERR_PROT: u32 = 0x0008;
/// Class: no acknowledgement of a frame sent.
const ERR_ACK: u32 = 0x0020;
/// Class: the controller went bus-off.
const ERR_BUSOFF: u32 = 0x0040;
/// Class: the controller was restarted (after bus-off).
const ERR_RESTARTED: u32 = 0x0100;
/// Class: data[6] and data[7] hold the tx and rx error counters.
const ERR_CNT: u32 = 0x0200;

/// data[1]: warning level reached (rx 0x04, tx 0x08).
const CRTL_WARNING: u8 = 0x04 | 0x08;
/// data[1]: error-passive reached (rx 0x10, tx 0x20).
const CRTL_PASSIVE: u8 = 0x10 | 0x20;
/// data[2]: a single bit error, or a dominant/recessive bit not sent as meant (0x08, 0x10).
const PROT_BIT: u8 = 0x01 | 0x08 | 0x10;
/// data[2]: a form error.
const PROT_FORM: u8 = 0x02;
/// data[2]: a bit-stuffing error.
const PROT_STUFF: u8 = 0x04;
/// data[3]: the error was in the ACK slot or its delimiter.
const LOC_ACK: [u8; 2] = [0x19, 0x1B];

/// The error frames a controller reported, counted by what they said. One frame may count
/// under several heads (a protocol error that also reports the warning level).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct ErrorFrameCounts {
    /// Error frames in all.
    pub frames: u32,
    /// Frames sent that nobody acknowledged (the ACK class, or a protocol error in the ACK slot).
    pub ack: u32,
    /// Bit errors: the controller read another level than it sent.
    pub bit: u32,
    /// Bit-stuffing errors.
    pub stuff: u32,
    /// Form errors.
    pub form: u32,
    /// Reports of the warning level (96 errors).
    pub warning: u32,
    /// Reports of error-passive (128 errors).
    pub passive: u32,
    /// Reports of bus-off.
    pub bus_off: u32,
    /// Restarts after bus-off.
    pub restarted: u32,
    /// The last tx and rx error counters an error frame carried.
    pub counters: Option<(u8, u8)>,
}

impl ErrorFrameCounts {
    /// Count one error frame: `can_id` with its class bits, `data` its detail bytes (a
    /// short frame counts by its class only).
    pub fn take(&mut self, can_id: u32, data: &[u8]) {
        let byte = |i: usize| data.get(i).copied().unwrap_or(0);
        self.frames += 1;
        let (crtl, prot, loc) = (byte(1), byte(2), byte(3));
        let prot_here = can_id & ERR_PROT != 0;
        if can_id & ERR_ACK != 0 || (prot_here && LOC_ACK.contains(&loc)) {
            self.ack += 1;
        }
        if prot_here {
            self.bit += u32::from(prot & PROT_BIT != 0);
            self.stuff += u32::from(prot & PROT_STUFF != 0);
            self.form += u32::from(prot & PROT_FORM != 0);
        }
        if can_id & ERR_CRTL != 0 {
            self.warning += u32::from(crtl & CRTL_WARNING != 0);
            self.passive += u32::from(crtl & CRTL_PASSIVE != 0);
        }
        self.bus_off += u32::from(can_id & ERR_BUSOFF != 0);
        self.restarted += u32::from(can_id & ERR_RESTARTED != 0);
        if can_id & ERR_CNT != 0 && data.len() >= 8 {
            self.counters = Some((data[6], data[7]));
        }
    }

    /// Whether frames were destroyed on the bus (bit, stuff or form errors): another bit
    /// rate, or the wiring.
    pub fn signal_errors(&self) -> bool {
        self.bit + self.stuff + self.form > 0
    }

    /// Whether the only trouble was frames nobody acknowledged: no other device powered,
    /// or the bus not terminated.
    pub fn only_ack(&self) -> bool {
        self.ack > 0 && !self.signal_errors()
    }
}

/// A CAN controller's state (SocketCAN's `can_state`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
// Exhaustive on purpose: canctl words every case, and the compiler says when one is new.
pub enum CanState {
    /// Taking part normally (fewer than 96 errors).
    ErrorActive,
    /// 96 errors or more: still taking part.
    ErrorWarning,
    /// 128 errors or more: it may no longer flag errors actively.
    ErrorPassive,
    /// Too many errors: it stopped taking part.
    BusOff,
    /// The interface is stopped.
    Stopped,
    /// The controller sleeps.
    Sleeping,
}

impl CanState {
    /// The state from its number in `linux/can/netlink.h`.
    pub(crate) fn from_raw(n: u32) -> Option<CanState> {
        use CanState::*;
        [ErrorActive, ErrorWarning, ErrorPassive, BusOff, Stopped, Sleeping].get(n as usize).copied()
    }
}

/// What the interface's controller says about itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(tag = "controller", rename_all = "snake_case")]
// Exhaustive on purpose: canctl words every case, and the compiler says when one is new.
pub enum Controller {
    /// A virtual interface (vcan): no controller, no state, no counters.
    Virtual,
    /// A CAN controller's report; a field it did not give is `None`.
    Can {
        /// Its state.
        state: Option<CanState>,
        /// The transmit error counter.
        tx_errors: Option<u16>,
        /// The receive error counter.
        rx_errors: Option<u16>,
        /// The automatic restart after bus-off, in ms; 0: never (it stays bus-off).
        restart_ms: Option<u32>,
        /// Its bit rate.
        bitrate: Option<u32>,
    },
}

/// What a link knows about the bus beyond its frames.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct LinkReport {
    /// The interface the report is about.
    pub iface: String,
    /// The controller's own report, when the link can read one.
    pub controller: Option<Controller>,
    /// The error frames it reported since it was opened.
    pub error_frames: ErrorFrameCounts,
    /// Frames that found the transmit queue full (ENOBUFS) and had to wait for room.
    pub queue_full: u32,
}

/// What a listen-only trial at one bit rate heard (a link that can change its rate).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct RateHeard {
    /// The bit rate tried, in kbit/s.
    pub kbit: u32,
    /// Frames decoded.
    pub frames: u32,
    /// Whether the adapter reported bus errors (or lines it could not decode) meanwhile.
    pub errors: bool,
}

impl RateHeard {
    /// Whether the bus's traffic decoded cleanly at this rate.
    pub fn clean(&self) -> bool {
        self.frames > 0 && !self.errors
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counted(frames: &[(u32, [u8; 8])]) -> ErrorFrameCounts {
        let mut c = ErrorFrameCounts::default();
        for (id, data) in frames {
            c.take(id | CAN_ERR_FLAG, data);
        }
        c
    }

    #[test]
    fn ack_errors_alone_say_nothing_acknowledges() {
        // A controller alone on the bus: the ACK class, and protocol errors in the ACK slot,
        // with the tx counter climbing to error-passive (data[1] 0x20).
        let c = counted(&[
            (0x020, [0; 8]),
            (0x008 | 0x200, [0, 0, 0, 0x19, 0, 0, 96, 0]),
            (0x004 | 0x200, [0, 0x20, 0, 0, 0, 0, 128, 0]),
        ]);
        assert_eq!((c.frames, c.ack, c.passive), (3, 2, 1));
        assert_eq!(c.counters, Some((128, 0)));
        assert!(c.only_ack());
        assert!(!c.signal_errors());
    }

    #[test]
    fn bit_stuff_and_form_errors_say_bit_rate_or_wiring() {
        // Listening at another bit rate: stuff and form errors on reception, a bit error.
        let c = counted(&[
            (0x008 | 0x080, [0, 0, 0x04, 0x08, 0, 0, 0, 0]),
            (0x008, [0, 0, 0x02, 0x0A, 0, 0, 0, 0]),
            (0x008, [0, 0, 0x01, 0x0A, 0, 0, 0, 0]),
            (0x008, [0, 0, 0x10, 0x19, 0, 0, 0, 0]),
        ]);
        assert_eq!((c.bit, c.stuff, c.form), (2, 1, 1));
        assert_eq!(c.ack, 1);
        assert!(c.signal_errors());
        assert!(!c.only_ack());
    }

    #[test]
    fn controller_states_bus_off_and_restart_are_counted() {
        let c = counted(&[(0x004, [0, 0x08, 0, 0, 0, 0, 0, 0]), (0x040, [0; 8]), (0x100, [0; 8])]);
        assert_eq!((c.warning, c.passive, c.bus_off, c.restarted), (1, 0, 1, 1));
        assert_eq!(c.counters, None);
        assert!(!c.only_ack());
    }

    #[test]
    fn a_short_error_frame_counts_by_its_class() {
        let mut c = ErrorFrameCounts::default();
        c.take(CAN_ERR_FLAG | 0x008 | 0x200, &[0, 0, 0x04]);
        assert_eq!((c.frames, c.stuff, c.counters), (1, 1, None));
    }

    #[test]
    fn states_by_number() {
        assert_eq!(CanState::from_raw(0), Some(CanState::ErrorActive));
        assert_eq!(CanState::from_raw(3), Some(CanState::BusOff));
        assert_eq!(CanState::from_raw(9), None);
    }
}
