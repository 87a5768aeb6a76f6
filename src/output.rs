//! The one place that decides how results look: human tables, JSON, CSV, JSON lines.
//! Results go to stdout; progress and diagnostics go to stderr. A command hands its
//! operation's report to [`Output::report`]; streams write records with [`RecordWriter`].

use crate::canopen::pdo::Layout;
use crate::canopen::types::Value;

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::fmt::Write as _;
use std::io::{IsTerminal, Write};

mod bars;
pub(crate) mod buses;
mod check;
mod command_error;
pub(crate) mod completion;
pub(crate) mod config;
pub(crate) mod diagnostics;
pub(crate) mod docs;
pub(crate) mod doctor;
mod drive;
mod events;
mod firmware;
mod health;
mod hints;
mod junit;
mod lss;
pub(crate) mod many_buses;
pub(crate) mod network;
mod nodes;
pub(crate) mod records;
mod remedies;
mod reports;
pub(crate) mod sim;
pub mod stderr;
pub(crate) mod stopped;
mod table;
mod usage;
mod verdicts;
mod wrap;
use table::{fitted, render, terminal_width};

pub use bars::Bars;
pub(crate) use bars::{item_end_text, item_status_text};
pub use command_error::{CommandError, CommandResult};
pub(crate) use drive::{last_seen_text, watching_text};
pub use events::{event_line, say_deviations};
pub(crate) use hints::explained;
pub use hints::{last_scan_hint, library_error_text, switch_hint, Explained};
pub(crate) use junit::{junit_xml, junit_xml_suites};
pub use junit::{TestCase, TestSuite};
pub(crate) use nodes::short_window_note;
pub use reports::{applied_failure_note, sentence, stored_eds_line, Each};
pub use usage::UsageError;

/// The form a report is rendered in (`--format`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Tables and sentences for people.
    Human,
    /// One JSON document per command (JSON lines for streams).
    Json,
    /// A header row and one row per record.
    Csv,
}

/// What `--format` takes: every command's formats, and JUnit XML for the commands that
/// check things. Kept apart from [`Format`] so that a command rendering its own output
/// never has to handle JUnit: the command line refuses it for the others.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum FormatArg {
    /// Tables and sentences for people.
    Human,
    /// One JSON document per command (JSON lines for streams).
    Json,
    /// A header row and one row per record.
    Csv,
    /// JUnit XML, one test case per node and check (network check, health): listed in
    /// their help only (`cli::CheckFormat`), refused by the others.
    #[value(hide = true)]
    Junit,
    /// An XDC (CiA 311 XML) instead of a DCF: config dump, whose help says so; hidden from
    /// the other commands' help and completion, which refuse it.
    #[value(hide = true)]
    Xdc,
}

impl FormatArg {
    /// The format of everything but the JUnit report itself (notes, refusals).
    pub fn format(self) -> Format {
        match self {
            FormatArg::Human | FormatArg::Junit | FormatArg::Xdc => Format::Human,
            FormatArg::Json => Format::Json,
            FormatArg::Csv => Format::Csv,
        }
    }
}

/// The renderer every command writes through: its format and what stdout and stderr are.
pub struct Output {
    /// The form reports take.
    pub format: Format,
    /// Reports that have a JUnit form are written as JUnit XML.
    pub junit: bool,
    /// Configuration files are written as XDC (CiA 311) rather than DCF.
    pub xdc: bool,
    /// Show progress bars: only when stderr is a terminal and not --quiet.
    pub progress: bool,
    /// `--quiet`: notes and progress left out, only results.
    pub quiet: bool,
    /// The width tables are fitted to: the terminal's, when stdout is one and `--wide` was
    /// not given; `None` keeps every column (pipes, files, `--wide`).
    pub fit: Option<usize>,
}

impl Output {
    /// A renderer for `format`, fitting tables and showing progress bars only on a terminal.
    pub fn new(format: Format, quiet: bool) -> Output {
        let fit = if std::io::stdout().is_terminal() { terminal_width() } else { None };
        Output { format, junit: false, xdc: false, progress: !quiet && std::io::stderr().is_terminal(), quiet, fit }
    }

    /// The output `--format` asks for.
    pub(crate) fn for_arg(format: FormatArg, quiet: bool) -> Output {
        Output {
            junit: format == FormatArg::Junit,
            xdc: format == FormatArg::Xdc,
            ..Output::new(format.format(), quiet)
        }
    }

