//! The binary gait file: one solved gait, embedded in firmware with `include_bytes!` and read
//! in place by [`Gait::from_bytes`], without a heap and without copying its checkpoint table.
//!
//! A gait is a [`GaitParams`] (model, `h`, `N`, `ᾱ`, `ḡ`, `μ`, `ξ^{−1}`, the joint limit
//! `α_max` if any), a table of [`CheckpointRecord`]s `(k, α_k, g_k, ξ^{k−1})` of the solution,
//! and, for a gait that rests on its joint limit, a table of [`Arc`]s (see [`crate::arc`]).
//! The byte layout (version [`VERSION`]; version 1, without arcs, is still read) is specified in
//! the repository's `docs/GAIT.md`: a 16-byte header (magic `PURCGAIT`, version, section count,
//! length), a directory of sections (tag, offset, record count, record size), the sections,
//! and a CRC-32 of all that. Version 2 has four sections: `PARM` (the parameters), `ARCS` (the
//! arcs), `CK64` (the checkpoints in `f64`) and `CK32` (the same checkpoints rounded to `f32`,
//! so that an `f32` replay restores a checkpoint with integer loads: no `f64` arithmetic, which
//! is soft-float on a Cortex-M4F).
//!
//! [`GaitParams`], [`CheckpointRecord`] and [`Arc`] are also the schema of purcell-sim's JSON
//! costate file (with the `serde` feature), and [`check`] is the one validation both formats go
//! through.
//!
//! ```
//! use purcell_core::gait::{self, CheckpointRecord, Gait, GaitParams, Model};
//!
//! // A gait as the offline solver would describe it (here: 100 steps, no checkpoint).
//! let params = GaitParams {
//!     model: Model { links: [1.0; 3], drag: 1.0, ratio: 2.0 },
//!     h: 0.01,
//!     steps: 100,
//!     alpha0: [0.0, 0.0],
//!     target: [0.0, 0.0, 0.0],
//!     mu: [0.1, 0.2, 0.0],
//!     xi0: [0.3, -0.1],
//!     checkpoint_every: 0,
//!     alpha_max: None,
//! };
//! let mut bytes = [0u8; gait::encoded_len(0, 0)];
//! gait::encode(&params, &[], &[], &mut bytes)?;
//!
//! // What a firmware does with `include_bytes!("gait.bin")`:
//! let gait = Gait::from_bytes(&bytes)?;
//! let end = gait.replay::<f32>()?.finish()?;
//! let error = gait.params().terminal_error(&end);
//! assert!(error.alpha.is_finite() && error.g.is_finite());
//!
//! // A flipped bit is refused.
//! bytes[100] ^= 1;
//! assert_eq!(Gait::from_bytes(&bytes).err(), Some(purcell_core::Error::GaitChecksum));
//! # Ok::<(), purcell_core::Error>(())
//! ```

pub use crate::arc::Arc;
use crate::arc::{self, ArcTable, Exits};
use crate::kinematics::{Kinematics, State};
use crate::replay::{Checkpoint, CheckpointTable, Costate, Replay, TerminalError};
use crate::swimmer::check_shape;
use crate::table::{Table, VALUES, record_len};
use crate::{Error, Real, Se2, Swimmer};
use core::mem::size_of;
use nalgebra::{Vector2, Vector3};

/// The first 8 bytes of every gait file.
pub const MAGIC: [u8; 8] = *b"PURCGAIT";
/// The version this build writes; it reads this one and version 1 (no joint limit, no arcs).
pub const VERSION: u16 = 2;

/// Header: magic (8), version (u16), section count (u16), file length (u32).
const HEADER_LEN: usize = 16;
/// Directory entry: tag (4 ASCII bytes), offset, record count, record size (u32 each).
const ENTRY_LEN: usize = 16;
/// The CRC-32 at the end.
const CRC_LEN: usize = 4;
const PARAMS_TAG: [u8; 4] = *b"PARM";
const ARCS_TAG: [u8; 4] = *b"ARCS";
const CK64_TAG: [u8; 4] = *b"CK64";
const CK32_TAG: [u8; 4] = *b"CK32";
/// Sections of a version-2 file, in the order [`encode`] writes them.
const SECTIONS: usize = 4;
/// `steps`, `checkpoint_every` (u32), then 16 `f64` (see [`Cursor::params`]), then in
/// version 2 `α_max` (`f64`, 0 for none).
const fn params_len(version: u16) -> usize {
    8 + 16 * 8 + if version == 1 { 0 } else { 8 }
}
/// How far `cos² θ + sin² θ` of a stored rotation may be from 1.
const UNIT_TOLERANCE: f64 = 1e-9;
/// How far (radians) a stored state may lie past the joint limit, and the state at an arc's
/// exit from it: the solver puts arc states on the limit to rounding (`1e-13` relative).
pub const LIMIT_TOLERANCE: f64 = 1e-9;

