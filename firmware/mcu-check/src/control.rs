//! A control loop's log (`purcell_fly::pilot`: the gait flown cycle after cycle from a
//! periodic timer) against the host: each cycle's digest is the host's flight of the gait, and
//! each cycle's pose the host's composition `P_c = P_{c−1}·g_N` in the same precision; every
//! tick ran, none overran, and the worst ended within the period.

use crate::error::HostError;
use crate::log::{finished, key, need_line, parse_hex, parse_num, same, value};
use purcell_core::cost::RunningCost;
use purcell_core::gait::{Stored, WithReplay};
use purcell_core::{Error, Flight, Gait, Replay, Se2};
use purcell_fly::line;

/// One cycle's end as the host computes it: the digest and `x y cos θ sin θ` of the pose as
/// raw bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CycleBits {
    /// The cycle's digest.
    pub digest: u64,
    /// The pose after it.
    pub pose: [u64; 4],
}

/// The first `cycles` cycles of `gait` flown in `S` on the host: one flight of the gait (the
/// same `Gait::replay` and `Replay::fly` as `purcell-sim replay`), its end composed onto the
/// pose once per cycle), through the law of the gait's cost.
pub fn host_cycles<S: Stored>(gait: &Gait<'_>, cycles: u32) -> Result<Vec<CycleBits>, HostError> {
    /// One flight of a replay of any cost.
    struct Fly;
    impl<'a, S: Stored> WithReplay<'a, S> for Fly {
        type Output = Result<Flight<S>, Error>;
        fn run<C: RunningCost>(self, replay: Replay<'a, S, C>) -> Self::Output {
            replay.fly(Replay::step)
        }
    }
    let flight = gait.with_replay(true, Fly)??;
    let mut pose = Se2::<S>::identity();
    Ok((0..cycles)
        .map(|_| {
            pose = pose.compose(&flight.end.g);
            CycleBits {
                digest: flight.digest.value(),
                pose: [pose.x(), pose.y(), pose.cos(), pose.sin()].map(S::to_bits),
            }
        })
        .collect())
}

/// What a control loop reported.
#[derive(Debug, Clone, PartialEq)]
pub struct LoopLog {
    /// The board it ran on.
    pub board: String,
    /// `"f32"` or `"f64"`.
    pub scalar: String,
    /// Steps of one cycle.
    pub steps: u32,
    /// CRC-32 of the gait it flew.
    pub gait_crc: u32,
    /// `insn` or `cycles`.
    pub unit: String,
    /// The cycles, in the order logged.
    pub cycles: Vec<(u32, CycleBits)>,
    /// Cycles it set out to fly.
    pub planned: u32,
    /// Ticks run.
    pub ticks: u32,
    /// The worst tick, in `unit`.
    pub max: u64,
    /// The mean tick, in `unit`.
    pub mean: f64,
    /// The period, in `unit`.
    pub period: u64,
    /// Ticks that ran into the next period.
    pub overruns: u32,
}

impl LoopLog {
    /// Reads a decoded control-loop log. Errors: [`HostError::Log`] for a missing line or
    /// field, including `result: ok`.
    pub fn parse(text: &str) -> Result<Self, HostError> {
        let header = need_line(text, line::LOOP)?;
        let ticks = need_line(text, line::TICKS)?;
        let cycles = text
            .lines()
            .filter_map(|l| value(l, line::CYCLE))
            .map(|c| {
                let (_, rest) = c
                    .split_once("pose_bits=")
                    .ok_or_else(|| HostError::Log(format!("no `pose_bits=` in `{c}`")))?;
                let bits: Vec<u64> = rest
                    .split_whitespace()
                    .take(4)
                    .map(parse_hex)
                    .collect::<Result<_, _>>()?;
                let pose = bits
                    .try_into()
                    .map_err(|_| HostError::Log(format!("pose_bits needs 4 values in `{c}`")))?;
                let digest = parse_hex(key(c, "digest")?)?;
                Ok((parse_num(key(c, "n")?, "n")?, CycleBits { digest, pose }))
            })
            .collect::<Result<_, HostError>>()?;
        finished(text)?;
        let crc = parse_hex(key(header, "gait")?)?;
        Ok(LoopLog {
            board: key(header, "board")?.to_string(),
            scalar: key(header, "scalar")?.to_string(),
            steps: parse_num(key(header, "steps")?, "steps")?,
            gait_crc: u32::try_from(crc).map_err(|_| HostError::Log("gait crc".into()))?,
            unit: key(ticks, "unit")?.to_string(),
            cycles,
            planned: parse_num(key(header, "cycles")?, "cycles")?,
            ticks: parse_num(key(ticks, "count")?, "count")?,
            max: parse_num(key(ticks, "max")?, "max")?,
            mean: parse_num(key(ticks, "mean")?, "mean")?,
            period: parse_num(key(ticks, "period")?, "period")?,
            overruns: parse_num(key(ticks, "overruns")?, "overruns")?,
        })
    }
}

