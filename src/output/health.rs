//! How the error history and the health report look: tables for people, JUnit for CI.

use super::{Human, Report};
use crate::ops::errors::ErrorHistory;

fn node_label(node: u8, name: Option<&str>) -> String {
    match name {
        Some(n) if !n.is_empty() => format!("node {node} ({n})"),
        _ => format!("node {node}"),
    }
}

/// `0x81 (generic, manufacturer)`, `0x00`, or `-` when unread.
pub(crate) fn register_text(register: Option<u8>) -> String {
    match register {
        None => "-".into(),
        Some(0) => "0x00".into(),
        Some(r) => format!("0x{r:02X} ({})", crate::canopen::emcy::register_bits(r).join(", ")),
    }
}

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
        let who = node_label(self.node, self.name.as_deref());
        let register = format!("error register {}", register_text(self.error_register));
        if !self.kept {
            return Human::Line(format!("{who} keeps no error history (it has no object 0x1003); {register}"));
        }
        let mut parts = vec![Human::Line(match self.count {
            Some(0) | None => format!("{who}: no errors logged in 0x1003; {register}"),
            Some(n) => format!("{who}: {n} error(s) logged in 0x1003, newest first; {register}"),
        })];
        let rows = self
            .entries
            .iter()
            .map(|e| {
                vec![
                    e.sub.to_string(),
                    format!("0x{:04X}", e.code),
                    format!("0x{:04X}", e.manufacturer),
                    e.meaning.to_string(),
                    source_text(e.source).to_string(),
                ]
            })
            .collect();
        parts.push(Human::Table { headers: vec!["#", "code", "mfr", "meaning", "from"], rows, when_empty: false });
        parts.extend(
            self.unreadable.iter().map(|u| Human::Note(format!("0x1003:{} could not be read: {}", u.sub, u.error))),
        );
        if self.cleared {
            parts.push(Human::Line(format!("{who}: error history cleared (0x1003:0 reads back 0)")));
        }
        Human::Parts(parts)
    }

    fn csv(&self) -> Human {
        let rows = self
            .entries
            .iter()
            .map(|e| {
                vec![
                    self.node.to_string(),
                    e.sub.to_string(),
                    e.raw.to_string(),
                    format!("0x{:04X}", e.code),
                    format!("0x{:04X}", e.manufacturer),
                    e.meaning.to_string(),
                    source_text(e.source).to_string(),
                ]
            })
            .collect();
        Human::Table {
            headers: vec!["node", "sub", "raw", "code", "manufacturer", "meaning", "source"],
            rows,
            when_empty: true,
        }
    }
}
