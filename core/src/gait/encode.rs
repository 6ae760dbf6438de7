//! Writing a gait file ([`encode`], [`encoded_len`]).

use crate::arc::{self, Arc};
use crate::gait::crc::crc32;
use crate::gait::layout::{
    ARCS_TAG, CK32_TAG, CK64_TAG, CRC_LEN, ENTRY_LEN, HEADER_LEN, MAGIC, PARAMS_TAG, SECTIONS,
    TRACKING_TAG, VERSION, VERSION_COST, VERSION_END_SHAPE, VERSION_TRACKING, params_len,
};
use crate::gait::schema::{CheckpointRecord, GaitParams};
use crate::gait::track::{TRACKING_RECORD_LEN, check_tracking};
use crate::gait::validate::check;
use crate::table::record_len;
use crate::tracking::Record;
use crate::{Cost, Error};

/// Writes little-endian fields front to back; running out is [`Error::CapacityExceeded`].
struct Out<'a>(&'a mut [u8]);

impl Out<'_> {
    fn put(&mut self, bytes: &[u8]) -> Result<(), Error> {
        let buf = core::mem::take(&mut self.0);
        let (head, rest) = buf
            .split_at_mut_checked(bytes.len())
            .ok_or(Error::CapacityExceeded)?;
        head.copy_from_slice(bytes);
        self.0 = rest;
        Ok(())
    }
    fn u32(&mut self, x: usize) -> Result<(), Error> {
        let x = u32::try_from(x).map_err(|_| Error::CapacityExceeded)?;
        self.put(&x.to_le_bytes())
    }
    fn f64s(&mut self, xs: &[f64]) -> Result<(), Error> {
        xs.iter().try_for_each(|x| self.put(&x.to_le_bytes()))
    }

    /// The `PARM` record of `version` ([`params_len`]).
    fn params(&mut self, p: &GaitParams, version: u16) -> Result<(), Error> {
        self.u32(p.steps as usize)?;
        self.u32(p.checkpoint_every as usize)?;
        self.f64s(&p.model.links)?;
        self.f64s(&[p.model.drag, p.model.ratio, p.h])?;
        self.f64s(&p.alpha0)?;
        self.f64s(&p.target)?;
        self.f64s(&p.mu)?;
        self.f64s(&p.xi0)?;
        self.f64s(&[p.alpha_max.unwrap_or(0.0)])?;
        if version == VERSION_COST {
            self.u32(p.cost.code() as usize)?;
            self.u32(usize::from(p.alpha_end.is_some()))?;
            return self.f64s(&p.alpha_end.unwrap_or([0.0; 2]));
        }
        match p.alpha_end {
            Some(end) => self.f64s(&end),
            None => Ok(()),
        }
    }
}

/// The version [`encode_with_tracking`] writes for `params` with `tracking` records: 5 for a
/// gait of a cost other than the effort, 4 for one with an end shape of its own, else 2 (3 with
/// a tracking table).
const fn version_of(params: &GaitParams, tracking: usize) -> u16 {
    if !matches!(params.cost, Cost::Effort) {
        return VERSION_COST;
    }
    match (params.alpha_end.is_some(), tracking) {
        (true, _) => VERSION_END_SHAPE,
        (false, 0) => VERSION,
        (false, _) => VERSION_TRACKING,
    }
}

/// The size of a file of `version` with these record counts, bytes.
const fn file_len(version: u16, checkpoints: usize, arcs: usize, tracking: usize) -> usize {
    let track = if tracking == 0 {
        0
    } else {
        ENTRY_LEN + tracking * TRACKING_RECORD_LEN
    };
    HEADER_LEN
        + SECTIONS * ENTRY_LEN
        + params_len(version)
        + arcs * arc::RECORD_LEN
        + checkpoints * (record_len(8) + record_len(4))
        + track
        + CRC_LEN
}

/// The size of the gait file [`encode`] writes for `checkpoints` checkpoints and `arcs` arcs,
/// bytes.
pub const fn encoded_len(checkpoints: usize, arcs: usize) -> usize {
    encoded_len_with_tracking(checkpoints, arcs, 0)
}

/// The size of the gait file [`encode_with_tracking`] writes with `tracking` records of the
/// tracking table (0: none, a version-2 file) for a gait without an end shape of its own,
/// bytes.
pub const fn encoded_len_with_tracking(checkpoints: usize, arcs: usize, tracking: usize) -> usize {
    file_len(VERSION, checkpoints, arcs, tracking)
}

