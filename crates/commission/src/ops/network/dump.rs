//! `network dump`: every node of the bus into a DCF, and the project that lists them.

use crate::bus::Bus;
use crate::canopen::ObjAddr;
use crate::error::{Error, Result};
use crate::od::cpj::{self, Commissioning, Project};
use crate::ops::config::{self, Dcf};
use crate::ops::progress::Progress;
use crate::ops::project_files::check_inside;
use serde::Serialize;
use std::path::Path;
use std::time::Duration;

use super::project::probe;
use crate::ops::project_files::PROJECT_FILE;

/// What `dump` read: the files of a project, to be written into one folder.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Dumped {
    /// The bus, as it describes itself.
    pub bus: String,
    /// Each node found, by node-id.
    pub nodes: Vec<DumpedNode>,
    /// Devices that answered LSS without a node-id (not in the project: they have no
    /// objects to read).
    pub unconfigured: usize,
    /// File name and content: `nodelist.cpj` first, then one DCF per node.
    #[serde(skip)]
    pub files: Vec<(String, Vec<u8>)>,
}

/// One node dumped into a DCF.
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct DumpedNode {
    /// The node-id.
    pub node: u8,
    /// Its name (0x1008); empty when it has none.
    pub name: String,
    /// Its DCF's file name in the project folder.
    pub file: String,
    /// How many objects it answered.
    pub objects: usize,
}

/// How to dump a network.
#[derive(Clone, Debug)]
pub struct DumpOptions {
    /// How long to wait for each SDO answer.
    pub timeout: Duration,
    /// How long the probes wait for answers.
    pub window: Duration,
    /// `NetName` of the project.
    pub net_name: String,
    /// The bus's bit rate in kbit/s, for each DCF's `Baudrate` (left out when unknown).
    pub baudrate_kbit: Option<u32>,
}

/// Scan the bus and read every node into a DCF (`nodeN.dcf`, with its
/// `[DeviceComissioning]`: node-id, name, bit rate, LSS serial number), listed in a
/// `nodelist.cpj`.
pub fn dump(bus: &mut dyn Bus, o: &DumpOptions, progress: &mut dyn Progress) -> Result<Dumped> {
    let found = probe(bus, o.window, progress)?;
    let unconfigured = crate::bus::lss::count_unconfigured(bus, o.window)?;
    let mut project = Project { net_name: Some(o.net_name.clone()), ..Project::default() };
    let mut nodes = Vec::new();
    let mut files = Vec::new();
    for node in found.keys().copied() {
        let file = format!("node{node}.dcf");
        let dumped = config::dump(bus, node, None, &file, o.timeout, progress)?;
        let parsed = Dcf::parse(&dumped.dcf, &file)?;
        let bytes_of = |addr| match parsed.eds.values.get(&addr) {
            Some(crate::od::Init::Bytes(b)) => Some(b),
            _ => None,
        };
        let serial = bytes_of(ObjAddr::SERIAL_NUMBER).map(|b| crate::ops::values::le_u32(b));
        let name = bytes_of(ObjAddr::DEVICE_NAME)
            .map_or(String::new(), |b| String::from_utf8_lossy(b).trim_end_matches('\0').to_string());
        let node_name = (!name.is_empty()).then(|| name.clone());
        let commissioning = Commissioning {
            node_id: Some(node),
            node_name: node_name.clone(),
            baudrate_kbit: o.baudrate_kbit,
            lss_serial: serial,
            ..Commissioning::default()
        };
        let bytes = cpj::with_commissioning(&dumped.dcf, &commissioning).map_err(|e| Error::NotWritable(e.into()))?;
        project.nodes.insert(node, cpj::Node { present: true, name: node_name, refd: None, dcf: Some(file.clone()) });
        nodes.push(DumpedNode { node, name, file: file.clone(), objects: dumped.objects });
        files.push((file, bytes));
    }
    let cpj = cpj::write(&project).map_err(|e| Error::NotWritable(e.into()))?;
    files.insert(0, (PROJECT_FILE.to_string(), cpj));
    Ok(Dumped { bus: bus.describe(), nodes, unconfigured, files })
}

/// Write a dumped project into `dir` (made if missing), each file atomically: the DCFs
/// first, the project file last.
pub fn write_project(dir: &Path, dumped: &Dumped) -> Result<()> {
    let unmade = |e| Error::Output { path: dir.display().to_string(), why: format!("cannot make the directory: {e}") };
    std::fs::create_dir_all(dir).map_err(unmade)?;
    // Every file checked before any is written: one refused changes none.
    for (name, _) in &dumped.files {
        check_inside(dir, &dir.join(name))?;
    }
    for (name, bytes) in dumped.files.iter().rev() {
        crate::atomic::write_atomic(&dir.join(name), bytes)?;
    }
    Ok(())
}
