//! The host's replay of a gait: the same `Gait::replay` and `Replay::fly` the firmware runs
//! (through `purcell_fly`), so equal digests prove that what flew is what was simulated.

use crate::error::HostError;
use purcell_core::cost::RunningCost;
use purcell_core::gait::Stored;
use purcell_core::{Error, Gait, Replay, TerminalError};

/// The host's flight of a gait in one precision.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    /// `"f32"` or `"f64"`.
    pub scalar: &'static str,
    /// The gait's CRC-32 (the firmware prints it in its header).
    pub gait_crc: u32,
    /// Steps replayed.
    pub steps: u32,
    /// Trajectory digest, with checkpoints (what the firmware flies).
    pub digest: u64,
    /// Final state bits in the replay's own type.
    pub final_bits: [u64; 6],
    /// `(α1, α2, x, y, θ)` at the end.
    pub end: [f64; 5],
    /// Terminal error with checkpoints.
    pub error: TerminalError,
    /// Terminal error of the same replay without checkpoints, or the error that stopped it.
    pub error_without_checkpoints: Result<TerminalError, Error>,
}

impl Reference {
    /// Flies `gait` on the host in `T`, with the law of its cost.
    pub fn compute<T: Stored>(gait: &Gait<'_>, scalar: &'static str) -> Result<Self, HostError> {
        purcell_core::with_cost!(gait.params().cost, C => Self::compute_for::<T, C>(gait, scalar))
    }

    /// [`Reference::compute`] with the law of `C`, the gait's cost.
    fn compute_for<T: Stored, C: RunningCost>(
        gait: &Gait<'_>,
        scalar: &'static str,
    ) -> Result<Self, HostError> {
        let with = gait.replay_for::<T, C>(true)?.fly(Replay::step)?;
        // Without checkpoints an f32 replay may leave the admissible set: report, don't fail.
        let without = gait
            .replay_for::<T, C>(false)
            .and_then(|r| r.fly(Replay::step));
        let (a, g) = (&with.end.alpha, &with.end.g);
        Ok(Reference {
            scalar,
            gait_crc: gait.crc(),
            steps: with.steps,
            digest: with.digest.value(),
            final_bits: with.final_bits(),
            end: [a.x, a.y, g.x(), g.y(), g.theta()].map(|x| x.to_f64()),
            error: gait.params().terminal_error(&with.end),
            error_without_checkpoints: without.map(|f| gait.params().terminal_error(&f.end)),
        })
    }

    /// The precision named in a firmware log.
    pub fn for_scalar(gait: &Gait<'_>, name: &str) -> Result<Self, HostError> {
        match name {
            "f32" => Self::compute::<f32>(gait, "f32"),
            "f64" => Self::compute::<f64>(gait, "f64"),
            other => Err(HostError::Log(format!("unknown scalar `{other}`"))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper() -> Gait<'static> {
        Gait::from_bytes(include_bytes!("../../../core/examples/paper.gait")).unwrap()
    }

    #[test]
    fn replays_with_checkpoints_end_at_the_target() {
        // The paper's gait is a solution: the f64 replay ends at (ᾱ, ḡ) to the solver's
        // residual, and the f32 replay, reset to the f64 state every checkpoint interval,
        // stays close to it; without checkpoints it does not.
        let gait = paper();
        let r64 = Reference::for_scalar(&gait, "f64").unwrap();
        assert!(
            r64.error.g < 1e-9 && r64.error.alpha < 1e-9,
            "{:?}",
            r64.error
        );
        let r32 = Reference::for_scalar(&gait, "f32").unwrap();
        assert!(
            r32.error.g < 1e-6 && r32.error.alpha < 1e-6,
            "{:?}",
            r32.error
        );
        let without = r32.error_without_checkpoints.unwrap();
        assert!(without.alpha > 1e3 * r32.error.alpha, "{without:?}");
        assert_ne!(r32.end, r64.end);
        assert_eq!((r32.steps, r64.steps), (10_000, 10_000));
        // In f64 the law alone also lands on the target (the checkpoints, the converged
        // trajectory's states, only take off its rounding drift).
        let without64 = r64.error_without_checkpoints.unwrap();
        assert!(
            without64.g < 1e-9 && without64.alpha < 1e-9,
            "{without64:?}"
        );
        assert!(Reference::for_scalar(&gait, "f16").is_err());
    }
}
