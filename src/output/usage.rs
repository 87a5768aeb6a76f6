//! The command line's refusals of arguments that each parse but do not go together, or name
//! nothing to do (exit 2), in words: what was wrong and what to give instead.

use crate::Error;
use std::path::Path;

/// The commands that work on several buses at once, named in the usage error of the others.
const ON_BUSES: &str = "scan, health, network check and firmware status";

/// Several `--bus` given to a command that works on one.
pub(crate) fn several_buses(buses: &[String]) -> Error {
    Error::Usage(format!(
        "{} buses given ({}), but only {ON_BUSES} work on several at once; give this command one --bus",
        buses.len(),
        buses.join(", ")
    ))
}

/// `--format junit` for a command that checks nothing.
pub(crate) fn junit_elsewhere() -> Error {
    Error::Usage(
        "--format junit is for commands that check things: canctl network check, canctl health, canctl doctor, canctl firmware download; use human, json or csv here"
            .into(),
    )
}

/// `--format xdc` for a command other than `config dump`.
pub(crate) fn xdc_elsewhere() -> Error {
    Error::Usage(
        "--format xdc is for canctl config dump (an XDC, CiA 311, instead of a DCF); use human, json or csv here"
            .into(),
    )
}

/// `buses --wait` longer than `max_secs`.
pub(crate) fn buses_wait(max_secs: u64) -> Error {
    Error::Usage(format!("--wait is at most {max_secs}s: beacons come every 3 s"))
}

/// An `lss VERB` that names no device.
pub(crate) fn lss_unnamed(verb: &str) -> Error {
    Error::Usage(format!(
        "say which device `lss {verb}` is for: --identity VENDOR:PRODUCT:REVISION:SERIAL for one, or \
         --global for every LSS device on the bus (a broadcast, so only when you mean it)"
    ))
}

/// `network dump` into a folder that holds a project, without `--force`.
pub(crate) fn project_exists(project: &Path) -> Error {
    Error::Usage(format!("{} exists: pick another folder, or --force to replace it", project.display()))
}

/// `network set-baud` without `--global`.
pub(crate) fn set_baud_not_global() -> Error {
    Error::Usage(
        "`network set-baud` switches every LSS device on the bus at once (a broadcast): add --global when you \
         mean it"
            .into(),
    )
}

/// `canctl sim` told nothing to serve.
pub(crate) fn nothing_to_serve() -> Error {
    Error::Usage(
        "say what to serve: --socketcan IFACE, --slcan, --socketcand PORT, --epos2-rs232 or --epos2-usb \
                 (or `canctl sim reset`)"
            .into(),
    )
}
