//! How the reports of scan, sdo and nmt look to people and in CSV.

use super::report::{Human, Report};
use crate::bus::ALL_NODES;
use crate::canopen::types::{hex, obvious_unsigned};
use crate::ops::nmt::{target_text, NodeState, Reset, SeenBy, Sent, Unconfirmed};
use crate::ops::scan::{Phase, Scan, StateFrom};
use crate::ops::sdo::{self, Read, Saved, Written};

/// The nodes found, one row each.
fn scan_table(scan: &Scan) -> Human {
    let hex = |v: Option<u32>| v.map_or("-".to_string(), |v| format!("0x{v:08X}"));
    let headers = ["node", "device_type", "vendor_id", "product_code", "revision", "serial", "name", "state"];
    let rows = scan.nodes.iter().map(|f| {
        let identity = [f.device_type, f.vendor_id, f.product_code, f.revision, f.serial].map(hex);
        let (name, state) = (f.name.clone().unwrap_or_else(|| "-".into()), f.state.map_or("unknown", |s| s.name()));
        [vec![f.node.to_string()], identity.to_vec(), vec![name, state.into()]].concat()
    });
    Human::table(&headers, rows.collect())
}

/// A part of a scan, as canctl names it.
fn phase_text(phase: Phase) -> &'static str {
    match phase {
        Phase::Probe => "probing node-ids 1 to 127 (stopped part-way: nodes not listed may be there)",
        Phase::Identities => "reading identity, name and heartbeat time",
        Phase::States => "learning NMT states",
        Phase::Unconfigured => "counting devices without a node-id (LSS)",
    }
}

impl Report for Scan {
    /// As it serialises, with the parts not done in words (the last key, when any).
    fn json_value(&self) -> serde_json::Value {
        let mut value = serde_json::to_value(self).expect("reports serialise");
        if !self.not_done.is_empty() {
            value["not_done"] = self.not_done.iter().map(|p| phase_text(*p)).collect::<Vec<_>>().into();
        }
        value
    }

    fn human(&self) -> Human {
        scan_human(self, Some(&self.bus))
    }

    fn human_among_buses(&self) -> Human {
        scan_human(self, None)
    }

    fn csv(&self) -> Human {
        scan_table(self)
    }

    fn notes(&self) -> Vec<String> {
        self.clashes.iter().map(|c| format!("warning: {c}{CLASH_REMEDY}")).collect()
    }
}

