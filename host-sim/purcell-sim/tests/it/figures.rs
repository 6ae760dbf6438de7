//! The figures are written and well-formed, by the library and by `solve --degrees` and
//! `field`: every SVG parses as XML with the figure's size, every PNG decodes at that size (at
//! least 1 200 pixels wide), the field's CSV has a row per cell; a joint limit and its arcs
//! are drawn (dashed bound, shaded spans, highlighted stretches, legend entries) exactly when
//! the gait has them. (How they look is checked by looking at them.)

use crate::common;

use common::{Solve, arg, assert_exit, read_dir, sim};
use nalgebra::{Vector2, Vector3};
use purcell_core::{Arc, Costate, Kinematics, Replay, State, Swimmer};
use purcell_sim::costate_file::{CheckpointRecord, CostateFile, GaitParams, Model};
use purcell_sim::plots::field::Component;
use purcell_sim::plots::style::{ARC, ARC_LABEL, ARC_LINE, ARC_SHADE, JOINT_LIMIT, LINE};
use purcell_sim::plots::{FieldGait, Options, PlotError, field_files, figures};
use purcell_solver::problem::{OVERLAP, Problem};
use purcell_solver::solver::Trajectory;
use std::collections::BTreeMap;
use std::path::Path;

/// A gait of 1 000 steps from an arbitrary costate (figures do not need an extremal), its
/// costate file with checkpoints every 100 steps, and the problem it solves.
fn gait() -> (Problem, Trajectory, Vector3<f64>, CostateFile) {
    let (h, steps) = (0.01, 1000);
    let mu = Vector3::new(0.3, 0.8, -0.1);
    let xi = Vector2::new(0.2, -0.3);
    let kin = Kinematics::new(Swimmer::purcell(), h).unwrap();
    let start = State::at_origin(Vector2::new(0.1, -0.2));
    let mut replay = Replay::new(kin, start, Costate { mu, xi }, steps, &[]).unwrap();
    let mut t = Trajectory::default();
    t.xis.push(xi);
    let mut checkpoints = Vec::new();
    while let Some(s) = replay.step().unwrap() {
        if s.k > 0 && s.k % 100 == 0 {
            let g = s.state.g;
            checkpoints.push(CheckpointRecord {
                k: s.k,
                alpha: [s.state.alpha.x, s.state.alpha.y],
                g: [g.x(), g.y(), g.cos(), g.sin()],
                xi: [t.xis[s.k as usize].x, t.xis[s.k as usize].y],
            });
        }
        t.states.push(s.state);
        t.controls.push(s.u);
        t.xis.push(s.xi);
    }
    let end = *replay.state();
    t.states.push(end);
    let file = CostateFile::new(
        GaitParams {
            model: Model {
                links: [1.0; 3],
                drag: 1.0,
                ratio: 2.0,
            },
            h,
            steps,
            alpha0: [start.alpha.x, start.alpha.y],
            target: [end.g.x(), end.g.y(), end.g.theta()],
            mu: [mu.x, mu.y, mu.z],
            xi0: [xi.x, xi.y],
            checkpoint_every: 100,
            alpha_max: None,
            alpha_end: None,
            cost: Default::default(),
        },
        Vec::new(),
        checkpoints,
    );
    let problem = file.problem().unwrap();
    (problem, t, mu, file)
}

/// `(width, height)` of a well-formed SVG.
fn svg_size(bytes: &[u8]) -> (u32, u32) {
    let text = std::str::from_utf8(bytes).expect("SVG is UTF-8");
    let doc = roxmltree::Document::parse(text).expect("SVG is XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    let dim = |a: &str| root.attribute(a).unwrap().parse::<u32>().unwrap();
    assert!(root.descendants().any(|n| n.has_tag_name("text")));
    (dim("width"), dim("height"))
}

/// `(width, height)` of a PNG that decodes whole.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .expect("PNG header");
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).expect("PNG data");
    assert_eq!(info.color_type, png::ColorType::Rgb);
    // Not blank: some pixels are dark (text, lines).
    assert!(buf.iter().any(|&v| v < 64));
    (info.width, info.height)
}

