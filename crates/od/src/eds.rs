//! EDS and DCF files (CiA 306): INI sections per object and sub-object, read into a
//! `Dictionary` (plus a DCF's `ParameterValue`s) and written from one.
//!
//! Real files are Latin-1, use CRLF, vary the case of keys and section names and leave out
//! optional keys; the reader takes all that. What it cannot read it names with file:line.

/// Re-exported for readers beside this one.
pub use super::lint::MAX_WARNINGS;
use super::lint::{Kind, Warning, Warnings};
use super::{Access, Dictionary, Entry, Init, ObjectKind};
use canctl_canopen::{DataType, ObjAddr};
use std::collections::{BTreeMap, BTreeSet};

/// A parsed EDS or DCF.
#[derive(Debug, Clone, Default)]
pub struct Eds {
    /// The file it was read from, as given (`-` for standard input).
    pub path: String,
    /// The objects it describes, with their defaults (or a DCF's values).
    pub dict: Dictionary,
    /// `ParameterValue`s of a DCF: what the device is to hold.
    pub values: BTreeMap<ObjAddr, Init>,
    /// `[DeviceComissioning] NodeID` of a DCF.
    pub node_id: Option<u8>,
    /// `[DeviceInfo]` keys, lower-cased, as written.
    pub info: BTreeMap<String, String>,
    /// Data types `[DummyUsage]` allows as gaps in a PDO mapping (`Dummy0005=1`: 0x0005).
    pub dummy_usage: BTreeSet<u16>,
    /// Where the file deviates from CiA 306 (objects left out, repeated keys, over-long
    /// lines, ...), each with file:line and what the reader did. The library never prints:
    /// the caller shows them.
    pub warnings: Warnings,
}

/// What both readers (INI and XML) say of a file as they read it.
impl Eds {
    pub(crate) fn warn(&mut self, line: usize, kind: Kind, message: String) {
        self.warnings.push(Warning::new(&self.path, line, kind, message));
    }

    /// The value `text` (at `line`, under `key`) of `addr`, read as it plainly means where
    /// it is not written as CiA 306 writes it, with a warning saying so.
    pub(crate) fn value_as_meant(
        &mut self,
        line: usize,
        key: &str,
        text: &str,
        who: &str,
        dtype: DataType,
    ) -> Result<Init, String> {
        let (value, meant) = parse_value_as_meant(text, dtype)?;
        if let Some(meant) = meant {
            self.warn(line, Kind::ValueAsMeant, read_as_meant(key, text, who, &meant));
        }
        Ok(value)
    }

    /// A value the file gives `entry` (at `line`, under `key`), kept when the file's own
    /// limits allow it, as `config apply` will judge it.
    pub(crate) fn keep_value(&mut self, entry: &Entry, value: Init, line: usize, key: &str) {
        match super::within_limits(entry, value, key) {
            Ok(value) => {
                self.values.insert(entry.addr, value);
            }
            Err((kind, why)) => self.warn(line, kind, why),
        }
    }

    /// The limit `text` (at `line`, under `key`) of `addr`; none, with a warning, where it
    /// is not an integer.
    pub(crate) fn limit(&mut self, line: usize, key: &str, text: &str, who: &str, dtype: DataType) -> Option<i128> {
        let Some((limit, meant)) = parse_limit(text, dtype) else {
            let why = format!("{key} '{text}' of {who} is not an integer: no limit");
            self.warn(line, Kind::ValueIgnored, why);
            return None;
        };
        if let Some(meant) = meant {
            self.warn(line, Kind::ValueAsMeant, read_as_meant(key, text, who, &meant));
        }
        Some(limit)
    }
}

