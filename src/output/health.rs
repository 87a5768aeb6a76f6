//! How the error history and the health report look: tables for people, JUnit for CI.

use super::hints::verdict_text;
use super::junit::{TestCase, TestSuite};
use super::network::node_label;
use super::report::{Human, Report};
use crate::ops::errors::{ErrorHistory, LoggedError};
use crate::ops::health::{Check, Health as HealthReport, NodeHealth};

fn source_text(s: crate::canopen::emcy::Source) -> &'static str {
    use crate::canopen::emcy::Source;
    match s {
        Source::Cia301 => "CiA 301",
        Source::Cia402 => "CiA 402",
        Source::Device => "device manual",
    }
}

impl Report for ErrorHistory {
    fn human(&self) -> Human {
        let who = node_label(self.node, self.name.as_deref().unwrap_or_default());
        let register = format!("error register {}", super::verdicts::register_text(self.error_register));
        if !self.kept {
            return Human::Line(format!("{who} keeps no error history (it has no object 0x1003); {register}"));
        }
        let mut parts = vec![Human::Line(match self.count {
            Some(0) | None => format!("{who}: no errors logged in 0x1003; {register}"),
            Some(n) => format!("{who}: {n} error(s) logged in 0x1003, newest first; {register}"),
        })];
        let rows = self.entries.iter().map(|e| [vec![e.sub.to_string()], entry_cells(e)].concat()).collect();
        parts.push(Human::Table { headers: vec!["#", "code", "mfr", "meaning", "from"], rows, when_empty: false });
        parts.extend(
            self.unreadable.iter().map(|u| Human::Note(format!("0x1003:{} could not be read: {}", u.sub, u.error))),
        );
        if self.cleared {
            parts.push(Human::Line(format!("{who}: error history cleared (0x1003:0 reads back 0)")));
        }
        match self.clear_interrupted {
            Some(true) => parts.push(Human::Note(format!(
                "{who}: interrupted: 0 written to 0x1003:0, not confirmed (canctl errors {} shows what is left)",
                self.node
            ))),
            Some(false) => parts.push(Human::Note(format!("{who}: interrupted before clearing: nothing was changed"))),
            None => {}
        }
        Human::Parts(parts)
    }

    fn csv(&self) -> Human {
        let row = |e: &LoggedError| [vec![self.node.to_string(), e.sub.to_string(), e.raw.to_string()], entry_cells(e)];
        let rows = self.entries.iter().map(|e| row(e).concat()).collect();
        Human::table(&["node", "sub", "raw", "code", "manufacturer", "meaning", "source"], rows)
    }
}

/// A logged error's code, manufacturer's part, meaning and where the meaning is from.
fn entry_cells(e: &LoggedError) -> Vec<String> {
    let (code, mfr) = (format!("0x{:04X}", e.code), format!("0x{:04X}", e.manufacturer));
    vec![code, mfr, e.meaning.to_string(), source_text(e.source).to_string()]
}

fn cell<'a>(h: &'a NodeHealth, check: &str) -> Option<&'a Check> {
    h.checks.iter().find(|c| c.check == check)
}

fn heartbeat_cell(h: &NodeHealth, watched: bool) -> String {
    match (h.heartbeat_ms, cell(h, "heartbeat")) {
        (None, _) => "-".into(),
        (Some(0), _) => "off".into(),
        (Some(ms), _) if !watched => format!("{ms} ms"),
        (Some(ms), Some(c)) if c.ok => format!("{ms} ms, on time"),
        (Some(ms), _) if h.heartbeats == 0 => format!("{ms} ms, NONE"),
        (Some(ms), _) => format!("{ms} ms, LATE ({} ms gap)", h.longest_gap_ms.unwrap_or(0)),
    }
}

impl Report for HealthReport {
    fn human(&self) -> Human {
        let mut parts = vec![self.csv()];
        for h in &self.nodes {
            for c in h.checks.iter().filter(|c| !c.ok) {
                // The node-id check fails on two devices on one id (its detail, the clash).
                let remedy = if c.check == "node-id" { super::nodes::CLASH_REMEDY } else { "" };
                parts.push(Human::Line(format!("node {} {}: {}{remedy}", h.node, c.check, verdict_text(c))));
            }
            if let Some(f) = &h.diagnosis {
                parts.push(Human::Line(format!("node {}{}", h.node, super::doctor::likely_cause_text(f))));
            }
        }
        Human::Parts(parts)
    }

