//! The binary gait file: what `encode` writes `from_bytes` reads back; a replay from its stored
//! tables is the replay from the same checkpoints in memory, bit for bit; every corruption is
//! refused with its typed error, and no input panics.

use crate::common;

use common::*;
use proptest::prelude::*;
use purcell_core::gait::{self, Arc, CheckpointRecord, Gait, GaitParams};
use purcell_core::{Checkpoint, Error, Real, Sample, State};

/// The paper's swimmer, 1 000 steps of the `|μ| ≈ 13` extremal's costate, and checkpoints every
/// 100 steps taken from its plain `f64` replay (as `purcell-sim solve` writes them).
fn example() -> (GaitParams, Vec<CheckpointRecord>) {
    let c = costate_mu13();
    let (mu, xi0) = ([c.mu.x, c.mu.y, c.mu.z], [c.xi.x, c.xi.y]);
    let params = paper_gait(1000, [0.1, 0.1, 0.0], mu, xi0);
    let records = states_along(c, 1000, 100)
        .into_iter()
        .skip(1)
        .enumerate()
        .map(|(i, (s, xi))| CheckpointRecord {
            k: 100 * (i as u32 + 1),
            alpha: [s.alpha.x, s.alpha.y],
            g: [s.g.x(), s.g.y(), s.g.cos(), s.g.sin()],
            xi: [xi.x, xi.y],
        })
        .collect();
    (params, records)
}

fn encode(params: &GaitParams, records: &[CheckpointRecord]) -> Vec<u8> {
    encode_arcs(params, records, &[])
}

fn encode_arcs(params: &GaitParams, records: &[CheckpointRecord], arcs: &[Arc]) -> Vec<u8> {
    let mut bytes = vec![0; gait::encoded_len(records.len(), arcs.len())];
    assert_eq!(
        gait::encode(params, records, arcs, &mut bytes),
        Ok(bytes.len())
    );
    bytes
}

/// Recomputes the CRC after a deliberate edit, so the check after it is what refuses the file.
fn reseal(bytes: &mut [u8]) {
    let n = bytes.len() - 4;
    let crc = gait::crc32(&bytes[..n]);
    bytes[n..].copy_from_slice(&crc.to_le_bytes());
}

fn put_f64(bytes: &mut [u8], at: usize, x: f64) {
    bytes[at..at + 8].copy_from_slice(&x.to_le_bytes());
}

/// Offsets in the file `encode` writes without arcs (docs/GAIT.md).
const PARAMS: usize = 80;
const CK64: usize = 224;
fn ck32(n: usize) -> usize {
    CK64 + 72 * n
}

#[test]
fn encode_then_from_bytes_gives_the_same_gait() {
    let (params, records) = example();
    assert_eq!(records.len(), 9);
    let bytes = encode(&params, &records);
    let gait = Gait::from_bytes(&bytes).unwrap();
    assert_eq!(gait.params(), &params);
    assert_eq!(gait.checkpoint_count(), 9);
    assert_eq!(gait.checkpoints().len(), 9);
    assert_eq!(gait.checkpoints().collect::<Vec<_>>(), records);
    assert_eq!(gait.crc(), gait::crc32(&bytes[..bytes.len() - 4]));
    // Too small a buffer is refused, and nothing is checked twice: invalid input is refused
    // before anything is written.
    let mut short = vec![0; bytes.len() - 1];
    assert_eq!(
        gait::encode(&params, &records, &[], &mut short),
        Err(Error::CapacityExceeded)
    );
    let mut bad = records.clone();
    bad[3].k = bad[2].k;
    let mut out = vec![7; bytes.len()];
    assert_eq!(
        gait::encode(&params, &bad, &[], &mut out),
        Err(Error::CheckpointSpacing)
    );
    assert!(out.iter().all(|&b| b == 7));
}

fn flight_from_memory<T: Real>(
    params: &GaitParams,
    records: &[CheckpointRecord],
) -> (Vec<Sample<T>>, State<T>) {
    let checkpoints: Vec<Checkpoint<T>> = records.iter().map(|r| r.to_checkpoint()).collect();
    let mut replay = replay_in_memory(params, &checkpoints, &[]);
    let samples = replay.by_ref().collect::<Result<Vec<_>, _>>().unwrap();
    (samples, *replay.state())
}