mod error;
mod ini;
mod values;
pub use error::EdsError;
mod write;
pub use ini::to_latin1;
use ini::{object_section, parse_ini, trim_blanks, Section, TextEncoding, BOM};
pub use values::{data_type_from_code, mandatory, object_kind, parse_limit, type_as_bytes};
pub use values::{format_value, parse_int, value_text};
use values::{parse_access, NODE_IDS};
pub use values::{parse_value_as_meant, read_as_meant};
pub use write::{parameter_text, write, write_bytes, Header, WriteError};
/// Parse an EDS or DCF. `path` is only for messages.
///
/// Only a file that is not an EDS at all (not INI, or no section an EDS has) is refused;
/// what a reader can safely interpret is read, and an object that cannot be understood is
/// left out; both are in [`Eds::warnings`] with file:line and the CiA 306 rule.
pub fn parse(bytes: &[u8], path: &str) -> Result<Eds, EdsError> {
    let (bytes, encoding) = match bytes.strip_prefix(BOM) {
        Some(rest) => (rest, TextEncoding { utf8: true }),
        None => (bytes, TextEncoding::of(bytes)),
    };
    let mut eds = Eds { path: path.to_string(), ..Eds::default() };
    let sections = parse_ini(bytes, path, &mut eds.warnings)?;
    let by_name: BTreeMap<(u16, Option<u8>), &Section> =
        sections.iter().filter_map(|s| object_section(&s.name).map(|k| (k, s))).collect();
    let known = |n: &str| matches!(n, "fileinfo" | "deviceinfo" | "devicecomissioning" | "devicecommissioning");
    if by_name.is_empty() && !sections.iter().any(|s| known(&s.name)) {
        return Err(EdsError {
            path: path.to_string(),
            line: sections.first().map_or(0, |s| s.line),
            msg: "not an EDS or DCF: it has no [FileInfo], [DeviceInfo] or object section such as [1000]".into(),
        });
    }
    let mut r = Reader { encoding, eds };
    for s in &sections {
        match s.name.as_str() {
            "deviceinfo" => r.eds.info = s.keys.iter().map(|(k, (v, _))| (k.clone(), encoding.decode(v))).collect(),
            "devicecomissioning" | "devicecommissioning" => r.commissioning(s),
            "dummyusage" => r.dummy_usage(s),
            _ => {}
        }
    }
    let compact: BTreeMap<String, &Section> = sections.iter().map(|s| (s.name.clone(), s)).collect();
    for ((index, sub), s) in &by_name {
        // Data type definitions (0x0001..0x025F) describe types, not objects.
        if sub.is_some() || *index < 0x1000 {
            continue;
        }
        let name = r.name_of(s, format!("Object {index:04X}"));
        let who = format!("{index:04X} ({name})");
        let (code, line) = match r.plain(s, "objecttype") {
            Some((v, line)) => (parse_int(v).ok_or_else(|| format!("ObjectType '{v}' is not a number")), line),
            None => (Ok(7), s.line),
        };
        let domain = code == Ok(2);
        let kind = match code.and_then(|code| object_kind(code).map_err(|why| format!("ObjectType {why}"))) {
            Ok(Some(kind)) => kind,
            Ok(None) => continue,
            Err(why) => {
                r.left_out(line, &who, &why);
                continue;
            }
        };
        if kind == ObjectKind::Var {
            if let Some(entry) = r.entry(s, ObjAddr::new(*index, 0), &name, domain) {
                r.eds.dict.insert(entry);
            }
            continue;
        }
        let compact_count = match r.plain(s, "compactsubobj") {
            Some((v, line)) => {
                match parse_int(v) {
                    Some(0) => None,
                    Some(n @ 1..=254) if kind == ObjectKind::Array => Some(n as u8),
                    // CiA 306 gives CompactSubObj to ARRAYs; Lely's dcfgen writes it for PDO
                    // mapping RECORDs too, whose members share one type all the same.
                    Some(n @ 1..=254) => {
                        let why = format!("{who} is a RECORD with CompactSubObj={v}: read as an ARRAY of {n} sub-objects of its DataType");
                        r.warn(line, Kind::CompactRecord, why);
                        Some(n as u8)
                    }
                    _ => {
                        r.left_out(line, &who, &format!("CompactSubObj={v} is not 1..254 for an ARRAY (0x8)"));
                        continue;
                    }
                }
            }
            None => None,
        };
        let entries = match compact_count {
            Some(n) => r.compact(s, *index, &name, n, &compact),
            None => {
                let subs: Vec<(u8, &Section)> = by_name
                    .range((*index, Some(0))..=(*index, Some(255)))
                    .map(|((_, sub), ss)| (sub.unwrap(), *ss))
                    .collect();
                if subs.is_empty() {
                    let why = format!("an ARRAY or RECORD without any [{index:04X}subN] section or CompactSubObj");
                    r.left_out(s.line, &who, &why);
                    continue;
                }
                r.sub_number(s, *index, &name, subs.len());
                subs.into_iter()
                    .filter_map(|(sub, ss)| {
                        let member = r.name_of(ss, format!("Sub-index {sub}"));
                        r.entry(ss, ObjAddr::new(*index, sub), &member, false)
                    })
                    .collect()
            }
        };
        if entries.is_empty() {
            continue;
        }
        r.eds.dict.object(*index, &name, kind);
        for e in entries {
            r.eds.dict.insert(e);
        }
    }
    r.object_lists(&sections, &by_name);
    // In the order of the file; the note that more were cut stays last.
    r.eds.warnings.sort_by_key(|w| if w.kind == Kind::MoreLeftOut { usize::MAX } else { w.line });
    Ok(r.eds)
}