/// A scan's count, table and remarks; the count names `bus` when given (alone: "4 node(s)
/// on sim").
fn scan_human(scan: &Scan, bus: Option<&str>) -> Human {
    let count = format!("{} node(s)", scan.nodes.len());
    let count = bus.map_or_else(|| count.clone(), |bus| format!("{count} on {bus}"));
    let mut parts = vec![Human::Note(count), scan_table(scan)];
    // Interrupted before the states were learned: the note at the end says so.
    for f in scan.nodes.iter().filter(|f| f.state.is_none() && f.state_from != StateFrom::NotAsked) {
        parts.push(Human::Line(format!("node {}: NMT state unknown: {}", f.node, f.state_from)));
    }
    // The probe asks again the ids that did not answer: a node that answered only then
    // is the technician's sign that frames are being lost.
    for r in &scan.answered_on_repeat {
        parts.push(Human::Line(repeat_text(r)));
    }
    // Without a state the line above says why it is listed.
    for f in scan.nodes.iter().filter(|f| !f.answers_sdo) {
        if let Some(state) = f.state {
            let elsewhere = scan.answers_elsewhere.iter().find(|e| e.node == f.node);
            let why = match (elsewhere, state) {
                (Some(e), _) => format!(
                    ": its SDO server answers on 0x{:03X}, not 0x{:03X} (its 0x1200 changed; canctl doctor {} says more)",
                    e.cob_id,
                    0x580 + u16::from(f.node),
                    f.node
                ),
                (None, crate::canopen::nmt::State::Stopped) => super::remedies::stopped_node_aside(f.node),
                (None, _) => format!(" (its SDO server is off or on other COB-IDs: canctl doctor {} says more)", f.node),
            };
            parts.push(Human::Line(format!(
                "node {}: seen by its {} ({}), but it answered none of the {} SDO probes{why}",
                f.node,
                f.state_from,
                state.name(),
                scan.probe_rounds,
            )));
        }
    }
    parts.extend(scan.not_there.iter().map(|node| Human::Line(not_there_text(*node))));
    for g in &scan.gone {
        parts.push(Human::Line(format!(
            "node {}: seen by the last scan, it answers nothing now: not the probe ({})",
            g.node, g.from
        )));
    }
    if scan.lss_unconfigured > 0 {
        parts.push(Human::Line(format!(
            "{} device(s) without a node-id answered LSS (canctl lss fastscan finds them, lss assign numbers them)",
            scan.lss_unconfigured
        )));
    }
    let configuring = &scan.lss_configuration;
    if configuring.count > 0 {
        let which = match configuring.one {
            Some((id, None)) => format!(": {id}, no node-id"),
            Some((id, Some(n))) => format!(": {id}, node-id {n}"),
            None if configuring.count > 1 => {
                " (several answered at once, so their identities cannot be told apart)".to_string()
            }
            None => " (not every identity inquiry was answered, so its identity is incomplete)".to_string(),
        };
        parts.push(Human::Line(format!(
            "{} device(s) waiting in LSS configuration state{which} (canctl lss set-id gives a node-id; \
             `canctl lss set-id 255 --global` or any LSS command sends them back to waiting)",
            configuring.count
        )));
    }
    if scan.interrupted {
        parts.push(Human::Note(format!(
            "scan interrupted, incomplete: {} node(s) found so far; not done: {}; nothing was changed on the devices",
            scan.nodes.len(),
            super::text::joined(scan.not_done.iter().map(|p| phase_text(*p)), ", ")
        )));
    }
    Human::Parts(parts)
}

/// A node-id the probe's answer came for, though no device has it ([`Scan::not_there`]).
pub(super) fn not_there_text(node: u8) -> String {
    format!(
        "node {node}: not listed: an answer to the probe came on its COB-ID 0x{:03X}, but asked alone it answers \
         nothing: another device's SDO server answers there (its 0x1200 changed)",
        0x580 + u16::from(node)
    )
}

/// What to do about two devices on one node-id (`ops::clash::Clash`), as canctl says it.
pub(crate) const CLASH_REMEDY: &str = "; give one of them another id (lss set-id NEW --identity ...)";

impl Report for Read {
    fn human(&self) -> Human {
        // What the device sent is one value: a line break in it is shown, not obeyed.
        Human::Line(match (&self.value, self.dtype) {
            (Some(v), Some(_)) => super::text::terminal_safe(&v.to_string()).into_owned(),
            _ => untyped(&self.bytes),
        })
    }

    fn csv(&self) -> Human {
        let (dtype, value) = (self.dtype.map_or("", |t| t.name()), self.value.as_ref().map(|v| v.to_string()));
        let values = [self.node.to_string(), self.object.to_string(), dtype.into(), self.size.to_string()];
        let values = [values.to_vec(), vec![hex(&self.bytes), value.unwrap_or_default()]].concat();
        Human::table(&["node", "object", "type", "size", "raw", "value"], vec![values])
    }
}

/// Raw bytes, then what they obviously are: `92 01 02 00  (u32 131474 = 0x00020192)`.
fn untyped(bytes: &[u8]) -> String {
    let mut s = super::text::joined(bytes.iter().map(|b| format!("{b:02X}")), " ");
    if let Some(v) = obvious_unsigned(bytes) {
        let width = bytes.len() * 2;
        s += &format!("  (u{} {v} = 0x{v:0width$X})", bytes.len() * 8);
    } else if !bytes.is_empty() && bytes.iter().all(|b| (0x20..0x7F).contains(b)) {
        s += &format!("  \"{}\"", String::from_utf8_lossy(bytes));
    } else if bytes.is_empty() {
        s = "(empty)".into();
    }
    s
}

