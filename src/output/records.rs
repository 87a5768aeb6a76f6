//! A PDO stream on stdout: the header once, then each record as it comes.

use super::command_error::CommandResult;
use super::report::{Format, Line, Output};
use super::text::{csv, joined, terminal_safe, time_of_day};
use crate::canopen::pdo::Layout;
use crate::canopen::types::Value;
use crate::ops::pdo::Record;
use std::fmt::Write as _;
use std::io::{BufWriter, IsTerminal, StdoutLock, Write};
use std::time::{Duration, Instant};

/// Where a stream's records go, in the format asked for.
pub struct Records {
    writers: Vec<RecordWriter>,
    /// The TPDO number of each layout.
    tpdos: Vec<u8>,
    node: u8,
    out: BufWriter<StdoutLock<'static>>,
    line: String,
    /// A terminal sees each record at once; a pipe gets them in batches.
    live: bool,
    last_flush: Instant,
}

impl Output {
    /// Start a stream of `node`'s records decoded by `layouts` (TPDO number, layout).
    pub fn records(&self, node: u8, layouts: &[(u16, Layout)]) -> std::io::Result<Records> {
        let stdout = std::io::stdout();
        let mut r = Records {
            writers: layouts.iter().map(|(_, l)| RecordWriter::new(l, self.format)).collect(),
            tpdos: layouts.iter().map(|(n, _)| *n as u8).collect(),
            node,
            live: stdout.is_terminal(),
            out: BufWriter::new(stdout.lock()),
            line: String::new(),
            last_flush: Instant::now(),
        };
        // One header; with several TPDOs the columns are those of the first.
        r.writers[0].preamble(&mut r.line);
        r.out.write_all(r.line.as_bytes())?;
        Ok(r)
    }
}

impl Output {
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
}

impl Records {
    /// One record; the first has the table's header above it.
    pub fn write(&mut self, r: &Record, first: bool) -> std::io::Result<()> {
        self.line.clear();
        let pdo = self.tpdos[r.layout];
        self.writers[r.layout].record(&mut self.line, r.time_ms, self.node, pdo, &r.values, first);
        self.out.write_all(self.line.as_bytes())?;
        // A reader at the other end of a pipe gets the stream as it goes, in batches.
        if self.live || self.last_flush.elapsed() >= Duration::from_millis(100) {
            self.out.flush()?;
            self.last_flush = Instant::now();
        }
        Ok(())
    }

    pub fn finish(mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

/// What the stream reads from each TPDO (`polled`: by remote frame at this interval), said
/// before the first record.
pub(crate) fn tpdo_lines(node: u8, layouts: &[(u16, Layout)], polled: Option<Duration>) -> Vec<String> {
    let how = polled.map_or(String::new(), |i| format!(", polled by remote frame every {} ms", i.as_millis()));
    layouts
        .iter()
        .map(|(n, l)| {
            let names = joined(l.fields.iter().map(|f| &f.name), ", ");
            format!("node {node} TPDO{n} (0x{:03X}, {} bytes{how}): {names}", l.cob_id, l.len())
        })
        .collect()
}

/// What was put back after a stream, said however the stream ended (README promises it).
pub(crate) fn restored_lines(node: u8, r: &crate::ops::pdo::Restored) -> Vec<String> {
    let mut lines = Vec::new();
    if let Some(n) = r.tpdo {
        lines.push(format!("put back node {node}'s TPDO{n} mapping and parameters as they were"));
    }
    if let Some(state) = r.state {
        lines.push(format!("node {node} back to {state}"));
    }
    lines
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
