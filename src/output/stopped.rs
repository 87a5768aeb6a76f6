//! What a command the user stopped says it did and did not do, and the state it leaves;
//! the command then ends as an interruption (exit 130).

use super::command_error::CommandResult;
use super::report::{Human, Output, Report};
use super::reports::{sentence, Each};
use crate::canopen::ObjAddr;
use crate::ops::store_all::{EachNode, Ended, StoppedBefore};
use crate::Error;
use serde::Serialize;
use std::path::Path;

const NOTHING_CHANGED: &str = "nothing was changed on the device";

/// What a command the user stopped (SIGINT, SIGTERM, Ctrl-C) had done, for the commands
/// whose own report has nothing to show for a stop: what was done, what was not, and the
/// state the device is left in. The command ends with exit 130 after it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub(crate) struct Stopped {
    /// The command, as typed: `sdo read`, `store`.
    pub command: String,
    /// Always true: the key every interrupted report has.
    pub interrupted: bool,
    /// What was finished before the stop, a line each.
    pub done: Vec<String>,
    /// What was not done because of it, a line each.
    pub not_done: Vec<String>,
    /// The state the device is left in, in a sentence (with what to do about it).
    pub state: String,
}

impl Stopped {
    /// The report of `command` stopped with `done` finished and `not_done` left, the device in
    /// `state`.
    pub fn new(command: &str, done: Vec<String>, not_done: Vec<String>, state: String) -> Stopped {
        Stopped { command: command.to_string(), interrupted: true, done, not_done, state }
    }
}

impl Report for Stopped {
    /// Nothing on stdout, where the result would have been: the report is said on stderr.
    fn human(&self) -> Human {
        Human::Parts(Vec::new())
    }

    fn notes(&self) -> Vec<String> {
        let list = |v: &[String]| super::text::listed(v, "nothing");
        vec![
            format!("{} interrupted: done {}; not done {}", self.command, list(&self.done), list(&self.not_done)),
            self.state.clone(),
        ]
    }
}

/// Say `report`, then end as an interruption.
fn said<T>(out: &Output, report: &Stopped) -> CommandResult<T> {
    out.report(report)?;
    Err(Error::Interrupted.into())
}

