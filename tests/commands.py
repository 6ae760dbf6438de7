#!/usr/bin/env python3
"""Runs every command the READMEs show, as a newcomer would type it; fails on the first one
that fails.

Usage: python3 tests/commands.py PURCELL_SIM   (run by tests/run.sh)

Commands are the lines of ```sh blocks and the inline code spans that start with a program
(`purcell-sim`, `cargo`, `bash`, ...), in every README.md outside target directories, in
order, in one scratch directory that links the repository's top-level entries (so
`core/examples/paper.gait` resolves). Each one is, by the first rule that matches:
- run: `purcell-sim ...` and `cargo run -p purcell-sim -- ...` with PURCELL_SIM (built by the
  test command), placeholders filled as a newcomer would (`X,Y,THETA`, `T`, `H`, `DIR`,
  `FILE`, `[...]`); a span cut short by `…`, or naming a subcommand and flags without all
  their values, must be refused only for what it leaves out (clap's usage error), so every
  name in it is checked;
- run in the repository: a few cheap cargo commands;
- run by CI: the stage of the test command that runs it (a line of that script, checked);
- skipped, with the reason printed (a board, hours of IPOPT, a network install).
A command no rule covers fails the test, so a new README command needs a rule. Every
relative link in the READMEs must lead to a file, and its `#anchor` to a heading there.
Standard library only.
"""

import os
import re
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PROGRAMS = (
    "purcell-sim ",
    "cargo ",
    "bash ",
    "pip ",
    "maturin ",
    "python3 ",
    "PURCELL_",
)

# Newcomers' values for the READMEs' placeholders: a small problem, so CI stays quick.
FILL = [
    (r"\bX,Y,THETA\b", "0.1,0.05,0"),
    (r"--horizon T\b", "--horizon 10"),
    (r"--step H\b", "--step 0.01"),
    (r"\bDIR/", "out/mine/"),
    (r"\bFILE\b", "core/examples/paper.gait"),
    (r"\[COMMAND\]", "solve"),
    (r"\[([^\]]*)\]", r"\1"),
]

# (pattern, script, line of that script that runs it): commands the test command runs.
IN_CI = [
    (r"^bash tests/run\.sh$", "tests/run.sh", "set -euo pipefail"),
    (r"^(bash )?(firmware|python)/check\.sh$", "tests/run.sh", "bash {2}/check.sh"),
    (r"^bash tests/packaged\.sh$", "tests/run.sh", "bash tests/packaged.sh"),
    (r"^python3 tests/readme\.py$", "tests/run.sh", "python3 tests/readme.py"),
    (
        r"^cargo test -p purcell-(sim|solver)\b",
        "tests/run.sh",
        "cargo test --workspace",
    ),
    (
        r"^cargo run -p purcell-core --example replay_gait$",
        "tests/run.sh",
        "cargo run -q -p purcell-core --example replay_gait",
    ),
    (r"^cargo doc -p purcell-solver", "tests/run.sh", "cargo doc --workspace"),
    (
        (
            r"^(PURCELL_GAIT=\S+ )?cargo run -p purcell-mcu --target thumbv7em-none-eabihf "
            r"--release$"
        ),
        "firmware/check.sh",
        "cargo run -q -p purcell-mcu --target thumbv7em-none-eabihf --release",
    ),
    (r"^cargo mcu-(m7|m3)$", "firmware/check.sh", "cargo -q mcu-{1}"),
    (
        (
            r"^(PURCELL_GAIT=\S+ )?cargo run -p purcell-mcu --example (control_loop|closed_loop) "
            r"--target thumbv7em-none-eabihf --release"
        ),
        "firmware/check.sh",
        "cargo run -q -p purcell-mcu --example {2} --target thumbv7em-none-eabihf --release",
    ),
    (r"^cargo run -p purcell-mcu-check -- loop ", "firmware/check.sh", "tool loop "),
    (
        r"^cargo build -p purcell-capi --release --target thumbv7em-none-eabihf$",
        "firmware/c-example/Makefile",
        "-p purcell-capi --release",
    ),
    (
        r"^(pip install \./python|maturin build)",
        "python/check.sh",
        '/bin/maturin" build',
    ),
    (
        r"^pip install python/target/wheels/purcell-\*\.whl$",
        "python/check.sh",
        "wheels=$root/python/target/wheels",
    ),
    (r"^cargo tree -p purcell-solver$", "tests/outside.sh", "purcell-solver"),
    (r"^cargo package$", "tests/packaged.sh", "cargo package"),
    (r"^cargo fmt --check$", "python/check.sh", "cargo fmt --check"),
    (
        r"^bash firmware/board-stm32f4-discovery/copy-out\.sh ",
        "tests/packaged.sh",
        'bash "$board/copy-out.sh"',
    ),
    (
        r"^(cd \.\./my-firmware|cargo build --release)$",
        "tests/packaged.sh",
        "cargo build -q --release --bins --examples",
    ),
    (r"^make -C firmware/c-example\b", "firmware/c-example/check.sh", "make -s -C"),
    (r"^firmware/c-example/check\.sh$", "firmware/check.sh", "c-example/check.sh"),
    (r"^firmware/capi/header\.sh$", "firmware/c-example/check.sh", "capi/header.sh"),
]

