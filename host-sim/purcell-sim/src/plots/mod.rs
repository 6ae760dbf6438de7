//! Figures, each written as SVG and PNG ([`mod@render`]), in one style ([`style`]; axes and
//! their ticks in [`axes`]).
//!
//! [`figures`] makes every figure of a solved gait (what `solve` writes); [`field_files`]
//! the curvature field alone (what `field` writes). Figure kinds: panels over time
//! ([`time`]), equal-aspect planes ([`plane`]), the field over the shape plane ([`field`]);
//! the figures of a gait are built in [`gait`], the replay-error figure in
//! [`replay_error`], the pose error of a mismatched plant in [`robustness`]; [`sweep_files`] the atlas of a sweep ([`sweep`]).
//!
//! Angles are in radians, or degrees with [`Options::degrees`]; lengths in metres, time in
//! seconds; costates and the curvature always in SI (per radian).
//!
//! Figures are data ([`time::Panel`], [`plane::Overlay`]) drawn by one routine per kind, so
//! a new mark is a field and a loop: the arcs on the joint limit are shaded time spans of a
//! `Panel` and highlighted stretches of an `Overlay`'s paths, in the style
//! [`style::ARC`] sets, built in [`gait`] with the bound ([`gait::bound`]: a joint
//! limit, dashed dark, always shown; else where the links overlap, dashed grey).

pub mod axes;
pub mod field;
pub mod gait;
pub mod plane;
pub mod render;
pub mod replay_error;
pub mod robustness;
pub mod style;
pub mod sweep;
pub mod time;

use crate::costate_file::CostateFile;
use field::{Component, FieldFigure};
use gait::GaitFigures;
use nalgebra::{Vector2, Vector3};
use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend};
use purcell_core::{Arc, State, Swimmer};
use purcell_solver::curvature::Field;
use purcell_solver::problem::Problem;
use purcell_solver::solver::Trajectory;
use purcell_solver::solver::continuation::{Lattice, SweepPoint};
use rayon::prelude::*;
use render::{Figure, render};

/// Why a figure could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The bundled font did not load.
    #[error("the bundled font did not load")]
    Font,
    /// A backend failed.
    #[error("drawing {0}")]
    Draw(String),
    /// The model refused a state of the gait.
    #[error("model: {0}")]
    Model(#[from] purcell_core::Error),
    /// Replaying the costate file failed before its first step.
    #[error("replaying the costate file: {0}")]
    Replay(String),
    /// The trajectory is not a gait of at least one step.
    #[error("the trajectory has {states} states and {controls} controls")]
    Trajectory {
        /// States.
        states: usize,
        /// Controls.
        controls: usize,
    },
    /// An arc is not a run of states of the gait.
    #[error("arc of joint {joint} over states {first}..={last} in a gait of {states} states")]
    Arc {
        /// Its joint (1 or 2).
        joint: u8,
        /// First state.
        first: u32,
        /// Last state.
        last: u32,
        /// States of the gait.
        states: usize,
    },
}

/// `arcs` are runs `first..=last` of a gait's `states` states, on joint 1 or 2.
fn check_arcs(arcs: &[Arc], states: usize) -> Result<(), PlotError> {
    match arcs
        .iter()
        .find(|a| !matches!(a.joint, 1 | 2) || a.first > a.last || a.last as usize >= states)
    {
        Some(a) => Err(PlotError::Arc {
            joint: a.joint,
            first: a.first,
            last: a.last,
            states,
        }),
        None => Ok(()),
    }
}

/// Choices for the figures.
#[derive(Clone, Copy, Debug, Default)]
pub struct Options {
    /// Angles in degrees and rates in deg/s (radians otherwise).
    pub degrees: bool,
}

/// How angles are shown.
#[derive(Clone, Copy, Debug)]
pub struct Units {
    /// Display units per radian.
    pub per_radian: f64,
    /// `deg` or `rad`.
    pub angle_unit: &'static str,
    /// `deg/s` or `rad/s`.
    pub rate_unit: &'static str,
}

impl Units {
    /// The units `options` ask for.
    pub fn new(options: &Options) -> Self {
        if options.degrees {
            Units {
                per_radian: 180.0 / std::f64::consts::PI,
                angle_unit: "deg",
                rate_unit: "deg/s",
            }
        } else {
            Units {
                per_radian: 1.0,
                angle_unit: "rad",
                rate_unit: "rad/s",
            }
        }
    }

