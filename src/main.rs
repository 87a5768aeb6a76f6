use clap::{CommandFactory, FromArgMatches};

fn main() {
    // COMPLETE=bash|zsh|fish|... : answer the shell's completion request and exit.
    canctl::cli::complete_from_env();
    let matches = canctl::cli::Cli::command().get_matches();
    let bus_from_env = matches.value_source("bus") == Some(clap::parser::ValueSource::EnvVariable);
    let cli = canctl::cli::Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    if let Err(err) = canctl::cli::run(cli, bus_from_env) {
        let (code, print) = canctl::cli::exit_code(&err);
        if print {
            eprintln!("canctl: {err:#}");
        }
        std::process::exit(code);
    }
}