    /// Write text to stdout as it is (machine formats, scripts, man pages). A closed pipe
    /// surfaces as `BrokenPipe` for main to end quietly; any other failure (a full disk) is
    /// an output error, exit 7.
    pub fn print(&self, text: &str) -> std::io::Result<()> {
        let mut out = std::io::stdout().lock();
        let mut write = || {
            out.write_all(text.as_bytes())?;
            if !text.ends_with('\n') {
                out.write_all(b"\n")?;
            }
            out.flush()
        };
        write().map_err(stdout_error)
    }

    /// Bytes as they are (a Latin-1 file's content, say).
    pub fn write_bytes(&self, bytes: &[u8]) -> std::io::Result<()> {
        let mut out = std::io::stdout().lock();
        out.write_all(bytes).and_then(|_| out.flush()).map_err(stdout_error)
    }

    /// Prints `value` as pretty JSON on stdout.
    pub fn json(&self, value: &serde_json::Value) -> std::io::Result<()> {
        self.print(&serde_json::to_string_pretty(value).expect("JSON serialises"))
    }

    /// A table for people (plain aligned columns, as `ps` and `ip` print them, on a terminal
    /// and in a pipe alike: one style, the one README shows), or CSV.
    /// On a terminal too narrow for it, the plain form without the columns least needed
    /// (as `ps` and `kubectl` do), a note saying which and that `--wide` shows them.
    pub fn table(&self, headers: &[&str], rows: &[Vec<String>]) -> std::io::Result<()> {
        if self.format == Format::Csv {
            return self.print(&csv(headers, rows));
        }
        let (text, hidden) = match self.fit {
            Some(width) => fitted(headers, rows, width),
            None => (render(headers, rows, None), Vec::new()),
        };
        self.print(&text)?;
        if !hidden.is_empty() {
            self.note(&format!(
                "not shown at {} columns: {} (--wide shows every column)",
                self.fit.unwrap_or_default(),
                hidden.join(", ")
            ));
        }
        Ok(())
    }

    /// A diagnostic on stderr, unless --quiet.
    pub fn note(&self, text: &str) {
        if !self.quiet {
            stderr::say(&fitted_to_stderr(&terminal_safe_lines(text)));
        }
    }

    /// Several diagnostics on stderr, a line each, unless --quiet.
    pub(crate) fn notes(&self, lines: impl IntoIterator<Item = String>) {
        lines.into_iter().for_each(|line| self.note(&line));
    }

    /// A progress bar over `len` steps, or a hidden one when progress is not shown. With
    /// nothing to count (`len` 0: an erase, a wait), a spinner and the time so far, so that
    /// the screen never stands still for seconds.
    pub fn bar(&self, len: u64, message: &str) -> ProgressBar {
        if len == 0 {
            return self.working(message);
        }
        let style = ProgressStyle::with_template("{msg} [{wide_bar}] {pos}/{len}").expect("valid template");
        self.drawn(Some(len), style.progress_chars("=> "), message)
    }

    /// A line that moves while work of unknown length goes on (listening, waiting for a
    /// device): a spinner, `message` and the seconds so far; hidden when progress is not
    /// shown.
    pub fn working(&self, message: &str) -> ProgressBar {
        let style = ProgressStyle::with_template("{spinner} {msg} ({elapsed})").expect("valid template");
        let line = self.drawn(None, style, message);
        // A hidden line needs no ticker thread.
        if self.progress {
            line.enable_steady_tick(std::time::Duration::from_millis(100));
        }
        line
    }

    /// A line saying where slow work stands, its message changed as it moves on, or a
    /// hidden one when progress is not shown.
    pub fn status(&self, message: &str) -> ProgressBar {
        self.drawn(None, ProgressStyle::with_template("{msg}").expect("valid template"), message)
    }

    /// A count of bytes moved whose total is not known beforehand (an SDO upload), or a
    /// hidden one when progress is not shown. It appears once the first bytes move.
    pub fn counter(&self, message: &str) -> ProgressBar {
        let style = ProgressStyle::with_template("{msg}: {bytes} ({bytes_per_sec})").expect("valid template");
        self.drawn(None, style, message)
    }

