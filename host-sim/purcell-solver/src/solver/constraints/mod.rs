//! The constraints of the direct method, one module each, apart from the cost
//! ([`super::cost`]) and the dynamics ([`super::stage`]), as acados keeps its constraint
//! modules:
//!
//! - [`terminal`]: the equality `s_N = s̄`, whose multiplier is the terminal costate;
//! - [`joint_limit`]: the inequality `|α_{k,i}| ≤ α_max` on the inner states, as a barrier
//!   in the objective or imposed on arcs.
//!
//! Each says what it does to a rollout (a state outside the barrier's domain fails it), to
//! the objective and its slope (the line search), to the derivatives along a rollout (the
//! costates, the stage Hessians, the controls it ties) and to the step (how far the line
//! search may go). The links' overlap `|α_i| < π` is no constraint of the direct method: the
//! angles wrap ([`super::stage::wrap`]) and whether an extremal is admissible is decided
//! afterwards ([`crate::problem::Problem::admits`]).

pub mod joint_limit;
pub mod terminal;
