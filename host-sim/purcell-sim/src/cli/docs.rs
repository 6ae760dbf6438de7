//! `completions` and `man`: the shell completion script (clap_complete) and the manual page
//! (clap_mangen), both generated from the flags themselves.

use super::Cli;
use super::args::{Failure, fail};
use clap::{Args, CommandFactory};

/// `completions` flags.
#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

/// `man` flags.
#[derive(Debug, Args)]
pub struct ManArgs {
    /// The command whose page to print (default: purcell-sim's own, which lists them all).
    pub command: Option<String>,
}

/// `completions`: the script, as printed.
pub(super) fn completions(a: &CompletionsArgs) -> String {
    let mut script = Vec::new();
    clap_complete::generate(a.shell, &mut Cli::command(), "purcell-sim", &mut script);
    String::from_utf8_lossy(&script).into_owned()
}

/// `man`: the page (roff) of purcell-sim or of `a.command` (`purcell-sim-COMMAND`), as
/// printed; exit 2 for a command that does not exist.
pub(super) fn man(a: &ManArgs) -> Result<String, Failure> {
    let mut cmd = Cli::command();
    cmd.build();
    let page = match &a.command {
        None => cmd,
        Some(name) => {
            // Built, it is named `purcell-sim-COMMAND` on its page.
            cmd.find_subcommand(name)
                .cloned()
                .ok_or_else(|| {
                    let names: Vec<&str> = cmd.get_subcommands().map(|c| c.get_name()).collect();
                    fail(
                        2,
                        format!("man: no command {name:?} (one of: {})", names.join(", ")),
                    )
                })?
                .version(super::VERSION)
        }
    };
    let mut roff = Vec::new();
    clap_mangen::Man::new(page)
        .render(&mut roff)
        .map_err(|e| fail(1, e))?;
    Ok(String::from_utf8_lossy(&roff).into_owned())
}