/// The size of the gait file [`encode_with_tracking`] writes for `params` (an end shape of its
/// own adds 16 bytes, [`VERSION_END_SHAPE`]), bytes.
pub const fn encoded_len_of(
    params: &GaitParams,
    checkpoints: usize,
    arcs: usize,
    tracking: usize,
) -> usize {
    file_len(version_of(params, tracking), checkpoints, arcs, tracking)
}

/// Writes the gait file (version [`VERSION`]; [`VERSION_END_SHAPE`] for a gait with an end
/// shape of its own) of `params`, `checkpoints` and `arcs` into the front of `out` and returns
/// its length ([`encoded_len_of`]). The `CK32` table holds each `CK64` value rounded to nearest.
///
/// Errors: those of [`check`] (nothing is written then), [`Error::CapacityExceeded`] if `out`
/// is shorter than [`encoded_len_of`] or the file would exceed 4 GiB.
pub fn encode(
    params: &GaitParams,
    checkpoints: &[CheckpointRecord],
    arcs: &[Arc],
    out: &mut [u8],
) -> Result<usize, Error> {
    encode_with_tracking(params, checkpoints, arcs, &[], out)
}

/// As [`encode`], with the tracking table `tracking` (`(k_j, record)`, docs/GAIT.md) in a
/// `TRCK` section: a version-[`VERSION_TRACKING`] file (version [`VERSION_END_SHAPE`] with an
/// end shape); none (empty) is [`encode`]'s file.
///
/// Errors: as [`encode`], and those of the table's check (nothing is written then) ([`Error::GaitLayout`]
/// for indices that do not start at 0, increase and stay below `N`; [`Error::NonFinite`]).
pub fn encode_with_tracking(
    params: &GaitParams,
    checkpoints: &[CheckpointRecord],
    arcs: &[Arc],
    tracking: &[(u32, Record<f32>)],
    out: &mut [u8],
) -> Result<usize, Error> {
    check(params, checkpoints.iter().copied(), arcs.iter().copied())?;
    if !tracking.is_empty() {
        check_tracking(tracking.iter().copied(), params.steps)?;
    }
    let n = checkpoints.len();
    let version = version_of(params, tracking.len());
    let len = encoded_len_of(params, n, arcs.len(), tracking.len());
    let file = out.get_mut(..len).ok_or(Error::CapacityExceeded)?;
    let sections = SECTIONS + usize::from(!tracking.is_empty());
    let mut w = Out(&mut *file);
    w.put(&MAGIC)?;
    w.put(&version.to_le_bytes())?;
    w.put(&(sections as u16).to_le_bytes())?;
    w.u32(len)?;
    let mut offset = HEADER_LEN + sections * ENTRY_LEN;
    let entries = [
        (PARAMS_TAG, 1, params_len(version)),
        (ARCS_TAG, arcs.len(), arc::RECORD_LEN),
        (CK64_TAG, n, record_len(8)),
        (CK32_TAG, n, record_len(4)),
        (TRACKING_TAG, tracking.len(), TRACKING_RECORD_LEN),
    ];
    for (tag, count, size) in entries.into_iter().take(sections) {
        w.put(&tag)?;
        w.u32(offset)?;
        w.u32(count)?;
        w.u32(size)?;
        offset += count * size;
    }
    w.params(params, version)?;
    for a in arcs {
        w.put(&a.to_bytes())?;
    }
    for c in checkpoints {
        w.u32(c.k as usize)?;
        w.u32(0)?;
        w.f64s(&c.values())?;
    }
    for c in checkpoints {
        w.u32(c.k as usize)?;
        for x in c.values() {
            w.put(&(x as f32).to_le_bytes())?;
        }
    }
    for (k, record) in tracking {
        w.u32(*k as usize)?;
        record.iter().try_for_each(|x| w.put(&x.to_le_bytes()))?;
    }
    let body = file.get(..len - CRC_LEN).ok_or(Error::CapacityExceeded)?;
    let crc = crc32(body);
    Out(file
        .get_mut(len - CRC_LEN..)
        .ok_or(Error::CapacityExceeded)?)
    .put(&crc.to_le_bytes())?;
    Ok(len)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn record_and_file_sizes() {
        assert_eq!((record_len(8), record_len(4)), (72, 36));
        assert_eq!(
            (params_len(1), params_len(2), arc::RECORD_LEN),
            (136, 144, 12)
        );
        assert_eq!(encoded_len(0, 0), 16 + 64 + 144 + 4);
        assert_eq!(encoded_len(99, 5), 228 + 99 * 108 + 5 * 12);
        assert_eq!(params_len(VERSION_END_SHAPE), 144 + 16);
    }
}