fn check_figures(files: &BTreeMap<String, Vec<u8>>, names: &[&str]) {
    for name in names {
        let svg = svg_size(&files[&format!("{name}.svg")]);
        let png = png_size(&files[&format!("{name}.png")]);
        assert_eq!(svg, png, "{name}");
        assert!(png.0 >= 1200, "{name}: {png:?}");
    }
}

fn check_field_csv(csv: &[u8]) {
    let text = std::str::from_utf8(csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("alpha1,alpha2,curvature_x,curvature_y,curvature_theta")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 180 * 180);
    assert!(
        rows.iter()
            .all(|r| r.len() == 5 && r.iter().all(|v| v.is_finite()))
    );
    // Radians, whatever the figures' units.
    assert!(rows.iter().all(|r| r[0].abs() < std::f64::consts::PI));
}

const ALL: [&str; 9] = [
    "shape_loop",
    "swimmer",
    "alpha",
    "controls",
    "position",
    "theta",
    "costate",
    "replay_error",
    "field",
];

/// What an SVG draws of a joint limit and its arcs: the legend entries, the dashes of the
/// limit (lines in [`JOINT_LIMIT`] as wide as the limit's dashes), the shaded spans and the
/// highlighted stretches (legend samples included).
#[derive(Debug, PartialEq)]
struct LimitMarks {
    limit_label: bool,
    arc_label: bool,
    dashes: usize,
    shaded: usize,
    stretches: usize,
}

fn limit_marks(svg: &[u8]) -> LimitMarks {
    let text = std::str::from_utf8(svg).unwrap();
    let doc = roxmltree::Document::parse(text).unwrap();
    let hex = |c: plotters::style::RGBColor| format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2);
    let width = |w: f64| format!("{}", w.round());
    let count = |tag: &str, attrs: &[(&str, String)]| {
        doc.descendants()
            .filter(|n| n.has_tag_name(tag))
            .filter(|n| attrs.iter().all(|(a, v)| n.attribute(*a) == Some(v)))
            .count()
    };
    let texts: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text().map(str::trim))
        .collect();
    LimitMarks {
        limit_label: texts.iter().any(|t| t.starts_with("joint limit ±")),
        arc_label: texts.contains(&ARC_LABEL),
        dashes: count(
            "polyline",
            &[
                ("stroke", hex(JOINT_LIMIT)),
                ("stroke-width", width(LINE - 1.0)),
            ],
        ),
        shaded: count("rect", &[("fill", hex(ARC_SHADE))]),
        stretches: count(
            "polyline",
            &[("stroke", hex(ARC)), ("stroke-width", width(ARC_LINE))],
        ),
    }
}

const NONE: LimitMarks = LimitMarks {
    limit_label: false,
    arc_label: false,
    dashes: 0,
    shaded: 0,
    stretches: 0,
};

/// The test gait under a joint limit at its largest `|α_i|`, with an arc of 11 states of that
/// joint ending there (or before the last state, where arcs end) and one of a single state
/// (drawn as a dot): the figures do not need the arcs to be an extremal's.
fn limited() -> (Problem, Vec<Arc>) {
    let (mut problem, t, _, _) = gait();
    let (k, joint) = (0..t.states.len())
        .flat_map(|k| [(k, 0), (k, 1)])
        .max_by(|a, b| {
            let v = |(k, i): (usize, usize)| t.states[k].alpha[i].abs();
            v(*a).total_cmp(&v(*b))
        })
        .unwrap();
    let peak = t.states[k].alpha[joint];
    assert!(peak.abs() < OVERLAP);
    problem.alpha_max = Some(peak.abs());
    let last = k.min(t.controls.len() - 1).max(10) as u32;
    let arcs = vec![
        Arc {
            joint: Arc::joint_of(joint),
            sign: if peak > 0.0 { 1 } else { -1 },
            first: last - 10,
            last,
        },
        Arc {
            joint: Arc::joint_of(1 - joint),
            sign: 1,
            first: 3,
            last: 3,
        },
    ];
    (problem, arcs)
}