impl Report for Saved {
    fn human(&self) -> Human {
        Human::Line(format!("{} bytes from node {} {} written to {}", self.size, self.node, self.object, self.file))
    }

    fn csv(&self) -> Human {
        let values = vec![self.node.to_string(), self.object.to_string(), self.size.to_string(), self.file.clone()];
        Human::table(&["node", "object", "size", "file"], vec![values])
    }
}

impl Report for Written {
    fn human(&self) -> Human {
        let what = match (self.verified, self.interrupted) {
            (true, _) => "written and verified",
            (false, true) => "written; not verified: interrupted before the read-back",
            (false, false) => "written",
        };
        let shown = if self.size > 32 { format!("{} bytes", self.size) } else { sdo::shown(self.dtype, &self.bytes) };
        Human::Line(format!("node {} {} = {shown} ({}): {what}", self.node, self.object, self.dtype))
    }

    fn csv(&self) -> Human {
        let (node, object, dtype) = (self.node.to_string(), self.object.to_string(), self.dtype.name().to_string());
        let value = sdo::shown(self.dtype, &self.bytes);
        let values = vec![node, object, dtype, self.size.to_string(), value, self.verified.to_string()];
        Human::table(&["node", "object", "type", "size", "value", "verified"], vec![values])
    }
}

impl Report for Sent {
    fn human(&self) -> Human {
        Human::Line(format!("NMT {} sent to {}", self.command.name(), target_text(self.target)))
    }

    fn csv(&self) -> Human {
        // The target as in JSON: 5, or "all" with its quotes.
        let target = if self.target == ALL_NODES { "\"all\"".into() } else { self.target.to_string() };
        Human::table(&["command", "target", "sent"], vec![vec![self.command.name().into(), target, "true".into()]])
    }
}

impl Report for Reset {
    fn human(&self) -> Human {
        let (command, target) = (self.command.name(), target_text(self.target));
        Human::Line(match (&self.booted, &self.why) {
            (Some(nodes), _) => {
                let (state, how) =
                    (self.state.map_or("", |s| s.name()), self.seen_by.map(seen_by_text).unwrap_or_default());
                format!(
                    "booted after NMT {command}: node {} (now {state}; seen by {how})",
                    super::text::joined(nodes, ", ")
                )
            }
            (None, why) => format!(
                "NMT {command} sent to {target}; not confirmed: {}",
                why.as_ref().map(unconfirmed_text).unwrap_or_default()
            ),
        })
    }

    /// As it serialises, with why the reset is not confirmed in words (before `interrupted`).
    fn json_value(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).expect("reports serialise");
        if let Some(map) = v.as_object_mut() {
            // The words go where the fields stand, before `interrupted` (the last key when
            // there): it is taken off and put back after them.
            let interrupted = map.remove("interrupted");
            if let Some(how) = self.seen_by {
                map.insert("seen_by".into(), seen_by_text(how).into());
            }
            if let Some(why) = &self.why {
                map.insert("why".into(), unconfirmed_text(why).into());
            }
            if let Some(i) = interrupted {
                map.insert("interrupted".into(), i);
            }
        }
        v
    }

    fn csv(&self) -> Human {
        let Some(nodes) = &self.booted else { return self.human() };
        let state = self.state.map_or("", |s| s.name());
        Human::table(&["node", "state"], nodes.iter().map(|n| vec![n.to_string(), state.into()]).collect())
    }
}

/// How a node was seen coming back from a reset, as canctl says it.
pub(crate) fn seen_by_text(how: SeenBy) -> String {
    match how {
        SeenBy::BootUpMessage => "boot-up message".into(),
        SeenBy::BootUpAnswer => "its boot-up, as the answer to a remote request".into(),
        SeenBy::StateChange { was } => format!("its state: {was} before, pre-operational after (remote requests)"),
    }
}

