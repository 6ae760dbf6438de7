//! What the subcommands share: the swimmer's and the problem's flags, the limits of a
//! search, reading input files, the progress bar, and the failure with its exit code.

use super::units;
use crate::costate_file::CostateFile;
use crate::{input, output};
use clap::Args;
use purcell_core::Gait;
use purcell_solver::problem::{Cost, Spec};
use purcell_solver::solver;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The exit codes, as `--help` lists them after every command's flags (the one list; the
/// README's table says more on each).
pub const EXIT_CODES: &str = "\
Exit codes:
  0  success
  1  I/O error after the work (writing the results or stdout), or no worker threads
  2  bad input or usage, refused before any work
  3  no solution: solve found no admissible extremal; replay: a replay failed
  130  interrupted (Ctrl-C; 143 SIGTERM, 129 SIGHUP): staging removed, nothing replaced";

// Number flags take values as typed, negative ones included (`--alpha -0.5,0.3`), angles in
// radians or degrees (`30deg`, [`units`]), and list their defaults as they can be typed back
// (`0.1,0.1,0`). A flag given twice is refused (clap's usage error), lists included:
// `--target 1,2 --target 3` is not `1,2,3`.

/// Swimmer parameters shared by the subcommands.
#[derive(Debug, Args)]
pub struct ModelArgs {
    /// Link lengths L0 (middle), L1 (front), L2 (rear), in metres (no unit suffix).
    #[arg(long, value_parser = units::lengths::<3>(), default_value = "1,1,1",
          allow_hyphen_values = true)]
    pub links: [f64; 3],
    /// Drag coefficient k (force per unit length per unit speed; scales forces only).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub drag: f64,
    /// Drag ratio r: normal over tangential drag (2 for slender bodies).
    #[arg(long, default_value_t = 2.0, allow_hyphen_values = true)]
    pub ratio: f64,
}

/// The problem's flags of a search (`solve`, `sweep`; the target is each one's own), with
/// the search's own flags `S` between the swimmer and the joint limit. `solve --help` shows
/// these help texts; `sweep` replaces those of `--horizon` and `--alpha-max` with shorter ones.
#[derive(Debug, Args)]
pub struct ProblemArgs<S: Args> {
    /// Horizon T in seconds; must be a whole number of steps (at most 1000000).
    #[arg(long, default_value_t = 100.0, allow_hyphen_values = true)]
    pub horizon: f64,
    /// Time step h in seconds.
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true)]
    pub step: f64,
    /// Start shape alpha_bar = A1,A2, each |A_i| < pi: radians, or degrees with deg
    /// (10deg,-5deg); also the end shape unless --alpha-end gives one.
    #[arg(long, value_parser = units::angles::<2>(), default_value = "0,0",
          allow_hyphen_values = true)]
    pub alpha0: [f64; 2],
    /// End shape B1,B2, each |B_i| < pi, as --alpha0 (default: --alpha0, a closed loop): the
    /// gait ends in this shape at the target, a transition from one shape to another.
    #[arg(long, value_parser = units::angles::<2>(), allow_hyphen_values = true)]
    pub alpha_end: Option<[f64; 2]>,
    /// Swimmer parameters.
    #[command(flatten)]
    pub model: ModelArgs,
    /// The search's flags.
    #[command(flatten)]
    pub search: S,
    /// Joint limit |alpha_i| <= alpha-max along the path, below pi: radians, or degrees
    /// with deg (85deg) (default: only the links' overlap at pi). The solver returns the
    /// cheapest gait within it, with the limit active on arcs where that is cheaper.
    #[arg(long, value_parser = units::angle(), allow_hyphen_values = true)]
    pub alpha_max: Option<f64>,
    /// The running cost minimised: effort (the joints', sum of h/2 |u_k|^2, the paper's) or
    /// power (what the fluid dissipates, sum of h/2 u_k^T G(alpha_k) u_k; docs/MODEL.md §11).
    #[arg(long, default_value = "effort", value_parser = units::cost)]
    pub cost: Cost,
}

impl<S: Args> ProblemArgs<S> {
    /// The problem's [`Spec`] for `target`.
    pub fn spec(&self, target: [f64; 3]) -> Spec {
        Spec {
            target,
            horizon: self.horizon,
            step: self.step,
            alpha0: self.alpha0,
            alpha_end: self.alpha_end,
            links: self.model.links,
            drag: self.model.drag,
            ratio: self.model.ratio,
            alpha_max: self.alpha_max,
            cost: self.cost,
        }
    }
}

