//! How `doctor`'s diagnosis looks: each finding, most likely first, with its evidence and
//! the fix, in words that name canctl's commands; and what was found fine.

use super::junit::{TestCase, TestSuite};
use super::report::{Human, Report};
use super::text::joined;
use crate::bus::controller::CanState;
use crate::canopen::sdo::{request_cob, response_cob};
use crate::ops::clash;
use crate::ops::doctor::{Cause, ControllerState, Diagnosis, Evidence, Finding, HostProblem, Remedy};

/// What doctor is doing while it works, for the line that moves meanwhile.
pub(crate) fn working(node: Option<u8>) -> String {
    node.map_or("doctor: looking at the bus".to_string(), |node| format!("doctor: looking at node {node}"))
}

/// What is wrong, in a sentence.
pub(crate) fn cause_text(cause: &Cause) -> String {
    match cause {
        Cause::Host { problem } => format!("the host: {}", host_text(*problem)),
        Cause::Controller { state: ControllerState::BusOff } => {
            "the CAN controller went bus-off: its frames were not acknowledged or were destroyed on the bus".into()
        }
        Cause::Controller { state: ControllerState::BusErrors } => {
            "the CAN controller reports bus errors: nothing acknowledges its frames, or the bus runs at another bit rate"
                .into()
        }
        Cause::BusSilent => "nothing on the bus: no frame heard, and no node answered a read".into(),
        Cause::NoAnswers => "frames are heard, but no node answered a read on any node-id: the devices serve no SDO \
             there (stopped, or on other COB-IDs)"
            .into(),
        Cause::Flood { cob_id } => format!(
            "a device floods the bus with 0x{cob_id:03X}: sent without pause, it wins every arbitration and no node \
             gets a frame through"
        ),
        Cause::NodeIdClash { node } => format!("node-id {node} is used by more than one device"),
        Cause::Stopped { node } => format!("node {node} is alive but stopped: a stopped node serves no SDO"),
        Cause::SdoSilent { node } => format!(
            "node {node} is alive but its SDO server does not answer on 0x{:03X}/0x{:03X} (its 0x1200 changed, or the server is off)",
            request_cob(*node),
            response_cob(*node)
        ),
        Cause::Moved { node, now } => format!("the device the last scan saw as node {node} answers as node {now} now"),
        Cause::SilentOrStopped { node } => format!(
            "node {node} answers nothing while the bus is not: stopped (this link cannot ask node guarding to tell), \
             or not powered, not connected, or on another node-id"
        ),
        Cause::NodeSilent { node } => {
            format!("node {node} is silent while the bus is not: not powered, not connected, or on another node-id")
        }
        Cause::Epos2CanErrors { register } => format!(
            "the EPOS2 gateway reports CAN errors (its error register 0x{register:02X}: {}): its side of the bus sees \
             overruns, error passive or bus-off (canctl errors 0 names them)",
            crate::canopen::emcy::register_bits(*register).join(", ")
        ),
        Cause::LssUnconfigured { count } => format!(
            "{count} device(s) wait in LSS configuration without a node-id: they answer no SDO and send no heartbeat"
        ),
        Cause::NothingAcknowledges => "nothing acknowledges the frames sent (only ACK errors): no other device is \
             powered, or the bus is not terminated"
            .into(),
        Cause::SignalErrors => "frames are destroyed on the bus (bit, stuff or form errors): a device at another bit \
             rate, or the wiring"
            .into(),
        Cause::OtherBitRate { kbit } => {
            format!("the bus runs at {kbit} kbit/s, not at the link's rate: its traffic decodes cleanly only there")
        }
    }
}

fn host_text(problem: HostProblem) -> &'static str {
    match problem {
        HostProblem::InterfaceDown => "the CAN interface is down",
        HostProblem::NoInterface => "there is no such CAN interface or serial port",
        HostProblem::NoPermission => "this user may not open the link",
        HostProblem::CannotOpen => "the link cannot be opened",
        HostProblem::TransmitQueueFull => "the transmit queue is full (ENOBUFS): frames wait and are not sent",
        HostProblem::AdapterNotAnswering => "the adapter or gateway does not answer as it should",
        HostProblem::LinkFailed => "the link failed",
    }
}

