//! Completion candidates as the shell shows them: the value, and its help in words.

use crate::canopen::types::ALL_TYPES;
use crate::ops::completion::{BusCandidate, ObjectCandidate};
use crate::ops::scan_cache::SeenNode;
use clap_complete::engine::CompletionCandidate;

fn candidate(value: impl Into<std::ffi::OsString>, help: impl Into<String>) -> CompletionCandidate {
    CompletionCandidate::new(value).help(Some(help.into().into()))
}

pub(crate) fn buses(buses: Vec<BusCandidate>) -> Vec<CompletionCandidate> {
    use crate::connect::BusAddr;
    use crate::epos2::Framing;
    buses
        .into_iter()
        .map(|b| match b {
            BusCandidate::Sim => candidate("sim", "the simulated demo network"),
            BusCandidate::Slcan(port) => candidate(format!("slcan:{port}"), "slcan CAN adapter (CANable, CANUSB)"),
            BusCandidate::Socketcand => {
                candidate("socketcand:", "socketcand:HOST[:PORT]/IFACE, a CAN interface over TCP")
            }
            BusCandidate::Heard(addr, what) => candidate(addr.to_string(), what),
            BusCandidate::Found(addr) => {
                let help = match &addr {
                    BusAddr::SocketCan { .. } => "CAN interface",
                    BusAddr::Epos2 { framing: Framing::Rs232, .. } => "maxon EPOS2 on RS232",
                    BusAddr::Epos2 { framing: Framing::Usb, .. } => "maxon EPOS2 on USB",
                    _ => "",
                };
                candidate(addr.to_string(), help)
            }
        })
        .collect()
}

/// Node-ids of the last scan of the bus, with what they are.
pub(crate) fn nodes(seen: Vec<SeenNode>) -> Vec<CompletionCandidate> {
    seen.into_iter()
        .map(|n| {
            let what = match (n.name, n.vendor_id) {
                (Some(name), Some(v)) => format!("{name} (vendor 0x{v:08X})"),
                (Some(name), None) => name,
                (None, Some(v)) => format!("vendor 0x{v:08X}"),
                (None, None) => "seen on the last scan".into(),
            };
            candidate(n.node.to_string(), what)
        })
        .collect()
}

/// Every object by address, then those the command finds by name by that name.
pub(crate) fn objects(objects: Vec<ObjectCandidate>) -> Vec<CompletionCandidate> {
    let mut out = Vec::new();
    let mut by_name = Vec::new();
    for o in objects {
        match o {
            ObjectCandidate::Described { addr, name, dtype, access, identifier } => {
                let kind = format!("{dtype} {}", access.name());
                out.push(candidate(addr.to_string(), format!("{name} ({kind})")));
                if let Some(id) = identifier {
                    by_name.push(candidate(id, format!("{addr} ({kind})")));
                }
            }
            ObjectCandidate::Answered(addr) => out.push(candidate(addr.to_string(), "answered before")),
        }
    }
    out.extend(by_name);
    out
}

pub(crate) fn types() -> Vec<CompletionCandidate> {
    ALL_TYPES.iter().map(|t| candidate(t.name(), format!("CiA 301 type 0x{:04X}", t.code()))).collect()
}

/// The CiA 305 bit timing table, reserved entries left out.
pub(crate) fn bit_rates() -> Vec<CompletionCandidate> {
    use crate::canopen::lss::{bit_rate_name, AUTO_BIT_RATE, BIT_TIMINGS};
    BIT_TIMINGS
        .iter()
        .filter(|(i, kbit)| kbit.is_some() || *i == AUTO_BIT_RATE)
        .map(|(i, _)| candidate(bit_rate_name(*i), format!("CiA 305 table index {i}")))
        .collect()
}
