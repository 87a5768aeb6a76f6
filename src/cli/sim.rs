//! `canctl sim`: manage the simulated demo network.

use super::{Ctx, GlobalArgs};
use crate::bus::BusUri;
use crate::error::Error;
use crate::output::Format;
use crate::sim::state::{default_path, StateFile};
use clap::Subcommand;
use serde_json::json;

#[derive(Subcommand, Debug)]
pub enum SimCommand {
    /// Forget the simulated network's saved state: devices start as built
    ///
    /// The sim network keeps node-ids, written and stored values and NMT states between
    /// invocations in a state file ($XDG_STATE_HOME/canctl/sim.json, or the path in
    /// --bus sim:PATH). This removes it.
    #[command(
        after_help = "Examples:\n  canctl sim reset\n  canctl --bus sim:/tmp/bench.json sim reset"
    )]
    Reset,
}

pub fn run(ctx: &Ctx, global: &GlobalArgs, cmd: &SimCommand) -> anyhow::Result<()> {
    let path = match global
        .bus
        .as_deref()
        .filter(|b| !b.is_empty())
        .map(str::parse::<BusUri>)
        .transpose()?
    {
        None | Some(BusUri::Sim { state: None }) => default_path(),
        Some(BusUri::Sim { state: Some(p) }) => p,
        Some(other) => {
            return Err(Error::Usage(format!(
                "`sim` works on the simulated bus, not {other:?}; use --bus sim or sim:PATH"
            ))
            .into())
        }
    };
    match cmd {
        SimCommand::Reset => {
            StateFile::lock(&path)?.reset()?;
            match ctx.out.format {
                Format::Json => ctx
                    .out
                    .json(&json!({ "reset": true, "state_file": path.display().to_string() }))?,
                _ => ctx
                    .out
                    .print(&format!("sim network reset ({})", path.display()))?,
            }
        }
    }
    Ok(())
}
