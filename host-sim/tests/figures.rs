//! The figures are written and well-formed, by the library and by `solve --degrees` and
//! `field`: every SVG parses as XML with the figure's size, every PNG decodes at that size (at
//! least 1 200 pixels wide), the field's CSV has a row per cell. (How they look is checked by
//! looking at them.)

use host_sim::costate_file::{CheckpointRecord, CostateFile, GaitParams, Model};
use host_sim::plots::field::Component;
use host_sim::plots::{Options, PlotError, field_files, figures};
use host_sim::problem::Problem;
use host_sim::solver::Trajectory;
use nalgebra::{Vector2, Vector3};
use purcell_core::{Costate, Kinematics, Replay, State, Swimmer};
use std::collections::BTreeMap;

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
        },
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

#[test]
fn every_figure_is_written_as_svg_and_png_in_both_units() {
    let (problem, t, mu, file) = gait();
    for degrees in [false, true] {
        let files: BTreeMap<_, _> = figures(&problem, &t, &mu, &file, &Options { degrees })
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
        Some((&problem, &t.states)),
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
    let e = figures(&problem, &t, &mu, &file, &Options::default()).unwrap_err();
    assert!(matches!(e, PlotError::Trajectory { .. }), "{e}");
}

fn sim(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_purcell-sim"))
        .args(args)
        .output()
        .expect("binary runs")
}

fn read_dir(dir: &std::path::Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

#[test]
fn solve_and_field_commands_write_every_figure() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("small");
    let o = sim(&[
        "solve",
        "--target",
        "0.02,0.02,0",
        "--horizon",
        "10",
        "--starts",
        "2",
        "--degrees",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let files = read_dir(&out);
    check_figures(&files, &ALL);
    check_field_csv(&files["field.csv"]);
    for name in ["trajectory.csv", "costate.json", "report.json"] {
        assert!(files.contains_key(name), "{name}");
    }

    // The field of that gait, one row, and the field of a swimmer given by its parameters.
    let costate = out.join("costate.json");
    let field = dir.path().join("field");
    let o = sim(&[
        "field",
        "--gait",
        costate.to_str().unwrap(),
        "--component",
        "theta",
        "--out",
        field.to_str().unwrap(),
    ]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let files = read_dir(&field);
    // field.svg, field.png, field.csv and the output manifest.
    assert_eq!(files.len(), 4);
    assert!(files.contains_key(host_sim::output::MANIFEST));
    check_figures(&files, &["field"]);
    let o = sim(&["field", "--ratio", "3", "--out", field.to_str().unwrap()]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    check_field_csv(&read_dir(&field)["field.csv"]);

    // A gait's file brings its own swimmer; a missing file writes nothing.
    let o = sim(&[
        "field",
        "--gait",
        costate.to_str().unwrap(),
        "--links",
        "1,2,1",
        "--out",
        field.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--links"));
    let nowhere = dir.path().join("nowhere");
    let o = sim(&[
        "field",
        "--gait",
        dir.path().join("missing.json").to_str().unwrap(),
        "--out",
        nowhere.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!nowhere.exists());
}
