//! `canctl completions` and `canctl man`: their arguments; the scripts and pages are
//! rendered by `output::docs` from the clap definition.

use super::ctx::Ctx;
use crate::output::docs::registration;
use crate::output::CommandResult;
use clap::Args;
use clap_complete::Shell;
use std::path::PathBuf;

/// Print a shell completion script
///
/// The script asks canctl for candidates as you type: bus URIs present here, node-ids from
/// the last scan of the bus, the objects the node is known to have (from its EDS, else
/// CiA 301's mandatory ones, its profile's and those it answered; never one it refused),
/// and the fixed sets (types, bit rates, formats). It reads files only, never the bus.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  source <(COMPLETE=bash canctl)           # or: source <(canctl completions bash)
  canctl completions zsh > ~/.zfunc/_canctl
  canctl completions fish > ~/.config/fish/completions/canctl.fish")]
pub(crate) struct CompletionsArgs {
    /// bash, zsh, fish, elvish or powershell
    pub shell: Shell,
}

/// Print the man page, or write every page to a directory
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl man | man -l -
  canctl man --out /usr/local/share/man/man1")]
pub(crate) struct ManArgs {
    /// Write canctl.1 and one page per subcommand into this directory
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

pub(crate) fn completions(args: &CompletionsArgs) -> CommandResult {
    let script = registration(args.shell);
    crate::output::Output::new(crate::output::Format::Human, true).write_bytes(&script)?;
    Ok(())
}

/// `canctl man`: the first of `pages` printed, or every one written to `--out`.
pub(crate) fn man(ctx: &Ctx, args: &ManArgs, pages: Vec<(String, Vec<u8>)>) -> CommandResult {
    match &args.out {
        Some(dir) => {
            crate::output::docs::write_all(dir, &pages)?;
            ctx.out.note(&format!("{} man pages written to {}", pages.len(), dir.display()));
        }
        None => ctx.out.print(&String::from_utf8_lossy(&pages[0].1))?,
    }
    Ok(())
}
