//! The INI layer of EDS and DCF files: sections and their keys as CiA 306 writes them,
//! the text encodings real files use, and which sections are objects.

use super::error::EdsError;
use crate::lint::{self, Kind, Warning};
use std::collections::BTreeMap;

/// CiA 306 keeps a line to 255 characters; longer ones are read, with a warning.
const MAX_LINE_CHARS: usize = 255;

pub(super) struct Section {
    pub(super) name: String,
    pub(super) line: usize,
    /// Lower-cased key → value and line; a repeated key keeps its last value.
    pub(super) keys: std::collections::HashMap<String, (String, usize)>,
    /// Lower-cased key → the key as the file spells it, for messages.
    pub(super) spelled: std::collections::HashMap<String, String>,
}

impl Section {
    pub(super) fn get(&self, key: &str) -> Option<(&str, usize)> {
        self.keys.get(key).map(|(v, l)| (v.as_str(), *l))
    }

    /// The section's name as CiA 306 spells it, for messages.
    pub(super) fn spelled_name(&self) -> &'static str {
        match self.name.as_str() {
            "mandatoryobjects" => "MandatoryObjects",
            "optionalobjects" => "OptionalObjects",
            _ => "ManufacturerObjects",
        }
    }
}

/// The blanks an INI line may have around keys and values: ASCII space and tab only, so
/// that Latin-1 bytes such as 0xA0 stay part of the value.
pub(super) fn trim_blanks(s: &str) -> &str {
    s.trim_matches([' ', '\t'])
}

/// Sections with their lines; keys lower-cased. Each byte becomes the Latin-1 character
/// of the same number, so a value's text gives back its exact bytes (`to_latin1`).
pub(super) fn parse_ini(bytes: &[u8], path: &str, warnings: &mut Vec<Warning>) -> Result<Vec<Section>, EdsError> {
    let text: String = bytes.iter().map(|b| *b as char).collect();
    let err = |line: usize, msg: String| EdsError { path: path.to_string(), line, msg };
    let mut sections: Vec<Section> = Vec::new();
    let mut seen_sections: BTreeMap<String, usize> = BTreeMap::new();
    for (i, raw) in text.split('\n').enumerate() {
        let no = i + 1;
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        if raw.chars().count() > MAX_LINE_CHARS {
            let msg = format!(
                "line of {} characters, more than the {MAX_LINE_CHARS} CiA 306 allows (read in full)",
                raw.chars().count()
            );
            lint::push(warnings, Warning::new(path, no, Kind::LongLine, msg));
        }
        let line = trim_blanks(raw);
        if line.is_empty() || line.starts_with(';') || line.starts_with('#') {
            continue;
        }
        if let Some(rest) = line.strip_prefix('[') {
            let name = rest
                .strip_suffix(']')
                .ok_or_else(|| err(no, format!("section header {} has no closing ]", quoted(line))))?;
            let name = trim_blanks(name).to_ascii_lowercase();
            if let Some(first) = seen_sections.insert(name.clone(), no) {
                let msg = format!("section {line} again (before at line {first}): this one replaces it");
                lint::push(warnings, Warning::new(path, no, Kind::RepeatedSection, msg));
            }
            sections.push(Section { name, line: no, keys: Default::default(), spelled: Default::default() });
            continue;
        }
        let (key, value) = line
            .split_once('=')
            .ok_or_else(|| err(no, format!("expected KEY=VALUE or [SECTION], found {}", quoted(line))))?;
        let section =
            sections.last_mut().ok_or_else(|| err(no, format!("{} comes before any [SECTION]", quoted(line))))?;
        let key_lower = trim_blanks(key).to_ascii_lowercase();
        section.spelled.insert(key_lower.clone(), trim_blanks(key).to_string());
        let value = (trim_blanks(value).to_string(), no);
        if let Some((_, first)) = section.keys.insert(key_lower, value) {
            let msg = format!(
                "{} repeated in [{}] (before at line {first}): the value of line {no} is used",
                trim_blanks(key),
                section.name
            );
            lint::push(warnings, Warning::new(path, no, Kind::RepeatedKey, msg));
        }
    }
    Ok(sections)
}