/// What to do, in a sentence naming the commands.
pub(crate) fn remedy_text(remedy: &Remedy) -> String {
    match remedy {
        Remedy::FixHost { problem } => match problem {
            HostProblem::InterfaceDown => {
                "bring the interface up at the bus's bit rate: sudo ip link set IFACE up type can bitrate 500000".into()
            }
            HostProblem::NoInterface => "check the name: ip link lists the CAN interfaces; --bus sim needs none".into(),
            HostProblem::NoPermission => {
                "give this user the rights the link needs (the dialout group for a serial port)".into()
            }
            HostProblem::TransmitQueueFull => "frames pile up when no node acknowledges them (see the bus), or the \
                 queue is too short for a burst: sudo ip link set IFACE txqueuelen 1000"
                .into(),
            HostProblem::AdapterNotAnswering => {
                "check that the adapter is the one named (slcan, EPOS2), that no other program uses it; replug it"
                    .into()
            }
            HostProblem::LinkFailed | HostProblem::CannotOpen => "the link's message above says what failed".into(),
        },
        Remedy::CheckBus => "check that another device is powered, that the bus is terminated (120 Ω at each end: \
             about 60 Ω between CAN_H and CAN_L, power off), the wiring (CAN_H, CAN_L, GND) and that every device runs \
             at the bus's bit rate"
            .into(),
        Remedy::WatchBus => "canctl monitor shows who sends what; a stopped node answers again after canctl nmt \
             preop NODE"
            .into(),
        Remedy::FindFlooder { cob_id } => format!(
            "find the device sending 0x{cob_id:03X} (canctl monitor shows it; an EMCY id 0x081-0x0FF names its node) \
             and power it off; then canctl doctor again"
        ),
        Remedy::PreOperational { node } => {
            format!("canctl nmt preop {node} (SDO works there; canctl nmt start {node} runs it again afterwards)")
        }
        Remedy::ResetCommunication { node } => format!(
            "canctl nmt reset-comm {node} brings back the default SDO COB-IDs unless they were stored; else use the \
             COB-IDs its 0x1200 has (its DCF says them)"
        ),
        Remedy::UseNewId { node, now, identity } => format!(
            "address it as node {now} (canctl scan refreshes what the last scan saw), or give it back its node-id: \
             canctl lss set-id {node} --identity {}",
            identity.lss().map_or("VENDOR:PRODUCT:REVISION:SERIAL".to_string(), |i| i.to_string())
        ),
        Remedy::SeparateIds { node } => format!(
            "give one of the devices on node-id {node} another one: canctl lss set-id NEW --identity \
             VENDOR:PRODUCT:REVISION:SERIAL"
        ),
        Remedy::LssAssign => "canctl lss assign --start ID numbers them (or canctl lss fastscan, then canctl lss \
             set-id ID --identity ... for one)"
            .into(),
        Remedy::CheckBusOrLss => format!(
            "{}; a device waiting without a node-id (LSS) answers none of this: canctl doctor --lss asks for one \
             (an LSS broadcast)",
            remedy_text(&Remedy::CheckBus)
        ),
        Remedy::CheckNodeOrLss { node } => format!(
            "{}; canctl doctor --lss finds such a device (an LSS broadcast)",
            remedy_text(&Remedy::CheckNode { node: *node })
        ),
        Remedy::CheckNode { node } => format!(
            "check that node {node} is powered and connected, and the node-id it has: canctl scan lists the ids that \
             answer; a device without one waits for canctl lss assign"
        ),
        Remedy::AutoRestart { iface } => format!(
            "{iface} stays bus-off until restarted: once the cause is fixed, sudo ip link set {iface} type can \
             restart-ms 100 (it then comes back by itself; sudo ip link set {iface} type can restart restarts it once)"
        ),
        Remedy::CheckTermination => "power another CANopen device on the bus (a lone controller gets no \
             acknowledgement), and terminate the bus: 120 Ω at each end, about 60 Ω between CAN_H and CAN_L with the \
             power off"
            .into(),
        Remedy::CheckBitRate { bitrate } => format!(
            "check that every device runs at the interface's bit rate{} (ip -details link show IFACE says it; sudo ip \
             link set IFACE down; sudo ip link set IFACE up type can bitrate RATE changes it), then the wiring: CAN_H \
             and CAN_L not swapped, GND connected (an slcan adapter finds the bus's rate: canctl doctor --sweep)",
            bitrate.map(|b| format!(", {} kbit/s", b / 1000)).unwrap_or_default()
        ),
        Remedy::CheckBusOrSweep { kbit } => format!(
            "the adapter runs at {kbit}k: canctl doctor --sweep finds the bus's rate (it tries each, a few \
             seconds off the bus); else {}",
            remedy_text(&Remedy::CheckBus)
        ),
        Remedy::UseBitRate { kbit } => format!(
            "open the link at {kbit} kbit/s (--bus slcan:PORT@{kbit}k); or, if the bus should run at the link's \
             rate, find the device set to {kbit} kbit/s"
        ),
    }
}

