//! What a device description file says in a way the standard does not, as typed values any
//! reader (EDS, DCF, XDD, XDC) can produce: where (file:line), which rule, and what the
//! reader did with it. `canctl config check` lists them; other commands show them as
//! warnings. The library never prints them.

use serde::Serialize;
use std::fmt;

/// How much a deviation matters to someone using the file.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// Read as the file plainly meant it: nothing is lost.
    Warning,
    /// Something the file describes is not used (an object left out, a value ignored).
    Error,
}

/// The kinds of deviation, each with the rule it breaks and whether anything is lost.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Kind {
    /// A line longer than 255 characters.
    LongLine,
    /// A key given twice in one section.
    RepeatedKey,
    /// A section given twice.
    RepeatedSection,
    /// A comment after a value on its line.
    InlineComment,
    /// A placeholder in `[DeviceComissioning]` (node-id 0, an unknown bit rate).
    PlaceholderCommissioning,
    /// An ARRAY or RECORD without `SubNumber`.
    MissingSubNumber,
    /// `SubNumber` differs from the sub-sections given.
    SubNumberMismatch,
    /// A `CompactSubObj` array whose name or value lists are wrong.
    BadCompactSection,
    /// `CompactSubObj` on a RECORD, which the standard allows on ARRAYs only.
    CompactRecord,
    /// The object lists and the object sections disagree.
    ObjectList,
    /// An object CiA 301 makes mandatory (0x1000, 0x1001, 0x1018) that the file lacks.
    MissingMandatory,
    /// A `[DummyUsage]` entry other than `Dummy0001`..`Dummy0007` = 0 or 1.
    BadDummyUsage,
    /// An object (or one of its sub-entries) that could not be understood, left out.
    ObjectLeftOut,
    /// A key whose value could not be understood, ignored.
    ValueIgnored,
    /// A value in a form CiA 306 does not give, with one plain meaning (a C suffix, a
    /// BOOLEAN as `false`/`true`), read as meant.
    ValueAsMeant,
    /// A value outside the limits the file gives its object, ignored.
    ValueOutsideLimits,
    /// A complex or manufacturer data type, read as DOMAIN.
    TypeAsBytes,
    /// A DOMAIN default that says "nothing" (`0`, `NULL`), read as empty.
    DomainDefault,
    /// The list was cut short.
    MoreLeftOut,
    /// The file is not read at all: not INI, or not an EDS/DCF.
    NotAnEds,
    /// An XML file that is not read at all: malformed, or not a CiA 311 description.
    NotAnXdd,
    /// A deviation a reader gave as a sentence only (`From<String>`).
    Other,
}

impl Kind {
    /// How much the deviation costs: an error loses something, a warning does not.
    pub fn severity(self) -> Severity {
        match self {
            Kind::ObjectLeftOut
            | Kind::ValueIgnored
            | Kind::ValueOutsideLimits
            | Kind::BadCompactSection
            | Kind::NotAnEds
            | Kind::NotAnXdd => Severity::Error,
            _ => Severity::Warning,
        }
    }

    /// The rule of the standard the file does not follow, in a few words.
    pub fn rule(self) -> &'static str {
        match self {
            Kind::LongLine => "CiA 306: a line holds at most 255 characters",
            Kind::RepeatedKey => "CiA 306: a key appears once in its section",
            Kind::RepeatedSection => "CiA 306: a section appears once in the file",
            Kind::InlineComment => {
                "CiA 306: a comment is a line of its own starting with ';'; a value is all text after '='"
            }
            Kind::PlaceholderCommissioning => {
                "CiA 306: [DeviceComissioning] NodeID is 1..127 and BaudRate a CiA 301 bit rate"
            }
            Kind::MissingSubNumber => "CiA 306: an ARRAY or RECORD gives its number of sub-indexes in SubNumber",
            Kind::SubNumberMismatch => "CiA 306: SubNumber is the number of [xxxxsubN] sections",
            Kind::BadCompactSection => {
                "CiA 306: [xxxxName]/[xxxxValue] list NrOfEntries entries of a CompactSubObj array"
            }
            Kind::CompactRecord => "CiA 306: CompactSubObj describes the sub-objects of an ARRAY (0x8)",
            Kind::ObjectList => {
                "CiA 306: [MandatoryObjects], [OptionalObjects] and [ManufacturerObjects] list each object section once, with SupportedObjects their number"
            }
            Kind::MissingMandatory => "CiA 301: every device has 0x1000 (device type), 0x1001 (error register) and 0x1018 (identity)",
            Kind::BadDummyUsage => "CiA 306: [DummyUsage] holds Dummy0001..Dummy0007 = 0 or 1",
            Kind::ObjectLeftOut => {
                "CiA 306: an object gives its ObjectType, DataType, AccessType, values of that type and, if an ARRAY or RECORD, its sub-objects"
            }
            Kind::ValueIgnored => "CiA 306: a key's value has the form the standard gives it",
            Kind::ValueAsMeant => {
                "CiA 306: an integer is decimal, 0x hex or 0 octal, without a C suffix (U, L); a BOOLEAN is 0 or 1"
            }
            Kind::ValueOutsideLimits => "CiA 306: a value lies within its object's LowLimit and HighLimit",
            Kind::TypeAsBytes => "CiA 306: a DataType beyond the basic types (0x0020..) is defined by DEFSTRUCT/DEFTYPE sections canctl does not read",
            Kind::DomainDefault => "CiA 306: a DOMAIN's DefaultValue is hex bytes, or empty for none",
            Kind::MoreLeftOut | Kind::Other => "",
            Kind::NotAnEds => "CiA 306: an EDS or DCF is INI text: [SECTION] headers and KEY=VALUE lines",
            Kind::NotAnXdd => "CiA 311: an XDD or XDC is well-formed XML: an ISO 15745 profile with a CANopenObjectList",
        }
    }
}

