#![no_std]
#![doc = include_str!("../README.md")]
#![deny(missing_docs)]
#![deny(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::indexing_slicing)]
#![cfg_attr(test, allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing))]

pub mod error;
pub mod real;
pub mod swimmer;

pub use error::Error;
pub use real::Real;
pub use swimmer::{Connection, Swimmer};
pub mod kinematics;
pub mod law;
pub mod se2;

pub use kinematics::{Kinematics, State};
pub use law::LawStep;
pub use se2::{Se2, Tangent};
pub mod replay;
pub use replay::{Checkpoint, Checkpoints, Costate, Replay, Sample};
