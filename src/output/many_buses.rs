//! One report of a command run on several buses: every bus's table merged into one with
//! a bus column, its sentences prefixed with the bus, JSON as one object per bus (each
//! with its `bus`), JUnit as one suite per bus. A single bus never comes here: its report
//! is the command's own, unchanged.

use super::junit::{TestCase, TestSuite};
use super::report::{Human, Report};
use crate::ops::many_buses::Ended;
use crate::ops::unmet::Shortfall;
use serde_json::{json, Value};

/// A bus's failure as shown: its message, the exit code it would have ended with alone,
/// and the bus its message begins with, when it names one
/// ([`crate::Error::names_bus`]).
struct Failure {
    text: String,
    exit_code: i32,
    names_bus: Option<String>,
}

impl Failure {
    fn of<R>(run: &Ended<R>) -> Option<Self> {
        let e = run.error.as_ref()?;
        // The commands run on several buses only read: a stop leaves every device as it was.
        let (text, names_bus) = match (e.is_interrupted(), &run.report) {
            (true, None) => {
                ("interrupted before its report was complete; nothing was changed on the devices".into(), None)
            }
            _ => shortfall_text(e),
        };
        Some(Self { text, exit_code: e.exit_code(), names_bus })
    }
}

/// A bus's shortfall as canctl says it, and the bus its words begin with, if they name one.
fn shortfall_text(e: &Shortfall) -> (String, Option<String>) {
    match e {
        Shortfall::Failed(e) => (super::hints::library_error_text(e), e.names_bus().map(str::to_string)),
        Shortfall::Unmet(u) => (u.to_string(), u.names_bus().map(str::to_string)),
        // One bus's run is never several buses'.
        Shortfall::OnBuses { worst, .. } => shortfall_text(worst),
    }
}

/// The reports of one command on several buses, in the order the buses were given.
pub(crate) struct OnBuses<'a, R> {
    /// The command as its JUnit suites name it: `canctl health`.
    pub command: &'static str,
    pub runs: &'a [Ended<R>],
}

impl<R: Report> serde::Serialize for OnBuses<'_, R> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.json_value().serialize(s)
    }
}

/// `part` with the bus's name before its sentences; its tables' rows, a bus column first,
/// go to `tables` (header, rows) instead.
fn prefixed(bus: &str, part: Human, tables: &mut Option<(Vec<&'static str>, Vec<Vec<String>>)>, out: &mut Vec<Human>) {
    match part {
        Human::Table { headers, rows, .. } => {
            let merged = tables.get_or_insert_with(|| ([&["bus"], &headers[..]].concat(), Vec::new()));
            merged.1.extend(rows.into_iter().map(|row| [vec![bus.to_string()], row].concat()));
        }
        Human::Line(text) => out.push(Human::Line(format!("{bus}: {text}"))),
        Human::Note(text) => out.push(Human::Note(format!("{bus}: {text}"))),
        Human::Parts(parts) => parts.into_iter().for_each(|p| prefixed(bus, p, tables, out)),
    }
}

impl<R: Report> OnBuses<'_, R> {
    /// Every bus's `shown` form, merged: the one table first, then the sentences.
    fn merged(&self, shown: impl Fn(&R) -> Human) -> Vec<Human> {
        let (mut table, mut lines) = (None, Vec::new());
        for run in self.runs {
            if let Some(report) = &run.report {
                prefixed(&run.bus, shown(report), &mut table, &mut lines);
            }
            // A bus with a report has its verdict in the report's own sentences.
            if let (None, Some(f)) = (&run.report, Failure::of(run)) {
                // A link's error names its bus itself.
                let text = match f.names_bus.as_deref() == Some(run.bus.as_str()) {
                    true => format!("{} (exit {})", f.text, f.exit_code),
                    false => format!("{}: {} (exit {})", run.bus, f.text, f.exit_code),
                };
                lines.push(Human::Line(text));
            }
        }
        let table = table.map(|(headers, rows)| Human::Table { headers, rows, when_empty: true });
        table.into_iter().chain(lines).collect()
    }
}

