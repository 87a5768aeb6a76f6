//! CiA 306-3 network projects: the `nodelist.cpj` that lists a network's nodes and the DCF
//! each is configured by, and the `[DeviceComissioning]` section of those DCFs (node-id,
//! bit rate, LSS serial number).
//!
//! A project's `[Topology]` section holds `NetName`, `NetRefd`, `Nodes` (how many nodes are
//! listed), `NodeXPresent` (0x01 listed, 0x00 not), `NodeXName`, `NodeXRefd`, `NodeXDCFName`
//! for node-id X (decimal, 1 to 127), and `EDSBaseName`, the folder the DCF names are
//! relative to. Neither may leave the project's folder (no absolute path, no `..`, and a DCF
//! name is a bare file name). Keys are matched without regard to case. Files are Latin-1 (UTF-8 is read
//! and written back as UTF-8) with CRLF or LF line ends; canctl writes CRLF. Keys canctl does
//! not know are kept, in order, and written back. What cannot be read is named with
//! file:line.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A project or DCF that cannot be read, at file:line (line 0: the whole file).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct CpjError {
    /// The file.
    pub path: String,
    /// The line (0: the whole file).
    pub line: usize,
    /// What is wrong there.
    pub msg: String,
}

impl std::fmt::Display for CpjError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            0 => write!(f, "{}: {}", self.path, self.msg),
            line => write!(f, "{}:{line}: {}", self.path, self.msg),
        }
    }
}

/// One node of the network.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Node {
    /// `NodeXPresent=0x01`: the node belongs to the network. A `0x00` entry is kept (and
    /// written back) but not checked or configured.
    pub present: bool,
    /// Its name (`NodeXName`).
    pub name: Option<String>,
    /// The reference designator (`NodeXRefd`), e.g. the cabinet label.
    pub refd: Option<String>,
    /// The node's DCF, relative to [`Project::dcf_dir`] unless absolute.
    pub dcf: Option<String>,
}

/// A network project (one `[Topology]`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Project {
    /// The network's name (`NetName`).
    pub net_name: Option<String>,
    /// The network's reference designator (`NetRefd`).
    pub net_refd: Option<String>,
    /// Where the nodes' files are (`EDSBaseName`).
    pub eds_base_name: Option<String>,
    /// The nodes, by node-id.
    pub nodes: BTreeMap<u8, Node>,
    /// Keys of `[Topology]` canctl does not know, as written, in order.
    pub other: Vec<(String, String)>,
    /// Whether the file's text was UTF-8 rather than Latin-1 (written back the same way).
    pub utf8: bool,
}

/// A parsed project with what deserves a look (each with file:line).
#[derive(Debug, Clone)]
pub struct Read {
    /// The project.
    pub project: Project,
    /// What deserves a look, each with file:line.
    pub warnings: Vec<String>,
}

impl Project {
    /// The nodes listed as present, in node-id order.
    pub fn present(&self) -> impl Iterator<Item = (u8, &Node)> {
        self.nodes.iter().filter(|(_, n)| n.present).map(|(id, n)| (*id, n))
    }

    /// The folder DCF names are relative to: `EDSBaseName` (relative to the project's folder,
    /// which it cannot leave), else the project's folder.
    pub fn dcf_dir(&self, project_file: &Path) -> PathBuf {
        let here = project_file.parent().map(Path::to_path_buf).unwrap_or_default();
        self.eds_base_name.as_deref().filter(|b| !b.is_empty()).map_or_else(|| here.clone(), |base| here.join(base))
    }

    /// Where node `id`'s DCF is, when the project names one.
    pub fn dcf_path(&self, project_file: &Path, id: u8) -> Option<PathBuf> {
        let name = self.nodes.get(&id)?.dcf.as_deref()?;
        Some(self.dcf_dir(project_file).join(name))
    }
}

/// One line of an INI file: its number, and its section, key and value.
struct IniLine {
    line: usize,
    section: String,
    key: String,
    value: String,
}

