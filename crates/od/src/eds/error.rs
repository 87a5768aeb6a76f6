//! The one error of reading an EDS or DCF: what is wrong, at file:line.

/// An EDS or DCF that cannot be read or parsed, at file:line when a line is to blame.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct EdsError {
    /// The file, as given.
    pub path: String,
    /// 0 when the file could not be read at all.
    pub line: usize,
    /// What is wrong, in words.
    pub msg: String,
}

impl std::fmt::Display for EdsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            0 => f.write_str(&self.msg),
            line => write!(f, "{}:{line}: {}", self.path, self.msg),
        }
    }
}