# Cargo commands run as typed in the repository (cheap: an earlier stage built them).
IN_REPOSITORY = [r"^cargo run -p purcell-mcu-check -- reference f(32|64)$"]

# (pattern, why it is not run here).
SKIP = [
    (
        r"^cargo install ",
        "installs a tool on the machine (.ci/run installs what CI needs)",
    ),
    (r"^(apt-get|rustup) ", "sets up the machine (.ci/run does it)"),
    (
        r"^(RAYON_NUM_THREADS=1 )?cargo bench\b",
        "benchmarks: minutes of release builds, timing only (not in CI)",
    ),
    (
        r"^(bash )?firmware/profile\.sh|^cargo mcu-m7-build$|^PURCELL_QEMU_MACHINE=\S+ firmware/profile",
        "a profile of the step's instructions, for reading (not in CI)",
    ),
    (r"casadi|peers/|ipopt", "needs CasADi and IPOPT; hours (the peers, not in CI)"),
    (r"^pip install \"", "installs from the network (dask, an optional extra)"),
    (r"^cargo \+nightly fuzz", "fuzzing, run by tests/run.sh with a time limit"),
    (r"board\.log|board-loop\.log|probe-rs", "needs an STM32F4-Discovery on a probe"),
    (
        r"^cd (firmware/board|\.\./\.\.$)|^cargo run --release( --example control_loop)?( 2>&1|$)",
        "flashes an STM32F4-Discovery (or changes to the board's folder and back)",
    ),
    (r"^cargo build/test|^pip install$", "a list of commands or a name, in prose"),
    (r"^cargo run -p purcell-mcu-check -- check ", "checks a board's log (a board)"),
    (r"^PURCELL_\w+$|^PURCELL_\w+\*?$", "an environment variable's name"),
    (r"^PURCELL_\w+=\S+$", "an environment variable's value"),
    (r"reference f32\|f64$", "two commands in one (`reference f32`, run above)"),
    (
        r"^arm-none-eabi-gcc .* your\.ld main\.c",
        "a template: your linker script, your main.c",
    ),
]


# (pattern, arguments added, why): commands run smaller, every name and value as typed, so
# that CI stays quick.
CHEAPER = [
    (
        r"^sweep --x -0\.3:0\.3:13 --y -0\.3:0\.3:13 ",
        ["--starts", "16", "--horizon", "10"],
        "169 global searches of up to 1 024 starts take minutes of CPU",
    ),
]


def fail(message: str) -> None:
    sys.exit(f"tests/commands.py: {message}")


def commands(readme: Path) -> list[str]:
    """The README's commands in order: ```sh lines (continuations joined, comments dropped)
    and inline code spans starting with a program."""
    text = readme.read_text()
    found: list[tuple[int, str]] = []
    for m in re.finditer(r"```(\w*)\n(.*?)```", text, re.DOTALL):
        if m.group(1) != "sh":
            continue
        for line in m.group(2).replace("\\\n", " ").splitlines():
            line = re.sub(r"(^|\s)#.*", "", line).strip()
            if line:
                found.append((m.start(), re.sub(r"\s+", " ", line)))
    prose = re.sub(r"```.*?```", lambda m: " " * len(m.group(0)), text, flags=re.DOTALL)
    for m in re.finditer(r"`([^`]+)`", prose):
        span = re.sub(r"\s+", " ", m.group(1)).strip()
        if span.startswith(PROGRAMS):
            found.append((m.start(), span))
    return [c for _, c in sorted(found, key=lambda f: f[0])]