/// Bytes as text: Latin-1, one character per byte, unless the file is UTF-8 (with a BOM, or
/// non-ASCII and valid UTF-8).
fn decode(bytes: &[u8]) -> (String, bool) {
    if let Some(rest) = bytes.strip_prefix(b"\xEF\xBB\xBF") {
        return (String::from_utf8_lossy(rest).into_owned(), true);
    }
    match std::str::from_utf8(bytes) {
        Ok(s) if !bytes.is_ascii() => (s.to_string(), true),
        _ => (bytes.iter().map(|b| *b as char).collect(), false),
    }
}

/// Every `KEY=VALUE` with its section (names as written, blanks around them trimmed);
/// comments (`;`, `#`) and blank lines skipped.
fn ini_lines(bytes: &[u8], path: &str) -> Result<(Vec<IniLine>, bool), CpjError> {
    let (text, utf8) = decode(bytes);
    let err = |line: usize, msg: String| CpjError { path: path.to_string(), line, msg };
    let mut section: Option<String> = None;
    let mut out = Vec::new();
    for (i, raw) in text.split('\n').enumerate() {
        let no = i + 1;
        let line = raw.strip_suffix('\r').unwrap_or(raw).trim_matches([' ', '\t']);
        if line.is_empty() || line.starts_with(';') || line.starts_with('#') {
            continue;
        }
        if let Some(rest) = line.strip_prefix('[') {
            let name =
                rest.strip_suffix(']').ok_or_else(|| err(no, format!("section header '{line}' has no closing ]")))?;
            section = Some(name.trim_matches([' ', '\t']).to_string());
            continue;
        }
        let (key, value) =
            line.split_once('=').ok_or_else(|| err(no, format!("expected KEY=VALUE or [SECTION], found '{line}'")))?;
        let section = section.clone().ok_or_else(|| err(no, format!("'{line}' comes before any [SECTION]")))?;
        out.push(IniLine {
            line: no,
            section,
            key: key.trim_matches([' ', '\t']).to_string(),
            value: value.trim_matches([' ', '\t']).to_string(),
        });
    }
    Ok((out, utf8))
}

/// A project's or commissioning section's number: `0x` hex, otherwise decimal, the one
/// number reading. Not [`crate::eds::parse_int`]'s CiA 306 octal: these values (node-ids,
/// bit rates, counts) were always read as decimal, and `010` turning into 8 would move a node.
fn number(text: &str) -> Option<u32> {
    canctl_canopen::number::parse_number(text)
}

/// `Node12Present` → (12, "present"); keys of other shapes → None.
fn node_key(key: &str) -> Option<(&str, String)> {
    key.get(..4).filter(|p| p.eq_ignore_ascii_case("node"))?;
    let tail = &key[4..];
    let digits = tail.len() - tail.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    (digits > 0).then(|| (&tail[..digits], tail[digits..].to_ascii_lowercase()))
}

/// Whether a file name from a project stays in the project's folder, so that a project
/// from someone else cannot make canctl read or rewrite a file elsewhere (`--update-project`
/// rewrites the DCFs): a DCF name is a bare file name; `EDSBaseName` (`folder` true) a
/// relative folder below the project's, without `..`. Both separators count, whatever the OS.
fn inside_the_folder(name: &str, folder: bool) -> Result<(), &'static str> {
    let name = name.trim();
    if name.starts_with(['/', '\\']) || name.as_bytes().get(1) == Some(&b':') {
        return Err("an absolute path: a project names files inside its own folder");
    }
    let parts: Vec<&str> = name.split(['/', '\\']).collect();
    if parts.contains(&"..") {
        return Err("'..' leaves the project's folder: a project names files inside its own folder");
    }
    if !folder && (parts.len() > 1 || name == ".") {
        return Err("a DCF name is a file name, without a folder (EDSBaseName names the folder)");
    }
    Ok(())
}

