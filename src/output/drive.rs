//! How `drive status`, `drive enable|disable|quick-stop|fault-reset` and `drive status
//! --watch` look to people.

use super::report::{Human, Line, Report};
use crate::ops::drive::{state_text, Change, Source, Status, Walk};
use serde_json::{json, Value as J};

/// Bits 12–15 depend on the mode or the manufacturer: shown only when set.
const ALWAYS_SHOWN_BITS: u8 = 12;

impl Report for Status {
    fn human(&self) -> Human {
        let mut parts = vec![Human::Line(format!(
            "node {}: {} (statusword 0x{:04X}; device type 0x{:08X})",
            self.node,
            self.state_name(),
            self.statusword,
            self.device_type
        ))];
        let rows = self
            .flags
            .iter()
            .filter(|f| f.bit < ALWAYS_SHOWN_BITS || f.set)
            .map(|f| vec![f.bit.to_string(), f.name.to_string(), if f.set { "yes" } else { "no" }.to_string()])
            .collect();
        parts.push(Human::table(&["bit", "flag", "set"], rows));
        parts.push(Human::Line(match &self.mode {
            Some(m) => {
                format!("mode of operation: {} {} ({})", m.value, m.name.unwrap_or("(not a CiA 402 mode)"), m.from)
            }
            None => "mode of operation: not available (no 0x6061 or 0x6060)".into(),
        }));
        let bits = super::text::listed(&self.error_register_bits, "no error");
        parts.push(Human::Line(format!("error register (0x1001): 0x{:02X} {bits}", self.error_register)));
        match &self.errors {
            None => parts.push(Human::Line("error history: none kept (no 0x1003)".into())),
            Some(e) if e.is_empty() => parts.push(Human::Line("error history (0x1003): empty".into())),
            Some(errors) => {
                parts.push(Human::Line(format!("error history (0x1003), newest first: {}", errors.len())));
                let rows = errors
                    .iter()
                    .enumerate()
                    .map(|(i, e)| {
                        vec![
                            (i + 1).to_string(),
                            format!("0x{:04X}", e.code),
                            e.meaning.to_string(),
                            format!("0x{:08X}", e.raw),
                        ]
                    })
                    .collect();
                parts.push(Human::Table { headers: vec!["#", "code", "meaning", "entry"], rows, when_empty: false });
            }
        }
        Human::Parts(parts)
    }

    fn csv(&self) -> Human {
        let rows = self.flags.iter().map(|f| vec![f.bit.to_string(), f.name.to_string(), f.set.to_string()]).collect();
        Human::table(&["bit", "flag", "set"], rows)
    }
}

impl Report for Walk {
    fn human(&self) -> Human {
        let node = self.node;
        let mut parts: Vec<Human> = self
            .transitions
            .iter()
            .map(|t| {
                let reached = state_text(t.reached, t.statusword);
                let arrow = if t.confirmed { reached } else { format!("still {reached}, not {}", t.expected) };
                Human::Line(format!("node {node}: {} (0x{:04X}): {} → {arrow}", t.command, t.controlword, t.from))
            })
            .collect();
        let state = state_text(self.state, self.statusword);
        let last = if self.done && self.transitions.is_empty() {
            format!("node {node}: already {state} (statusword 0x{:04X}); nothing to do", self.statusword)
        } else if self.done {
            format!("node {node}: {state} (statusword 0x{:04X})", self.statusword)
        } else if self.interrupted {
            format!("node {node}: interrupted; the drive is left in {state} (statusword 0x{:04X})", self.statusword)
        } else if self.state.is_none() && self.stopped == Some(crate::error::DriveStop::NoAnswer) {
            // The last answer and the read back were lost: the statusword held is stale.
            format!("node {node}: stopped answering; its state is unknown (the last command may have taken effect): see `canctl drive status {node}`")
        } else {
            format!("node {node}: stopped in {state} (statusword 0x{:04X})", self.statusword)
        };
        parts.push(Human::Line(last));
        Human::Parts(parts)
    }

    fn csv(&self) -> Human {
        let rows = self
            .transitions
            .iter()
            .map(|t| {
                vec![
                    t.command.to_string(),
                    format!("0x{:04X}", t.controlword),
                    t.from.to_string(),
                    state_text(t.reached, t.statusword),
                    format!("0x{:04X}", t.statusword),
                    t.confirmed.to_string(),
                ]
            })
            .collect();
        Human::table(&["command", "controlword", "from", "reached", "statusword", "confirmed"], rows)
    }
}

impl Line for Change {
    const CSV_HEADER: &'static [&'static str] = &["time", "node", "statusword", "state", "source"];
    fn json(&self) -> J {
        json!({
            "time": self.time_ms as f64 / 1000.0,
            "node": self.node,
            "statusword": self.statusword,
            "state": self.state,
            "source": self.source,
        })
    }

    fn csv(&self) -> String {
        format!(
            "{:.3},{},0x{:04X},\"{}\",{}",
            self.time_ms as f64 / 1000.0,
            self.node,
            self.statusword,
            state_text(self.state, self.statusword),
            self.source
        )
    }

    fn text(&self) -> String {
        format!(
            "{}  node {}: {} (statusword 0x{:04X}, by {})",
            super::text::time_of_day(self.time_ms),
            self.node,
            state_text(self.state, self.statusword),
            self.statusword,
            self.source.to_uppercase()
        )
    }
}

/// Where `drive status --watch` reads the statusword from.
pub(crate) fn watching_text(node: u8, source: &Source) -> String {
    match source {
        Source::Tpdo { cob_id, .. } => format!("node {node}: watching the statusword in TPDO 0x{cob_id:03X}"),
        Source::Sdo(i) => format!("node {node}: reading the statusword by SDO every {} ms", i.as_millis()),
    }
}

/// The state `drive status --watch` saw last, said when it ends.
pub(crate) fn last_seen_text(node: u8, last: &Change) -> String {
    format!("node {node}: last seen {}", state_text(last.state, last.statusword))
}
