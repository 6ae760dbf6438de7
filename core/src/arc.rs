//! Joint-limit arcs (MODEL.md §9): the stretches of a constrained gait on which a joint rests
//! at its limit.
//!
//! On an arc of joint `i`, `σ·α_{k,i} = α_max` for the states `k = first … last`, so
//! `u_{k,i} = 0` for `k = first … last − 1` and the law runs its other row only
//! ([`Kinematics::law_step`](crate::Kinematics::law_step) with it `on`). The costate's jump
//! at the exit `last` is not fixed by the law: a replay restores a full-state checkpoint
//! `(α, g, ξ̃^{last−1})` there, so every arc's `last` must carry one ([`Error::ArcCheckpoint`]).
//! A touch point (`first = last`) has no step on the limit, only its checkpoint.
//!
//! An arc table is sorted by `(first, joint)`, and two arcs of one joint do not share a state
//! ([`check`]). A [`crate::Replay`] walks it with a cursor (no search per step); a
//! [`crate::Gait`] stores it in its `ARCS` section, read in place.

use crate::Error;

/// A joint-limit arc: joint `joint` rests at `sign·α_max` for the states `k = first ..= last`.
///
/// The record of a gait's arc table, in the binary gait file and in purcell-sim's JSON costate
/// file alike (with the `serde` feature).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct Arc {
    /// The joint, `1` (front, `α1`) or `2` (rear, `α2`), as in MODEL.md.
    pub joint: u8,
    /// `+1` at the upper limit `+α_max`, `−1` at the lower one.
    pub sign: i8,
    /// The first state on the limit (at least 1: `α_0 = ᾱ` lies inside).
    pub first: u32,
    /// The last state on the limit (below `N`); the replay restores a checkpoint there.
    pub last: u32,
}

impl Arc {
    /// The arc of joint `joint` at `sign·α_max` over the states `first ..= last`.
    #[inline]
    pub const fn new(joint: u8, sign: i8, first: u32, last: u32) -> Self {
        Arc {
            joint,
            sign,
            first,
            last,
        }
    }

    /// `Ok` if `joint ∈ {1, 2}`, `sign = ±1` and `1 ≤ first ≤ last < steps`, else
    /// [`Error::ArcInvalid`].
    pub fn check(&self, steps: u32) -> Result<(), Error> {
        let joint = matches!(self.joint, 1 | 2);
        let sign = matches!(self.sign, 1 | -1);
        if joint && sign && 1 <= self.first && self.first <= self.last && self.last < steps {
            Ok(())
        } else {
            Err(Error::ArcInvalid)
        }
    }

    /// The joint's index in `α` (0 or 1) of a checked arc.
    #[inline]
    pub fn index(&self) -> usize {
        usize::from(self.joint == 2)
    }

    /// The joint (1 or 2) whose index in `α` is `index` (0 or 1): the inverse of
    /// [`Arc::index`].
    #[inline]
    pub const fn joint_of(index: usize) -> u8 {
        if index == 0 { 1 } else { 2 }
    }
}

/// `Ok` if every arc passes [`Arc::check`] ([`Error::ArcInvalid`]) and the table is sorted by
/// `(first, joint)` with no two arcs of one joint sharing a state ([`Error::ArcOrder`]).
pub fn check(arcs: impl IntoIterator<Item = Arc>, steps: u32) -> Result<(), Error> {
    let mut previous: Option<Arc> = None;
    // The last state of each joint's previous arc (0: none yet; arcs start at 1).
    let mut ends = [0u32; 2];
    for a in arcs {
        a.check(steps)?;
        let sorted = previous.is_none_or(|p| (p.first, p.joint) < (a.first, a.joint));
        let end = ends.get_mut(a.index()).ok_or(Error::ArcInvalid)?;
        if !sorted || (*end != 0 && a.first <= *end) {
            return Err(Error::ArcOrder);
        }
        *end = a.last;
        previous = Some(a);
    }
    Ok(())
}

/// The arcs of one joint in a [`check`]ed table, in order (so their exits increase).
#[derive(Clone, Debug)]
struct JointExits<I> {
    arcs: I,
    joint: u8,
    next: Option<Arc>,
}

impl<I: Iterator<Item = Arc>> JointExits<I> {
    fn new(arcs: I, joint: u8) -> Self {
        let mut exits = JointExits {
            arcs,
            joint,
            next: None,
        };
        exits.advance();
        exits
    }

