//! A firmware log (decoded by `defmt-print --log-format '{s}'`: one result per line,
//! `name: key=value …`, as `purcell_fly` prints them, named in [`line`](mod@line)) and its
//! check against the host's flight.
//!
//! The QEMU firmware reports `insn_per_step` (instructions, exact under `-icount`) and the
//! step's stack; a board reports `cycles_per_step` (its cycle counter) and no stack.

use crate::error::HostError;
use crate::reference::Reference;
use purcell_fly::line;

/// What the per-step figures count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unit {
    /// Instructions (QEMU `-icount`).
    Instructions,
    /// Core clock cycles (a board's DWT counter).
    Cycles,
}

/// The per-step figures split between the steps on a joint-limit arc and the others.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Split {
    /// Steps with a joint at rest on an arc.
    pub steps: u32,
    /// Their mean.
    pub mean: f64,
    /// Their largest.
    pub max: u32,
    /// Mean of the other steps.
    pub free_mean: f64,
    /// Largest of the other steps.
    pub free_max: u32,
}

/// What a firmware run reported.
#[derive(Debug, Clone, PartialEq)]
pub struct FirmwareLog {
    /// The board (or QEMU machine) the firmware says it ran on.
    pub board: String,
    /// `"f32"` or `"f64"`.
    pub scalar: String,
    /// Steps replayed.
    pub steps: u32,
    /// CRC-32 of the gait it flew.
    pub gait_crc: u32,
    /// What the per-step figures count.
    pub unit: Unit,
    /// Mean per step.
    pub mean: f64,
    /// Largest single step.
    pub max: u32,
    /// The same over the steps on a joint-limit arc ([`Split`]).
    pub arcs: Split,
    /// Deepest stack use of one step, bytes (measured by the QEMU harness only).
    pub stack_bytes: Option<u32>,
    /// Trajectory digest.
    pub digest: u64,
    /// Final state bits.
    pub final_bits: [u64; 6],
}

/// What follows `<name>:` on line `l`, if `l` is that line.
pub(crate) fn value<'a>(l: &'a str, name: &str) -> Option<&'a str> {
    l.trim()
        .strip_prefix(name)
        .and_then(|rest| rest.strip_prefix(':'))
        .map(str::trim)
}

/// What follows `<name>:` on the first line of that name.
pub(crate) fn find_line<'a>(text: &'a str, name: &str) -> Option<&'a str> {
    text.lines().find_map(|l| value(l, name))
}

pub(crate) fn need_line<'a>(text: &'a str, name: &str) -> Result<&'a str, HostError> {
    find_line(text, name).ok_or_else(|| HostError::Log(format!("no line starting with `{name}:`")))
}

/// `Ok` if the log has the `result: ok` line (the firmware finished).
pub(crate) fn finished(text: &str) -> Result<(), HostError> {
    if text
        .lines()
        .any(|l| value(l, line::RESULT) == Some(line::OK))
    {
        Ok(())
    } else {
        Err(HostError::Log(format!(
            "no `{}: {}` line",
            line::RESULT,
            line::OK
        )))
    }
}

pub(crate) fn key<'a>(rest: &'a str, name: &str) -> Result<&'a str, HostError> {
    rest.split_whitespace()
        .find_map(|kv| kv.strip_prefix(name).and_then(|v| v.strip_prefix('=')))
        .ok_or_else(|| HostError::Log(format!("no `{name}=` in `{rest}`")))
}

pub(crate) fn parse_num<T: std::str::FromStr>(s: &str, what: &str) -> Result<T, HostError> {
    s.parse()
        .map_err(|_| HostError::Log(format!("`{what}`: cannot parse `{s}`")))
}

pub(crate) fn parse_hex(s: &str) -> Result<u64, HostError> {
    let digits = s
        .strip_prefix("0x")
        .ok_or_else(|| HostError::Log(format!("`{s}` is not 0x-prefixed hex")))?;
    u64::from_str_radix(digits, 16).map_err(|_| HostError::Log(format!("bad hex `{s}`")))
}

