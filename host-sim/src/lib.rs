//! Offline solver for the initial costate of the Purcell swimmer, and replay through the core.
//!
//! Pipeline of `purcell-sim solve` ([`solve`]): elliptic start loops ([`seed`]) → a direct
//! method on Fourier loops ([`direct`]) → a least-squares fit of `(μ, ξ^{−1})` ([`seed::fit`])
//! → Newton on the multiple-shooting system ([`multiple`]), whose Jacobian comes from the
//! core's own control law run on dual numbers ([`dual`]); then an independent optimality
//! check ([`kkt`]), the costate file ([`costate_file`]), outputs ([`output`], [`plots`]) and
//! replays in `f64`/`f32` ([`replay`]). [`curvature`] is the shape-space view of the model
//! (the curvature of the connection) that `purcell-sim field` draws. [`shooting`] holds the single-shooting map and its
//! Levenberg–Marquardt solver and homotopy; [`problem`] the validated inputs; [`cli`] the
//! command line.
#![deny(missing_docs)]

pub mod cli;
pub mod costate_file;
pub mod curvature;
pub mod direct;
pub mod dual;
pub mod kkt;
pub mod multiple;
pub mod output;
pub mod plots;
pub mod problem;
pub mod replay;
pub mod seed;
pub mod shooting;
pub mod solve;
