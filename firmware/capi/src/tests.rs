//! The C API called as C calls it: a flight is the core's `Replay::fly` of the same gait, bit
//! for bit; a gait is refused with the code of the core's first error; every misuse gets its
//! code; every code in the header has its message.

use super::*;
use proptest::prelude::*;
use purcell_core::cost::RunningCost;
use purcell_core::gait::{WithReplay, crc32};
use purcell_core::{Error, Flight, Replay};
use std::boxed::Box;
use std::string::String;
use std::vec::Vec;

static PAPER: &[u8] = include_bytes!("../../../core/examples/paper.gait");
static LIMIT: &[u8] = include_bytes!("../../../core/examples/paper-limit.gait");
static POWER: &[u8] = include_bytes!("../../../core/examples/paper-power.gait");

/// A zeroed flight on the heap (as a C static is zeroed).
fn zeroed() -> Box<PurcellFlight> {
    Box::new(PurcellFlight {
        opaque: [0; PURCELL_FLIGHT_WORDS],
    })
}

/// Opens `bytes` (leaked: a flight borrows its gait for ever).
fn open_with(bytes: &[u8], options: u32) -> (Box<PurcellFlight>, PurcellStatus) {
    let bytes: &'static [u8] = Vec::leak(bytes.to_vec());
    let mut f = zeroed();
    let s = unsafe { purcell_flight_open(&mut *f, bytes.as_ptr(), bytes.len(), options) };
    (f, s)
}

fn read<T: Default>(
    f: &PurcellFlight,
    get: unsafe extern "C" fn(*const PurcellFlight, *mut T) -> PurcellStatus,
) -> Result<T, PurcellStatus> {
    let mut out = T::default();
    match unsafe { get(f, &mut out) } {
        PurcellStatus::Ok => Ok(out),
        s => Err(s),
    }
}

/// The core's flight of `bytes` in `f32`, through the law of its cost.
fn core_flight(bytes: &[u8]) -> (Gait<'_>, Flight<f32>, Vec<Sample<f32>>) {
    struct Fly;
    impl<'a> WithReplay<'a, f32> for Fly {
        type Output = (Flight<f32>, Vec<Sample<f32>>);
        fn run<C: RunningCost>(self, replay: Replay<'a, f32, C>) -> Self::Output {
            let samples = replay.clone().map(Result::unwrap).collect();
            (replay.fly(Replay::step).unwrap(), samples)
        }
    }
    let gait = Gait::from_bytes(bytes).unwrap();
    let (flight, samples) = gait.with_replay(true, Fly).unwrap();
    (gait, flight, samples)
}

/// The committed gaits (the paper's, its constrained one with arcs, and the power-optimal
/// one, which flies through the power's law): every sample, the digest, the final state and
/// the terminal error are the core's; without the digest option the flight is the same and
/// the digest is refused.
#[test]
fn a_flight_is_the_cores_flight() {
    for bytes in [PAPER, LIMIT, POWER] {
        let (gait, flight, samples) = core_flight(bytes);
        let (mut f, s) = open_with(bytes, PURCELL_OPTION_DIGEST);
        assert_eq!(s, PurcellStatus::Ok);
        assert_eq!(
            read(&f, purcell_flight_sample),
            Err(PurcellStatus::NoSample)
        );
        for expected in &samples {
            assert_eq!(unsafe { purcell_flight_step(&mut *f) }, PurcellStatus::Ok);
            assert_eq!(read(&f, purcell_flight_sample), Ok(sample(expected)));
        }
        assert_eq!(
            read(&f, purcell_flight_digest),
            Err(PurcellStatus::NotFinished)
        );
        assert_eq!(
            read(&f, purcell_flight_terminal_error),
            Err(PurcellStatus::NotFinished)
        );
        for _ in 0..2 {
            assert_eq!(
                unsafe { purcell_flight_step(&mut *f) },
                PurcellStatus::Finished
            );
        }
        assert_eq!(read(&f, purcell_flight_digest), Ok(flight.digest.value()));
        let end = read(&f, purcell_flight_state).unwrap();
        assert_eq!(end, state(&flight.end));
        let e = gait.params().terminal_error(&flight.end);
        let got = read(&f, purcell_flight_terminal_error).unwrap();
        assert_eq!((got.alpha, got.g), (e.alpha, e.g));
        let info = read(&f, purcell_flight_info).unwrap();
        assert_eq!(
            (info.steps, info.steps_done, info.crc, info.h),
            (flight.steps, flight.steps, gait.crc(), gait.params().h)
        );
        assert_eq!(info.arcs as usize, gait.arc_count());

        let (mut plain, _) = open_with(bytes, 0);
        while unsafe { purcell_flight_step(&mut *plain) } == PurcellStatus::Ok {}
        assert_eq!(read(&plain, purcell_flight_state), Ok(end));
        assert_eq!(
            read(&plain, purcell_flight_digest),
            Err(PurcellStatus::NoDigest)
        );
    }
}

