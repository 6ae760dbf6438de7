//! `connection`: the local connection `A(α)` and its derivatives as JSON (MODEL.md §7).

use super::args::{Failure, ModelArgs, fail};
use super::units;
use clap::Args;
use purcell_solver::problem::{Problem, Spec};
use serde_json::json;

/// `connection` flags.
#[derive(Debug, Args)]
pub struct ConnectionArgs {
    /// Shape A1,A2, each |A_i| < pi: radians, or degrees with deg (30deg,-20deg).
    #[arg(long, value_parser = units::angles::<2>(), allow_hyphen_values = true,
          required = true)]
    pub alpha: [f64; 2],
    /// Swimmer parameters.
    #[command(flatten)]
    pub model: ModelArgs,
}

/// `connection`: `A`, `∂A/∂α_1`, `∂A/∂α_2` at `--alpha`, rows `x, y, θ`, as printed.
pub(super) fn run_connection(a: ConnectionArgs) -> Result<String, Failure> {
    let alpha = a.alpha;
    let spec = Spec {
        links: a.model.links,
        drag: a.model.drag,
        ratio: a.model.ratio,
        alpha0: alpha,
        ..Spec::default()
    };
    let problem =
        Problem::new(&spec).map_err(|e| fail(2, e.to_string().replace("alpha0", "alpha")))?;
    let c = problem
        .swimmer
        .connection_with_derivatives(&nalgebra::Vector2::new(alpha[0], alpha[1]))
        .map_err(|e| fail(2, e))?;
    let rows =
        |m: &nalgebra::Matrix3x2<f64>| (0..3).map(|r| [m[(r, 0)], m[(r, 1)]]).collect::<Vec<_>>();
    let out = json!({"A": rows(&c.a), "dA_dalpha1": rows(&c.da[0]), "dA_dalpha2": rows(&c.da[1])});
    Ok(serde_json::to_string_pretty(&out).map_err(|e| fail(1, e))? + "\n")
}
