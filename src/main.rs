use clap::{CommandFactory, FromArgMatches};

// pub(crate): the test build of canctl (tests/seams/canctl.rs) runs this same `main`.
pub(crate) fn main() {
    // Before anything else, so that a SIGTERM at any moment is a request to stop, reported.
    let cancel = interrupt::install();
    // COMPLETE=bash|zsh|fish|... : answer the shell's completion request and exit.
    canctl::cli::complete_from_env();
    let matches = canctl::cli::Cli::command().try_get_matches().unwrap_or_else(|e| usage_error(e));
    let bus_from_env = matches.value_source("bus") == Some(clap::parser::ValueSource::EnvVariable);
    let cli = canctl::cli::Cli::from_arg_matches(&matches).unwrap_or_else(|e| usage_error(e));
    let json = cli.format() == canctl::output::FormatArg::Json;
    if let Err(err) = canctl::cli::run(cli, bus_from_env, cancel) {
        let (code, print) = err.exit_code();
        if !print {
            std::process::exit(code);
        }
        // A silent node or a failed link, with its likely cause, as one JSON object.
        let error_json = if json { err.json() } else { None };
        let message = match error_json {
            Some(value) => value.to_string(),
            // Messages may quote what a device or a file said: no control characters.
            None => canctl::output::fitted_to_stderr(&format!(
                "canctl: {}",
                canctl::output::terminal_safe_lines(&err.text())
            )),
        };
        std::process::exit(canctl::output::stderr::last_words(&message, code));
    }
}

/// clap's own errors in canctl's voice (`canctl: ...`, exit 2); help and version as clap
/// prints them.
fn usage_error(e: clap::Error) -> ! {
    if !e.use_stderr() {
        e.exit()
    }
    let text = e.render().to_string();
    // Not run at all: exit 2 whether or not anyone reads why.
    canctl::output::stderr::say(&format!("canctl: {}", text.strip_prefix("error: ").unwrap_or(&text)));
    std::process::exit(canctl::error::ErrorClass::Usage.exit_code())
}

/// Ctrl-C and termination (SIGINT and SIGTERM on Unix; Ctrl-C, Ctrl-Break and console close
/// on Windows) as the program's request to stop, for every command. How a procedure heeds
/// it (between steps, or at its next call to the bus) is the library's: `ops::stop`.
mod interrupt {
    use canctl::cancel::Cancel;

    /// Called first thing in `main`, whatever the command: from then on an interruption
    /// cancels the program's [`Cancel`] instead of ending the process, so a stop that comes
    /// while the bus opens, or before the command's first step, is still seen and reported
    /// (exit 130). Installed lazily by each command, a supervisor's SIGTERM in that window
    /// killed canctl with no report. A second request ends the process at once: the user
    /// asked twice.
    pub(crate) fn install() -> Cancel {
        let requested = Cancel::new();
        let handler = requested.clone();
        // Only fails when a handler is already set: this is the one, set once.
        let _ = ctrlc::set_handler(move || {
            if handler.check().is_err() {
                canctl::output::stderr::say(
                    "canctl: interrupted again: stopped at once, what was under way may be half done",
                );
                std::process::exit(canctl::error::ErrorClass::Interrupted.exit_code());
            }
            handler.cancel();
        });
        requested
    }
}
