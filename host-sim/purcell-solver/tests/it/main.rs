//! The integration tests of the crate, one module per subject, linked into one test binary (each
//! binary costs a compile and a link at opt-level 3). A new `tests/<name>.rs` builds as its own
//! binary.

mod certificates;
mod curvature;
mod ladder;
mod limited;
mod power;
mod seeds;
mod seeds_classes;
mod sweep;
mod switches;
mod tracking;
mod transition;