impl<R: Report> Report for OnBuses<'_, R> {
    fn human(&self) -> Human {
        Human::Parts(self.merged(R::human_among_buses))
    }

    fn csv(&self) -> Human {
        // CSV is the table alone: sentences are notes on stderr there.
        let note = |part| match part {
            Human::Line(text) => Human::Note(text),
            part => part,
        };
        Human::Parts(self.merged(R::csv).into_iter().map(note).collect())
    }

    fn notes(&self) -> Vec<String> {
        let runs = self.runs.iter().filter_map(|r| Some((&r.bus, r.report.as_ref()?)));
        runs.flat_map(|(bus, report)| report.notes_among_buses().into_iter().map(move |n| format!("{bus}: {n}")))
            .collect()
    }

    fn junit_suites(&self) -> Vec<TestSuite> {
        let mut suites = Vec::new();
        for run in self.runs {
            let name = format!("{}: {}", self.command, run.bus);
            let mut cases = run.report.as_ref().and_then(|r| r.junit()).map_or(Vec::new(), |s| s.cases);
            // A bus without a report (not opened, stopped) fails its suite by one case.
            if let (None, Some(f)) = (&run.report, Failure::of(run)) {
                let detail = format!("{} (exit {})", f.text, f.exit_code);
                cases.push(TestCase {
                    class: run.bus.clone(),
                    name: "bus".into(),
                    detail,
                    failure: Some(f.text.clone()),
                });
            }
            suites.push(TestSuite { name, cases });
        }
        suites
    }

    fn json_value(&self) -> Value {
        let buses = self.runs.iter().map(|run| {
            let mut value = match &run.report {
                Some(report) => report.json_value(),
                None => json!({}),
            };
            if let Value::Object(map) = &mut value {
                map.insert("bus".into(), run.bus.clone().into());
                if let Some(f) = Failure::of(run) {
                    map.insert("error".into(), f.text.into());
                    map.insert("exit_code".into(), f.exit_code.into());
                }
            }
            value
        });
        json!({ "buses": buses.collect::<Vec<_>>() })
    }
}

/// Progress of one bus of several, on stderr: each phase and notice a line prefixed with
/// the bus (bars of several threads would overwrite each other), phases only where bars
/// would be shown (a terminal, not --quiet).
pub(crate) struct BusNotes<'a> {
    pub out: &'a super::report::Output,
    pub bus: String,
}

impl crate::ops::Progress for BusNotes<'_> {
    fn start(&mut self, what: &str, _len: u64) {
        if self.out.progress {
            self.out.note(&format!("{}: {what}", self.bus));
        }
    }
    fn event(&mut self, event: crate::ops::Event) {
        self.out.note(&format!("{}: {}", self.bus, super::events::event_line(&event)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Serialize)]
    struct Nothing;

    impl Report for Nothing {
        fn human(&self) -> Human {
            Human::Parts(Vec::new())
        }
        fn junit(&self) -> Option<TestSuite> {
            None
        }
    }

    fn failed(bus: &str, error: impl Into<Shortfall>) -> Ended<Nothing> {
        Ended { bus: bus.into(), report: None, error: Some(error.into()) }
    }

    fn lines(runs: Vec<Ended<Nothing>>) -> Vec<String> {
        let Human::Parts(parts) = (OnBuses { command: "canctl health", runs: &runs }).human() else { panic!("parts") };
        parts.into_iter().map(|p| if let Human::Line(l) = p { l } else { panic!("a line only") }).collect()
    }

    /// A failure line names its bus once: not again when the error names that very bus, but
    /// when it names another (one whose name the first's begins) or merely begins alike.
    #[test]
    fn a_failure_is_prefixed_with_its_bus_unless_it_names_that_bus() {
        let unhealthy = |bus: &str| crate::ops::unmet::Unmet::Unhealthy {
            bus: bus.into(),
            total: 1,
            nodes: vec![crate::ops::unmet::NotHealthy { node: 5, failed: vec!["nmt"] }],
        };
        let state = crate::error::LinkError::StateFile {
            path: "/tmp/s.json".into(),
            what: "cannot save",
            detail: "full".into(),
            afresh: false,
        };
        let shown = lines(vec![
            failed("socketcan:vcan1", unhealthy("socketcan:vcan1")),
            failed("socketcan:vcan1", unhealthy("socketcan:vcan10")),
            failed("sim", crate::Error::from(state)),
        ]);
        assert_eq!(
            shown,
            [
                "socketcan:vcan1: 1 of 1 node(s) not healthy: node 5: nmt (exit 6)",
                "socketcan:vcan1: socketcan:vcan10: 1 of 1 node(s) not healthy: node 5: nmt (exit 6)",
                "sim: sim state file /tmp/s.json: cannot save: full (exit 5)",
            ]
        );
    }
}
