//! How `firmware status` and `firmware download` look to people.

use super::junit::{TestCase, TestSuite};
use super::report::{Human, Report};
use crate::ops::firmware::{
    Batch, DownloadEnd, DownloadReport, FirmwareError, State, StatusReport, Transfer, Unfinished, Where,
};

/// How a node's download ended, in a word, for its progress line.
pub(super) fn download_end_word(end: DownloadEnd) -> &'static str {
    match end {
        DownloadEnd::Skipped => "skipped",
        DownloadEnd::Done => "done",
        DownloadEnd::Interrupted => "interrupted",
        DownloadEnd::Failed => "failed",
    }
}

/// Where the device is, and what to do next, as canctl says it.
fn state_text(state: State) -> &'static str {
    match state {
        State::AlreadyRuns => {
            "it already runs the image (same identification): nothing written; --force downloads anyway"
        }
        State::OnTrial => {
            "it runs the image on trial: unconfirmed, its bootloader returns to the old program at the next reset"
        }
        State::At(Where::RunsImage) => "it runs the image",
        State::At(Where::Unchanged) => "nothing was changed on the device",
        State::At(Where::BootloaderWithProgram) => {
            "in its bootloader, its program intact; run the same command again, or write 1 to 0x1F51 to start it"
        }
        State::At(Where::BootloaderNoProgram) => "in its bootloader with no valid program; run the same command again",
        State::At(Where::Unknown) => {
            "the new program was started but has not shown that it runs; check it with canctl firmware status"
        }
    }
}

/// A download's failure as canctl says it: its message, then its remedy in canctl's terms.
pub(crate) fn firmware_error_text(e: &FirmwareError) -> String {
    match e {
        FirmwareError::Bus(e) => super::hints::library_error_text(e),
        e @ FirmwareError::StillBusy { .. } => format!("{e}{}", super::remedies::longer_busy_wait()),
        e => e.to_string(),
    }
}

fn unfinished_text(u: &Unfinished) -> String {
    match u {
        Unfinished::Failed(e) => firmware_error_text(e),
        u => u.to_string(),
    }
}

/// The report as JSON, the state worded.
fn report_json(r: &DownloadReport) -> serde_json::Value {
    let mut value = serde_json::to_value(r).expect("reports serialise");
    value["state"] = state_text(r.state).into();
    value
}

/// Milliseconds as seconds to the millisecond: `1.250 s`.
fn seconds(ms: u64) -> String {
    format!("{:.3} s", ms as f64 / 1000.0)
}

fn id_text(id: Option<u32>) -> String {
    id.map_or("-".into(), |v| format!("0x{v:08X}"))
}

impl Report for StatusReport {
    fn human(&self) -> Human {
        if self.programs.is_empty() {
            return Human::Line(format!("node {}: 0x1F51:0 says it has no program numbers", self.node));
        }
        let rows = self
            .programs
            .iter()
            .map(|p| {
                vec![
                    p.program.to_string(),
                    p.control.map_or("-".into(), |c| format!("{} {}", c.code(), c.state_meaning())),
                    id_text(p.software_id),
                    p.flash_status.map_or("-".into(), |s| format!("0x{:08X} {s}", s.raw)),
                ]
            })
            .collect();
        Human::Parts(vec![
            Human::Line(format!("node {}: programs (CiA 302-3)", self.node)),
            Human::Table {
                headers: vec!["program", "control (0x1F51)", "identification (0x1F56)", "flash status (0x1F57)"],
                rows,
                when_empty: false,
            },
        ])
    }
}

impl Report for DownloadReport {
    fn human(&self) -> Human {
        let head = format!(
            "node {}, program {}: {} bytes, identification 0x{:08X}",
            self.node, self.program, self.image_bytes, self.image_id
        );
        let rows = self.steps.iter().map(|s| vec![seconds(s.at_ms), s.step.describe().to_string()]).collect();
        let mut lines = vec![Human::Line(head), Human::Table { headers: vec!["at", "step"], rows, when_empty: false }];
        if let (Some(ms), Some(rate)) = (self.download_ms, self.bytes_per_second) {
            let how = match self.transfer {
                Some(Transfer::Segmented) => ", segmented (no block transfer)",
                Some(Transfer::Block) => ", block transfer",
                _ => "",
            };
            lines.push(Human::Line(format!("download: {}, {rate} bytes/s{how}", seconds(ms))));
        }
        if let Some(ms) = self.erase_ms {
            lines.push(Human::Line(format!("erase: {} ({} polls of 0x1F57 while busy)", seconds(ms), self.busy_polls)));
        }
        if let Some(s) = self.flash_status {
            lines.push(Human::Line(format!("flash status: 0x{:08X} {s}", s.raw)));
        }
        let (before, after) = (id_text(self.id_before), id_text(self.id_after));
        lines.push(Human::Line(format!("identification: {before} before, {after} after")));
        let end = match (self.interrupted, self.skipped, self.device) {
            (true, ..) => "interrupted",
            (_, true, _) => "skipped",
            (.., Where::RunsImage) => "done",
            _ => "failed",
        };
        lines.push(Human::Line(format!("{end} in {}: {}", seconds(self.total_ms), state_text(self.state))));
        Human::Parts(lines)
    }

