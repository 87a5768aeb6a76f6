//! XDD and XDC files (CiA 311): the XML form of an EDS and a DCF, read into the same
//! [`Eds`] the INI reader gives, and an XDC written from a dictionary and its values.
//!
//! A `CANopenObject` (and `CANopenSubObject`) carries its type, access and values as
//! attributes (`dataType="0007"`, `accessType="rw"`, `defaultValue`, `actualValue`), or
//! names a `parameter` of the device profile by `uniqueIDRef`, where the same things are
//! an element (`<UDINT/>`), an `access` attribute and `defaultValue`/`actualValue`
//! elements (CANopenEditor writes that form). Attributes of the object win.

use super::cpj::Commissioning;
use super::eds::{self, Eds, Header, WriteError};
use super::lint::Kind;
use super::{Access, Dictionary, Entry, Init, ObjectKind, Values, MANDATORY};
use canctl_canopen::{DataType, ObjAddr};
use roxmltree::{Document, Node};
use std::collections::HashMap;

/// An XML file that cannot be read, or an XDD that is not one, at file:line:column.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct XmlError {
    /// The file, as given.
    pub path: String,
    /// 0 when the file could not be read at all.
    pub line: u32,
    /// The column on `line`; 0 when not known.
    pub column: u32,
    /// What is wrong, in words.
    pub msg: String,
}

impl std::fmt::Display for XmlError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            0 => f.write_str(&self.msg),
            line => write!(f, "{}:{line}:{}: {}", self.path, self.column, self.msg),
        }
    }
}

const BOM: &[u8] = b"\xEF\xBB\xBF";

/// Whether a device description is XML (an XDD or XDC) rather than INI (an EDS or DCF):
/// by content, so that a file named `.eds` that is XML, or an XDC without its extension,
/// is read as what it is.
pub fn is_xml(bytes: &[u8]) -> bool {
    if utf16(bytes).is_some() {
        return true;
    }
    let bytes = bytes.strip_prefix(BOM).unwrap_or(bytes);
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace()).unwrap_or(bytes.len());
    bytes[start..].starts_with(b"<")
}

/// A file in UTF-16 with its byte order mark, as some Windows tools write XDDs: its code
/// units, when it is one.
fn utf16(bytes: &[u8]) -> Option<Vec<u16>> {
    let (rest, little) = match bytes {
        [0xFF, 0xFE, rest @ ..] => (rest, true),
        [0xFE, 0xFF, rest @ ..] => (rest, false),
        _ => return None,
    };
    let unit = |c: &[u8]| if little { u16::from_le_bytes([c[0], c[1]]) } else { u16::from_be_bytes([c[0], c[1]]) };
    Some(rest.chunks_exact(2).map(unit).collect())
}

/// The text of the file: UTF-8 (XML's default), UTF-16 with its byte order mark, or
/// Latin-1 where the declaration says so.
fn decode(bytes: &[u8], path: &str) -> Result<String, XmlError> {
    let error = |line, column, msg: &str| XmlError { path: path.to_string(), line, column, msg: msg.into() };
    if let Some(units) = utf16(bytes) {
        return String::from_utf16(&units)
            .map_err(|_| error(1, 1, "begins with a UTF-16 byte order mark but is not UTF-16"));
    }
    let bytes = bytes.strip_prefix(BOM).unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        Ok(s) => Ok(s.to_string()),
        Err(e) => {
            let head = String::from_utf8_lossy(&bytes[..bytes.len().min(200)]).to_ascii_lowercase();
            if head.contains("iso-8859-1") || head.contains("latin1") || head.contains("windows-1252") {
                return Ok(bytes.iter().map(|b| *b as char).collect());
            }
            let at = e.valid_up_to();
            let line = bytes[..at].iter().filter(|b| **b == b'\n').count() as u32 + 1;
            let column = (at - bytes[..at].iter().rposition(|b| *b == b'\n').map_or(0, |p| p + 1)) as u32 + 1;
            Err(error(line, column, "not UTF-8, and the XML declaration names no other encoding"))
        }
    }
}

