//! Host side: the `f32`/`f64` reference replay, the check of a firmware log against it, and
//! the analysis of the firmware's disassembly (soft-float helpers, code size of the step).
//!
//! The firmware's decoded log (defmt-print with `--log-format {s}`) has one result per line,
//! `name: key=value key=value …`; [`FirmwareLog::parse`] reads the lines this crate writes.

use crate::{Outcome, Problem, Scalar, replay_digest};
use purcell_core::{Error, Real, Replay, Se2, State};
use std::collections::{BTreeMap, BTreeSet};
use std::string::{String, ToString};
use std::vec::Vec;
use std::{fmt, format, vec};

/// Why a host-side check failed.
#[derive(Debug, Clone, PartialEq)]
pub enum HostError {
    /// The core refused the problem or a step failed.
    Core(Error),
    /// The firmware log lacks a line or a field, or a value does not parse.
    Log(String),
    /// The firmware and the host disagree, or a budget is exceeded.
    Mismatch(String),
    /// The disassembly lacks the root function, or reaches what it must not.
    Disassembly(String),
}

impl fmt::Display for HostError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HostError::Core(e) => write!(f, "core: {e}"),
            HostError::Log(m) => write!(f, "firmware log: {m}"),
            HostError::Mismatch(m) => write!(f, "mismatch: {m}"),
            HostError::Disassembly(m) => write!(f, "disassembly: {m}"),
        }
    }
}

impl std::error::Error for HostError {}

impl From<Error> for HostError {
    fn from(e: Error) -> Self {
        HostError::Core(e)
    }
}

/// The lines the firmware prints (and the host reference prints the same way).
pub mod line {
    /// `purcell-mcu: board=<machine> scalar=<f32|f64> steps=<N> passes=<P> checkpoints=<C>`.
    pub const HEADER: &str = "purcell-mcu:";
    /// `insn_per_step: mean=<M> max=<X>` (instructions per control step, over the replay).
    pub const INSN: &str = "insn_per_step:";
    /// `stack_step: bytes=<B>` (deepest stack use below the caller of one step).
    pub const STACK: &str = "stack_step:";
    /// `digest: <0x…>` ([`purcell_core::TrajectoryDigest`] of the whole replay).
    pub const DIGEST: &str = "digest:";
    /// `final_state_bits: <0x…> ×6` (`α1 α2 x y cos θ sin θ` as raw bits).
    pub const FINAL: &str = "final_state_bits:";
    /// `result: ok` (the last line of a successful run).
    pub const RESULT: &str = "result: ok";
}

/// What a firmware run reported.
#[derive(Debug, Clone, PartialEq)]
pub struct FirmwareLog {
    /// QEMU machine the firmware says it was built for.
    pub board: String,
    /// `"f32"` or `"f64"`.
    pub scalar: String,
    /// Steps replayed.
    pub steps: u32,
    /// Mean instructions per step.
    pub insn_mean: f64,
    /// Largest instruction count of one step.
    pub insn_max: u32,
    /// Deepest stack use of one step, bytes.
    pub stack_bytes: u32,
    /// Trajectory digest.
    pub digest: u64,
    /// Final state bits.
    pub final_bits: [u64; 6],
}

fn find_line<'a>(text: &'a str, prefix: &str) -> Result<&'a str, HostError> {
    text.lines()
        .map(str::trim)
        .find_map(|l| l.strip_prefix(prefix))
        .map(str::trim)
        .ok_or_else(|| HostError::Log(format!("no line starting with `{prefix}`")))
}

fn key<'a>(rest: &'a str, name: &str) -> Result<&'a str, HostError> {
    rest.split_whitespace()
        .find_map(|kv| kv.strip_prefix(name).and_then(|v| v.strip_prefix('=')))
        .ok_or_else(|| HostError::Log(format!("no `{name}=` in `{rest}`")))
}

fn parse_num<T: std::str::FromStr>(s: &str, what: &str) -> Result<T, HostError> {
    s.parse()
        .map_err(|_| HostError::Log(format!("`{what}`: cannot parse `{s}`")))
}

