//! Where `config dump` and `config eds` put the file they read: the `--out` file, written
//! whole and said on stderr, or standard output (what was read then said on stderr).

use super::report::Output;
use super::stopped;
use crate::ops::config::Dump;
use crate::ops::stored_eds::StoredEds;
use std::path::Path;

/// `config dump`'s DCF (or XDC) written where it was asked for; a dump the user stopped is
/// said as such (counting the objects read when it got that far), nothing written.
pub(crate) fn dumped(
    out: &Output,
    node: u8,
    file: Option<&Path>,
    dump: crate::Result<Dump>,
) -> super::command_error::CommandResult {
    let dump = match dump {
        // A stop the dump could not count objects for: said as one before the profile was read.
        Err(e) if e.is_interrupted() => return stopped::config_dump(out, node, 0, 0, file),
        other => other?,
    };
    if dump.interrupted {
        return stopped::config_dump(out, node, dump.objects, dump.wanted, file);
    }
    match file {
        Some(path) => {
            crate::atomic::write_atomic(path, &dump.dcf)?;
            out.note(&format!("{} objects of node {} written to {}", dump.objects, node, path.display()));
        }
        None => out.write_bytes(&dump.dcf)?,
    }
    Ok(())
}

/// `config eds`'s EDS of `node` saved to `file` (its report then says so), or written to
/// standard output, what was read said on stderr; `network` is the bus's URI the report
/// names. Stopped, what was not done is said.
pub(crate) fn stored_eds(
    out: &Output,
    node: u8,
    file: Option<&Path>,
    network: Option<&str>,
    read: crate::Result<StoredEds>,
) -> super::command_error::CommandResult {
    let mut eds = match read {
        Err(e) if e.is_interrupted() => return stopped::config_eds(out, node, file, e),
        other => other?,
    };
    match file {
        Some(path) => {
            eds.save(node, path, network)?;
            out.report(&eds)?;
        }
        None => {
            out.write_bytes(&eds.file)?;
            out.note(&super::reports::stored_eds_line(&eds));
            out.notes(super::report::Report::notes(&eds));
        }
    }
    Ok(())
}
