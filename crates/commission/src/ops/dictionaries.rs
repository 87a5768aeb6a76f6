//! Which dictionary describes a node: an EDS or DCF given for it (or for every node), else
//! the built-in one; and objects by address or by name.

use crate::canopen::ObjAddr;
use crate::error::Error;
use crate::od::eds::Eds;
use crate::od::{builtin, names, Dictionary, Entry};
use crate::settings::{EdsFile, Source, Sourced};

/// The EDS files given for a command, each for one node or for any: which dictionary names and
/// types a node's objects.
#[derive(Default)]
pub struct Dictionaries {
    files: Vec<(Option<u8>, Eds)>,
}

impl Dictionaries {
    /// Read every file; an unreadable one is a usage error citing file:line. What the files
    /// describe in a way canctl passes over is in [`Dictionaries::warnings`].
    pub fn load(args: &[EdsFile]) -> Result<Dictionaries, Error> {
        let files = args.iter().map(|a| Ok((a.node, crate::od::read_description(&a.path)?)));
        Ok(Dictionaries { files: files.collect::<Result<_, Error>>()? })
    }

    /// [`Dictionaries::load`] of the files in force: one a settings file names is cited, when
    /// it cannot be read, at that file's line (`canctl.toml:4: cannot read mh.eds: ...`).
    pub fn load_in_force(files: &[Sourced<EdsFile>]) -> Result<Dictionaries, Error> {
        let read = |f: &Sourced<EdsFile>| {
            let eds = crate::od::read_description(&f.value.path).map_err(|e| match &f.from {
                Source::Line { file, line } => {
                    Error::InSettingsFile { file: file.display().to_string(), line: *line, error: Box::new(e.into()) }
                }
                _ => Error::from(e),
            })?;
            Ok((f.value.node, eds))
        };
        Ok(Dictionaries { files: files.iter().map(read).collect::<Result<_, Error>>()? })
    }

    /// The files' warnings, with file:line.
    pub fn warnings(&self) -> impl Iterator<Item = &crate::od::lint::Warning> {
        self.files.iter().flat_map(|(_, eds)| &eds.warnings)
    }

    /// The EDS bound to this node, else one given for every node.
    pub fn eds_for(&self, node: u8) -> Option<&Eds> {
        self.files
            .iter()
            .find(|(n, _)| *n == Some(node))
            .or_else(|| self.files.iter().find(|(n, _)| n.is_none()))
            .map(|(_, e)| e)
    }

    /// The PDO layouts (TPDO and RPDO mappings) the EDS/DCF files give for `nodes` (every
    /// node when empty), by COB-ID: what a bus monitor decodes PDOs with.
    pub fn pdo_layouts(&self, nodes: &[u8]) -> std::collections::BTreeMap<u16, crate::canopen::pdo::Layout> {
        let all: Vec<u8> = (1..=127).collect();
        let nodes = if nodes.is_empty() { &all[..] } else { nodes };
        let of = |node: &u8| self.eds_for(*node).map(|eds| super::pdo::dcf_layouts(eds, *node));
        nodes.iter().filter_map(of).flatten().collect()
    }

    /// The dictionary for `node`: its own EDS, else one given for any node, else the built-in one
    /// for its profile.
    pub fn for_node(&self, node: u8) -> &Dictionary {
        self.eds_for(node).map_or_else(|| builtin::dictionary(None), |e| &e.dict)
    }

    /// An object argument: an address (`0x1018:1`, `1018sub1`) or a name from the node's
    /// dictionary. The dictionary entry comes along when there is one.
    pub fn resolve(&self, node: u8, text: &str) -> Result<(ObjAddr, Option<&Entry>), Error> {
        let dict = self.for_node(node);
        let addr = match text.parse::<ObjAddr>() {
            Ok(a) => a,
            Err(addr_err) => {
                if text.chars().all(|c| c.is_ascii_hexdigit() || ":xXsubSUB".contains(c)) {
                    return Err(Error::Usage(addr_err));
                }
                let source = self.eds_for(node).map_or("the built-in dictionary".to_string(), |e| e.path.clone());
                names::find(dict, text)
                    .map_err(|e| Error::Usage(format!("{e} (looked in {source} for node {node})")))?
            }
        };
        Ok((addr, dict.get(addr)))
    }

    /// Objects of the node's dictionary near one the node says it does not have
    /// ([`names::near_addrs`]): candidates, which only the node can confirm.
    pub fn near(&self, node: u8, addr: ObjAddr, object_missing: bool) -> Vec<ObjAddr> {
        names::near_addrs(self.for_node(node), addr, object_missing)
    }

    /// An object's address and name in the node's dictionary.
    pub fn label(&self, node: u8, addr: ObjAddr) -> String {
        names::label(self.for_node(node), addr)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[test]
    fn eds_arguments() {
        let a: EdsFile = "5=sensors/mh.eds".parse().unwrap();
        assert_eq!((a.node, a.path), (Some(5), PathBuf::from("sensors/mh.eds")));
        assert_eq!("mh.eds".parse::<EdsFile>().unwrap().node, None);
        assert_eq!("C:=odd".parse::<EdsFile>().unwrap().node, None);
        assert!("200=x.eds".parse::<EdsFile>().is_err());
    }

    #[test]
    fn near_misses_are_suggested() {
        let d = Dictionaries::default();
        let near: Vec<String> = d.near(1, ObjAddr::new(0x1081, 1), true).into_iter().map(|a| d.label(1, a)).collect();
        assert!(
            near[0].starts_with("0x1001:0")
                || near.iter().any(|n| n.starts_with("0x1018:1 (Identity object: Vendor-ID)")),
            "{near:?}"
        );
        assert!(near.iter().any(|n| n.starts_with("0x1018:1")), "{near:?}");
        let subs = d.near(1, ObjAddr::new(0x1018, 7), false);
        assert_eq!(subs, (0..5).map(|s| ObjAddr::new(0x1018, s)).collect::<Vec<_>>());
        assert!(d.near(1, ObjAddr::new(0x7777, 0), false).is_empty());
        // A node without object 0x1801 at all is not offered its other sub-indexes.
        assert!(d.near(5, ObjAddr::new(0x1801, 1), true).iter().all(|a| a.index != 0x1801));
    }

    #[test]
    fn objects_by_address_or_name() {
        let d = Dictionaries::default();
        assert_eq!(d.resolve(5, "1017").unwrap().0, ObjAddr::new(0x1017, 0));
        let (addr, entry) = d.resolve(5, "ProducerHeartbeatTime").unwrap();
        assert_eq!(addr, ObjAddr::new(0x1017, 0));
        assert_eq!(entry.unwrap().dtype, crate::canopen::DataType::U16);
        let e = d.resolve(5, "10180:1").unwrap_err().to_string();
        assert!(e.contains("1 to 4 hex digits"), "{e}");
        let e = d.resolve(5, "HeartbeatTme").unwrap_err().to_string();
        assert!(e.contains("no object named") && e.contains("built-in dictionary"), "{e}");
    }
}