fn parse_hex(s: &str) -> Result<u64, HostError> {
    let digits = s
        .strip_prefix("0x")
        .ok_or_else(|| HostError::Log(format!("`{s}` is not 0x-prefixed hex")))?;
    u64::from_str_radix(digits, 16).map_err(|_| HostError::Log(format!("bad hex `{s}`")))
}

impl FirmwareLog {
    /// Reads a decoded firmware log. Errors: [`HostError::Log`] for a missing line or field,
    /// including a missing `result: ok` (the firmware did not finish).
    pub fn parse(text: &str) -> Result<Self, HostError> {
        let header = find_line(text, line::HEADER)?;
        let insn = find_line(text, line::INSN)?;
        let bits: Vec<u64> = find_line(text, line::FINAL)?
            .split_whitespace()
            .map(parse_hex)
            .collect::<Result<_, _>>()?;
        let final_bits: [u64; 6] = bits
            .try_into()
            .map_err(|_| HostError::Log("final_state_bits needs 6 values".into()))?;
        if !text.lines().any(|l| l.trim() == line::RESULT) {
            return Err(HostError::Log(format!("no `{}` line", line::RESULT)));
        }
        Ok(FirmwareLog {
            board: key(header, "board")?.to_string(),
            scalar: key(header, "scalar")?.to_string(),
            steps: parse_num(key(header, "steps")?, "steps")?,
            insn_mean: parse_num(key(insn, "mean")?, "mean")?,
            insn_max: parse_num(key(insn, "max")?, "max")?,
            stack_bytes: parse_num(key(find_line(text, line::STACK)?, "bytes")?, "bytes")?,
            digest: parse_hex(find_line(text, line::DIGEST)?)?,
            final_bits,
        })
    }
}

/// The host's replay of the costate file in one precision.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    /// `"f32"` or `"f64"`.
    pub scalar: &'static str,
    /// Digest and final state, with checkpoints (what the firmware runs).
    pub outcome: Outcome<f64>,
    /// Digest and final bits in the replay's own type.
    pub digest: u64,
    /// Final state bits in the replay's own type.
    pub final_bits: [u64; 6],
    /// Terminal error with checkpoints.
    pub error: TerminalError,
    /// Terminal error of the same replay without checkpoints, or the error that stopped it.
    pub error_without_checkpoints: Result<TerminalError, Error>,
}

/// How far a final state is from the target `(ᾱ, ḡ)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TerminalError {
    /// `|α_N − ᾱ|` (Euclidean).
    pub alpha: f64,
    /// `|log(ḡ⁻¹ g_N)|` (Euclidean norm of the twist `(x, y, θ)`).
    pub position: f64,
}

fn widen<T: Real>(s: &State<T>) -> State<f64> {
    State {
        alpha: nalgebra::Vector2::new(s.alpha.x.to_f64(), s.alpha.y.to_f64()),
        g: Se2::new(
            s.g.x().to_f64(),
            s.g.y().to_f64(),
            s.g.sin().to_f64().atan2(s.g.cos().to_f64()),
        ),
    }
}

/// The terminal error of `last` against the costate file's target, in `f64`.
pub fn terminal_error<T: Real>(last: &State<T>) -> Result<TerminalError, HostError> {
    let p = Problem::<f64>::load()?;
    let last = widen(last);
    let d = last.alpha - p.start.alpha;
    let twist = p.target.between(&last.g).log();
    Ok(TerminalError {
        alpha: d.norm(),
        position: twist.norm(),
    })
}

