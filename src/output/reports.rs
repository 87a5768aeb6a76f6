//! How the reports of settings, store/restore, config, monitor and the simulator look to
//! people.

use super::report::{Human, Line, Report};
use super::text::time_of_day;
use crate::ops::config::{Applied, Change, Diff};
use crate::ops::monitor::{Event, Summary};
use crate::ops::store::{Restored, Stored};
use crate::settings::SettingsReport;
use serde_json::{json, Value as J};
use std::collections::BTreeMap;

impl Report for SettingsReport {
    fn human(&self) -> Human {
        let mut rows = vec![
            vec![
                "bus".into(),
                self.bus.clone().unwrap_or("(none)".into()),
                self.bus_from.clone().unwrap_or("-".into()),
            ],
            vec!["timeout".into(), format!("{} ms", self.timeout_ms), self.timeout_from.clone()],
        ];
        rows.extend(self.eds.iter().map(|e| vec![format!("eds ({})", e.node), e.file.clone(), e.from.clone()]));
        Human::table(&["setting", "value", "from"], rows)
    }

    fn notes(&self) -> Vec<String> {
        if !self.files.is_empty() {
            return Vec::new();
        }
        let user = crate::settings::user_file().map_or("(no home directory)".to_string(), |p| p.display().to_string());
        vec![format!("no settings file: canctl.toml here or in a parent directory, or {user}")]
    }
}

impl Report for crate::sim::serve::Reset {
    fn human(&self) -> Human {
        let faults = if self.faults.is_empty() { String::new() } else { format!(", faults {}", self.faults.join(" ")) };
        let clock = if self.virtual_time { ", on virtual time" } else { "" };
        let boot = self.bootloader.map(|n| format!(", a CiA 302-3 bootloader on node {n}")).unwrap_or_default();
        Human::Line(format!(
            "sim network reset ({}): profile {}, {}bit/s, {} device(s) without a node-id{boot}, seed {}{faults}{clock}",
            self.state_file, self.profile, self.bit_rate, self.unconfigured, self.seed
        ))
    }
}

/// The reports of one command run on several nodes, in order: a JSON array, and each
/// node's report for people.
#[derive(serde::Serialize)]
#[serde(transparent)]
pub struct Each<R>(pub Vec<R>);

impl<R: Report> Report for Each<R> {
    fn human(&self) -> Human {
        Human::Parts(self.0.iter().map(Report::human).collect())
    }

    /// Each report's JSON, as canctl words it.
    fn json_value(&self) -> J {
        J::Array(self.0.iter().map(Report::json_value).collect())
    }
}

/// A report that is one sentence, as that sentence.
pub fn sentence(report: &impl Report) -> Option<String> {
    match report.human() {
        Human::Line(text) => Some(text),
        _ => None,
    }
}

impl Report for Stored {
    fn human(&self) -> Human {
        Human::Line(format!("node {}: {} stored ({})", self.node, self.class.text(), self.object))
    }
}

impl Report for Restored {
    /// As it serialises, with why a reset is not confirmed in words.
    fn json_value(&self) -> J {
        let mut v = serde_json::to_value(self).expect("reports serialise");
        if let Some(why) = &self.reset_unconfirmed {
            v["reset_unconfirmed"] = super::nodes::unconfirmed_text(why).into();
        }
        v
    }

    fn human(&self) -> Human {
        let (node, class, addr) = (self.node, self.class.text(), self.object);
        Human::Line(match (&self.reset_unconfirmed, self.reset) {
            (Some(why), _) => format!(
                "node {node}: {class} back to defaults ({addr}); NMT reset sent, not confirmed: {}",
                super::nodes::unconfirmed_text(why)
            ),
            (None, true) => {
                format!("node {node}: {class} back to defaults ({addr}); the node was reset and booted with them")
            }
            (None, false) => {
                format!("node {node}: {class} will be back to defaults after the next reset ({addr}; --reset does it)")
            }
        })
    }
}

impl Report for Diff {
    fn human(&self) -> Human {
        let rows = self
            .differences
            .iter()
            .map(|d| vec![d.object.to_string(), d.name.clone(), d.device.clone(), d.file.clone()]);
        Human::Table { headers: vec!["object", "name", "device", "file"], rows: rows.collect(), when_empty: false }
    }