/// The output directory of `solve`, `sweep` and `field` ([`output::OutputDir`]).
#[derive(Debug, Args)]
pub struct OutDirArgs {
    /// Output directory: created, or replaced in one step if it is empty or a previous
    /// result of purcell-sim (anything else is refused before any work).
    #[arg(short, long)]
    pub out: PathBuf,
    /// Replace --out even if it holds files purcell-sim did not write.
    #[arg(long)]
    pub force: bool,
}

impl OutDirArgs {
    /// The directory, checked and its staging created for `command`'s result before any
    /// work; `inputs` are the command's input files, which it must not hold (exit 2).
    pub(super) fn prepare(
        &self,
        command: &'static str,
        inputs: &[&Path],
    ) -> Result<output::OutputDir, Failure> {
        output::OutputDir::prepare(output::Claim::new(&self.out, command, self.force, inputs))
            .map_err(output_failure(true))
    }
}

/// What `solve` and `sweep` print on stdout: a short summary, or with `--json` their
/// `report.json` (`-q` prints neither).
#[derive(Debug, Args)]
pub struct PrintArgs {
    /// Print report.json on stdout instead of the summary.
    #[arg(long)]
    pub json: bool,
}

/// A warning on stderr, unless `quiet` (`-q`).
pub(super) fn warn(quiet: bool, message: std::fmt::Arguments<'_>) {
    if !quiet {
        eprintln!("warning: {message}");
    }
}

/// The step and memory budget ([`crate::budget::check`]) of `steps` steps of `work` on the
/// stored gait `path`, before any work (exit 2); what a large run needs is said on stderr
/// first, unless `quiet`.
pub(super) fn budget(
    path: &Path,
    steps: u32,
    work: crate::budget::Work,
    quiet: bool,
) -> Result<(), Failure> {
    let note = crate::budget::check(u64::from(steps), work)
        .map_err(|e| fail(2, format!("{}: {e}", path.display())))?;
    if let Some(note) = note {
        warn(quiet, format_args!("{}: {note}", path.display()));
    }
    Ok(())
}

/// A failure of the command, with its exit code (the README's "Exit codes").
#[derive(Debug)]
pub struct Failure {
    /// Message for stderr.
    pub message: String,
    /// Exit code: 2 bad input (nothing done), 3 no solution (`solve`: no extremal;
    /// `replay`: a replay failed), 1 I/O.
    pub code: u8,
    /// What to print on stdout all the same (the `replay` report).
    pub stdout: String,
}

/// A failure with exit code `code` and nothing on stdout.
pub(super) fn fail(code: u8, message: impl ToString) -> Failure {
    Failure {
        message: message.to_string(),
        code,
        stdout: String::new(),
    }
}

/// Exit code for an output refused or not creatable before the work (2), or failing after
/// it (1).
pub(super) fn output_failure(before_work: bool) -> impl FnOnce(output::OutputError) -> Failure {
    move |e| fail(if before_work { 2 } else { 1 }, e)
}

/// The progress of a long command on stderr, phase by phase ([`solver::Progress`]): on a
/// terminal a bar per phase; otherwise a line as each phase begins and one at the end, with
/// the time since the command began (as cargo prints); nothing if `quiet`.
pub(super) struct Progress {
    t0: Instant,
    bar: Option<indicatif::ProgressBar>,
    lines: bool,
}

impl Progress {
    /// The progress of a command that began at `t0`.
    pub(super) fn new(t0: Instant, quiet: bool) -> Self {
        let terminal = !quiet && std::io::stderr().is_terminal();
        let bar = terminal.then(|| {
            let b = indicatif::ProgressBar::new(0);
            let template = "{prefix:>12} {bar:30} {pos}/{len} {msg} ({elapsed})";
            b.set_style(
                indicatif::ProgressStyle::with_template(template)
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            b
        });
        Self {
            t0,
            bar,
            lines: !quiet && !terminal,
        }
    }

    fn line(&self, what: std::fmt::Arguments<'_>) {
        if self.lines {
            eprintln!("{:>9.2} s  {what}", self.t0.elapsed().as_secs_f64());
        }
    }

    /// Runs `f` (which prints to stderr) with the bar hidden.
    pub(super) fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        match &self.bar {
            Some(b) => b.suspend(f),
            None => f(),
        }
    }

