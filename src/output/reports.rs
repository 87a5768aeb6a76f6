//! How the reports of settings, store/restore, config and the simulator look to people.

use super::{Human, Report};
use crate::settings::SettingsReport;

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
        Human::Table { headers: vec!["setting", "value", "from"], rows, when_empty: true }
    }

    fn notes(&self) -> Vec<String> {
        if !self.files.is_empty() {
            return Vec::new();
        }
        let user = crate::settings::user_file().map_or("(no home directory)".to_string(), |p| p.display().to_string());
        vec![format!("no settings file: canctl.toml here or in a parent directory, or {user}")]
    }
}
