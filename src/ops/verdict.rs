//! One check's verdict, the same for `health` and `network check`: what was checked,
//! whether it passed, and what was found.

use super::config;
use crate::hint::Hint;
use serde::Serialize;

/// One check of one node: `present`, `identity`, `objects`, `state`, `error register`...
#[derive(Debug, Serialize)]
#[non_exhaustive]
pub struct Verdict {
    /// What was checked.
    pub check: &'static str,
    /// Whether it passed.
    pub ok: bool,
    /// What was found, in a sentence.
    pub detail: String,
    /// What the user can do about it, for the front end to word after the detail (in JSON
    /// too: a front end serialises the detail with it).
    #[serde(skip)]
    pub remedy: Option<Hint>,
    /// For `objects`: each writable object that differs.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub differences: Vec<config::Difference>,
}

impl Verdict {
    /// A verdict with no object differences.
    pub fn new(check: &'static str, ok: bool, detail: String) -> Verdict {
        Verdict { check, ok, detail, remedy: None, differences: Vec::new() }
    }

    /// This verdict with `remedy` to follow its detail.
    pub fn with_remedy(self, remedy: Option<Hint>) -> Verdict {
        Verdict { remedy, ..self }
    }
}
