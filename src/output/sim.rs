//! `canctl sim`'s own words: where the devices are served, and why they cannot be.

use crate::canopen::lss::bit_rate_name;
use crate::epos2::Framing;
use crate::sim::serve::{ServeError, Serving};

/// How to reach the devices now served, as the note `canctl sim` prints.
pub(crate) fn serving(s: &Serving) -> String {
    match s {
        Serving::SocketCan { iface } => {
            format!("the sim network's devices are on {iface} (nodes 1, 5, 10, 32); stop with Ctrl-C")
        }
        Serving::Epos2 { framing, pty } => {
            let kind = if *framing == Framing::Rs232 { "epos2-rs232" } else { "epos2-usb" };
            format!("serving the sim network's EPOS2 (node 1) on {pty}: use --bus {kind}:{pty}; stop with Ctrl-C")
        }
        Serving::Slcan { pty, bit_rate } => {
            let rate = bit_rate_name(*bit_rate);
            format!(
                "the sim network's devices are behind an slcan adapter on {pty} ({rate}): use --bus slcan:{pty}@{rate}; \
                 stop with Ctrl-C"
            )
        }
        Serving::Socketcand { bound, bus, iface } => format!(
            "the sim network's devices are behind a socketcand server on {bound} (interface {iface}): use --bus {bus}; \
             several programs may use it at once; stop with Ctrl-C"
        ),
    }
}

/// What to do instead of what `canctl sim` could not serve; `None` when serving failed.
pub(crate) fn serve_refusal(e: &ServeError) -> Option<String> {
    Some(match e {
        ServeError::NoSocketCan => "SocketCAN is Linux's: `sim --socketcan` runs on Linux only; try `sim --slcan`".into(),
        ServeError::NoPty => "the simulated serial devices (--epos2-rs232, --epos2-usb, --slcan) sit on a pseudo-terminal, \
                              which this OS lacks; use --bus sim directly, or run them on Linux or macOS"
            .into(),
        ServeError::AdapterFault(kind) => format!(
            "the slcan adapter takes the faults nack (a bell), crc, garbage, drop and mute, not {kind:?}; device faults \
             go to `canctl sim reset --fault`"
        ),
        ServeError::Failed(_) => return None,
        ServeError::BusOffElsewhere => "the fault bus:off is modelled on --bus sim itself and behind `sim --slcan` only \
                                        (behind a CAN interface, socketcand or an EPOS2 the controller is not the \
                                        simulator's): use one of those, or `canctl sim reset` without it"
            .into(),
    })
}
