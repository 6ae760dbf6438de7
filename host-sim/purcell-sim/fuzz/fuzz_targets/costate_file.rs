//! The costate-file reader on arbitrary bytes: `CostateFile::parse` and the checks `replay`
//! runs never panic; a file they accept round-trips bit for bit, and short ones replay
//! through the core with finite results or a typed failure.
#![no_main]

use purcell_sim::costate_file::CostateFile;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(file) = CostateFile::parse(text) else {
        return;
    };
    let again = CostateFile::parse(&file.to_json()).expect("an accepted file round-trips");
    assert_eq!(again, file);
    let checkpoints = file.checkpoints.iter().copied();
    if file.problem().is_err()
        || purcell_solver::problem::check_gait_precision::<f32>(&file.gait, checkpoints, "f32").is_err()
    {
        return;
    }
    if file.steps <= 1000 {
        let bytes = file.to_gait().expect("an accepted file encodes");
        let gait = purcell_core::Gait::from_bytes(&bytes).expect("its gait decodes");
        for r in purcell_sim::replay::standard_replays(&gait) {
            match (&r.failure, r.alpha_error, r.g_error) {
                (None, Some(a), Some(g)) => assert!(a.is_finite() && g.is_finite(), "{r:?}"),
                (Some(_), None, None) => {}
                _ => panic!("inconsistent replay result {r:?}"),
            }
        }
    }
});
