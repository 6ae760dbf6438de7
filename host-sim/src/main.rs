//! `purcell-sim`: see `purcell-sim --help`.
use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = host_sim::cli::Cli::parse();
    match host_sim::cli::run(cli) {
        Ok(out) => {
            print!("{out}");
            ExitCode::SUCCESS
        }
        Err(f) => {
            eprintln!("error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}
