use clap::{CommandFactory, FromArgMatches};

fn main() {
    // Before anything else, so that a SIGTERM at any moment is a request to stop, reported.
    canctl::cli::install_interrupt();
    // COMPLETE=bash|zsh|fish|... : answer the shell's completion request and exit.
    canctl::cli::complete_from_env();
    let matches = canctl::cli::Cli::command().try_get_matches().unwrap_or_else(|e| usage_error(e));
    let bus_from_env = matches.value_source("bus") == Some(clap::parser::ValueSource::EnvVariable);
    let cli = canctl::cli::Cli::from_arg_matches(&matches).unwrap_or_else(|e| usage_error(e));
    // The library reports through `tracing`; -v/-q choose what reaches stderr.
    canctl::cli::install_diagnostics(cli.global.verbose, cli.global.quiet);
    if let Err(err) = canctl::cli::run(cli, bus_from_env) {
        let (code, print) = canctl::cli::exit_code(&err);
        if print {
            // Messages may quote what a device or a file said: no control characters.
            eprintln!("canctl: {}", canctl::output::terminal_safe_lines(&canctl::output::error_text(&err)));
        }
        std::process::exit(code);
    }
}

/// clap's own errors in canctl's voice (`canctl: ...`, exit 2); help and version as clap
/// prints them.
fn usage_error(e: clap::Error) -> ! {
    if !e.use_stderr() {
        e.exit()
    }
    let text = e.render().to_string();
    eprint!("canctl: {}", text.strip_prefix("error: ").unwrap_or(&text));
    std::process::exit(canctl::error::ErrorClass::Usage.exit_code())
}
