//! The controller's side of the diagnosis: its state and counters (SocketCAN's netlink
//! details) and the error frames it reported during the checks. Read only: doctor asks the
//! link what it knows, it never changes the interface.

use super::report::{Cause, ControllerState, Diagnosis, Evidence, Finding, HostProblem, Remedy};
use crate::bus::controller::{CanState, Controller, LinkReport};
use crate::bus::Bus;

/// Add what the link's controller report shows, after the other checks (the error
/// frames of their requests count too). Links that know nothing of the kind add nothing.
pub(super) fn examine(bus: &mut dyn Bus, d: &mut Diagnosis) {
    if let Some(report) = bus.link_report() {
        judge(&report, d);
    }
}

/// The findings (or the fine evidence) one report shows.
fn judge(r: &LinkReport, d: &mut Diagnosis) {
    let iface = r.iface.clone();
    if r.queue_full > 0 {
        let problem = HostProblem::TransmitQueueFull;
        let evidence = vec![Evidence::QueueFull { iface: iface.clone(), frames: r.queue_full }];
        add(d, Finding { cause: Cause::Host { problem }, evidence, remedy: Remedy::FixHost { problem } });
    }
    let mut evidence = Vec::new();
    let (state, restart_ms, bitrate) = match r.controller {
        Some(Controller::Can { state, tx_errors, rx_errors, restart_ms, bitrate }) => {
            let shown =
                Evidence::ControllerReport { iface: iface.clone(), state, tx_errors, rx_errors, restart_ms, bitrate };
            match state {
                Some(CanState::ErrorWarning | CanState::ErrorPassive | CanState::BusOff) => evidence.push(shown),
                _ => d.fine.push(shown),
            }
            (state, restart_ms, bitrate)
        }
        // No controller: no state to report, and none is made up.
        Some(Controller::Virtual) => {
            d.fine.push(Evidence::NoController { iface: iface.clone() });
            (None, None, None)
        }
        None => (None, None, None),
    };
    let counts = r.error_frames;
    if counts.frames > 0 {
        evidence.push(Evidence::ErrorFrames { iface: iface.clone(), counts });
    }
    let bus_off = state == Some(CanState::BusOff) || counts.bus_off > counts.restarted;
    // What destroyed or went unacknowledged says why; the state alone says only how bad.
    let (cause, remedy) = if counts.signal_errors() {
        (Cause::SignalErrors, Remedy::CheckBitRate { bitrate })
    } else if counts.only_ack() {
        (Cause::NothingAcknowledges, Remedy::CheckTermination)
    } else if bus_off {
        (Cause::Controller { state: ControllerState::BusOff }, Remedy::CheckBus)
    } else if evidence.is_empty() {
        return;
    } else {
        (Cause::Controller { state: ControllerState::BusErrors }, Remedy::CheckBus)
    };
    add(d, Finding { cause, evidence: evidence.clone(), remedy });
    // A controller that stays bus-off needs bringing back even once the cause is fixed.
    if bus_off && restart_ms == Some(0) {
        let cause = Cause::Controller { state: ControllerState::BusOff };
        add(d, Finding { cause, evidence, remedy: Remedy::AutoRestart { iface } });
    }
}

