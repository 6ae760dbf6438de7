//! The gait file's tracking table (section `TRCK`, version 3): written and read back as given,
//! walked step by step by its cursor, refused with its typed error when its indices or values
//! are wrong; without one, the file is the version-2 file as before.

use crate::common;
use purcell_core::Error;

use common::paper_gait;
use purcell_core::gait::{self, Gait, GaitParams, TRACKING_RECORD_LEN};
use purcell_core::tracking::{RECORD_VALUES, Record};

/// 10 steps of the paper's swimmer, no checkpoint.
fn params() -> GaitParams {
    GaitParams {
        checkpoint_every: 0,
        ..paper_gait(10, [0.1, 0.0, 0.0], [0.1, 0.2, 0.0], [0.3, -0.1])
    }
}

/// Records at `starts`, record `j`'s values `j + i/100`.
fn records(starts: &[u32]) -> Vec<(u32, Record<f32>)> {
    starts
        .iter()
        .enumerate()
        .map(|(j, &k)| (k, core::array::from_fn(|i| j as f32 + i as f32 / 100.0)))
        .collect()
}

fn encode(tracking: &[(u32, Record<f32>)]) -> Result<Vec<u8>, Error> {
    let mut out = vec![0; gait::encoded_len_with_tracking(0, 0, tracking.len())];
    gait::encode_with_tracking(&params(), &[], &[], tracking, &mut out).map(|_| out)
}

/// The file with its CRC recomputed.
fn reseal(mut bytes: Vec<u8>) -> Vec<u8> {
    let body = bytes.len() - 4;
    let crc = gait::crc32(&bytes[..body]);
    bytes[body..].copy_from_slice(&crc.to_le_bytes());
    bytes
}

/// Where the `TRCK` records start in a file without checkpoints or arcs: after the header,
/// five directory entries and `PARM` (the version-2 file less its CRC, plus an entry).
const TABLE_AT: usize = gait::encoded_len(0, 0) - 4 + 16;

#[test]
fn a_tracking_table_is_read_back_as_written_and_walked_by_step() {
    let written = records(&[0, 3, 4, 9]);
    let bytes = encode(&written).unwrap();
    assert_eq!(bytes[8..10], gait::VERSION_TRACKING.to_le_bytes());
    assert_eq!(
        bytes.len(),
        gait::encoded_len(0, 0) + 16 + 4 * TRACKING_RECORD_LEN
    );
    let gait = Gait::from_bytes(&bytes).unwrap();
    let table = gait.tracking().unwrap();
    assert_eq!(table.len(), 4);
    assert!(table.iter().eq(written.iter().copied()));
    // The cursor: the record in force at each step, and whether the step starts it.
    let mut cursor = table.cursor();
    let walked: Vec<(f32, bool)> = (0..10)
        .map(|k| {
            let (r, first) = cursor.at(k);
            (r[0], first)
        })
        .collect();
    let expected = [0, 0, 0, 1, 2, 2, 2, 2, 2, 3].map(|j| j as f32);
    let firsts = [
        true, false, false, true, true, false, false, false, false, true,
    ];
    assert!(walked.iter().map(|w| w.0).eq(expected));
    assert!(walked.iter().map(|w| w.1).eq(firsts));
}

#[test]
fn without_a_tracking_table_the_file_is_version_2_as_before() {
    let mut plain = vec![0; gait::encoded_len(0, 0)];
    gait::encode(&params(), &[], &[], &mut plain).unwrap();
    assert_eq!(encode(&[]).unwrap(), plain);
    assert_eq!(plain[8..10], gait::VERSION.to_le_bytes());
    assert!(Gait::from_bytes(&plain).unwrap().tracking().is_none());
}

#[test]
fn bad_indices_and_values_are_refused_on_writing_and_on_reading() {
    let mut nan = records(&[0, 5]);
    nan[1].1[RECORD_VALUES - 1] = f32::NAN;
    for (starts, error) in [
        (&[1u32, 5][..], Error::GaitLayout),
        (&[0, 5, 5], Error::GaitLayout),
        (&[0, 6, 5], Error::GaitLayout),
        (&[0, 10], Error::GaitLayout),
    ] {
        assert_eq!(encode(&records(starts)).err(), Some(error), "{starts:?}");
    }
    assert_eq!(encode(&nan).err(), Some(Error::NonFinite));

    // The same mistakes in a file: k_1 rewritten, a value rewritten.
    let good = encode(&records(&[0, 5])).unwrap();
    let second = TABLE_AT + TRACKING_RECORD_LEN;
    for (k, error) in [(0u32, Error::GaitLayout), (10, Error::GaitLayout)] {
        let mut bad = good.clone();
        bad[second..second + 4].copy_from_slice(&k.to_le_bytes());
        assert_eq!(Gait::from_bytes(&reseal(bad)).err(), Some(error), "k = {k}");
    }
    let mut bad = good.clone();
    bad[second + 4..second + 8].copy_from_slice(&f32::INFINITY.to_le_bytes());
    assert_eq!(Gait::from_bytes(&reseal(bad)).err(), Some(Error::NonFinite));
}

#[test]
fn the_section_belongs_to_version_3_only() {
    let good = encode(&records(&[0])).unwrap();
    // Version 2 with a TRCK section, version 3 without one (one section fewer), an empty table.
    let mut v2 = good.clone();
    v2[8..10].copy_from_slice(&gait::VERSION.to_le_bytes());
    let mut fewer = good.clone();
    fewer[10..12].copy_from_slice(&4u16.to_le_bytes());
    let entry = 16 + 4 * 16;
    assert_eq!(&good[entry..entry + 4], b"TRCK");
    let mut empty = good.clone();
    empty[entry + 8..entry + 12].copy_from_slice(&0u32.to_le_bytes());
    let mut size = good;
    size[entry + 12..entry + 16].copy_from_slice(&72u32.to_le_bytes());
    for bad in [v2, fewer, empty, size] {
        assert_eq!(
            Gait::from_bytes(&reseal(bad)).err(),
            Some(Error::GaitLayout)
        );
    }
}
