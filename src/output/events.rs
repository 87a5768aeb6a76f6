//! The words for a procedure's [`Event`]s: the one place warnings and notices of the
//! library become sentences (those naming flags among them), as `canctl` prints them on
//! stderr.

use super::hints::library_error_text;
use crate::canopen::abort;
use crate::error::LinkError;
use crate::ops::silence::Silence;
use crate::ops::{Event, Notice, Warning};

/// The line `canctl` prints for `event`.
pub fn event_line(event: &Event) -> String {
    match event {
        Event::Warning(w) => warning_line(w),
        Event::Notice(n) => notice_line(n),
    }
}

fn warning_line(w: &Warning) -> String {
    match w {
        // Where the user did not ask for the value, raising a limit is no remedy: the
        // device's answer is the finding.
        Warning::Failed { error: crate::Error::Link(LinkError::UploadOverLimit { node, obj, limit, .. }), .. } => {
            format!("warning: node {node} sends {obj} without end: cut at {limit} bytes")
        }
        Warning::Failed { node: Some(node), error } => format!("warning: node {node}: {}", library_error_text(error)),
        Warning::Failed { node: None, error } => format!("warning: {}", library_error_text(error)),
        Warning::PdoLength { node, pdo, cob_id, got, want } => format!(
            "warning: node {node} TPDO{pdo} (0x{cob_id:03X}) came with {got} bytes, its mapping makes {want}: not \
             decoded (this is said once)"
        ),
        Warning::SyncDoesNotDrive { node, pdo, transmission } => format!(
            "warning: --sync does not drive node {node}'s TPDO{pdo}: transmission type {transmission} (event-driven) \
             sends on its own; 1..240 makes it answer SYNC"
        ),
        Warning::File(w) => format!("canctl: warning: {w}"),
        Warning::ActivationStrands { rate, refused, confirmed } => format!(
            "the last `lss set-baud {rate} --global` on this bus was refused by {refused} device(s) ({confirmed} took \
             it): activating switches those and leaves the others at the old rate, where they no longer hear the bus"
        ),
    }
}

fn notice_line(n: &Notice) -> String {
    match n {
        Notice::PdoInvalid { node, pdo, comm, cob } => {
            format!("TPDO{pdo} of node {node} is not valid (0x{comm:04X}:1 = 0x{cob:08X}); left out")
        }
        Notice::Refused { addr, code } => format!("note: {addr}: {}", abort::meaning(*code)),
        Notice::LeftOut { addr, file, why } => format!("note: {addr} left out of the {file}: {why}"),
        Notice::Silent { node, after, why } => {
            format!(
                "nothing from node {node} after {} ms; still listening. Why it may be silent: {}.",
                after.as_millis(),
                super::text::joined(why.iter().map(silence_text), "; ")
            )
        }
        Notice::Assigned { identity, node } => format!("{identity} -> node {node}"),
    }
}

/// A reason a stream may be silent, naming the flags that remedy it.
fn silence_text(why: &Silence) -> String {
    match why {
        Silence::NotOperational { node, state, source } => {
            format!("node {node} is {state} (by {source}): it sends PDOs only when operational (--start)")
        }
        Silence::StateUnknown { node } => {
            format!("node {node} may not be operational; --start puts it there for the stream")
        }
        Silence::WaitsForSync { pdo, kind } => {
            format!("TPDO{pdo} is synchronous (transmission type {kind}): it answers SYNC, which --sync PERIOD sends")
        }
        Silence::OnRequest { pdo, kind } => format!("TPDO{pdo} is sent only on request (transmission type {kind})"),
        Silence::SyncDoesNotDrive { pdo, kind } => {
            format!("TPDO{pdo} is event-driven (transmission type {kind}): --sync does not make it send")
        }
        Silence::NoEventTimer { pdo } => format!("TPDO{pdo} has no event timer: it sends when its values change"),
        Silence::NothingFound => "the TPDOs are valid and set to send: the node may have nothing to say".into(),
    }
}

/// How many of a file's deviations are said one by one on every command that reads it.
const SAID_EACH: usize = 3;

/// A file's deviations from CiA 306 on stderr: a few one by one (what is left out first),
/// then how many more and where to see them all, so that a vendor's file with dozens of
/// harmless deviations does not bury the command's own output.
pub fn say_deviations<'a>(warnings: impl Iterator<Item = &'a crate::od::lint::Warning>) {
    use crate::od::lint::Severity;
    let mut by_file: Vec<(&str, Vec<&crate::od::lint::Warning>)> = Vec::new();
    for w in warnings {
        match by_file.iter_mut().find(|(p, _)| *p == w.path) {
            Some((_, list)) => list.push(w),
            None => by_file.push((&w.path, vec![w])),
        }
    }
    for (path, mut list) in by_file {
        list.sort_by_key(|w| (w.severity != Severity::Error, w.line));
        for w in list.iter().take(SAID_EACH) {
            tracing::warn!("{w}");
        }
        if list.len() > SAID_EACH {
            tracing::warn!(
                "{path}: {} more deviation(s) from CiA 306; canctl config check {path} lists them all",
                list.len() - SAID_EACH
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canopen::ObjAddr;
    use std::time::Duration;

    /// The lines are the ones the procedures printed themselves before they sent events.
    #[test]
    fn events_are_worded_as_before() {
        let line = |e: Event| event_line(&e);
        let e = crate::Error::Usage("bad".into());
        assert_eq!(line(Warning::Failed { node: Some(5), error: e }.into()), "warning: node 5: bad");
        assert_eq!(
            line(Warning::PdoLength { node: 5, pdo: 1, cob_id: 0x185, got: 2, want: 6 }.into()),
            "warning: node 5 TPDO1 (0x185) came with 2 bytes, its mapping makes 6: not decoded (this is said once)"
        );
        assert!(line(Warning::SyncDoesNotDrive { node: 5, pdo: 2, transmission: 255 }.into())
            .starts_with("warning: --sync does not drive node 5's TPDO2: transmission type 255"));
        assert_eq!(
            line(Notice::PdoInvalid { node: 5, pdo: 2, comm: 0x1801, cob: 0x8000_0285 }.into()),
            "TPDO2 of node 5 is not valid (0x1801:1 = 0x80000285); left out"
        );
        let addr = ObjAddr::new(0x2000, 1);
        assert_eq!(
            line(Notice::LeftOut { addr, file: "DCF", why: "a newline".into() }.into()),
            "note: 0x2000:1 left out of the DCF: a newline"
        );
        assert!(line(Notice::Refused { addr, code: 0x0601_0000 }.into()).starts_with("note: 0x2000:1: "));
        assert_eq!(
            line(
                Notice::Silent {
                    node: 7,
                    after: Duration::from_secs(1),
                    why: vec![Silence::NoEventTimer { pdo: 1 }, Silence::StateUnknown { node: 7 }]
                }
                .into()
            ),
            "nothing from node 7 after 1000 ms; still listening. Why it may be silent: TPDO1 has no event timer: it \
             sends when its values change; node 7 may not be operational; --start puts it there for the stream."
        );
    }
}
