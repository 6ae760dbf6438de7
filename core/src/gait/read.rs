//! Reading a gait file in place ([`Gait::from_bytes`]) and replaying it ([`Gait::replay`]).

use crate::arc::{self, Arc, ArcTable};
use crate::cost::RunningCost;
use crate::gait::any::{AnyReplay, WithVariant};
use crate::gait::crc::crc32;
use crate::gait::layout::{
    ARCS_TAG, CK32_TAG, CK64_TAG, CRC_LEN, ENTRY_LEN, HEADER_LEN, MAGIC, PARAMS_TAG, SECTIONS,
    TRACKING_TAG, VERSION, VERSION_COST, VERSION_END_SHAPE, VERSION_TRACKING, params_len,
};
use crate::gait::records::Records;
use crate::gait::schema::{GaitParams, Model};
use crate::gait::track::{TRACKING_RECORD_LEN, TrackingTable, check_tracking};
use crate::gait::validate::check;
use crate::replay::{CheckpointTable, Replay};
use crate::table::{Table, record_len};
use crate::{Cost, Error, Real};
use core::mem::size_of;

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
    /// The `TRCK` records (empty before version 3).
    tracking: &'a [u8],
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

    /// The `PARM` record of a file of `version` ([`params_len`]).
    fn params(&mut self, version: u16) -> Result<GaitParams, Error> {
        let (steps, checkpoint_every) = (self.u32()?, self.u32()?);
        let links = self.f64s()?;
        let [drag, ratio, h] = self.f64s()?;
        let (alpha0, target, mu, xi0) = (self.f64s()?, self.f64s()?, self.f64s()?, self.f64s()?);
        let alpha_max = match version {
            1 => None,
            _ => Some(f64::from_le_bytes(self.take()?)).filter(|&a| a != 0.0),
        };
        let (cost, alpha_end) = match version {
            VERSION_END_SHAPE => (Cost::Effort, Some(self.f64s()?)),
            VERSION_COST => self.cost_and_end()?,
            _ => (Cost::Effort, None),
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
            alpha_end,
            cost,
        })
    }

    /// Version 5's tail of `PARM`: the cost (a known code, not the effort's, whose gaits are
    /// the older versions), whether the end shape is stored (0 or 1) and the end shape (zero
    /// if not); else [`Error::GaitLayout`].
    fn cost_and_end(&mut self) -> Result<(Cost, Option<[f64; 2]>), Error> {
        let cost = Cost::from_code(self.u32()?)
            .filter(|&c| c != Cost::Effort)
            .ok_or(Error::GaitLayout)?;
        let stored = self.u32()?;
        let end = self.f64s()?;
        match stored {
            1 => Ok((cost, Some(end))),
            0 if end == [0.0; 2] => Ok((cost, None)),
            _ => Err(Error::GaitLayout),
        }
    }
}

/// The sections of a file, found through its directory.
struct Sections<'a> {
    params: &'a [u8],
    arcs: &'a [u8],
    t64: &'a [u8],
    t32: &'a [u8],
    /// Checkpoints in each table.
    count: usize,
    tracking: &'a [u8],
    /// Whether the file has a `TRCK` section.
    tracked: bool,
}

impl<'a> Sections<'a> {
    /// Reads the directory of `sections` entries of a file of `version` (`body`: the file
    /// without its CRC): each section after the previous one, inside the body, with a known
    /// tag and record size, each once, the two checkpoint tables of one count; else
    /// [`Error::GaitLayout`].
    fn read(body: &'a [u8], sections: usize, version: u16) -> Result<Self, Error> {
        let mut directory = Cursor(body.get(HEADER_LEN..).ok_or(Error::GaitLayout)?);
        let mut end = HEADER_LEN + sections * ENTRY_LEN;
        let (mut params, mut table64, mut table32) = (None, None, None);
        // Version 1 has no arc table: read as an empty one.
        let mut arcs = (version == 1).then_some((&[][..], 0));
        // Version 3 has a tracking table, version 4 one if it has a fifth section: read as an
        // empty one otherwise.
        let tracked = version == VERSION_TRACKING
            || (matches!(version, VERSION_END_SHAPE | VERSION_COST) && sections == SECTIONS + 1);
        let mut tracking = (!tracked).then_some((&[][..], 0));
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
                (TRACKING_TAG, TRACKING_RECORD_LEN) if tracked => &mut tracking,
                _ => return Err(Error::GaitLayout),
            };
            if slot.replace((data, count)).is_some() {
                return Err(Error::GaitLayout);
            }
        }
        match (params, arcs, table64, table32, tracking) {
            (
                Some((params, _)),
                Some((arcs, _)),
                Some((t64, count)),
                Some((t32, count32)),
                Some((tracking, _)),
            ) if count == count32 => Ok(Sections {
                params,
                arcs,
                t64,
                t32,
                count,
                tracking,
                tracked,
            }),
            _ => Err(Error::GaitLayout),
        }
    }
}

