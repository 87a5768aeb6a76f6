//! Shell completions and man pages, generated from the clap definition.

use super::{Cli, Ctx};
use clap::{Args, CommandFactory};
use clap_complete::Shell;
use std::path::{Path, PathBuf};

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
pub struct CompletionsArgs {
    /// bash, zsh, fish, elvish or powershell
    pub shell: Shell,
}

/// Print the man page, or write every page to a directory
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  canctl man | man -l -
  canctl man --out /usr/local/share/man/man1")]
pub struct ManArgs {
    /// Write canctl.1 and one page per subcommand into this directory
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

pub fn completions(args: &CompletionsArgs) -> anyhow::Result<()> {
    let script = registration(args.shell);
    super::Output::new(crate::output::Format::Human, true).print(&String::from_utf8(script)?)?;
    Ok(())
}

/// The shell code that asks canctl for candidates as you type (clap_complete's dynamic
/// completion): the same as `COMPLETE=SHELL canctl` prints.
fn registration(shell: Shell) -> Vec<u8> {
    let shells = clap_complete::env::Shells::builtins();
    let completer = shells.completer(&shell.to_string()).expect("clap_complete knows every Shell");
    let mut out = Vec::new();
    completer.write_registration("COMPLETE", "canctl", "canctl", "canctl", &mut out).expect("write to memory");
    if shell == Shell::Zsh {
        // Installed as `_canctl` in $fpath, zsh runs this file on the first <Tab>: complete
        // then too, not only from the second <Tab> on.
        out.extend_from_slice(
            b"if [[ ${zsh_eval_context[-1]} == loadautofunc ]]; then\n    _clap_dynamic_completer_canctl \"$@\"\nfi\n",
        );
    }
    out
}

/// Every completion script: (file name, contents).
pub fn completion_scripts() -> Vec<(String, Vec<u8>)> {
    [Shell::Bash, Shell::Zsh, Shell::Fish, Shell::Elvish, Shell::PowerShell]
        .into_iter()
        .map(|shell| {
            let name = match shell {
                Shell::Bash => "canctl.bash".to_string(),
                Shell::Zsh => "_canctl".to_string(),
                Shell::Fish => "canctl.fish".to_string(),
                Shell::Elvish => "canctl.elv".to_string(),
                _ => "_canctl.ps1".to_string(),
            };
            (name, registration(shell))
        })
        .collect()
}

pub fn write_completions(dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    for (name, data) in completion_scripts() {
        std::fs::write(dir.join(name), data)?;
    }
    Ok(())
}

/// Every man page: `canctl.1`, then `canctl-sdo-read.1` and so on for each subcommand.
pub fn man_pages() -> Vec<(String, Vec<u8>)> {
    let mut cmd = Cli::command();
    cmd.build();
    let mut pages = Vec::new();
    collect(&cmd, "canctl", &mut pages);
    pages
}

fn collect(cmd: &clap::Command, name: &str, pages: &mut Vec<(String, Vec<u8>)>) {
    let mut out = Vec::new();
    // The plain version: the commit and target of `--version` would change every page per build.
    let named = cmd.clone().name(name.to_string()).bin_name(name.replace('-', " ")).long_version(None);
    clap_mangen::Man::new(named).render(&mut out).expect("render to memory");
    pages.push((format!("{name}.1"), out));
    for sub in cmd.get_subcommands().filter(|s| s.get_name() != "help") {
        collect(sub, &format!("{name}-{}", sub.get_name()), pages);
    }
}

pub fn man(ctx: &Ctx, args: &ManArgs) -> anyhow::Result<()> {
    let pages = man_pages();
    match &args.out {
        Some(dir) => {
            // Every failure names the path: "No such file or directory" alone says not which.
            let output = |path: &Path, e: std::io::Error| crate::Error::Output {
                path: path.display().to_string(),
                why: e.to_string(),
            };
            std::fs::create_dir_all(dir).map_err(|e| output(dir, e))?;
            for (name, data) in &pages {
                let page = dir.join(name);
                std::fs::write(&page, data).map_err(|e| output(&page, e))?;
            }
            ctx.out.note(&format!("{} man pages written to {}", pages.len(), dir.display()));
        }
        None => ctx.out.print(&String::from_utf8_lossy(&pages[0].1))?,
    }
    Ok(())
}