impl Reference {
    /// Replays the costate file on the host in `T`.
    pub fn compute<T: Scalar>() -> Result<Self, HostError> {
        let p = Problem::<T>::load()?;
        let with = replay_digest(p.replay(true)?, Replay::step)?;
        // Without checkpoints an f32 replay may leave the admissible set: report, don't fail.
        let without = replay_digest(p.replay(false)?, Replay::step);
        Ok(Reference {
            scalar: T::NAME,
            outcome: Outcome {
                digest: with.digest,
                last: widen(&with.last),
                steps: with.steps,
            },
            digest: with.digest.value(),
            final_bits: with.final_bits(),
            error: terminal_error(&with.last)?,
            error_without_checkpoints: match without {
                Ok(o) => Ok(terminal_error(&o.last)?),
                Err(e) => Err(e),
            },
        })
    }

    /// The precision named in a firmware log.
    pub fn for_scalar(name: &str) -> Result<Self, HostError> {
        match name {
            "f32" => Self::compute::<f32>(),
            "f64" => Self::compute::<f64>(),
            other => Err(HostError::Log(format!("unknown scalar `{other}`"))),
        }
    }
}

/// The limits a firmware run must meet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    /// Largest allowed instructions per step: the mean and the largest single step.
    pub insn_mean: f64,
    /// Largest allowed stack use of a step, bytes.
    pub stack_bytes: u32,
}

/// Compares a firmware log with the host reference: same precision, step count, digest and
/// final bits, and the budget met. Errors: [`HostError::Mismatch`] naming the first failure.
pub fn check(log: &FirmwareLog, reference: &Reference, budget: &Budget) -> Result<(), HostError> {
    let mismatch = |m: String| Err(HostError::Mismatch(m));
    if log.scalar != reference.scalar {
        return mismatch(format!(
            "firmware ran {}, reference is {}",
            log.scalar, reference.scalar
        ));
    }
    if log.steps != reference.outcome.steps {
        return mismatch(format!(
            "firmware ran {} steps, host {}",
            log.steps, reference.outcome.steps
        ));
    }
    if log.digest != reference.digest {
        return mismatch(format!(
            "digest: firmware {:#x}, host {:#x}",
            log.digest, reference.digest
        ));
    }
    if log.final_bits != reference.final_bits {
        return mismatch(format!(
            "final state bits: firmware {:x?}, host {:x?}",
            log.final_bits, reference.final_bits
        ));
    }
    if log.insn_mean.is_nan() || log.insn_mean > budget.insn_mean {
        return mismatch(format!(
            "mean instructions per step {} above the budget {}",
            log.insn_mean, budget.insn_mean
        ));
    }
    if f64::from(log.insn_max) > budget.insn_mean {
        return mismatch(format!(
            "largest step {} instructions, above the budget {}",
            log.insn_max, budget.insn_mean
        ));
    }
    if log.stack_bytes > budget.stack_bytes {
        return mismatch(format!(
            "stack of a step {} B above the budget {} B",
            log.stack_bytes, budget.stack_bytes
        ));
    }
    Ok(())
}

/// One function of a disassembly.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Function {
    /// Bytes of code and literal pools.
    pub bytes: u32,
    /// Functions it calls or tail-calls (by symbol).
    pub calls: BTreeSet<String>,
    /// Branches through a register (`blx rN`, `bx rN` other than `bx lr`).
    pub indirect: u32,
}

/// The call graph of a GNU `objdump -d` listing (with raw instruction bytes).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CallGraph {
    /// Functions by symbol.
    pub functions: BTreeMap<String, Function>,
}

/// Symbols of soft-float helpers: the ARM EABI ones (`__aeabi_dadd`, `__aeabi_f2d`,
/// `__aeabi_i2d`, …) and the libgcc/compiler-builtins ones (`__adddf3`, `__extendsfdf2`,
/// `__fixdfsi`, `__eqsf2`, …).
pub fn is_soft_float(symbol: &str) -> bool {
    if let Some(rest) = symbol.strip_prefix("__aeabi_") {
        const FLOAT_OPS: [&str; 16] = [
            "dadd", "dsub", "drsub", "dmul", "ddiv", "dneg", "dcmp", "fadd", "fsub", "frsub",
            "fmul", "fdiv", "fneg", "fcmp", "d2", "f2",
        ];
        return FLOAT_OPS.iter().any(|op| rest.starts_with(op))
            || rest.ends_with("2d")
            || rest.ends_with("2f");
    }
    if let Some(rest) = symbol.strip_prefix("__") {
        // `__<op><df|sf>[<df|sf|si|di>]<digit>`, e.g. __adddf3, __truncdfsf2, __floatsisf.
        let core = rest.trim_end_matches(|c: char| c.is_ascii_digit());
        let is_op = |s: &str| s.chars().all(|c| c.is_ascii_lowercase());
        return is_op(core) && (core.contains("df") || core.contains("sf"));
    }
    false
}