#[test]
fn a_joint_limit_and_its_arcs_are_drawn_only_when_the_gait_has_them() {
    let (free, t, mu, file) = gait();
    let (problem, arcs) = limited();
    let options = Options { degrees: true };
    let render = |p: &Problem, arcs: &[Arc]| -> BTreeMap<String, Vec<u8>> {
        figures(p, &t, arcs, &mu, &file, &options)
            .unwrap()
            .into_iter()
            .collect()
    };
    let with = render(&problem, &arcs);
    check_figures(&with, &ALL);
    let marks = |name: &str| limit_marks(&with[&format!("{name}.svg")]);
    // The square (sides inside the view) and the α(t) levels, dashed.
    for (name, panels) in [("shape_loop", 1), ("field", 3)] {
        let m = marks(name);
        assert!(
            m.limit_label && m.arc_label && m.dashes >= 40,
            "{name}: {m:?}"
        );
        // Per panel one stretch of 11 states (the single state is a dot); the legend sample.
        assert_eq!((m.stretches, m.shaded), (panels + 1, 0), "{name}");
    }
    let m = marks("alpha");
    assert!(m.limit_label && m.arc_label && m.dashes >= 40, "{m:?}");
    // Two spans and the legend sample.
    assert_eq!((m.shaded, m.stretches), (3, 0));
    // The same spans, without the bound.
    for name in ["controls", "costate"] {
        let m = marks(name);
        assert!(
            m.arc_label && !m.limit_label && m.dashes == 0,
            "{name}: {m:?}"
        );
        assert_eq!(m.shaded, 3, "{name}");
    }
    for name in ["swimmer", "position", "theta", "replay_error"] {
        assert_eq!(marks(name), NONE, "{name}");
    }

    // A joint limit without arcs: the bound alone.
    let bare = render(&problem, &[]);
    let m = limit_marks(&bare["shape_loop.svg"]);
    assert!(m.limit_label && !m.arc_label && m.dashes >= 40 && m.stretches == 0);
    assert_eq!(limit_marks(&bare["controls.svg"]), NONE);
    // No joint limit: neither.
    let free = render(&free, &[]);
    for name in ALL {
        assert_eq!(limit_marks(&free[&format!("{name}.svg")]), NONE, "{name}");
    }
}

#[test]
fn arcs_outside_the_gait_are_refused() {
    let (problem, t, mu, file) = gait();
    let n = t.states.len() as u32;
    for (joint, first, last) in [(3, 1, 2), (1, 5, 4), (2, n - 2, n)] {
        let arc = Arc {
            joint,
            sign: 1,
            first,
            last,
        };
        let e = figures(&problem, &t, &[arc], &mu, &file, &Options::default()).unwrap_err();
        assert!(matches!(e, PlotError::Arc { .. }), "{e}");
        let e = field_files(
            &problem.swimmer,
            Some(FieldGait {
                problem: &problem,
                states: &t.states,
                arcs: &[arc],
            }),
            &[Component::X],
            &Options::default(),
        )
        .unwrap_err();
        assert!(matches!(e, PlotError::Arc { .. }), "{e}");
    }
}

#[test]
fn every_figure_is_written_as_svg_and_png_in_both_units() {
    let (problem, t, mu, file) = gait();
    for degrees in [false, true] {
        let files: BTreeMap<_, _> = figures(&problem, &t, &[], &mu, &file, &Options { degrees })
            .unwrap()
            .into_iter()
            .collect();
        assert_eq!(files.len(), 2 * ALL.len() + 1);
        check_figures(&files, &ALL);
        check_field_csv(&files["field.csv"]);
        let alpha = std::str::from_utf8(&files["alpha.svg"]).unwrap();
        let unit = if degrees { "(deg)" } else { "(rad)" };
        assert!(alpha.contains(unit), "degrees {degrees}");
    }
}

#[test]
fn field_alone_with_and_without_a_gait() {
    let (problem, t, _, _) = gait();
    let options = Options { degrees: true };
    let bare = field_files(&problem.swimmer, None, &[Component::Theta], &options).unwrap();
    let with = field_files(
        &problem.swimmer,
        Some(FieldGait {
            problem: &problem,
            states: &t.states,
            arcs: &[],
        }),
        &Component::ALL,
        &options,
    )
    .unwrap();
    for files in [bare, with] {
        let files: BTreeMap<_, _> = files.into_iter().collect();
        assert_eq!(files.len(), 3);
        check_figures(&files, &["field"]);
        check_field_csv(&files["field.csv"]);
    }
}

#[test]
fn a_trajectory_that_is_not_a_gait_is_refused() {
    let (problem, mut t, mu, file) = gait();
    t.controls.clear();
    let e = figures(&problem, &t, &[], &mu, &file, &Options::default()).unwrap_err();
    assert!(matches!(e, PlotError::Trajectory { .. }), "{e}");
}

