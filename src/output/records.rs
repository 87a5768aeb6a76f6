//! A PDO stream on stdout: the header once, then each record as it comes.

use super::{Output, RecordWriter};
use crate::canopen::pdo::Layout;
use crate::ops::pdo::Record;
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
            let names: Vec<&str> = l.fields.iter().map(|f| f.name.as_str()).collect();
            format!("node {node} TPDO{n} (0x{:03X}, {} bytes{how}): {}", l.cob_id, l.len(), names.join(", "))
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
