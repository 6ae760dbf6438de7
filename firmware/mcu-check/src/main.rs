//! `purcell-mcu-check`, the firmware's checker on the host, by job:
//! [`reference`](mod@reference) flies a gait on the host through the same core code as the
//! firmware, [`log`] reads a firmware log (QEMU's or a board's) and checks it against that
//! flight, [`disasm`] scans the firmware's disassembly for what the step reaches. See
//! `firmware/README.md`.

mod control;
mod disasm;
mod error;
mod log;
mod reference;

use control::{LoopLog, check_loop};
use disasm::{CallGraph, CodeReport};
use log::{Budget, FirmwareLog, Unit, check};
use purcell_core::Gait;
use purcell_fly::line;
use reference::Reference;
use std::path::PathBuf;
use std::process::ExitCode;

const USAGE: &str = "\
purcell-mcu-check: checks on the host what the firmware printed and compiled to. The firmware
(purcell-mcu) builds for thumbv7em-none-eabihf (M4F, M7) and thumbv7m-none-eabi (M3): run it
with `cargo run -p purcell-mcu --target thumbv7em-none-eabihf --release`, `cargo mcu-m7` or
`cargo mcu-m3`.

usage:
  purcell-mcu-check reference [--gait FILE] [f32|f64]
      fly the gait on the host; print digest, final state and terminal error
  purcell-mcu-check check LOG [--gait FILE] [--max-insn M] [--max-step-insn S] [--max-cycles C]
                      [--max-stack B]
      compare a decoded firmware log (QEMU's, or a board's with cycles_per_step) with the
      host's flight of the same gait in the same precision; fail on another gait, a digest
      or final-state mismatch, a mean above M instructions (default 1000) or a largest step
      above S (default M), a mean or a largest step above C cycles (default: no limit), the
      steps on a joint-limit arc dearer than the free ones (mean or largest), or a step
      stack above B bytes (default 2048)
  purcell-mcu-check loop LOG [--gait FILE]
      compare a control loop's log (the gait flown cycle after cycle from a timer,
      firmware/mcu/examples/control_loop.rs) with the host: each cycle's digest is the
      host's flight of the gait, each cycle's pose the host's composition of the cycles in
      the same precision; fail on a mismatch, a missing tick, an overrun or a tick longer
      than the period
  purcell-mcu-check disasm LISTING [--root SYMBOL] [--soft-float]
      from `arm-none-eabi-objdump -d` output: code reachable from SYMBOL (default
      purcell_mcu_step), its size; fail if a soft-float helper or an indirect branch is
      reachable (with --soft-float, for a core without FPU: list the helpers, do not fail)

FILE: the gait the firmware embedded (default: $PURCELL_GAIT, else the committed paper's
gait core/examples/paper.gait).";

fn print_reference(r: &Reference) {
    println!(
        "{}: board=host scalar={} steps={} gait={:#010x}",
        line::HEADER,
        r.scalar,
        r.steps,
        r.gait_crc
    );
    println!("{}: {:#018x}", line::DIGEST, r.digest);
    let bits: Vec<String> = r.final_bits.iter().map(|b| format!("{b:#x}")).collect();
    println!("{}: {}", line::FINAL, bits.join(" "));
    let [a1, a2, x, y, theta] = r.end;
    println!("final_state: alpha=[{a1}, {a2}] g=[{x}, {y}, {theta}]");
    let e = &r.error;
    println!(
        "terminal_error: {} with checkpoints alpha={:.2e} g={:.2e}",
        r.scalar, e.alpha, e.g
    );
    match &r.error_without_checkpoints {
        Ok(e) => println!(
            "terminal_error: {} without checkpoints alpha={:.2e} g={:.2e}",
            r.scalar, e.alpha, e.g
        ),
        Err(e) => println!(
            "terminal_error: {} without checkpoints: the replay failed: {e}",
            r.scalar
        ),
    }
}

/// The value of `--name VALUE`, or `default`.
fn flag<T: std::str::FromStr>(args: &[String], name: &str, default: T) -> Result<T, String> {
    match args.iter().position(|a| a == name) {
        None => Ok(default),
        Some(i) => args
            .get(i + 1)
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| format!("{name} needs a value")),
    }
}

/// The arguments that are neither flags nor flag values.
fn positionals(args: &[String]) -> Vec<&str> {
    let mut out = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        if a.starts_with("--") {
            it.next();
        } else {
            out.push(a.as_str());
        }
    }
    out
}

/// The gait file's bytes: `--gait`, else `$PURCELL_GAIT`, else the paper's.
fn gait_bytes(args: &[String]) -> Result<(PathBuf, Vec<u8>), String> {
    let default = std::env::var_os("PURCELL_GAIT").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../core/examples/paper.gait"),
        PathBuf::from,
    );
    let path = flag(args, "--gait", default)?;
    let bytes = std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    Ok((path, bytes))
}

