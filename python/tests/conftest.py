"""Fixtures: the `purcell-sim` command line the package is checked against, and its results."""

import json
import os
import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli():
    """Runs `purcell-sim` with arguments: $PURCELL_SIM, else the workspace's build."""
    exe = os.environ.get("PURCELL_SIM")
    if not exe:
        # The workspace's build in the test profile (optimised), as firmware/check.sh runs it.
        cargo = ["cargo", "build", "-q", "--profile", "test", "-p", "purcell-sim"]
        subprocess.run(cargo, cwd=ROOT, check=True)
        meta = subprocess.run(
            ["cargo", "metadata", "--format-version", "1", "--no-deps"],
            cwd=ROOT,
            check=True,
            capture_output=True,
            text=True,
        )
        exe = str(Path(json.loads(meta.stdout)["target_directory"]) / "debug" / "purcell-sim")

    def run(*args, code=0):
        done = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
        assert done.returncode == code, done.stderr
        return done

    return run


@pytest.fixture(scope="session")
def public():
    """The public problems by name (tests/problems/public.json)."""
    problems = json.loads((ROOT / "tests" / "problems" / "public.json").read_text())
    return {p["name"]: p for p in problems}


def cli_flags(problem):
    """The command-line flags of a problem of public.json."""
    flags = ["--target", ",".join(map(repr, problem["target"]))]
    for key in ("horizon", "step", "alpha0", "links", "drag", "ratio", "alpha_max"):
        if key in problem:
            value = problem[key]
            value = ",".join(map(repr, value)) if isinstance(value, list) else repr(value)
            flags += ["--" + key.replace("_", "-"), value]
    return flags


def kwargs(problem):
    """The keyword arguments of `purcell.solve` for a problem of public.json."""
    keys = ("horizon", "step", "alpha0", "links", "drag", "ratio", "alpha_max")
    return {k: problem[k] for k in keys if k in problem}


def in_python_words(message):
    """A command-line message with its flags as Python's keyword names: `--alpha-max 0.8`
    as `alpha_max=0.8`, `--starts` as `starts` (and the solver's `alpha-max` as `alpha_max`)."""
    message = re.sub(r"--([a-z0-9-]+) (?=[-0-9])", lambda m: m[1].replace("-", "_") + "=", message)
    message = re.sub(r"--([a-z0-9-]+)", lambda m: m[1].replace("-", "_"), message)
    return message.replace("alpha-max", "alpha_max")
