//! The one place that decides how results look: human tables, JSON, CSV. Results go to
//! stdout; progress and diagnostics go to stderr.

use comfy_table::{presets, Table};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::{IsTerminal, Write};

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Tables and sentences for people.
    Human,
    /// One JSON document per command (JSON lines for streams).
    Json,
    /// A header row and one row per record.
    Csv,
}

pub struct Output {
    pub format: Format,
    /// Show progress bars: only when stderr is a terminal and not --quiet.
    pub progress: bool,
    pub quiet: bool,
}

impl Output {
    pub fn new(format: Format, quiet: bool) -> Output {
        Output { format, progress: !quiet && std::io::stderr().is_terminal(), quiet }
    }

    /// Write text to stdout. A closed pipe surfaces as `BrokenPipe` for main to end quietly.
    pub fn print(&self, text: &str) -> std::io::Result<()> {
        let mut out = std::io::stdout().lock();
        out.write_all(text.as_bytes())?;
        if !text.ends_with('\n') {
            out.write_all(b"\n")?;
        }
        out.flush()
    }

    /// Bytes as they are (a Latin-1 file's content, say).
    pub fn write_bytes(&self, bytes: &[u8]) -> std::io::Result<()> {
        let mut out = std::io::stdout().lock();
        out.write_all(bytes)?;
        out.flush()
    }

    pub fn json(&self, value: &serde_json::Value) -> std::io::Result<()> {
        self.print(&serde_json::to_string_pretty(value).expect("JSON serialises"))
    }

    /// A table for people (framed on a terminal, plain aligned columns in a pipe), or CSV.
    pub fn table(&self, headers: &[&str], rows: &[Vec<String>]) -> std::io::Result<()> {
        if self.format == Format::Csv {
            return self.print(&csv(headers, rows));
        }
        let mut t = Table::new();
        if std::io::stdout().is_terminal() {
            t.load_preset(presets::UTF8_FULL_CONDENSED);
        } else {
            t.load_preset(presets::NOTHING);
        }
        t.set_header(headers.to_vec());
        for r in rows {
            t.add_row(r.clone());
        }
        let text: String = t.to_string().lines().map(|l| l.trim_end().to_string() + "\n").collect();
        self.print(&text)
    }

    /// A diagnostic on stderr, unless --quiet.
    pub fn note(&self, text: &str) {
        if !self.quiet {
            eprintln!("{text}");
        }
    }

    /// A progress bar over `len` steps, or a hidden one when progress is not shown.
    pub fn bar(&self, len: u64, message: &str) -> ProgressBar {
        if !self.progress {
            return ProgressBar::hidden();
        }
        let bar = ProgressBar::new(len);
        bar.set_style(
            ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len}").expect("valid template").progress_chars("=> "),
        );
        bar.set_message(message.to_string());
        bar
    }
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

#[cfg(test)]
mod tests {
    #[test]
    fn csv_quotes_what_needs_it() {
        let rows = vec![vec!["1".to_string(), "a,b".to_string(), "say \"hi\"".to_string()]];
        assert_eq!(super::csv(&["n", "x", "y"], &rows), "n,x,y\n1,\"a,b\",\"say \"\"hi\"\"\"\n");
    }
}
