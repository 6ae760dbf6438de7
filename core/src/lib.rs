#![no_std]
#![doc = include_str!("../README.md")]
#![deny(missing_docs)]
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]
#![cfg_attr(
    test,
    allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)
)]

pub mod arc;
pub mod cost;
pub mod digest;
pub mod error;
pub mod gait;
pub mod kinematics;
pub mod law;
pub mod passes;
pub mod real;
pub mod replay;
pub mod sample;
pub mod se2;
pub mod swimmer;
mod table;
#[cfg(feature = "test-kit")]
pub mod testkit;
pub mod tracking;

pub use arc::Arc;
pub use cost::Cost;
pub use digest::TrajectoryDigest;
pub use error::Error;
pub use gait::Gait;
pub use kinematics::{Kinematics, State};
pub use law::{LawStep, OnArcs};
pub use passes::{PassKind, Passes};
pub use real::Real;
pub use replay::{Checkpoint, Checkpoints, Costate, Flight, Replay, TerminalError};
pub use sample::Sample;
pub use se2::{Se2, Tangent};
pub use swimmer::{Connection, Swimmer};

/// The linear-algebra crate of every signature here (`Vector2`, `Vector3`, `Matrix3x2`, …), so
/// that a user's `nalgebra` types are the core's without pinning the same version.
pub use nalgebra;

/// With the `defmt` feature, every public value type can be logged (checked at compile time).
#[cfg(feature = "defmt")]
const _: () = {
    const fn loggable<T: defmt::Format>() {}
    loggable::<Error>();
    loggable::<State<f32>>();
    loggable::<Se2<f32>>();
    loggable::<Swimmer<f32>>();
    loggable::<LawStep<f32>>();
    loggable::<Arc>();
    loggable::<OnArcs>();
    loggable::<Cost>();
    loggable::<Costate<f32>>();
    loggable::<Checkpoint<f32>>();
    loggable::<Sample<f32>>();
    loggable::<TrajectoryDigest>();
    loggable::<Flight<f32>>();
    loggable::<TerminalError>();
    loggable::<State<f64>>();
};
