//! A gait whose end shape differs from its start (version 4): written and read back as given,
//! with or without a tracking table; a loop (no end shape) is still the version-2/3 file byte
//! for byte; the end shape is validated like the start and is what the terminal error measures
//! against.

use crate::common;

use common::paper_gait;
use purcell_core::gait::{self, Gait, GaitParams};
use purcell_core::tracking::Record;
use purcell_core::{Error, State};

/// 10 steps of the paper's swimmer from `ᾱ = (0.3, −0.2)`, ending at `end`, no checkpoint.
fn params(end: Option<[f64; 2]>) -> GaitParams {
    GaitParams {
        checkpoint_every: 0,
        alpha0: [0.3, -0.2],
        alpha_end: end,
        ..paper_gait(10, [0.1, 0.0, 0.0], [0.1, 0.2, 0.0], [0.3, -0.1])
    }
}

fn encode(p: &GaitParams, tracking: &[(u32, Record<f32>)]) -> Result<Vec<u8>, Error> {
    let mut out = vec![0; gait::encoded_len_of(p, 0, 0, tracking.len())];
    let n = gait::encode_with_tracking(p, &[], &[], tracking, &mut out)?;
    assert_eq!(n, out.len());
    Ok(out)
}

#[test]
fn an_end_shape_is_version_4_and_read_back_as_written() {
    let end = Some([1.0, -0.75]);
    let bytes = encode(&params(end), &[]).unwrap();
    assert_eq!(bytes[8..10], gait::VERSION_END_SHAPE.to_le_bytes());
    assert_eq!(bytes.len(), gait::encoded_len(0, 0) + 16);
    let read = Gait::from_bytes(&bytes).unwrap();
    assert_eq!(*read.params(), params(end));
    assert!(read.tracking().is_none());
    // The end shape is the last 16 bytes of PARM (after α_max), before the CRC here.
    let at = bytes.len() - 4 - 16;
    assert_eq!(bytes[at..at + 8], 1.0f64.to_le_bytes());
    assert_eq!(bytes[at + 8..at + 16], (-0.75f64).to_le_bytes());

    let tracking: Vec<(u32, Record<f32>)> = vec![(0, [0.5; 18]), (4, [0.25; 18])];
    let bytes = encode(&params(end), &tracking).unwrap();
    assert_eq!(bytes[8..10], gait::VERSION_END_SHAPE.to_le_bytes());
    let read = Gait::from_bytes(&bytes).unwrap();
    assert_eq!(*read.params(), params(end));
    assert!(read.tracking().unwrap().iter().eq(tracking.iter().copied()));
}

#[test]
fn a_loop_is_the_version_2_or_3_file_as_before() {
    let bytes = encode(&params(None), &[]).unwrap();
    assert_eq!(bytes[8..10], gait::VERSION.to_le_bytes());
    assert_eq!(bytes.len(), gait::encoded_len(0, 0));
    let mut plain = vec![0; gait::encoded_len(0, 0)];
    gait::encode(&params(None), &[], &[], &mut plain).unwrap();
    assert_eq!(bytes, plain);
    assert_eq!(Gait::from_bytes(&bytes).unwrap().params().alpha_end, None);
    let tracked = encode(&params(None), &[(0, [1.0; 18])]).unwrap();
    assert_eq!(tracked[8..10], gait::VERSION_TRACKING.to_le_bytes());
}

#[test]
fn a_bad_end_shape_is_refused_like_the_start() {
    let refused = |end: [f64; 2], limit: Option<f64>| {
        let p = GaitParams {
            alpha_max: limit,
            ..params(Some(end))
        };
        encode(&p, &[]).err()
    };
    assert_eq!(refused([f64::NAN, 0.0], None), Some(Error::NonFinite));
    assert_eq!(refused([3.2, 0.0], None), Some(Error::ShapeLimit));
    assert_eq!(refused([1.2, 0.0], Some(1.0)), Some(Error::JointLimit));
    assert_eq!(refused([0.9, 0.0], Some(1.0)), None);
    // A version-4 file whose PARM record is cut to version 2's length is a layout error.
    let mut bytes = encode(&params(Some([1.0, 0.0])), &[]).unwrap();
    bytes[8..10].copy_from_slice(&gait::VERSION.to_le_bytes());
    let n = bytes.len() - 4;
    let crc = gait::crc32(&bytes[..n]);
    bytes[n..].copy_from_slice(&crc.to_le_bytes());
    assert_eq!(Gait::from_bytes(&bytes).err(), Some(Error::GaitLayout));
}

#[test]
fn the_terminal_error_is_against_the_end_shape() {
    let p = params(Some([1.0, -0.75]));
    let at = |a1: f64, a2: f64| {
        let mut s = State::at_origin(nalgebra::Vector2::new(a1, a2));
        s.g = purcell_core::Se2::new(0.1, 0.0, 0.0);
        p.terminal_error(&s)
    };
    assert_eq!(at(1.0, -0.75).alpha, 0.0);
    assert!((at(0.3, -0.2).alpha - 0.7).abs() < 1e-15);
    assert_eq!(params(None).end_shape(), [0.3, -0.2]);
}
