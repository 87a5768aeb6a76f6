//! What a command the user stopped says it did and did not do, and the state it leaves;
//! the command then ends as an interruption (exit 130).

use super::{sentence, Each, Output, Report};
use crate::ops::store_all::{EachNode, Ended};
use crate::ops::Stopped;
use crate::Error;
use std::path::Path;

const NOTHING_CHANGED: &str = "nothing was changed on the device";

/// Say `report`, then end as an interruption.
fn said(out: &Output, report: &Stopped) -> anyhow::Result<()> {
    out.report(report)?;
    Err(Error::Interrupted.into())
}

/// What a read-only command read, or, stopped part-way (`not_done`: what it was reading),
/// its report saying so and an interruption; any other error as it is.
pub(crate) fn read<R>(out: &Output, command: &str, not_done: String, read: crate::Result<R>) -> anyhow::Result<R> {
    match read {
        Err(e) if e.is_interrupted() => {
            out.report(&Stopped::new(command, Vec::new(), vec![not_done], NOTHING_CHANGED.into()))?;
            Err(Error::Interrupted.into())
        }
        read => Ok(read?),
    }
}

/// What an interrupted command did not write: `--out FILE` (kept as it was) or the `what`
/// on standard output.
fn not_written(file: Option<&Path>, what: &str) -> String {
    match file {
        Some(path) if path.exists() => format!("writing {} (the old file is unchanged)", path.display()),
        Some(path) => format!("writing {} (no file made)", path.display()),
        None => format!("the {what} on standard output (none printed: it would be incomplete)"),
    }
}

/// An NMT command stopped by the user before it went out; any other error as it is.
pub(crate) fn nmt_not_sent(out: &Output, name: &str, target: u8, e: Error) -> anyhow::Result<()> {
    if !e.is_interrupted() {
        return Err(e.into());
    }
    let whom = crate::ops::nmt::target_text(target);
    let not_done = vec![format!("NMT {name} to {whom}")];
    let state = format!("nothing was sent: {whom} is in the state it was in");
    said(out, &Stopped::new(&format!("nmt {name}"), Vec::new(), not_done, state))
}

/// An SDO transfer the user stopped (`report` is the library's account of it), with the
/// `--out` file it did not write; any other error as it is.
pub(crate) fn sdo(out: &Output, report: Option<Stopped>, file: Option<&Path>, e: Error) -> anyhow::Result<()> {
    let Some(mut report) = report else { return Err(e.into()) };
    if let Some(path) = file {
        let old = if path.exists() { "the old file is unchanged" } else { "nothing written" };
        report.not_done.push(format!("{} ({old})", path.display()));
    }
    said(out, &report)
}

/// `config eds` stopped while reading the node's stored EDS; `e` (the interruption) is
/// returned as it is.
pub(crate) fn config_eds(out: &Output, node: u8, file: Option<&Path>, e: Error) -> anyhow::Result<()> {
    let not_done = vec![format!("reading node {node}'s EDS (0x1021)"), not_written(file, "EDS")];
    out.report(&Stopped::new("config eds", vec![], not_done, NOTHING_CHANGED.into()))?;
    Err(e.into())
}

/// `config dump` stopped after `objects` of the `wanted` objects (0: before the profile was
/// read).
pub(crate) fn config_dump(
    out: &Output,
    node: u8,
    objects: usize,
    wanted: usize,
    file: Option<&Path>,
) -> anyhow::Result<()> {
    let read = match wanted {
        0 => format!("node {node}'s profile not read yet"),
        wanted => format!("read {objects} of {wanted} objects of node {node}"),
    };
    let not_done = vec!["reading the other objects".to_string(), not_written(file, "DCF")];
    said(out, &Stopped::new("config dump", vec![read], not_done, NOTHING_CHANGED.into()))
}

/// A run over several nodes. One node: its report. Several: their reports together;
/// stopped part-way, which nodes were done and which were not; failed, the reports of
/// those done, then the error.
pub(crate) fn each_node<R: Report + serde::Serialize>(
    out: &Output,
    command: &str,
    nodes: &[u8],
    run: EachNode<R>,
) -> anyhow::Result<()> {
    let EachNode { done, ended } = run;
    let i = done.len();
    match ended {
        Some(Ended::Stopped(mut report)) => {
            if nodes.len() > 1 {
                let before = done.iter().filter_map(sentence);
                report.done = before.chain(report.done).collect();
                report.not_done.extend(nodes[i + 1..].iter().map(|n| format!("{command} on node {n}")));
            }
            said(out, &report)
        }
        Some(Ended::Failed(e)) => {
            if !done.is_empty() {
                out.report(&Each(done))?;
                let list: Vec<String> = nodes[i..].iter().map(|n| n.to_string()).collect();
                out.note(&format!("{command} not done on node {}", list.join(", ")));
            }
            Err(e.into())
        }
        None if done.len() == 1 => Ok(out.report(&done[0])?),
        None => Ok(out.report(&Each(done))?),
    }
}