/// Parse a project. `path` names the file in messages.
pub fn parse(bytes: &[u8], path: &str) -> Result<Read, CpjError> {
    let (lines, utf8) = ini_lines(bytes, path)?;
    let err = |line: usize, msg: String| CpjError { path: path.to_string(), line, msg };
    let mut project = Project { utf8, ..Project::default() };
    let mut warnings = Vec::new();
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    let mut nodes_key: Option<(u32, usize)> = None;
    let mut node_lines: BTreeMap<u8, usize> = BTreeMap::new();
    let mut topology = false;
    for l in &lines {
        let section = l.section.to_ascii_lowercase();
        if section != "topology" {
            if section.starts_with("topology") {
                return Err(err(
                    l.line,
                    format!("[{}] describes a further network: canctl takes one network per project", l.section),
                ));
            }
            if seen.insert(format!("[{section}]"), l.line).is_none() {
                warnings.push(format!(
                    "{path}:{}: section [{}] is not part of a network project; passed over",
                    l.line, l.section
                ));
            }
            continue;
        }
        topology = true;
        let key = l.key.to_ascii_lowercase();
        if let Some(first) = seen.insert(key.clone(), l.line) {
            return Err(err(l.line, format!("{} given again (first at line {first})", l.key)));
        }
        let value = || (!l.value.is_empty()).then(|| l.value.clone());
        match key.as_str() {
            "netname" => project.net_name = value(),
            "netrefd" => project.net_refd = value(),
            "edsbasename" => {
                inside_the_folder(&l.value, true)
                    .map_err(|why| err(l.line, format!("{}={}: {why}", l.key, l.value)))?;
                project.eds_base_name = value();
            }
            "nodes" => {
                let n = number(&l.value)
                    .filter(|n| *n <= 127)
                    .ok_or_else(|| err(l.line, format!("Nodes={} is not a number of nodes (0 to 127)", l.value)))?;
                nodes_key = Some((n, l.line));
            }
            _ => match node_key(&l.key) {
                Some((digits, field)) if ["present", "name", "refd", "dcfname"].contains(&field.as_str()) => {
                    let id = digits
                        .parse::<u8>()
                        .ok()
                        .filter(|id| (1..=127).contains(id) && !digits.starts_with('0'))
                        .ok_or_else(|| err(l.line, format!("{}: node-id {digits} is not 1 to 127", l.key)))?;
                    node_lines.entry(id).or_insert(l.line);
                    let node = project.nodes.entry(id).or_default();
                    match field.as_str() {
                        "present" => {
                            let why = || format!("{}={} must be 0x01 (listed) or 0x00 (not)", l.key, l.value);
                            node.present = number(&l.value).filter(|v| *v <= 1).ok_or_else(|| err(l.line, why()))? == 1;
                        }
                        "name" => node.name = value(),
                        "refd" => node.refd = value(),
                        _ => {
                            inside_the_folder(&l.value, false)
                                .map_err(|why| err(l.line, format!("{}={}: {why}", l.key, l.value)))?;
                            node.dcf = value();
                        }
                    }
                }
                _ => project.other.push((l.key.clone(), l.value.clone())),
            },
        }
    }
    if !topology {
        return Err(err(0, "no [Topology] section: not a CiA 306-3 network project".into()));
    }
    // A node named without NodeXPresent is not part of the network.
    for (id, line) in &node_lines {
        if !seen.contains_key(&format!("node{id}present")) {
            warnings.push(format!(
                "{path}:{line}: node {id} has no Node{id}Present=0x01, so it is not part of the network"
            ));
        }
    }
    let listed = project.present().count() as u32;
    match nodes_key {
        Some((n, line)) if n != listed => warnings.push(format!(
            "{path}:{line}: Nodes={n}, but {listed} node(s) have NodeXPresent=0x01 (the list is what counts)"
        )),
        None => warnings.push(format!("{path}: no Nodes= key in [Topology]")),
        _ => {}
    }
    Ok(Read { project, warnings })
}

/// Read a project file from disk.
pub fn read_file(path: &Path) -> Result<Read, CpjError> {
    let bytes = crate::eds::read_bytes(path).map_err(|e| CpjError { path: e.path, line: 0, msg: e.msg })?;
    parse(&bytes, &path.display().to_string())
}

/// A value no INI line can carry.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("cannot write {key}={value:?}: {why}")]
pub struct WriteError {
    /// The key.
    pub key: String,
    /// The value that cannot be written.
    pub value: String,
    /// Why.
    pub why: String,
}

