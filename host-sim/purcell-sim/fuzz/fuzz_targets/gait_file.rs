//! The gait-file reader on arbitrary bytes: `Gait::from_bytes` and the checks `replay --gait`
//! runs never panic; a gait they accept encodes back to the same numbers, and short ones
//! replay through the core with finite results or a typed failure. Each input is also read
//! with its length field and checksum rewritten, so that mutations reach past the CRC.
#![no_main]

use libfuzzer_sys::fuzz_target;
use purcell_core::{Gait, gait};
use purcell_solver::problem::{Problem, check_gait_precision};

fuzz_target!(|data: &[u8]| {
    read(data);
    // Header: magic (8 bytes), version, section count (u16 each), length (u32); CRC at the end.
    if let Some(len) = u32::try_from(data.len()).ok().filter(|&n| n >= 20) {
        let mut fixed = data.to_vec();
        fixed[12..16].copy_from_slice(&len.to_le_bytes());
        let body = fixed.len() - 4;
        let crc = gait::crc32(&fixed[..body]);
        fixed[body..].copy_from_slice(&crc.to_le_bytes());
        read(&fixed);
    }
});

fn read(bytes: &[u8]) {
    let Ok(gait) = Gait::from_bytes(bytes) else {
        return;
    };
    // Encoded again (the current version, no gaps): the same numbers.
    let checkpoints: Vec<_> = gait.checkpoints().collect();
    let arcs: Vec<_> = gait.arcs().collect();
    let tracking: Vec<_> = gait.tracking().iter().flat_map(|t| t.iter()).collect();
    let mut again =
        vec![0; gait::encoded_len_with_tracking(checkpoints.len(), arcs.len(), tracking.len())];
    gait::encode_with_tracking(gait.params(), &checkpoints, &arcs, &tracking, &mut again)
        .expect("an accepted gait encodes");
    let back = Gait::from_bytes(&again).expect("its encoding decodes");
    assert_eq!(back.params(), gait.params());
    assert!(back.checkpoints().eq(checkpoints.iter().copied()));
    assert!(back.arcs().eq(arcs.iter().copied()));
    let bits = |t: Vec<(u32, [f32; 18])>| {
        t.into_iter()
            .map(|(k, r)| (k, r.map(f32::to_bits)))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        bits(back.tracking().iter().flat_map(|t| t.iter()).collect()),
        bits(tracking)
    );
    let params = gait.params();
    if Problem::of_gait(params).is_err()
        || check_gait_precision::<f32>(params, gait.checkpoints(), "f32").is_err()
    {
        return;
    }
    if params.steps <= 1000 {
        for r in purcell_sim::replay::standard_replays(&gait) {
            match (&r.failure, r.alpha_error, r.g_error) {
                (None, Some(a), Some(g)) => assert!(a.is_finite() && g.is_finite(), "{r:?}"),
                (Some(_), None, None) => {}
                _ => panic!("inconsistent replay result {r:?}"),
            }
        }
    }
}