impl CallGraph {
    /// Parses `objdump -d` output: function headers `<addr> <symbol>:` and instruction lines
    /// `<addr>:\t<hex bytes>\t<mnemonic>\t<operands>`.
    pub fn parse(listing: &str) -> Self {
        let mut graph = CallGraph::default();
        let mut current: Option<String> = None;
        for raw in listing.lines() {
            let l = raw.trim_end();
            if let Some(name) = l
                .split_once(" <")
                .filter(|(addr, rest)| {
                    !addr.is_empty()
                        && addr.chars().all(|c| c.is_ascii_hexdigit())
                        && rest.ends_with(">:")
                })
                .map(|(_, rest)| rest.trim_end_matches(">:"))
            {
                graph.functions.entry(name.to_string()).or_default();
                current = Some(name.to_string());
                continue;
            }
            let Some(func) = current.as_ref().and_then(|c| graph.functions.get_mut(c)) else {
                continue;
            };
            let mut fields = l.split('\t');
            let addr = fields.next().unwrap_or("").trim();
            if !addr.ends_with(':') {
                continue;
            }
            let bytes: String = fields.next().unwrap_or("").split_whitespace().collect();
            if bytes.is_empty() || !bytes.chars().all(|c| c.is_ascii_hexdigit()) {
                continue;
            }
            func.bytes += (bytes.len() / 2) as u32;
            let mnemonic = fields.next().unwrap_or("").trim();
            let operands = fields.next().unwrap_or("").trim();
            let branch = mnemonic.starts_with('b') || mnemonic.starts_with("cb");
            if !branch || mnemonic.starts_with("bic") || mnemonic.starts_with("bfi") {
                continue;
            }
            if let Some(target) = operands
                .split_once('<')
                .and_then(|(_, t)| t.split_once('>'))
                .map(|(t, _)| t.split('+').next().unwrap_or(t))
            {
                if current.as_deref() != Some(target) {
                    func.calls.insert(target.to_string());
                }
            } else if (mnemonic.starts_with("blx") || mnemonic.starts_with("bx"))
                && operands != "lr"
            {
                func.indirect += 1;
            }
        }
        graph
    }

    /// Every function reachable from `root` through direct calls and tail calls, `root`
    /// included. Errors: [`HostError::Disassembly`] if `root` is not in the listing.
    pub fn reachable(&self, root: &str) -> Result<BTreeSet<String>, HostError> {
        if !self.functions.contains_key(root) {
            return Err(HostError::Disassembly(format!("no function `{root}`")));
        }
        let mut seen = BTreeSet::new();
        let mut todo = vec![root.to_string()];
        while let Some(f) = todo.pop() {
            if seen.insert(f.clone())
                && let Some(func) = self.functions.get(&f)
            {
                todo.extend(func.calls.iter().filter(|c| !seen.contains(*c)).cloned());
            }
        }
        Ok(seen)
    }
}

/// What the code reachable from one function contains.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CodeReport {
    /// Reachable functions.
    pub functions: BTreeSet<String>,
    /// Their bytes of code and literal pools.
    pub bytes: u32,
    /// Indirect branches among them.
    pub indirect: u32,
    /// Soft-float helpers among them.
    pub soft_float: Vec<String>,
}

