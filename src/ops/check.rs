//! `config check`: a device description file against CiA 306, every deviation with
//! file:line, its rule and what a reader does with it. No bus: the file alone.

use crate::error::{Error, Result};
use crate::od::lint::{Kind, Severity, Warning};
use crate::od::{eds, ReadError};
use serde::Serialize;
use std::path::Path;

/// What `config check` found in one file.
#[derive(Debug, Clone, Serialize)]
#[non_exhaustive]
pub struct Checked {
    pub file: String,
    /// `EDS` or `DCF` (a file with values or a node-id to commission).
    pub format: &'static str,
    /// `ok`, `warnings` (read as meant), `errors` (something left out) or `refused`.
    pub verdict: &'static str,
    /// Objects and entries (sub-indexes) read.
    pub objects: usize,
    pub entries: usize,
    pub errors: usize,
    pub warnings: usize,
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

/// Read `path` as canctl reads it everywhere, and say how it deviates.
pub fn check(path: &Path) -> Result<Checked> {
    let file = path.display().to_string();
    // The name says which it is; without .eds or .dcf, whether it has values to commission.
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    let dcf_name = ext.as_deref() == Some("dcf");
    let (read, refusal) = match crate::od::read_description(path) {
        Ok(read) => (Ok(read), Kind::NotAnEds),
        Err(ReadError::Ini(e)) => (Err(e), Kind::NotAnEds),
        // An XML description (XDD, XDC) that does not parse: refused at its line and column.
        Err(ReadError::Xml(e)) => (
            Err(eds::EdsError {
                path: e.path.clone(),
                line: e.line as usize,
                msg: if e.line == 0 { e.msg } else { format!("column {}: {}", e.column, e.msg) },
            }),
            Kind::NotAnXdd,
        ),
    };
    match read {
        Ok(read) => {
            let count = |s| read.warnings.iter().filter(|w| w.severity == s).count();
            let (errors, warnings) = (count(Severity::Error), count(Severity::Warning));
            let verdict = match (errors, warnings) {
                (0, 0) => "ok",
                (0, _) => "warnings",
                _ => "errors",
            };
            let dcf = match ext.as_deref() {
                Some("eds" | "xdd") => false,
                Some("dcf" | "xdc") => true,
                _ => !read.values.is_empty() || read.node_id.is_some(),
            };
            let xml = matches!(ext.as_deref(), Some("xdd" | "xdc"));
            Ok(Checked {
                file,
                format: match (xml, dcf) {
                    (false, false) => "EDS",
                    (false, true) => "DCF",
                    (true, false) => "XDD",
                    (true, true) => "XDC",
                },
                verdict,
                objects: read.dict.objects().count(),
                entries: read.dict.entries().count(),
                errors,
                warnings,
                findings: read.warnings.into_vec(),
            })
        }
        // Not read at all (missing, a directory, too large): nothing to check.
        Err(e) if e.line == 0 => Err(Error::Usage(format!("cannot check {e}"))),
        Err(e) => Ok(Checked {
            file,
            format: match (refusal, dcf_name) {
                (Kind::NotAnXdd, _) => "XDD",
                (_, true) => "DCF",
                _ => "EDS",
            },
            verdict: "refused",
            objects: 0,
            entries: 0,
            errors: 1,
            warnings: 0,
            findings: vec![Warning::new(&e.path, e.line, refusal, format!("{}; the file is refused", e.msg))],
        }),
    }
}
