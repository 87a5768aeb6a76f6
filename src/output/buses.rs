//! `canctl buses`: a table of the buses found, each with the `--bus` value that reaches it.

use super::report::{Human, Report};
use crate::ops::buses::{BusKind, Buses};

/// What `buses` is doing while it listens, for the line that moves meanwhile.
pub(crate) fn listening(wait: std::time::Duration) -> String {
    format!("buses: listening for socketcand beacons for {wait:?}")
}

fn kind(k: BusKind) -> &'static str {
    match k {
        BusKind::CanInterface => "CAN interface",
        BusKind::Slcan => "slcan adapter",
        BusKind::Epos2Usb => "EPOS2 (USB)",
        BusKind::Socketcand => "socketcand",
    }
}

impl Report for Buses {
    fn human(&self) -> Human {
        match self.buses.is_empty() {
            true => Human::Parts(vec![
                Human::Line("no bus found".into()),
                Human::Note("try canctl --bus sim scan, the built-in simulated network".into()),
            ]),
            false => self.csv(),
        }
    }

    /// CSV is the table, its header row alone when nothing was found: a sentence would be
    /// read as a row.
    fn csv(&self) -> Human {
        let rows = self.buses.iter().map(|b| vec![b.bus.clone(), kind(b.kind).into(), b.what.clone()]).collect();
        Human::table(&["--bus", "kind", "what"], rows)
    }

    fn notes(&self) -> Vec<String> {
        let mut notes = Vec::new();
        if let Some(why) = &self.not_listened {
            notes.push(format!(
                "socketcand beacons not listened for: UDP port {} could not be opened ({why}); is another \
                 discovery (python-can, another canctl buses) running?",
                self.beacon_port
            ));
        } else if !self.buses.iter().any(|b| b.kind == BusKind::Socketcand) {
            notes.push(format!(
                "no socketcand beacon heard in {} ms (a server sends one every 3 s; listen longer with --wait 10s; \
                 a server behind a router or a tunnel is not heard: give --bus socketcand:HOST/IFACE)",
                self.listened_ms
            ));
        }
        if !self.other_serial_ports.is_empty() {
            notes.push(format!(
                "other serial ports: {} (an EPOS2 on RS232: --bus epos2-rs232:PORT)",
                self.other_serial_ports.join(", ")
            ));
        }
        if self.interrupted {
            notes.push("interrupted: listened for beacons for a shorter time".into());
        }
        notes
    }
}