/// Why a reset is not confirmed, as canctl says it: what was seen instead, and the command
/// that shows more.
pub(crate) fn unconfirmed_text(why: &Unconfirmed) -> String {
    match why {
        Unconfirmed::NoBootUps { bus } => {
            format!("{bus} passes on no boot-up messages; check the nodes with `canctl scan`")
        }
        Unconfirmed::StateAsBefore { node, after, bus, .. } => format!(
            "node {node} answers and is {after}, as before; {bus} passes on no boot-up messages, so a reset cannot be \
             told from none. To see one, put the node in another state first (`canctl nmt stop {node}`)"
        ),
        Unconfirmed::UndefinedState { node, code, bus } => format!(
            "node {node} answers with state code 0x{code:02X}, which CiA 301 does not define; {bus} passes on no \
             boot-up messages"
        ),
        Unconfirmed::Interrupted { target } => format!(
            "interrupted while waiting for the boot-up: the reset went out, whether {} came back is not known \
             (canctl nmt state or scan says)",
            target_text(*target)
        ),
    }
}

impl Report for NodeState {
    fn human(&self) -> Human {
        Human::Line(format!("node {}: {} (from {})", self.node, self.state, self.source))
    }

    fn csv(&self) -> Human {
        Human::table(
            &["node", "state", "source"],
            vec![vec![self.node.to_string(), self.state.name().into(), self.source.to_string()]],
        )
    }
}

/// Why a scan with a short window left the scan cache as it was.
pub(crate) fn short_window_note() -> String {
    format!(
        "a window under {} ms may miss slow devices: the scan cache is kept as it was",
        crate::ops::scan::FULL_WINDOW.as_millis()
    )
}

