//! How the network project reports look: tables for people, JUnit for CI.

use super::junit::{TestCase, TestSuite};
use super::report::{Human, Report};
use crate::ops::failure::Failure;
use crate::ops::network::{
    Applied, BaudSwitched, Checked, Dumped, NodeApplied, NodeCheck, NodeResult, Outcome, PROJECT_FILE,
};
use std::path::{Path, PathBuf};

/// A network project's warnings (a DCF that deviates, a node listed twice), as lines on stderr.
pub(crate) fn load_warning_lines(loaded: &crate::ops::network::Loaded) -> Vec<String> {
    loaded.warnings.iter().map(|w| format!("canctl: warning: {w}")).collect()
}

pub(crate) struct DumpReport<'a> {
    pub dumped: &'a Dumped,
    pub dir: &'a Path,
}

impl serde::Serialize for DumpReport<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        #[derive(serde::Serialize)]
        struct Json<'a> {
            dir: String,
            project: String,
            #[serde(flatten)]
            dumped: &'a Dumped,
        }
        Json {
            dir: self.dir.display().to_string(),
            project: self.dir.join(PROJECT_FILE).display().to_string(),
            dumped: self.dumped,
        }
        .serialize(s)
    }
}

impl Report for DumpReport<'_> {
    fn human(&self) -> Human {
        let rows = self
            .dumped
            .nodes
            .iter()
            .map(|n| vec![n.node.to_string(), n.name.clone(), n.file.clone(), n.objects.to_string()]);
        Human::table(&["node", "name", "file", "objects"], rows.collect())
    }

    fn notes(&self) -> Vec<String> {
        let mut notes = vec![format!(
            "{} and {} DCF(s) written from {}",
            self.dir.join(PROJECT_FILE).display(),
            self.dumped.nodes.len(),
            self.dumped.bus
        )];
        if self.dumped.unconfigured > 0 {
            notes.push(format!(
                "{} device(s) without a node-id answered LSS: not in the project (canctl lss assign numbers them)",
                self.dumped.unconfigured
            ));
        }
        notes
    }
}

/// `node 5 (name)`, or `node 5` without a name.
pub(super) fn node_label(node: u8, name: &str) -> String {
    if name.is_empty() {
        format!("node {node}")
    } else {
        format!("node {node} ({name})")
    }
}

/// Devices waiting for a node-id: said by check, no difference (see `ops::network`).
fn unconfigured_note(count: usize) -> String {
    format!(
        "{count} device(s) without a node-id answered LSS: not in the project, and no difference (lss assign or network apply --assign numbers them)"
    )
}

/// A check's detail with its remedy as `network check` words it: a node that answers no
/// SDO is told in parentheses, after what cannot be checked.
fn detail_text(c: &crate::ops::network::Verdict) -> String {
    match c.remedy {
        Some(crate::ops::verdict::Remedy::PreOperational { node }) => {
            format!("{}{}", super::verdicts::finding_text(c), super::remedies::stopped_node_aside(node))
        }
        _ => super::hints::verdict_text(c),
    }
}

