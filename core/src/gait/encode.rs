//! Writing a gait file ([`encode`], [`encoded_len`]).

use crate::Error;
use crate::arc::{self, Arc};
use crate::gait::crc::crc32;
use crate::gait::layout::{
    ARCS_TAG, CK32_TAG, CK64_TAG, CRC_LEN, ENTRY_LEN, HEADER_LEN, MAGIC, PARAMS_TAG, SECTIONS,
    VERSION, params_len,
};
use crate::gait::schema::{CheckpointRecord, GaitParams};
use crate::gait::validate::check;
use crate::table::record_len;

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

    /// The `PARM` record of version 2 ([`params_len`]).
    fn params(&mut self, p: &GaitParams) -> Result<(), Error> {
        self.u32(p.steps as usize)?;
        self.u32(p.checkpoint_every as usize)?;
        self.f64s(&p.model.links)?;
        self.f64s(&[p.model.drag, p.model.ratio, p.h])?;
        self.f64s(&p.alpha0)?;
        self.f64s(&p.target)?;
        self.f64s(&p.mu)?;
        self.f64s(&p.xi0)?;
        self.f64s(&[p.alpha_max.unwrap_or(0.0)])
    }
}

/// The size of the gait file [`encode`] writes for `checkpoints` checkpoints and `arcs` arcs,
/// bytes.
pub const fn encoded_len(checkpoints: usize, arcs: usize) -> usize {
    HEADER_LEN
        + SECTIONS * ENTRY_LEN
        + params_len(VERSION)
        + arcs * arc::RECORD_LEN
        + checkpoints * (record_len(8) + record_len(4))
        + CRC_LEN
}

/// Writes the gait file (version [`VERSION`]) of `params`, `checkpoints` and `arcs` into the
/// front of `out` and returns its length ([`encoded_len`]). The `CK32` table holds each `CK64`
/// value rounded to nearest.
///
/// Errors: those of [`check`] (nothing is written then), [`Error::CapacityExceeded`] if `out`
/// is shorter than [`encoded_len`] or the file would exceed 4 GiB.
pub fn encode(
    params: &GaitParams,
    checkpoints: &[CheckpointRecord],
    arcs: &[Arc],
    out: &mut [u8],
) -> Result<usize, Error> {
    check(params, checkpoints.iter().copied(), arcs.iter().copied())?;
    let n = checkpoints.len();
    let len = encoded_len(n, arcs.len());
    let file = out.get_mut(..len).ok_or(Error::CapacityExceeded)?;
    let mut w = Out(&mut *file);
    w.put(&MAGIC)?;
    w.put(&VERSION.to_le_bytes())?;
    w.put(&(SECTIONS as u16).to_le_bytes())?;
    w.u32(len)?;
    let mut offset = HEADER_LEN + SECTIONS * ENTRY_LEN;
    for (tag, count, size) in [
        (PARAMS_TAG, 1, params_len(VERSION)),
        (ARCS_TAG, arcs.len(), arc::RECORD_LEN),
        (CK64_TAG, n, record_len(8)),
        (CK32_TAG, n, record_len(4)),
    ] {
        w.put(&tag)?;
        w.u32(offset)?;
        w.u32(count)?;
        w.u32(size)?;
        offset += count * size;
    }
    w.params(params)?;
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
    }
}
