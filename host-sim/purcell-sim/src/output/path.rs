//! A path as CSV, one row per state `k = 0..=N`: `trajectory.csv` (the solver's extremal)
//! and `replay --trace` (a replay through the core) share its columns, so the two compare
//! row by row.
//!
//! Columns ([`HEADER`]): `k`; the time `t_k = k·h` as an exact decimal
//! ([`crate::decimal::time`]: `99.99`, never `99.99000000000001`); the shape `α_k`
//! (rad); the control `u_k` (rad/s, 0 on the last row, which has no step); the position
//! `g_k = (x, y, θ)` (m, m, rad); the costate `ξ^{k−1}` the law takes in at step `k`
//! (rad/s, the units of `u`; row 0 holds `ξ^{−1}`; at a state on the joint limit `ξ̃^{k−1}`,
//! with that state's jump, MODEL.md §9); and the joint-limit arcs the state is on: `arc1`,
//! `arc2` are `+1` (`α_i = +α_max`), `−1` (`α_i = −α_max`) or `0` (off any arc of joint `i`).
//! On an arc of joint `i` the two files differ in `ξ_i` alone: `trajectory.csv` holds the
//! solver's `ξ̃_i` (with the jump), a trace the core's `ξ_i`, which the arc step sets to
//! `(Aᵀζ)_i` (MODEL.md §9); elsewhere they agree to the law's rounding.
//! Numbers in shortest round-trip form of their type (`f32` for an `f32` replay).

use crate::decimal;
use purcell_core::Arc;
use std::fmt::{Display, Write as _};

/// The header line's columns, units in their names.
pub const HEADER: &str = "k,t_s,alpha1_rad,alpha2_rad,u1_rad_per_s,u2_rad_per_s,x_m,y_m,\
                          theta_rad,xi1_rad_per_s,xi2_rad_per_s,arc1,arc2";

/// One state of a path, in the path's number type `T`.
#[derive(Clone, Copy, Debug)]
pub struct Row<T> {
    /// `α_k`.
    pub alpha: [T; 2],
    /// `u_k` (`None` on the last row).
    pub u: Option<[T; 2]>,
    /// `(x, y, θ)` of `g_k`.
    pub g: [T; 3],
    /// `ξ^{k−1}` as the law takes it in at step `k`.
    pub xi: [T; 2],
}

/// A path's CSV, written row by row.
#[derive(Debug)]
pub struct PathCsv {
    text: String,
    h: f64,
    /// Per state `k`, the sign of the arc each joint is on (`0`: none).
    on: Vec<[i8; 2]>,
    k: u64,
}

impl PathCsv {
    /// An empty path of `steps` steps of `h` seconds on the joint-limit `arcs`.
    pub fn new(h: f64, steps: u32, arcs: impl IntoIterator<Item = Arc>) -> Self {
        let mut on = vec![[0i8; 2]; steps as usize + 1];
        for a in arcs {
            let joint = a.index();
            for flags in on
                .iter_mut()
                .take(a.last as usize + 1)
                .skip(a.first as usize)
            {
                flags[joint] = a.sign;
            }
        }
        PathCsv {
            text: format!("{HEADER}\n"),
            h,
            on,
            k: 0,
        }
    }

    /// Appends the next state's row.
    pub fn push<T: Display + Default + Copy>(&mut self, row: &Row<T>) {
        let k = self.k;
        let [a1, a2] = self.on.get(k as usize).copied().unwrap_or_default();
        let [u1, u2] = row.u.unwrap_or_default();
        let [x, y, theta] = &row.g;
        let _ = writeln!(
            self.text,
            "{k},{},{},{},{u1},{u2},{x},{y},{theta},{},{},{a1},{a2}",
            decimal::time(k, self.h),
            row.alpha[0],
            row.alpha[1],
            row.xi[0],
            row.xi[1],
        );
        self.k += 1;
    }

    /// The CSV text.
    pub fn finish(self) -> String {
        self.text
    }
}