impl<'a> Gait<'a> {
    /// Reads and validates a gait file in place (the checkpoint tables stay in `bytes`).
    ///
    /// ```
    /// use purcell_core::{Gait, Replay};
    ///
    /// // In firmware: `static GAIT: &[u8] = include_bytes!("gait.bin");`
    /// static GAIT: &[u8] = include_bytes!("../../examples/paper.gait");
    /// let gait = Gait::from_bytes(GAIT)?;
    /// assert_eq!((gait.params().steps, gait.checkpoint_count()), (10_000, 99));
    /// let flight = gait.replay::<f32>()?.fly(Replay::step)?;
    /// let error = gait.params().terminal_error(&flight.end);
    /// assert!(error.alpha < 1e-6 && error.g < 1e-6);
    /// # Ok::<(), purcell_core::Error>(())
    /// ```
    ///
    /// Reads version [`VERSION`], version 1 (no `α_max`, no arcs), version
    /// [`VERSION_TRACKING`] (with a tracking table), version [`VERSION_END_SHAPE`] (with
    /// an end shape, and a tracking table or not) and version [`VERSION_COST`] (a cost other
    /// than the effort, with an end shape or not, a tracking table or not).
    ///
    /// In this order: [`Error::GaitMagic`], [`Error::GaitVersion`], [`Error::GaitLength`]
    /// (the length field is not `bytes.len()`), [`Error::GaitChecksum`],
    /// [`Error::GaitLayout`] (sections, or an arc record's padding), then the values as
    /// [`check`] does ([`Error::NonFinite`], [`Error::InvalidParameters`],
    /// [`Error::InvalidStep`], [`Error::ShapeLimit`], [`Error::JointLimit`],
    /// [`Error::ArcInvalid`], [`Error::ArcOrder`], [`Error::NotRotation`],
    /// [`Error::CheckpointSpacing`], [`Error::ArcCheckpoint`], [`Error::ArcOffLimit`]), and
    /// [`Error::GaitLayout`] if the `f32` table is not the `f64` one rounded to nearest; then
    /// the tracking table's indices ([`Error::GaitLayout`]: `k_0 = 0`, increasing, below `N`)
    /// and values ([`Error::NonFinite`]).
    pub fn from_bytes(bytes: &'a [u8]) -> Result<Self, Error> {
        if bytes.first_chunk() != Some(&MAGIC) {
            return Err(Error::GaitMagic);
        }
        let mut header = Cursor(bytes.get(MAGIC.len()..).unwrap_or_default());
        let version = header.u16().map_err(|_| Error::GaitLength)?;
        if !matches!(
            version,
            1 | VERSION | VERSION_TRACKING | VERSION_END_SHAPE | VERSION_COST
        ) {
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

        let found = Sections::read(body, sections, version)?;
        let (arcs, count) = (found.arcs, found.count);
        // The arc records' padding is zero.
        let padded = arcs
            .chunks_exact(arc::RECORD_LEN)
            .all(|r| r.first_chunk().is_some_and(|r| Arc::from_bytes(r).1));
        if !padded {
            return Err(Error::GaitLayout);
        }
        let params = Cursor(found.params).params(version)?;
        let gait = Gait {
            params,
            count,
            table64: Table::new(found.t64),
            table32: Table::new(found.t32),
            arcs,
            tracking: found.tracking,
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
        if found.tracked {
            check_tracking(TrackingTable::new(gait.tracking).iter(), params.steps)?;
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
        Records::new(self.table64, self.count)
    }

    /// The joint-limit arcs, in order (none for a gait that never rests on its limit).
    pub fn arcs(&self) -> impl Iterator<Item = Arc> + Clone + 'a {
        ArcTable::Stored(self.arcs)
    }

    /// Number of arcs.
    pub fn arc_count(&self) -> usize {
        self.arcs.len() / arc::RECORD_LEN
    }

    /// The tracking table (version 3, or 4 with one), read in place; `None` for a gait without
    /// one.
    pub fn tracking(&self) -> Option<TrackingTable<'a>> {
        let table = TrackingTable::new(self.tracking);
        (!table.is_empty()).then_some(table)
    }

    /// The file's CRC-32 (its last four bytes): a name for this gait in logs.
    pub fn crc(&self) -> u32 {
        self.crc
    }

    /// A replay of the whole gait in `T` that restores the checkpoints from the table stored
    /// in `T`, read in place as the replay reaches them, and runs the effort's law on the arcs
    /// ([`Replay::with_arcs`]). A gait of another cost: [`Gait::replay_for`], or of any cost:
    /// [`Gait::with_replay`], [`Gait::replay_any`].
    ///
    /// Errors: as [`Replay::new`] (the parameters and checkpoints rounded to `T` are checked
    /// again, e.g. an angle that rounds up to `π` in `f32`); [`Error::InvalidParameters`] for a
    /// gait solved for another cost than the effort.
    pub fn replay<T: Stored>(&self) -> Result<Replay<'a, T>, Error> {
        self.replay_for(true)
    }

