//! Benchmarks live in `step.rs` (the control-law step) and `solve.rs` (the offline solver).