/// The swimmer's geometry and drag as stored (see [`Swimmer::new`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct Model {
    /// `(L0 middle, L1 front, L2 rear)`, metres.
    pub links: [f64; 3],
    /// Drag coefficient `k`.
    pub drag: f64,
    /// Drag ratio `r` (normal over tangential).
    pub ratio: f64,
}

/// Everything a gait holds besides its checkpoints, in `f64` as stored.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct GaitParams {
    /// The swimmer.
    pub model: Model,
    /// Time step `h`, seconds.
    pub h: f64,
    /// Number of steps `N`.
    pub steps: u32,
    /// Start and end shape `ᾱ`, radians.
    pub alpha0: [f64; 2],
    /// Target position `ḡ = (x, y, θ)`, reached from the identity.
    pub target: [f64; 3],
    /// Spatial momentum `μ`.
    pub mu: [f64; 3],
    /// Shape costate before the first step, `ξ^{−1}`.
    pub xi0: [f64; 2],
    /// Spacing of the periodic checkpoints in steps (0: none): there is one at every
    /// multiple of it below `N`, besides those at the arcs' exits ([`check`]).
    pub checkpoint_every: u32,
    /// The joint limit `|α_i| ≤ α_max` the gait was solved under, radians (`None`: only the
    /// links' overlap, `|α_i| < π`); required by arcs, which rest on it.
    pub alpha_max: Option<f64>,
}

/// One checkpoint `(k, α_k, g_k, ξ^{k−1})` as stored, `g` as `(x, y, cos θ, sin θ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct CheckpointRecord {
    /// Step index `k`.
    pub k: u32,
    /// `α_k`, radians.
    pub alpha: [f64; 2],
    /// `g_k` as `(x, y, cos θ, sin θ)`, the core's own representation.
    pub g: [f64; 4],
    /// `ξ^{k−1}`.
    pub xi: [f64; 2],
}

fn all_finite<const N: usize>(xs: [f64; N]) -> Result<(), Error> {
    if f64::all_finite(xs) {
        Ok(())
    } else {
        Err(Error::NonFinite)
    }
}

impl GaitParams {
    /// `Ok` if a replay can start from these numbers. Errors: [`Error::NonFinite`] (any
    /// number), [`Error::InvalidParameters`] (model), [`Error::InvalidStep`] (`h ≤ 0` or
    /// `N = 0`), [`Error::ShapeLimit`] (`ᾱ`), [`Error::JointLimit`] (an `α_max` outside
    /// `]max |ᾱ_i|, π[`).
    pub fn check(&self) -> Result<(), Error> {
        let ([l0, l1, l2], [a1, a2], [tx, ty, tt]) = (self.model.links, self.alpha0, self.target);
        let ([m1, m2, m3], [x1, x2]) = (self.mu, self.xi0);
        all_finite([l0, l1, l2, self.model.drag, self.model.ratio, self.h])?;
        all_finite([a1, a2, tx, ty, tt, m1, m2, m3, x1, x2])?;
        self.kinematics::<f64>()?;
        if self.steps == 0 {
            return Err(Error::InvalidStep);
        }
        check_shape(&Vector2::new(a1, a2))?;
        match self.alpha_max {
            Some(limit) => {
                let pi = core::f64::consts::PI;
                let inside = limit.is_finite() && limit > a1.abs().max(a2.abs()) && limit < pi;
                if inside {
                    Ok(())
                } else {
                    Err(Error::JointLimit)
                }
            }
            None => Ok(()),
        }
    }

    /// The swimmer and time step in `T` (each number rounded to nearest).
    ///
    /// Errors: [`Error::InvalidParameters`], [`Error::InvalidStep`].
    pub fn kinematics<T: Real>(&self) -> Result<Kinematics<T>, Error> {
        let m = &self.model;
        let c = T::from_f64;
        Kinematics::new(
            Swimmer::new(m.links.map(c), c(m.drag), c(m.ratio))?,
            c(self.h),
        )
    }

    /// The start `(ᾱ, e)` in `T`.
    pub fn start<T: Real>(&self) -> State<T> {
        State::at_origin(Vector2::new(
            T::from_f64(self.alpha0[0]),
            T::from_f64(self.alpha0[1]),
        ))
    }

