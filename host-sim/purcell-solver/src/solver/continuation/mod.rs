//! Solving from a known extremal: a stored one (`solve --from`) or a neighbour's in a sweep of
//! targets (`sweep`).
//!
//! An extremal of one problem is a start for a nearby one: its shape path, carried to the new
//! grid (and horizon: `α(t/T)` kept, so controls scale by `T_old/T_new`), with its terminal
//! multiplier. [`continue_to`] first tries Newton on the target itself; if that fails, it
//! walks the target from the old one to the new one in steps that halve on failure and grow
//! on success (natural-parameter continuation), on a medium grid, then refines. Every point
//! it accepts is admissible (`|α_i| < π`, or within the joint limit): a branch that would
//! leave the admissible shapes stops there, and [`solve_from`] falls back to the global
//! search.
//!
//! [`warm`] holds the warm starts (`solve --from`: [`Warm`], [`continue_to`], [`solve_from`]),
//! [`atlas`] the sweeps of targets ([`sweep`], [`Atlas`]).

pub mod atlas;
pub mod warm;

pub use atlas::{Atlas, KEEP, Lattice, SweepPoint, refine_target, search_target, sweep};
pub use warm::{Warm, continue_to, solve_from};