/// What a read-only command read, or, stopped part-way (`not_done`: what it was reading),
/// its report saying so and an interruption; any other error as it is.
pub(crate) fn read<R>(out: &Output, command: &str, not_done: String, read: crate::Result<R>) -> CommandResult<R> {
    match read {
        Err(e) if e.is_interrupted() => {
            said(out, &Stopped::new(command, Vec::new(), vec![not_done], NOTHING_CHANGED.into()))
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
pub(crate) fn nmt_not_sent(out: &Output, name: &str, target: u8, e: Error) -> CommandResult {
    if !e.is_interrupted() {
        return Err(e.into());
    }
    let whom = crate::ops::nmt::target_text(target);
    let not_done = vec![format!("NMT {name} to {whom}")];
    let state = format!("nothing was sent: {whom} is in the state it was in");
    said(out, &Stopped::new(&format!("nmt {name}"), Vec::new(), not_done, state))
}

/// A read (`write` false) or write of `object` on `node` that the user stopped, as the
/// error that ended it tells, with the `--out` file it did not write; any other error as
/// it is.
pub(crate) fn sdo(
    out: &Output,
    (node, object, write): (u8, ObjAddr, bool),
    file: Option<&Path>,
    e: Error,
) -> CommandResult {
    let Some(mut report) = sdo_stopped(node, object, write, &e) else { return Err(e.into()) };
    if let Some(path) = file {
        let old = if path.exists() { "the old file is unchanged" } else { "nothing written" };
        report.not_done.push(format!("{} ({old})", path.display()));
    }
    said(out, &report)
}

/// The report of a read or write of `object` that the user stopped, from the error that
/// ended it; `None` when that error is no interruption.
fn sdo_stopped(node: u8, object: ObjAddr, write: bool, e: &Error) -> Option<Stopped> {
    let (command, verb, dir) = if write { ("sdo write", "write", "to") } else { ("sdo read", "read", "from") };
    let whole = format!("{verb} of {object} {dir} node {node}");
    let unchanged = if write {
        format!("node {node} {object} keeps its previous value")
    } else {
        "nothing was changed on the device".to_string()
    };
    Some(match e.root() {
        Error::Interrupted => {
            Stopped::new(command, Vec::new(), vec![whole], format!("{unchanged}: the {verb} had not begun"))
        }
        Error::SdoInterrupted { moved, aborted, .. } => {
            let done = vec![format!("{object}: {moved} {}", if write { "sent" } else { "read (not kept)" })];
            let how = match aborted {
                Some(code) => format!(
                    "the transfer was aborted (SDO abort 0x{code:08X}), so node {node} is ready for the next one{}",
                    if write { " and takes nothing of an aborted write (CiA 301)" } else { "" }
                ),
                None => "stopped between two segments; the EPOS2 protocol has no command to abort a transfer, \
                         so nothing more was sent"
                    .to_string(),
            };
            Stopped::new(command, done, vec![format!("the rest of the {verb}")], format!("{unchanged}; {how}"))
        }
        _ => return None,
    })
}

/// Where a node's store or restore was stopped, as canctl says it: what was done on it,
/// what was not, the state it is left in and what to do about that.
fn node_stop_report(stop: StoppedBefore) -> Stopped {
    match stop {
        StoppedBefore::Save { node, class } => Stopped::new(
            "store",
            Vec::new(),
            vec![format!("'save' to 0x1010:{} of node {node}", class as u8 + 1)],
            format!("nothing was stored on node {node}: its non-volatile memory is as it was"),
        ),
        StoppedBefore::Load { node, class } => Stopped::new(
            "restore",
            Vec::new(),
            vec![format!("'load' to 0x1011:{} of node {node}", class as u8 + 1)],
            format!("nothing was changed: node {node} keeps its parameters"),
        ),
        StoppedBefore::Reset { node, object } => Stopped::new(
            "restore",
            vec![format!("node {node}: 'load' written to {object}")],
            vec![format!("NMT reset of node {node}")],
            format!(
                "node {node}: the defaults are loaded and apply from its next reset{}",
                super::remedies::reset_node(node)
            ),
        ),
        StoppedBefore::BootUp { node, object } => Stopped::new(
            "restore",
            vec![format!("node {node}: 'load' written to {object}"), format!("NMT reset of node {node}")],
            vec![format!("confirming that node {node} booted")],
            format!(
                "node {node}: the defaults are loaded and the reset went out; whether it booted with them is not \
                 known{}",
                super::remedies::read_nmt_state(node)
            ),
        ),
    }
}

/// `config eds` stopped while reading the node's stored EDS; `e` (the interruption) is
/// returned as it is.
pub(crate) fn config_eds(out: &Output, node: u8, file: Option<&Path>, e: Error) -> CommandResult {
    let not_done = vec![format!("reading node {node}'s EDS (0x1021)"), not_written(file, "EDS")];
    out.report(&Stopped::new("config eds", vec![], not_done, NOTHING_CHANGED.into()))?;
    Err(e.into())
}

/// `config dump` stopped after `objects` of the `wanted` objects (0: before the profile was
/// read).
pub(crate) fn config_dump(out: &Output, node: u8, objects: usize, wanted: usize, file: Option<&Path>) -> CommandResult {
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
) -> CommandResult {
    let EachNode { done, ended } = run;
    let i = done.len();
    match ended {
        Some(Ended::Stopped(stop)) => {
            let mut report = node_stop_report(stop);
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
                out.note(&format!("{command} not done on node {}", super::text::joined(&nodes[i..], ", ")));
            }
            Err(e.into())
        }
        None if done.len() == 1 => Ok(out.report(&done[0])?),
        None => Ok(out.report(&Each(done))?),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each point a restore can be stopped at, said as canctl always said it: the state,
    /// then what to do about it in canctl's terms (in JSON too).
    #[test]
    fn a_stopped_restore_says_what_it_left_and_what_to_do() {
        let object = ObjAddr::new(0x1011, 1);
        let stopped = node_stop_report(StoppedBefore::Reset { node: 5, object });
        let said = "node 5: the defaults are loaded and apply from its next reset (canctl nmt reset 5 does it)";
        assert_eq!(Report::notes(&stopped)[1], said);
        let json = Report::json_value(&stopped);
        assert_eq!(json["state"], said);
        assert_eq!(
            json.as_object().unwrap().keys().collect::<Vec<_>>(),
            ["command", "interrupted", "done", "not_done", "state"]
        );
        let stopped = node_stop_report(StoppedBefore::BootUp { node: 3, object });
        assert_eq!(
            Report::notes(&stopped),
            [
                "restore interrupted: done node 3: 'load' written to 0x1011:1, NMT reset of node 3; not done \
                 confirming that node 3 booted",
                "node 3: the defaults are loaded and the reset went out; whether it booted with them is not known \
                 (canctl nmt state 3 says)"
            ]
        );
    }
}
