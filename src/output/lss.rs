//! How the LSS reports look to people and in CSV.

use super::report::{Human, Report};
use crate::ops::lss::NotStored;
use crate::ops::lss::{Activated, Assignment, Configured, Found, Inquired, LssTally, PaceUsed, Took};

impl Report for Inquired {
    fn human(&self) -> Human {
        Human::Line(format!("{}  node-id {}", self.identity.0, self.node.map_or("none".to_string(), |n| n.to_string())))
    }
    fn csv(&self) -> Human {
        let node = self.node.map_or(String::new(), |n| n.to_string());
        Human::table(&["identity", "node"], vec![vec![self.identity.0.to_string(), node]])
    }
}

/// What a configuration service gave, and what makes it take effect, as canctl says it.
fn took_text(took: Took) -> String {
    use crate::canopen::lss::bit_rate_name;
    const EPOS2_TAKES_EFFECT: &str = "in force only after `canctl lss store --node 0` and a power cycle of the EPOS2 \
                                      (until then it keeps the old one)";
    match took {
        Took::NodeId(id) => format!("node-id {id}"),
        Took::NoNodeId => "node-id removed (255)".into(),
        Took::BitRate(index) => {
            format!("bit rate {} (active after `lss activate`, or after store and a reset)", bit_rate_name(index))
        }
        Took::Stored => "LSS configuration stored".into(),
        Took::Epos2NodeId(id) => format!("node-id {id} written to object 0x2000; {EPOS2_TAKES_EFFECT}"),
        Took::Epos2BitRate { index, code } => {
            format!("CAN bit rate {} written to object 0x2001 (= {code}); {EPOS2_TAKES_EFFECT}", bit_rate_name(index))
        }
        Took::Epos2Stored => "parameters stored (0x1010:1)".into(),
    }
}

impl Report for Configured {
    fn human(&self) -> Human {
        let result = took_text(self.result);
        match &self.tally {
            Some(t) if !t.refused.is_empty() => {
                Human::Line(format!("{}: {result}: {}; the devices that confirmed have it", self.target, tally_text(t)))
            }
            Some(t) => Human::Line(format!("{}: {result} ({})", self.target, tally_text(t))),
            None => Human::Line(format!("{}: {result}", self.target)),
        }
    }
    fn json_value(&self) -> serde_json::Value {
        let mut value = serde_json::to_value(self).expect("reports serialise");
        value["result"] = took_text(self.result).into();
        value
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
        let row = vec![self.command.into(), self.target.clone(), took_text(self.result)];
        Human::table(&["command", "target", "result"], vec![row])
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
        let how = format!("found in {} steps, {} ms; {}", self.steps, self.elapsed_ms, pace_text(&self.pace));
        Human::Parts(vec![Human::Line(self.identity.0.to_string()), Human::Note(how)])
    }
    fn csv(&self) -> Human {
        let (steps, step_ms, elapsed_ms) =
            (self.steps.to_string(), self.step_ms.to_string(), self.elapsed_ms.to_string());
        Human::table(
            &["identity", "steps", "step_ms", "elapsed_ms"],
            vec![vec![self.identity.0.to_string(), steps, step_ms, elapsed_ms]],
        )
    }
}

/// Why a device `assign` numbered may not keep its node-id, with what settles it.
fn not_stored_text(why: &NotStored) -> String {
    match why {
        NotStored::NoAnswer { identity, .. } => {
            format!("{why} (canctl lss store --identity {identity} stores it again)")
        }
        NotStored::Failed(e) => super::hints::library_error_text(e),
        _ => why.to_string(),
    }
}