    fn json_value(&self) -> serde_json::Value {
        report_json(self)
    }
}

impl Report for Batch {
    fn human(&self) -> Human {
        let mut parts = Vec::new();
        for n in &self.nodes {
            if let Some(r) = &n.report {
                parts.push(r.human());
            }
            // Under its report the node is named already (and most errors name it too).
            match (&n.error, &n.report) {
                (Some(e), Some(_)) => parts.push(Human::Line(unfinished_text(e))),
                (Some(e), None) => parts.push(Human::Line(format!("node {}: {}", n.node, unfinished_text(e)))),
                (None, _) => {}
            }
        }
        let rows = self
            .nodes
            .iter()
            .map(|n| {
                let state = n.report.as_ref().map_or("not begun", |r| state_text(r.state));
                let result = match (&n.error, &n.report) {
                    (None, Some(r)) if r.skipped => "skipped",
                    (None, _) => "done",
                    (Some(_), Some(r)) if r.interrupted => "interrupted",
                    (Some(_), None) => "not begun",
                    _ => "failed",
                };
                vec![n.node.to_string(), result.to_string(), state.to_string()]
            })
            .collect();
        parts.push(Human::Table { headers: vec!["node", "result", "the device"], rows, when_empty: false });
        Human::Parts(parts)
    }

    fn junit(&self) -> Option<TestSuite> {
        let cases = self
            .nodes
            .iter()
            .map(|n| {
                let class = format!("node {}", n.node);
                let detail = n.report.as_ref().map_or("not begun", |r| state_text(r.state)).to_string();
                TestCase {
                    failure: n.error.as_ref().map(|e| format!("{class}: {}; {detail}", unfinished_text(e))),
                    class,
                    name: "firmware download".into(),
                    detail,
                }
            })
            .collect();
        Some(TestSuite { name: "canctl firmware download".into(), cases })
    }

    fn json_value(&self) -> serde_json::Value {
        let mut value = serde_json::to_value(self).expect("reports serialise");
        for (k, n) in self.nodes.iter().enumerate() {
            if let Some(r) = &n.report {
                value["nodes"][k]["report"] = report_json(r);
            }
            if let Some(e) = &n.error {
                value["nodes"][k]["error"] = unfinished_text(e).into();
            }
        }
        value
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ops::firmware::NodeDownload;
    use std::time::Duration;

    fn report(node: u8, state: State) -> DownloadReport {
        DownloadReport { device: Where::BootloaderNoProgram, state, ..DownloadReport::begun(node, 1, 10, 1) }
    }

    /// A batch says each node's failure with its remedy, and where each device is, in
    /// canctl's words, as it did when the library stored them as text.
    #[test]
    fn a_batch_says_each_failure_with_its_remedy() {
        let busy = FirmwareError::StillBusy {
            node: 5,
            program: 1,
            after: "the clear",
            polls: 9,
            waited: Duration::from_secs(1),
        };
        let batch = Batch {
            nodes: vec![
                NodeDownload {
                    node: 5,
                    report: Some(report(5, State::At(Where::BootloaderNoProgram))),
                    error: Some(Unfinished::Failed(busy)),
                },
                NodeDownload { node: 6, report: None, error: Some(Unfinished::NotBegun) },
            ],
            interrupted: true,
        };
        let json = batch.json_value();
        assert_eq!(
            json["nodes"][0]["error"],
            "node 5: the flash is still busy (0x1F57:1) 1 s after the clear, 9 polls; the device may need longer: give \
             --busy-wait"
        );
        assert_eq!(
            json["nodes"][0]["report"]["state"],
            "in its bootloader with no valid program; run the same command again"
        );
        assert_eq!(json["nodes"][1]["error"], "not begun: interrupted");
        let Human::Parts(parts) = batch.human() else { panic!("parts") };
        assert!(matches!(&parts[1], Human::Line(l) if l.ends_with("give --busy-wait")));
    }
}