#[test]
fn stored_tables_replay_like_the_same_checkpoints_in_memory() {
    let (params, records) = example();
    let bytes = encode(&params, &records);
    let gait = Gait::from_bytes(&bytes).unwrap();

    let mut stored = gait.replay::<f32>().unwrap();
    let samples: Vec<Sample<f32>> = stored.by_ref().collect::<Result<_, _>>().unwrap();
    assert_eq!(
        (samples, *stored.state()),
        flight_from_memory::<f32>(&params, &records)
    );
    let mut stored = gait.replay::<f64>().unwrap();
    let samples: Vec<Sample<f64>> = stored.by_ref().collect::<Result<_, _>>().unwrap();
    let in_memory = flight_from_memory::<f64>(&params, &records);
    assert_eq!((samples, *stored.state()), in_memory);

    // The f64 checkpoints are the plain f64 replay's own states: applying them changes no bit.
    let with = fly(gait.replay::<f64>()).unwrap();
    let without = fly(gait.replay_without_checkpoints::<f64>()).unwrap();
    assert_eq!(with, without);
    assert_eq!(with.end, in_memory.1);
    // In f32 they matter (they reset the drifting recursion).
    let with32 = fly(gait.replay::<f32>()).unwrap();
    let without32 = fly(gait.replay_without_checkpoints::<f32>());
    assert_ne!(Ok(with32), without32);
    assert_eq!(with32.steps, 1000);
}

#[test]
fn fly_digests_every_sample_then_the_end() {
    let (params, records) = example();
    let bytes = encode(&params, &records);
    let gait = Gait::from_bytes(&bytes).unwrap();
    let flight = fly(gait.replay::<f32>()).unwrap();
    let mut digest = purcell_core::TrajectoryDigest::new();
    let mut replay = gait.replay::<f32>().unwrap();
    while let Some(s) = replay.step().unwrap() {
        digest.push_sample(s);
    }
    digest.push_state(replay.state());
    assert_eq!(flight.digest, digest);
    assert_eq!(flight.end, *replay.state());
    let e = flight.end;
    let bits = [e.alpha.x, e.alpha.y, e.g.x(), e.g.y(), e.g.cos(), e.g.sin()];
    assert_eq!(flight.final_bits(), bits.map(|x| u64::from(x.to_bits())));
    // A step that fails ends the flight with its error.
    let mut n = 0;
    let failed = gait.replay::<f32>().unwrap().fly(|r| {
        n += 1;
        if n == 3 {
            Err(Error::Singular)
        } else {
            r.step()
        }
    });
    assert_eq!(failed, Err(Error::Singular));
}

#[test]
fn the_terminal_error_is_the_largest_component_in_f64() {
    let (params, _) = example();
    let end = State {
        alpha: nalgebra::Vector2::new(3e-3f32, -4e-3),
        g: purcell_core::Se2::new(0.1, 0.1 + 2e-3, 1e-3),
    };
    let e = params.terminal_error(&end);
    assert!((e.alpha - 4e-3).abs() < 1e-9, "{e:?}");
    // log(ḡ⁻¹ g) of a pure offset (0, 2e-3, 1e-3) from ḡ = (0.1, 0.1, 0): largest component
    // is the y translation, 2e-3 to first order.
    assert!((e.g - 2e-3).abs() < 1e-5, "{e:?}");
    let exact = params.terminal_error(&State::at_origin(nalgebra::Vector2::<f64>::zeros()));
    assert_eq!(exact.alpha, 0.0);
    assert!((exact.g - 0.1).abs() < 0.01);
}

/// The error `from_bytes` gives for the file `good` after `edit`.
fn refused(good: &[u8], edit: impl FnOnce(&mut Vec<u8>)) -> Option<Error> {
    let mut b = good.to_vec();
    edit(&mut b);
    Gait::from_bytes(&b).err()
}

/// [`refused`] with the CRC recomputed after the edit, so that a later check refuses the file.
fn refused_sealed(good: &[u8], edit: impl FnOnce(&mut Vec<u8>)) -> Option<Error> {
    refused(good, |b| {
        edit(b);
        reseal(b)
    })
}