/// Add a finding, or merge it into the one with the same cause (the link's own bus-off
/// error): its evidence added, and a remedy more precise than checking the bus.
fn add(d: &mut Diagnosis, f: Finding) {
    match d.findings.iter_mut().find(|g| g.cause == f.cause) {
        Some(g) => {
            for e in f.evidence {
                if !g.evidence.contains(&e) {
                    g.evidence.push(e);
                }
            }
            if g.remedy == Remedy::CheckBus {
                g.remedy = f.remedy;
            }
        }
        None => d.findings.push(f),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::controller::{ErrorFrameCounts, CAN_ERR_FLAG};

    fn diagnosis() -> Diagnosis {
        Diagnosis { bus: "can0".into(), node: None, listened_ms: 0, findings: vec![], fine: vec![], ok: false }
    }

    fn can(state: CanState, restart_ms: u32) -> Option<Controller> {
        Some(Controller::Can {
            state: Some(state),
            tx_errors: Some(128),
            rx_errors: Some(0),
            restart_ms: Some(restart_ms),
            bitrate: Some(250_000),
        })
    }

    fn errors(frames: &[(u32, [u8; 8])]) -> ErrorFrameCounts {
        let mut c = ErrorFrameCounts::default();
        for (id, data) in frames {
            c.take(CAN_ERR_FLAG | id, data);
        }
        c
    }

    fn judged(controller: Option<Controller>, error_frames: ErrorFrameCounts) -> Diagnosis {
        let mut d = diagnosis();
        judge(&LinkReport { iface: "can0".into(), controller, error_frames, queue_full: 0 }, &mut d);
        d
    }

    #[test]
    fn vcan_is_reported_as_having_no_controller() {
        let d = judged(Some(Controller::Virtual), ErrorFrameCounts::default());
        assert!(d.findings.is_empty());
        assert_eq!(d.fine, vec![Evidence::NoController { iface: "can0".into() }]);
    }

    #[test]
    fn error_active_without_error_frames_is_fine() {
        let d = judged(can(CanState::ErrorActive, 0), ErrorFrameCounts::default());
        assert!(d.findings.is_empty());
        assert!(matches!(d.fine[..], [Evidence::ControllerReport { state: Some(CanState::ErrorActive), .. }]));
    }

    #[test]
    fn only_ack_errors_and_passive_say_nothing_acknowledges() {
        let d =
            judged(can(CanState::ErrorPassive, 100), errors(&[(0x020, [0; 8]), (0x004, [0, 0x20, 0, 0, 0, 0, 0, 0])]));
        assert_eq!(d.findings.len(), 1);
        assert_eq!(d.findings[0].cause, Cause::NothingAcknowledges);
        assert_eq!(d.findings[0].remedy, Remedy::CheckTermination);
        assert_eq!(d.findings[0].evidence.len(), 2);
    }

    #[test]
    fn stuff_errors_say_bit_rate_with_the_interfaces_rate() {
        let d = judged(can(CanState::ErrorWarning, 100), errors(&[(0x008, [0, 0, 0x04, 0x08, 0, 0, 0, 0])]));
        assert_eq!(d.findings[0].cause, Cause::SignalErrors);
        assert_eq!(d.findings[0].remedy, Remedy::CheckBitRate { bitrate: Some(250_000) });
    }

    #[test]
    fn bus_off_without_restart_ms_names_the_restart() {
        let d = judged(can(CanState::BusOff, 0), errors(&[(0x020, [0; 8]), (0x040, [0; 8])]));
        let causes: Vec<_> = d.findings.iter().map(|f| (&f.cause, &f.remedy)).collect();
        assert_eq!(
            causes,
            vec![
                (&Cause::NothingAcknowledges, &Remedy::CheckTermination),
                (&Cause::Controller { state: ControllerState::BusOff }, &Remedy::AutoRestart { iface: "can0".into() }),
            ]
        );
    }

    #[test]
    fn bus_off_with_restart_ms_needs_no_restart_command() {
        let d = judged(can(CanState::BusOff, 100), ErrorFrameCounts::default());
        assert_eq!(d.findings.len(), 1);
        assert_eq!(d.findings[0].remedy, Remedy::CheckBus);
    }

    #[test]
    fn the_links_bus_off_error_gets_the_controllers_evidence_and_remedy() {
        let mut d = diagnosis();
        let link = crate::error::LinkError::BusOff { iface: "can0".into(), detail: "bus off".into() };
        d.findings.push(super::super::link_finding(&link));
        let report = LinkReport {
            iface: "can0".into(),
            controller: can(CanState::BusOff, 0),
            error_frames: errors(&[(0x040, [0; 8])]),
            queue_full: 0,
        };
        judge(&report, &mut d);
        assert_eq!(d.findings.len(), 1);
        assert_eq!(d.findings[0].remedy, Remedy::AutoRestart { iface: "can0".into() });
        assert_eq!(d.findings[0].evidence.len(), 3);
    }

    #[test]
    fn frames_that_waited_for_the_queue_name_the_host() {
        let report = LinkReport {
            iface: "vcan0".into(),
            controller: Some(Controller::Virtual),
            error_frames: ErrorFrameCounts::default(),
            queue_full: 3,
        };
        let mut d = diagnosis();
        judge(&report, &mut d);
        let problem = HostProblem::TransmitQueueFull;
        assert_eq!(d.findings[0].cause, Cause::Host { problem });
        assert_eq!(d.findings[0].remedy, Remedy::FixHost { problem });
        assert_eq!(d.findings[0].evidence, vec![Evidence::QueueFull { iface: "vcan0".into(), frames: 3 }]);
    }
}
