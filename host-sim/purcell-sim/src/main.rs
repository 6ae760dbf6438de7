//! `purcell-sim`: see `purcell-sim --help`, and the README's "Exit codes".
use clap::Parser;
use std::io::Write;
use std::process::ExitCode;

fn main() -> ExitCode {
    // Before any thread starts: Ctrl-C removes this run's staging entries (exit 130).
    purcell_sim::output::remove_staging_on_interrupt();
    let cli = purcell_sim::cli::Cli::parse();
    let (stdout, failure) = match purcell_sim::cli::run(cli) {
        Ok(out) => (out, None),
        Err(mut f) => (std::mem::take(&mut f.stdout), Some(f)),
    };
    // A reader that closed the pipe (`| head`) wanted no more: end quietly. Any other
    // failure to write stdout (a full disk) is an I/O error.
    let mut out = std::io::stdout().lock();
    let printed = out.write_all(stdout.as_bytes()).and_then(|()| out.flush());
    let io_failure = match printed {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => None,
        Err(e) => Some(format!("writing to stdout: {e}")),
        Ok(()) => None,
    };
    // stderr may be closed too: never panic over a message.
    let mut err = std::io::stderr().lock();
    if let Some(f) = &failure {
        let _ = writeln!(err, "error: {}", f.message);
    }
    if let Some(m) = &io_failure {
        let _ = writeln!(err, "error: {m}");
    }
    match (failure, io_failure) {
        (Some(f), _) => ExitCode::from(f.code),
        (None, Some(_)) => ExitCode::from(1),
        (None, None) => ExitCode::SUCCESS,
    }
}