/// A node that answered fewer probes than it was sent: the technician's sign that frames are
/// being lost (scan's and health's note).
pub(super) fn repeat_text(r: &crate::ops::scan::Repeat) -> String {
    format!(
        "node {} answered {} of {} probes: frames are being lost (an overloaded adapter or gateway, or errors on the bus)",
        r.node, r.answered, r.probes
    )
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::canopen::nmt;
    use crate::ops::scan::{Configuring, Gone, Node, Repeat, StateFrom};

    fn lines(h: Human) -> Vec<String> {
        match h {
            Human::Parts(parts) => parts.into_iter().flat_map(lines).collect(),
            Human::Line(l) => vec![l],
            _ => vec![],
        }
    }

    /// The technician must learn that the bus loses frames, and why a listed node has no
    /// identity: one line under the table each.
    #[test]
    fn a_node_found_on_a_repeat_and_one_seen_only_by_its_heartbeat_get_a_line_each() {
        let node = |node, answers_sdo, state| Node {
            node,
            device_type: None,
            vendor_id: None,
            product_code: None,
            revision: None,
            serial: None,
            name: None,
            state,
            state_from: StateFrom::Heartbeat,
            heartbeat_ms: None,
            answers_sdo,
        };
        let scan = Scan {
            bus: "can0".into(),
            nodes: vec![node(5, false, Some(nmt::State::Stopped)), node(21, true, Some(nmt::State::Operational))],
            lss_unconfigured: 0,
            lss_configuration: Configuring::default(),
            clashes: vec![],
            probe_rounds: 3,
            answered_on_repeat: vec![Repeat { node: 21, probes: 2, answered: 1 }],
            interrupted: false,
            not_done: vec![],
            gone: vec![Gone { node: 7, from: StateFrom::Silent { heartbeat: false } }],
            answers_elsewhere: vec![],
            not_there: vec![],
        };
        let lines = lines(scan.human());
        assert!(
            lines.iter().any(|l| l.starts_with("node 21 answered 1 of 2 probes: frames are being lost")),
            "{lines:?}"
        );
        assert!(
            lines
                .iter()
                .any(|l| l
                    .starts_with("node 5: seen by its heartbeat (stopped), but it answered none of the 3 SDO probes")),
            "{lines:?}"
        );
        // A node the last scan saw that shows nothing now is said, never left out.
        let gone = "node 7: seen by the last scan, it answers nothing now: not the probe (no heartbeat configured, \
                    and no answer to node guarding)";
        assert!(lines.iter().any(|l| l == gone), "{lines:?}");
        assert_eq!(lines.len(), 3, "{lines:?}");
        let said = "node 5: seen by its heartbeat (stopped), but it answered none of the 3 SDO probes (a Stopped node \
                    answers no SDO: canctl nmt preop 5)";
        assert!(lines.iter().any(|l| l == said), "{lines:?}");
    }

    /// Why a reset is not confirmed reads as when the library worded it, in JSON in its
    /// place (`why` before `interrupted`).
    #[test]
    fn an_unconfirmed_reset_reads_as_before() {
        let bus = "epos2-usb:/dev/ttyUSB0".to_string();
        let cases = [
            (
                Unconfirmed::NoBootUps { bus: bus.clone() },
                "epos2-usb:/dev/ttyUSB0 passes on no boot-up messages; check the nodes with `canctl scan`".to_string(),
            ),
            (
                Unconfirmed::StateAsBefore {
                    node: 5,
                    before: Some(nmt::State::Operational),
                    after: nmt::State::Operational,
                    bus: bus.clone(),
                },
                format!(
                    "node 5 answers and is {}, as before; epos2-usb:/dev/ttyUSB0 passes on no boot-up messages, so a \
                     reset cannot be told from none. To see one, put the node in another state first (`canctl nmt stop 5`)",
                    nmt::State::Operational
                ),
            ),
            (
                Unconfirmed::UndefinedState { node: 5, code: 0x42, bus },
                "node 5 answers with state code 0x42, which CiA 301 does not define; epos2-usb:/dev/ttyUSB0 passes on \
                 no boot-up messages"
                    .to_string(),
            ),
            (
                Unconfirmed::Interrupted { target: ALL_NODES },
                "interrupted while waiting for the boot-up: the reset went out, whether all nodes came back is not \
                 known (canctl nmt state or scan says)"
                    .to_string(),
            ),
        ];
        for (why, text) in cases {
            assert_eq!(unconfirmed_text(&why), text);
        }
        let reset = Reset {
            command: nmt::Command::ResetNode,
            target: 5,
            sent: true,
            confirmed: false,
            booted: None,
            state: None,
            seen_by: None,
            why: Some(Unconfirmed::Interrupted { target: 5 }),
            interrupted: true,
        };
        let json = reset.json_value();
        let keys: Vec<&String> = json.as_object().unwrap().keys().collect();
        assert_eq!(keys, ["command", "target", "sent", "confirmed", "booted", "why", "interrupted"]);
        assert_eq!(json["why"], unconfirmed_text(&Unconfirmed::Interrupted { target: 5 }));
        let Human::Line(line) = reset.human() else { panic!("a line") };
        assert!(line.ends_with("whether node 5 came back is not known (canctl nmt state or scan says)"), "{line}");

        // Confirmed: how it was seen, in words, where the field stands.
        let seen = SeenBy::StateChange { was: nmt::State::Stopped };
        let reset = Reset {
            confirmed: true,
            booted: Some(vec![5]),
            state: Some(nmt::State::PreOperational),
            seen_by: Some(seen),
            why: None,
            interrupted: false,
            ..reset
        };
        let json = reset.json_value();
        let keys: Vec<&String> = json.as_object().unwrap().keys().collect();
        assert_eq!(keys, ["command", "target", "sent", "confirmed", "booted", "state", "seen_by"]);
        assert_eq!(json["seen_by"], "its state: stopped before, pre-operational after (remote requests)");
        let Human::Line(line) = reset.human() else { panic!("a line") };
        assert_eq!(
            line,
            "booted after NMT reset node: node 5 (now pre-operational; seen by its state: stopped before, \
             pre-operational after (remote requests))"
        );
    }
}