impl Report for Checked {
    /// As it serialises, each check's detail worded in its place, with its remedy.
    fn json_value(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).expect("reports serialise");
        if let Some(nodes) = v["nodes"].as_array_mut() {
            for (json, n) in nodes.iter_mut().zip(&self.nodes) {
                super::verdicts::word_details(&mut json["checks"], &n.checks, detail_text);
            }
        }
        v
    }

    fn human(&self) -> Human {
        let mut rows = Vec::new();
        for n in &self.nodes {
            for c in &n.checks {
                let result = if c.ok { "ok" } else { "DIFFERS" };
                rows.push(vec![n.node.to_string(), n.name.clone(), c.check.to_string(), result.into(), detail_text(c)]);
            }
        }
        for u in &self.unlisted {
            let t = u.device_type.map_or("-".to_string(), |t| format!("device type 0x{t:08X}"));
            rows.push(vec![
                u.node.to_string(),
                "-".into(),
                "listed".into(),
                "DIFFERS".into(),
                format!("answers, but the project does not list it ({t})"),
            ]);
        }
        Human::table(&["node", "name", "check", "result", "detail"], rows)
    }

    fn notes(&self) -> Vec<String> {
        let name = self.net_name.clone().unwrap_or_else(|| self.project.clone());
        let mut notes = if self.ok {
            vec![format!("{name}: all {} node(s) as the project says", self.nodes.len())]
        } else {
            let failed = self.nodes.iter().filter(|n| n.checks.iter().any(|c| !c.ok)).count();
            vec![format!(
                "{name}: {failed} of {} node(s) differ, {} unlisted node(s)",
                self.nodes.len(),
                self.unlisted.len()
            )]
        };
        if self.unconfigured > 0 {
            notes.push(unconfigured_note(self.unconfigured));
        }
        notes
    }

    fn junit(&self) -> Option<TestSuite> {
        let mut cases = Vec::new();
        for n in &self.nodes {
            for c in &n.checks {
                let failure = (!c.ok).then(|| format!("{}: {}", node_label(n.node, &n.name), c.check));
                cases.push(TestCase {
                    class: node_label(n.node, &n.name),
                    name: c.check.to_string(),
                    detail: detail_text(c),
                    failure,
                });
            }
        }
        let unlisted = super::text::joined(self.unlisted.iter().map(|u| u.node), ", ");
        cases.push(TestCase {
            class: "network".into(),
            name: "no unlisted nodes".into(),
            detail: if unlisted.is_empty() {
                "every node that answers is in the project".into()
            } else {
                format!("node(s) {unlisted} answer but are not in the project")
            },
            failure: (!self.unlisted.is_empty()).then(|| format!("{} unlisted node(s)", self.unlisted.len())),
        });
        cases.push(TestCase {
            class: "network".into(),
            name: "devices without a node-id (said, no difference)".into(),
            detail: unconfigured_note(self.unconfigured),
            failure: None,
        });
        let name = self.net_name.clone().unwrap_or_else(|| self.project.clone());
        Some(TestSuite { name: format!("canctl network check: {name}"), cases })
    }
}

impl Report for Applied {
    fn human(&self) -> Human {
        let rows = self.nodes.iter().map(|n| {
            vec![
                n.node.to_string(),
                n.name.clone(),
                n.written.to_string(),
                node_result_words(n, super::hints::failure_text),
            ]
        });
        Human::table(&["node", "name", "written", "result"], rows.collect())
    }

    fn json_value(&self) -> serde_json::Value {
        let mut value = serde_json::to_value(self).expect("reports serialise");
        for (k, n) in self.nodes.iter().enumerate() {
            value["nodes"][k]["result"] = node_result_words(n, super::hints::failure_text).into();
            super::hints::word_change_results(&mut value["nodes"][k]["objects"], &n.objects);
        }
        value
    }

    fn notes(&self) -> Vec<String> {
        let verb = if self.dry_run { "would be written" } else { "written" };
        let mut notes = Vec::new();
        if self.dry_run {
            let would: usize = self
                .nodes
                .iter()
                .map(|n| n.objects.iter().filter(|c| c.result.action == crate::ops::config::Action::WouldWrite).count())
                .sum();
            notes.push(format!(
                "dry run: {would} object(s) {verb} on {} node(s); nothing was written",
                self.nodes.len()
            ));
        } else if self.written == 0 && self.ok {
            notes.push(format!("the network already matches {}: 0 objects written", self.project));
        } else {
            let written_to = self.nodes.iter().filter(|n| n.written > 0).count();
            notes.push(format!("{} object(s) {verb} on {written_to} of {} node(s)", self.written, self.nodes.len()));
        }
        if !self.unlisted.is_empty() {
            notes.push(format!(
                "node(s) {} answer but are not in the project: the network does not match it (add them, or take them off the bus)",
                super::text::joined(self.unlisted.iter().map(|u| u.node), ", ")
            ));
        }
        let interrupted = [
            (
                Outcome::StoppedPartWay,
                "stopped part-way, each at a point between two transfers (see its result for what was written and \
                 the state it is left in)",
            ),
            (Outcome::StoppedUnchanged, "stopped before anything was written, as they were"),
            (Outcome::NotBegun, "not begun; the same command finishes the job (only what differs is written)"),
        ];
        for (outcome, what) in interrupted {
            match self.nodes.iter().filter(|n| n.outcome == outcome).count() {
                0 => {}
                count => notes.push(format!("interrupted: {count} node(s) {what}")),
            }
        }
        notes
    }
}