    /// A bar over the `len` bytes of a download, with its rate and the time left.
    pub fn bytes_bar(&self, len: u64, message: &str) -> ProgressBar {
        // The bar takes the width the rest leaves: the line fits the terminal.
        let template = "{msg} [{wide_bar}] {bytes}/{total_bytes} {bytes_per_sec}, {eta} left";
        let style = ProgressStyle::with_template(template).expect("valid template").progress_chars("=> ");
        self.drawn(Some(len), style, message)
    }

    /// A transfer's hook that moves `bar`, only when progress is shown: a hook given to a
    /// transfer takes the place of the one the bus was given.
    pub fn transfer_hook(&self, bar: &ProgressBar) -> Option<crate::bus::TransferHook> {
        let shown = bar.clone();
        // Rate and time left count from the first bytes, not from when the bar was made:
        // an erase or a wait before the transfer would make both wrong for the whole run.
        let started = std::sync::Once::new();
        self.progress.then(|| -> crate::bus::TransferHook {
            std::sync::Arc::new(move |b| {
                started.call_once(|| {
                    shown.reset_elapsed();
                    shown.reset_eta();
                });
                shown.set_position(b as u64)
            })
        })
    }

    /// A progress display on stderr, or a hidden one when progress is not shown. Made
    /// hidden and then pointed at stderr: a message set on a bar that draws would draw it
    /// at once, outside a MultiProgress it is about to join, a line left on the screen.
    fn drawn(&self, len: Option<u64>, style: ProgressStyle, message: &str) -> ProgressBar {
        if !self.progress {
            return ProgressBar::hidden();
        }
        let bar = ProgressBar::with_draw_target(len, indicatif::ProgressDrawTarget::hidden());
        bar.set_style(style);
        bar.set_message(message.to_string());
        bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        bar
    }
}

/// Prose for stderr, wrapped at the terminal's width when stderr is a terminal; whole
/// lines otherwise, for logs and grep.
pub fn fitted_to_stderr(text: &str) -> String {
    match std::io::stderr().is_terminal().then(table::terminal_width).flatten() {
        Some(width) => wrap::wrap(text, width),
        None => text.to_string(),
    }
}

/// How a report looks to people (and in CSV, where it is a table).
pub enum Human {
    /// A sentence on stdout.
    Line(String),
    /// A table; `when_empty` says whether a table without rows is still shown (its header).
    Table {
        /// The column names.
        headers: Vec<&'static str>,
        /// The rows, each a cell per column.
        rows: Vec<Vec<String>>,
        /// Whether a table without rows still shows its header.
        when_empty: bool,
    },
    /// A remark on stderr (not with --quiet), in its place among [`Human::Parts`].
    Note(String),
    /// Several of the above, in order (a table, then sentences about it).
    Parts(Vec<Human>),
}

impl Human {
    /// A table shown even without rows (its header alone).
    pub(crate) fn table(headers: &[&'static str], rows: Vec<Vec<String>>) -> Human {
        Human::Table { headers: headers.to_vec(), rows, when_empty: true }
    }
}

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

/// A typed report: serialised as it is for JSON, shown as [`Human`] otherwise.
pub trait Report: serde::Serialize {
    /// How the report looks to people.
    fn human(&self) -> Human;
    /// How the report looks in CSV, when that is not as for people (a row for a sentence).
    fn csv(&self) -> Human {
        self.human()
    }
    /// Remarks on stderr after the result (not in JSON, not with --quiet).
    fn notes(&self) -> Vec<String> {
        Vec::new()
    }
    /// [`Report::human`] as one bus's part of a report on several buses, where every sentence
    /// is prefixed with the bus's address: without the bus the report's sentences name.
    fn human_among_buses(&self) -> Human {
        self.human()
    }
    /// [`Report::notes`] as one bus's part of a report on several buses (see
    /// [`Report::human_among_buses`]).
    fn notes_among_buses(&self) -> Vec<String> {
        self.notes()
    }
    /// The report as test results, for reports of checks.
    fn junit(&self) -> Option<TestSuite> {
        None
    }
    /// The report as test results in several suites (one per bus of a command run on
    /// several); [`Report::junit`]'s one suite otherwise.
    fn junit_suites(&self) -> Vec<TestSuite> {
        self.junit().into_iter().collect()
    }
    /// The report as JSON: as it serialises, but for what canctl words itself (an error's
    /// remedy naming its flags).
    fn json_value(&self) -> serde_json::Value {
        serde_json::to_value(self).expect("reports serialise")
    }
}

/// One line of a stream: a JSON line, a CSV row, or text for people. Every stream's `time`
/// is Unix time in seconds to the millisecond (JSON, CSV) and the time of day (UTC) for
/// people, as [`RecordWriter`]'s.
pub trait Line {
    /// The CSV header row's column names, in the order of [`Line::csv`]'s fields.
    const CSV_HEADER: &'static [&'static str];
    /// The line as a JSON object (one per line in JSON lines).
    fn json(&self) -> serde_json::Value;
    /// The line as a CSV row, without its newline.
    fn csv(&self) -> String;
    /// The line for people.
    fn text(&self) -> String;
}

