//! Offline solver for the initial costate of the Purcell swimmer, and replay through the core.
//!
//! [`solver`] finds the cheapest admissible extremal (global search on a coarse grid, Newton–SQP
//! with a Riccati step on the problem's own grid, the costate from the multipliers,
//! independent certificates); [`costate_file`] is the file format the firmware flies,
//! [`output`] and [`plots`] the outputs, [`replay`] replays a costate file through the core in
//! `f64`/`f32`; [`curvature`] is the shape-space view of the model (the curvature of the
//! connection) that `purcell-sim field` draws; [`problem`] holds the validated inputs,
//! [`input`] reads input files (bounded, JSON without repeated keys), [`dual`] dual numbers
//! for exact derivatives, [`cli`] the command line.
#![deny(missing_docs)]

pub mod cli;
pub mod costate_file;
pub mod curvature;
pub mod dual;
pub mod input;
pub mod output;
pub mod plots;
pub mod problem;
pub mod replay;
pub mod solver;