/// The header's checks of `from_bytes`, each reached by one edit of a valid file: magic,
/// version, length, checksum.
#[test]
fn a_corrupt_header_is_refused_with_its_reason() {
    let (params, records) = example();
    let good = encode(&params, &records);
    let n = records.len();
    assert_eq!(refused(&good, |b| b[0] = b'X'), Some(Error::GaitMagic));
    assert_eq!(Gait::from_bytes(&[]).err(), Some(Error::GaitMagic));
    assert_eq!(Gait::from_bytes(b"PURCGAIT").err(), Some(Error::GaitLength));
    assert_eq!(refused(&good, |b| b[8] = 6), Some(Error::GaitVersion(6)));
    assert_eq!(refused(&good, |b| b[8] = 0), Some(Error::GaitVersion(0)));
    assert_eq!(
        refused(&good, |b| b.truncate(b.len() - 1)),
        Some(Error::GaitLength)
    );
    assert_eq!(refused(&good, |b| b.push(0)), Some(Error::GaitLength));
    let checksum = Some(Error::GaitChecksum);
    assert_eq!(refused(&good, |b| b[ck32(n) + 5] ^= 0x10), checksum);
    assert_eq!(refused(&good, |b| b[PARAMS + 9] ^= 1), checksum);
    let last = good.len() - 1;
    assert_eq!(refused(&good, |b| b[last] ^= 0x80), checksum);
}

/// The sections' checks (directory entries PARM, ARCS, CK64, CK32 at 16, 32, 48, 64), each
/// reached by one edit of a valid file resealed: an unknown tag, a wrong record size (CK64's,
/// PARM's of version 1 in version 2), a duplicate, a count mismatch, an offset out of bounds
/// or overlapping, a missing one, a non-zero pad, an f32 table that is not the f64 one
/// rounded; a version-1 file may not have arcs.
#[test]
fn a_corrupt_section_is_refused_as_a_layout_error() {
    let (params, records) = example();
    let good = encode(&params, &records);
    let n = records.len();
    let layout = Some(Error::GaitLayout);
    let sealed = |edit: &dyn Fn(&mut Vec<u8>)| refused_sealed(&good, edit);
    assert_eq!(sealed(&|b| b[32..36].copy_from_slice(b"ARCZ")), layout);
    assert_eq!(sealed(&|b| b[60] = 73), layout);
    assert_eq!(sealed(&|b| b[28] = 136), layout);
    assert_eq!(sealed(&|b| b[64..68].copy_from_slice(b"CK64")), layout);
    assert_eq!(sealed(&|b| b[72] = 8), layout);
    assert_eq!(
        sealed(&|b| b[52..56].copy_from_slice(&60u32.to_le_bytes())),
        layout
    );
    assert_eq!(
        sealed(&|b| b[68..72].copy_from_slice(&9999u32.to_le_bytes())),
        layout
    );
    assert_eq!(sealed(&|b| b[10] = 3), layout);
    assert_eq!(sealed(&|b| b[8] = 1), layout);
    assert_eq!(sealed(&|b| b[CK64 + 4] = 1), layout);
    assert_eq!(sealed(&|b| b[ck32(n) + 4] ^= 1), layout);
    assert_eq!(sealed(&|b| b[ck32(n)] ^= 1), layout);
}

/// The values' checks, as in `gait::check`, each reached by one edit of a valid file
/// resealed, or by `encode` of an invalid checkpoint.
#[test]
fn invalid_values_are_refused_as_the_gait_check_refuses_them() {
    let (params, records) = example();
    let good = encode(&params, &records);
    let n = records.len();
    let sealed = |edit: &dyn Fn(&mut Vec<u8>)| refused_sealed(&good, edit);
    assert_eq!(
        sealed(&|b| put_f64(b, PARAMS + 40, f64::NAN)),
        Some(Error::NonFinite)
    );
    assert_eq!(
        sealed(&|b| put_f64(b, PARAMS + 8, 0.0)),
        Some(Error::InvalidParameters)
    );
    assert_eq!(
        sealed(&|b| put_f64(b, PARAMS + 48, -0.01)),
        Some(Error::InvalidStep)
    );
    assert_eq!(
        sealed(&|b| b[PARAMS..PARAMS + 4].fill(0)),
        Some(Error::InvalidStep)
    );
    assert_eq!(
        sealed(&|b| put_f64(b, PARAMS + 56, 3.2)),
        Some(Error::ShapeLimit)
    );
    // α_max (0: none) must lie in ]max |ᾱ_i|, π[.
    for bad in [-1.0, 3.2, f64::NAN] {
        assert_eq!(
            sealed(&|b| put_f64(b, PARAMS + 136, bad)),
            Some(Error::JointLimit)
        );
    }
    // Checkpoint 0 copied over checkpoint 1 in both tables (so they still agree): a repeated k.
    assert_eq!(
        sealed(&|b| {
            b.copy_within(CK64..CK64 + 72, CK64 + 72);
            let c = ck32(n);
            b.copy_within(c..c + 36, c + 36);
        }),
        Some(Error::CheckpointSpacing)
    );
    assert_eq!(
        sealed(&|b| b[PARAMS..PARAMS + 4].copy_from_slice(&900u32.to_le_bytes())),
        Some(Error::CheckpointSpacing)
    );
    let mut rotated = records.clone();
    rotated[0].g[2] *= 1.0 + 1e-8;
    let mut out = vec![0; good.len()];
    assert_eq!(
        gait::encode(&params, &rotated, &[], &mut out),
        Err(Error::NotRotation)
    );
    let mut overlap = records.clone();
    overlap[0].alpha[1] = -3.2;
    assert_eq!(
        gait::encode(&params, &overlap, &[], &mut out),
        Err(Error::ShapeLimit)
    );
}