/// The IEC 61131 type elements of CiA 311 and the CiA 301 type codes they stand for.
/// BITSTRING is an OCTET_STRING, or a DOMAIN when it has no default (CANopenEditor writes
/// both so).
fn type_code(element: &str) -> Option<u16> {
    Some(match element {
        "BOOL" => 0x01,
        "SINT" | "CHAR" => 0x02,
        "INT" => 0x03,
        "DINT" => 0x04,
        "USINT" | "BYTE" => 0x05,
        "UINT" | "WORD" => 0x06,
        "UDINT" | "DWORD" => 0x07,
        "REAL" => 0x08,
        "STRING" => 0x09,
        "BITSTRING" => 0x0A,
        "WSTRING" => 0x0B,
        "LREAL" => 0x11,
        "LINT" => 0x15,
        "ULINT" | "LWORD" => 0x1B,
        _ => return None,
    })
}

fn access_of(text: &str) -> Option<Access> {
    Some(match text {
        "ro" | "read" => Access::Ro,
        "wo" | "write" => Access::Wo,
        "rw" | "rwr" | "rww" | "readWrite" | "readWriteInput" | "readWriteOutput" => Access::Rw,
        "const" => Access::Const,
        _ => return None,
    })
}

struct Reader<'a, 'i> {
    doc: &'a Document<'i>,
    path: &'a str,
    /// `parameter` elements by `uniqueID`.
    parameters: HashMap<&'a str, Node<'a, 'i>>,
    eds: Eds,
}

fn child<'a, 'i>(n: Node<'a, 'i>, name: &str) -> Option<Node<'a, 'i>> {
    n.children().find(|c| c.is_element() && c.tag_name().name() == name)
}

impl<'a, 'i> Reader<'a, 'i> {
    fn at(&self, n: Node) -> (u32, u32) {
        let pos = self.doc.text_pos_at(n.range().start);
        (pos.row, pos.col)
    }

    fn error(&self, n: Node, msg: String) -> XmlError {
        let (line, column) = self.at(n);
        XmlError { path: self.path.to_string(), line, column, msg }
    }

    fn line(&self, n: Node) -> usize {
        self.at(n).0 as usize
    }

    /// A deviation at the line of element `n`, of its kind and severity.
    fn find(&mut self, n: Node, kind: Kind, msg: String) {
        self.eds.warn(self.line(n), kind, msg);
    }

    /// The parameter an object names by `uniqueIDRef`, if any.
    fn parameter(&self, n: Node<'a, 'i>) -> Option<Node<'a, 'i>> {
        n.attribute("uniqueIDRef").and_then(|id| self.parameters.get(id).copied())
    }

    /// CANopenEditor keeps objects a CANopenNode device leaves out in the file, marked
    /// `CO_disabled`; its EDS export leaves them out, and so does canctl.
    fn disabled(&self, n: Node<'a, 'i>) -> bool {
        self.parameter(n).is_some_and(|p| {
            p.children().any(|c| {
                c.tag_name().name() == "property"
                    && c.attribute("name") == Some("CO_disabled")
                    && c.attribute("value") == Some("true")
            })
        })
    }

    /// An attribute of the object, else the `value` of that element of its parameter.
    fn value_of(&self, n: Node<'a, 'i>, attr: &str, element: &str) -> Option<(&'a str, Node<'a, 'i>)> {
        n.attribute(attr).map(|v| (v, n)).or_else(|| {
            let e = child(self.parameter(n)?, element)?;
            e.attribute("value").map(|v| (v, e))
        })
    }

