#!/usr/bin/env python3
"""Re-measures every number README.md quotes and fails on the first one that differs.

Usage: python3 tests/readme.py PURCELL_SIM [MCU_LOG_DIR]   (run by tests/run.sh)

- The blocks after `<!-- readme-check: NAME -->` are compared line by line with a fresh run
  (`solve`: the summary of the main job, all but its `time` line; `replay`: the committed
  paper's gait flown in f32). The `time` line, which depends on the machine, is checked
  loosely: the fresh run's shape (`time  T s (S s solving)`) and within a factor of ten of
  the README's figures.
- The committed gaits are the main job's: `core/examples/paper.gait` and `paper-limit.gait`
  equal byte for byte what `export` writes from a fresh `solve` (and `--alpha-max 1.5`).
- Every other number the README states is computed here from fresh outputs (report.json,
  trajectory.csv, replays, the shared suite's reference, the M4F's log written by
  firmware/check.sh when MCU_LOG_DIR is given) and must appear in the README as printed.
Standard library only.
"""

import csv
import json
import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text()


def fail(message: str) -> None:
    sys.exit(f"tests/readme.py: {message}")


def run(sim: str, *args: str, cwd: Path) -> str:
    out = subprocess.run(
        [sim, *args], check=False, cwd=cwd, capture_output=True, text=True
    )
    if out.returncode != 0:
        fail(f"`purcell-sim {' '.join(args)}` exited {out.returncode}: {out.stderr}")
    return out.stdout


def block(name: str) -> list[str]:
    """The fenced block after `<!-- readme-check: name -->`."""
    match = re.search(
        rf"<!-- readme-check: {name} -->\n```\w*\n(.*?)```", README, re.DOTALL
    )
    if not match:
        fail(f"README has no block `readme-check: {name}`")
    return match.group(1).splitlines()


def same_block(name: str, fresh: str, skip: str | None = None) -> None:
    keep = lambda lines: [l for l in lines if not (skip and l.startswith(skip))]
    quoted, measured = keep(block(name)), keep(fresh.splitlines())
    if quoted != measured:
        fail(
            f"block `{name}` differs from a fresh run:\nREADME:\n"
            + "\n".join(quoted)
            + "\nfresh:\n"
            + "\n".join(measured)
        )


def sci(value: float) -> str:
    """`1.7e-7`, as the Rust tools print two digits."""
    return re.sub(r"e([+-]?)0*(\d)", r"e\1\2", f"{value:.1e}").replace("e+", "e")


def quoted(text: str, what: str) -> None:
    if text not in README:
        fail(f"README should state {text!r} ({what})")


def solve(sim: str, cwd: Path, name: str, *args: str) -> dict:
    run(sim, "solve", "-q", "--no-plots", "--out", name, *args, cwd=cwd)
    return json.loads((cwd / name / "report.json").read_text())


TIME = re.compile(r"time {7}([0-9.]+) s \(([0-9.]+) s solving\)")


def same_time(name: str, fresh: str) -> None:
    """The `time` lines of block `name` and of `fresh`: the same shape, times within a
    factor of ten (the machine's load and core count change them, not the work)."""
    lines = lambda text: [l for l in text if l.startswith("time ")]
    (quoted,), (measured,) = lines(block(name)), lines(fresh.splitlines())
    q, m = TIME.fullmatch(quoted), TIME.fullmatch(measured)
    if not (q and m):
        fail(
            f"block `{name}`: time line {quoted!r} not shaped as the fresh {measured!r}"
        )
    for said, now in zip(map(float, q.groups()), map(float, m.groups())):
        if not said / 10 <= now <= said * 10:
            fail(
                f"block `{name}`: {quoted!r} is not within 10x of the fresh {measured!r}"
            )


