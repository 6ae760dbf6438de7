//! What long work reports as it goes: its phases, each counted in ticks, and points at which
//! it may be cancelled.

/// A sink for the progress of [`super::solve`], [`super::continuation::sweep`] and the
/// callers' own phases. Any method may unwind to cancel the work (the Python package's
/// Ctrl-C does).
pub trait Progress: Sync {
    /// Phase `name` begins, at most `total` ticks of `unit` long (it may end sooner).
    fn phase(&self, name: &str, total: usize, unit: &str);
    /// One tick of the current phase done.
    fn tick(&self);
    /// A point at which the work may be cancelled, nothing counted (called at least once a
    /// Newton iteration in the refinement).
    fn pulse(&self) {}
}

/// A plain closure counts ticks only.
impl<F: Fn() + Sync> Progress for F {
    fn phase(&self, _: &str, _: usize, _: &str) {}

    fn tick(&self) {
        self()
    }
}

/// The work of one tick of `0`, inside it: its ticks are `0`'s pulses, its phases none.
pub struct Within<'a>(pub &'a dyn Progress);

impl Progress for Within<'_> {
    fn phase(&self, _: &str, _: usize, _: &str) {}

    fn tick(&self) {
        self.0.pulse()
    }

    fn pulse(&self) {
        self.0.pulse()
    }
}
