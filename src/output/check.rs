//! `config check`: each deviation as compilers show theirs, `file:line: severity: what`,
//! then the rule it breaks; a summary line last.

use super::report::{Human, Report};
use crate::ops::check::Checked;

/// What `value` is called in JSON (a unit variant's name there).
fn json_name(value: impl serde::Serialize) -> String {
    serde_json::to_value(value).ok().and_then(|v| v.as_str().map(String::from)).unwrap_or_default()
}

impl Report for Checked {
    fn human(&self) -> Human {
        let mut parts: Vec<Human> = self
            .findings
            .iter()
            .map(|w| {
                let severity = match w.severity {
                    crate::od::lint::Severity::Error => "error",
                    crate::od::lint::Severity::Warning => "warning",
                };
                let place = if w.line == 0 { w.path.clone() } else { format!("{}:{}", w.path, w.line) };
                let rule = if w.rule.is_empty() { String::new() } else { format!("\n    {}", w.rule) };
                Human::Line(format!("{place}: {severity}: {}{rule}", w.message))
            })
            .collect();
        let summary = match self.verdict {
            "refused" => format!("{}: not read as an {}", self.file, self.format),
            _ => format!(
                "{}: {}, {} objects ({} entries) read; {} error(s), {} warning(s)",
                self.file, self.format, self.objects, self.entries, self.errors, self.warnings
            ),
        };
        parts.push(Human::Line(summary));
        Human::Parts(parts)
    }

    fn csv(&self) -> Human {
        let rows = self
            .findings
            .iter()
            .map(|w| {
                vec![
                    w.path.clone(),
                    w.line.to_string(),
                    json_name(w.severity),
                    json_name(w.kind),
                    w.message.clone(),
                    w.rule.to_string(),
                ]
            })
            .collect();
        Human::table(&["file", "line", "severity", "kind", "message", "rule"], rows)
    }
}
