//! The `purcell-sim` command line over [`purcell_solver`]: the files it reads and writes and
//! the figures.
//!
//! [`cli`] is the command line, over the library layer that every front end (it, the Python
//! package) calls: [`spec`] checks and prepares a search from plain numbers ([`units`] parses
//! numbers with units; [`words`] words its refusals for each front end), [`report`] builds what a solve writes; [`costate_file`] the file format the firmware flies (and its
//! binary gait export); [`output`] and [`plots`] the outputs (written atomically) and figures;
//! [`decimal`] writes times and grid values as exact decimals;
//! [`replay`] replays a costate file through the core in `f64`/`f32`; [`robustness`] holds what
//! a gait flown through a mismatched plant reports, [`replan`] re-plans such a flight; [`input`] reads input files (bounded, JSON
//! without repeated keys); [`budget`] the step and memory budget of every reader of a stored
//! gait; [`suite`] the problems file of the public solver suite.
#![deny(missing_docs)]

pub mod budget;
#[cfg(feature = "cli")]
pub mod cli;
pub mod costate_file;
pub mod decimal;
pub mod find;
pub mod input;
pub mod output;
pub mod plots;
pub mod replan;
pub mod replay;
pub mod report;
pub mod robustness;
pub mod spec;
pub mod suite;
pub mod units;
pub mod words;
