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
//! is soft-float on a Cortex-M4F). Version 3 adds a fifth section, `TRCK`: the gait's tracking
//! table in `f32` ([`TrackingTable`], [`crate::tracking`]), for a closed-loop flight. Version 4
//! is a gait whose end shape differs from its start ([`GaitParams::alpha_end`]): version 2's
//! sections (`TRCK` optional) with the end shape appended to `PARM`. Version 5 is a gait of a
//! cost other than the effort ([`GaitParams::cost`], [`crate::Cost`]): version 4's sections with
//! the cost in `PARM`; files of the effort stay what they were.
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
//!     alpha_end: None,
//!     cost: purcell_core::Cost::Effort,
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

mod any;
mod crc;
mod encode;
mod layout;
mod read;
mod records;
mod schema;
mod track;
mod validate;

pub use crate::arc::Arc;
pub use any::{AnyReplay, WithAnyReplay, WithVariant};
pub use crc::crc32;
pub use encode::{
    encode, encode_with_tracking, encoded_len, encoded_len_of, encoded_len_with_tracking,
};
pub use layout::{MAGIC, VERSION, VERSION_COST, VERSION_END_SHAPE, VERSION_TRACKING};
pub use read::{Gait, Stored, WithReplay};
pub use records::Records;
pub use schema::{CheckpointRecord, GaitParams, Model};
pub use track::{TRACKING_RECORD_LEN, TrackingCursor, TrackingTable};
pub use validate::{LIMIT_TOLERANCE, check};