    fn advance(&mut self) {
        let joint = self.joint;
        self.next = self.arcs.by_ref().find(|a| a.joint == joint);
    }
}

/// Walks the exits (`last`) of a [`check`]ed arc table beside a list of checkpoint steps in
/// increasing order: [`Exits::at`] for each checkpoint, then [`Exits::finish`]. `O(arcs)` in
/// all, no allocation.
#[derive(Clone, Debug)]
pub(crate) struct Exits<I>([JointExits<I>; 2]);

impl<I: Iterator<Item = Arc> + Clone> Exits<I> {
    pub(crate) fn new(arcs: I) -> Self {
        Exits([JointExits::new(arcs.clone(), 1), JointExits::new(arcs, 2)])
    }

    /// The arcs (at most one per joint) whose exit is the checkpoint at step `k`.
    ///
    /// Errors: [`Error::ArcCheckpoint`] if an exit below `k` had no checkpoint.
    pub(crate) fn at(&mut self, k: u32) -> Result<[Option<Arc>; 2], Error> {
        let mut found = [None; 2];
        for (joint, out) in self.0.iter_mut().zip(&mut found) {
            match joint.next {
                Some(a) if a.last < k => return Err(Error::ArcCheckpoint),
                Some(a) if a.last == k => {
                    *out = Some(a);
                    joint.advance();
                }
                _ => {}
            }
        }
        Ok(found)
    }

    /// `Ok` if every exit had its checkpoint, else [`Error::ArcCheckpoint`].
    pub(crate) fn finish(&self) -> Result<(), Error> {
        if self.0.iter().all(|j| j.next.is_none()) {
            Ok(())
        } else {
            Err(Error::ArcCheckpoint)
        }
    }
}

/// Where a replay's arcs come from: a slice, or a gait file's `ARCS` section read in place.
#[derive(Clone, Copy, Debug)]
pub(crate) enum ArcTable<'a> {
    /// Arcs in memory.
    Slice(&'a [Arc]),
    /// A [`crate::Gait`]'s records ([`crate::gait`]: `RECORD_LEN` bytes each).
    Stored(&'a [u8]),
}

/// Bytes of a stored arc record: `joint` (u8), `sign` (i8), 2 zero bytes, `first`, `last`
/// (u32, little-endian).
pub(crate) const RECORD_LEN: usize = 12;

impl Arc {
    /// The stored record of this arc.
    pub(crate) fn to_bytes(self) -> [u8; RECORD_LEN] {
        let mut b = [0; RECORD_LEN];
        let (head, tail) = b.split_at_mut(4);
        head.copy_from_slice(&[self.joint, self.sign.to_le_bytes()[0], 0, 0]);
        let (first, last) = tail.split_at_mut(4);
        first.copy_from_slice(&self.first.to_le_bytes());
        last.copy_from_slice(&self.last.to_le_bytes());
        b
    }

    /// The arc of a stored record, and whether its padding is zero.
    pub(crate) fn from_bytes(b: &[u8; RECORD_LEN]) -> (Self, bool) {
        let [joint, sign, p0, p1, f0, f1, f2, f3, l0, l1, l2, l3] = *b;
        let arc = Arc {
            joint,
            sign: i8::from_le_bytes([sign]),
            first: u32::from_le_bytes([f0, f1, f2, f3]),
            last: u32::from_le_bytes([l0, l1, l2, l3]),
        };
        (arc, p0 == 0 && p1 == 0)
    }
}

impl Iterator for ArcTable<'_> {
    type Item = Arc;

    /// Removes the first arc.
    #[inline]
    fn next(&mut self) -> Option<Arc> {
        match self {
            ArcTable::Slice(s) => {
                let (first, rest) = s.split_first()?;
                *s = rest;
                Some(*first)
            }
            ArcTable::Stored(b) => {
                let (record, rest) = b.split_first_chunk::<RECORD_LEN>()?;
                *b = rest;
                Some(Arc::from_bytes(record).0)
            }
        }
    }
}

impl ArcTable<'_> {
    /// The first state of the next arc.
    #[inline]
    pub(crate) fn next_first(&self) -> Option<u32> {
        let mut copy = *self;
        copy.next().map(|a| a.first)
    }
}