/// The file being read: where its deviations go.
struct Reader {
    encoding: TextEncoding,
    eds: Eds,
}

/// `0x3ED ; prevent homing` → `0x3ED`: the text before a `;` that follows a blank.
fn strip_comment(v: &str) -> Option<&str> {
    let at = v.char_indices().find(|(i, c)| *c == ';' && *i > 0 && v[..*i].ends_with([' ', '\t']))?.0;
    Some(trim_blanks(&v[..at]))
}

impl Reader {
    fn warn(&mut self, line: usize, kind: Kind, message: String) {
        self.eds.warn(line, kind, message);
    }

    fn left_out(&mut self, line: usize, who: &str, why: &str) {
        self.warn(line, Kind::ObjectLeftOut, format!("{who} left out: {why}"));
    }

    fn name_of(&self, s: &Section, fallback: String) -> String {
        s.get("parametername").map_or(fallback, |(v, _)| self.encoding.decode(v))
    }

    /// A key whose value is a number, a code or a value of a non-string type: an inline
    /// comment after it is read as python-canopen and Lely's dcfchk read it, and said so.
    fn plain<'s>(&mut self, s: &'s Section, key: &str) -> Option<(&'s str, usize)> {
        let (v, line) = s.get(key)?;
        let Some(value) = strip_comment(v) else { return Some((v, line)) };
        let key = s.spelled.get(key).map_or(key, String::as_str);
        let why = format!("{key}={v}: the text from ';' on is read as a comment; the value is '{value}'");
        self.warn(line, Kind::InlineComment, why);
        Some((value, line))
    }

    fn commissioning(&mut self, s: &Section) {
        if let Some((v, line)) = self.plain(s, "nodeid") {
            match parse_int(v) {
                Some(id) if NODE_IDS.contains(&id) => self.eds.node_id = Some(id as u8),
                Some(0) => self.warn(
                    line,
                    Kind::PlaceholderCommissioning,
                    "NodeID=0 is a placeholder, not a node-id: the node given on the command line is used".into(),
                ),
                _ => self.warn(line, Kind::ValueIgnored, format!("NodeID {v} is not 1 to 127: ignored")),
            }
        }
        if let Some((v, line)) = self.plain(s, "baudrate") {
            match parse_int(v) {
                Some(10 | 20 | 50 | 125 | 250 | 500 | 800 | 1000) => {}
                Some(0) => self.warn(
                    line,
                    Kind::PlaceholderCommissioning,
                    "BaudRate=0 is a placeholder, not a bit rate: the bus's own bit rate is used".into(),
                ),
                _ => self.warn(
                    line,
                    Kind::ValueIgnored,
                    format!("BaudRate {v} is not a CiA 301 bit rate in kbit/s (10 ... 1000): ignored"),
                ),
            }
        }
    }

    /// `Dummy0002=1`: the data type 0x0002 may be mapped into a PDO as a gap.
    fn dummy_usage(&mut self, s: &Section) {
        let mut keys: Vec<(&String, &(String, usize))> = s.keys.iter().collect();
        keys.sort_by_key(|(_, (_, line))| *line);
        for (key, (v, line)) in keys {
            let code = key.strip_prefix("dummy").filter(|c| c.len() == 4).and_then(|c| u16::from_str_radix(c, 16).ok());
            match (code, parse_int(v)) {
                (Some(code), Some(1)) => {
                    self.eds.dummy_usage.insert(code);
                }
                (Some(_), Some(0)) => {}
                _ => {
                    let key = s.spelled.get(key.as_str()).unwrap_or(key);
                    let why = format!("[DummyUsage] {key}={v} is not DummyNNNN=0 or 1: ignored");
                    self.warn(*line, Kind::BadDummyUsage, why)
                }
            }
        }
    }

    /// `[MandatoryObjects]`, `[OptionalObjects]`, `[ManufacturerObjects]` against the
    /// object sections there are. The reader goes by the sections; a list that says
    /// otherwise is said, as is a mandatory object (CiA 301: 0x1000, 0x1001, 0x1018) the
    /// file lacks. A file without any list (a snippet, a test file) is not held to them.
    fn object_lists(&mut self, sections: &[Section], by_name: &BTreeMap<(u16, Option<u8>), &Section>) {
        const LISTS: [&str; 3] = ["mandatoryobjects", "optionalobjects", "manufacturerobjects"];
        let lists: Vec<&Section> = sections.iter().filter(|s| LISTS.contains(&s.name.as_str())).collect();
        let Some(first) = lists.first() else { return };
        let mut listed = BTreeSet::new();
        for list in &lists {
            let title = list.spelled_name();
            let mut entries: Vec<(usize, &str, usize)> = Vec::new();
            for (key, (v, line)) in &list.keys {
                if key == "supportedobjects" {
                    continue;
                }
                match (parse_int(key), parse_int(v).and_then(|i| u16::try_from(i).ok())) {
                    (Some(n), Some(index)) if n >= 1 => {
                        entries.push((n as usize, v, *line));
                        if !by_name.contains_key(&(index, None)) {
                            self.warn(
                                *line,
                                Kind::ObjectList,
                                format!("[{title}] lists 0x{index:04X}, which has no [{index:04X}] section: nothing to read"),
                            );
                        }
                        listed.insert(index);
                    }
                    _ => self.warn(*line, Kind::ObjectList, format!("[{title}] {key}={v} is not N=index: ignored")),
                }
            }
            match list.get("supportedobjects") {
                Some((v, line)) if parse_int(v) != Some(entries.len() as i128) => self.warn(
                    line,
                    Kind::ObjectList,
                    format!("[{title}] SupportedObjects={v} but it lists {}: the sections are read", entries.len()),
                ),
                None => self.warn(
                    list.line,
                    Kind::ObjectList,
                    format!("[{title}] has no SupportedObjects: the {} it lists are read", entries.len()),
                ),
                _ => {}
            }
        }
        for ((index, _), s) in by_name.range((0x1000, None)..).filter(|((_, sub), _)| sub.is_none()) {
            if !listed.contains(index) {
                self.warn(
                    s.line,
                    Kind::ObjectList,
                    format!("[{index:04X}] is in no object list ([MandatoryObjects], [OptionalObjects], [ManufacturerObjects]): read all the same"),
                );
            }
        }
        for index in super::MANDATORY {
            if !by_name.contains_key(&(index, None)) {
                let why = format!("no [{index:04X}] section: {}", mandatory(index));
                self.warn(first.line, Kind::MissingMandatory, why);
            }
        }
    }

    /// SubNumber, which the reader does not need (it reads the sections there are).
    fn sub_number(&mut self, s: &Section, index: u16, name: &str, found: usize) {
        match self.plain(s, "subnumber") {
            None => self.warn(
                s.line,
                Kind::MissingSubNumber,
                format!("{index:04X} ({name}) has no SubNumber: its {found} [{index:04X}subN] sections are read"),
            ),
            Some((v, line)) => match parse_int(v) {
                Some(n) if n == found as i128 => {}
                _ => self.warn(
                    line,
                    Kind::SubNumberMismatch,
                    format!(
                        "{index:04X} ({name}) has SubNumber={v} but {found} [{index:04X}subN] sections: those are read"
                    ),
                ),
            },
        }
    }

    /// A CompactSubObj array: sub 0 holds the count, subs 1..=n share the object's type,
    /// access and default; `[xxxxName]` names them and a DCF's `[xxxxValue]` gives values.
    fn compact(
        &mut self,
        s: &Section,
        index: u16,
        name: &str,
        n: u8,
        sections: &BTreeMap<String, &Section>,
    ) -> Vec<Entry> {
        let Some(template) = self.entry(s, ObjAddr::new(index, 1), name, false) else { return Vec::new() };
        // The object section's own ParameterValue is no member's.
        self.eds.values.remove(&ObjAddr::new(index, 1));
        let names = self.compact_list(sections.get(&format!("{index:04x}name")).copied(), index, n);
        let values = self.compact_list(sections.get(&format!("{index:04x}value")).copied(), index, n);
        let mut out = vec![Entry::count(index, "NrOfObjects", n)];
        for sub in 1..=n {
            let addr = ObjAddr::new(index, sub);
            let member = names.get(&sub).map_or_else(|| format!("{name}{sub}"), |(v, _)| self.encoding.decode(v));
            let entry = Entry { addr, name: member, ..template.clone() };
            if let Some((text, line)) = values.get(&sub) {
                let key = format!("[{index:04X}Value] {sub}:");
                match self.eds.value_as_meant(*line, &key, text, &format!("{addr} ({})", entry.name), template.dtype) {
                    Ok(v) => self.eds.keep_value(&entry, v, *line, &key),
                    Err(m) => self.warn(*line, Kind::ValueIgnored, format!("[{index:04X}Value] {sub}: {m}; ignored")),
                }
            }
            out.push(entry);
        }
        if !values.is_empty() {
            // The count the device is to hold is the number of values given.
            self.eds
                .values
                .insert(ObjAddr::new(index, 0), Init::Bytes(vec![values.keys().max().copied().unwrap_or(0)]));
        }
        out
    }

    /// The `N=text` lines of a `[xxxxName]` or `[xxxxValue]` section, by subindex.
    fn compact_list(&mut self, s: Option<&Section>, index: u16, n: u8) -> BTreeMap<u8, (String, usize)> {
        let Some(s) = s else { return BTreeMap::new() };
        let mut out = BTreeMap::new();
        for (key, (v, line)) in &s.keys {
            if key == "nrofentries" {
                continue;
            }
            match parse_int(key).filter(|k| (1..=i128::from(n)).contains(k)) {
                Some(sub) => {
                    out.insert(sub as u8, (v.clone(), *line));
                }
                None => self.warn(
                    *line,
                    Kind::BadCompactSection,
                    format!(
                        "[{}] {key}={v}: {key} is not a sub-index 1..{n} of {index:04X}'s CompactSubObj; ignored",
                        s.name
                    ),
                ),
            }
        }
        out
    }

    /// One entry; `None` when it cannot be understood (said, with its line).
    fn entry(&mut self, s: &Section, addr: ObjAddr, name: &str, domain: bool) -> Option<Entry> {
        match self.try_entry(s, addr, name, domain) {
            Ok(e) => Some(e),
            Err((line, why)) => {
                self.left_out(line, &format!("{addr} ({name})"), &why);
                None
            }
        }
    }

    fn try_entry(&mut self, s: &Section, addr: ObjAddr, name: &str, domain: bool) -> Result<Entry, (usize, String)> {
        let who = format!("{addr} ({name})");
        // A complex, manufacturer or profile type: its bytes, as python-canopen reads it.
        let mut as_bytes = None;
        let dtype = match self.plain(s, "datatype") {
            Some((dt, line)) => {
                let code = parse_int(dt).ok_or((line, format!("DataType '{dt}' is not a number")))?;
                match data_type_from_code(code).map_err(|m| (line, m))? {
                    Some(t) => t,
                    None => {
                        as_bytes = Some((line, code));
                        DataType::D
                    }
                }
            }
            // A DOMAIN object needs no DataType: it is one.
            None if domain => DataType::D,
            None => return Err((s.line, "it has no DataType".into())),
        };
        let access = match self.plain(s, "accesstype") {
            Some((v, line)) => {
                parse_access(v).ok_or((line, format!("AccessType '{v}' is not ro, wo, rw, rwr, rww or const")))?
            }
            // DOMAINs are often described by type alone.
            None if dtype == DataType::D => Access::Rw,
            None => return Err((s.line, "it has no AccessType".into())),
        };
        let value_key = |r: &mut Self, key: &str| -> Option<(String, usize)> {
            if dtype == DataType::Unicode {
                s.get(key).map(|(v, l)| (r.encoding.decode(v), l))
            } else if dtype == DataType::Vs {
                s.get(key).map(|(v, l)| (v.to_string(), l))
            } else {
                r.plain(s, key).map(|(v, l)| (v.to_string(), l))
            }
        };
        if let Some((line, code)) = as_bytes {
            self.warn(line, Kind::TypeAsBytes, type_as_bytes(&who, code));
        }
        let default = match value_key(self, "defaultvalue").filter(|_| as_bytes.is_none()) {
            // What DOMAIN defaults often say for "nothing".
            Some((v, line))
                if dtype == DataType::D && ["0", "0x0", "null"].contains(&v.to_ascii_lowercase().as_str()) =>
            {
                self.warn(line, Kind::DomainDefault, format!("DefaultValue={v} of DOMAIN {who} read as empty"));
                Init::Bytes(Vec::new())
            }
            Some((v, line)) => match self.eds.value_as_meant(line, "DefaultValue", &v, &who, dtype) {
                Ok(init) => init,
                // A DOMAIN's default is often a file name or a note: not its content.
                Err(m) if dtype == DataType::D => {
                    self.warn(line, Kind::ValueIgnored, format!("DefaultValue of {who}: {m}; read as empty"));
                    Init::Bytes(Vec::new())
                }
                Err(m) => return Err((line, format!("DefaultValue {m}"))),
            },
            None => Init::Bytes(if let Some(size) = dtype.size() { vec![0; size] } else { Vec::new() }),
        };
        let limit = |r: &mut Self, key: &str| -> Option<i128> {
            let (v, line) = value_key(r, key)?;
            if v.is_empty() || dtype.int_range().is_none() {
                return None;
            }
            r.eds.limit(line, s.spelled.get(key).map_or(key, String::as_str), &v, &who, dtype)
        };
        let (low, high) = (limit(self, "lowlimit"), limit(self, "highlimit"));
        let range = super::limits(&who, dtype, low, high).unwrap_or_else(|(kind, why)| {
            self.warn(s.get("lowlimit").map_or(s.line, |(_, line)| line), kind, why);
            None
        });
        let entry = Entry { addr, name: name.to_string(), dtype, access, default, range };
        if let Some((v, line)) = value_key(self, "parametervalue") {
            match self.eds.value_as_meant(line, "ParameterValue", &v, &who, dtype) {
                Ok(value) => self.eds.keep_value(&entry, value, line, "ParameterValue"),
                Err(m) => self.warn(line, Kind::ValueIgnored, format!("ParameterValue of {who}: {m}; ignored")),
            }
        }
        Ok(entry)
    }
}

/// Read a file from disk: a regular file within `input::MAX_EDS_BYTES`.
pub fn read_file(path: &std::path::Path) -> Result<Eds, EdsError> {
    parse(&read_bytes(path)?, &path.display().to_string())
}

/// The bytes of a description file on disk, within `input::MAX_EDS_BYTES`.
pub(crate) fn read_bytes(path: &std::path::Path) -> Result<Vec<u8>, EdsError> {
    let read = crate::input::read_regular_file(path, crate::input::EDS);
    read.map_err(|e| EdsError { path: path.display().to_string(), line: 0, msg: e.to_string() })
}

#[cfg(test)]
mod tests;