/// What happened to a node, in a sentence, its failure worded by `failure`: its node-id
/// given over LSS first, then what its DCF did, then its reset.
pub(super) fn node_result_words(n: &NodeApplied, failure: fn(&Failure) -> String) -> String {
    let node = n.node;
    let verified = |v: bool| if v { ", verified" } else { "" };
    let what = match &n.result {
        NodeResult::NoDcf => "present; the project names no DCF for it".to_string(),
        NodeResult::WouldWrite { count: 0 } => "up to date: nothing would be written".to_string(),
        NodeResult::WouldWrite { count } => format!("{count} object(s) would be written"),
        NodeResult::Written { count: 0, .. } => "up to date: nothing written".to_string(),
        NodeResult::Written { count, verified: v, stored } => {
            format!("{count} object(s) written{}{}", verified(*v), if *stored { ", stored" } else { "" })
        }
        NodeResult::Failed => match &n.failure {
            Some(f) => format!("failed: {}", failure(f)),
            None => "failed".to_string(),
        },
        NodeResult::Interrupted { incomplete, not_stored } => {
            let mut text = format!("interrupted: {}", super::reports::incomplete_lines(incomplete).join("; "));
            if *not_stored {
                text.push_str(&format!("; not stored (canctl store {node} keeps what was written)"));
            }
            text
        }
        NodeResult::StoppedBeforeStore { written, verified: v } => {
            format!(
                "interrupted: {written} object(s) written{}, not stored (canctl store {node} keeps them)",
                verified(*v)
            )
        }
        NodeResult::WouldAssign => format!(
            "would be looked for over LSS ({}) and given node-id {node}",
            n.assigned.as_deref().unwrap_or_default()
        ),
        NodeResult::NotConfigured { interrupted } => format!(
            "node-id given over LSS; not configured: {}",
            if *interrupted {
                "interrupted before this node was begun"
            } else {
                "the run ended (link lost) before this node was begun"
            }
        ),
        NodeResult::NotBegun => "not done: interrupted before this node was begun".to_string(),
    };
    // Given its node-id over LSS, then configured: said first (the two above say it
    // their own way).
    let given = n.assigned.is_some() && !matches!(n.result, NodeResult::WouldAssign | NodeResult::NotConfigured { .. });
    let reset = match n.reset {
        Some(true) => ", reset, booted",
        Some(false) => ", reset, but not back",
        None => "",
    };
    format!("{}{what}{reset}", if given { "node-id given over LSS; " } else { "" })
}

/// How a node's check ended, for its progress line.
pub(super) fn checked_words(checked: &crate::Result<NodeCheck>) -> String {
    match checked {
        Ok(n) => match n.checks.iter().filter(|c| !c.ok).count() {
            0 => "as the project says".to_string(),
            k => format!("{k} check(s) differ"),
        },
        Err(e) => format!("failed: {e}"),
    }
}

/// Why a network-wide switch to `rate` was not activated, as canctl says it.
fn not_activated_text(why: crate::ops::network::NotActivated, rate: &str) -> String {
    use crate::ops::network::NotActivated;
    match why {
        NotActivated::NoneTook => "no device took the new rate".into(),
        NotActivated::Refused { count } => {
            format!("{count} device(s) refused {rate} (--force switches the others and leaves them behind)")
        }
        NotActivated::Interrupted => "interrupted before the activation".into(),
    }
}

/// What became of a node expected to follow a network-wide switch, in a few words.
fn followed_text(r: &BaudSwitched, n: &crate::ops::network::NodeFollowed) -> String {
    match (r.activated, r.bus_followed, n.before, n.after) {
        (false, ..) => "not switched".into(),
        (true, false, ..) => format!("not checked: {} stays at the old rate", r.bus),
        (true, true, _, Some(true)) => format!("answers at {}", r.rate),
        (true, true, true, _) => format!("did not follow: answered before the switch, not at {}", r.rate),
        (true, true, false, _) => "not found: did not answer before the switch nor after it".into(),
    }
}

/// `network set-baud`'s report, with the project files it rewrote and what to do with a
/// link that stayed at the old rate.
pub(crate) struct SetBaudReport<'a> {
    pub switched: &'a BaudSwitched,
    pub updated: &'a [PathBuf],
    /// Nodes of the project whose DCFs were left at their rate: not heard at the new one.
    pub left: &'a [u8],
    pub hint: String,
}

