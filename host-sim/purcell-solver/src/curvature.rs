//! The curvature of the local connection over the shape plane (MODEL.md §8).
//!
//! With our convention `ξ = g⁻¹ġ = −A(α)·α̇` (columns `A₁`, `A₂` of `A`), a small shape loop
//! that encloses the signed area `S` (positive counter-clockwise in the `(α1, α2)` plane)
//! moves the body, in its frame at the start, by
//!
//! ```text
//! log g_end = F(α)·S + O(|S|^{3/2}),   F = −(∂A₂/∂α1 − ∂A₁/∂α2) + [A₁, A₂],
//! ```
//!
//! `[X, Y] = ad_X·Y` the bracket of se(2) (zero in the θ row). For a larger loop the integral
//! of `F` over the area it encloses is the leading-order estimate of the net motion; this is
//! the colour field gait designers draw under their gaits.

use nalgebra::{Vector2, Vector3};
use purcell_core::{Error, Swimmer};
use std::f64::consts::PI;
use std::fmt::Write as _;

/// `F(α) = −(∂A₂/∂α1 − ∂A₁/∂α2) + [A₁, A₂]`, rows x, y (m/rad²) and θ (1/rad).
///
/// Errors: those of [`Swimmer::connection_with_derivatives`] (`|α_i| ≥ π`, non-finite).
pub fn curvature(swimmer: &Swimmer<f64>, alpha: &Vector2<f64>) -> Result<Vector3<f64>, Error> {
    let c = swimmer.connection_with_derivatives(alpha)?;
    let (a1, a2) = (c.a.column(0).into_owned(), c.a.column(1).into_owned());
    let exterior = c.da[0].column(1) - c.da[1].column(0);
    Ok(purcell_core::se2::ad(&a1) * a2 - exterior)
}

/// `F` sampled at the centres of an `n × n` grid of cells covering `]−π, π[²`.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// Cell centres along each axis, radians, increasing (the same for `α1` and `α2`).
    pub centres: Vec<f64>,
    /// `F` at `(centres[i], centres[j])`, stored at `j·n + i` (`α1` varies fastest).
    pub values: Vec<Vector3<f64>>,
}

impl Field {
    /// Cells per axis of the figures' field: 2° cells.
    pub const CELLS: usize = 180;

    /// Samples `F` on `cells × cells` cells.
    ///
    /// Errors: those of [`curvature`] (cell centres stay inside `]−π, π[`, so only a
    /// numerically singular swimmer can fail).
    pub fn sample(swimmer: &Swimmer<f64>, cells: usize) -> Result<Self, Error> {
        let w = 2.0 * PI / cells as f64;
        let centres: Vec<f64> = (0..cells).map(|i| -PI + (i as f64 + 0.5) * w).collect();
        let mut values = Vec::with_capacity(cells * cells);
        for &a2 in &centres {
            for &a1 in &centres {
                values.push(curvature(swimmer, &Vector2::new(a1, a2))?);
            }
        }
        Ok(Field { centres, values })
    }

    /// Width of one cell, radians.
    pub fn cell(&self) -> f64 {
        2.0 * PI / self.centres.len() as f64
    }

    /// `F` at cell `(i, j)`.
    pub fn at(&self, i: usize, j: usize) -> Vector3<f64> {
        self.values[j * self.centres.len() + i]
    }

    /// `∬ F(α)·w(α) dα1 dα2` over the cells, `w` the winding number of the closed polygon
    /// `path` (radians) around each cell centre: the leading-order estimate of the net motion
    /// of the gait `path` (exact as the gait shrinks and the cells get finer; see the module
    /// docs for what it misses on large gaits).
    pub fn integral_over(&self, path: &[Vector2<f64>]) -> Vector3<f64> {
        let n = self.centres.len();
        let area = self.cell() * self.cell();
        let mut sum = Vector3::zeros();
        let mut crossings: Vec<(f64, i32)> = Vec::new();
        for (j, &y) in self.centres.iter().enumerate() {
            // Where the path crosses the line α2 = y, and upwards (+1) or downwards (−1);
            // w(x, y) is the sum of the signs of the crossings right of x.
            crossings.clear();
            for (i, a) in path.iter().enumerate() {
                let b = path[(i + 1) % path.len()];
                if (a.y <= y) != (b.y <= y) {
                    let x = a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x);
                    crossings.push((x, if b.y > a.y { 1 } else { -1 }));
                }
            }
            crossings.sort_by(|p, q| p.0.total_cmp(&q.0));
            let mut w: i32 = crossings.iter().map(|c| c.1).sum();
            let mut next = 0;
            for i in 0..n {
                while next < crossings.len() && crossings[next].0 < self.centres[i] {
                    w -= crossings[next].1;
                    next += 1;
                }
                if w != 0 {
                    sum += self.at(i, j) * (w as f64 * area);
                }
            }
        }
        sum
    }

    /// The field as CSV: `alpha1,alpha2,curvature_x,curvature_y,curvature_theta` (rad, rad,
    /// m/rad², m/rad², 1/rad), one row per cell, `α1` varying fastest.
    pub fn to_csv(&self) -> String {
        let mut s = String::from("alpha1,alpha2,curvature_x,curvature_y,curvature_theta\n");
        let n = self.centres.len();
        for j in 0..n {
            for i in 0..n {
                let f = self.at(i, j);
                let _ = writeln!(
                    s,
                    "{},{},{},{},{}",
                    self.centres[i], self.centres[j], f.x, f.y, f.z
                );
            }
        }
        s
    }
}