fn read(path: &str) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("cannot read {path}: {e}"))
}

fn run(args: &[String]) -> Result<(), String> {
    let pos = positionals(args);
    match pos.first().copied() {
        Some("reference") => {
            let (path, bytes) = gait_bytes(args)?;
            let gait = Gait::from_bytes(&bytes).map_err(|e| format!("{}: {e}", path.display()))?;
            let scalar = pos.get(1).copied().unwrap_or("f32");
            print_reference(&Reference::for_scalar(&gait, scalar).map_err(|e| e.to_string())?);
            Ok(())
        }
        Some("check") => run_check(args, &pos),
        Some("loop") => run_loop(args, &pos),
        Some("disasm") => run_disasm(args, &pos),
        _ => Err(USAGE.to_string()),
    }
}

/// `check LOG`: a firmware log against the host's flight of its gait, within the budgets.
fn run_check(args: &[String], pos: &[&str]) -> Result<(), String> {
    let text = read(pos.get(1).ok_or("check needs a log file")?)?;
    let insn = flag(args, "--max-insn", 1000.0)?;
    let budget = Budget {
        insn,
        insn_step: flag(args, "--max-step-insn", insn)?,
        cycles: flag(args, "--max-cycles", f64::NAN).map(|c| (!c.is_nan()).then_some(c))?,
        stack_bytes: flag(args, "--max-stack", 2048)?,
    };
    let log = FirmwareLog::parse(&text).map_err(|e| e.to_string())?;
    let (path, bytes) = gait_bytes(args)?;
    let gait = Gait::from_bytes(&bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    let r = Reference::for_scalar(&gait, &log.scalar).map_err(|e| e.to_string())?;
    print_reference(&r);
    check(&log, &r, &budget).map_err(|e| e.to_string())?;
    let (unit, limit) = match log.unit {
        Unit::Instructions => (
            line::INSN,
            format!("{} mean, {} a step", budget.insn, budget.insn_step),
        ),
        Unit::Cycles => (
            line::CYCLES,
            budget.cycles.map_or("none".to_string(), |l| l.to_string()),
        ),
    };
    let stack = log.stack_bytes.map_or("not measured".to_string(), |s| {
        format!("{s} B (budget {} B)", budget.stack_bytes)
    });
    let a = &log.arcs;
    println!(
        "check: ok board={} scalar={} gait={:#010x} digest={:#018x} bit-identical to the \
         host; {unit} mean={} max={} (budget {limit}); on arcs: {} steps, mean={} max={} \
         (free steps: mean={} max={}); stack_step={stack}",
        log.board,
        log.scalar,
        log.gait_crc,
        log.digest,
        log.mean,
        log.max,
        a.steps,
        a.mean,
        a.max,
        a.free_mean,
        a.free_max
    );
    Ok(())
}

/// `loop LOG`: a control loop's log against the host, cycle by cycle.
fn run_loop(args: &[String], pos: &[&str]) -> Result<(), String> {
    let text = read(pos.get(1).ok_or("loop needs a log file")?)?;
    let log = LoopLog::parse(&text).map_err(|e| e.to_string())?;
    let (path, bytes) = gait_bytes(args)?;
    let gait = Gait::from_bytes(&bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    check_loop(&log, &gait).map_err(|e| e.to_string())?;
    println!(
        "loop: ok board={} scalar={} gait={:#010x} cycles={} each bit-identical to the \
         host (digest and composed pose); ticks={} mean={} max={} {unit} period={} \
         margin={} {unit} overruns=0",
        log.board,
        log.scalar,
        log.gait_crc,
        log.planned,
        log.ticks,
        log.mean,
        log.max,
        log.period,
        log.period - log.max,
        unit = log.unit
    );
    Ok(())
}

/// `disasm LISTING`: the code reachable from the step, with no soft-float helper.
fn run_disasm(args: &[String], pos: &[&str]) -> Result<(), String> {
    let text = read(pos.get(1).ok_or("disasm needs an objdump listing")?)?;
    let root: String = flag(args, "--root", "purcell_mcu_step".to_string())?;
    let report = CodeReport::new(&CallGraph::parse(&text), &root).map_err(|e| e.to_string())?;
    println!(
        "step_code: root={root} functions={} bytes={} indirect_branches={} soft_float_helpers={}",
        report.functions.len(),
        report.bytes,
        report.indirect,
        report.soft_float.len()
    );
    for f in &report.functions {
        println!("  reachable: {f}");
    }
    if args.iter().any(|a| a == "--soft-float") {
        for f in &report.soft_float {
            println!("  soft-float: {f}");
        }
        return Ok(());
    }
    report.ensure_hard_float().map_err(|e| e.to_string())?;
    println!("step_code: ok, no soft-float helper reachable from {root}");
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}