/// `; likely cause: ...; fix: ...`: the finding of the quick checks as it follows the
/// message of a node that did not answer.
pub(crate) fn likely_cause_text(f: &Finding) -> String {
    format!("; likely cause: {}; fix: {}", cause_text(&f.cause), remedy_text(&f.remedy))
}

/// A finding as JSON: its typed cause, evidence and remedy, and `summary` and `fix` in words.
pub(crate) fn finding_json(f: &Finding) -> serde_json::Value {
    let mut json = serde_json::to_value(f).expect("findings serialise");
    json["summary"] = cause_text(&f.cause).into();
    json["fix"] = remedy_text(&f.remedy).into();
    json
}

/// What a piece of evidence checked, by the name JSON gives its kind (`one_device`,
/// `link_quiet`): a passing check's name in JUnit.
fn evidence_kind(e: &Evidence) -> String {
    let json = serde_json::to_value(e).expect("reports serialise");
    json["kind"].as_str().unwrap_or("check").to_string()
}

/// What was seen, in a sentence.
pub(crate) fn evidence_text(e: &Evidence) -> String {
    match e {
        Evidence::Traffic { frames } => {
            const SHOWN: usize = 8;
            let total: usize = frames.iter().map(|f| f.count).sum();
            let mut list: Vec<String> =
                frames.iter().take(SHOWN).map(|f| format!("0x{:03X} ×{}", f.cob_id, f.count)).collect();
            if frames.len() > SHOWN {
                list.push(format!("{} more id(s)", frames.len() - SHOWN));
            }
            format!("{total} frame(s) heard: {}", list.join(", "))
        }
        Evidence::NothingHeard { listened_ms } => format!("no frame heard in {listened_ms} ms"),
        Evidence::Heartbeats { node, count, state } => {
            format!(
                "{count} heartbeat(s) of node {node} on 0x{:03X}, the last saying {state}",
                0x700 + u16::from(*node)
            )
        }
        Evidence::Guarding { node, state } => format!("node {node} answered node guarding: {state}"),
        Evidence::NoGuardingAnswer { node, waited_ms } => {
            format!("no answer to node guarding of node {node} (0x{:03X}, {waited_ms} ms)", 0x700 + u16::from(*node))
        }
        Evidence::SdoAnswer { node, obj, value: Some(v) } => {
            format!("node {node} answered the SDO read of {obj}: 0x{v:08X}")
        }
        Evidence::SdoAnswer { node, obj, value: None } => {
            format!("node {node} answered the SDO read of {obj} (with an abort)")
        }
        Evidence::GuardingNotAState { node } => format!("node {node} answered node guarding, but with no NMT state"),
        Evidence::GuardingUnavailable { node } => {
            format!("node guarding of node {node} cannot be asked: this link carries no remote (RTR) frames")
        }
        Evidence::SdoAnswerUnread { node, obj } => {
            format!("node {node} answered the SDO read of {obj} (its value follows in segments, not read here)")
        }
        Evidence::NoSdoAnswer { node, obj, requests, waited_ms } => format!(
            "no answer on 0x{:03X} to {requests} SDO read(s) of {obj} sent on 0x{:03X} ({waited_ms} ms in all)",
            response_cob(*node),
            request_cob(*node)
        ),
        Evidence::SdoAnswerOn { node, cob_id } => {
            format!("an answer to that read came on 0x{cob_id:03X}, not on 0x{:03X}", response_cob(*node))
        }
        Evidence::ProbeAnswers { nodes, waited_ms } if nodes.is_empty() => {
            format!("no node answered a read of 0x1000 sent to every node-id ({waited_ms} ms)")
        }
        Evidence::ProbeAnswers { nodes, waited_ms } => {
            format!(
                "a read of 0x1000 sent to every node-id was answered by node(s) {} ({waited_ms} ms)",
                joined(nodes, ", ")
            )
        }
        Evidence::LastScanNodeAnswers { node, waited_ms } => {
            format!("node {node}, seen by the last scan, answered a read of 0x1000 ({waited_ms} ms)")
        }
        Evidence::NodesHeard { nodes } => {
            format!("the bus showed node(s) {} in use during this command", joined(nodes, ", "))
        }
        Evidence::LastScan { node, vendor_id, name } => format!(
            "the last scan saw node {node}: vendor-ID {}{}",
            vendor_id.map_or("-".into(), |v| format!("0x{v:08X}")),
            name.as_ref().map(|n| format!(", \"{n}\"")).unwrap_or_default()
        ),
        Evidence::Identity { node, identity, name } => format!(
            "node {node}, not on the last scan, answers vendor-ID 0x{:08X}{}{}",
            identity.vendor,
            identity.serial.map(|s| format!(", serial number 0x{s:08X}")).unwrap_or_default(),
            name.as_ref().map(|n| format!(", \"{n}\"")).unwrap_or_default()
        ),
        Evidence::Clash { shown_by } => match shown_by {
            clash::Evidence::SdoAnswers { values } => {
                let each = values.iter().map(|v| v.map_or("an abort".into(), |s| format!("0x{s:08X}")));
                format!("one read of 0x1018:4 got {} answers ({})", values.len(), joined(each, ", "))
            }
            clash::Evidence::HeartbeatStates { states } => {
                format!("its heartbeats said {} in one listen", joined(states.iter().map(|s| s.name()), " and "))
            }
            clash::Evidence::IdentityChanged { values } => {
                format!("0x1018:4 read {} in turn", joined(values.iter().map(|v| format!("0x{v:08X}")), ", "))
            }
        },
        Evidence::LinkReported { message } => format!("the link reported: {message}"),
        Evidence::OneDevice { node } => format!("one device on node-id {node}: no second answer, one serial number"),
        Evidence::LinkQuiet => "the link reported no bus errors".into(),
        Evidence::Epos2Gateway { error_register, bit_rate_code } => format!(
            "the EPOS2 gateway: error register {}, CAN bit rate {}",
            super::verdicts::register_text(*error_register),
            match bit_rate_code {
                None => "unread".to_string(),
                Some(crate::epos2::objects::BIT_RATE_DETECTED) => "detected from the bus (0x2001 = 9)".to_string(),
                Some(code) => match crate::epos2::objects::bit_rate_index(*code) {
                    Some(i) => format!("{} (0x2001 = {code})", crate::canopen::lss::bit_rate_name(i)),
                    None => format!("code {code} (0x2001), not one of its rates"),
                },
            }
        ),
        Evidence::FramesReceived { count } => format!("{count} frame(s) received while the command ran"),
        Evidence::LssAnswers { count: 0, waited_ms } => {
            format!("no device without a node-id answered LSS identify non-configured ({waited_ms} ms)")
        }
        Evidence::LssAnswers { count, waited_ms } => {
            format!("{count} device(s) without a node-id answered LSS identify non-configured ({waited_ms} ms)")
        }
        Evidence::ScanState { node, state, from } => format!("the scan saw node {node} {state} (from {from})"),
        Evidence::ControllerReport { iface, state, tx_errors, rx_errors, restart_ms, bitrate } => {
            let or_unknown = |v: Option<String>| v.unwrap_or_else(|| "not said".into());
            format!(
                "{iface}'s controller: {}, tx errors {}, rx errors {}, restart-ms {}, bit rate {}",
                or_unknown(state.map(can_state_text)),
                or_unknown(tx_errors.map(|n| n.to_string())),
                or_unknown(rx_errors.map(|n| n.to_string())),
                match restart_ms {
                    Some(0) => "0 (no automatic restart after bus-off)".into(),
                    other => or_unknown(other.map(|ms| ms.to_string())),
                },
                or_unknown(bitrate.map(|b| b.to_string())),
            )
        }
        Evidence::NoController { iface } => {
            format!("{iface} is a virtual interface: no controller, so no controller state or error counters")
        }
        Evidence::ErrorFrames { iface, counts: c } => {
            let counts = [
                (c.ack, "ACK"),
                (c.bit, "bit"),
                (c.stuff, "stuff"),
                (c.form, "form"),
                (c.warning, "warning-level"),
                (c.passive, "error-passive"),
                (c.bus_off, "bus-off"),
                (c.restarted, "restarted"),
            ];
            let parts = joined(counts.iter().filter(|(n, _)| *n > 0).map(|(n, what)| format!("{n} {what}")), ", ");
            let counters = c.counters.map(|(tx, rx)| format!("; last counters tx {tx}, rx {rx}")).unwrap_or_default();
            format!("{} error frame(s) from {iface}: {parts}{counters}", c.frames)
        }
        Evidence::Sweep { trials } => {
            let each = trials.iter().map(|t| match (t.frames, t.errors) {
                (n, false) if n > 0 => format!("{}k: {n} frame(s), clean", t.kbit),
                (n, true) => format!("{}k: {n} frame(s), bus errors", t.kbit),
                _ => format!("{}k: nothing", t.kbit),
            });
            format!("listen-only at each rate: {}", joined(each, "; "))
        }
        Evidence::NoSweep { bus } => format!(
            "{bus} cannot change its bit rate for a sweep; for a CAN interface try each rate by hand, listen-only: \
             sudo ip link set IFACE down; sudo ip link set IFACE up type can bitrate RATE listen-only on; canctl \
             monitor"
        ),
        Evidence::QueueFull { iface, frames } => format!(
            "{frames} frame(s) found {iface}'s transmit queue full (ENOBUFS) and waited for room; ip -details link \
             show {iface} says its qlen"
        ),
    }
}

