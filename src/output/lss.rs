//! How the LSS reports look to people and in CSV.

use super::{Human, Report};
use crate::ops::lss::{Activated, Assignment, Configured, Found, Inquired};

fn table(headers: Vec<&'static str>, row: Vec<String>) -> Human {
    Human::Table { headers, rows: vec![row], when_empty: true }
}

impl Report for Inquired {
    fn human(&self) -> Human {
        Human::Line(format!("{}  node-id {}", self.identity.0, self.node.map_or("none".to_string(), |n| n.to_string())))
    }
    fn csv(&self) -> Human {
        table(
            vec!["identity", "node"],
            vec![self.identity.0.to_string(), self.node.map_or(String::new(), |n| n.to_string())],
        )
    }
}

impl Report for Configured {
    fn human(&self) -> Human {
        match &self.tally {
            Some(t) if !t.refused.is_empty() => Human::Line(format!(
                "{}: {}: {}; the devices that confirmed have it",
                self.target,
                self.result,
                t.text()
            )),
            Some(t) => Human::Line(format!("{}: {} ({})", self.target, self.result, t.text())),
            None => Human::Line(format!("{}: {}", self.target, self.result)),
        }
    }
    fn notes(&self) -> Vec<String> {
        if !self.interrupted {
            return Vec::new();
        }
        let kept = match self.command {
            "store" => "it is stored",
            _ => "it holds until a reset or power-off; `canctl lss store` with the same target keeps it",
        };
        vec![format!("interrupted after the {} was confirmed: {kept}; nothing else was done", self.command)]
    }
    fn csv(&self) -> Human {
        table(vec!["command", "target", "result"], vec![self.command.into(), self.target.clone(), self.result.clone()])
    }
}

impl Report for Activated {
    fn human(&self) -> Human {
        let (who, bus) = (&self.devices, &self.bus);
        Human::Line(if self.bus_followed {
            format!(
                "configured bit rates activated on {who}; {bus} switched with them, and they are back in LSS waiting state"
            )
        } else {
            format!(
                "configured bit rates activated on {who}. Switch {bus} to the new rate too (e.g. sudo ip link set can0 \
                 down && sudo ip link set can0 up type can bitrate 250000); until an LSS command reaches them at the new \
                 rate the devices stay in LSS configuration state (every `canctl lss` command ends by sending them \
                 back to waiting)"
            )
        })
    }
}

impl Report for Found {
    fn human(&self) -> Human {
        let how = format!("found in {} steps, {} ms; {}", self.steps, self.elapsed_ms, self.pace.text());
        Human::Parts(vec![Human::Line(self.identity.0.to_string()), Human::Note(how)])
    }
    fn csv(&self) -> Human {
        let row = [
            self.identity.0.to_string(),
            self.steps.to_string(),
            self.step_ms.to_string(),
            self.elapsed_ms.to_string(),
        ];
        table(vec!["identity", "steps", "step_ms", "elapsed_ms"], row.into())
    }
}

impl Report for Assignment {
    fn json_value(&self) -> serde_json::Value {
        let mut value = serde_json::to_value(self).expect("reports serialise");
        if let Some(e) = &self.failure {
            value["error"] = crate::output::library_error_text(e).into();
        }
        value
    }
    fn human(&self) -> Human {
        if self.nothing_to_assign() {
            return Human::Line("no device without a node-id: nothing to assign".into());
        }
        self.csv()
    }
    fn csv(&self) -> Human {
        let stored = |d: &crate::ops::lss::AssignedNode| match (&d.store_error, d.stored) {
            (_, true) => "yes".to_string(),
            (e, false) => e.clone().unwrap_or_default(),
        };
        let rows = self.assigned.iter().map(|d| vec![d.identity.0.to_string(), d.node.to_string(), stored(d)]);
        Human::Table { headers: vec!["identity", "node", "stored"], rows: rows.collect(), when_empty: true }
    }
    fn notes(&self) -> Vec<String> {
        let mut notes = vec![format!(
            "{} device(s) given a node-id in {} ms ({} fastscan steps, {})",
            self.assigned.len(),
            self.elapsed_ms,
            self.fastscan_steps,
            self.pace.text()
        )];
        if self.interrupted {
            notes.push("interrupted: every LSS device was sent back to waiting state".into());
        }
        if let Some(crate::Error::NoFreeNodeId { identity, .. }) = &self.failure {
            let taken = |n: &u8| self.in_use_before.contains(n) || self.assigned.iter().any(|d| d.node == *n);
            let lower = match (1..=127u8).find(|n| !taken(n)) {
                Some(n) => format!("node-ids in use are skipped, and {n} is free"),
                None => "every node-id 1 to 127 is in use".to_string(),
            };
            notes.push(format!(
                "out of node-ids: {identity} (and any device after it) still has none, the devices above keep \
                 theirs; {lower}"
            ));
        }
        notes
    }
}
