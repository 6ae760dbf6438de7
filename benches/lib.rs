//! Benchmarks live in `step.rs` (the control-law step), `solve.rs` (the offline solver) and `limits.rs` (joint-limited solves against the paper's).