    /// A replay of the whole gait in `T` from `(μ, ξ^{−1})` and the arc table alone: the
    /// only checkpoints it restores are those at the arcs' exits, which the law needs (MODEL.md
    /// §9); none for a gait without arcs.
    ///
    /// Errors: as [`Gait::replay`] (only the checkpoints it restores are checked in `T`).
    pub fn replay_without_checkpoints<T: Stored>(&self) -> Result<Replay<'a, T>, Error> {
        self.replay_for(false)
    }

    /// [`Gait::replay`] (with `checkpoints`) or [`Gait::replay_without_checkpoints`] running
    /// the law of the cost `C`, which must be the gait's (`params().cost`): a caller that flies
    /// gaits of any cost matches on it once and runs each cost's replay (see
    /// [`crate::cost`]).
    ///
    /// Errors: as [`Gait::replay`]; [`Error::InvalidParameters`] if `C` is not the gait's cost.
    pub fn replay_for<T: Stored, C: RunningCost>(
        &self,
        checkpoints: bool,
    ) -> Result<Replay<'a, T, C>, Error> {
        let p = &self.params;
        if p.cost != C::COST {
            return Err(Error::InvalidParameters);
        }
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
            checkpoints,
        )
    }

    /// [`Gait::replay`] of the gait's own cost, held as an [`AnyReplay`] (for a caller that
    /// keeps it between calls; a generic one: [`Gait::with_replay`]).
    ///
    /// Errors: as [`Gait::replay_for`].
    pub fn replay_any<T: Stored>(&self) -> Result<AnyReplay<'a, T>, Error> {
        /// The gait's replay of `C` in its variant.
        struct Any<'g, 'a>(&'g Gait<'a>);
        impl<'a, T: Stored> WithVariant<'a, T> for Any<'_, 'a> {
            type Output = Result<AnyReplay<'a, T>, Error>;
            fn run<C: RunningCost>(
                self,
                variant: fn(Replay<'a, T, C>) -> AnyReplay<'a, T>,
            ) -> Self::Output {
                self.0.replay_for(true).map(variant)
            }
        }
        AnyReplay::for_cost(self.params.cost, Any(self))
    }

    /// Runs `with` on the replay in `T` of the gait's own cost ([`Gait::replay_for`], with or
    /// without `checkpoints`): the one match on the cost for a caller that flies gaits of any
    /// cost, each cost's replay its own compiled code.
    ///
    /// Errors: as [`Gait::replay_for`], before `with` runs.
    pub fn with_replay<T: Stored, W: WithReplay<'a, T>>(
        &self,
        checkpoints: bool,
        with: W,
    ) -> Result<W::Output, Error> {
        crate::with_cost!(self.params.cost, C => {
            Ok(with.run(self.replay_for::<T, C>(checkpoints)?))
        })
    }
}

/// What a caller does with the replay of a gait of any cost ([`Gait::with_replay`]): one
/// function generic over the cost.
pub trait WithReplay<'a, T: Stored> {
    /// What it gives.
    type Output;
    /// Runs on `replay`, which runs the law of `C`, the gait's cost.
    fn run<C: RunningCost>(self, replay: Replay<'a, T, C>) -> Self::Output;
}