    fn read(&mut self) -> Result<(), XmlError> {
        let doc = self.doc;
        for n in doc.descendants().filter(|n| n.is_element()) {
            match n.tag_name().name() {
                "DeviceIdentity" => {
                    let keys = [
                        ("vendorName", "vendorname"),
                        ("vendorID", "vendornumber"),
                        ("productName", "productname"),
                        ("productID", "productnumber"),
                    ];
                    for (element, key) in keys {
                        if let Some(text) = child(n, element).and_then(|e| e.text()) {
                            self.eds.info.insert(key.into(), text.trim().to_string());
                        }
                    }
                }
                "DeviceCommissioning" => {
                    if let Some(v) = n.attribute("nodeID") {
                        match eds::parse_int(v).filter(|id| (1..=127).contains(id)) {
                            Some(id) => self.eds.node_id = Some(id as u8),
                            // CiA 311 tools leave 0 for "not yet commissioned": the node
                            // then comes from the command line.
                            None if eds::parse_int(v) == Some(0) => self.find(
                                n,
                                Kind::PlaceholderCommissioning,
                                "nodeID=0 is a placeholder, not a node-id: the node given on the command line is used"
                                    .into(),
                            ),
                            None => self.find(n, Kind::ValueIgnored, format!("nodeID '{v}' is not 1 to 127: ignored")),
                        }
                    }
                }
                "CANopenObject" => self.object(n)?,
                _ => {}
            }
        }
        Ok(())
    }

    fn object(&mut self, n: Node<'a, 'i>) -> Result<(), XmlError> {
        let index = n
            .attribute("index")
            .filter(|i| i.len() == 4)
            .and_then(|i| u16::from_str_radix(i, 16).ok())
            .ok_or_else(|| self.error(n, "CANopenObject without an index of 4 hex digits".into()))?;
        let name = n.attribute("name").map_or_else(|| format!("Object {index:04X}"), str::to_string);
        let code = match n.attribute("objectType") {
            Some(t) => eds::parse_int(t).ok_or_else(|| format!("objectType '{t}' is not a number")),
            None => Ok(7),
        };
        let left_out = format!("{index:04X} ({name}) left out");
        let kind = match code.and_then(|code| eds::object_kind(code).map_err(|why| format!("objectType {why}"))) {
            Ok(Some(kind)) => kind,
            Ok(None) => return Ok(()),
            Err(why) => {
                self.find(n, Kind::ObjectLeftOut, format!("{left_out}: {why}"));
                return Ok(());
            }
        };
        if index < 0x1000 || self.disabled(n) {
            return Ok(());
        }
        if kind == ObjectKind::Var {
            self.entry(n, ObjAddr::new(index, 0), &name);
            return Ok(());
        }
        let subs: Vec<Node> =
            n.children().filter(|c| c.is_element() && c.tag_name().name() == "CANopenSubObject").collect();
        if subs.is_empty() {
            self.find(n, Kind::ObjectLeftOut, format!("{left_out}: an ARRAY or RECORD without any CANopenSubObject"));
        }
        for s in subs {
            let Some(sub) = s.attribute("subIndex").and_then(|v| u8::from_str_radix(v, 16).ok()) else {
                let why = format!("a sub-object of {index:04X} ({name}) left out: it has no subIndex of hex digits");
                self.find(s, Kind::ObjectLeftOut, why);
                continue;
            };
            let member = s.attribute("name").map_or_else(|| format!("Sub-index {sub}"), str::to_string);
            self.entry(s, ObjAddr::new(index, sub), &member);
        }
        // As an EDS's: an object none of whose sub-objects could be read is not there.
        if self.eds.dict.has_index(index) {
            self.eds.dict.object(index, &name, kind);
        }
        Ok(())
    }

    /// One value: its type, access, default, limits and (XDC) actual value. What cannot be
    /// understood is left out, said at the line of its element, as an EDS's is.
    fn entry(&mut self, n: Node<'a, 'i>, addr: ObjAddr, name: &str) {
        match self.try_entry(n, addr, name) {
            Ok(entry) => self.eds.dict.insert(entry),
            Err((at, why)) => self.find(at, Kind::ObjectLeftOut, format!("{addr} ({name}) left out: {why}")),
        }
    }

