//! The integration tests of the crate, one module per subject, linked into one test binary (each
//! binary costs a compile and a link at opt-level 3). A new `tests/<name>.rs` builds as its own
//! binary; `tests/common/` is the kit all of them share.

#[path = "../common/mod.rs"]
mod common;

mod arcs;
mod connection;
mod costs;
mod end_shape;
mod errors;
mod gait;
mod golden;
mod kinematics;
mod law;
mod perf_api;
mod power_gait;
mod power_law;
mod replay;
mod se2;
mod switches;
mod tracking_section;
mod vectors;
