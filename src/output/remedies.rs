//! What the user can do about a failure, in canctl's terms: the one place remedies name
//! canctl's flags and commands. A remedy is chosen here, by matching the library's typed
//! error (or the report that tells of it); the error's own message says what happened and
//! names no flag.

use crate::canopen::lss::FastscanError;
use crate::epos2::{Epos2Error, Epos2Problem};
use crate::error::{DriveStop, Error, LinkError, Service, Unfinished};

/// The remedy for `error`, to follow its message, if one fits.
pub(crate) fn error_remedy(error: &Error) -> Option<String> {
    let text = match error {
        Error::Advised { error, .. } => return error_remedy(error),
        Error::TpdoNotPutBack { node, .. } => restore_stored(*node),
        Error::NodeIdInUse { .. } => {
            "; choose a free id (canctl scan lists those in use), or --force gives it anyway".into()
        }
        Error::NoStoredEds { .. } => "; get the EDS from its vendor and give it with --eds".into(),
        Error::NoFreeNodeId { .. } => ": give a lower --start".into(),
        Error::OtherDevice { .. } => "; --force applies it anyway".into(),
        Error::NoAnswer { what: Service::AfterReset, .. } => {
            ". Check the node with `canctl scan`, or wait longer (--wait)".into()
        }
        Error::LssSetIdUnknown { identity, .. } | Error::LssStillConfiguring { identity, .. } => {
            format!(" (canctl lss inquire --identity {identity} shows its node-id)")
        }
        Error::DriveStopped { why: DriveStop::FaultPresent, .. } => {
            " (canctl drive fault-reset NODE clears it once its cause is gone)".into()
        }
        Error::DriveStopped { why: DriveStop::FaultRemains, .. } => {
            " (canctl drive status NODE shows the errors)".into()
        }
        Error::Fastscan { error: FastscanError::Unconfirmed(_), .. } => "; try again, or a longer --step".into(),
        Error::NotOfType { .. } => "; try another --type".into(),
        Error::NoSuchTpdo { .. } => "; without --tpdo, every TPDO it has is streamed".into(),
        Error::NoValidTpdo { .. } => " (--map makes one for the session)".into(),
        Error::InquiryAnsweredByMany { .. } => ": address one with --identity (lss fastscan finds them)".into(),
        Error::Link(LinkError::SimInUse { serving: Some(bus), .. }) => {
            format!(", or use --bus {bus}, where that process serves the devices")
        }
        Error::Link(LinkError::SimInUse { serving: None, .. }) => {
            ", or serve the network where several commands share it as on a real bus (`canctl sim --socketcan \
             vcan0`, then --bus vcan0); --bus sim:OTHER.state would be another network, not this one"
                .into()
        }
        Error::Link(LinkError::NoInterface { iface, available }) => set_up_interface(iface, available),
        Error::NoSocketCan { .. } => ", or try --bus sim".into(),
        Error::NothingAnswered { error } => match error.root() {
            Error::Link(LinkError::AdapterBusError { port, .. }) => adapter_bit_rate(port),
            e => return error_remedy(e),
        },
        Error::MapSizeUnread { .. } => {
            "; --map learns the size of an object the dictionary does not give by reading it once (--eds gives its \
             type)"
                .into()
        }
        Error::TypeNeeded { .. } => "; --type is needed (or --eds, a dictionary with an entry for it)".into(),
        Error::NoLssOnDirectEpos2 { .. } => "; set-id, set-baud and store work on it through its own objects, and \
                                             without --node LSS goes to the devices on the CAN bus behind it"
            .into(),
        Error::Epos2RateOnStore => ": use `lss store --node 0`".into(),
        Error::NoAnswer { what: Service::ProjectNode { lss: Some(id) }, .. } => {
            format!("; --assign gives it its node-id over LSS ({id})")
        }
        Error::NoAnswer { what: Service::ProjectNode { lss: None }, .. } => {
            " (its DCF names no LSS serial number, so --assign cannot find it)".into()
        }
        Error::Link(LinkError::Epos2(Epos2Error::Serial { failure, retry, .. }))
            if retry.as_ref().unwrap_or(failure).may_be_slow() =>
        {
            "; a slow device may need a longer --timeout".into()
        }
        Error::SdoUnfinished { why: Unfinished::Deadline { timeout, .. }, .. } => {
            format!("; the deadline follows from the size and --timeout {} ms", timeout.as_millis())
        }
        // The SDO client aborts with "out of memory" only at the upload limit.
        Error::Link(LinkError::SdoProtocol { aborted: Some(crate::canopen::abort::OUT_OF_MEMORY), .. })
        | Error::Link(LinkError::UploadOverLimit { .. }) => " (sdo read --max-size raises the limit)".into(),
        Error::LssCrowded { .. } => " (`canctl scan` lists the devices left in configuration state)".into(),
        Error::LssLeftInConfiguration { .. } => ": `canctl scan` lists it; power-cycle it if it stays there".into(),
        Error::DcfNotReadWhole { file, .. } => format!(" (canctl config check {file} lists them)"),
        Error::NotADcf { .. } => " (canctl config dump makes one)".into(),
        Error::Link(LinkError::Epos2(Epos2Error::Answer {
            problem: Epos2Problem::EmptySegments { node, .. }, ..
        })) => {
            format!(": reset the node (`canctl nmt reset {node}`) and read again")
        }
        Error::Link(LinkError::StateFile { afresh: true, .. }) => " (`canctl sim reset` starts afresh)".into(),
        _ => return None,
    };
    Some(text)
}