    /// The data type of an object: its `dataType` attribute, else its parameter's type
    /// element; a CiA 301 type canctl does not handle is read as DOMAIN, as in an EDS
    /// (`Err` says why there is none).
    fn data_type(&mut self, n: Node<'a, 'i>, who: &str, no_default: bool) -> Result<(DataType, bool), String> {
        let code = match n.attribute("dataType") {
            Some(dt) => {
                let hex = dt.strip_prefix("0x").or_else(|| dt.strip_prefix("0X")).unwrap_or(dt);
                i128::from_str_radix(hex, 16).map_err(|_| format!("dataType '{dt}' is not a hex number"))?
            }
            None => {
                let element = self
                    .parameter(n)
                    .and_then(|p| p.children().filter(|c| c.is_element()).find_map(|c| type_code(c.tag_name().name())));
                match element.ok_or("it has no dataType, nor a parameter with a type element")? {
                    // BITSTRING without a default is a DOMAIN (CANopenEditor writes both so).
                    0x0A if no_default => 0x0F,
                    code => i128::from(code),
                }
            }
        };
        match eds::data_type_from_code(code)? {
            Some(dtype) => Ok((dtype, false)),
            None => {
                self.find(n, Kind::TypeAsBytes, eds::type_as_bytes(who, code));
                Ok((DataType::D, true))
            }
        }
    }

    /// Who may access an object: its `accessType`, else its parameter's `access`, which
    /// CiA 311 makes "read" when not given.
    fn access(&self, n: Node<'a, 'i>) -> Result<Access, String> {
        match n.attribute("accessType") {
            Some(a) => access_of(a).ok_or_else(|| format!("accessType '{a}' is not ro, wo, rw, rwr, rww or const")),
            None => {
                let a = self.parameter(n).and_then(|p| p.attribute("access")).unwrap_or("read");
                access_of(a).ok_or_else(|| format!("its parameter's access '{a}' is not read, write or readWrite"))
            }
        }
    }

    fn try_entry(&mut self, n: Node<'a, 'i>, addr: ObjAddr, name: &str) -> Result<Entry, (Node<'a, 'i>, String)> {
        let default = self.value_of(n, "defaultValue", "defaultValue");
        let no_default = default.is_none_or(|(v, _)| v.trim().is_empty());
        let who = format!("{addr} ({name})");
        let (dtype, as_bytes) = self.data_type(n, &who, no_default).map_err(|why| (n, why))?;
        let access = self.access(n).map_err(|why| (n, why))?;
        // As in an EDS, a value may be read as it plainly means (a C suffix), said so.
        let value = |r: &mut Self, key: &str, text: &str, at: Node| match dtype {
            // XML carries text as Unicode: a string's bytes are its UTF-8.
            DataType::Vs => Ok(Init::Bytes(text.as_bytes().to_vec())),
            DataType::D => canctl_canopen::types::parse_hex(text).map(Init::Bytes),
            _ => r.eds.value_as_meant(r.line(at), key, text, &who, dtype),
        };
        let default = match default.filter(|_| !as_bytes) {
            Some((text, at)) => match value(self, "defaultValue", text, at) {
                Ok(v) => v,
                // A DOMAIN's default is often a file name or a note: not its content.
                Err(why) if dtype == DataType::D => {
                    let why = format!("defaultValue of DOMAIN {who}: {why}; read as empty");
                    self.find(at, Kind::ValueIgnored, why);
                    Init::Bytes(Vec::new())
                }
                Err(why) => return Err((at, format!("defaultValue {why}"))),
            },
            None => Init::Bytes(dtype.size().map_or_else(Vec::new, |size| vec![0; size])),
        };
        let line = self.line(n);
        let mut limit = |attr: &str| {
            let text = n.attribute(attr).filter(|t| !t.is_empty() && dtype.int_range().is_some())?;
            self.eds.limit(line, attr, text, &who, dtype)
        };
        let (low, high) = (limit("lowLimit"), limit("highLimit"));
        let range = super::limits(&who, dtype, low, high).unwrap_or_else(|(kind, why)| {
            self.find(n, kind, why);
            None
        });
        let entry = Entry { addr, name: name.to_string(), dtype, access, default, range };
        if let Some((text, at)) = self.value_of(n, "actualValue", "actualValue") {
            let line = self.line(at);
            match value(self, "actualValue", text, at) {
                Ok(v) => self.eds.keep_value(&entry, v, line, "actualValue"),
                Err(why) => self.find(at, Kind::ValueIgnored, format!("actualValue of {who}: {why}; ignored")),
            }
        }
        Ok(entry)
    }