    fn notes(&self) -> Vec<String> {
        let mut notes = vec![format!(
            "node {}: {} object(s) differ from {}, {} match",
            self.node,
            self.differences.len(),
            self.file,
            self.same
        )];
        if !self.other_device.is_empty() {
            notes.push(format!(
                "warning: {} is for another device ({}); config apply refuses it without --force",
                self.file,
                self.other_device.join(", ")
            ));
        }
        if self.interrupted {
            notes.push(format!(
                "diff interrupted, incomplete: {} object(s) not compared; nothing was changed on the device",
                self.not_compared
            ));
        }
        notes
    }
}

impl Report for Applied {
    fn human(&self) -> Human {
        if self.objects.is_empty() && !self.interrupted {
            // A header over no rows says nothing: say so in words.
            return Human::Line(format!("nothing to change: node {} already matches {}", self.node, self.file));
        }
        self.csv()
    }

    /// One row per object: the same in the table and in CSV (which shows its header alone
    /// when there are none).
    fn csv(&self) -> Human {
        let row = |r: &Change| {
            let result = super::hints::change_result_text(&r.result);
            vec![r.object.to_string(), r.name.clone(), r.old.clone(), r.new.clone(), result]
        };
        let rows = self.objects.iter().map(row).collect();
        Human::Table { headers: vec!["object", "name", "old", "new", "result"], rows, when_empty: false }
    }

    fn json_value(&self) -> serde_json::Value {
        let mut value = serde_json::to_value(self).expect("reports serialise");
        super::hints::word_change_results(&mut value["objects"], &self.objects);
        if let Some(left) = &self.state {
            value["state"] = left_in_text(left).into();
        }
        value
    }

    fn notes(&self) -> Vec<String> {
        let mut notes = Vec::new();
        if self.stored {
            notes.push(format!("node {}: parameters stored (0x1010:1)", self.node));
        }
        notes.extend(self.incomplete().map(|i| incomplete_lines(&i)).unwrap_or_default());
        notes
    }
}

/// What a run that did not finish did and left ([`crate::ops::config::Incomplete`]): what was
/// written, what was not, what was put back, and the state the device is left in, a
/// sentence each.
pub(crate) fn incomplete_lines(incomplete: &crate::ops::config::Incomplete) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(cut) = &incomplete.cut {
        out.push(format!(
            "interrupted after {} write(s): written {}; not written {}",
            cut.written.len(),
            super::text::listed(&cut.written, "nothing"),
            super::text::listed(&cut.not_written, "nothing")
        ));
    }
    for pdo in &incomplete.rolled_back {
        out.push(format!("{pdo}: its change was under way; rolled back to its previous mapping and COB-ID"));
    }
    if !incomplete.to_fix.is_empty() {
        let fixes: Vec<String> = incomplete
            .to_fix
            .iter()
            .map(|f| format!("{} = {}", f.object, f.value.as_deref().unwrap_or("(previous value unknown)")))
            .collect();
        out.push(format!(
            "the rollback did not finish: to put the PDO back, write in this order {} (or run config apply again to finish the change)",
            fixes.join(", ")
        ));
    }
    out.extend(incomplete.state.as_ref().map(left_in_text));
    out
}

/// What a run that did not finish left the device holding, in a sentence.
pub(crate) fn left_in_text(left: &crate::ops::config::LeftIn) -> String {
    use crate::ops::config::LeftIn;
    let (node, new, of, interim, rolled_back, rollback_failed, store_asked) = match left {
        LeftIn::Unread { node } => {
            return format!("node {node} is as it was: interrupted while reading it, nothing was written")
        }
        LeftIn::Written { node, new, of, interim, rolled_back, rollback_failed, store_asked } => {
            (node, new, of, *interim, *rolled_back, *rollback_failed, *store_asked)
        }
    };
    let mut s = match (new.is_empty(), interim) {
        (true, false) => format!("node {node} is as it was before the run"),
        (true, true) => format!("node {node} holds none of the file's values"),
        (false, _) => format!(
            "node {node} holds the file's values for {} of {of} object(s) ({}), its previous values for the rest",
            new.len(),
            super::text::joined(new, ", ")
        ),
    };
    if rollback_failed || interim {
        s.push_str("; a PDO is left unusable: see the writes above");
    } else if rolled_back {
        s.push_str(" (the PDO that was being changed rolled back)");
    }
    if store_asked {
        s.push_str("; nothing stored: a reset brings back the stored parameters");
    }
    s.push_str(". config apply again finishes the change");
    s
}

