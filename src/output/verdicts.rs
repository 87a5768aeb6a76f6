//! What a check of `health` or `network check` found, in words: the one place their
//! verdicts' details are worded.

use crate::ops::verdict::{Finding, Logged, Verdict};

/// The verdict's finding in a sentence (without its remedy: see `hints::verdict_text`).
pub(crate) fn finding_text(verdict: &Verdict) -> String {
    match &verdict.detail {
        // health
        Finding::Gone { from } => format!("seen by the last scan, it answers nothing now: not the probe ({from})"),
        Finding::SilentToSdo { from } => {
            format!("answered none of the scan's probes in time, though the bus shows it is there ({from})")
        }
        Finding::StateUnknown { from } => format!("state unknown: {from}"),
        Finding::StateNotCheckable { from } => format!("not checkable here: {from}"),
        Finding::State { state, from } => format!("{state} (from {from})"),
        Finding::WrongState { state, from, want } => format!("{state} (from {from}), not {want}"),
        Finding::NoHeartbeatObject => "none (no 0x1017)".into(),
        Finding::HeartbeatOff => "not produced (0x1017 = 0)".into(),
        Finding::HeartbeatUnwatched { period_ms } => {
            format!("every {period_ms} ms (not watched: this link shows no traffic)")
        }
        Finding::HeartbeatMissing { period_ms, watched_ms } => {
            format!("0x1017 says every {period_ms} ms, but none came in {watched_ms} ms")
        }
        Finding::HeartbeatLate { period_ms, longest_gap_ms, beats, watched_ms } => {
            format!("every {period_ms} ms, but late: {longest_gap_ms} ms without one ({beats} in {watched_ms} ms)")
        }
        Finding::HeartbeatOnTime { period_ms, beats, watched_ms } => {
            format!("every {period_ms} ms, on time ({beats} in {watched_ms} ms)")
        }
        Finding::RegisterUnread { error } => format!("could not be read: {error}"),
        Finding::RegisterEmpty => "0x1001 answered with no data".into(),
        Finding::Register { register: 0, logged } => format!("0x00: no error{}", logged_text(logged)),
        Finding::Register { register, logged } => format!(
            "0x{register:02X}: {}{}",
            crate::canopen::emcy::register_bits(*register).join(", "),
            logged_text(logged)
        ),
        Finding::EmcyUnwatched => "not watched: this link shows no traffic".into(),
        Finding::NoEmcy { watched_ms } => format!("none in {watched_ms} ms"),
        Finding::Emcys { seen } => {
            super::text::joined(seen.iter().map(|e| format!("0x{:04X} {}", e.code, e.meaning)), "; ")
        }
        Finding::StatuswordUnread { error } => format!("statusword 0x6041 could not be read: {error}"),
        Finding::StatuswordShort => "statusword 0x6041 answered with too few bytes".into(),
        Finding::NoDriveState { statusword } => format!("statusword 0x{statusword:04X} codes no CiA 402 state"),
        Finding::Drive { state, statusword, warning } => {
            let warning = if *warning { ", warning" } else { "" };
            format!("{state} (statusword 0x{statusword:04X}{warning})")
        }
        Finding::NodeIdClash { clash } => clash.to_string(),

        // network check
        Finding::Answered { node } => format!("node {node} answered"),
        Finding::SilentListed { node, state, rounds, window_ms } => format!(
            "node {node} is there ({state}, by its heartbeat) but answered none of {rounds} SDO probes of \
             {window_ms} ms: nothing of it can be checked"
        ),
        Finding::Absent { node, rounds, window_ms } => {
            format!("node {node} did not answer any of {rounds} probes of {window_ms} ms")
        }
        Finding::IdentityMatches { parts } => {
            super::text::joined(parts.iter().map(|p| format!("{} {}", p.what, p.device_text())), ", ")
        }
        Finding::IdentityUnnamed { file } => format!("{file} names no vendor-ID or product code: not compared"),
        Finding::IdentityDiffers { differ, file } => {
            let differ = differ.iter().map(|p| format!("{} {}, 0x{:08X} in {file}", p.what, p.device_text(), p.file));
            format!("another device: {}", super::text::joined(differ, ", "))
        }
        Finding::ObjectsMatch { file } => format!("every writable object as in {file}"),
        Finding::ObjectsDiffer { file } => {
            let each = |d: &crate::ops::config::Difference| {
                format!("{} {}: {} on the node, {} in the file", d.object, d.name, d.device, d.file)
            };
            let list = super::text::joined(verdict.differences.iter().map(each), "; ");
            format!("{} object(s) differ from {file}: {list}", verdict.differences.len())
        }
        Finding::NetworkState { state, from, want } => format!("{state} (from its {from}), {want} expected"),
        Finding::NoNetworkState { want } => {
            format!("no heartbeat seen and no answer to node guarding; {want} expected")
        }
    }
}

