//! How the control law converges at each step: after its first iterate, a fixed number of
//! passes of one kind, chosen per scalar type ([`crate::Real::PASSES`]; [`crate::law`] derives
//! both kinds).

/// The kind of the passes that follow the first iterate (see [`crate::law`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PassKind {
    /// Fixed-point passes: `ζ` at the last `u`, then the 2×2 solve again.
    Plain,
    /// Newton passes `u ← u − J(u)⁻¹R(u)`.
    Newton,
}

/// How many passes of which kind the law runs after its first iterate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Passes {
    /// Their kind.
    pub kind: PassKind,
    /// Their number (0: the first iterate is the step's `u_k`).
    pub count: usize,
}

impl Passes {
    /// `count` plain fixed-point passes.
    pub const fn plain(count: usize) -> Self {
        Passes {
            kind: PassKind::Plain,
            count,
        }
    }

    /// `count` Newton passes.
    pub const fn newton(count: usize) -> Self {
        Passes {
            kind: PassKind::Newton,
            count,
        }
    }
}