impl serde::Serialize for SetBaudReport<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        #[derive(serde::Serialize)]
        struct Json<'a> {
            #[serde(flatten)]
            switched: &'a BaudSwitched,
            updated: Vec<String>,
            #[serde(skip_serializing_if = "<[u8]>::is_empty")]
            dcfs_left: &'a [u8],
            #[serde(skip_serializing_if = "Option::is_none")]
            link_to_switch: Option<&'a str>,
        }
        let json = Json {
            switched: self.switched,
            updated: self.updated.iter().map(|p| p.display().to_string()).collect(),
            dcfs_left: self.left,
            link_to_switch: (self.switched.activated && !self.switched.bus_followed).then_some(self.hint.as_str()),
        };
        let mut value = serde_json::to_value(json).map_err(serde::ser::Error::custom)?;
        // Why it was not activated, in canctl's words, where the report has it.
        if let Some(why) = self.switched.not_activated {
            value["not_activated"] = not_activated_text(why, &self.switched.rate).into();
        }
        for (json, n) in value["nodes"].as_array_mut().into_iter().flatten().zip(&self.switched.nodes) {
            json["result"] = followed_text(self.switched, n).into();
        }
        value.serialize(s)
    }
}

impl Report for SetBaudReport<'_> {
    fn human(&self) -> Human {
        let r = self.switched;
        let mut parts =
            vec![Human::Line(format!("configure bit timing {}: {}", r.rate, super::lss::tally_text(&r.configured)))];
        if let Some(stored) = &r.stored {
            parts.push(Human::Line(format!("store configuration: {}", super::lss::tally_text(stored))));
        }
        parts.push(Human::Line(match (r.activated, r.bus_followed) {
            (false, _) => format!(
                "not activated: {}; every device is back in LSS waiting state at the old rate",
                r.not_activated.map_or("stopped".into(), |why| not_activated_text(why, &r.rate))
            ),
            (true, true) => format!(
                "activated (switch delay {} ms); {} switched with the devices, which are back in LSS waiting state",
                r.delay_ms, r.bus
            ),
            (true, false) => format!(
                "activated (switch delay {} ms); {} does not switch by itself, so nothing is checked yet: {}; then \
                 `canctl lss activate --global` or any `canctl lss` command sends the devices back to LSS waiting \
                 state, and `canctl scan` shows who followed",
                r.delay_ms, r.bus, self.hint
            ),
        }));
        let yes_no = |b: bool| if b { "yes" } else { "no" }.to_string();
        let rows = r
            .nodes
            .iter()
            .map(|n| {
                vec![
                    n.node.to_string(),
                    n.name.clone(),
                    yes_no(n.before),
                    n.after.map_or("-".to_string(), yes_no),
                    followed_text(r, n),
                ]
            })
            .collect();
        parts.push(Human::table(&["node", "name", "before", "after", "result"], rows));
        Human::Parts(parts)
    }

    fn notes(&self) -> Vec<String> {
        let r = self.switched;
        let mut notes = vec![format!("expected nodes from {}", r.expected_from)];
        if !r.unexpected.is_empty() {
            notes.push(format!(
                "node(s) {} answer at {} but were not expected",
                super::text::joined(&r.unexpected, ", "),
                r.rate
            ));
        }
        match r.unconfigured_after {
            Some(after) if after != r.unconfigured_before => notes.push(format!(
                "devices without a node-id: {} before the switch, {after} at {}",
                r.unconfigured_before, r.rate
            )),
            _ => {}
        }
        for p in self.updated {
            notes.push(format!("{}: Baudrate set to {}", p.display(), r.rate));
        }
        if !self.left.is_empty() {
            notes.push(format!(
                "the DCF(s) of node(s) {} left at their rate: not heard at {}",
                super::text::joined(self.left, ", "),
                r.rate
            ));
        }
        notes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each node expected to follow a network-wide switch is said as it went: not switched,
    /// not checked (a link that stays at the old rate), found at the new rate, left behind,
    /// or never there; in the table and in JSON alike.
    #[test]
    fn a_node_expected_to_follow_a_switch_is_said_as_it_went() {
        use crate::ops::network::{BaudSwitched, NodeFollowed};
        let node =
            |node: u8, before: bool, after: Option<bool>| NodeFollowed { node, name: String::new(), before, after };
        let switched = |activated: bool, bus_followed: bool, nodes: Vec<NodeFollowed>| BaudSwitched {
            bus: "socketcan:can0".into(),
            rate: "250k".into(),
            expected_from: "the probe before the switch".into(),
            configured: Default::default(),
            stored: None,
            activated,
            not_activated: None,
            delay_ms: 100,
            bus_followed,
            nodes,
            unexpected: Vec::new(),
            unconfigured_before: 0,
            unconfigured_after: None,
            ok: false,
            failure: None,
        };
        let said = |r: &BaudSwitched| -> Vec<String> { r.nodes.iter().map(|n| followed_text(r, n)).collect() };
        assert_eq!(said(&switched(false, false, vec![node(5, true, None)])), ["not switched"]);
        assert_eq!(
            said(&switched(true, false, vec![node(5, true, None)])),
            ["not checked: socketcan:can0 stays at the old rate"]
        );
        let r = switched(
            true,
            true,
            vec![node(5, true, Some(true)), node(10, true, Some(false)), node(32, false, Some(false))],
        );
        let words = [
            "answers at 250k",
            "did not follow: answered before the switch, not at 250k",
            "not found: did not answer before the switch nor after it",
        ];
        assert_eq!(said(&r), words);
        let report = SetBaudReport { switched: &r, updated: &[], left: &[], hint: String::new() };
        let json = serde_json::to_value(&report).unwrap();
        let results: Vec<&str> =
            json["nodes"].as_array().unwrap().iter().map(|n| n["result"].as_str().unwrap()).collect();
        assert_eq!(results, words);
        assert_eq!(json["nodes"][0].as_object().unwrap().keys().next_back().map(String::as_str), Some("result"));
    }

    fn row(result: NodeResult, assigned: Option<&str>, reset: Option<bool>) -> NodeApplied {
        NodeApplied {
            node: 20,
            name: String::new(),
            file: None,
            assigned: assigned.map(str::to_string),
            written: 3,
            stored: true,
            result,
            reset,
            failure: None,
            outcome: Outcome::Done,
            ok: true,
            objects: Vec::new(),
        }
    }

    /// The node-id given over LSS comes first and the reset last, around what the DCF did;
    /// the results that tell the node-id their own way are not prefixed again.
    #[test]
    fn a_node_result_is_worded_with_its_node_id_and_reset() {
        let written = NodeResult::Written { count: 3, verified: true, stored: true };
        assert_eq!(
            node_result_words(&row(written, Some("0x1/0x2/0x3/0x4"), Some(false)), crate::output::hints::failure_text),
            "node-id given over LSS; 3 object(s) written, verified, stored, reset, but not back"
        );
        assert_eq!(
            node_result_words(
                &row(NodeResult::WouldAssign, Some("0x1/0x2/0x3/0x4"), None),
                crate::output::hints::failure_text
            ),
            "would be looked for over LSS (0x1/0x2/0x3/0x4) and given node-id 20"
        );
        assert_eq!(
            node_result_words(
                &row(NodeResult::NotConfigured { interrupted: false }, Some("x"), None),
                crate::output::hints::failure_text
            ),
            "node-id given over LSS; not configured: the run ended (link lost) before this node was begun"
        );
        let stopped = NodeResult::StoppedBeforeStore { written: 3, verified: false };
        assert_eq!(
            node_result_words(&row(stopped, None, None), crate::output::hints::failure_text),
            "interrupted: 3 object(s) written, not stored (canctl store 20 keeps them)"
        );
    }

    /// A listed node that beats but answers no SDO: the remedy in parentheses, as before.
    #[test]
    fn a_silent_listed_node_reads_as_before() {
        let said = "node 5 is there (stopped, by its heartbeat) but answered none of 3 SDO probes of 100 ms: nothing \
                    of it can be checked";
        let stopped = crate::canopen::nmt::State::Stopped;
        let silent = crate::ops::network::Finding::SilentListed { node: 5, state: stopped, rounds: 3, window_ms: 100 };
        let v = crate::ops::network::Verdict::new("present", false, silent)
            .with_remedy(Some(crate::ops::verdict::Remedy::PreOperational { node: 5 }));
        assert_eq!(detail_text(&v), format!("{said} (a Stopped node answers no SDO: canctl nmt preop 5)"));
    }
}