impl FirmwareLog {
    /// Reads a decoded firmware log. Errors: [`HostError::Log`] for a missing line or field,
    /// including a missing `result: ok` (the firmware did not finish), both or neither of the
    /// per-step lines, or an instruction count without the stack line.
    pub fn parse(text: &str) -> Result<Self, HostError> {
        let header = need_line(text, line::HEADER)?;
        let (unit, counts) = match (find_line(text, line::INSN), find_line(text, line::CYCLES)) {
            (Some(c), None) => (Unit::Instructions, c),
            (None, Some(c)) => (Unit::Cycles, c),
            _ => {
                return Err(HostError::Log(format!(
                    "need exactly one of `{}:` and `{}:`",
                    line::INSN,
                    line::CYCLES
                )));
            }
        };
        let stack_bytes = match find_line(text, line::STACK) {
            Some(s) => Some(parse_num(key(s, "bytes")?, "bytes")?),
            None if unit == Unit::Instructions => {
                return Err(HostError::Log(format!(
                    "no line starting with `{}:`",
                    line::STACK
                )));
            }
            None => None,
        };
        let bits: Vec<u64> = need_line(text, line::FINAL)?
            .split_whitespace()
            .map(parse_hex)
            .collect::<Result<_, _>>()?;
        let final_bits: [u64; 6] = bits
            .try_into()
            .map_err(|_| HostError::Log("final_state_bits needs 6 values".into()))?;
        finished(text)?;
        let crc = parse_hex(key(header, "gait")?)?;
        let arcs = need_line(text, line::ARCS)?;
        Ok(FirmwareLog {
            board: key(header, "board")?.to_string(),
            scalar: key(header, "scalar")?.to_string(),
            steps: parse_num(key(header, "steps")?, "steps")?,
            gait_crc: u32::try_from(crc).map_err(|_| HostError::Log("gait crc".into()))?,
            unit,
            mean: parse_num(key(counts, "mean")?, "mean")?,
            max: parse_num(key(counts, "max")?, "max")?,
            arcs: Split {
                steps: parse_num(key(arcs, "steps")?, "steps")?,
                mean: parse_num(key(arcs, "mean")?, "mean")?,
                max: parse_num(key(arcs, "max")?, "max")?,
                free_mean: parse_num(key(arcs, "free_mean")?, "free_mean")?,
                free_max: parse_num(key(arcs, "free_max")?, "free_max")?,
            },
            stack_bytes,
            digest: parse_hex(need_line(text, line::DIGEST)?)?,
            final_bits,
        })
    }
}

/// The limits a firmware run must meet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    /// Largest allowed mean instructions per step (instruction logs).
    pub insn: f64,
    /// Largest allowed instructions of a single step (instruction logs): a step that
    /// restores a checkpoint also reads it from the gait's table.
    pub insn_step: f64,
    /// Largest allowed cycles per step, likewise (cycle logs; `None`: report only).
    pub cycles: Option<f64>,
    /// Largest allowed stack use of a step, bytes (when the log has it).
    pub stack_bytes: u32,
}

/// Compares a firmware log with the host's flight of the same gait: same gait (CRC),
/// precision, step count, digest and final bits, the budget met, and the steps on a
/// joint-limit arc no dearer than the free ones (mean and largest). Errors:
/// [`HostError::Mismatch`] naming the first failure.
pub fn check(log: &FirmwareLog, reference: &Reference, budget: &Budget) -> Result<(), HostError> {
    same_flight(log, reference)?;
    within_budget(log, budget)
}

/// `Ok` if the firmware and the host say the same, else the mismatch `say(firmware, host)`.
pub(crate) fn same<T: PartialEq>(
    firmware: T,
    host: T,
    say: impl FnOnce(T, T) -> String,
) -> Result<(), HostError> {
    if firmware == host {
        Ok(())
    } else {
        Err(HostError::Mismatch(say(firmware, host)))
    }
}

/// The firmware flew what the host flew: the same gait, precision and step count, bit for bit.
fn same_flight(log: &FirmwareLog, reference: &Reference) -> Result<(), HostError> {
    same(log.gait_crc, reference.gait_crc, |f, h| {
        format!(
            "the firmware flew gait {f:#010x}, the host replayed gait {h:#010x} (pass the \
             firmware's gait with --gait)"
        )
    })?;
    same(log.scalar.as_str(), reference.scalar, |f, h| {
        format!("firmware ran {f}, reference is {h}")
    })?;
    same(log.steps, reference.steps, |f, h| {
        format!("firmware ran {f} steps, host {h}")
    })?;
    same(log.digest, reference.digest, |f, h| {
        format!("digest: firmware {f:#018x}, host {h:#018x}")
    })?;
    same(log.final_bits, reference.final_bits, |f, h| {
        format!("final state bits: firmware {f:x?}, host {h:x?}")
    })
}

