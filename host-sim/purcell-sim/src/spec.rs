//! One place that checks and prepares a search from plain numbers, for every front end (the
//! command line, the Python package): a solve's [`SolveSpec`] ([`prepare`]), a sweep's
//! problem ([`sweep_options`]) and lattice ([`axis`], [`lattice`]), the limits of a search,
//! and a stored extremal as a start ([`warm_of`]). Refusals are typed ([`SpecError`]): the
//! parameter and its numbers, worded by each front end ([`crate::words`]).

use crate::costate_file::CostateFile;
use crate::decimal::Decimal;
use crate::units::{self, Quantity};
use crate::words::{Front, Worded};
use purcell_solver::problem::{InputError, Problem, Spec};
use purcell_solver::solver::SolveOptions;
use purcell_solver::solver::continuation::{Lattice, Warm};

/// Largest start budget (each start is a Newton–SQP run on the coarse grid, a few ms).
pub const MAX_STARTS: usize = 4096;
/// Largest horizon a search accepts, in steps (its memory grows by about 0.3 kB per step
/// and start); a replay accepts up to [`purcell_solver::problem::MAX_STEPS`].
pub const MAX_SOLVE_STEPS: u32 = 1_000_000;
/// The smallest nonzero target a solve takes (largest of `|x|`, `|y|` in m and `|θ|` in
/// rad): below it the terminal tolerance (1e-10) is more than 1e-4 of the motion.
pub const MIN_TARGET: f64 = 1e-6;
/// The checkpoint spacing when not given.
pub const CHECKPOINT_EVERY: u32 = 100;
/// Most periodic checkpoints a solve writes (0.33 kB each in the costate file), so that its
/// files stay below [`crate::input::MAX_INPUT_BYTES`] and can be read back.
pub const MAX_CHECKPOINTS: u32 = 100_000;
/// Largest number of targets a sweep accepts.
pub const MAX_SWEEP_TARGETS: usize = 10_000;

/// Why a search's numbers were refused, before any work: the parameter and its numbers,
/// worded by each front end ([`Worded`]; `Display` is the command line's).
#[derive(Clone, Debug, PartialEq)]
pub enum SpecError {
    /// A start budget outside `1..=MAX_STARTS`.
    Starts(i128),
    /// More than [`MAX_SOLVE_STEPS`] steps.
    SolveSteps(u32),
    /// A nonzero target below [`MIN_TARGET`] (the target as given, its largest component).
    TinyTarget {
        /// The target as given.
        target: [f64; 3],
        /// Its largest component, theta wrapped.
        largest: f64,
    },
    /// The problem's own checks, or a number beyond `f32`.
    Problem(InputError),
    /// A checkpoint spacing given not below the horizon's steps.
    CheckpointsNone {
        /// The spacing.
        every: u32,
        /// The horizon's steps.
        steps: u32,
    },
    /// More than [`MAX_CHECKPOINTS`] checkpoints.
    Checkpoints {
        /// The spacing.
        every: u32,
        /// The horizon's steps.
        steps: u32,
    },
    /// An axis of a sweep that is no number nor `FROM:TO:COUNT` (`why` empty, or `: ` and
    /// the reason).
    Axis {
        /// The axis, `x`, `y` or `theta`.
        name: String,
        /// Its text.
        text: String,
        /// What is wrong, if more than the shape.
        why: String,
    },
    /// A lattice of more than [`MAX_SWEEP_TARGETS`] targets.
    Targets(usize),
}

impl Worded for SpecError {
    fn words(&self, f: Front) -> String {
        match self {
            SpecError::Starts(n) => {
                format!("{} must be 1 to {MAX_STARTS} (got {n})", f.arg("starts"))
            }
            SpecError::SolveSteps(n) => {
                format!("horizon T/h = {n} steps is more than solve's limit of {MAX_SOLVE_STEPS}")
            }
            SpecError::TinyTarget { target, largest } => format!(
                "{}: a motion this small (largest component {largest:e}) is below what solve \
                 resolves: its terminal tolerance, 1e-10, is more than 1e-4 of any target under \
                 {MIN_TARGET:e} (m or rad); {} is the zero gait (J = 0)",
                f.given("target", f.list(target)),
                match f {
                    Front::Cli => "0,0,0",
                    Front::Python => "(0, 0, 0)",
                },
            ),
            // The solver names its fields as the library does, but for the joint limit, which
            // it spells as the command line does.
            SpecError::Problem(e) => match f {
                Front::Cli => e.to_string(),
                Front::Python => e.to_string().replace("alpha-max", "alpha_max"),
            },
            SpecError::CheckpointsNone { every, steps } => format!(
                "{} is not below the horizon's {steps} steps: the costate file would have no \
                 checkpoint (0 for none)",
                f.given("checkpoint_every", every)
            ),
            SpecError::Checkpoints { every, steps } => format!(
                "{} gives {} checkpoints over {steps} steps, more than the limit \
                 {MAX_CHECKPOINTS}",
                f.given("checkpoint_every", every),
                (steps - 1) / every
            ),
            SpecError::Axis { name, text, why } => {
                format!(
                    "{} takes a number or FROM:TO:COUNT{why} (got {text:?})",
                    f.arg(name)
                )
            }
            SpecError::Targets(n) => {
                format!("{n} targets: more than the limit {MAX_SWEEP_TARGETS}")
            }
        }
    }
}