    /// CiA 301's mandatory objects the file lacks, said at its object list.
    fn mandatory_objects(&mut self) {
        let Some(list) = self.doc.descendants().find(|n| n.tag_name().name() == "CANopenObjectList") else { return };
        for index in MANDATORY {
            if !self.eds.dict.has_index(index) {
                self.find(list, Kind::MissingMandatory, format!("no object 0x{index:04X}: {}", eds::mandatory(index)));
            }
        }
    }
}

/// Parse an XDD or XDC. `path` is only for messages.
pub fn parse(bytes: &[u8], path: &str) -> Result<Eds, XmlError> {
    let text = decode(bytes, path)?;
    let doc = document(&text, path)?;
    let root = doc.root_element();
    let not_xdd = |msg: String| {
        let pos = doc.text_pos_at(root.range().start);
        XmlError { path: path.to_string(), line: pos.row, column: pos.col, msg }
    };
    if root.tag_name().name() != "ISO15745ProfileContainer" {
        let msg = "is not an XDD or XDC: CiA 311 files begin with <ISO15745ProfileContainer>";
        return Err(not_xdd(format!("<{}> {msg}", root.tag_name().name())));
    }
    let parameters = doc
        .descendants()
        .filter(|n| n.is_element() && n.tag_name().name() == "parameter")
        .filter_map(|n| n.attribute("uniqueID").map(|id| (id, n)))
        .collect();
    let mut reader = Reader { doc: &doc, path, parameters, eds: Eds { path: path.to_string(), ..Eds::default() } };
    reader.read()?;
    reader.mandatory_objects();
    // In the order of the file; the note that more were cut stays last.
    reader.eds.warnings.sort_by_key(|w| if w.kind == Kind::MoreLeftOut { usize::MAX } else { w.line });
    // An object that could not be read is a finding; a file without any is no XDD.
    if !doc.descendants().any(|n| n.tag_name().name() == "CANopenObject") {
        return Err(not_xdd("no CANopenObjectList with objects: not a CANopen XDD or XDC".into()));
    }
    Ok(reader.eds)
}

/// The `DeviceCommissioning` of an XDC (node-id, name, bit rate, network); empty when the
/// file has none. A nodeID of 0 is "not commissioned yet", as CiA 311 tools leave it.
pub fn read_commissioning(bytes: &[u8], path: &str) -> Result<Commissioning, XmlError> {
    let text = decode(bytes, path)?;
    let doc = document(&text, path)?;
    let mut c = Commissioning::default();
    let Some(n) = doc.descendants().find(|n| n.tag_name().name() == "DeviceCommissioning") else {
        return Ok(c);
    };
    let text = |attr: &str| n.attribute(attr).map(str::trim).filter(|v| !v.is_empty()).map(str::to_string);
    c.node_id = text("nodeID").and_then(|v| eds::parse_int(&v)).filter(|id| (1..=127).contains(id)).map(|id| id as u8);
    c.node_name = text("nodeName");
    // "500 Kbps", as CiA 311 writes it; a bare number is kbit/s too.
    c.baudrate_kbit = text("actualBaudRate")
        .and_then(|v| v.to_ascii_lowercase().trim_end_matches("kbps").trim_end_matches("kbit/s").trim().parse().ok());
    c.net_number = text("networkNumber").and_then(|v| eds::parse_int(&v)).and_then(|v| u32::try_from(v).ok());
    c.network_name = text("networkName");
    c.canopen_manager = text("CANopenManager").map(|v| v == "true" || v == "1");
    Ok(c)
}

