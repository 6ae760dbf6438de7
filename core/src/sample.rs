//! What a replay lends at each step ([`Sample`]), what a trajectory's digest and a firmware's
//! log are made of.

use crate::kinematics::State;
use nalgebra::Vector2;

/// One replayed step.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sample<T> {
    /// Step index `k`.
    pub k: u32,
    /// `(α_k, g_k)`.
    pub state: State<T>,
    /// `u_k`.
    pub u: Vector2<T>,
    /// `ξ^k`.
    pub xi: Vector2<T>,
}