    /// The initial costate `(μ, ξ^{−1})` in `T`.
    pub fn costate<T: Real>(&self) -> Costate<T> {
        let ([m1, m2, m3], [x1, x2]) = (self.mu.map(T::from_f64), self.xi0.map(T::from_f64));
        Costate {
            mu: Vector3::new(m1, m2, m3),
            xi: Vector2::new(x1, x2),
        }
    }

    /// The target `ḡ`.
    pub fn target(&self) -> Se2<f64> {
        let [x, y, theta] = self.target;
        Se2::new(x, y, theta)
    }

    /// How far `end` lands from `(ᾱ, ḡ)` ([`TerminalError`]).
    pub fn terminal_error<T: Real>(&self, end: &State<T>) -> TerminalError {
        TerminalError::new(end, &Vector2::from(self.alpha0), &self.target())
    }
}

impl CheckpointRecord {
    /// `Ok` if the checkpoint can be restored. Errors: [`Error::NonFinite`],
    /// [`Error::ShapeLimit`] (`α_k`), [`Error::NotRotation`] (`|cos² θ + sin² θ − 1| > 1e-9`).
    pub fn check(&self) -> Result<(), Error> {
        let ([a1, a2], [x, y, c, s], [x1, x2]) = (self.alpha, self.g, self.xi);
        all_finite([a1, a2, x, y, c, s, x1, x2])?;
        check_shape(&Vector2::new(a1, a2))?;
        if (c * c + s * s - 1.0).abs() > UNIT_TOLERANCE {
            return Err(Error::NotRotation);
        }
        Ok(())
    }

    /// The checkpoint in `T` (each number rounded to nearest; `g` as stored, not
    /// renormalised).
    pub fn to_checkpoint<T: Real>(&self) -> Checkpoint<T> {
        Checkpoint::from_values(self.k, self.values().map(T::from_f64))
    }

    fn values(&self) -> [f64; VALUES] {
        let ([a1, a2], [x, y, c, s], [x1, x2]) = (self.alpha, self.g, self.xi);
        [a1, a2, x, y, c, s, x1, x2]
    }
}

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

/// The scalars a gait stores a checkpoint table in: `f32` (section `CK32`) and `f64`
/// (`CK64`). Sealed.
pub trait Stored: Real + sealed::Sealed {}
impl Stored for f32 {}
impl Stored for f64 {}

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// A gait file, validated, read in place.
#[derive(Clone, Copy, Debug)]
pub struct Gait<'a> {
    params: GaitParams,
    count: usize,
    table64: Table<'a>,
    table32: Table<'a>,
    /// The `ARCS` records (empty in version 1).
    arcs: &'a [u8],
    crc: u32,
}

/// Reads the little-endian fields of a byte slice front to back; running out is
/// [`Error::GaitLayout`].
struct Cursor<'a>(&'a [u8]);

impl<'a> Cursor<'a> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], Error> {
        let (head, rest) = self.0.split_first_chunk().ok_or(Error::GaitLayout)?;
        self.0 = rest;
        Ok(*head)
    }
    fn u16(&mut self) -> Result<u16, Error> {
        self.take().map(u16::from_le_bytes)
    }
    fn u32(&mut self) -> Result<u32, Error> {
        self.take().map(u32::from_le_bytes)
    }
    fn usize(&mut self) -> Result<usize, Error> {
        usize::try_from(self.u32()?).map_err(|_| Error::GaitLayout)
    }
    fn f64s<const N: usize>(&mut self) -> Result<[f64; N], Error> {
        let mut out = [0.0; N];
        for x in &mut out {
            *x = f64::from_le_bytes(self.take()?);
        }
        Ok(out)
    }

    /// The `PARM` record of a file of `version` (field order of [`Out::params`]).
    fn params(&mut self, version: u16) -> Result<GaitParams, Error> {
        let (steps, checkpoint_every) = (self.u32()?, self.u32()?);
        let links = self.f64s()?;
        let [drag, ratio, h] = self.f64s()?;
        let (alpha0, target, mu, xi0) = (self.f64s()?, self.f64s()?, self.f64s()?, self.f64s()?);
        let alpha_max = match version {
            1 => None,
            _ => Some(f64::from_le_bytes(self.take()?)).filter(|&a| a != 0.0),
        };
        Ok(GaitParams {
            model: Model { links, drag, ratio },
            h,
            steps,
            alpha0,
            target,
            mu,
            xi0,
            checkpoint_every,
            alpha_max,
        })
    }
}

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

    /// The `PARM` record of version 2: `steps`, `checkpoint_every`, then `L0 L1 L2 k r h`, `ᾱ`,
    /// `ḡ`, `μ`, `ξ^{−1}`, `α_max` (17 `f64`; `α_max = 0` for none).
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

