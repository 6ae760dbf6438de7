//! The checkpoints of a [`crate::Gait`] as [`CheckpointRecord`]s, read from its `f64` table.

use crate::gait::schema::CheckpointRecord;
use crate::table::Table;

/// The checkpoints of a [`crate::Gait`], in `f64`.
#[derive(Clone, Debug)]
pub struct Records<'a> {
    table: Table<'a>,
    left: usize,
}

impl<'a> Records<'a> {
    /// The first `count` records of an `f64` table.
    pub(super) fn new(table: Table<'a>, count: usize) -> Self {
        Records { table, left: count }
    }
}

impl Iterator for Records<'_> {
    type Item = CheckpointRecord;

    fn next(&mut self) -> Option<CheckpointRecord> {
        self.left = self.left.checked_sub(1)?;
        let (k, [a1, a2, x, y, c, s, x1, x2]) = self.table.pop_values::<f64>()?;
        Some(CheckpointRecord {
            k,
            alpha: [a1, a2],
            g: [x, y, c, s],
            xi: [x1, x2],
        })
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        (self.left, Some(self.left))
    }
}

impl ExactSizeIterator for Records<'_> {}