    /// An angle (or a rate) in display units.
    pub fn angle(&self, radians: f64) -> f64 {
        radians * self.per_radian
    }

    /// An angle as text with its unit.
    pub fn format_angle(&self, radians: f64) -> String {
        if self.per_radian == 1.0 {
            format!("{radians:.3} rad")
        } else {
            format!("{:.1}°", self.angle(radians))
        }
    }
}

/// Every figure of a gait, as `(file name, bytes)`: for each of `shape_loop`, `swimmer`,
/// `alpha`, `controls`, `position`, `theta`, `costate`, `replay_error` and `field` an SVG
/// and a PNG, and `field.csv`.
///
/// `trajectory` holds `k = 0..=N` states, `k < N` controls and `ξ^{k−1}` for `k = 0..=N`;
/// `arcs` are its arcs on the problem's joint limit (marked in `shape_loop`, `alpha`,
/// `controls`, `costate` and `field`); `mu` is its `μ`; `file` is its costate file (replayed in `f32`
/// and `f64` for the replay-error figure).
pub fn figures(
    problem: &Problem,
    trajectory: &Trajectory,
    arcs: &[Arc],
    mu: &Vector3<f64>,
    file: &CostateFile,
    options: &Options,
) -> Result<Vec<(String, Vec<u8>)>, PlotError> {
    let (states, controls) = (trajectory.states.len(), trajectory.controls.len());
    if controls == 0 || states != controls + 1 || trajectory.xis.len() != states {
        return Err(PlotError::Trajectory { states, controls });
    }
    check_arcs(arcs, states)?;
    let units = Units::new(options);
    let gait = GaitFigures {
        problem,
        trajectory,
        arcs,
        units,
    };
    let field = Field::sample(&problem.swimmer, Field::CELLS)?;
    let list = [
        ("shape_loop", Any::Plane(gait.shape_loop())),
        ("swimmer", Any::Plane(gait.swimmer())),
        ("alpha", Any::Time(gait.alpha())),
        ("controls", Any::Time(gait.controls())),
        ("position", Any::Time(gait.position())),
        ("theta", Any::Time(gait.theta())),
        ("costate", Any::Time(gait.costate(mu)?)),
        ("replay_error", Any::Time(replay_error::figure(file)?)),
        (
            "field",
            Any::Field(field_figure(
                &field,
                Some(FieldGait {
                    problem,
                    states: &trajectory.states,
                    arcs,
                }),
                &Component::ALL,
                units,
            )),
        ),
    ];
    let mut files = render_all(&list)?;
    files.push(("field.csv".into(), field.to_csv().into_bytes()));
    Ok(files)
}

/// A gait drawn over the field: its problem (the joint limit, the start), its states
/// `k = 0..=N` and its arcs on the joint limit.
#[derive(Clone, Copy, Debug)]
pub struct FieldGait<'a> {
    /// The problem it solves.
    pub problem: &'a Problem,
    /// States `k = 0..=N`.
    pub states: &'a [State<f64>],
    /// Arcs on the joint limit.
    pub arcs: &'a [Arc],
}

/// The curvature of the connection of `swimmer` over the shape plane: `field.svg`,
/// `field.png` (the `components` as panels) and `field.csv` (all three rows, SI units); with
/// a gait (its problem, states `k = 0..=N` and arcs on the joint limit), the gait, its arcs
/// and its joint limit drawn on top and, per row, the integral of `F` over the area it
/// encloses beside the motion it makes.
pub fn field_files(
    swimmer: &Swimmer<f64>,
    gait: Option<FieldGait<'_>>,
    components: &[Component],
    options: &Options,
) -> Result<Vec<(String, Vec<u8>)>, PlotError> {
    if let Some(g) = gait {
        check_arcs(g.arcs, g.states.len())?;
    }
    let field = Field::sample(swimmer, Field::CELLS)?;
    let figure = field_figure(&field, gait, components, Units::new(options));
    let mut files = render_all(&[("field", Any::Field(figure))])?;
    files.push(("field.csv".into(), field.to_csv().into_bytes()));
    Ok(files)
}