/// `solve` of [`Solve::small`] with `extra` arguments into `out`: exit 0, every figure
/// written; what it wrote.
fn solve_small(out: &Path, extra: &[&str]) -> BTreeMap<String, Vec<u8>> {
    let o = Solve::small().out(out).with(extra).run();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{extra:?}: {err}");
    let files = read_dir(out);
    check_figures(&files, &ALL);
    check_field_csv(&files["field.csv"]);
    files
}

/// `field` with `args`, which must succeed.
fn field(args: &[&str]) {
    let o = sim(&[&["field"][..], args].concat());
    assert_exit(&o, 0, "");
}

/// `solve` draws every figure; under a joint limit it reaches, the gait slides along it on
/// arcs, which the figures mark, and `field --costate` of its costate file draws them too.
#[test]
fn solve_writes_every_figure_and_marks_the_arcs_on_a_joint_limit() {
    let dir = tempfile::tempdir().unwrap();
    let files = solve_small(&dir.path().join("small"), &[]);
    for name in ["trajectory.csv", "costate.json", "report.json"] {
        assert!(files.contains_key(name), "{name}");
    }
    for name in ALL {
        assert_eq!(limit_marks(&files[&format!("{name}.svg")]), NONE, "{name}");
    }

    // The same problem under a joint limit it reaches: the gait slides along it on arcs
    // (two, on the lower limit, found by the solver), which the figures mark.
    let limited = dir.path().join("limited");
    let files = solve_small(&limited, &["--alpha-max", "1.2"]);
    let report: serde_json::Value = serde_json::from_slice(&files["report.json"]).unwrap();
    let arcs = report["arcs"].as_array().unwrap().len();
    assert!(arcs > 0);
    let marks = |name: &str| limit_marks(&files[&format!("{name}.svg")]);
    for name in ["shape_loop", "field"] {
        let m = marks(name);
        assert!(
            m.limit_label && m.arc_label && m.dashes >= 40,
            "{name}: {m:?}"
        );
        assert!(m.stretches >= 2, "{name}: {m:?}");
    }
    for name in ["alpha", "controls", "costate"] {
        let m = marks(name);
        assert!(
            m.arc_label && m.shaded == arcs + 1,
            "{name}: {m:?} for {arcs} arcs"
        );
    }

    // `field --costate` of the constrained gait's costate file: its limit and arcs come with it.
    let limited_field = dir.path().join("limited-field");
    let costate = limited.join("costate.json");
    field(&["--costate", arg(&costate), "--out", arg(&limited_field)]);
    let m = limit_marks(&read_dir(&limited_field)["field.svg"]);
    assert!(m.limit_label && m.arc_label && m.stretches >= 2, "{m:?}");
}

/// `field` of a gait (the small problem's costate file, one row) and of a swimmer given by
/// its parameters; a gait's file brings its own swimmer, and a missing file writes nothing.
#[test]
fn field_draws_a_gait_or_a_swimmer() {
    let dir = tempfile::tempdir().unwrap();
    let small = dir.path().join("small");
    assert_exit(&Solve::small().no_plots().out(&small).run(), 0, "");
    let costate = small.join("costate.json");
    let out = dir.path().join("field");
    field(&[
        "--costate",
        arg(&costate),
        "--component",
        "theta",
        "--out",
        arg(&out),
    ]);
    let files = read_dir(&out);
    // field.svg, field.png, field.csv and the output manifest.
    assert_eq!(files.len(), 4);
    assert!(files.contains_key(purcell_sim::output::MANIFEST));
    check_figures(&files, &["field"]);
    field(&["--ratio", "3", "--out", arg(&out)]);
    check_field_csv(&read_dir(&out)["field.csv"]);

    // A gait's file brings its own swimmer; a missing file writes nothing.
    let o = sim(&[
        "field",
        "--costate",
        arg(&costate),
        "--links",
        "1,2,1",
        "--out",
        arg(&out),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--links"));
    let nowhere = dir.path().join("nowhere");
    let missing = dir.path().join("missing.json");
    let o = sim(&["field", "--costate", arg(&missing), "--out", arg(&nowhere)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!nowhere.exists());
}
