//! The problems file (`tests/problems/*.json`, the format of the public solver suite).

use crate::input;
use purcell_solver::problem::Spec;

/// One problem of a problems file (`tests/problems/*.json`, the format of the public solver
/// suite): the flags of `purcell-sim solve` that differ from the defaults, the cheapest
/// admissible cost an independent solver found (`ref`), and the expected outcome where it is
/// not a solution (`expect`, e.g. `"exit 3"`).
#[derive(Clone, Debug, PartialEq)]
pub struct SuiteProblem {
    /// Its name.
    pub name: String,
    /// The inputs.
    pub spec: Spec,
    /// Reference cost, if one was computed.
    pub reference: Option<f64>,
    /// Expected outcome other than a solution.
    pub expect: Option<String>,
}

/// Reads a problems file.
pub fn read_suite(text: &str) -> Result<Vec<SuiteProblem>, String> {
    #[derive(serde::Deserialize)]
    struct Entry {
        name: String,
        target: [f64; 3],
        horizon: Option<f64>,
        step: Option<f64>,
        alpha0: Option<[f64; 2]>,
        alpha_end: Option<[f64; 2]>,
        links: Option<[f64; 3]>,
        drag: Option<f64>,
        ratio: Option<f64>,
        alpha_max: Option<f64>,
        #[serde(rename = "ref")]
        reference: Option<f64>,
        expect: Option<String>,
    }
    let entries: Vec<Entry> = input::json(text.as_bytes()).map_err(|e| e.to_string())?;
    let d = Spec::default();
    Ok(entries
        .into_iter()
        .map(|e| SuiteProblem {
            name: e.name,
            spec: Spec {
                target: e.target,
                horizon: e.horizon.unwrap_or(d.horizon),
                step: e.step.unwrap_or(d.step),
                alpha0: e.alpha0.unwrap_or(d.alpha0),
                alpha_end: e.alpha_end,
                links: e.links.unwrap_or(d.links),
                drag: e.drag.unwrap_or(d.drag),
                ratio: e.ratio.unwrap_or(d.ratio),
                alpha_max: e.alpha_max,
                cost: d.cost,
            },
            reference: e.reference,
            expect: e.expect,
        })
        .collect())
}