/// The XML document of `text`, without a DTD (entities that expand are refused).
fn document<'t>(text: &'t str, path: &str) -> Result<Document<'t>, XmlError> {
    let opts = roxmltree::ParsingOptions { allow_dtd: false, ..Default::default() };
    Document::parse_with_options(text, opts).map_err(|e| {
        let pos = e.pos();
        // roxmltree ends its text with the position, which the error gives first.
        let text = e.to_string();
        let text = text.strip_suffix(&format!(" at {pos}")).unwrap_or(&text).to_string();
        XmlError { path: path.to_string(), line: pos.row, column: pos.col, msg: format!("malformed XML: {text}") }
    })
}

/// Text for an XML attribute: markup characters and the white space that attribute
/// normalisation would change escaped; characters XML 1.0 cannot carry refused.
fn attr(text: &str) -> Result<String, String> {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\t' => out.push_str("&#x9;"),
            '\n' => out.push_str("&#xA;"),
            '\r' => out.push_str("&#xD;"),
            c if (c as u32) < 0x20 => {
                return Err(format!("it holds the control character 0x{:02X}, which XML 1.0 cannot carry", c as u32))
            }
            c => out.push(c),
        }
    }
    Ok(out)
}

/// The text of a value in an XDC: as in an EDS, except that a string is Unicode text.
fn value_text(e: &Entry, init: &Init) -> Result<String, String> {
    match (e.dtype, init) {
        (DataType::Vs, Init::Bytes(b)) => {
            let s = std::str::from_utf8(b).map_err(|_| "it is not UTF-8 text, which an XML file needs".to_string())?;
            attr(s)
        }
        _ => eds::value_text(init, e.dtype).and_then(|t| attr(&t)),
    }
}