/// The per-step figures, the arc steps and the stack within `budget`.
fn within_budget(log: &FirmwareLog, budget: &Budget) -> Result<(), HostError> {
    let mismatch = |m: String| Err(HostError::Mismatch(m));
    let (limits, what) = match log.unit {
        Unit::Instructions => (Some((budget.insn, budget.insn_step)), "instructions"),
        Unit::Cycles => (budget.cycles.map(|c| (c, c)), "cycles"),
    };
    if let Some((mean, step)) = limits {
        if log.mean.is_nan() || log.mean > mean {
            return mismatch(format!(
                "mean {what} per step {} above the budget {mean}",
                log.mean
            ));
        }
        if f64::from(log.max) > step {
            return mismatch(format!(
                "largest step {} {what}, above the budget {step}",
                log.max
            ));
        }
    }
    let a = &log.arcs;
    // Arc steps run the law's other row only: on average no dearer than free steps (their
    // largest, like every step's, is held to the per-step budget above; a step that also
    // restores a checkpoint can land a few instructions either side of the free maximum).
    if a.steps > 0 && a.mean > a.free_mean {
        return mismatch(format!(
            "steps on a joint-limit arc cost more than free steps on average: {} > {}",
            a.mean, a.free_mean
        ));
    }
    if let Some(stack) = log.stack_bytes
        && stack > budget.stack_bytes
    {
        return mismatch(format!(
            "stack of a step {stack} B above the budget {} B",
            budget.stack_bytes
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use purcell_core::Gait;

    const QEMU_LOG: &str = "\
insn_calibration: overhead_ticks=3 0nop+read=1 1000nop+read=1001 2000nop+read=2001
purcell-mcu: board=mps2-an386 scalar=f32 steps=10000 passes=2 checkpoints=99 arcs=0 gait=0x77b998a7
insn_per_step: mean=812.5 max=845
arc_steps: steps=0 mean=0.0 max=0 free_mean=812.5 free_max=845
replay_total: steps=10000 units=8125000
stack_step: bytes=312
digest: 0x000000deadbeef01
final_state_bits: 0x1 0x2 0x3 0x4 0x5 0x6
result: ok
";

    #[test]
    fn firmware_log_parses_and_needs_every_line() {
        let log = FirmwareLog::parse(QEMU_LOG).unwrap();
        assert_eq!(
            (log.board.as_str(), log.scalar.as_str()),
            ("mps2-an386", "f32")
        );
        assert_eq!((log.steps, log.gait_crc), (10000, 0x77b9_98a7));
        assert_eq!(
            (log.unit, log.mean, log.max),
            (Unit::Instructions, 812.5, 845)
        );
        assert_eq!((log.stack_bytes, log.digest), (Some(312), 0xdead_beef01));
        assert_eq!(log.final_bits, [1, 2, 3, 4, 5, 6]);
        for drop in [1, 2, 3, 5, 6, 7, 8] {
            let text: Vec<&str> = QEMU_LOG
                .lines()
                .enumerate()
                .filter(|&(i, _)| i != drop)
                .map(|(_, l)| l)
                .collect();
            assert!(
                matches!(FirmwareLog::parse(&text.join("\n")), Err(HostError::Log(_))),
                "line {drop}"
            );
        }
        assert!(FirmwareLog::parse(&QEMU_LOG.replace("0x6", "0x6 0x7")).is_err());
        assert!(FirmwareLog::parse(&QEMU_LOG.replace("0x000000deadbeef01", "deadbeef01")).is_err());
        assert!(FirmwareLog::parse(&QEMU_LOG.replace(" gait=0x77b998a7", "")).is_err());
        let both = QEMU_LOG.replace("stack_step", "cycles_per_step: mean=1 max=1\nstack_step");
        assert!(FirmwareLog::parse(&both).is_err());
    }

    /// A board's log: cycles instead of instructions, no stack line, RTT noise around it.
    #[test]
    fn a_board_log_with_cycles_parses() {
        let board = QEMU_LOG
            .replace("insn_calibration: overhead_ticks=3 0nop+read=1 1000nop+read=1001 2000nop+read=2001\n", "")
            .replace("board=mps2-an386", "board=stm32f4-discovery")
            .replace("insn_per_step: mean=812.5 max=845", "cycles_per_step: mean=1134.2 max=1203")
            .replace("stack_step: bytes=312\n", "");
        let text = format!(
            "      Erasing ✔ 100% [####################]\n{board}Firmware exited successfully\n"
        );
        let log = FirmwareLog::parse(&text).unwrap();
        assert_eq!((log.unit, log.mean, log.max), (Unit::Cycles, 1134.2, 1203));
        assert_eq!(
            (log.board.as_str(), log.stack_bytes),
            ("stm32f4-discovery", None)
        );
    }

    /// Within budget on every figure.
    const BUDGET: Budget = Budget {
        insn: 1000.0,
        insn_step: 1100.0,
        cycles: Some(2000.0),
        stack_bytes: 2048,
    };

    /// The host's flight of the paper's gait in f32, and the log of a firmware that flew it
    /// within [`BUDGET`].
    fn paper_flight() -> (Reference, FirmwareLog) {
        let gait = Gait::from_bytes(include_bytes!("../../../core/examples/paper.gait")).unwrap();
        let reference = Reference::for_scalar(&gait, "f32").unwrap();
        let log = FirmwareLog {
            board: "mps2-an386".into(),
            scalar: "f32".into(),
            steps: reference.steps,
            gait_crc: gait.crc(),
            unit: Unit::Instructions,
            mean: 900.0,
            max: 950,
            arcs: Split {
                steps: 0,
                mean: 0.0,
                max: 0,
                free_mean: 900.0,
                free_max: 950,
            },
            stack_bytes: Some(300),
            digest: reference.digest,
            final_bits: reference.final_bits,
        };
        (reference, log)
    }

    /// `log` with 500 steps on joint-limit arcs, of the given mean and largest.
    fn on_arcs(log: &FirmwareLog, mean: f64, max: u32) -> FirmwareLog {
        FirmwareLog {
            arcs: Split {
                steps: 500,
                mean,
                max,
                ..log.arcs
            },
            ..log.clone()
        }
    }

    /// `log` as a board's: cycles within [`BUDGET`], no stack line.
    fn in_cycles(log: &FirmwareLog) -> FirmwareLog {
        FirmwareLog {
            unit: Unit::Cycles,
            mean: 1500.0,
            max: 1999,
            stack_bytes: None,
            ..log.clone()
        }
    }

    #[test]
    fn the_host_flight_within_budget_passes() {
        let (reference, log) = paper_flight();
        let cycles = in_cycles(&log);
        let unbudgeted = Budget {
            cycles: None,
            ..BUDGET
        };
        let passing = [
            (log.clone(), BUDGET),
            (on_arcs(&log, 880.0, 950), BUDGET),
            // The largest step on the per-step budget.
            (FirmwareLog { max: 1100, ..log }, BUDGET),
            (cycles.clone(), BUDGET),
            (
                FirmwareLog {
                    max: 99_999,
                    ..cycles
                },
                unbudgeted,
            ),
        ];
        for (log, budget) in passing {
            check(&log, &reference, &budget).unwrap();
        }
    }

    #[test]
    fn another_flight_is_refused() {
        let (reference, log) = paper_flight();
        let mut bits = log.final_bits;
        bits[5] ^= 1;
        let others = [
            FirmwareLog {
                digest: log.digest ^ 1,
                ..log.clone()
            },
            FirmwareLog {
                final_bits: bits,
                ..log.clone()
            },
            FirmwareLog {
                gait_crc: log.gait_crc ^ 1,
                ..log.clone()
            },
            FirmwareLog {
                scalar: "f64".into(),
                ..log.clone()
            },
            FirmwareLog {
                steps: 9999,
                ..log.clone()
            },
        ];
        for other in others {
            assert!(
                matches!(
                    check(&other, &reference, &BUDGET),
                    Err(HostError::Mismatch(_))
                ),
                "{other:?}"
            );
        }
    }

    #[test]
    fn a_figure_above_its_budget_is_refused() {
        let (reference, log) = paper_flight();
        let over = [
            FirmwareLog {
                mean: 1000.1,
                ..log.clone()
            },
            FirmwareLog {
                mean: f64::NAN,
                ..log.clone()
            },
            FirmwareLog {
                max: 1101,
                ..log.clone()
            },
            FirmwareLog {
                stack_bytes: Some(4096),
                ..log.clone()
            },
            FirmwareLog {
                max: 2001,
                ..in_cycles(&log)
            },
            // Arc steps dearer than the free ones on average.
            on_arcs(&log, 900.1, 900),
        ];
        for o in over {
            assert!(
                matches!(check(&o, &reference, &BUDGET), Err(HostError::Mismatch(_))),
                "{o:?}"
            );
        }
    }
}
