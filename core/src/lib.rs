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

pub mod digest;
pub mod error;
pub mod kinematics;
pub mod law;
pub mod real;
pub mod replay;
pub mod se2;
pub mod swimmer;

pub use digest::TrajectoryDigest;
pub use error::Error;
pub use kinematics::{Kinematics, State};
pub use law::{LawStep, PassKind, Passes};
pub use real::Real;
pub use replay::{Checkpoint, Checkpoints, Costate, Replay, Sample};
pub use se2::{Se2, Tangent};
pub use swimmer::{Connection, Swimmer};

/// With the `defmt` feature, every public value type can be logged (checked at compile time).
#[cfg(feature = "defmt")]
const _: () = {
    const fn loggable<T: defmt::Format>() {}
    loggable::<Error>();
    loggable::<State<f32>>();
    loggable::<Se2<f32>>();
    loggable::<Swimmer<f32>>();
    loggable::<LawStep<f32>>();
    loggable::<Costate<f32>>();
    loggable::<Checkpoint<f32>>();
    loggable::<Sample<f32>>();
    loggable::<TrajectoryDigest>();
    loggable::<State<f64>>();
};
