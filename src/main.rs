use clap::Parser;

fn main() {
    let cli = canctl::cli::Cli::parse();
    if let Err(err) = canctl::cli::run(cli) {
        let (code, print) = canctl::cli::exit_code(&err);
        if print {
            eprintln!("canctl: {err:#}");
        }
        std::process::exit(code);
    }
}