impl Report for Assignment {
    fn json_value(&self) -> serde_json::Value {
        let mut value = serde_json::to_value(self).expect("reports serialise");
        if let Some(e) = &self.failure {
            value["error"] = super::hints::library_error_text(e).into();
        }
        for (k, d) in self.assigned.iter().enumerate() {
            if let Some(e) = &d.store_error {
                value["assigned"][k]["store_error"] = not_stored_text(e).into();
            }
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
            (e, false) => e.as_ref().map(not_stored_text).unwrap_or_default(),
        };
        let rows = self.assigned.iter().map(|d| vec![d.identity.0.to_string(), d.node.to_string(), stored(d)]);
        Human::table(&["identity", "node", "stored"], rows.collect())
    }
    fn notes(&self) -> Vec<String> {
        let mut notes = vec![format!(
            "{} device(s) given a node-id in {} ms ({} fastscan steps, {})",
            self.assigned.len(),
            self.elapsed_ms,
            self.fastscan_steps,
            pace_text(&self.pace)
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

/// The pace a search used: its step and the slowest answer.
fn pace_text(pace: &PaceUsed) -> String {
    match pace.slowest_answer_ms {
        Some(s) => format!("step {} ms (slowest answer {s:.1} ms)", pace.step_ms),
        None => format!("step {} ms", pace.step_ms),
    }
}

/// How the devices answered a global LSS service: "3 device(s) confirmed, 1 refused (...)".
pub(crate) fn tally_text(t: &LssTally) -> String {
    match t.refused.len() {
        0 => format!("{} device(s) confirmed", t.confirmed),
        n => format!("{} device(s) confirmed, {n} refused ({})", t.confirmed, t.refused.join("; ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canopen::lss::Identity;
    use crate::ops::lss::{AssignedNode, Identified, PaceUsed};

    fn assigned(node: u8, store_error: Option<NotStored>) -> AssignedNode {
        let identity = Identity { vendor: 1, product: 2, revision: 3, serial: u32::from(node) };
        AssignedNode { identity: Identified(identity), node, stored: store_error.is_none(), store_error }
    }

    /// A store that went unanswered says how to settle it, in the table and in JSON, as
    /// it did when the library wrote the sentence.
    #[test]
    fn an_unanswered_store_says_how_to_store_again() {
        let identity = Identity { vendor: 1, product: 2, revision: 3, serial: 6 };
        let report = Assignment {
            assigned: vec![
                assigned(5, None),
                assigned(6, Some(NotStored::NoAnswer { node: 6, identity })),
                assigned(7, Some(NotStored::NotAsked)),
            ],
            in_use_before: vec![],
            fastscan_steps: 0,
            step_ms: 0,
            pace: PaceUsed { step_ms: 0, slowest_answer_ms: None, escalations: 0 },
            elapsed_ms: 0,
            interrupted: false,
            failure: None,
        };
        let said = "no answer to the store: unknown whether node 6 keeps its id across a power cycle \
                    (canctl lss store --identity 0x00000001:0x00000002:0x00000003:0x00000006 stores it again)";
        let Human::Table { rows, .. } = report.csv() else { panic!("a table") };
        let stored: Vec<&str> = rows.iter().map(|r| r[2].as_str()).collect();
        assert_eq!(stored, ["yes", said, "not asked"]);
        let json = report.json_value();
        assert_eq!(json["assigned"][0]["store_error"], serde_json::Value::Null);
        assert_eq!(json["assigned"][1]["store_error"], said);
        assert_eq!(json["assigned"][2]["store_error"], "not asked");
        // The library's own words name no flag.
        assert!(!NotStored::NoAnswer { node: 6, identity }.to_string().contains("--"));
    }

    #[test]
    fn what_a_configuration_gave_says_what_makes_it_count() {
        assert_eq!(took_text(Took::NodeId(40)), "node-id 40");
        let epos2 = took_text(Took::Epos2BitRate { index: 4, code: 4 });
        assert_eq!(
            epos2,
            "CAN bit rate 125k written to object 0x2001 (= 4); in force only after `canctl lss store --node 0` and a \
             power cycle of the EPOS2 (until then it keeps the old one)"
        );
    }
}