/// A line of the file quoted in a message, in quotes: a binary file's "line" can be
/// thousands of bytes, so at most [`QUOTED_CHARS`] characters are shown (the length said
/// when cut), and each byte a terminal does not show as text is written `\xNN`.
fn quoted(line: &str) -> String {
    let mut shown = String::new();
    for c in line.chars() {
        let c = if c.is_control() { format!("\\x{:02X}", c as u32) } else { c.to_string() };
        if shown.chars().count() + c.chars().count() > QUOTED_CHARS {
            return format!("'{shown}…' ({} characters)", line.chars().count());
        }
        shown.push_str(&c);
    }
    format!("'{shown}'")
}

/// The most characters of a line [`quoted`] shows.
const QUOTED_CHARS: usize = 60;

/// `1018` → (0x1018, None); `1018sub2` → (0x1018, Some(2)); anything else → None.
pub(super) fn object_section(name: &str) -> Option<(u16, Option<u8>)> {
    let (index, sub) = name.split_once("sub").map_or((name, None), |(i, s)| (i, Some(s)));
    if index.len() != 4 || !index.chars().all(|c| c.is_ascii_hexdigit()) {
        return None;
    }
    let index = u16::from_str_radix(index, 16).ok()?;
    match sub {
        None => Some((index, None)),
        Some(s) if !s.is_empty() && s.len() <= 2 => Some((index, Some(u8::from_str_radix(s, 16).ok()?))),
        Some(_) => None,
    }
}

/// How names and descriptions are encoded: Latin-1 as CiA 306 files traditionally are, or
/// UTF-8 where the file says so with a byte order mark or is valid UTF-8 beyond ASCII.
#[derive(Clone, Copy)]
pub(super) struct TextEncoding {
    pub(super) utf8: bool,
}

impl TextEncoding {
    pub(super) fn of(bytes: &[u8]) -> TextEncoding {
        TextEncoding { utf8: !bytes.is_ascii() && std::str::from_utf8(bytes).is_ok() }
    }

    /// Text read as Latin-1 (one character per byte), as the file meant it: UTF-8, or
    /// Windows-1252, whose quotes and dashes take Latin-1's unused control codes 0x80..0x9F.
    pub(super) fn decode(self, latin1: &str) -> String {
        if self.utf8 {
            if let Ok(s) = String::from_utf8(to_latin1(latin1)) {
                return s;
            }
        }
        latin1.chars().map(cp1252).collect()
    }
}

/// Windows-1252's characters for 0x80..0x9F (C1 controls in Latin-1, never text in an EDS).
fn cp1252(c: char) -> char {
    const HIGH: [char; 32] = [
        '€', '\u{81}', '‚', 'ƒ', '„', '…', '†', '‡', 'ˆ', '‰', 'Š', '‹', 'Œ', '\u{8D}', 'Ž', '\u{8F}', '\u{90}', '‘',
        '’', '“', '”', '•', '–', '—', '˜', '™', 'š', '›', 'œ', '\u{9D}', 'ž', 'Ÿ',
    ];
    match c as u32 {
        n @ 0x80..=0x9F => HIGH[(n - 0x80) as usize],
        _ => c,
    }
}

pub(super) const BOM: &[u8] = b"\xEF\xBB\xBF";

/// EDS files are Latin-1: text as its bytes (a character beyond Latin-1 becomes '?').
/// For text from `write`, whose characters stand for bytes, this gives those bytes.
pub fn to_latin1(text: &str) -> Vec<u8> {
    text.chars().map(|c| u8::try_from(c as u32).unwrap_or(b'?')).collect()
}