fn can_state_text(s: CanState) -> String {
    match s {
        CanState::ErrorActive => "error-active",
        CanState::ErrorWarning => "error-warning",
        CanState::ErrorPassive => "error-passive",
        CanState::BusOff => "bus-off",
        CanState::Stopped => "stopped",
        CanState::Sleeping => "sleeping",
    }
    .into()
}

fn heading(d: &Diagnosis) -> String {
    let what = d.node.map_or_else(|| d.bus.clone(), |n| format!("{}, node {n}", d.bus));
    match d.findings.len() {
        0 => format!("{what}: nothing wrong found"),
        n => format!("{what}: {n} problem(s) found, most likely cause first"),
    }
}

fn finding_lines(i: usize, f: &Finding) -> Vec<Human> {
    let mut lines = vec![Human::Line(format!("{}. {}", i + 1, cause_text(&f.cause)))];
    lines.extend(f.evidence.iter().map(|e| Human::Line(format!("   seen: {}", evidence_text(e)))));
    lines.push(Human::Line(format!("   fix:  {}", remedy_text(&f.remedy))));
    lines
}

impl Report for Diagnosis {
    fn human(&self) -> Human {
        let mut parts = vec![Human::Line(heading(self))];
        for (i, f) in self.findings.iter().enumerate() {
            parts.extend(finding_lines(i, f));
        }
        parts.extend(self.fine.iter().map(|e| Human::Line(format!("fine: {}", evidence_text(e)))));
        Human::Parts(parts)
    }