    /// As it serialises, a node's diagnosis with its cause and fix in words too, and each
    /// check's detail with its remedy.
    fn json_value(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).expect("reports serialise");
        if let Some(nodes) = v["nodes"].as_array_mut() {
            for (json, h) in nodes.iter_mut().zip(&self.nodes) {
                super::verdicts::word_details(&mut json["checks"], &h.checks, verdict_text);
                json["diagnosis"] = h.diagnosis.as_ref().map(super::doctor::finding_json).into();
            }
        }
        v
    }

    /// One row per node: the same in the table and in CSV.
    fn csv(&self) -> Human {
        let watched = self.watched_ms > 0;
        let rows = self
            .nodes
            .iter()
            .map(|h| {
                let failed: Vec<&str> = h.checks.iter().filter(|c| !c.ok).map(|c| c.check).collect();
                vec![
                    h.node.to_string(),
                    h.name.clone().unwrap_or_default(),
                    h.nmt.map_or("unknown".to_string(), |s| s.name().to_string()),
                    heartbeat_cell(h, watched),
                    super::verdicts::register_text(h.error_register),
                    h.errors_logged.map_or("-".into(), |n| n.to_string()),
                    match h.emcy.len() {
                        0 if !watched => "-".into(),
                        0 => "0".into(),
                        _ => super::text::joined(h.emcy.iter().map(|e| format!("0x{:04X}", e.code)), " "),
                    },
                    h.drive_state.map_or(
                        if h.statusword.is_some() || cell(h, "drive").is_some() { "?".into() } else { String::new() },
                        |s| s.name().to_string(),
                    ),
                    if failed.is_empty() { "ok".into() } else { format!("UNHEALTHY: {}", failed.join(", ")) },
                ]
            })
            .collect();
        Human::table(&["node", "name", "nmt", "heartbeat", "error register", "logged", "emcy", "drive", "health"], rows)
    }

    fn notes(&self) -> Vec<String> {
        health_notes(self, Some(&self.bus))
    }

    fn notes_among_buses(&self) -> Vec<String> {
        health_notes(self, None)
    }

    fn junit(&self) -> Option<TestSuite> {
        let cases = self
            .nodes
            .iter()
            .flat_map(|h| {
                let class = node_label(h.node, h.name.as_deref().unwrap_or_default());
                let likely = h.diagnosis.as_ref().map(super::doctor::likely_cause_text).unwrap_or_default();
                h.checks.iter().map(move |c| TestCase {
                    class: class.clone(),
                    name: c.check.to_string(),
                    detail: verdict_text(c),
                    failure: (!c.ok).then(|| format!("{class}: {}: {}{likely}", c.check, verdict_text(c))),
                })
            })
            .collect();
        Some(TestSuite { name: format!("canctl health: {}", self.bus), cases })
    }
}

/// The verdict and the remarks after a health table, the verdict prefixed with `bus` when
/// given (alone: "sim: all 4 node(s) healthy").
fn health_notes(h: &HealthReport, bus: Option<&str>) -> Vec<String> {
    let bad = h.nodes.iter().filter(|n| !n.ok).count();
    let watched = if h.watched_ms > 0 {
        format!("heartbeats and EMCYs watched for {} ms", h.watched_ms)
    } else {
        "no traffic watched: this link shows none".to_string()
    };
    let verdict = if bad == 0 {
        format!("all {} node(s) healthy ({watched})", h.nodes.len())
    } else {
        format!("{bad} of {} node(s) not healthy ({watched})", h.nodes.len())
    };
    let mut notes = vec![bus.map_or_else(|| verdict.clone(), |bus| format!("{bus}: {verdict}"))];
    if h.lss_unconfigured > 0 {
        notes.push(format!(
            "{} device(s) without a node-id answered LSS (not judged; canctl lss assign numbers them)",
            h.lss_unconfigured
        ));
    }
    notes.extend(h.not_there.iter().map(|node| super::nodes::not_there_text(*node)));
    notes.extend(h.answered_on_repeat.iter().map(super::nodes::repeat_text));
    notes
}
