//! `canctl buses`: list what this machine can reach.

use super::ctx::Ctx;
use crate::ops::buses;
use crate::output::CommandResult;
use crate::sim::socketcand_serve::beacon_port;
use clap::Args;
use std::time::Duration;

/// The longest `--wait`: discovery is a look around, not a watch.
const MAX_WAIT: Duration = Duration::from_secs(60);

/// List the buses this machine can reach, each with the --bus value that reaches it
///
/// CAN interfaces of this machine (SocketCAN), serial ports whose USB vendor and product
/// are those of an slcan adapter (CANable, CANtact) or a maxon EPOS2, and socketcand
/// servers whose discovery beacon (UDP port 42000, sent every 3 s) is heard within --wait.
/// Other serial ports are named in a note. The socketcand buses heard are offered by shell
/// completion of --bus until the next `canctl buses`. Nothing is sent: beacons are only
/// listened for.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl buses
  canctl buses --wait 10s --format json")]
pub(crate) struct BusesArgs {
    /// How long to listen for socketcand beacons (at most 60s; 0s: not at all)
    #[arg(long, value_name = "DUR", default_value = "3s", value_parser = super::ctx::parse_duration)]
    pub wait: Duration,
}

pub(crate) fn run(ctx: &Ctx, a: &BusesArgs) -> CommandResult {
    if a.wait > MAX_WAIT {
        return Err(crate::output::UsageError::BusesWait(MAX_WAIT.as_secs()).into());
    }
    let working = ctx.out.working(&crate::output::buses::listening(a.wait));
    let report = buses::find(a.wait, beacon_port(), &ctx.cancel);
    working.finish_and_clear();
    ctx.report_then(&report, report.interrupted)
}
