//! Replays a committed gait on the host exactly as firmware flies it: the file that
//! `purcell-sim export` wrote, embedded with `include_bytes!`, read in place, replayed in `f32`
//! (what a Cortex-M4F flies) and in `f64`.
//!
//! `cargo run -p purcell-core --example replay_gait`

use purcell_core::{Gait, Replay};

/// The paper's gait: `ḡ = (0.1, 0.1, 0)`, `N = 10 000` steps of `h = 0.01 s`, checkpoints
/// every 100 steps.
static GAIT: &[u8] = include_bytes!("paper.gait");

fn main() -> Result<(), purcell_core::Error> {
    let gait = Gait::from_bytes(GAIT)?;
    let p = gait.params();
    println!(
        "gait: {} steps of {} s to target {:?}, {} checkpoints, crc {:#010x}",
        p.steps,
        p.h,
        p.target,
        gait.checkpoint_count(),
        gait.crc()
    );

    // As a control loop runs it: one step at a time, each lending its control u_k.
    let mut replay = gait.replay::<f32>()?;
    let mut fastest = 0.0f32;
    while let Some(sample) = replay.step()? {
        fastest = fastest.max(sample.u.x.abs()).max(sample.u.y.abs());
    }
    println!("f32: largest joint speed |u_i| = {fastest:.3} rad/s");

    // The whole flight, digested: the numbers to compare with a microcontroller's log.
    let f32_flight = gait.replay::<f32>()?.fly(Replay::step)?;
    let f64_flight = gait.replay::<f64>()?.fly(Replay::step)?;
    for (name, digest, error) in [
        ("f32", f32_flight.digest, p.terminal_error(&f32_flight.end)),
        ("f64", f64_flight.digest, p.terminal_error(&f64_flight.end)),
    ] {
        println!(
            "{name}: digest: {:#018x}, ends {:.1e} rad from alpha0 and {:.1e} (m, rad) from the target",
            digest.value(),
            error.alpha,
            error.g
        );
    }
    Ok(())
}
