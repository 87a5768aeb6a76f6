//! A whole network from one CiA 306-3 project (`nodelist.cpj` plus one DCF per node):
//! [`dump`] a live bus into one, [`check`] a bus against one, [`apply`] one to a bus.

pub use super::lss::LssTally;
pub use super::project_files::PROJECT_FILE;

mod apply;
mod baud;
mod check;
mod dump;
mod parallel;
mod project;
pub(crate) mod report;

pub use apply::*;
pub use baud::*;
pub use check::*;
pub use dump::*;
pub use project::{load, Listed, LoadWarning, Loaded};
pub use report::{NodeApplied, NodeCheck, NodeResult, Outcome};

#[cfg(test)]
mod tests {
    use super::project::probe;
    use super::*;
    use crate::bus::Bus;
    use crate::cancel::Cancel;
    use crate::connect::{BusAddr, OpenOptions};
    use crate::error::Error;
    use crate::ops::config;
    use crate::ops::progress::Progress;
    use crate::ops::unmet::{Shortfall, Unmet};
    use std::path::Path;
    use std::time::Duration;

    #[test]
    fn a_project_warning_shows_its_file_and_line() {
        use crate::od::lint::{Kind, Warning};
        let dcf = LoadWarning::Dcf(Warning::new("node5.dcf", 12, Kind::RepeatedKey, "DefaultValue given twice".into()));
        assert_eq!(dcf.to_string(), "node5.dcf:12: DefaultValue given twice");
        let project = LoadWarning::Project("nodelist.cpj: no Nodes= key in [Topology]".into());
        assert_eq!(project.to_string(), "nodelist.cpj: no Nodes= key in [Topology]");
    }

    fn demo() -> Box<dyn Bus> {
        let mut opts = OpenOptions::new(Duration::from_millis(500));
        opts.ephemeral = true;
        crate::connect::open(&"sim".parse::<BusAddr>().unwrap(), &opts).unwrap()
    }

    fn example() -> Loaded {
        load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/sim-machine/nodelist.cpj")).unwrap()
    }

    /// Sets the stop flag once `after` nodes are done (or begun, one after the other), in
    /// the applying phase (the probe before it has its own).
    struct StopAfter {
        flag: Cancel,
        after: u64,
        applying: bool,
    }

    impl Progress for StopAfter {
        fn start(&mut self, what: &str, _: u64) {
            self.applying = what == "applying";
        }
        fn advance(&mut self, done: u64) {
            if self.applying && done >= self.after {
                self.flag.cancel();
            }
        }
    }

    /// Sets the flag once the probe before the switch is over.
    struct StopAfterProbe(Cancel);

    impl Progress for StopAfterProbe {
        fn finish(&mut self) {
            self.0.cancel();
        }
    }

    fn set_baud_options(flag: &Cancel) -> SetBaudOptions {
        SetBaudOptions {
            timeout: Duration::from_millis(200),
            window: Duration::from_millis(100),
            index: 3,
            delay_ms: 5,
            store: false,
            force: true,
            interrupted: flag.clone(),
        }
    }

    /// Interrupted before the activation, nothing is switched: every device back in waiting
    /// state at the old rate, the run reported as interrupted.
    #[test]
    fn set_baud_interrupted_before_the_activation_switches_nothing() {
        let flag = Cancel::new();
        let mut bus = demo();
        let report = set_baud(bus.as_mut(), None, &set_baud_options(&flag), &mut StopAfterProbe(flag.clone())).unwrap();
        assert!(!report.activated);
        assert!(matches!(report.failure, Some(Shortfall::Failed(Error::Interrupted))));
        assert_eq!(report.configured.confirmed, 6, "the stepper refuses, the others confirm");
        let still: Vec<u8> =
            probe(bus.as_mut(), Duration::from_millis(100), &mut super::super::Silent).unwrap().into_keys().collect();
        assert_eq!(still, [1, 5, 10, 32]);
    }

    /// Forced past the stepper's refusal: the others switch, the bus with them, and the
    /// stepper is named as left behind.
    #[test]
    fn set_baud_names_the_node_left_behind() {
        let flag = Cancel::new();
        let mut bus = demo();
        let report = set_baud(bus.as_mut(), None, &set_baud_options(&flag), &mut super::super::Silent).unwrap();
        assert!(report.activated && report.bus_followed);
        assert!(matches!(&report.failure, Some(Shortfall::Unmet(Unmet::NotFollowed { nodes, .. })) if nodes == &[32]));
        let after: Vec<(u8, Option<bool>)> = report.nodes.iter().map(|n| (n.node, n.after)).collect();
        assert_eq!(after, [(1, Some(true)), (5, Some(true)), (10, Some(true)), (32, Some(false))]);
    }

    /// An interruption stops between nodes, one after the other or several at once: the
    /// nodes under way finish, the others are reported as not begun, and the run ends as
    /// interrupted.
    #[test]
    fn an_interruption_stops_between_nodes_and_says_which_were_not_done() {
        for jobs in [1, 2] {
            let flag = Cancel::new();
            let loaded = example();
            let mut o = ApplyOptions {
                config: config::ApplyOptions::new(Duration::from_millis(500)),
                assign: false,
                window: Duration::from_millis(100),
                boot_wait: Duration::from_secs(1),
                jobs,
                reset: false,
                interrupted: flag.clone(),
            };
            o.config.verify = true;
            let mut bus = demo();
            let report = apply(bus.as_mut(), &loaded, &o, &mut StopAfter { flag, after: 1, applying: false }).unwrap();
            let done: Vec<u8> = report.nodes.iter().filter(|n| n.ok).map(|n| n.node).collect();
            let not_begun: Vec<u8> =
                report.nodes.iter().filter(|n| matches!(n.result, NodeResult::NotBegun)).map(|n| n.node).collect();
            // The demo network has nodes 1, 5, 10 and 32; 20 to 24 wait for --assign.
            assert_eq!(done, [1, 5], "--jobs {jobs}: {:?}", report.nodes.iter().map(|n| &n.result).collect::<Vec<_>>());
            assert_eq!(not_begun, [10, 32], "--jobs {jobs}");
            assert!(matches!(report.failure, Some(Shortfall::Failed(Error::Interrupted))));
            assert!(!report.ok);
        }
    }
}