/// An angle below π in f64 that rounds to π in f32 is refused by the f32 replay only.
#[test]
fn checkpoints_are_checked_again_in_the_replay_scalar() {
    let (params, mut records) = example();
    records[0].alpha[0] = core::f64::consts::PI - 1e-9; // rounds up to π in f32
    let bytes = encode(&params, &records);
    let gait = Gait::from_bytes(&bytes).unwrap();
    assert!(gait.replay::<f64>().is_ok());
    assert_eq!(gait.replay::<f32>().err(), Some(Error::ShapeLimit));
    assert!(gait.replay_without_checkpoints::<f32>().is_ok());
}

proptest! {
    #![proptest_config(proptest_config())]

    /// Any change of one byte of a valid file is refused (CRC-32 catches every error burst of
    /// up to 32 bits), and never panics.
    #[test]
    fn any_changed_byte_is_refused(at in 0usize..gait::encoded_len(9, 0), flip in 1u8..=255) {
        let (params, records) = example();
        let mut bytes = encode(&params, &records);
        bytes[at] ^= flip;
        prop_assert!(Gait::from_bytes(&bytes).is_err());
    }

    /// Arbitrary bytes, and arbitrary bytes behind a valid header, never panic.
    #[test]
    fn garbage_never_panics(mut bytes in proptest::collection::vec(any::<u8>(), 0..400), len in any::<bool>()) {
        if len && bytes.len() >= 16 {
            bytes[..8].copy_from_slice(&gait::MAGIC);
            bytes[8..10].copy_from_slice(&gait::VERSION.to_le_bytes());
            let n = bytes.len() as u32;
            bytes[12..16].copy_from_slice(&n.to_le_bytes());
            if bytes.len() >= 20 {
                reseal(&mut bytes);
            }
        }
        let _ = Gait::from_bytes(&bytes);
    }
}

