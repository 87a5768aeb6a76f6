//! The command line's refusals of arguments that each parse but do not go together, or name
//! nothing to do (exit 2), in words: what was wrong and what to give instead. They are the
//! command line's own: the library's errors never carry them.

use crate::sim::serve::ServeError;
use std::path::PathBuf;

/// The commands that work on several buses at once, named in the usage error of the others.
const ON_BUSES: &str = "scan, health, network check and firmware status";

/// Arguments the command line refuses.
#[derive(Debug, thiserror::Error)]
pub enum UsageError {
    /// A command that needs a bus was given none: the CAN `interfaces` and serial `ports`
    /// this machine has, to name one.
    #[error("{}", no_bus_text(interfaces, ports))]
    NoBus {
        /// The CAN interfaces here.
        interfaces: Vec<String>,
        /// The serial ports here.
        ports: Vec<String>,
    },
    /// Several `--bus` given to a command that works on one.
    #[error("{} buses given ({}), but only {ON_BUSES} work on several at once; give this command one --bus", .0.len(), .0.join(", "))]
    SeveralBuses(Vec<String>),
    /// `--format junit` for a command that checks nothing.
    #[error(
        "--format junit is for commands that check things: canctl network check, canctl health, canctl doctor, \
         canctl firmware download; use human, json or csv here"
    )]
    JunitElsewhere,
    /// `--format xdc` for a command other than `config dump`.
    #[error("--format xdc is for canctl config dump (an XDC, CiA 311, instead of a DCF); use human, json or csv here")]
    XdcElsewhere,
    /// `buses --wait` longer than its most, in seconds.
    #[error("--wait is at most {0}s: beacons come every 3 s")]
    BusesWait(u64),
    /// An `lss VERB` that names no device.
    #[error(
        "say which device `lss {0}` is for: --identity VENDOR:PRODUCT:REVISION:SERIAL for one, or --global for every \
         LSS device on the bus (a broadcast, so only when you mean it)"
    )]
    LssUnnamed(String),
    /// `network dump` into a folder that holds a project, without `--force`.
    #[error("{} exists: pick another folder, or --force to replace it", .0.display())]
    ProjectExists(PathBuf),
    /// `network set-baud` without `--global`.
    #[error(
        "`network set-baud` switches every LSS device on the bus at once (a broadcast): add --global when you mean it"
    )]
    SetBaudNotGlobal,
    /// `canctl sim` told nothing to serve.
    #[error(
        "say what to serve: --socketcan IFACE, --slcan, --socketcand PORT, --epos2-rs232 or --epos2-usb (or `canctl \
         sim reset`)"
    )]
    NothingToServe,
    /// `canctl sim` given a bus that is not the sim network.
    #[error("`canctl sim` runs the simulated network: use --bus sim or sim:PATH (or no --bus)")]
    NotASimBus,
    /// `canctl sim` asked to serve what it cannot serve here, or so (never
    /// [`ServeError::Failed`]: that is the library's error).
    #[error("{}", super::sim::serve_refusal(.0).unwrap_or_else(|| .0.to_string()))]
    CannotServe(ServeError),
}

/// Why a command that needs a bus has none, how to name one, and the CAN `interfaces` and
/// serial `ports` this machine has (the caller lists them: output does no I/O of the bus's).
fn no_bus_text(interfaces: &[String], ports: &[String]) -> String {
    let list = |v: &[String]| super::text::listed(v, "none found");
    format!(
        "no bus given: pass --bus URI, set CANCTL_BUS, or put bus = \"...\" in canctl.toml\n  \
         CAN interfaces here: {}\n  \
         serial ports here:   {}\n  \
         forms: socketcan:can0 (or can0), slcan:/dev/ttyACM0@500k, epos2-rs232:/dev/ttyS0?baud=115200, \
         epos2-usb:/dev/ttyUSB0, socketcand:HOST[:PORT]/IFACE\n  \
         no hardware? try the demo network: canctl --bus sim scan",
        list(interfaces),
        list(ports)
    )
}