impl std::fmt::Display for SpecError {
    fn fmt(&self, out: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        out.write_str(&self.words(Front::Cli))
    }
}

impl std::error::Error for SpecError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SpecError::Problem(e) => Some(e),
            _ => None,
        }
    }
}

impl From<InputError> for SpecError {
    fn from(e: InputError) -> Self {
        SpecError::Problem(e)
    }
}

/// A solve, as plain numbers.
#[derive(Clone, Debug)]
pub struct SolveSpec {
    /// The problem, its target as given (theta not yet wrapped).
    pub problem: Spec,
    /// Budget of start loops (`None`: the problem's default, [`SolveOptions::budget`]).
    pub starts: Option<usize>,
    /// Order of the start loops.
    pub seed: u64,
    /// Costate checkpoint spacing in steps (`None`: [`CHECKPOINT_EVERY`]; 0: none).
    pub checkpoint_every: Option<u32>,
}

/// A solve checked and ready to run.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// The problem.
    pub problem: Problem,
    /// Its checkpoint spacing.
    pub checkpoint_every: u32,
    /// The search's options.
    pub options: SolveOptions,
}

/// `spec` checked as a solve: the target's size, the model ([`Problem::new`]), every number
/// within `f32` (the costate file is for the `f32` firmware, and the report replays it in
/// `f32`), the search's limits, the checkpoint spacing.
pub fn prepare(spec: &SolveSpec) -> Result<Prepared, SpecError> {
    let [x, y, theta] = spec.problem.target;
    let target = [x, y, units::wrap_angle(theta)];
    let largest = target.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if largest > 0.0 && largest < MIN_TARGET {
        let target = spec.problem.target;
        return Err(SpecError::TinyTarget { target, largest });
    }
    let problem = Problem::new(&Spec {
        target,
        ..spec.problem.clone()
    })?;
    problem.check_precision::<f32>("f32")?;
    search_limits(&problem, spec.starts)?;
    let checkpoint_every = checkpoint_spacing(spec.checkpoint_every, problem.steps)?;
    let options = SolveOptions {
        starts: spec.starts,
        seed: spec.seed,
        ..SolveOptions::default()
    };
    Ok(Prepared {
        problem,
        checkpoint_every,
        options,
    })
}

/// The bounds of a search: `1 ≤ starts ≤ MAX_STARTS` if given, at most `MAX_SOLVE_STEPS`
/// steps.
pub fn search_limits(problem: &Problem, starts: Option<usize>) -> Result<(), SpecError> {
    if let Some(starts) = starts.filter(|s| !(1..=MAX_STARTS).contains(s)) {
        return Err(SpecError::Starts(starts as i128));
    }
    if problem.steps > MAX_SOLVE_STEPS {
        return Err(SpecError::SolveSteps(problem.steps));
    }
    Ok(())
}

/// The checkpoint spacing of a solve of `steps` steps: as given, below `steps` (or 0), with
/// at most [`MAX_CHECKPOINTS`] checkpoints; [`CHECKPOINT_EVERY`] if not given.
fn checkpoint_spacing(given: Option<u32>, steps: u32) -> Result<u32, SpecError> {
    let every = given.unwrap_or(CHECKPOINT_EVERY);
    if given.is_some() && every != 0 && every >= steps {
        return Err(SpecError::CheckpointsNone { every, steps });
    }
    if every != 0 && (steps - 1) / every > MAX_CHECKPOINTS {
        return Err(SpecError::Checkpoints { every, steps });
    }
    Ok(every)
}

/// The search options of a sweep of `spec` (its target unused) with `starts` starts each
/// (`None`: the problem's default), the problem and the search's limits checked.
pub fn sweep_options(spec: &Spec, starts: Option<usize>) -> Result<SolveOptions, SpecError> {
    search_limits(&Problem::new(spec)?, starts)?;
    Ok(SolveOptions {
        starts,
        ..SolveOptions::default()
    })
}

