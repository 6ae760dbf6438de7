//! Offline solver for the cheapest gait of the Purcell swimmer and its initial costate
//! (MODEL.md §4): no command line, no files, no figures.
//!
//! [`problem`] holds the validated inputs; [`solver`] finds the cheapest admissible extremal
//! (global search on a coarse grid, Newton–SQP with a Riccati step on the problem's own grid,
//! joint limits as state constraints, the costate from the multipliers, certificates through
//! the core); [`tracking`] the gait under model error (a mismatched plant, open and closed
//! loop, the tracking gains); [`curvature`] is the curvature of the connection over the shape plane; [`dual`]
//! dual numbers for exact derivatives. With the `test-kit` feature, `testkit` holds what the
//! test crates share (a small problem, the checks of a returned extremal).
//!
//! The Newton iterations are traced through the [`log`] crate (see [`solver::direct`]); the
//! library installs no logger.
//!
//! The paper's problem (`ḡ = (0.1, 0.1, 0)`, `T = 100 s`, `h = 0.01 s`, unit links, `k = 1`,
//! `r = 2`):
//!
//! ```
//! use purcell_solver::problem::{Problem, Spec};
//! use purcell_solver::solver::{SolveOptions, solve};
//!
//! let problem = Problem::new(&Spec::default())?;
//! let solution = solve(&problem, &SolveOptions::default(), &|| {})?;
//! let gait = &solution.extremals[solution.best];
//! assert!((gait.cost - 0.6817478).abs() < 1e-7);
//! assert!(gait.admissible && gait.local_min);
//! // The five numbers the firmware's law runs from: μ and ξ^{−1}.
//! println!("J = {:.7}, mu = {:?}, xi0 = {:?}", gait.cost, gait.mu, gait.xi0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

pub mod curvature;
pub mod dual;
pub mod problem;
pub mod seeded;
pub mod solver;
#[cfg(feature = "test-kit")]
pub mod testkit;
pub mod tracking;
