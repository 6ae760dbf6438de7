//! The byte layout of a gait file (the repository's `docs/GAIT.md`): a header, a directory of
//! sections, the sections, a CRC-32. The checkpoint records' layout is [`crate::table`]'s, the
//! arc records' [`crate::arc`]'s.

/// The first 8 bytes of every gait file.
pub const MAGIC: [u8; 8] = *b"PURCGAIT";
/// The version this build writes for a gait without a tracking table; it reads this one,
/// version 1 (no joint limit, no arcs) and [`VERSION_TRACKING`].
pub const VERSION: u16 = 2;
/// The version this build writes for a gait with a tracking table: version 2 and a fifth
/// section, `TRCK` (a version-2 reader refuses unknown sections, so the version changes).
pub const VERSION_TRACKING: u16 = 3;
/// The version this build writes for a gait whose end shape differs from its start
/// (`GaitParams::alpha_end`): version 2's sections, `TRCK` optional, and the end shape appended
/// to the `PARM` record (an older reader refuses it rather than fly it as a loop).
pub const VERSION_END_SHAPE: u16 = 4;
/// The version this build writes for a gait of a cost other than the effort
/// (`GaitParams::cost`, MODEL.md §11): version 4's sections, `TRCK` optional, and `PARM` with
/// the cost's code, whether it has an end shape, and the end shape (an older reader refuses it
/// rather than fly a power costate through the effort's law).
pub const VERSION_COST: u16 = 5;

/// Header: magic (8), version (u16), section count (u16), file length (u32).
pub(super) const HEADER_LEN: usize = 16;
/// Directory entry: tag (4 ASCII bytes), offset, record count, record size (u32 each).
pub(super) const ENTRY_LEN: usize = 16;
/// The CRC-32 at the end.
pub(super) const CRC_LEN: usize = 4;
pub(super) const PARAMS_TAG: [u8; 4] = *b"PARM";
pub(super) const ARCS_TAG: [u8; 4] = *b"ARCS";
pub(super) const CK64_TAG: [u8; 4] = *b"CK64";
pub(super) const CK32_TAG: [u8; 4] = *b"CK32";
pub(super) const TRACKING_TAG: [u8; 4] = *b"TRCK";
/// Sections of a version-2 file, in the order `encode` writes them (a version-3 file has
/// `TRCK` after them).
pub(super) const SECTIONS: usize = 4;
/// The `PARM` record: `steps`, `checkpoint_every` (u32), then 16 `f64` (`L0 L1 L2 k r h`, `ᾱ`,
/// `ḡ`, `μ`, `ξ^{−1}`), then from version 2 `α_max` (`f64`, 0 for none), then in version 4
/// the end shape `α_N` (2 `f64`); in version 5 the cost's code and whether the end shape is
/// stored (u32 each), then the end shape (2 `f64`, zero if not).
pub(super) const fn params_len(version: u16) -> usize {
    8 + 16 * 8
        + match version {
            1 => 0,
            VERSION_END_SHAPE => 8 + 16,
            VERSION_COST => 8 + 8 + 16,
            _ => 8,
        }
}