def main() -> None:
    if len(sys.argv) < 2:
        fail("usage: readme.py PURCELL_SIM [MCU_LOG_DIR]")
    sim = str(Path(sys.argv[1]).resolve())
    with tempfile.TemporaryDirectory() as tmp:
        cwd = Path(tmp)
        # The main job's summary, and the committed gait is its gait.
        summary = run(sim, "solve", "--out", "out/paper", cwd=cwd)
        same_block("solve", summary, skip="time ")
        same_time("solve", summary)
        for name, args in [("paper", []), ("paper-limit", ["--alpha-max", "1.5"])]:
            if args:
                solve(sim, cwd, "limit", *args)
            source = "out/paper" if not args else "limit"
            run(
                sim,
                "export",
                "--costate",
                f"{source}/costate.json",
                "--out",
                f"{name}.gait",
                cwd=cwd,
            )
            if (cwd / f"{name}.gait").read_bytes() != (
                ROOT / f"core/examples/{name}.gait"
            ).read_bytes():
                fail(
                    f"core/examples/{name}.gait is not the gait of `solve {' '.join(args)}`"
                )
        gait = str(ROOT / "core/examples/paper.gait")
        same_block(
            "replay", run(sim, "replay", "--gait", gait, "--precision", "f32", cwd=cwd)
        )

        report = json.loads((cwd / "out/paper/report.json").read_text())
        problem = report["problem"]
        quoted(
            "`ḡ = ({} m, {} m, {:g})`".format(*problem["target"]), "the paper's target"
        )
        quoted(
            f"`T = {problem['horizon']:g} s`, `h = {problem['step']:g} s`",
            "the horizon",
        )
        if problem["links"] != [1.0, 1.0, 1.0]:
            fail(f"the paper's links are not unit: {problem['links']}")
        quoted(
            f"drag `k = {problem['drag']:g}`, ratio `r = {problem['ratio']:g}`",
            "the drag",
        )
        cost = report["cost"]
        quoted(f"**J = {cost:.7f}**", "the returned cost")
        suite = json.loads((ROOT / "tests/problems/public.json").read_text())
        ref = next(p["ref"] for p in suite if p["name"] == "paper")
        if abs(cost / ref - 1) >= 1e-11:
            fail(f"J = {cost} is not IPOPT's {ref} to 1e-11")
        amax = report["max_abs_alpha"]
        quoted(f"{amax:.4f} rad ({math.degrees(amax):.1f}°", "the largest joint angle")
        cheaper = [e["cost"] for e in report["extremals"] if e["cost"] < cost]
        quoted(
            f"{len(cheaper)}, from J = {min(cheaper):.7f}",
            "the cheaper inadmissible extremals",
        )
        residuals = f"{sci(report['residual'])}, {sci(report['kkt_residual'])}"
        quoted(f"| {residuals} |", "the terminal and KKT residuals")
        if report["local_min"] is not True:
            fail("the returned gait is not certified a strict local minimum")

        replay = run(sim, "replay", "--gait", gait, cwd=cwd)
        errors = dict(
            re.findall(
                r"replay: (.*)\n(?:.*\n){2}terminal_error: alpha=(\S+ g=\S+)", replay
            )
        )
        for flight in ["f64 with checkpoints", "f32 with checkpoints"]:
            a, g = (float(v) for v in errors[flight].split(" g="))
            quoted(f"{sci(a)} / {sci(g)}", f"the {flight} replay's end error")

        # Our gait against the paper's figures.
        with open(cwd / "out/paper/trajectory.csv", newline="") as f:
            rows = list(csv.DictReader(f))
        col = lambda k: [float(r[k]) for r in rows]
        deg = lambda v: f"{round(math.degrees(v))}°".replace("-", "−")
        a1, a2 = col("alpha1_rad"), col("alpha2_rad")
        quoted(f"α₁ = {deg(min(a1))}", "the gait's most negative α₁")
        quoted(f"α₂ = {deg(min(a2))} … {deg(max(a2))}", "the gait's range of α₂")
        rate = max(abs(u) for u in col("u1_rad_per_s") + col("u2_rad_per_s"))
        quoted(f"up to {math.degrees(rate):.1f}°/s", "the gait's fastest joint")
        quoted(f"by up to {deg(max(col('theta_rad')))}", "the body's largest turn")
        y = col("y_m")
        first = next(v for v in y if abs(v) > 0.01)
        quoted(
            f"first moves towards {'+' if first > 0 else '−'}y (the body",
            "the gait's first move",
        )
        horizon = report["problem"]["horizon"]
        bound = horizon / 2 * 2 * math.radians(4) ** 2
        quoted(f"(4°/s)² = {bound:.3f}", "the cost bound of the paper's rates")
        within = solve(sim, cwd, "paper140", "--alpha-max", "140deg")
        quoted(
            f"costs J = {within['cost']:.7f}, on {len(within['arcs'])} arcs",
            "within 140°",
        )

        # The joint-limit table.
        for limit in ["3.0", "2.5", "2.0", "1.5"]:
            r = solve(sim, cwd, f"limit{limit}", "--alpha-max", limit)
            arcs = len(r["arcs"])
            shape = (
                "interior" if arcs == 0 else f"{arcs} arc" + ("s" if arcs > 1 else "")
            )
            quoted(f"{r['cost']:.7f} ({shape})", f"the cost within {limit}")
        ipopt = re.search(
            r"\| 3\.0 \| paper \| [\d.]+ \| \d+ \| [^|]+\| [^|]+\| (0\.\d+) \|",
            (ROOT / "docs/MODEL.md").read_text(),
        )
        if not ipopt:
            fail("MODEL.md §9 has no IPOPT cost within 3.0")
        quoted("0.5020008", "IPOPT's best within 3.0")
        if f"{float(ipopt.group(1)):.7f}" != "0.5020008":
            fail(f"MODEL.md's IPOPT cost within 3.0 is {ipopt.group(1)}")

    licence = re.search(
        r'^license = "(.*)"', (ROOT / "Cargo.toml").read_text(), re.MULTILINE
    )
    quoted(f"Licence: {licence.group(1)}.", "the licence")

    # The M4F's figures, from firmware/check.sh's log of the paper's gait.
    if len(sys.argv) > 2:
        log = (Path(sys.argv[2]) / "m4f.log").read_text()
        mean, top = re.search(r"insn_per_step: mean=(\S+) max=(\d+)", log).groups()
        quoted(f"| {mean} / {top} |", "the M4F's instructions per step")
        quoted(
            f"in about {round(float(mean))} instructions",
            "the M4F's instructions, rounded",
        )
        if block("replay")[2] not in log:
            fail("the M4F's log does not show the README's digest")
    print("README.md: every quoted number re-measured")


if __name__ == "__main__":
    main()
