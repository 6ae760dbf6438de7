//! The figure that shows why checkpoints exist: an `f32` replay of the costate file against
//! the `f64` one, step by step, with and without the file's checkpoints.

use super::PlotError;
use super::gait::{POINTS, thin};
use super::style::*;
use super::time::{Mark, Panel, Series, TimeFigure};
use crate::costate_file::CostateFile;
use purcell_core::cost::RunningCost;
use purcell_core::{Gait, State, TerminalError};

/// One `f32` replay against the `f64` one: per plotted step, the largest state error (the
/// replays' metric, [`TerminalError`]: the larger of `|Δα|` and `|log(g₆₄⁻¹g₃₂)|`) since the
/// previous plotted step, as `log10`; and where it stopped if it failed.
struct Run {
    points: Vec<(f64, f64)>,
    failure: Option<(f64, f64, String)>,
}

fn run(file: &CostateFile, checkpoints: bool) -> Result<Run, PlotError> {
    purcell_core::with_cost!(file.cost, C => run_for::<C>(file, checkpoints))
}

/// [`run`] with the law of `C`, the file's cost.
fn run_for<C: RunningCost>(file: &CostateFile, checkpoints: bool) -> Result<Run, PlotError> {
    let replay_error = |e: purcell_core::Error| PlotError::Replay(e.to_string());
    let bytes = file.to_gait().map_err(replay_error)?;
    let gait = Gait::from_bytes(&bytes).map_err(replay_error)?;
    let mut r64 = gait.replay_for::<f64, C>(true).map_err(replay_error)?;
    let mut r32 = gait
        .replay_for::<f32, C>(checkpoints)
        .map_err(replay_error)?;
    let n = file.steps as usize;
    let plotted = thin(n, POINTS);
    let mut next = plotted.iter().copied().peekable();
    let (mut points, mut worst) = (Vec::new(), 0.0f64);
    let time = |k: usize| file.h * k as f64;
    for k in 0..=n {
        let (a, b): (State<f64>, State<f32>) = (*r64.state(), *r32.state());
        let e = TerminalError::new(&b, &a.alpha, &a.g);
        worst = worst.max(e.alpha.max(e.g));
        if next.peek() == Some(&k) {
            next.next();
            if worst > 0.0 {
                points.push((time(k), worst.log10()));
            }
            worst = 0.0;
        }
        if k == n {
            break;
        }
        r64.step().map_err(|e| PlotError::Replay(e.to_string()))?;
        if let Err(e) = r32.step() {
            let last = points.last().map_or(0.0, |p| p.1);
            return Ok(Run {
                points,
                failure: Some((time(k), last, e.to_string())),
            });
        }
    }
    Ok(Run {
        points,
        failure: None,
    })
}

/// The error over time of the `f32` replay with the file's checkpoints and without.
pub fn figure(file: &CostateFile) -> Result<TimeFigure, PlotError> {
    let with = run(file, true)?;
    let without = run(file, false)?;
    let every = file.checkpoint_every;
    let mut panel = Panel::new(
        "largest state error (rad, m)",
        vec![
            Series {
                label: "f32 from (μ, ξ⁻¹) alone".into(),
                color: VERMILLION,
                points: without.points,
            },
            Series {
                label: if file.checkpoints.is_empty() {
                    "f32 (the file has no checkpoints)".into()
                } else {
                    format!("f32 with checkpoints every {every} steps")
                },
                color: BLUE,
                points: with.points,
            },
        ],
    );
    panel.log10 = true;
    for (failure, color) in [(with.failure, BLUE), (without.failure, VERMILLION)] {
        if let Some((t, e, why)) = failure {
            panel.marks.push(Mark {
                at: (t, e),
                marker: Marker::Cross,
                color,
                label: Some(format!("replay stopped: {why}")),
            });
        }
    }
    Ok(TimeFigure {
        title: "f32 replay against f64, at every step".into(),
        t: (0.0, file.h * file.steps as f64),
        panels: vec![panel],
    })
}
