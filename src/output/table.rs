//! Tables for people: plain aligned columns, fitted to the terminal's width by dropping
//! the columns least needed first, then by wrapping cells.

use super::text::terminal_safe;
use comfy_table::{presets, Table};

/// The terminal's width in columns: `COLUMNS` when set (as `ls` and `ps` take it), else
/// what the terminal says.
pub(super) fn terminal_width() -> Option<usize> {
    let from_env = std::env::var("COLUMNS").ok().and_then(|c| c.trim().parse::<usize>().ok()).filter(|c| *c > 0);
    from_env.or_else(|| Table::new().width().map(usize::from)).filter(|w| *w > 0)
}

/// Columns given up first when a table is wider than the terminal, least needed first:
/// identity details that `--wide`, JSON or `sdo read` give, counts that the verdict
/// column sums up. Columns not named here go only after these, from the right.
const DROP_FIRST: &[&str] = &[
    "revision",
    "serial",
    "product_code",
    "vendor_id",
    "device_type",
    "error register",
    "logged",
    "emcy",
    "mfr",
    "from",
    "source",
    "raw",
];

/// A table as text: plain aligned columns; with `wrap_to`, its cells wrapped so that its
/// lines fit that width where they can.
pub(super) fn render(headers: &[&str], rows: &[Vec<String>], wrap_to: Option<usize>) -> String {
    let mut t = Table::new();
    t.load_preset(presets::NOTHING);
    if let Some(width) = wrap_to {
        t.set_content_arrangement(comfy_table::ContentArrangement::Dynamic);
        t.set_width(u16::try_from(width).unwrap_or(u16::MAX));
    }
    t.set_header(headers.to_vec());
    for r in rows {
        // Cells hold what devices and files say: nothing in them may drive the terminal.
        t.add_row(r.iter().map(|c| terminal_safe(c).into_owned()).collect::<Vec<_>>());
    }
    t.to_string().lines().map(|l| l.trim_end().to_string() + "\n").collect()
}

/// The table with the columns of [`DROP_FIRST`] dropped until it fits `width`, and if it
/// still does not, its cells wrapped to the width (a result in words is not dropped); and
/// the headers of the columns dropped.
pub(super) fn fitted(headers: &[&str], rows: &[Vec<String>], width: usize) -> (String, Vec<String>) {
    let fits = |text: &str| text.lines().all(|l| l.chars().count() <= width);
    let mut kept: Vec<usize> = (0..headers.len()).collect();
    loop {
        let shown: Vec<&str> = kept.iter().map(|&i| headers[i]).collect();
        let cells: Vec<Vec<String>> =
            rows.iter().map(|r| kept.iter().map(|&i| r.get(i).cloned().unwrap_or_default()).collect()).collect();
        let hidden = || (0..headers.len()).filter(|i| !kept.contains(i)).map(|i| headers[i].to_string()).collect();
        let plain = render(&shown, &cells, None);
        if fits(&plain) {
            return (plain, hidden());
        }
        match DROP_FIRST.iter().find_map(|d| kept.iter().position(|&i| i > 0 && headers[i] == *d)) {
            Some(at) => {
                kept.remove(at);
            }
            None => return (render(&shown, &cells, Some(width)), hidden()),
        }
    }
}