/// One deviation: `path:line: message`, the rule, and what the reader did.
#[derive(Clone, PartialEq, Eq, Debug, Serialize)]
pub struct Warning {
    /// The file it is in, as given.
    pub path: String,
    /// 0 when it concerns the whole file.
    pub line: usize,
    /// Which deviation.
    pub kind: Kind,
    /// Whether anything was lost.
    pub severity: Severity,
    /// What the file says and what the reader does with it.
    pub message: String,
    /// The rule the file breaks, in a few words; empty when none applies.
    pub rule: &'static str,
}

impl Warning {
    /// A deviation at `path:line` of this kind, its severity and rule those of the kind.
    pub fn new(path: &str, line: usize, kind: Kind, message: String) -> Warning {
        Warning { path: path.to_string(), line, kind, severity: kind.severity(), message, rule: kind.rule() }
    }
}

/// A deviation given as a sentence that already says where (`file:line: ...`).
impl From<String> for Warning {
    fn from(message: String) -> Warning {
        Warning { path: String::new(), line: 0, kind: Kind::Other, severity: Severity::Warning, message, rule: "" }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            0 if self.path.is_empty() => f.write_str(&self.message),
            0 => write!(f, "{}: {}", self.path, self.message),
            line => write!(f, "{}:{line}: {}", self.path, self.message),
        }
    }
}

/// The deviations kept: a file with thousands of repeated keys gives a list, not a flood.
pub const MAX_WARNINGS: usize = 200;

/// A reader's deviations, in the order of the file; at most [`MAX_WARNINGS`] and one that
/// says more were cut.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(transparent)]
pub struct Warnings(Vec<Warning>);

impl Warnings {
    /// Adds a deviation; past the limit, one line says the rest are left out.
    pub fn push(&mut self, w: impl Into<Warning>) {
        push(&mut self.0, w.into());
    }

    /// The deviations, in the order found.
    pub fn into_vec(self) -> Vec<Warning> {
        self.0
    }
}

impl std::ops::Deref for Warnings {
    type Target = Vec<Warning>;
    fn deref(&self) -> &Vec<Warning> {
        &self.0
    }
}

impl std::ops::DerefMut for Warnings {
    fn deref_mut(&mut self) -> &mut Vec<Warning> {
        &mut self.0
    }
}

impl<'a> IntoIterator for &'a Warnings {
    type Item = &'a Warning;
    type IntoIter = std::slice::Iter<'a, Warning>;
    fn into_iter(self) -> Self::IntoIter {
        self.0.iter()
    }
}

/// Add a deviation to a reader's list, up to [`MAX_WARNINGS`] and one that says more were cut.
pub fn push(list: &mut Vec<Warning>, w: Warning) {
    match list.len() {
        n if n < MAX_WARNINGS => list.push(w),
        MAX_WARNINGS => list.push(Warning::new(
            &w.path,
            0,
            Kind::MoreLeftOut,
            format!("further deviations left out (the first {MAX_WARNINGS} are listed)"),
        )),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reader_may_give_a_sentence_or_a_typed_deviation() {
        let mut list = Warnings::default();
        list.push("x.xdd:3:7: attribute repeated".to_string());
        list.push(Warning::new("x.eds", 4, Kind::InlineComment, "DefaultValue=1 ; one".into()));
        let said: Vec<String> = list.iter().map(|w| w.to_string()).collect();
        assert_eq!(said, ["x.xdd:3:7: attribute repeated", "x.eds:4: DefaultValue=1 ; one"]);
        assert_eq!((list[0].kind, list[0].severity), (Kind::Other, Severity::Warning));
        for _ in 0..MAX_WARNINGS + 5 {
            list.push("again".to_string());
        }
        assert_eq!(list.len(), MAX_WARNINGS + 1, "bounded, with one that says more were cut");
        assert_eq!(list[MAX_WARNINGS].kind, Kind::MoreLeftOut);
    }
}