/// Two gaits over the field of `swimmer` (both its gaits), `field.svg`, `field.png` and
/// `field.csv` as [`field_files`] writes them for the first: the second drawn on top in
/// another colour, each path labelled with `labels` in the legend, `note` after the title
/// (e.g. the effort-optimal and the power-optimal gait, their costs and the saving).
pub fn comparison_files(
    swimmer: &Swimmer<f64>,
    gaits: [FieldGait<'_>; 2],
    labels: [String; 2],
    note: &str,
    components: &[Component],
    options: &Options,
) -> Result<Vec<(String, Vec<u8>)>, PlotError> {
    for g in &gaits {
        check_arcs(g.arcs, g.states.len())?;
    }
    let field = Field::sample(swimmer, Field::CELLS)?;
    let units = Units::new(options);
    let mut figure = field_figure(&field, Some(gaits[0]), components, units);
    let second = field_figure(&field, Some(gaits[1]), components, units).overlay;
    figure
        .overlay
        .paths
        .extend(second.paths.into_iter().map(|mut p| {
            p.color = style::VERMILLION;
            p
        }));
    for (path, label) in figure.overlay.paths.iter_mut().zip(labels) {
        path.label = label;
    }
    match (&mut figure.overlay.stretches, second.stretches) {
        (Some(mine), Some(theirs)) => mine.lines.extend(theirs.lines),
        (mine @ None, theirs) => *mine = theirs,
        (Some(_), None) => {}
    }
    figure.title = format!("{}; {note}", figure.title);
    let mut files = render_all(&[("field", Any::Field(figure))])?;
    files.push(("field.csv".into(), field.to_csv().into_bytes()));
    Ok(files)
}

fn field_figure<'a>(
    field: &'a Field,
    gait: Option<FieldGait<'_>>,
    components: &[Component],
    units: Units,
) -> FieldFigure<'a> {
    let (overlay, motion) = match gait {
        Some(FieldGait {
            problem,
            states,
            arcs,
        }) if !states.is_empty() => {
            let alphas: Vec<Vector2<f64>> = states.iter().map(|s| s.alpha).collect();
            let estimate = field.integral_over(&alphas);
            let actual = states[0].g.between(&states[states.len() - 1].g).log();
            let motion = [0, 1, 2].map(|i| (estimate[i], actual[i]));
            // Drawn with fewer points than the other figures: the field's SVG is large.
            let mut overlay = gait::shape_overlay(problem, &alphas, arcs, units, style::INK, 600);
            if problem.alpha_max.is_none() {
                // The overlap limit is the edge of the field.
                overlay.limit = None;
            }
            (overlay, Some(motion))
        }
        _ => (plane::Overlay::default(), None),
    };
    FieldFigure {
        title: "Curvature of the connection, −(∂A₂/∂α₁ − ∂A₁/∂α₂) + [A₁, A₂]".into(),
        field,
        components: components.to_vec(),
        overlay,
        motion,
        units,
    }
}

/// The sweep's atlas, `sweep.svg` and `sweep.png` ([`sweep::SweepFigure`]), its problems of
/// horizon `horizon` seconds.
pub fn sweep_files(
    lattice: &Lattice,
    points: &[SweepPoint],
    horizon: f64,
) -> Result<Vec<(String, Vec<u8>)>, PlotError> {
    Ok(render(
        "sweep",
        &sweep::SweepFigure {
            lattice,
            points,
            horizon,
        },
    )?
    .into())
}

/// Any figure, so that a list of them renders in parallel.
enum Any<'a> {
    Time(time::TimeFigure),
    Plane(plane::PlaneFigure),
    Field(FieldFigure<'a>),
}

impl Figure for Any<'_> {
    fn size(&self) -> (u32, u32) {
        match self {
            Any::Time(f) => f.size(),
            Any::Plane(f) => f.size(),
            Any::Field(f) => f.size(),
        }
    }

    fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        scale: f64,
    ) -> render::DrawResult
    where
        DB::ErrorType: 'static,
    {
        match self {
            Any::Time(f) => f.draw(area, scale),
            Any::Plane(f) => f.draw(area, scale),
            Any::Field(f) => f.draw(area, scale),
        }
    }
}

/// Renders `(name, figure)`s on all cores, in order.
fn render_all(list: &[(&str, Any<'_>)]) -> Result<Vec<(String, Vec<u8>)>, PlotError> {
    let rendered: Result<Vec<_>, PlotError> =
        list.par_iter().map(|(name, f)| render(name, f)).collect();
    Ok(rendered?.into_iter().flatten().collect())
}
