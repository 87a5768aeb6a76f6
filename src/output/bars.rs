//! Progress on a terminal: a bar per phase and a line for the item under way, drawn on
//! stderr while a command works.

use super::events::event_line;
use super::report::{style, Output};
use super::{firmware, network};
use crate::ops::{ItemEnd, Progress};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget};
use std::collections::BTreeMap;

/// Where an item of a phase is, as its progress line says it after its name.
pub(crate) fn item_status_text(status: crate::ops::ItemStatus) -> String {
    use crate::ops::ItemStatus;
    match status {
        ItemStatus::Begun => "under way".into(),
        ItemStatus::Transfers { reads, writes } => format!("{reads} read(s), {writes} write(s)"),
        ItemStatus::Step { number, of } => format!("{number} of {of}"),
        ItemStatus::Firmware(step) => step.describe().into(),
    }
}

/// How an item of a phase ended, as its progress line says it.
pub(crate) fn item_end_text(end: &crate::ops::ItemEnd<'_>) -> String {
    use crate::ops::ItemEnd;
    match end {
        // The failure's message alone: its remedy is the report's to give.
        ItemEnd::Applied(row) => network::node_result_words(row, |f| f.to_string()),
        ItemEnd::Checked(checked) => network::checked_words(checked),
        ItemEnd::Downloaded(end) => firmware::download_end_word(*end).to_string(),
    }
}

/// [`crate::ops::Progress`] on a terminal: a bar per phase, notes on stderr.
pub struct Bars<'a> {
    out: &'a Output,
    /// Every line below is drawn through it: lines drawn on their own would overwrite
    /// each other's.
    screen: MultiProgress,
    bar: Option<ProgressBar>,
    /// The line of the item under way, `item: status` (one at a time on this display).
    line: Option<ProgressBar>,
}

impl Output {
    /// Progress of an operation as bars and notes on stderr.
    pub fn progress(&self) -> Bars<'_> {
        let target = if self.progress { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() };
        Bars::new(self, MultiProgress::with_draw_target(target))
    }
}

impl<'a> Bars<'a> {
    /// Bars for `out`, drawn on `screen`.
    fn new(out: &'a Output, screen: MultiProgress) -> Bars<'a> {
        Bars { out, screen, bar: None, line: None }
    }

    /// `bar` drawn on this display, with its other lines (a bar made elsewhere, such as
    /// a download's bytes, joins them here).
    pub fn adopt(&self, bar: ProgressBar) -> ProgressBar {
        self.screen.add(bar)
    }
}

impl crate::ops::Progress for Bars<'_> {
    fn start(&mut self, what: &str, len: u64) {
        self.bar = Some(self.adopt(self.out.bar(len, what)));
    }
    fn transfer(&mut self, what: &str, len: Option<u64>) -> Option<crate::bus::TransferHook> {
        let bar = len.map_or_else(|| self.out.counter(what), |len| self.out.bytes_bar(len, what));
        let bar = self.adopt(bar);
        let hook = self.out.transfer_hook(&bar);
        self.bar = Some(bar);
        hook
    }
    fn advance(&mut self, done: u64) {
        if let Some(b) = &self.bar {
            b.set_position(done);
        }
    }
    fn finish(&mut self) {
        for b in [self.bar.take(), self.line.take()].into_iter().flatten() {
            b.finish_and_clear();
        }
    }
    fn item(&mut self, item: &str, status: crate::ops::ItemStatus) {
        let text = format!("{item}: {}", item_status_text(status));
        match &self.line {
            Some(b) => b.set_message(text),
            None => self.line = Some(self.adopt(self.out.status(&text))),
        }
    }
    fn item_ended(&mut self, _item: &str, _end: crate::ops::ItemEnd<'_>) {
        // One line at a time: an item that ended leaves it (its result is the report's).
        if let Some(b) = self.line.take() {
            b.finish_and_clear();
        }
    }
    fn event(&mut self, event: crate::ops::Event) {
        self.out.note(&event_line(&event));
    }
}

/// Progress of a network procedure on a terminal: the phase's bar, and under it one line
/// per node under way (its transfers so far, then its result), cleared at the end. Nothing
/// is drawn when stderr is not a terminal or with --quiet.
pub(crate) struct NodeBars<'a> {
    out: &'a Output,
    multi: MultiProgress,
    phase: Option<ProgressBar>,
    nodes: BTreeMap<String, ProgressBar>,
}

impl<'a> NodeBars<'a> {
    pub fn new(out: &'a Output) -> NodeBars<'a> {
        let target = if out.progress { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() };
        NodeBars { out, multi: MultiProgress::with_draw_target(target), phase: None, nodes: BTreeMap::new() }
    }

    /// The line of `item`, added under the others the first time.
    fn line(&mut self, item: &str) -> &ProgressBar {
        let multi = &self.multi;
        self.nodes.entry(item.to_string()).or_insert_with(|| {
            let bar = multi.add(ProgressBar::new_spinner());
            bar.set_style(style("  {prefix:<9} {spinner} {wide_msg}"));
            bar.set_prefix(item.to_string());
            bar
        })
    }

    fn clear(&mut self) {
        for (_, bar) in std::mem::take(&mut self.nodes) {
            bar.finish_and_clear();
        }
        if let Some(bar) = self.phase.take() {
            bar.finish_and_clear();
        }
    }
}

impl Progress for NodeBars<'_> {
    fn start(&mut self, what: &str, len: u64) {
        self.clear();
        self.phase = Some(self.multi.add(self.out.bar(len, what)));
    }
    fn advance(&mut self, done: u64) {
        if let Some(bar) = &self.phase {
            bar.set_position(done);
        }
    }
    fn finish(&mut self) {
        self.clear();
    }
    fn event(&mut self, event: crate::ops::Event) {
        let line = super::events::event_line(&event);
        self.multi.suspend(|| self.out.note(&line));
    }
    fn item(&mut self, item: &str, status: crate::ops::ItemStatus) {
        if !self.out.progress {
            return;
        }
        let status = item_status_text(status);
        let bar = self.line(item);
        bar.set_message(status);
        bar.tick();
    }
    fn item_ended(&mut self, item: &str, end: ItemEnd<'_>) {
        if !self.out.progress {
            return;
        }
        let text = super::text::terminal_safe(&item_end_text(&end)).into_owned();
        self.line(item).finish_with_message(text);
    }
}

impl Drop for NodeBars<'_> {
    fn drop(&mut self) {
        self.clear();
    }
}