    fn csv(&self) -> Human {
        let mut rows: Vec<Vec<String>> = Vec::new();
        for (i, f) in self.findings.iter().enumerate() {
            for e in &f.evidence {
                rows.push(vec![(i + 1).to_string(), cause_text(&f.cause), evidence_text(e), remedy_text(&f.remedy)]);
            }
        }
        rows.extend(self.fine.iter().map(|e| vec![String::new(), "fine".into(), evidence_text(e), String::new()]));
        Human::table(&["rank", "cause", "evidence", "fix"], rows)
    }

    fn notes(&self) -> Vec<String> {
        // A link that failed (the host's side, or its controller bus-off) ended the listen:
        // that is not a link that shows no traffic.
        let failed =
            self.findings.iter().any(|f| f.evidence.iter().any(|e| matches!(e, Evidence::LinkReported { .. })));
        if self.listened_ms == 0 && !failed {
            return vec!["this link shows no traffic: nothing was listened to, only requests answered".into()];
        }
        Vec::new()
    }

    fn junit(&self) -> Option<TestSuite> {
        let class = self.node.map_or("bus".to_string(), |n| format!("node {n}"));
        let mut cases: Vec<TestCase> = self
            .findings
            .iter()
            .map(|f| TestCase {
                class: class.clone(),
                name: cause_text(&f.cause),
                detail: joined(f.evidence.iter().map(evidence_text), "; "),
                failure: Some(format!("{}; fix: {}", cause_text(&f.cause), remedy_text(&f.remedy))),
            })
            .collect();
        cases.extend(self.fine.iter().map(|e| TestCase {
            class: class.clone(),
            name: evidence_kind(e),
            detail: evidence_text(e),
            failure: None,
        }));
        Some(TestSuite { name: format!("canctl doctor: {}", self.bus), cases })
    }

