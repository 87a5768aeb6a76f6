//! `firmware download 5,6,7 IMAGE`: the same download into each node in turn, one report
//! for each.

use super::download::{download, ended, DownloadOptions, DownloadReport, Failed, FirmwareError, Outcome};
use crate::bus::Bus;
use crate::ops::progress::{ItemEnd, Progress};
use serde::Serialize;

/// One node of a download to several.
#[derive(Debug, Serialize)]
pub struct NodeDownload {
    /// The node-id.
    pub node: u8,
    /// What was done to it (none when it was not begun: an earlier node was interrupted).
    pub report: Option<DownloadReport>,
    /// Why it did not finish.
    #[serde(serialize_with = "crate::ops::lss::error_text")]
    pub error: Option<Unfinished>,
}

/// Why one node of a download to several did not finish.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Unfinished {
    /// An earlier node was interrupted: this one was not begun.
    #[error("not begun: interrupted")]
    NotBegun,
    /// Its download failed.
    #[error(transparent)]
    Failed(FirmwareError),
}

/// `firmware download 5,6,7 IMAGE`: each node in turn, the same report for each.
#[derive(Debug, Serialize)]
pub struct Batch {
    /// One entry per node, in the order given.
    pub nodes: Vec<NodeDownload>,
    /// The user asked to stop: the nodes after the one under way were not begun.
    pub interrupted: bool,
}

impl Batch {
    /// The first node's failure, which decides the exit code.
    pub fn into_failure(self) -> Option<FirmwareError> {
        self.nodes.into_iter().find_map(|n| match n.error {
            Some(Unfinished::Failed(e)) => Some(e),
            _ => None,
        })
    }

    /// The row of `node`: how its download ended, or `None` when it was not begun.
    pub(super) fn push(&mut self, node: u8, outcome: Option<Outcome>) {
        self.nodes.push(match outcome {
            None => NodeDownload { node, report: None, error: Some(Unfinished::NotBegun) },
            Some(Ok(report)) => NodeDownload { node, report: Some(report), error: None },
            Some(Err(failed)) => {
                let Failed { error, report } = *failed;
                self.interrupted |= report.interrupted;
                NodeDownload { node, report: Some(*report), error: Some(Unfinished::Failed(error)) }
            }
        });
    }
}

/// Download `image` into each of `nodes` in turn. A node that fails does not stop the
/// others; an interruption does (the nodes not begun are listed without a report). The
/// first failure ([`Batch::into_failure`]) decides the exit code.
pub fn download_each(
    bus: &mut dyn Bus,
    nodes: &[u8],
    image: &[u8],
    o: &DownloadOptions,
    progress: &mut dyn Progress,
) -> Batch {
    let mut batch = Batch { nodes: Vec::new(), interrupted: false };
    for (i, &node) in nodes.iter().enumerate() {
        if batch.interrupted {
            batch.push(node, None);
            continue;
        }
        progress
            .item(&format!("node {node}"), crate::ops::progress::ItemStatus::Step { number: i + 1, of: nodes.len() });
        let outcome = download(bus, node, image, o, progress);
        progress.item_ended(&format!("node {node}"), ItemEnd::Downloaded(ended(&outcome)));
        batch.push(node, Some(outcome));
    }
    batch
}