impl<'a> Gait<'a> {
    /// Reads and validates a gait file in place (the checkpoint tables stay in `bytes`).
    ///
    /// ```
    /// use purcell_core::{Gait, Replay};
    ///
    /// // In firmware: `static GAIT: &[u8] = include_bytes!("gait.bin");`
    /// static GAIT: &[u8] = include_bytes!("../examples/paper.gait");
    /// let gait = Gait::from_bytes(GAIT)?;
    /// assert_eq!((gait.params().steps, gait.checkpoint_count()), (10_000, 99));
    /// let flight = gait.replay::<f32>()?.fly(Replay::step)?;
    /// let error = gait.params().terminal_error(&flight.end);
    /// assert!(error.alpha < 1e-6 && error.g < 1e-6);
    /// # Ok::<(), purcell_core::Error>(())
    /// ```
    ///
    /// Reads version [`VERSION`] and version 1 (no `α_max`, no arcs).
    ///
    /// In this order: [`Error::GaitMagic`], [`Error::GaitVersion`], [`Error::GaitLength`]
    /// (the length field is not `bytes.len()`), [`Error::GaitChecksum`],
    /// [`Error::GaitLayout`] (sections, or an arc record's padding), then the values as
    /// [`check`] does ([`Error::NonFinite`], [`Error::InvalidParameters`],
    /// [`Error::InvalidStep`], [`Error::ShapeLimit`], [`Error::JointLimit`],
    /// [`Error::ArcInvalid`], [`Error::ArcOrder`], [`Error::NotRotation`],
    /// [`Error::CheckpointSpacing`], [`Error::ArcCheckpoint`], [`Error::ArcOffLimit`]), and
    /// [`Error::GaitLayout`] if the `f32` table is not the `f64` one rounded to nearest.
    pub fn from_bytes(bytes: &'a [u8]) -> Result<Self, Error> {
        if bytes.first_chunk() != Some(&MAGIC) {
            return Err(Error::GaitMagic);
        }
        let mut header = Cursor(bytes.get(MAGIC.len()..).unwrap_or_default());
        let version = header.u16().map_err(|_| Error::GaitLength)?;
        if !matches!(version, 1 | VERSION) {
            return Err(Error::GaitVersion(version));
        }
        let sections = usize::from(header.u16().map_err(|_| Error::GaitLength)?);
        let len = header.usize().map_err(|_| Error::GaitLength)?;
        if len != bytes.len() || len < HEADER_LEN + CRC_LEN {
            return Err(Error::GaitLength);
        }
        let (body, crc) = bytes
            .split_last_chunk::<CRC_LEN>()
            .ok_or(Error::GaitLength)?;
        let crc = u32::from_le_bytes(*crc);
        if crc32(body) != crc {
            return Err(Error::GaitChecksum);
        }

        // The directory: each section after the previous one, inside the body.
        let mut directory = Cursor(body.get(HEADER_LEN..).ok_or(Error::GaitLayout)?);
        let mut end = HEADER_LEN + sections * ENTRY_LEN;
        let (mut params, mut table64, mut table32) = (None, None, None);
        // Version 1 has no arc table: read as an empty one.
        let mut arcs = (version == 1).then_some((&[][..], 0));
        for _ in 0..sections {
            let (tag, offset) = (directory.take::<4>()?, directory.usize()?);
            let (count, size) = (directory.usize()?, directory.usize()?);
            let stop = count
                .checked_mul(size)
                .and_then(|n| n.checked_add(offset))
                .ok_or(Error::GaitLayout)?;
            let data = body.get(offset..stop).ok_or(Error::GaitLayout)?;
            if offset < end {
                return Err(Error::GaitLayout);
            }
            end = stop;
            let slot = match (tag, size) {
                (PARAMS_TAG, s) if s == params_len(version) && count == 1 => &mut params,
                (ARCS_TAG, arc::RECORD_LEN) if version != 1 => &mut arcs,
                (CK64_TAG, s) if s == record_len(8) => &mut table64,
                (CK32_TAG, s) if s == record_len(4) => &mut table32,
                _ => return Err(Error::GaitLayout),
            };
            if slot.replace((data, count)).is_some() {
                return Err(Error::GaitLayout);
            }
        }
        let (Some((params, _)), Some((arcs, _)), Some((t64, count)), Some((t32, count32))) =
            (params, arcs, table64, table32)
        else {
            return Err(Error::GaitLayout);
        };
        if count != count32 {
            return Err(Error::GaitLayout);
        }
        // The arc records' padding is zero.
        let padded = arcs
            .chunks_exact(arc::RECORD_LEN)
            .all(|r| r.first_chunk().is_some_and(|r| Arc::from_bytes(r).1));
        if !padded {
            return Err(Error::GaitLayout);
        }
        let params = Cursor(params).params(version)?;
        let gait = Gait {
            params,
            count,
            table64: Table::new(t64),
            table32: Table::new(t32),
            arcs,
            crc,
        };
        check(&params, gait.checkpoints(), gait.arcs())?;

        // The f64 records' padding is zero, and the f32 table is the f64 one rounded.
        let (mut wide, mut narrow) = (gait.table64, gait.table32);
        for _ in 0..count {
            let pad = wide.next_padding();
            let (k, v64) = wide.pop_values::<f64>().ok_or(Error::GaitLayout)?;
            let (k32, v32) = narrow.pop_values::<f32>().ok_or(Error::GaitLayout)?;
            let rounded = v64
                .iter()
                .zip(&v32)
                .all(|(&a, &b)| (a as f32).to_bits() == b.to_bits());
            if pad != Some(&[0; 4]) || k32 != k || !rounded {
                return Err(Error::GaitLayout);
            }
        }
        Ok(gait)
    }

