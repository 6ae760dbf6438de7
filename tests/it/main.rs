//! The workspace-level tests of the core's properties (equivariance, isotropic drag, f32
//! precision), one module per subject, linked into one test binary (each binary costs a
//! compile and a link at opt-level 3).

mod equivariance;
mod isotropic;
mod precision;
