//! `config check`: a device description file against CiA 306, every deviation with
//! file:line, its rule and what a reader does with it. No bus: the file alone.

use crate::error::{Error, Result};
use crate::od::lint::{Kind, Severity, Warning};
use crate::od::ReadError;
use serde::Serialize;
use std::path::Path;

/// What `config check` found in one file.
#[derive(Debug, Clone, Default, Serialize)]
#[non_exhaustive]
pub struct Checked {
    /// The file, as named.
    pub file: String,
    /// `EDS` or `DCF` (a file with values or a node-id to commission).
    pub format: &'static str,
    /// `ok`, `warnings` (read as meant), `errors` (something left out) or `refused`.
    pub verdict: &'static str,
    /// Objects read.
    pub objects: usize,
    /// Entries (sub-indexes) read.
    pub entries: usize,
    /// How many findings are errors.
    pub errors: usize,
    /// How many findings are warnings.
    pub warnings: usize,
    /// Each finding, with its line.
    pub findings: Vec<Warning>,
}

impl Checked {
    /// Exit 6 when the file has errors (something it describes is not used, or it cannot
    /// be read at all); warnings alone are 0.
    pub fn check(&self) -> Result<()> {
        match self.errors {
            0 => Ok(()),
            count => Err(Error::FileDeviates { file: self.file.clone(), errors: count, warnings: self.warnings }),
        }
    }
}

/// Read `path` as canctl reads it everywhere, and say how it deviates. A file that cannot
/// be read at all (missing, a directory, too large) is a usage error; one that is read but
/// is no device description is refused, with its findings.
pub fn check(path: &Path) -> Result<Checked> {
    let file = path.display().to_string();
    let bytes = crate::input::read_regular_file(path, crate::input::EDS)?;
    // Told by content, as every command tells it; whether it holds values to commission
    // by its name (.dcf, .xdc), else by whether it has any.
    let xml = crate::od::xdd::is_xml(&bytes);
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    let named_dcf = matches!(ext.as_deref(), Some("dcf" | "xdc"));
    let named_eds = matches!(ext.as_deref(), Some("eds" | "xdd"));
    let read = match crate::od::parse_description(&bytes, &file) {
        Ok(read) => read,
        Err(refusal) => return Ok(refused(file, format_name(xml, named_dcf), refusal)),
    };
    let count = |s| read.warnings.iter().filter(|w| w.severity == s).count();
    let (errors, warnings) = (count(Severity::Error), count(Severity::Warning));
    let verdict = match (errors, warnings) {
        (0, 0) => "ok",
        (0, _) => "warnings",
        _ => "errors",
    };
    let dcf = named_dcf || (!named_eds && (!read.values.is_empty() || read.node_id.is_some()));
    Ok(Checked {
        file,
        format: format_name(xml, dcf),
        verdict,
        objects: read.dict.objects().count(),
        entries: read.dict.entries().count(),
        errors,
        warnings,
        findings: read.warnings.into_vec(),
    })
}

/// `EDS`, `DCF`, `XDD` or `XDC`.
fn format_name(xml: bool, dcf: bool) -> &'static str {
    [["EDS", "DCF"], ["XDD", "XDC"]][usize::from(xml)][usize::from(dcf)]
}

/// A file read but not a device description: one error, at its line (and column, XML).
fn refused(file: String, format: &'static str, refusal: ReadError) -> Checked {
    let finding = match refusal {
        ReadError::Ini(e) => Warning::new(&e.path, e.line, Kind::NotAnEds, e.msg),
        ReadError::Xml(e) => {
            let msg = if e.line == 0 { e.msg } else { format!("column {}: {}", e.column, e.msg) };
            Warning::new(&e.path, e.line as usize, Kind::NotAnXdd, msg)
        }
    };
    let message = format!("{}; the file is refused", finding.message);
    Checked {
        file,
        format,
        verdict: "refused",
        errors: 1,
        findings: vec![Warning { message, ..finding }],
        ..Checked::default()
    }
}