/// What `purcell_flight_open` must answer for `bytes`: the core's first error, else Ok.
fn expected(bytes: &[u8]) -> PurcellStatus {
    struct Opened;
    impl<'a> WithReplay<'a, f32> for Opened {
        type Output = ();
        fn run<C: RunningCost>(self, _: Replay<'a, f32, C>) {}
    }
    match Gait::from_bytes(bytes).and_then(|g| g.with_replay(true, Opened)) {
        Ok(()) => PurcellStatus::Ok,
        Err(e) => e.into(),
    }
}

/// Recomputes the CRC after an edit, so the reader's later checks see it.
fn reseal(b: &mut [u8]) {
    let n = b.len() - 4;
    let crc = crc32(&b[..n]);
    b[n..].copy_from_slice(&crc.to_le_bytes());
}

proptest! {
    /// Any edit of a committed gait (resealed or not) is answered with the core's error, and a
    /// refused flight answers it to every call.
    #[test]
    fn a_gait_is_refused_as_the_core_refuses_it(
        limit in any::<bool>(),
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..4),
        sealed in any::<bool>(),
        cut in prop::option::of(any::<prop::sample::Index>()),
    ) {
        let mut b = if limit { LIMIT } else { PAPER }.to_vec();
        for (at, byte) in edits {
            let i = at.index(b.len());
            b[i] = byte;
        }
        if sealed {
            reseal(&mut b);
        }
        if let Some(cut) = cut {
            b.truncate(cut.index(b.len()));
        }
        let (mut f, s) = open_with(&b, PURCELL_OPTION_DIGEST);
        prop_assert_eq!(s, expected(&b));
        if s != PurcellStatus::Ok {
            prop_assert_eq!(unsafe { purcell_flight_step(&mut *f) }, s);
            prop_assert_eq!(read(&f, purcell_flight_state), Err(s));
        }
    }
}

/// Each of the core's errors has its own code, and its message is the core's.
#[test]
fn each_core_error_has_its_code_and_message() {
    let mut codes: Vec<i32> = status::CORE.iter().map(|&(_, s)| s as i32).collect();
    for (e, s) in status::CORE {
        assert_eq!(PurcellStatus::from(e), s);
        assert_eq!(PurcellStatus::message(s as i32), Some(e.message()));
    }
    assert_eq!(
        PurcellStatus::from(Error::GaitVersion(7)),
        PurcellStatus::GaitVersion
    );
    codes.sort_unstable();
    codes.dedup();
    assert_eq!(codes.len(), status::CORE.len());
}

/// Every `PURCELL_STATUS_*` of the committed header has a distinct value and a message, and
/// the header has them all.
#[test]
fn every_code_of_the_header_has_a_message() {
    let header = include_str!("../include/purcell.h");
    let mut values: Vec<i32> = header
        .lines()
        .filter_map(|l| l.trim().strip_prefix("PURCELL_STATUS_"))
        .map(|l| l.split(" = ").nth(1).unwrap().trim_end_matches(','))
        .map(|v| v.parse().unwrap())
        .collect();
    let codes = status::CORE.len() + status::OWN.len();
    assert_eq!(values.len(), codes);
    for &v in &values {
        assert!(
            PurcellStatus::message(v).is_some_and(|m| !m.is_empty()),
            "{v}"
        );
    }
    values.sort_unstable();
    values.dedup();
    assert_eq!(values.len(), codes);
    assert_eq!(PurcellStatus::message(2), None);
}

/// NULL, misaligned, unopened flights, unknown options, NULL outputs.
#[test]
fn misuse_gets_its_code() {
    let null = core::ptr::null_mut::<PurcellFlight>();
    let (p, n) = (PAPER.as_ptr(), PAPER.len());
    unsafe {
        assert_eq!(purcell_flight_open(null, p, n, 0), PurcellStatus::Null);
        assert_eq!(purcell_flight_step(null), PurcellStatus::Null);
        let mut f = zeroed();
        assert_eq!(purcell_flight_step(&mut *f), PurcellStatus::NotOpen);
        assert_eq!(read(&f, purcell_flight_info), Err(PurcellStatus::NotOpen));
        let misaligned = (&raw mut *f).cast::<u8>().add(4).cast::<PurcellFlight>();
        assert_eq!(
            purcell_flight_open(misaligned, p, n, 0),
            PurcellStatus::Misaligned
        );
        assert_eq!(purcell_flight_step(misaligned), PurcellStatus::Misaligned);
        assert_eq!(
            purcell_flight_open(&mut *f, core::ptr::null(), n, 0),
            PurcellStatus::Null
        );
        assert_eq!(purcell_flight_step(&mut *f), PurcellStatus::Null);
        assert_eq!(
            purcell_flight_open(&mut *f, p, n, 2),
            PurcellStatus::BadOptions
        );
        assert_eq!(purcell_flight_step(&mut *f), PurcellStatus::BadOptions);
        assert_eq!(purcell_flight_open(&mut *f, p, n, 0), PurcellStatus::Ok);
        assert_eq!(
            purcell_flight_state(&*f, core::ptr::null_mut()),
            PurcellStatus::Null
        );
    }
}

/// Messages are cut and NUL-terminated as `snprintf` does.
#[test]
fn messages_are_cut_like_snprintf() {
    let full = PurcellStatus::message(PurcellStatus::GaitChecksum as i32).unwrap();
    let code = PurcellStatus::GaitChecksum as i32;
    let mut buf = [0xffu8; 9];
    let n = unsafe { purcell_status_message(code, buf.as_mut_ptr().cast(), buf.len()) };
    assert_eq!(n, full.len());
    assert_eq!(&buf[..8], &full.as_bytes()[..8]);
    assert_eq!(buf[8], 0);
    let mut one = [0xffu8; 1];
    assert_eq!(
        unsafe { purcell_status_message(code, one.as_mut_ptr().cast(), 0) },
        full.len()
    );
    assert_eq!(one, [0xff]);
    assert_eq!(
        unsafe { purcell_status_message(7, one.as_mut_ptr().cast(), 1) },
        0
    );
    assert_eq!(one, [0]);
    let mut text = [0u8; 128];
    let n = unsafe { purcell_status_message(0, text.as_mut_ptr().cast(), text.len()) };
    assert_eq!(String::from_utf8_lossy(&text[..n]), "ok");
}