/// An XDC (with `actualValue`s) or an XDD (without) for `dict`, as the bytes of the file.
/// Every value reads back to the same bytes (`parse`), or nothing is written and the error
/// names the object and why.
pub fn write_bytes(dict: &Dictionary, values: Option<&Values>, h: &Header) -> Result<Vec<u8>, WriteError> {
    let text = |what: &str, s: &str| attr(s).map_err(|why| WriteError { what: what.to_string(), why });
    let mut o = String::new();
    o.push_str("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
    o.push_str("<!-- written by canctl -->\n");
    o.push_str("<ISO15745ProfileContainer xmlns=\"http://www.canopen.org/xml/1.1\">\n");
    o.push_str("  <ISO15745Profile>\n    <ProfileHeader>\n      <ProfileIdentification>CANopen device profile</ProfileIdentification>\n      <ProfileRevision>1.1</ProfileRevision>\n      <ProfileName/>\n      <ProfileSource/>\n      <ProfileClassID>Device</ProfileClassID>\n      <ISO15745Reference><ISO15745Part>1</ISO15745Part><ISO15745Edition>1</ISO15745Edition><ProfileTechnology>CANopen</ProfileTechnology></ISO15745Reference>\n    </ProfileHeader>\n");
    o.push_str(&format!(
        "    <ProfileBody formatName=\"CANopen\" formatVersion=\"1.0\" fileName=\"{}\" fileCreator=\"canctl\" fileVersion=\"1\">\n",
        text("fileName", &h.file_name)?
    ));
    o.push_str("      <DeviceIdentity>\n");
    o.push_str(&format!("        <vendorName>{}</vendorName>\n", text("vendorName", &h.vendor_name)?));
    o.push_str(&format!("        <vendorID>0x{:08X}</vendorID>\n", h.vendor_number));
    o.push_str(&format!("        <productName>{}</productName>\n", text("productName", &h.product_name)?));
    o.push_str(&format!("        <productID>0x{:08X}</productID>\n", h.product_number));
    o.push_str(&format!(
        "        <productText><description lang=\"en\">{}</description></productText>\n",
        text("description", &h.description)?
    ));
    o.push_str("      </DeviceIdentity>\n    </ProfileBody>\n  </ISO15745Profile>\n");
    o.push_str("  <ISO15745Profile>\n    <ProfileHeader>\n      <ProfileIdentification>CANopen communication network profile</ProfileIdentification>\n      <ProfileRevision>1.1</ProfileRevision>\n      <ProfileName/>\n      <ProfileSource/>\n      <ProfileClassID>CommunicationNetwork</ProfileClassID>\n      <ISO15745Reference><ISO15745Part>1</ISO15745Part><ISO15745Edition>1</ISO15745Edition><ProfileTechnology>CANopen</ProfileTechnology></ISO15745Reference>\n    </ProfileHeader>\n");
    o.push_str(
        "    <ProfileBody formatName=\"CANopen\" formatVersion=\"1.0\" fileCreator=\"canctl\" fileVersion=\"1\">\n",
    );
    o.push_str("      <ApplicationLayers>\n        <CANopenObjectList>\n");
    for (index, name, kind) in dict.objects() {
        let entries: Vec<&Entry> = dict.object_entries(index).collect();
        if entries.is_empty() {
            continue;
        }
        let name = text(&format!("0x{index:04X} name"), name)?;
        if kind == ObjectKind::Var {
            o.push_str(&format!("          <CANopenObject index=\"{index:04X}\" name=\"{name}\" objectType=\"7\""));
            o.push_str(&keys(dict, entries[0], values, h.node_id)?);
            o.push_str("/>\n");
            continue;
        }
        o.push_str(&format!(
            "          <CANopenObject index=\"{index:04X}\" name=\"{name}\" objectType=\"{}\" subNumber=\"{}\">\n",
            kind.code(),
            entries.len()
        ));
        for e in entries {
            let member = text(&format!("{} name", e.addr), &e.name)?;
            o.push_str(&format!(
                "            <CANopenSubObject subIndex=\"{:02X}\" name=\"{member}\" objectType=\"7\"",
                e.addr.sub
            ));
            o.push_str(&keys(dict, e, values, h.node_id)?);
            o.push_str("/>\n");
        }
        o.push_str("          </CANopenObject>\n");
    }
    o.push_str("        </CANopenObjectList>\n      </ApplicationLayers>\n");
    if let Some(id) = h.node_id.filter(|_| values.is_some()) {
        o.push_str(&format!("      <DeviceCommissioning nodeID=\"{id}\" nodeName=\"\" actualBaudRate=\"\"/>\n"));
    }
    o.push_str("    </ProfileBody>\n  </ISO15745Profile>\n</ISO15745ProfileContainer>\n");
    Ok(o.into_bytes())
}

/// The `actualValue` text of `bytes` for entry `e` in an XDC for `node` (escaped for an
/// attribute), or why an XDC cannot carry it exactly.
pub fn actual_value_text(e: &Entry, bytes: &[u8], node: Option<u8>) -> Result<String, String> {
    match e.dtype {
        DataType::Vs => value_text(e, &Init::Bytes(bytes.to_vec())),
        // The same $NODEID form for COB-IDs of the predefined connection set as a DCF.
        _ => eds::parameter_text(e, bytes, node).and_then(|t| attr(&t)),
    }
}

/// The attributes of one value: type, access, default, limits, and its actual value.
fn keys(dict: &Dictionary, e: &Entry, values: Option<&Values>, node: Option<u8>) -> Result<String, WriteError> {
    let refuse = |key: &str, why: String| WriteError {
        what: format!("{} ({}) {key}", e.addr, dict.display_name(e.addr).unwrap_or_else(|| e.name.clone())),
        why,
    };
    let mut o = format!(" dataType=\"{:04X}\" accessType=\"{}\"", e.dtype.code(), e.access.name());
    // A DOMAIN's default is its content, which has no place in the file.
    if e.dtype != DataType::D {
        let text = value_text(e, &e.default).map_err(|why| refuse("defaultValue", why))?;
        o.push_str(&format!(" defaultValue=\"{text}\""));
    }
    if let Some((lo, hi)) = e.range {
        o.push_str(&format!(" lowLimit=\"{lo}\" highLimit=\"{hi}\""));
    }
    o.push_str(" PDOmapping=\"no\"");
    if let Some(v) = values.and_then(|v| v.get(&e.addr)) {
        let text = actual_value_text(e, v, node).map_err(|why| refuse("actualValue", why))?;
        o.push_str(&format!(" actualValue=\"{text}\""));
    }
    Ok(o)
}

#[cfg(test)]
mod tests;
