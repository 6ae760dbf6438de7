//! The figure of `robustness`: the plant's pose error against the nominal pose over time,
//! open loop and closed loop (the cases whose only error is the drag ratio at ±10 %, or the
//! one case flown), each re-plan marked on its curve.

use super::PlotError;
use super::gait::{POINTS, thin};
use super::style::*;
use super::time::{Mark, Panel, Series, TimeFigure};
use crate::robustness::{CaseReport, percent};

/// The flights' pose error over time (`h` the step), `log10`.
pub fn figure(cases: &[CaseReport], h: f64) -> Result<TimeFigure, PlotError> {
    let only_ratio = |c: &&CaseReport| {
        cases.len() == 1
            || ((c.ratio_error.abs() - 0.1).abs() < 1e-12
                && c.length_error == 0.0
                && c.drag_error == 0.0
                && c.pose_noise == 0.0
                && c.shape_noise == 0.0)
    };
    let colors = [[VERMILLION, BLUE], [PURPLE, GREEN]];
    let (mut series, mut marks) = (Vec::new(), Vec::new());
    let mut steps = 1;
    for (c, [open, closed]) in cases.iter().filter(only_ratio).zip(colors) {
        for (name, f, color) in [("open", &c.open, open), ("closed", &c.closed, closed)] {
            steps = steps.max(f.deviation.len());
            let points = thin(f.deviation.len().saturating_sub(1), POINTS)
                .into_iter()
                .filter_map(|k| {
                    let d = *f.deviation.get(k)?;
                    (d > 0.0).then(|| (h * k as f64, d.log10()))
                })
                .collect();
            series.push(Series {
                label: format!("{name} loop, r {}", percent(c.ratio_error)),
                color,
                points,
            });
            // Each re-plan (`--replan`) on its flight's curve.
            for r in &f.replans {
                let d = f.deviation.get(r.step as usize).copied().unwrap_or(0.0);
                marks.push(Mark {
                    at: (r.time, d.max(f64::MIN_POSITIVE).log10()),
                    marker: Marker::Diamond,
                    color,
                    label: (marks.is_empty()).then(|| "re-plan".to_string()),
                });
            }
        }
    }
    let mut panel = Panel::new("pose error against the nominal (m, rad)", series);
    panel.log10 = true;
    panel.marks = marks;
    Ok(TimeFigure {
        title: "the gait under a drag-ratio error: open and closed loop".into(),
        t: (0.0, h * steps as f64),
        panels: vec![panel],
    })
}