/// The JSON of `checks` (an array, as they serialise), each `detail` worded by `text` in its
/// place (with its remedy).
pub(crate) fn word_details(json: &mut serde_json::Value, checks: &[Verdict], text: fn(&Verdict) -> String) {
    for (json, c) in json.as_array_mut().into_iter().flatten().zip(checks) {
        json["detail"] = text(c).into();
    }
}

/// What the error history says, to end the error register's sentence.
fn logged_text(logged: &Logged) -> String {
    match logged {
        Logged::Unsaid => String::new(),
        Logged::Nothing => "; no errors logged".into(),
        Logged::Count(k) => format!("; {k} error(s) logged in 0x1003"),
        Logged::NoHistory => "; no error history (0x1003)".into(),
        Logged::Unread(e) => format!("; 0x1003:0 could not be read: {e}"),
    }
}

/// `0x81 (generic, manufacturer)`, `0x00`, or `-` when unread.
pub(crate) fn register_text(register: Option<u8>) -> String {
    match register {
        None => "-".into(),
        Some(0) => "0x00".into(),
        Some(r) => format!("0x{r:02X} ({})", crate::canopen::emcy::register_bits(r).join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canopen::{abort, cia402, nmt, ObjAddr};
    use crate::ops::clash::{Clash, Evidence};
    use crate::ops::config::Difference;
    use crate::ops::health::SeenEmcy;
    use crate::ops::node::IdPart;
    use crate::ops::scan::StateFrom;

    fn text(f: Finding) -> String {
        finding_text(&Verdict::new("any", true, f))
    }

    /// Each finding reads as the sentence the library used to build for it.
    #[test]
    fn findings_read_as_the_library_worded_them() {
        let from = StateFrom::Heartbeat;
        let (pre, op) = (nmt::State::PreOperational, nmt::State::Operational);
        let e = crate::Error::SdoAbort { node: 5, obj: ObjAddr::new(0x1001, 0), code: abort::GENERAL_ERROR };
        let cases = [
            (
                Finding::SilentToSdo { from },
                "answered none of the scan's probes in time, though the bus shows it is there (heartbeat)".to_string(),
            ),
            (Finding::StateUnknown { from: StateFrom::NotAState }, format!("state unknown: {}", StateFrom::NotAState)),
            (Finding::State { state: pre, from }, "pre-operational (from heartbeat)".into()),
            (Finding::WrongState { state: pre, from, want: op }, "pre-operational (from heartbeat), not operational".into()),
            (Finding::NoHeartbeatObject, "none (no 0x1017)".into()),
            (Finding::HeartbeatOff, "not produced (0x1017 = 0)".into()),
            (Finding::HeartbeatUnwatched { period_ms: 40 }, "every 40 ms (not watched: this link shows no traffic)".into()),
            (
                Finding::HeartbeatMissing { period_ms: 40, watched_ms: 300 },
                "0x1017 says every 40 ms, but none came in 300 ms".into(),
            ),
            (
                Finding::HeartbeatLate { period_ms: 100, longest_gap_ms: 380, beats: 1, watched_ms: 400 },
                "every 100 ms, but late: 380 ms without one (1 in 400 ms)".into(),
            ),
            (
                Finding::HeartbeatOnTime { period_ms: 40, beats: 8, watched_ms: 300 },
                "every 40 ms, on time (8 in 300 ms)".into(),
            ),
            (Finding::RegisterUnread { error: (&e).into() }, format!("could not be read: {e}")),
            (Finding::RegisterEmpty, "0x1001 answered with no data".into()),
            (Finding::Register { register: 0, logged: Logged::Nothing }, "0x00: no error; no errors logged".into()),
            (Finding::Register { register: 0, logged: Logged::Unsaid }, "0x00: no error".into()),
            (
                Finding::Register { register: 0x81, logged: Logged::Count(2) },
                format!(
                    "0x81: {}; 2 error(s) logged in 0x1003",
                    crate::canopen::emcy::register_bits(0x81).join(", ")
                ),
            ),
            (
                Finding::Register { register: 0, logged: Logged::NoHistory },
                "0x00: no error; no error history (0x1003)".into(),
            ),
            (
                Finding::Register { register: 0, logged: Logged::Unread((&e).into()) },
                format!("0x00: no error; 0x1003:0 could not be read: {e}"),
            ),
            (Finding::EmcyUnwatched, "not watched: this link shows no traffic".into()),
            (Finding::NoEmcy { watched_ms: 300 }, "none in 300 ms".into()),
            (
                Finding::Emcys {
                    seen: vec![
                        SeenEmcy { code: 0x5000, register: 0x81, meaning: "Device hardware" },
                        SeenEmcy { code: 0, register: 0, meaning: "Error reset or no error" },
                    ],
                },
                "0x5000 Device hardware; 0x0000 Error reset or no error".into(),
            ),
            (Finding::StatuswordUnread { error: (&e).into() }, format!("statusword 0x6041 could not be read: {e}")),
            (Finding::StatuswordShort, "statusword 0x6041 answered with too few bytes".into()),
            (Finding::NoDriveState { statusword: 0x0001 }, "statusword 0x0001 codes no CiA 402 state".into()),
            (
                Finding::Drive { state: cia402::State::Fault, statusword: 0x0508, warning: false },
                format!("{} (statusword 0x0508)", cia402::State::Fault.name()),
            ),
            (
                Finding::Drive { state: cia402::State::Fault, statusword: 0x0588, warning: true },
                format!("{} (statusword 0x0588, warning)", cia402::State::Fault.name()),
            ),
            (Finding::Answered { node: 5 }, "node 5 answered".into()),
            (
                Finding::SilentListed { node: 5, state: nmt::State::Stopped, rounds: 3, window_ms: 100 },
                "node 5 is there (stopped, by its heartbeat) but answered none of 3 SDO probes of 100 ms: nothing of it \
                 can be checked"
                    .into(),
            ),
            (
                Finding::Absent { node: 7, rounds: 3, window_ms: 100 },
                "node 7 did not answer any of 3 probes of 100 ms".into(),
            ),
            (
                Finding::IdentityUnnamed { file: "node5.dcf".into() },
                "node5.dcf names no vendor-ID or product code: not compared".into(),
            ),
            (Finding::ObjectsMatch { file: "node5.dcf".into() }, "every writable object as in node5.dcf".into()),
            (
                Finding::NetworkState { state: pre, from: StateFrom::NodeGuarding, want: op },
                "pre-operational (from its node guarding), operational expected".into(),
            ),
            (
                Finding::NoNetworkState { want: op },
                "no heartbeat seen and no answer to node guarding; operational expected".into(),
            ),
        ];
        for (finding, said) in cases {
            assert_eq!(text(finding), said);
        }

        let clash = Clash { node: 5, evidence: Evidence::HeartbeatStates { states: vec![pre, op] } };
        assert_eq!(text(Finding::NodeIdClash { clash: clash.clone() }), clash.to_string());

        let vendor = crate::ops::node::IdentityPart { what: IdPart::Vendor, file: 0xC0, device: Ok(0xC0) };
        let product =
            crate::ops::node::IdentityPart { what: IdPart::Product, file: 0x10, device: Err(abort::NO_OBJECT) };
        assert_eq!(text(Finding::IdentityMatches { parts: vec![vendor] }), "vendor-ID 0x000000C0");
        assert_eq!(
            text(Finding::IdentityDiffers { differ: vec![product], file: "node5.dcf".into() }),
            format!(
                "another device: product code unreadable ({}), 0x00000010 in node5.dcf",
                abort::meaning(abort::NO_OBJECT)
            )
        );

        let difference = |sub| Difference {
            object: ObjAddr::new(0x2000, sub),
            name: "Gain".into(),
            device: "3".into(),
            file: "4".into(),
        };
        let objects = Verdict {
            differences: vec![difference(1), difference(2)],
            ..Verdict::new("objects", false, Finding::ObjectsDiffer { file: "node5.dcf".into() })
        };
        assert_eq!(
            finding_text(&objects),
            format!(
                "2 object(s) differ from node5.dcf: {} Gain: 3 on the node, 4 in the file; {} Gain: 3 on the node, 4 in \
                 the file",
                ObjAddr::new(0x2000, 1),
                ObjAddr::new(0x2000, 2)
            )
        );
    }
}
