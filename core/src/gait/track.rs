//! The tracking table of a gait file (section `TRCK`, version 3, docs/GAIT.md), read in place:
//! record `j` is the step `k_j` from which it holds (`u32`) and the 18 `f32` of a
//! [`crate::tracking::Record`] (`K`, `κ`, `ψ`, `β`), little-endian. `k_0 = 0`, the `k_j`
//! increase and stay below `N`; record `j` holds for the steps `k_j … k_{j+1} − 1` (the last
//! one up to `N − 1`), and the tracking law updates its estimate at each `k_j`.

use crate::Error;
use crate::tracking::{RECORD_VALUES, Record};

/// Bytes of one `TRCK` record: `k` and 18 `f32`.
pub const TRACKING_RECORD_LEN: usize = 4 + 4 * RECORD_VALUES;

/// A gait's tracking table, read in place (whole records, checked by the gait's reader).
#[derive(Clone, Copy, Debug)]
pub struct TrackingTable<'a> {
    records: &'a [u8],
}

impl<'a> TrackingTable<'a> {
    pub(super) fn new(records: &'a [u8]) -> Self {
        TrackingTable { records }
    }

    /// Number of records.
    pub fn len(&self) -> usize {
        self.records.len() / TRACKING_RECORD_LEN
    }

    /// Whether there are none (never, for a table a gait holds).
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// The bytes of record `j`.
    #[inline]
    fn record(&self, j: usize) -> Option<&'a [u8]> {
        let at = j.checked_mul(TRACKING_RECORD_LEN)?;
        self.records.get(at..at.checked_add(TRACKING_RECORD_LEN)?)
    }

    /// The step `k_j` from which record `j` holds.
    #[inline]
    fn start(&self, j: usize) -> Option<u32> {
        self.record(j)?
            .first_chunk()
            .map(|k| u32::from_le_bytes(*k))
    }

    /// The values of record `j`.
    #[inline]
    fn values(&self, j: usize) -> Option<Record<f32>> {
        let mut out = [0f32; RECORD_VALUES];
        let bytes = self.record(j)?.get(4..)?;
        for (v, b) in out.iter_mut().zip(bytes.chunks_exact(4)) {
            *v = f32::from_le_bytes(b.first_chunk().copied()?);
        }
        Some(out)
    }

    /// Record `j`: `(k_j, values)`.
    pub fn get(&self, j: usize) -> Option<(u32, Record<f32>)> {
        Some((self.start(j)?, self.values(j)?))
    }

    /// The records in order.
    pub fn iter(&self) -> impl Iterator<Item = (u32, Record<f32>)> + 'a {
        let table = *self;
        (0..self.len()).map_while(move |j| table.get(j))
    }

    /// A cursor that walks the steps `0, 1, …` ([`TrackingCursor::at`]).
    pub fn cursor(&self) -> TrackingCursor<'a> {
        TrackingCursor {
            table: *self,
            next: 0,
            current: [0.0; RECORD_VALUES],
        }
    }
}

/// The one check of a tracking table's records, in order: `Ok` if `k_0 = 0`, the `k_j`
/// increase and stay below `steps`, and every value is finite. Errors: [`Error::GaitLayout`]
/// (the indices, or no record), [`Error::NonFinite`].
pub(super) fn check_tracking(
    records: impl IntoIterator<Item = (u32, Record<f32>)>,
    steps: u32,
) -> Result<(), Error> {
    let mut previous = None;
    for (k, values) in records {
        let ordered = previous.map_or(k == 0, |p| k > p);
        if !ordered || k >= steps {
            return Err(Error::GaitLayout);
        }
        if !values.iter().all(|v| v.is_finite()) {
            return Err(Error::NonFinite);
        }
        previous = Some(k);
    }
    match previous {
        Some(_) => Ok(()),
        None => Err(Error::GaitLayout),
    }
}

/// Walks a [`TrackingTable`] step by step with integer loads only.
#[derive(Clone, Debug)]
pub struct TrackingCursor<'a> {
    table: TrackingTable<'a>,
    next: usize,
    current: Record<f32>,
}

impl TrackingCursor<'_> {
    /// The record of step `k` and whether `k` is its first step; called with `k = 0, 1, …`
    /// (the record in force is kept: a step between two records reads nothing).
    #[inline]
    pub fn at(&mut self, k: u32) -> (&Record<f32>, bool) {
        let first = self.table.start(self.next) == Some(k);
        if first {
            if let Some(values) = self.table.values(self.next) {
                self.current = values;
            }
            self.next += 1;
        }
        (&self.current, first)
    }
}
