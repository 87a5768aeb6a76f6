//! The renderer every command writes through ([`Output`]), and what it renders: a typed
//! [`Report`] (JSON as it serialises, [`Human`] for people and CSV) and the [`Line`]s of a
//! stream.

use super::junit::{junit_xml, junit_xml_suites, TestSuite};
use super::table::{fitted, render, terminal_width};
use super::text::{csv, terminal_safe, terminal_safe_lines};
use super::{stderr, wrap};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::{IsTerminal, Write};

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
        stderr::write_line(&mut std::io::stdout().lock(), text).map_err(stdout_error)
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
        let style = style("{msg} [{wide_bar}] {pos}/{len}");
        self.drawn(Some(len), style.progress_chars("=> "), message)
    }

    /// A line that moves while work of unknown length goes on (listening, waiting for a
    /// device): a spinner, `message` and the seconds so far; hidden when progress is not
    /// shown.
    pub fn working(&self, message: &str) -> ProgressBar {
        let style = style("{spinner} {msg} ({elapsed})");
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
        self.drawn(None, style("{msg}"), message)
    }

    /// A count of bytes moved whose total is not known beforehand (an SDO upload), or a
    /// hidden one when progress is not shown. It appears once the first bytes move.
    pub fn counter(&self, message: &str) -> ProgressBar {
        let style = style("{msg}: {bytes} ({bytes_per_sec})");
        self.drawn(None, style, message)
    }

    /// A bar over the `len` bytes of a download, with its rate and the time left.
    pub fn bytes_bar(&self, len: u64, message: &str) -> ProgressBar {
        // The bar takes the width the rest leaves: the line fits the terminal.
        let template = "{msg} [{wide_bar}] {bytes}/{total_bytes} {bytes_per_sec}, {eta} left";
        let style = style(template).progress_chars("=> ");
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
    let width = std::io::stderr().is_terminal().then(terminal_width).flatten();
    width.map_or_else(|| text.to_string(), |width| wrap::wrap(text, width))
}

/// A progress display's style from its template (one of canctl's own, all valid).
pub(crate) fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template).expect("valid template")
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