def filled(command: str) -> str:
    for pattern, value in FILL:
        command = re.sub(pattern, value, command)
    return command


def sim_args(command: str) -> list[str] | None:
    """The arguments of a `purcell-sim` command (also through `cargo run -p purcell-sim`)."""
    m = re.match(
        r"(cargo run (--release )?-p purcell-sim -- |purcell-sim(\s|$))(.*)", command
    )
    return shlex.split(m.group(4)) if m else None


def run_sim(sim: str, args: list[str], cwd: Path) -> str:
    """Runs one command; a bare `DIR` is `solve`'s `out/mine` (which `DIR/costate.json`
    reads), another command's `out/COMMAND`."""
    sub = args[0] if args else ""
    args = [
        re.sub(r"^DIR$", "out/mine" if sub == "solve" else f"out/{sub}", a)
        for a in args
    ]
    note = ""
    for pattern, extra, why in CHEAPER:
        if re.search(pattern, shlex.join(args)):
            args += extra
            note = f" with {' '.join(extra)} ({why})"
    cut = "…" in args
    if cut:
        args = args[: args.index("…")]
    out = subprocess.run(
        [sim, *args], cwd=cwd, capture_output=True, text=True, check=False
    )
    usage = re.search(
        r"a value is required|required arguments were not provided", out.stderr
    )
    if out.returncode == 0 and not cut:
        return "ran" + note
    if out.returncode == 2 and usage:
        return "names checked (a mention: clap asks for what it leaves out)"
    fail(
        f"`purcell-sim {shlex.join(args)}` exited {out.returncode}:\n{out.stderr.strip()}"
    )
    return ""


def covered(command: str) -> str | None:
    if any(re.search(p, command) for p in IN_REPOSITORY):
        out = subprocess.run(
            shlex.split(command), cwd=ROOT, capture_output=True, text=True, check=False
        )
        if out.returncode != 0:
            fail(f"`{command}` exited {out.returncode}:\n{out.stderr.strip()}")
        return "ran in the repository"
    for pattern, script, line in IN_CI:
        m = re.search(pattern, command)
        if not m:
            continue
        needle = line.format(*[""] + [g or "" for g in m.groups()])
        if needle not in (ROOT / script).read_text():
            fail(f"`{command}`: {script} should run it (`{needle}`)")
        return f"run by {script}"
    for pattern, why in SKIP:
        if re.search(pattern, command):
            return f"skipped: {why}"
    return None


def slug(heading: str) -> str:
    """GitHub's anchor of a Markdown heading."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def check_links(readme: Path) -> None:
    text = re.sub(r"```.*?```", "", readme.read_text(), flags=re.DOTALL)
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"\w+:", target):
            continue
        path, _, anchor = target.partition("#")
        linked = (readme.parent / path).resolve() if path else readme
        if not linked.exists():
            fail(f"{readme.relative_to(ROOT)}: link {target} leads to no file")
        if anchor and linked.suffix == ".md":
            headings = re.findall(r"^#+ (.*)$", linked.read_text(), re.MULTILINE)
            if anchor not in {slug(h) for h in headings}:
                fail(f"{readme.relative_to(ROOT)}: link {target}: no such heading")


def main() -> None:
    if len(sys.argv) != 2:
        fail("usage: commands.py PURCELL_SIM")
    sim = str(Path(sys.argv[1]).resolve())
    readmes = sorted(
        p.relative_to(ROOT)
        for p in ROOT.rglob("README.md")
        if not {"target", "node_modules", ".git"} & set(p.relative_to(ROOT).parts)
    )
    with tempfile.TemporaryDirectory() as tmp:
        cwd = Path(tmp)
        for entry in ROOT.iterdir():
            if entry.name not in {"out", "target", ".git"}:
                os.symlink(entry, cwd / entry.name)
        for readme in readmes:
            check_links(ROOT / readme)
            for command in commands(ROOT / readme):
                parts = [filled(c.strip()) for c in command.split("&&")]
                verdicts = []
                for part in parts:
                    args = sim_args(part)
                    verdict = (
                        run_sim(sim, args, cwd) if args is not None else covered(part)
                    )
                    if verdict is None:
                        fail(
                            f"{readme}: `{part}` is run by no rule of tests/commands.py"
                        )
                    verdicts.append(verdict)
                print(f"{readme}: {command}\n    {'; '.join(verdicts)}")


if __name__ == "__main__":
    main()