/// A flash that stayed busy past the wait: wait longer.
pub(crate) fn longer_busy_wait() -> String {
    ": give --busy-wait".into()
}

/// A node seen on the bus that answers no SDO, as a Stopped node does: put it in
/// Pre-operational, where it answers.
pub(crate) fn pre_operational(node: u8) -> String {
    format!(": a Stopped node answers no SDO (canctl nmt preop {node})")
}

/// The same, in parentheses after what could not be done with the node.
pub(crate) fn stopped_node_aside(node: u8) -> String {
    format!(" (a Stopped node answers no SDO: canctl nmt preop {node})")
}

/// A node that logged errors in its history (0x1003): read them, with their meanings.
pub(crate) fn read_error_history(node: u8) -> String {
    format!(" (canctl errors {node})")
}

/// Whether a reset node booted is not known: its NMT state says.
pub(crate) fn read_nmt_state(node: u8) -> String {
    format!(" (canctl nmt state {node} says)")
}

/// What a node was told to load applies from its next reset: reset it.
pub(crate) fn reset_node(node: u8) -> String {
    format!(" (canctl nmt reset {node} does it)")
}

/// A node's parameters were left changed: loading its stored ones (0x1011) puts them back.
fn restore_stored(node: u8) -> String {
    format!(": `canctl restore {node}` loads the stored parameters")
}

/// There is no network interface `iface`: the one of a near name (the demo network's or one
/// of the `available` CAN interfaces), how to set one up, or the demo network.
fn set_up_interface(iface: &str, available: &[String]) -> String {
    format!(
        "{} (CAN interfaces here: {}).\n  \
         A CAN adapter: plug it in, then sudo ip link set {iface} up type can bitrate 500000\n  \
         A virtual bus: sudo ip link add dev {iface} type vcan && sudo ip link set up {iface}\n  \
         No hardware: try the demo network, --bus sim",
        near_interface(iface, available).map(|c| format!("; did you mean --bus {c}?")).unwrap_or_default(),
        if available.is_empty() { "none".to_string() } else { available.join(", ") }
    )
}

/// The name one or two letters from `iface` (`sims`, `cna0`): `sim` or an interface that
/// exists, the nearest first.
fn near_interface(iface: &str, available: &[String]) -> Option<String> {
    std::iter::once("sim")
        .chain(available.iter().map(String::as_str))
        .map(|c| (crate::od::names::distance(iface, c), c))
        .filter(|(d, c)| *d <= 2 && *d < c.len())
        .min()
        .map(|(_, c)| c.to_string())
}

/// `; frames nobody acknowledges are what an adapter at another bit rate ...`, with the
/// address to give: a serial CAN adapter (`port`, its bus address) that sees frames nobody
/// acknowledges.
fn adapter_bit_rate(port: &str) -> String {
    // The address without its rate: `slcan:/dev/ttyACM0@250k` -> `slcan:/dev/ttyACM0`.
    let base = port.split_once('@').map_or(port, |(base, _)| base);
    let rates: Vec<String> = crate::slcan::wire::BIT_RATES.iter().map(|(_, k)| crate::connect::kbit_text(*k)).collect();
    format!(
        "; frames nobody acknowledges are what an adapter at another bit rate than the bus's sees: give the \
         bus's rate in the address, --bus {base}@RATE (RATE one of {}), or bus = \"{base}@RATE\" in canctl.toml",
        rates.join(" ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sim network held by another command: the remedy is to serve it where several share it.
    #[test]
    fn a_sim_network_in_use_is_answered_with_the_way_to_share_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sim.json");
        let _held = crate::sim::state::StateFile::lock_within(&path, std::time::Duration::ZERO).unwrap();
        let err = crate::sim::state::StateFile::lock_within(&path, std::time::Duration::from_millis(50)).err().unwrap();
        let remedy = error_remedy(&err).unwrap_or_default();
        assert!(remedy.contains("`canctl sim --socketcan vcan0`, then --bus vcan0"), "{err}{remedy}");
    }

    #[test]
    fn the_remedy_is_found_under_the_advice_added() {
        let e = Error::NoStoredEds { node: 5 };
        let remedy = error_remedy(&e);
        assert!(remedy.is_some());
        assert_eq!(error_remedy(&e.advised(crate::error::Advice::PortTaken)), remedy);
        assert_eq!(error_remedy(&Error::Interrupted), None);
        // The message itself names no flag: the front end adds that.
        assert!(!Error::NoStoredEds { node: 5 }.to_string().contains("--"));
    }

    /// A mistyped interface is answered with the nearest name that exists, `sim` included.
    #[test]
    fn a_mistyped_interface_is_answered_with_the_nearest_one() {
        let available = vec!["can0".to_string(), "vcan0".to_string()];
        assert_eq!(near_interface("cna0", &available).as_deref(), Some("can0"));
        assert_eq!(near_interface("sims", &available).as_deref(), Some("sim"));
        assert_eq!(near_interface("eth0", &available), None);
    }
}