impl Output {
    /// Render a report in the format asked for.
    pub fn report(&self, report: &impl Report) -> std::io::Result<()> {
        if self.junit {
            match &report.junit_suites()[..] {
                [] => {}
                [suite] => return self.print(&junit_xml(suite)),
                suites => {
                    return self.print(&junit_xml_suites(suites[0].name.split(':').next().unwrap_or("canctl"), suites))
                }
            }
        }
        if self.format == Format::Json {
            return self.json(&report.json_value());
        }
        self.human(if self.format == Format::Csv { report.csv() } else { report.human() })?;
        for note in report.notes() {
            self.note(&note);
        }
        Ok(())
    }

    fn human(&self, shown: Human) -> std::io::Result<()> {
        match shown {
            Human::Line(text) => {
                let text = terminal_safe_lines(&text);
                // Prose fitted to the terminal as tables are; a pipe gets whole lines.
                self.print(&self.fit.map_or_else(|| text.to_string(), |width| wrap::wrap(&text, width)))?
            }
            Human::Table { headers, rows, when_empty } => {
                if when_empty || self.format == Format::Csv || !rows.is_empty() {
                    self.table(&headers, &rows)?;
                }
            }
            Human::Note(text) => self.note(&text),
            Human::Parts(parts) => parts.into_iter().try_for_each(|part| self.human(part))?,
        }
        Ok(())
    }

    /// Progress of an operation as bars and notes on stderr.
    pub fn progress(&self) -> Bars<'_> {
        let target = if self.progress { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() };
        Bars::new(self, MultiProgress::with_draw_target(target))
    }

    /// A stream of lines on standard output, each flushed as it comes, until `next` has no
    /// more; the last line, for what ends the stream.
    pub(crate) fn stream<L: Line>(
        &self,
        mut next: impl FnMut() -> crate::Result<Option<L>>,
    ) -> CommandResult<Option<L>> {
        let stdout = std::io::stdout();
        let mut out = std::io::BufWriter::new(stdout.lock());
        // In CSV its header row first, whether or not any line follows.
        if self.format == Format::Csv {
            write!(out, "{}", csv(L::CSV_HEADER, &[]))?;
        }
        let mut last = None;
        while let Some(line) = next()? {
            self.line(&mut out, &line)?;
            out.flush()?;
            last = Some(line);
        }
        Ok(last)
    }

    /// A line of a stream, in the format asked for.
    pub fn line(&self, w: &mut impl Write, line: &impl Line) -> std::io::Result<()> {
        match self.format {
            Format::Json => writeln!(w, "{}", line.json()),
            Format::Csv => writeln!(w, "{}", line.csv()),
            Format::Human => writeln!(w, "{}", terminal_safe(&line.text())),
        }
    }

    /// What ends a stream: its last JSON line, else a note on stderr.
    pub fn summary(&self, w: &mut impl Write, line: &impl Line) -> std::io::Result<()> {
        if self.format == Format::Json {
            writeln!(w, "{}", line.json())?;
        } else {
            w.flush()?;
            self.note(&line.text());
        }
        w.flush()
    }
}

/// A failure to write standard output, said as such (the kind kept: a closed pipe stays
/// `BrokenPipe`).
fn stdout_error(e: std::io::Error) -> std::io::Error {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        return e;
    }
    std::io::Error::new(e.kind(), format!("cannot write to standard output: {e}"))
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

/// A stream's records (decoded PDOs) in the format asked for, into a reused buffer: this
/// is the hot path of a stream, so no allocation per record.
pub struct RecordWriter {
    format: Format,
    /// Field names as they are (table, CSV header)...
    fields: Vec<String>,
    /// ...and as JSON strings.
    keys: Vec<String>,
}

