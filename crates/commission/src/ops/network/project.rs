//! A CiA 306-3 project as read: the project file, each listed node and its DCF, and the
//! probe that finds which nodes answer.

use crate::bus::Bus;
use crate::canopen::lss::Identity;
use crate::error::{Error, ProjectProblem, Result};
use crate::od::cpj::{self, Commissioning, Project};
use crate::ops::config::Dcf;
use crate::ops::progress::Progress;
use crate::ops::project_files::{check_inside, folder_of};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

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
pub(super) fn read_dcf(file: &Path, path: &Path, node: Option<u8>) -> Result<(String, Vec<u8>)> {
    check_inside(folder_of(file), path)?;
    let name = path.display().to_string();
    let bytes = crate::input::read_regular_file(path, crate::input::EDS).map_err(|error| {
        let project = file.display().to_string();
        Error::ProjectUnusable(Box::new(ProjectProblem::Dcf { dcf: name.clone(), node, project, error }))
    })?;
    Ok((name, bytes))
}

/// Every node that answers (`ops::scan::probe`), with its device type where it gave one.
pub(super) fn probe(
    bus: &mut dyn Bus,
    window: Duration,
    progress: &mut dyn Progress,
) -> Result<BTreeMap<u8, Option<u32>>> {
    Ok(crate::ops::scan::probe(bus, window, progress)?.into_iter().collect())
}
