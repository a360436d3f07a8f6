//! The `opengrasp` command line; see [`opengrasp::cli`].

use clap::Parser;

fn main() -> std::process::ExitCode {
    let cli = opengrasp::cli::Cli::parse();
    match opengrasp::cli::execute(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
