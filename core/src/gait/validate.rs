//! The one validation of a gait ([`check`]), for the binary file and the JSON costate file
//! alike.

use crate::Error;
use crate::arc::{self, Arc, Exits};
use crate::gait::schema::{CheckpointRecord, GaitParams};

/// How far (radians) a stored state may lie past the joint limit, and the state at an arc's
/// exit from it: the solver puts arc states on the limit to rounding (`1e-13` relative).
pub const LIMIT_TOLERANCE: f64 = 1e-9;

/// The one validation of a gait, for the binary file and the JSON costate file alike, in
/// this order: [`GaitParams::check`]; the arcs ([`crate::arc::check`]: [`Error::ArcInvalid`],
/// [`Error::ArcOrder`]; [`Error::JointLimit`] for arcs without an `α_max`); then the
/// checkpoints in order: [`Error::CheckpointSpacing`] unless they sit exactly at
/// `k = M, 2M, …` below `N` (`M` = `checkpoint_every`; none for `M = 0`) and at every arc's
/// `last`, nowhere else ([`Error::ArcCheckpoint`] for an arc's `last` without one),
/// [`CheckpointRecord::check`] for each, [`Error::ArcOffLimit`] unless the arc's joint lies on
/// `sign·α_max` at its exit's checkpoint, and [`Error::JointLimit`] for a checkpoint past the
/// limit (each to [`LIMIT_TOLERANCE`]). A checkpoint at `k = 0` would silently replace the
/// start `(ᾱ, e, ξ^{−1})`.
pub fn check<A>(
    params: &GaitParams,
    checkpoints: impl IntoIterator<Item = CheckpointRecord>,
    arcs: A,
) -> Result<(), Error>
where
    A: IntoIterator<Item = Arc>,
    A::IntoIter: Clone,
{
    params.check()?;
    let arcs = arcs.into_iter();
    arc::check(arcs.clone(), params.steps)?;
    let limit = match params.alpha_max {
        Some(limit) => limit,
        None if arcs.clone().next().is_some() => return Err(Error::JointLimit),
        None => f64::INFINITY,
    };
    let (every, steps) = (u64::from(params.checkpoint_every), u64::from(params.steps));
    // The next multiple of M due (at or past N: none left).
    let mut due = if every == 0 { steps } else { every };
    let mut exits = Exits::new(arcs);
    for c in checkpoints {
        let k = u64::from(c.k);
        if due < k.min(steps) {
            return Err(Error::CheckpointSpacing);
        }
        let periodic = k == due && k < steps;
        let exiting = exits.at(c.k)?;
        if !periodic && exiting == [None; 2] {
            return Err(Error::CheckpointSpacing);
        }
        if periodic {
            due += every;
        }
        c.check()?;
        for a in exiting.into_iter().flatten() {
            let alpha = c.alpha.get(a.index()).copied().unwrap_or(f64::NAN);
            // `alpha` is finite (checked above), and so is `limit` with arcs.
            if (f64::from(a.sign) * alpha - limit).abs() > LIMIT_TOLERANCE {
                return Err(Error::ArcOffLimit);
            }
        }
        if c.alpha.iter().any(|a| a.abs() > limit + LIMIT_TOLERANCE) {
            return Err(Error::JointLimit);
        }
    }
    exits.finish()?;
    if due < steps {
        return Err(Error::CheckpointSpacing);
    }
    Ok(())
}
