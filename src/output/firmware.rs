//! How `firmware status` and `firmware download` look to people.

use super::{Human, Report, TestCase, TestSuite};
use crate::ops::firmware::{Batch, DownloadReport, StatusReport, Where};

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
        let rows = self
            .steps
            .iter()
            .map(|s| vec![format!("{:.3} s", s.at_ms as f64 / 1000.0), s.step.describe().to_string()])
            .collect();
        let mut lines = vec![Human::Line(head), Human::Table { headers: vec!["at", "step"], rows, when_empty: false }];
        if let (Some(ms), Some(rate)) = (self.download_ms, self.bytes_per_second) {
            lines.push(Human::Line(format!("download: {:.3} s, {} bytes/s", ms as f64 / 1000.0, rate)));
        }
        if let Some(ms) = self.erase_ms {
            lines.push(Human::Line(format!(
                "erase: {:.3} s ({} polls of 0x1F57 while busy)",
                ms as f64 / 1000.0,
                self.busy_polls
            )));
        }
        if let Some(s) = self.flash_status {
            lines.push(Human::Line(format!("flash status: 0x{:08X} {s}", s.raw)));
        }
        lines.push(Human::Line(format!(
            "identification: {} before, {} after",
            id_text(self.id_before),
            id_text(self.id_after)
        )));
        let end = match (self.interrupted, self.skipped, self.device) {
            (true, ..) => "interrupted",
            (_, true, _) => "skipped",
            (.., Where::RunsImage) => "done",
            _ => "failed",
        };
        lines.push(Human::Line(format!("{end} in {:.3} s: {}", self.total_ms as f64 / 1000.0, self.state)));
        Human::Parts(lines)
    }
}

impl Report for Batch {
    fn human(&self) -> Human {
        let mut parts = Vec::new();
        for n in &self.nodes {
            if let Some(r) = &n.report {
                parts.push(r.human());
            }
            if let Some(e) = &n.error {
                parts.push(Human::Line(format!("node {}: {e}", n.node)));
            }
        }
        let rows = self
            .nodes
            .iter()
            .map(|n| {
                let state = n.report.as_ref().map_or("not begun", |r| r.state);
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
                let detail = n.report.as_ref().map_or("not begun".to_string(), |r| r.state.to_string());
                TestCase {
                    failure: n.error.as_ref().map(|e| format!("{class}: {e}; {detail}")),
                    class,
                    name: "firmware download".into(),
                    detail,
                }
            })
            .collect();
        Some(TestSuite { name: "canctl firmware download".into(), cases })
    }
}
