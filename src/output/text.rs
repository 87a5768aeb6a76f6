//! Text as canctl writes it: safe for a terminal, joined into lists, CSV, times of day.

use std::fmt::Write as _;

/// Each of `items` as text, `sep` between them.
pub(crate) fn joined<T: std::fmt::Display>(items: impl IntoIterator<Item = T>, sep: &str) -> String {
    items.into_iter().map(|i| i.to_string()).collect::<Vec<_>>().join(sep)
}

/// [`joined`] by commas, or `none` when there are no items.
pub(crate) fn listed<T: std::fmt::Display>(items: impl IntoIterator<Item = T>, none: &str) -> String {
    let list = joined(items, ", ");
    if list.is_empty() {
        none.to_string()
    } else {
        list
    }
}

/// Text for a terminal with every control character escaped (`\x1b`, `\n`, `\u{9b}`), and
/// the bidirectional overrides that reorder what is shown: a string from a device or a file
/// cannot move the cursor, retitle the window or hide part of a line. JSON and CSV keep
/// the exact text with their own escaping; this is for human output only.
pub(crate) fn terminal_safe(text: &str) -> std::borrow::Cow<'_, str> {
    escape(text, false)
}

/// `terminal_safe`, line breaks kept: for messages of several lines.
pub fn terminal_safe_lines(text: &str) -> std::borrow::Cow<'_, str> {
    escape(text, true)
}

fn unsafe_char(c: char) -> bool {
    c.is_control() || matches!(c, '\u{200E}' | '\u{200F}' | '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}')
}

fn escape(text: &str, keep_newlines: bool) -> std::borrow::Cow<'_, str> {
    if !text.chars().any(|c| unsafe_char(c) && !(keep_newlines && c == '\n')) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            '\n' if keep_newlines => out.push('\n'),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if unsafe_char(c) && (c as u32) < 0x80 => {
                let _ = write!(out, "\\x{:02x}", c as u32);
            }
            c if unsafe_char(c) => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
    }
    std::borrow::Cow::Owned(out)
}

/// RFC 4180 CSV.
pub fn csv(headers: &[&str], rows: &[Vec<String>]) -> String {
    let field = |f: &str| {
        if f.contains([',', '"', '\n', '\r']) {
            format!("\"{}\"", f.replace('"', "\"\""))
        } else {
            f.to_string()
        }
    };
    let mut s = headers.iter().map(|h| field(h)).collect::<Vec<_>>().join(",") + "\n";
    for r in rows {
        s += &(r.iter().map(|f| field(f)).collect::<Vec<_>>().join(",") + "\n");
    }
    s
}

/// Unix time in ms as the time of day (UTC) for people: `HH:MM:SS.mmm`.
pub(crate) fn time_of_day(time_ms: u64) -> String {
    let secs = time_ms / 1000;
    let (h, m, s, ms) = (secs / 3600 % 24, secs / 60 % 60, secs % 60, time_ms % 1000);
    format!("{h:02}:{m:02}:{s:02}.{ms:03}")
}
