//! A whole network from one CiA 306-3 project (`nodelist.cpj` plus one DCF per node):
//! [`dump`] a live bus into one, [`check`] a bus against one, [`apply`] one to a bus.

use super::back;
use super::config::{self, Dcf};
pub use super::lss::LssTally;
use super::progress::{ItemEnd, Progress};
use super::project_files::{check_inside, folder_of};
use crate::bus::lss::LssMaster;
use crate::bus::{Bus, LssWait};
use crate::cancel::Cancel;
use crate::canopen::lss::{Identity, Request};
use crate::canopen::ObjAddr;
use crate::error::{Error, ProjectProblem, Result, Service};
use crate::od::cpj::{self, Commissioning, Project};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

pub use super::project_files::PROJECT_FILE;

/// A project with each listed node's DCF read.
#[derive(Debug)]
#[non_exhaustive]
pub struct Loaded {
    /// The project file.
    pub(crate) file: PathBuf,
    /// The project as read.
    pub(crate) project: Project,
    /// The nodes it lists as present, with their DCFs.
    pub(crate) nodes: Vec<Listed>,
    /// What the files say that deserves a look, with file:line.
    pub warnings: Vec<LoadWarning>,
}

/// Something a project's files say that deserves a look (the project is used all the same).
#[derive(Debug, Clone)]
#[non_exhaustive]
pub enum LoadWarning {
    /// In the project file itself, as its reader words it.
    Project(String),
    /// In a node's DCF, with its file, line and rule.
    Dcf(crate::od::lint::Warning),
}

/// A project's warning in a line: file:line and what it says.
impl std::fmt::Display for LoadWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadWarning::Project(text) => f.write_str(text),
            LoadWarning::Dcf(w) => write!(f, "{w}"),
        }
    }
}

/// A node the project lists as present.
#[derive(Debug)]
#[non_exhaustive]
pub struct Listed {
    /// The node-id.
    pub(crate) node: u8,
    /// `NodeXName`, else the DCF's product name, else empty.
    pub name: String,
    /// Its DCF; none when the project names none.
    pub(crate) dcf: Option<Dcf>,
    /// What its DCF's commissioning section says (node-id, name, bit rate, LSS serial); all empty without a DCF.
    pub(crate) commissioning: Commissioning,
}

impl Listed {
    /// Its DCF's name as the project gives it; none when it names none.
    pub(crate) fn file(&self) -> Option<String> {
        self.dcf.as_ref().map(|d| d.path().to_string())
    }

    /// The identity an LSS device with this configuration answers to: the DCF's vendor-ID,
    /// product code and revision, and the commissioning's LSS serial number.
    pub(crate) fn lss_identity(&self) -> Option<Identity> {
        let dcf = self.dcf.as_ref()?;
        let (vendor, product) = dcf.identity();
        let serial = self.commissioning.lss_serial.filter(|s| *s != 0)?;
        let revision = dcf.info_number("revisionnumber").unwrap_or(0);
        (vendor != 0 && product != 0).then_some(Identity { vendor, product, revision, serial })
    }
}

/// Read a project and the DCF of every node it lists; any file that cannot be used is a
/// usage error naming it (file:line where a line is to blame).
pub fn load(file: &Path) -> Result<Loaded> {
    let folder = folder_of(file);
    check_inside(folder, file)?;
    let read = cpj::read_file(file).map_err(|e| Error::ProjectUnusable(Box::new(ProjectProblem::Project(e))))?;
    let mut warnings: Vec<LoadWarning> = read.warnings.into_iter().map(LoadWarning::Project).collect();
    let project = read.project;
    let mut nodes = Vec::new();
    for (node, entry) in project.present() {
        let (dcf, commissioning) = match project.dcf_path(file, node) {
            None => (None, Commissioning::default()),
            Some(path) => {
                let (name, bytes) = read_dcf(file, &path, Some(node))?;
                let dcf = Dcf::parse(&bytes, &name)?;
                let xml = crate::od::xdd::is_xml(&bytes);
                let c = match xml {
                    true => crate::od::xdd::read_commissioning(&bytes, &name).map_err(ProjectProblem::XdcCommissioning),
                    false => cpj::read_commissioning(&bytes, &name).map_err(ProjectProblem::Commissioning),
                }
                .map_err(|p| Error::ProjectUnusable(Box::new(p)))?;
                if let Some(id) = c.node_id.filter(|id| *id != node) {
                    let project = file.display().to_string();
                    let other = ProjectProblem::OtherNodeId { dcf: name, id, node, project, xml };
                    return Err(Error::ProjectUnusable(Box::new(other)));
                }
                warnings.extend(dcf.warnings().iter().cloned().map(LoadWarning::Dcf));
                (Some(dcf), c)
            }
        };
        let name = entry.name.clone().or_else(|| dcf.as_ref().and_then(|d| d.eds.info.get("productname").cloned()));
        nodes.push(Listed { node, name: name.unwrap_or_default(), dcf, commissioning });
    }
    Ok(Loaded { file: file.to_path_buf(), project, nodes, warnings })
}

/// The bytes of a DCF of the project `file` names (with the name messages give it), once it
/// is known to be inside the project's folder; one that cannot be read is a usage error.
fn read_dcf(file: &Path, path: &Path, node: Option<u8>) -> Result<(String, Vec<u8>)> {
    check_inside(folder_of(file), path)?;
    let name = path.display().to_string();
    let bytes = crate::input::read_regular_file(path, crate::input::EDS).map_err(|error| {
        let project = file.display().to_string();
        Error::ProjectUnusable(Box::new(ProjectProblem::Dcf { dcf: name.clone(), node, project, error }))
    })?;
    Ok((name, bytes))
}

/// Every node that answers (`ops::scan::probe`), with its device type where it gave one.
fn probe(bus: &mut dyn Bus, window: Duration, progress: &mut dyn Progress) -> Result<BTreeMap<u8, Option<u32>>> {
    Ok(super::scan::probe(bus, window, progress)?.into_iter().collect())
}

mod apply;
mod baud;
mod check;
mod dump;
mod parallel;
pub(crate) mod report;

pub use apply::*;
pub use baud::*;
pub use check::*;
pub use dump::*;
pub use report::{NodeApplied, NodeCheck, NodeResult, Outcome};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::connect::{BusAddr, OpenOptions};
    use crate::ops::unmet::{Shortfall, Unmet};

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