impl RecordWriter {
    /// A writer for PDOs of `layout`, in `format`; field names from a file are escaped for a
    /// terminal.
    pub fn new(layout: &Layout, format: Format) -> RecordWriter {
        let fields: Vec<String> = layout.fields.iter().map(|f| f.name.clone()).collect();
        let keys = fields.iter().map(|f| json_string(f)).collect();
        // Names come from EDS files: in a table for people, their control characters escaped.
        let fields = match format {
            Format::Human => fields.iter().map(|f| terminal_safe(f).into_owned()).collect(),
            _ => fields,
        };
        RecordWriter { format, keys, fields }
    }

    /// What comes before the first record: the CSV header.
    pub(crate) fn preamble(&self, out: &mut String) {
        if self.format == Format::Csv {
            let headers: Vec<&str> =
                ["time", "pdo"].into_iter().chain(self.fields.iter().map(|f| f.as_str())).collect();
            out.push_str(&csv(&headers, &[]));
        }
    }

    /// One record; `first` puts the table's header above it.
    pub fn record(&self, out: &mut String, time_ms: u64, node: u8, pdo: u8, values: &[Value], first: bool) {
        match self.format {
            Format::Csv => self.csv(out, time_ms, pdo, values),
            Format::Json => self.json(out, time_ms, node, pdo, values),
            Format::Human => self.human(out, time_ms, pdo, values, first),
        }
    }

    /// Appends one record as a CSV row: time, PDO number, then the values.
    pub fn csv(&self, out: &mut String, time_ms: u64, pdo: u8, values: &[Value]) {
        let _ = write!(out, "{}.{:03},{pdo}", time_ms / 1000, time_ms % 1000);
        for v in values {
            out.push(',');
            push_value(out, v);
        }
        out.push('\n');
    }

    /// Appends one record as a JSON line: time, node, PDO number and each field by name.
    pub fn json(&self, out: &mut String, time_ms: u64, node: u8, pdo: u8, values: &[Value]) {
        let _ = write!(out, "{{\"time\":{}.{:03},\"node\":{node},\"pdo\":{pdo}", time_ms / 1000, time_ms % 1000);
        for (key, v) in self.keys.iter().zip(values) {
            out.push(',');
            out.push_str(key);
            out.push(':');
            match v {
                Value::Text(_) | Value::Bytes(_) => out.push_str(&json_string(&v.to_string())),
                Value::Real(r, _) if !r.is_finite() => out.push_str("null"),
                _ => push_value(out, v),
            }
        }
        out.push_str("}\n");
    }

    /// Aligned columns, the time of day (UTC) first.
    /// Column titles of the human table: the names where they fit the column, else `#1`,
    /// `#2`, ... with the names in a legend above the table.
    fn titles(&self) -> Vec<String> {
        if self.fields.iter().all(|f| f.chars().count() <= COLUMN) {
            return self.fields.clone();
        }
        (1..=self.fields.len()).map(|i| format!("#{i}")).collect()
    }

    fn human(&self, out: &mut String, time_ms: u64, pdo: u8, values: &[Value], first: bool) {
        if first {
            let titles = self.titles();
            if titles != self.fields {
                for (t, f) in titles.iter().zip(&self.fields) {
                    let _ = writeln!(out, "{t:>4}  {f}");
                }
            }
            let _ = write!(out, "{:<14}  {:<5}", "time", "pdo");
            for t in &titles {
                let _ = write!(out, "  {t:>COLUMN$}");
            }
            out.push('\n');
        }
        let _ = write!(out, "{}    TPDO{pdo:<1}", time_of_day(time_ms));
        for v in values {
            let _ = match v {
                Value::Text(t) => write!(out, "  {:>COLUMN$}", terminal_safe(t)),
                _ => write!(out, "  {:>COLUMN$}", v.to_string()),
            };
        }
        out.push('\n');
    }
}

/// The width of a value column in the human PDO table.
const COLUMN: usize = 14;

fn push_value(out: &mut String, v: &Value) {
    let _ = match v {
        Value::Uint(u) => write!(out, "{u}"),
        Value::Int(i) => write!(out, "{i}"),
        other => write!(out, "{other}"),
    };
}

fn json_string(s: &str) -> String {
    serde_json::to_string(s).expect("string serialises")
}

#[cfg(test)]
mod tests;
// The error messages as canctl prints them, remedy included (issue 28).
#[cfg(test)]
mod error_texts;