/// Compares a control loop's log with the host: same gait, every planned cycle logged once in
/// order with the host's digest and pose bits ([`host_cycles`]), one tick per step of every
/// cycle, no overrun, the worst tick within the period. Errors: [`HostError::Mismatch`]
/// naming the first failure.
pub fn check_loop(log: &LoopLog, gait: &Gait<'_>) -> Result<(), HostError> {
    same(log.gait_crc, gait.crc(), |f, h| {
        format!("the loop flew gait {f:#010x}, the host's file is {h:#010x}")
    })?;
    let host = match log.scalar.as_str() {
        "f32" => host_cycles::<f32>(gait, log.planned)?,
        "f64" => host_cycles::<f64>(gait, log.planned)?,
        other => return Err(HostError::Log(format!("unknown scalar `{other}`"))),
    };
    let logged: Vec<u32> = log.cycles.iter().map(|(n, _)| *n).collect();
    same(logged, (1..=log.planned).collect(), |f, h| {
        format!("cycles logged {f:?}, planned {h:?}")
    })?;
    for ((n, mcu), host) in log.cycles.iter().zip(&host) {
        same(mcu, host, |f, h| {
            format!("cycle {n}: the loop says {f:x?}, the host {h:x?}")
        })?;
    }
    same(log.ticks, log.planned * log.steps, |f, h| {
        format!("{f} ticks for {h} steps")
    })?;
    same(log.overruns, 0, |f, _| format!("{f} ticks overran"))?;
    if log.max >= log.period {
        return Err(HostError::Mismatch(format!(
            "the worst tick took {} {}, the period is {}",
            log.max, log.unit, log.period
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper() -> Gait<'static> {
        Gait::from_bytes(include_bytes!("../../../core/examples/paper.gait")).unwrap()
    }

    /// A log as the loop prints it, from the host's cycles.
    fn log_text(gait: &Gait<'_>, cycles: &[CycleBits], overruns: u32) -> String {
        let mut text = format!(
            "purcell-loop: board=test scalar=f32 steps=10000 h=0.01 period=156250 unit=insn cycles={} gait={:#010x}\n",
            cycles.len(),
            gait.crc()
        );
        for (n, c) in cycles.iter().enumerate() {
            let [x, y, cos, sin] = c.pose;
            text += &format!(
                "cycle: n={} digest={:#018x} pose_bits={x:#x} {y:#x} {cos:#x} {sin:#x} x=0 y=0 theta=0\n",
                n + 1,
                c.digest
            );
        }
        text += &format!(
            "ticks: unit=insn count={} mean=890.0 max=1300 period=156250 margin=154950 overruns={overruns}\nresult: ok\n",
            10_000 * cycles.len()
        );
        text
    }

    #[test]
    fn a_loop_matches_the_host_cycle_after_cycle() {
        let gait = paper();
        let host = host_cycles::<f32>(&gait, 3).unwrap();
        // Left-invariance: every cycle has the one flight's digest, the pose moves on.
        assert!(host.iter().all(|c| c.digest == host[0].digest));
        assert_ne!(host[0].pose, host[2].pose);
        let log = LoopLog::parse(&log_text(&gait, &host, 0)).unwrap();
        assert_eq!(log.cycles.len(), 3);
        check_loop(&log, &gait).unwrap();

        let mut moved = host.clone();
        moved[2].pose[1] ^= 1;
        let log = LoopLog::parse(&log_text(&gait, &moved, 0)).unwrap();
        assert!(
            matches!(check_loop(&log, &gait), Err(HostError::Mismatch(m)) if m.contains("cycle 3"))
        );

        let log = LoopLog::parse(&log_text(&gait, &host, 2)).unwrap();
        assert!(
            matches!(check_loop(&log, &gait), Err(HostError::Mismatch(m)) if m.contains("overran"))
        );

        let log = LoopLog::parse(&log_text(&gait, &host[..2], 0).replace("cycles=2", "cycles=3"))
            .unwrap();
        assert!(check_loop(&log, &gait).is_err());
    }
}
