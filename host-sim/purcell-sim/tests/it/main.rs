//! The integration tests of the crate, one module per subject, linked into one test binary (each
//! binary costs a compile and a link at opt-level 3). A new `tests/<name>.rs` builds as its own
//! binary; `tests/common/` is the kit all of them share.

#[path = "../common/mod.rs"]
mod common;

mod c_pair;
mod cli;
mod cli_props;
mod conventions;
mod costate_files;
mod costs;
mod exit3;
mod extra_problems;
mod figures;
mod gait_files;
mod never_lose;
mod output_files;
mod outputs;
mod power_fronts;
mod power_gaits;
mod replan;
mod report_order;
mod robustness;
mod solve_cli;
mod solver;
mod transitions;