/// Lines of text as file bytes, each ended by `eol`, Latin-1 unless `utf8`.
fn encode(lines: &[(String, String)], header: &str, utf8: bool, eol: &str) -> Result<Vec<u8>, WriteError> {
    let mut text = format!("{header}{eol}");
    for (key, value) in lines {
        if value.contains(['\r', '\n']) || value.trim_matches([' ', '\t']) != value {
            let why = "a line break, or blanks at either end, would not read back".to_string();
            return Err(WriteError { key: key.clone(), value: value.clone(), why });
        }
        if !utf8 && value.chars().any(|c| c as u32 > 0xFF) {
            let why = "a character beyond Latin-1 in a Latin-1 file".to_string();
            return Err(WriteError { key: key.clone(), value: value.clone(), why });
        }
        text.push_str(&format!("{key}={value}{eol}"));
    }
    Ok(if utf8 { text.into_bytes() } else { text.chars().map(|c| c as u8).collect() })
}

/// The project file's bytes: `[Topology]` with its keys in the order CiA 306-3 lists them,
/// nodes in node-id order, then the keys canctl does not know.
pub fn write(project: &Project) -> Result<Vec<u8>, WriteError> {
    let mut lines: Vec<(String, String)> = Vec::new();
    let mut put = |key: String, value: &Option<String>| lines.extend(value.clone().map(|v| (key, v)));
    put("NetName".into(), &project.net_name);
    put("NetRefd".into(), &project.net_refd);
    put("Nodes".into(), &Some(format!("0x{:02X}", project.present().count())));
    for (id, node) in &project.nodes {
        put(format!("Node{id}Present"), &Some(format!("0x{:02X}", u8::from(node.present))));
        put(format!("Node{id}Name"), &node.name);
        put(format!("Node{id}Refd"), &node.refd);
        put(format!("Node{id}DCFName"), &node.dcf);
    }
    put("EDSBaseName".into(), &project.eds_base_name);
    lines.extend(project.other.iter().cloned());
    encode(&lines, "[Topology]", project.utf8, "\r\n")
}

/// A DCF's `[DeviceComissioning]` section (CiA 306; the standard spells it with one 'm').
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Commissioning {
    /// `NodeID`: the node-id the device is to have.
    pub node_id: Option<u8>,
    /// `NodeName`.
    pub node_name: Option<String>,
    /// In kbit/s, as CiA 306 writes it.
    pub baudrate_kbit: Option<u32>,
    /// `NetNumber`.
    pub net_number: Option<u32>,
    /// `NetworkName`.
    pub network_name: Option<String>,
    /// `CANopenManager`: whether the device is the network's manager.
    pub canopen_manager: Option<bool>,
    /// The LSS serial number (0x1018:4) the node-id is assigned to.
    pub lss_serial: Option<u32>,
}

/// The `[DeviceComissioning]` of a DCF (also spelt `DeviceCommissioning`); empty when the
/// file has none.
pub fn read_commissioning(bytes: &[u8], path: &str) -> Result<Commissioning, CpjError> {
    let (lines, _) = ini_lines(bytes, path)?;
    let err = |line: usize, msg: String| CpjError { path: path.to_string(), line, msg };
    let mut c = Commissioning::default();
    for l in lines {
        if !matches!(l.section.to_ascii_lowercase().as_str(), "devicecomissioning" | "devicecommissioning") {
            continue;
        }
        let num =
            |what: &str| number(&l.value).ok_or_else(|| err(l.line, format!("{what}={} is not a number", l.value)));
        let text = (!l.value.is_empty()).then(|| l.value.clone());
        match l.key.to_ascii_lowercase().as_str() {
            "nodeid" => {
                let id = num("NodeID")?;
                c.node_id = Some(
                    u8::try_from(id)
                        .ok()
                        .filter(|id| (1..=127).contains(id))
                        .ok_or_else(|| err(l.line, format!("NodeID={} is not 1 to 127", l.value)))?,
                );
            }
            "nodename" => c.node_name = text,
            "baudrate" => c.baudrate_kbit = Some(num("Baudrate")?),
            "netnumber" => c.net_number = Some(num("NetNumber")?),
            "networkname" => c.network_name = text,
            "canopenmanager" => c.canopen_manager = Some(num("CANopenManager")? != 0),
            "lss_serialnumber" => c.lss_serial = Some(num("LSS_SerialNumber")?),
            _ => {}
        }
    }
    Ok(c)
}