/// What a person must read after a failed `config apply`, in every format (the JSON
/// document lists it too): what a dry run would stop at, or what was written before the
/// failure.
pub fn applied_failure_note(report: &Applied) -> Option<String> {
    report.failure.as_ref()?;
    if report.dry_run {
        return Some("dry run: a real run would stop at the refused write above; nothing was written".into());
    }
    if report.interrupted {
        return None;
    }
    Some(format!("written before the failure: {}", super::text::listed(&report.written, "nothing")))
}

impl Line for Event {
    const CSV_HEADER: &'static [&'static str] = &["time", "cob", "node", "kind", "text"];
    fn json(&self) -> J {
        let time = self.time_ms as f64 / 1000.0;
        let mut j = json!({ "time": time, "cob": format!("0x{:03X}", self.cob), "node": self.node, "kind": self.kind });
        if let (Some(o), J::Object(extra)) = (j.as_object_mut(), &self.fields) {
            o.extend(extra.clone());
        }
        j
    }

    fn csv(&self) -> String {
        let node = self.node.map_or(String::new(), |n| n.to_string());
        let time = self.time_ms as f64 / 1000.0;
        format!("{time:.3},0x{:03X},{node},{},\"{}\"", self.cob, self.kind, self.text.replace('"', "\"\""))
    }

    fn text(&self) -> String {
        let node = self.node.map_or("       ".to_string(), |n| format!("node {n:<2}"));
        format!("{}  {:03X}  {node}  {:<13} {}", time_of_day(self.time_ms), self.cob, self.kind, self.text)
    }
}

impl Line for Summary {
    const CSV_HEADER: &'static [&'static str] = &[];
    fn json(&self) -> J {
        let per_cob: BTreeMap<String, u64> = self.per_cob_id.iter().map(|(c, n)| (format!("0x{c:03X}"), *n)).collect();
        let mut summary =
            json!({ "frames": self.frames(), "per_cob_id": per_cob, "nodes": self.nodes, "emcy": self.emcy });
        if self.interrupted {
            summary["interrupted"] = J::Bool(true);
        }
        json!({ "summary": summary })
    }

    fn csv(&self) -> String {
        self.text()
    }

    fn text(&self) -> String {
        let cobs: Vec<String> = self.per_cob_id.iter().map(|(c, n)| format!("{c:03X}×{n}")).collect();
        format!(
            "{} frame(s) in {:.1} s; per COB-ID: {}; nodes seen: {}; EMCYs: {}",
            self.frames(),
            self.elapsed.as_secs_f64(),
            if cobs.is_empty() { "-".into() } else { cobs.join(" ") },
            super::text::listed(&self.nodes, "-"),
            self.emcy
        ) + if self.interrupted { " (interrupted; nothing was sent to the bus)" } else { "" }
    }
}

/// What `config eds` read and where it went, in one sentence.
pub fn stored_eds_line(e: &crate::ops::stored_eds::StoredEds) -> String {
    let what = e.objects.map_or_else(|| "which canctl cannot read".to_string(), |n| format!("{n} objects"));
    let form = match (e.format_given, e.format) {
        (false, _) => "plain text: the node has no 0x1022".to_string(),
        (true, crate::od::stored::PLAIN) => "plain text".to_string(),
        (true, _) => format!("{}, {} bytes stored", e.format_name, e.stored_bytes),
    };
    let file = e.saved_to.as_deref().unwrap_or("standard output");
    let mut line = format!("node {}: its EDS, {} bytes ({form}), {what}, saved to {file}", e.node, e.bytes);
    if let (Some(path), Some(_)) = (&e.saved_to, e.objects) {
        line.push_str(&format!("; use it with --eds {}={path}", e.node));
    }
    line
}

impl Report for crate::ops::stored_eds::StoredEds {
    fn human(&self) -> Human {
        Human::Line(stored_eds_line(self))
    }

    fn notes(&self) -> Vec<String> {
        self.unreadable.iter().map(|why| format!("warning: canctl cannot read it: {why}")).collect()
    }
}