    /// The gait's parameters.
    pub fn params(&self) -> &GaitParams {
        &self.params
    }

    /// Number of checkpoints.
    pub fn checkpoint_count(&self) -> usize {
        self.count
    }

    /// The checkpoints, in `f64` as stored.
    pub fn checkpoints(&self) -> Records<'a> {
        Records {
            table: self.table64,
            left: self.count,
        }
    }

    /// The joint-limit arcs, in order (none for a gait that never rests on its limit).
    pub fn arcs(&self) -> impl Iterator<Item = Arc> + Clone + 'a {
        ArcTable::Stored(self.arcs)
    }

    /// Number of arcs.
    pub fn arc_count(&self) -> usize {
        self.arcs.len() / arc::RECORD_LEN
    }

    /// The file's CRC-32 (its last four bytes): a name for this gait in logs.
    pub fn crc(&self) -> u32 {
        self.crc
    }

    /// A replay of the whole gait in `T` that restores the checkpoints from the table stored
    /// in `T`, read in place as the replay reaches them, and runs the law on the arcs
    /// ([`Replay::with_arcs`]).
    ///
    /// Errors: as [`Replay::new`] (the parameters and checkpoints rounded to `T` are checked
    /// again, e.g. an angle that rounds up to `π` in `f32`).
    pub fn replay<T: Stored>(&self) -> Result<Replay<'a, T>, Error> {
        self.replay_with(true)
    }

    /// A replay of the whole gait in `T` from `(μ, ξ^{−1})` and the arc table alone: the
    /// only checkpoints it restores are those at the arcs' exits, which the law needs (MODEL.md
    /// §9); none for a gait without arcs.
    ///
    /// Errors: as [`Replay::new`] (only the checkpoints it restores are checked in `T`).
    pub fn replay_without_checkpoints<T: Stored>(&self) -> Result<Replay<'a, T>, Error> {
        self.replay_with(false)
    }

    fn replay_with<T: Stored>(&self, periodic: bool) -> Result<Replay<'a, T>, Error> {
        let p = &self.params;
        let table = if size_of::<T>() == 4 {
            self.table32
        } else {
            self.table64
        };
        Replay::with_tables(
            p.kinematics()?,
            p.start(),
            p.costate(),
            p.steps,
            CheckpointTable::Stored(table),
            ArcTable::Stored(self.arcs),
            periodic,
        )
    }
}

/// The checkpoints of a [`Gait`], in `f64`.
#[derive(Clone, Debug)]
pub struct Records<'a> {
    table: Table<'a>,
    left: usize,
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

/// CRC-32 of `bytes` as in zip, PNG and IEEE 802.3: reflected, polynomial `0xEDB88320`,
/// initial value and final XOR `0xFFFFFFFF` (`crc32(b"123456789") = 0xCBF43926`). Bitwise,
/// no table: it runs once per gait.
pub fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
        }
    }
    !crc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc32_check_value() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        assert_eq!(crc32(b""), 0);
    }

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