    /// Removes the bar, or says the command is done.
    pub(super) fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
        self.line(format_args!("done"));
    }
}

/// An unfinished command's bar goes with it (its error follows).
impl Drop for Progress {
    fn drop(&mut self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

impl solver::Progress for Progress {
    fn phase(&self, name: &str, total: usize, unit: &str) {
        if let Some(b) = &self.bar {
            b.reset();
            b.set_length(total as u64);
            b.set_prefix(name.to_string());
            b.set_message(unit.to_string());
        }
        match total {
            1 => self.line(format_args!("{name}")),
            _ => self.line(format_args!("{name}, up to {total} {unit}")),
        }
    }

    fn tick(&self) {
        if let Some(b) = &self.bar {
            b.inc(1);
        }
    }
}

/// Reads an input file, at most [`input::MAX_INPUT_BYTES`] (exit 2 if unreadable).
pub(super) fn read_input(path: &Path) -> Result<Vec<u8>, Failure> {
    input::read(path).map_err(|e| fail(2, format!("reading {}: {e}", path.display())))
}

/// Reads a costate file (exit 2 if unreadable or invalid, or a binary gait file:
/// [`CostateFile::read`]).
pub(super) fn read_costate(path: &Path) -> Result<CostateFile, Failure> {
    CostateFile::read(path).map_err(|e| fail(2, e))
}

/// Reads a binary gait file (exit 2 if unreadable, or a costate file: the message says so;
/// the core checks the rest).
pub(super) fn read_gait(path: &Path) -> Result<Vec<u8>, Failure> {
    let bytes = read_input(path)?;
    if bytes.trim_ascii_start().starts_with(b"{") {
        return Err(fail(
            2,
            format!(
                "{}: a costate file (JSON), not a binary gait file (export's output); pass it \
                 as --costate",
                path.display()
            ),
        ));
    }
    Ok(bytes)
}

/// The gait a command reads: a costate file or a binary gait file, exactly one
/// (`replay`, `export`, `robustness`; `field` draws one optionally, with its own flags).
#[derive(Debug, Args)]
#[group(required = true, multiple = false)]
pub struct GaitInput {
    /// The costate file written by `solve` (DIR/costate.json).
    #[arg(long)]
    pub costate: Option<PathBuf>,
    /// A binary gait file written by `export`.
    #[arg(long)]
    pub gait: Option<PathBuf>,
}

impl GaitInput {
    /// The path given, either flag's.
    fn path(&self) -> &Path {
        match (&self.costate, &self.gait) {
            (Some(p), _) | (None, Some(p)) => p,
            // clap's group makes one of the two required.
            (None, None) => Path::new(""),
        }
    }

    /// The path and its gait file's bytes, a costate file converted (exit 2 if unreadable,
    /// invalid or of the other kind).
    pub(super) fn gait_bytes(&self) -> Result<(&Path, Vec<u8>), Failure> {
        let path = self.path();
        let bytes = match &self.costate {
            Some(_) => read_costate(path)?
                .to_gait()
                .map_err(|e| fail(2, format!("{}: {e}", path.display())))?,
            None => read_gait(path)?,
        };
        Ok((path, bytes))
    }

    /// The path and its numbers as a costate file, a gait file read back (exit 2 likewise).
    pub(super) fn costate_file(&self) -> Result<(&Path, CostateFile), Failure> {
        let path = self.path();
        match &self.costate {
            Some(_) => Ok((path, read_costate(path)?)),
            None => Ok((path, costate_of_gait(path)?)),
        }
    }
}

/// The numbers of the binary gait file `path`, as a costate file (exit 2 if it is none).
pub(super) fn costate_of_gait(path: &Path) -> Result<CostateFile, Failure> {
    let bytes = read_gait(path)?;
    let gait = Gait::from_bytes(&bytes).map_err(|e| fail(2, format!("{}: {e}", path.display())))?;
    Ok(CostateFile::new(
        *gait.params(),
        gait.arcs().collect(),
        gait.checkpoints().collect(),
    ))
}