/// The section's lines, as canctl writes them.
pub fn commissioning_lines(c: &Commissioning) -> Vec<(String, String)> {
    [
        ("NodeID", c.node_id.map(|n| n.to_string())),
        ("NodeName", c.node_name.clone()),
        ("Baudrate", c.baudrate_kbit.map(|b| b.to_string())),
        ("NetNumber", c.net_number.map(|n| n.to_string())),
        ("NetworkName", c.network_name.clone()),
        ("CANopenManager", c.canopen_manager.map(|m| u8::from(m).to_string())),
        ("LSS_SerialNumber", c.lss_serial.map(|s| format!("0x{s:08X}"))),
    ]
    .into_iter()
    .filter_map(|(key, value)| Some((key.to_string(), value?)))
    .collect()
}

/// A DCF's bytes with its `[DeviceComissioning]` section replaced by `c` (or added before
/// the object lists when it has none), with the file's own line ends. The rest of the file
/// is left byte for byte.
pub fn with_commissioning(dcf: &[u8], c: &Commissioning) -> Result<Vec<u8>, WriteError> {
    let utf8 = decode(dcf).1;
    let eol = if dcf.windows(2).any(|w| w == b"\r\n") { "\r\n" } else { "\n" };
    let section = encode(&commissioning_lines(c), "[DeviceComissioning]", utf8, eol)?;
    // Lines as byte ranges; section headers are ASCII, so bytes can be matched directly.
    let mut starts = vec![0];
    starts.extend(dcf.iter().enumerate().filter(|(_, b)| **b == b'\n').map(|(i, _)| i + 1));
    let header = |at: usize| -> Option<String> {
        let end = dcf[at..].iter().position(|b| *b == b'\n').map_or(dcf.len(), |p| at + p);
        let line = String::from_utf8_lossy(&dcf[at..end]);
        let t = line.trim();
        t.strip_prefix('[').and_then(|r| r.strip_suffix(']')).map(|n| n.trim().to_ascii_lowercase())
    };
    let headers: Vec<(usize, String)> =
        starts.iter().filter(|s| **s < dcf.len()).filter_map(|s| header(*s).map(|h| (*s, h))).collect();
    let found = headers.iter().position(|(_, h)| h == "devicecomissioning" || h == "devicecommissioning");
    // The section replaces the one there, else goes before the object lists.
    let (from, to) = match found {
        Some(i) => (headers[i].0, headers.get(i + 1).map_or(dcf.len(), |(s, _)| *s)),
        None => {
            let lists = ["mandatoryobjects", "optionalobjects", "manufacturerobjects"];
            let at = headers.iter().find(|(_, h)| lists.contains(&h.as_str())).map_or(dcf.len(), |(s, _)| *s);
            (at, at)
        }
    };
    let mut out = Vec::with_capacity(dcf.len() + section.len());
    out.extend_from_slice(&dcf[..from]);
    out.extend_from_slice(&section);
    out.extend_from_slice(eol.as_bytes());
    out.extend_from_slice(&dcf[to..]);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A project as canctl writes it, with a Latin-1 byte (0xE9, é) in a name.
    const CANONICAL: &[u8] =
        b"[Topology]\r\nNetName=Cabinet A\r\nNodes=0x02\r\nNode1Present=0x01\r\nNode1Name=drive\r\n\
Node1Refd=-K1\r\nNode1DCFName=node1.dcf\r\nNode5Present=0x01\r\nNode5Name=capteur \xE9\r\nNode5DCFName=node5.dcf\r\n\
Node9Present=0x00\r\nNode9Name=spare\r\nEDSBaseName=dcf\r\nVendorKey=kept\r\n";

    #[test]
    fn a_canonical_project_reads_and_writes_back_byte_for_byte() {
        let read = parse(CANONICAL, "nodelist.cpj").unwrap();
        assert!(read.warnings.is_empty(), "{:?}", read.warnings);
        let p = &read.project;
        assert_eq!(p.net_name.as_deref(), Some("Cabinet A"));
        assert_eq!(p.eds_base_name.as_deref(), Some("dcf"));
        assert_eq!(p.present().map(|(id, _)| id).collect::<Vec<_>>(), [1, 5]);
        assert_eq!(p.nodes[&5].name.as_deref(), Some("capteur é"));
        assert_eq!(p.nodes[&1].refd.as_deref(), Some("-K1"));
        assert!(!p.nodes[&9].present);
        assert_eq!(p.other, [("VendorKey".to_string(), "kept".to_string())]);
        assert_eq!(write(p).unwrap(), CANONICAL);
    }

    #[test]
    fn a_written_project_reads_back_the_same() {
        let mut p = Project { net_name: Some("Zelle 3 – Förderband".into()), utf8: true, ..Project::default() };
        for id in [1u8, 10, 127] {
            let node =
                Node { present: true, name: Some(format!("n{id}")), refd: None, dcf: Some(format!("node{id}.dcf")) };
            p.nodes.insert(id, node);
        }
        let bytes = write(&p).unwrap();
        let back = parse(&bytes, "x.cpj").unwrap();
        assert!(back.warnings.is_empty(), "{:?}", back.warnings);
        assert_eq!(back.project, p);
        assert_eq!(write(&back.project).unwrap(), bytes);
    }

    #[test]
    fn lf_lines_any_key_case_and_blanks_are_read() {
        let text = b"; made by hand\n[TOPOLOGY]\nnetname = Line 2\nNODES=2\nnode3present=1\n Node3DcfName = a.dcf \nNode4Present=0x01\n";
        let p = parse(text, "p.cpj").unwrap().project;
        assert_eq!(p.net_name.as_deref(), Some("Line 2"));
        assert_eq!(p.nodes[&3].dcf.as_deref(), Some("a.dcf"));
        assert!(p.nodes[&4].present && p.nodes[&4].dcf.is_none());
    }

    #[test]
    fn errors_name_file_and_line() {
        let cases: [(&[u8], &str); 6] = [
            (
                b"[Topology]\nNodes=1\nNode1Present=yes\n",
                "p.cpj:3: Node1Present=yes must be 0x01 (listed) or 0x00 (not)",
            ),
            (b"[Topology]\nNode128Present=1\n", "p.cpj:2: Node128Present: node-id 128 is not 1 to 127"),
            (b"[Topology]\nNode0Present=1\n", "p.cpj:2: Node0Present: node-id 0 is not 1 to 127"),
            (b"[Topology]\nNetName=a\nnetname=b\n", "p.cpj:3: netname given again (first at line 2)"),
            (
                b"[Topology]\nNodes=1\n[Topology2]\nNodes=1\n",
                "p.cpj:4: [Topology2] describes a further network: canctl takes one network per project",
            ),
            (b"[Topology\n", "p.cpj:1: section header '[Topology' has no closing ]"),
        ];
        for (text, msg) in cases {
            assert_eq!(parse(text, "p.cpj").unwrap_err().to_string(), msg);
        }
        assert_eq!(
            parse(b"[FileInfo]\nA=1\n", "p.cpj").unwrap_err().to_string(),
            "p.cpj: no [Topology] section: not a CiA 306-3 network project"
        );
    }

    /// A project from someone else must not make canctl read or write outside its folder.
    #[test]
    fn file_names_that_leave_the_project_folder_are_refused() {
        let cases: [(&[u8], &str); 7] = [
            (b"[Topology]\nNode5Present=1\nNode5DCFName=../outside.dcf\n", "Node5DCFName=../outside.dcf"),
            (b"[Topology]\nNode5Present=1\nNode5DCFName=/etc/x.dcf\n", "Node5DCFName=/etc/x.dcf"),
            (b"[Topology]\nNode5Present=1\nNode5DCFName=sub/x.dcf\n", "Node5DCFName=sub/x.dcf"),
            (b"[Topology]\nNode5Present=1\nNode5DCFName=sub\\x.dcf\n", "Node5DCFName=sub\\x.dcf"),
            (b"[Topology]\nNode5Present=1\nNode5DCFName=..\n", "Node5DCFName=.."),
            (b"[Topology]\nNode5Present=1\nEDSBaseName=../up\n", "EDSBaseName=../up"),
            (b"[Topology]\nNode5Present=1\nEDSBaseName=/tmp\n", "EDSBaseName=/tmp"),
        ];
        for (text, what) in cases {
            let e = parse(text, "p.cpj").unwrap_err().to_string();
            assert!(e.starts_with(&format!("p.cpj:3: {what}: ")), "{e}");
        }
        let ok = parse(b"[Topology]\nNode5Present=1\nEDSBaseName=dcf/a\nNode5DCFName=n5.dcf\n", "p.cpj").unwrap();
        assert_eq!(ok.project.dcf_path(Path::new("m/p.cpj"), 5).unwrap(), Path::new("m/dcf/a/n5.dcf"));
    }

    #[test]
    fn a_wrong_count_and_a_node_without_present_are_warned_about() {
        let w = parse(b"[Topology]\nNodes=0x03\nNode1Present=1\nNode2Name=x\n", "p.cpj").unwrap().warnings;
        assert_eq!(
            w,
            [
                "p.cpj:4: node 2 has no Node2Present=0x01, so it is not part of the network",
                "p.cpj:2: Nodes=3, but 1 node(s) have NodeXPresent=0x01 (the list is what counts)"
            ]
        );
    }

    #[test]
    fn values_that_cannot_be_written_are_refused() {
        let p = Project { net_name: Some("two\nlines".into()), ..Project::default() };
        assert!(write(&p).is_err());
        let p = Project { net_name: Some("€".into()), utf8: false, ..Project::default() };
        assert!(write(&p).is_err());
    }

    #[test]
    fn dcf_paths_follow_eds_base_name() {
        let mut p = Project { eds_base_name: Some("dcf".into()), ..Project::default() };
        p.nodes.insert(5, Node { present: true, dcf: Some("node5.dcf".into()), ..Node::default() });
        assert_eq!(p.dcf_path(Path::new("/m/nodelist.cpj"), 5).unwrap(), Path::new("/m/dcf/node5.dcf"));
        assert!(p.dcf_path(Path::new("/m/nodelist.cpj"), 6).is_none());
    }

    #[test]
    fn commissioning_is_read_and_replaced_in_place() {
        let dcf = b"[FileInfo]\r\nFileName=a.dcf\r\n\r\n[DeviceComissioning]\r\nNodeID=5\r\n\r\n[MandatoryObjects]\r\nSupportedObjects=0\r\n";
        let mut c = read_commissioning(dcf, "a.dcf").unwrap();
        assert_eq!(c, Commissioning { node_id: Some(5), ..Commissioning::default() });
        c.baudrate_kbit = Some(500);
        c.lss_serial = Some(0x0950_1234);
        c.node_name = Some("sensor".into());
        let out = with_commissioning(dcf, &c).unwrap();
        assert_eq!(
            out,
            b"[FileInfo]\r\nFileName=a.dcf\r\n\r\n[DeviceComissioning]\r\nNodeID=5\r\nNodeName=sensor\r\nBaudrate=500\r\n\
LSS_SerialNumber=0x09501234\r\n\r\n[MandatoryObjects]\r\nSupportedObjects=0\r\n"
        );
        assert_eq!(read_commissioning(&out, "a.dcf").unwrap(), c);
        // Added before the object lists when missing.
        let bare = b"[FileInfo]\r\nFileName=a.dcf\r\n\r\n[MandatoryObjects]\r\nSupportedObjects=0\r\n";
        let out = with_commissioning(bare, &c).unwrap();
        assert_eq!(read_commissioning(&out, "a.dcf").unwrap(), c);
        assert!(out.ends_with(b"\r\n\r\n[MandatoryObjects]\r\nSupportedObjects=0\r\n"));
        // A file with LF line ends keeps them.
        let lf = b"[DeviceComissioning]\nNodeID=5\n\n[MandatoryObjects]\n";
        let out = with_commissioning(lf, &c).unwrap();
        assert!(!out.contains(&b'\r'), "{}", String::from_utf8_lossy(&out));
        assert_eq!(read_commissioning(&out, "a.dcf").unwrap(), c);
        // The other spelling is read too; a bad node-id is named.
        let e = read_commissioning(b"[DeviceCommissioning]\nNodeID=200\n", "b.dcf").unwrap_err();
        assert_eq!(e.to_string(), "b.dcf:2: NodeID=200 is not 1 to 127");
    }
}