impl CodeReport {
    /// Analyses the code reachable from `root`.
    pub fn new(graph: &CallGraph, root: &str) -> Result<Self, HostError> {
        let functions = graph.reachable(root)?;
        let (mut bytes, mut indirect) = (0, 0);
        for f in functions.iter().filter_map(|f| graph.functions.get(f)) {
            bytes += f.bytes;
            indirect += f.indirect;
        }
        let soft_float = functions
            .iter()
            .filter(|f| is_soft_float(f))
            .cloned()
            .collect();
        Ok(CodeReport {
            functions,
            bytes,
            indirect,
            soft_float,
        })
    }

    /// `Ok` when nothing reachable is a soft-float helper and no branch is indirect (which
    /// could reach one unseen).
    pub fn ensure_hard_float(&self) -> Result<(), HostError> {
        if !self.soft_float.is_empty() {
            return Err(HostError::Disassembly(format!(
                "soft-float helpers reachable: {}",
                self.soft_float.join(", ")
            )));
        }
        if self.indirect > 0 {
            return Err(HostError::Disassembly(format!(
                "{} indirect branches reachable: cannot prove no soft-float helper is called",
                self.indirect
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LOG: &str = "\
purcell-mcu: board=mps2-an386 scalar=f32 steps=10000 passes=2 checkpoints=99
insn_per_step: mean=812.5 max=845
stack_step: bytes=312
digest: 0xdeadbeef01
final_state_bits: 0x1 0x2 0x3 0x4 0x5 0x6
result: ok
";

    #[test]
    fn firmware_log_parses_and_needs_every_line() {
        let log = FirmwareLog::parse(LOG).unwrap();
        assert_eq!(log.board, "mps2-an386");
        assert_eq!(log.scalar, "f32");
        assert_eq!(
            (log.steps, log.insn_mean, log.insn_max),
            (10000, 812.5, 845)
        );
        assert_eq!((log.stack_bytes, log.digest), (312, 0xdead_beef01));
        assert_eq!(log.final_bits, [1, 2, 3, 4, 5, 6]);
        for drop in [0, 1, 2, 3, 4, 5] {
            let text: Vec<&str> = LOG
                .lines()
                .enumerate()
                .filter(|&(i, _)| i != drop)
                .map(|(_, l)| l)
                .collect();
            assert!(matches!(
                FirmwareLog::parse(&text.join("\n")),
                Err(HostError::Log(_))
            ));
        }
        assert!(FirmwareLog::parse(&LOG.replace("0x6", "0x6 0x7")).is_err());
        assert!(FirmwareLog::parse(&LOG.replace("0xdeadbeef01", "deadbeef01")).is_err());
    }

    #[test]
    fn check_accepts_the_reference_and_refuses_any_difference() {
        let reference = Reference::compute::<f32>().unwrap();
        let budget = Budget {
            insn_mean: 1000.0,
            stack_bytes: 2048,
        };
        let log = FirmwareLog {
            board: "mps2-an386".into(),
            scalar: "f32".into(),
            steps: reference.outcome.steps,
            insn_mean: 900.0,
            insn_max: 950,
            stack_bytes: 300,
            digest: reference.digest,
            final_bits: reference.final_bits,
        };
        check(&log, &reference, &budget).unwrap();
        let bad = [
            FirmwareLog {
                digest: log.digest ^ 1,
                ..log.clone()
            },
            FirmwareLog {
                final_bits: {
                    let mut b = log.final_bits;
                    b[5] ^= 1;
                    b
                },
                ..log.clone()
            },
            FirmwareLog {
                insn_mean: 1000.1,
                ..log.clone()
            },
            FirmwareLog {
                insn_mean: f64::NAN,
                ..log.clone()
            },
            FirmwareLog {
                insn_max: 1001,
                ..log.clone()
            },
            FirmwareLog {
                stack_bytes: 4096,
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
        for b in bad {
            assert!(matches!(
                check(&b, &reference, &budget),
                Err(HostError::Mismatch(_))
            ));
        }
    }

    #[test]
    fn replays_with_checkpoints_end_at_the_target() {
        // The file is a solution: the f64 replay ends at (ᾱ, ḡ) to the solver's residual, and
        // the f32 replay, reset to the f64 state every checkpoint interval, stays close to it.
        let r64 = Reference::compute::<f64>().unwrap();
        assert!(r64.error.position < 1e-9, "f64: {:?}", r64.error);
        assert!(r64.error.alpha < 1e-9, "f64: {:?}", r64.error);
        let r32 = Reference::compute::<f32>().unwrap();
        assert!(r32.error.position < 1e-6, "f32: {:?}", r32.error);
        assert!(r32.error.alpha < 1e-5, "f32: {:?}", r32.error);
        // The f32 replay is not the f64 one (else this would test nothing about precision).
        assert_ne!(r32.outcome.last, r64.outcome.last);
        assert_eq!(r32.outcome.steps, r64.outcome.steps);
    }

    #[test]
    fn soft_float_names() {
        for s in [
            "__aeabi_dadd",
            "__aeabi_dcmplt",
            "__aeabi_f2d",
            "__aeabi_d2f",
            "__aeabi_i2d",
            "__aeabi_ul2d",
            "__aeabi_fmul",
            "__adddf3",
            "__extendsfdf2",
            "__truncdfsf2",
            "__fixdfsi",
            "__floatsidf",
            "__unorddf2",
            "__addsf3",
        ] {
            assert!(is_soft_float(s), "{s}");
        }
        for s in [
            "__aeabi_memcpy",
            "__aeabi_uldivmod",
            "__aeabi_memclr4",
            "purcell_mcu_step",
            "__udivdi3",
            "memset",
            "sinf",
        ] {
            assert!(!is_soft_float(s), "{s}");
        }
    }

    const LISTING: &str = "
elf:     file format elf32-littlearm

Disassembly of section .text:

00000400 <root>:
     400:\tb580      \tpush\t{r7, lr}
     402:\tf000 f803 \tbl\t40c <helper>
     406:\td001      \tbeq.n\t40a <root+0xa>
     408:\te008      \tb.n\t41c <tail>
     40a:\tbd80      \tpop\t{r7, pc}

0000040c <helper>:
     40c:\tf000 f808 \tbl\t420 <__aeabi_dmul>
     410:\t4770      \tbx\tlr
     412:\tbf00      \tnop
     414:\t3f800000 \t.word\t0x3f800000

0000041c <tail>:
     41c:\t4770      \tbx\tlr
     41e:\tbf00      \tnop

00000420 <__aeabi_dmul>:
     420:\t4770      \tbx\tlr

00000422 <unrelated>:
     422:\t4798      \tblx\tr3
     424:\tf7ff fffc \tbl\t420 <__aeabi_dmul>
";

    #[test]
    fn call_graph_finds_reachable_helpers_and_sizes() {
        let g = CallGraph::parse(LISTING);
        assert_eq!(g.functions.len(), 5);
        assert_eq!(g.functions["root"].bytes, 12);
        assert_eq!(g.functions["helper"].bytes, 12);
        assert_eq!(g.functions["unrelated"].indirect, 1);
        let r = CodeReport::new(&g, "root").unwrap();
        let names: Vec<&str> = r.functions.iter().map(String::as_str).collect();
        assert_eq!(names, ["__aeabi_dmul", "helper", "root", "tail"]);
        assert_eq!(r.bytes, 12 + 12 + 4 + 2);
        assert_eq!(r.indirect, 0);
        assert_eq!(r.soft_float, ["__aeabi_dmul"]);
        assert!(r.ensure_hard_float().is_err());
        let t = CodeReport::new(&g, "tail").unwrap();
        t.ensure_hard_float().unwrap();
        assert!(
            CodeReport::new(&g, "unrelated")
                .unwrap()
                .ensure_hard_float()
                .is_err()
        );
        assert!(matches!(
            CodeReport::new(&g, "missing"),
            Err(HostError::Disassembly(_))
        ));
    }
}
