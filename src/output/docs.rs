//! Shell completions and man pages, generated from the clap definition of `cli` (which
//! `cli` hands in: output sits below it).

use clap_complete::Shell;

/// The shell code that asks canctl for candidates as you type (clap_complete's dynamic
/// completion): the same as `COMPLETE=SHELL canctl` prints.
pub(crate) fn registration(shell: Shell) -> Vec<u8> {
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

/// Every man page of `cmd`: `canctl.1`, then `canctl-sdo-read.1` and so on for each subcommand.
pub fn man_pages(mut cmd: clap::Command) -> Vec<(String, Vec<u8>)> {
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

/// Write each `(file name, contents)` into `dir`, made if missing. Every failure names the
/// path: "No such file or directory" alone says not which.
pub(crate) fn write_all(dir: &std::path::Path, files: &[(String, Vec<u8>)]) -> crate::Result<()> {
    let failed = |path: &std::path::Path, e: std::io::Error| crate::Error::Output {
        path: path.display().to_string(),
        why: e.to_string(),
    };
    std::fs::create_dir_all(dir).map_err(|e| failed(dir, e))?;
    for (name, data) in files {
        let file = dir.join(name);
        std::fs::write(&file, data).map_err(|e| failed(&file, e))?;
    }
    Ok(())
}
