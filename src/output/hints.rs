//! The command line's words around the library's errors: an error with its remedy
//! ([`super::remedies`]), what the front end learnt about a silent node, and the texts that
//! say how to name a bus or follow a switch of bit rate.

use super::remedies;

/// A check's detail as canctl says it: what was found, then the remedy in canctl's terms.
pub(crate) fn verdict_text(verdict: &crate::ops::verdict::Verdict) -> String {
    use crate::ops::verdict::Remedy;
    let found = super::verdicts::finding_text(verdict);
    match verdict.remedy {
        Some(Remedy::PreOperational { node }) => found + &remedies::pre_operational(node),
        Some(Remedy::ReadErrorHistory { node }) => found + &remedies::read_error_history(node),
        None => found,
    }
}

/// A library error as canctl says it: its message, then its remedy in canctl's terms.
pub fn library_error_text(err: &crate::Error) -> String {
    match err {
        // The remedy belongs to the error, before the advice added to it.
        crate::Error::Advised { error, advice } => format!("{}{advice}", library_error_text(error)),
        // The failed write's remedy in its place, before what was left; the way back ends it.
        crate::Error::TpdoNotPutBack { node, tpdo, error } => format!(
            "{}{}{}",
            library_error_text(error),
            crate::error::tpdo_left(*node, *tpdo),
            remedies::error_remedy(err).unwrap_or_default()
        ),
        e => format!("{e}{}", remedies::error_remedy(e).unwrap_or_default()),
    }
}

/// A library error with what the front end learnt about it (`explained`): the nodes the last
/// scan saw and, when the quick checks found one, the likely cause of a node's silence
/// (`--format json` gives that finding as the error's `diagnosis`). It ends the process as
/// `error` does; canctl prints `error` with its remedy, then `advice`.
#[derive(Debug)]
pub struct Explained {
    /// The library's error.
    pub(crate) error: crate::Error,
    /// What was learnt, in words, to follow the error's remedy.
    pub(crate) advice: String,
    /// The likely cause the quick checks found, if they found one.
    pub(crate) finding: Option<crate::ops::doctor::Finding>,
}

impl std::fmt::Display for Explained {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}{}", self.error, self.advice)
    }
}

// Not the error as its source: the message would read twice in `{:#}`.
impl std::error::Error for Explained {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        std::error::Error::source(&self.error)
    }
}

/// What to add to a message about a silent node: the nodes the last scan of `bus` saw
/// (`seen`), or the command that lists them.
pub fn last_scan_hint(bus: &str, seen: &[crate::ops::scan_cache::SeenNode]) -> String {
    if seen.is_empty() {
        return format!("; `canctl scan` lists the nodes on {bus}");
    }
    format!("; nodes seen on the last scan of {bus}: {}", super::text::joined(seen.iter().map(|n| n.node), ", "))
}

/// What the user must do to bring a link that does not follow an LSS switch to `index`.
pub fn switch_hint(uri: Option<&str>, index: u8) -> String {
    let name = crate::canopen::lss::bit_rate_name(index);
    let bps = crate::canopen::lss::BIT_TIMINGS[index as usize].1.unwrap_or(0) * 1000;
    match uri.and_then(|u| u.parse::<crate::connect::BusAddr>().ok()) {
        Some(crate::connect::BusAddr::SocketCan { iface }) => format!(
            "switch {iface} to the new rate: sudo ip link set {iface} down && sudo ip link set {iface} up type can \
             bitrate {bps}"
        ),
        Some(crate::connect::BusAddr::Epos2 { .. }) => format!(
            "the EPOS2 keeps its own CAN rate: `canctl lss set-baud {name} --node 0`, `canctl lss store --node 0`, then \
             power it off and on"
        ),
        Some(crate::connect::BusAddr::Slcan { port, .. }) => {
            format!("reopen the adapter at the new rate: --bus slcan:{port}@{name}")
        }
        _ => format!("switch the CAN interface to {name}"),
    }
}

/// A failure a report row tells of, as canctl says it: the error with its remedy.
pub(crate) fn failure_text(failure: &crate::ops::failure::Failure) -> String {
    library_error_text(&failure.error)
}