/// The lattice of `axes` (x, y, theta), at most [`MAX_SWEEP_TARGETS`] targets.
pub fn lattice(axes: [Vec<f64>; 3]) -> Result<Lattice, SpecError> {
    let lattice = Lattice { axes };
    match lattice.len() {
        n if n > MAX_SWEEP_TARGETS => Err(SpecError::Targets(n)),
        _ => Ok(lattice),
    }
}

/// Axis `name` of the lattice: `FROM:TO:COUNT` or a single value, of kind `q` (an angle's
/// degrees converted to radians). A range's values are the decimals
/// `FROM + i·(TO − FROM)/(COUNT − 1)` computed exactly from the numbers as typed where they
/// are decimals in the same unit (`0.05`, not `0.050000000000000044`), so that `sweep.csv`
/// shows, and the solver uses, the value meant; evenly spaced floats ([`Lattice::spaced`])
/// otherwise (e.g. thirds).
pub fn axis(name: &str, text: &str, q: Quantity) -> Result<Vec<f64>, SpecError> {
    let bad = |why: String| SpecError::Axis {
        name: name.into(),
        text: text.into(),
        why,
    };
    // An end: its value, as a decimal if it is one, and whether it is in degrees.
    let end = |s: &str| -> Result<(f64, Option<Decimal>, bool), SpecError> {
        let (number, degrees) = units::split_unit(s, q).map_err(|e| bad(format!(": {e}")))?;
        let v = number.parse::<f64>().ok().filter(|v| v.is_finite());
        Ok((
            v.ok_or_else(|| bad(String::new()))?,
            Decimal::parse(number),
            degrees,
        ))
    };
    match text.split(':').collect::<Vec<_>>().as_slice() {
        [v] => {
            let (v, _, degrees) = end(v)?;
            Ok(vec![units::radians(v, degrees)])
        }
        [a, b, n] => {
            let ((a, da, deg_a), (b, db, deg_b)) = (end(a)?, end(b)?);
            let n: usize = n.trim().parse().map_err(|_| bad(String::new()))?;
            if n == 0 || n > MAX_SWEEP_TARGETS {
                return Err(bad(String::new()));
            }
            let exact = match (da, db) {
                (Some(da), Some(db)) if deg_a == deg_b => (0..n)
                    .map(|i| Decimal::lerp(da, db, i, n).map(|d| units::radians(d.to_f64(), deg_a)))
                    .collect::<Option<Vec<f64>>>(),
                _ => None,
            };
            Ok(exact.unwrap_or_else(|| {
                Lattice::spaced(units::radians(a, deg_a), units::radians(b, deg_b), n)
            }))
        }
        _ => Err(bad(String::new())),
    }
}

/// Why a stored extremal is no start, its file named `name` in the message.
#[derive(Debug, thiserror::Error)]
pub enum WarmError {
    /// The file could not be read.
    #[error(transparent)]
    Read(#[from] crate::costate_file::ReadError),
    /// Its problem is invalid.
    #[error("{name}: {error}")]
    Problem {
        /// The file's name.
        name: String,
        /// Why.
        error: InputError,
    },
    /// Its replay fails.
    #[error("{name}: its replay fails ({error})")]
    Replay {
        /// The file's name.
        name: String,
        /// Why.
        error: purcell_core::Error,
    },
    /// Its trajectory is empty.
    #[error("{name}: empty trajectory")]
    Empty {
        /// The file's name.
        name: String,
    },
}

/// The stored extremal of the costate file `path` as a start for a problem ([`warm_of`]).
pub fn warm_start(path: &std::path::Path) -> Result<Warm, WarmError> {
    warm_of(&CostateFile::read(path)?, &path.display().to_string())
}

/// The extremal of a costate `file` (named `name` in messages) as a start for a problem of
/// any swimmer: the gait's neighbouring extremal for another drag ratio or other links, where
/// Newton reaches it.
pub fn warm_of(file: &CostateFile, name: &str) -> Result<Warm, WarmError> {
    let name = || name.to_string();
    let stored = file.problem().map_err(|error| WarmError::Problem {
        name: name(),
        error,
    })?;
    let t = crate::replay::trajectory(file).map_err(|error| WarmError::Replay {
        name: name(),
        error,
    })?;
    let mu = nalgebra::Vector3::from(file.mu);
    Warm::from_trajectory(&t, &mu, stored.horizon())
        .ok_or_else(|| WarmError::Empty { name: name() })
}