/// `data/tiny-limit.gait` (written by `purcell-sim export` from purcell-sim's
/// `tests/data/tiny-limit.costate.json`: a 300-step gait to `ḡ = (0.01, 0.005, 0)` within
/// `|α_i| ≤ 0.8`, two arcs, checkpoints at 100 and 200 and at the arcs' exits 137 and 185) is
/// read as these numbers and written back byte for byte, and its header, directory and
/// sections are where docs/GAIT.md says: changing the layout fails here.
#[test]
fn the_committed_limit_gait_locks_the_layout() {
    let bytes: &[u8] = include_bytes!("../data/tiny-limit.gait");
    let params = GaitParams {
        alpha_max: Some(0.8),
        ..paper_gait(
            300,
            [0.01, 0.005, 0.0],
            [-56.867426414422425, 281.2775050523989, 1.2826606795323952],
            [47.92457979744187, -46.10058568703169],
        )
    };
    let arcs = [
        Arc {
            joint: 2,
            sign: 1,
            first: 117,
            last: 137,
        },
        Arc {
            joint: 1,
            sign: 1,
            first: 165,
            last: 185,
        },
    ];
    let exit = CheckpointRecord {
        k: 137,
        alpha: [0.6477345645475362, 0.7999999999999998],
        g: [
            -0.007968802609140516,
            0.027239689385942636,
            0.927442202327413,
            -0.3739665243602398,
        ],
        xi: [51.417133353267936, -50.71471354662252],
    };
    let gait = Gait::from_bytes(bytes).unwrap();
    assert_eq!(gait.params(), &params);
    assert_eq!(
        (gait.arcs().collect::<Vec<_>>(), gait.arc_count()),
        (arcs.to_vec(), 2)
    );
    let records: Vec<_> = gait.checkpoints().collect();
    let ks: Vec<u32> = records.iter().map(|c| c.k).collect();
    assert_eq!((ks, records[1]), (vec![100, 137, 185, 200], exit));
    assert_eq!(encode_arcs(&params, &records, &arcs), bytes);

    let u16_at = |at: usize| u16::from_le_bytes([bytes[at], bytes[at + 1]]);
    let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    let f64_at = |at: usize| f64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
    let f32_at = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    assert_eq!(&bytes[..8], b"PURCGAIT");
    assert_eq!((u16_at(8), u16_at(10), u32_at(12)), (2, 4, 684));
    // Directory: tag, offset, count, record size.
    let entry = |i: usize| {
        let at = 16 + 16 * i;
        (
            &bytes[at..at + 4],
            u32_at(at + 4),
            u32_at(at + 8),
            u32_at(at + 12),
        )
    };
    assert_eq!(entry(0), (&b"PARM"[..], 80, 1, 144));
    assert_eq!(entry(1), (&b"ARCS"[..], 224, 2, 12));
    assert_eq!(entry(2), (&b"CK64"[..], 248, 4, 72));
    assert_eq!(entry(3), (&b"CK32"[..], 536, 4, 36));
    // PARM: steps, checkpoint_every, then L0 L1 L2 k r h ᾱ ḡ μ ξ⁻¹ α_max as f64.
    assert_eq!((u32_at(80), u32_at(84)), (300, 100));
    assert_eq!(f64_at(88 + 5 * 8), 0.01);
    assert_eq!(f64_at(88 + 11 * 8), params.mu[0]);
    assert_eq!(f64_at(88 + 16 * 8), 0.8);
    // ARCS: joint (u8), sign (i8), zero pad, first, last.
    assert_eq!(&bytes[224..228], &[2, 1, 0, 0]);
    assert_eq!((u32_at(228), u32_at(232)), (117, 137));
    assert_eq!(&bytes[236..240], &[1, 1, 0, 0]);
    // CK64: k, zero pad, α1 α2 x y cos sin ξ1 ξ2; CK32: k, the same values as f32.
    assert_eq!(
        (u32_at(248 + 72), u32_at(252 + 72), f64_at(256 + 72)),
        (137, 0, exit.alpha[0])
    );
    assert_eq!(
        (u32_at(536 + 36), f32_at(540 + 36)),
        (137, exit.alpha[0] as f32)
    );
    assert_eq!(u32_at(680), gait::crc32(&bytes[..680]));
    assert_eq!(gait.crc(), 0x20e6_3071);
}

/// Version 1 (written before joint limits, `data/tiny-v1.gait`: a 200-step gait to
/// `ḡ = (0.002, 0.001, 0)`, one checkpoint) is still read, as a gait without a joint limit and
/// without arcs; written again it is version 2 and flies the same.
#[test]
fn version_1_gaits_are_still_read() {
    let bytes: &[u8] = include_bytes!("../data/tiny-v1.gait");
    let params = paper_gait(
        200,
        [0.002, 0.001, 0.0],
        [-102.05775417345498, 590.1701561480827, -31.45148654572925],
        [91.01363029151028, -106.55065114553868],
    );
    let records = [CheckpointRecord {
        k: 100,
        alpha: [0.5131721216763051, 0.5285235518697851],
        g: [
            0.00012596203150517707,
            0.0030525506774003877,
            0.9629447973701601,
            -0.269698567326082,
        ],
        xi: [95.78484708845677, -112.98913203930218],
    }];
    assert_eq!(u16::from_le_bytes([bytes[8], bytes[9]]), 1);
    let v1 = Gait::from_bytes(bytes).unwrap();
    assert_eq!(v1.params(), &params);
    assert_eq!(v1.checkpoints().collect::<Vec<_>>(), records);
    assert_eq!(v1.arc_count(), 0);
    let v2 = encode(&params, &records);
    assert_eq!(v2.len(), gait::encoded_len(1, 0));
    let v2 = Gait::from_bytes(&v2).unwrap();
    assert_eq!(fly(v1.replay::<f32>()), fly(v2.replay::<f32>()));
    assert_eq!(
        fly(v1.replay_without_checkpoints::<f32>()),
        fly(v2.replay_without_checkpoints::<f32>())
    );
}