    /// As it serialises, each finding with its cause and fix in words too.
    fn json_value(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).expect("reports serialise");
        if let Some(findings) = v["findings"].as_array_mut() {
            for (json, f) in findings.iter_mut().zip(&self.findings) {
                *json = finding_json(f);
            }
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canopen::nmt::State;

    #[test]
    fn a_finding_reads_cause_evidence_and_fix() {
        let d = Diagnosis {
            bus: "sim".into(),
            node: Some(5),
            listened_ms: 1000,
            findings: vec![Finding {
                cause: Cause::Stopped { node: 5 },
                evidence: vec![Evidence::Heartbeats { node: 5, count: 10, state: State::Stopped }],
                remedy: Remedy::PreOperational { node: 5 },
            }],
            fine: vec![Evidence::LinkQuiet],
            ok: false,
        };
        let Human::Parts(parts) = d.human() else { panic!("parts") };
        let lines: Vec<String> =
            parts.iter().filter_map(|p| if let Human::Line(l) = p { Some(l.clone()) } else { None }).collect();
        assert_eq!(lines[0], "sim, node 5: 1 problem(s) found, most likely cause first");
        assert!(lines[1].starts_with("1. node 5 is alive but stopped"), "{lines:?}");
        assert!(lines[2].contains("10 heartbeat(s) of node 5 on 0x705, the last saying stopped"), "{lines:?}");
        assert!(lines[3].contains("canctl nmt preop 5"), "{lines:?}");
        let json = d.json_value();
        assert!(json["findings"][0]["fix"].as_str().unwrap().contains("canctl nmt preop 5"), "{json}");
        let suite = d.junit().unwrap();
        assert_eq!(suite.cases.iter().filter(|c| c.failure.is_some()).count(), 1);
    }
}