/// What happened to one object of a `config apply`, as canctl says it: a failed write
/// with its remedy.
pub(crate) fn change_result_text(outcome: &crate::ops::config::Outcome) -> String {
    outcome.text(failure_text)
}

/// A report's JSON `changes`, each `result` as canctl says it ([`change_result_text`]).
pub(crate) fn word_change_results(value: &mut serde_json::Value, changes: &[crate::ops::config::Change]) {
    for (k, c) in changes.iter().enumerate() {
        if matches!(c.result.action, crate::ops::config::Action::Failed(_)) {
            value[k]["result"] = change_result_text(&c.result).into();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::CommandError;

    /// What the user reads is what canctl printed before the remedy was typed.
    #[test]
    fn the_remedy_follows_the_message_naming_the_flag() {
        let e = CommandError::from(crate::Error::NoStoredEds { node: 5 });
        assert_eq!(
            e.text(),
            "node 5: the device does not store its EDS (0x1021); get the EDS from its vendor and give it with --eds"
        );
        let e = CommandError::from(crate::Error::NodeIdInUse { node: 7, identity: None, by: "its heartbeat" });
        assert!(e.text().ends_with(
            "Nothing was sent; choose a free id (canctl scan lists those in use), or --force gives it anyway"
        ));
        let e = CommandError::from(crate::Error::Interrupted);
        assert_eq!(e.text(), e.to_string());
    }

    /// The errors whose remedy became typed read as they did when the library named the
    /// flag itself (the type's and the EPOS2's reworded only to keep the flag out of the
    /// message: the same facts, the same remedy).
    #[test]
    fn remedies_made_typed_read_as_before() {
        use crate::canopen::ObjAddr;
        let cases: Vec<(crate::Error, &str)> = vec![
            (
                crate::Error::NoSocketCan { bus: "socketcan:can0".into() },
                "socketcan:can0: SocketCAN is Linux's; on this OS reach the bus through a serial-line adapter \
                 (slcan:PORT, e.g. slcan:COM5 or slcan:/dev/tty.usbmodem1101) or an EPOS2 (epos2-usb:PORT), or try \
                 --bus sim",
            ),
            (
                crate::Error::MapSizeUnread {
                    obj: ObjAddr::new(0x5FF0, 15),
                    error: Box::new(crate::Error::SdoAbort { node: 1, obj: ObjAddr::new(0x5FF0, 15), code: 0x0601_0001 }),
                },
                "node 1: SDO abort 0x06010001 on 0x5FF0:15: Attempt to read a write only object; --map learns the \
                 size of an object the dictionary does not give by reading it once (--eds gives its type)",
            ),
            (
                crate::Error::TypeNeeded { value: "12".into(), object: ObjAddr::new(0x5FF0, 3) },
                "no data type to encode '12' for 0x5FF0:3 (no dictionary entry): one of b u8 u16 u24 u32 u40 u48 \
                 u56 u64 i8 i16 i24 i32 i40 i48 i56 i64 r32 r64 t td vs us os d; --type is needed (or --eds, a \
                 dictionary with an entry for it)",
            ),
            (
                crate::Error::NoLssOnDirectEpos2 { verb: "inquire".into() },
                "an EPOS2 reached directly (node 0) has no LSS, so `lss inquire` cannot be done on it; set-id, \
                 set-baud and store work on it through its own objects, and without --node LSS goes to the devices \
                 on the CAN bus behind it",
            ),
            (
                crate::Error::Epos2RateOnStore,
                "an EPOS2 reached directly takes its new bit rate when it is stored and reset: use `lss store --node 0`",
            ),
        ];
        for (error, text) in cases {
            assert_eq!(library_error_text(&error), text);
            assert!(!error.to_string().contains("--"), "the remedy is canctl's to word: {error}");
        }
    }

    /// The bit-rate remedy follows the adapter's bus errors where nothing answered a wait
    /// (`ops::unheard`), not any failure that names them.
    #[test]
    fn the_bit_rate_remedy_gives_the_address_without_its_rate() {
        let bus_error = crate::Error::from(crate::error::LinkError::AdapterBusError {
            port: "slcan:/dev/ttyACM0@250k".into(),
            flags: vec!["bus error"],
        });
        assert_eq!(library_error_text(&bus_error), bus_error.to_string());
        let e = crate::Error::NothingAnswered { error: Box::new(bus_error) };
        assert!(e.root().class() == crate::error::ErrorClass::Link && e.class() == crate::error::ErrorClass::Link);
        let text = library_error_text(&e);
        assert!(text.starts_with(&e.to_string()), "{text}");
        assert!(text.contains("--bus slcan:/dev/ttyACM0@RATE"), "{text}");
        assert!(text.contains("bus = \"slcan:/dev/ttyACM0@RATE\" in canctl.toml"), "{text}");
        assert!(text.contains(" 500k ") && text.contains(" 1M"), "{text}");
    }

    /// A failure kept in a report row (`network apply`'s node, `config apply`'s object)
    /// reads as the error itself does, remedy and added advice in their places.
    #[test]
    fn a_failure_kept_in_a_row_reads_as_the_error() {
        use crate::canopen::lss::Identity;
        use crate::error::Service;
        use crate::ops::config::{Action, Outcome};
        use crate::ops::failure::Failure;
        let id = Identity { vendor: 1, product: 2, revision: 3, serial: 4 };
        let absent = |lss| crate::Error::NoAnswer {
            node: 5,
            what: Service::ProjectNode { lss },
            waited: std::time::Duration::from_millis(100),
        };
        assert_eq!(
            library_error_text(&absent(Some(id))),
            format!("node 5 did not answer; --assign gives it its node-id over LSS ({id})")
        );
        assert_eq!(
            library_error_text(&absent(None)),
            "node 5 did not answer (its DCF names no LSS serial number, so --assign cannot find it)"
        );
        for e in [
            absent(Some(id)),
            absent(None).advised(crate::error::Advice::Near(vec!["0x1017:0".into()])),
            crate::Error::Interrupted,
        ] {
            let f = Failure::from(&e);
            assert_eq!(f.to_string(), e.to_string());
            assert_eq!(failure_text(&f), library_error_text(&e));
            let outcome = Outcome { action: Action::Failed(f), interim: None, rollback: true, read_back: None };
            assert_eq!(change_result_text(&outcome), format!("failed: {} (rollback)", library_error_text(&e)));
        }
    }

    /// Report texts whose command became a typed remedy (a check's, a stop's, a reset's, a
    /// TPDO left changed) read as when the library named the command itself.
    #[test]
    fn report_remedies_made_typed_read_as_before() {
        use crate::ops::verdict::{Finding, Logged, Remedy, Verdict};
        let from = crate::ops::scan::StateFrom::Heartbeat;
        let sdo = Verdict::new("sdo", false, Finding::SilentToSdo { from })
            .with_remedy(Some(Remedy::PreOperational { node: 5 }));
        assert_eq!(
            verdict_text(&sdo),
            "answered none of the scan's probes in time, though the bus shows it is there (heartbeat): a Stopped \
             node answers no SDO (canctl nmt preop 5)"
        );
        let register =
            Verdict::new("error register", true, Finding::Register { register: 0, logged: Logged::Count(2) })
                .with_remedy(Some(Remedy::ReadErrorHistory { node: 7 }));
        assert_eq!(verdict_text(&register), "0x00: no error; 2 error(s) logged in 0x1003 (canctl errors 7)");
        let operational = Finding::State { state: crate::canopen::nmt::State::Operational, from };
        assert_eq!(verdict_text(&Verdict::new("nmt", true, operational)), "operational (from heartbeat)");

        // The write's own remedy in its place, then what was left, then the way back.
        let write = || crate::Error::NoAnswer {
            node: 1,
            what: crate::error::Service::AfterReset,
            waited: std::time::Duration::from_millis(100),
        };
        let left = "; node 1's TPDO2 was not put back as it was (0x1801:1 may leave it switched off)";
        let hinted = format!("{}{left}", library_error_text(&write()));
        assert!(hinted.contains("(--wait)"), "{hinted}");
        let before = format!("{hinted}: `canctl restore 1` loads the stored parameters");
        let e = crate::Error::TpdoNotPutBack { node: 1, tpdo: 2, error: Box::new(write()) };
        assert_eq!(e.to_string(), format!("{}{left}", e.root()));
        assert!(!e.to_string().contains("canctl"), "{e}");
        assert_eq!(library_error_text(&e), before);
        assert_eq!(CommandError::from(e).text(), before);
    }
}
