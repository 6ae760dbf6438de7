//! A gait file's checkpoint table (its `CK64` or `CK32` section, see [`crate::gait`]), read
//! front to back in place: what a [`crate::Gait`] validates and a [`crate::Replay`] restores
//! its checkpoints from, without copying the table.
//!
//! A record of values `w` bytes wide (`w = 8` for `f64`, 4 for `f32`) is the step index `k`
//! (`u32`, then zero padding to `w` bytes) and the [`VALUES`] values
//! `α1 α2 x y cos θ sin θ ξ1 ξ2`, all little-endian: [`record_len`]`(w)` bytes.

use crate::Real;
use core::mem::size_of;

/// Numbers in a checkpoint: `α1 α2 x y cos θ sin θ ξ1 ξ2`.
pub(crate) const VALUES: usize = 8;

/// A checkpoint record of values `width` bytes wide: `k` in a field of that width (`u32`,
/// then zero padding in `f64` records), then the values.
pub(crate) const fn record_len(width: usize) -> usize {
    width * (1 + VALUES)
}

/// A stored checkpoint table of one precision, read front to back in place.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Table<'a> {
    records: &'a [u8],
}

impl<'a> Table<'a> {
    /// The table whose records are `records` (whole records, checked by the gait's reader).
    pub(crate) fn new(records: &'a [u8]) -> Self {
        Table { records }
    }

    /// The step index of the first record.
    #[inline]
    pub(crate) fn next_k(&self) -> Option<u32> {
        self.records.first_chunk().map(|b| u32::from_le_bytes(*b))
    }

    /// The padding after the first record's `k` in an `f64` table (zero in a valid file).
    pub(crate) fn next_padding(&self) -> Option<&'a [u8]> {
        self.records.get(4..8)
    }

    /// Removes the first record: its step index and values. `T` must be the table's scalar
    /// (`f32` for `CK32`, `f64` for `CK64`): records are `record_len(size_of::<T>())` bytes.
    #[inline]
    pub(crate) fn pop_values<T: Real>(&mut self) -> Option<(u32, [T; VALUES])> {
        let width = size_of::<T>();
        let (record, rest) = self.records.split_at_checked(record_len(width))?;
        self.records = rest;
        let k = u32::from_le_bytes(*record.first_chunk()?);
        let mut values = [T::zero(); VALUES];
        for (v, bytes) in values
            .iter_mut()
            .zip(record.get(width..)?.chunks_exact(width))
        {
            let mut bits = [0u8; 8];
            bits.get_mut(..width)?.copy_from_slice(bytes);
            *v = T::from_bits(u64::from_le_bytes(bits));
        }
        Some((k, values))
    }
}
