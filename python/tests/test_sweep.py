"""`purcell.sweep` against `purcell-sim sweep`, and `purcell.distributed.sweep` against it."""

import csv
import time

import pytest
from conftest import in_python_words

import purcell

# Short horizons: the same lattice code as the paper's horizon, a second or two each.
SMALL = {"horizon": 10.0, "step": 0.05}
CASES = [
    (("-0.1:0.1:3", "0:0.2:3", "0"), SMALL, []),
    # Under a joint limit a budget of 128 starts (not 160) keeps the searches short.
    (
        ("0.05:0.15:2", "0.05", "0:0.2:2"),
        dict(SMALL, alpha_max=1.5, starts=128),
        ["--alpha-max", "1.5", "--starts", "128"],
    ),
]


def cli_sweep(cli, tmp_path, axes, given, flags):
    """The command line's sweep.csv rows for the same lattice and problem."""
    x, y, theta = axes
    out = tmp_path / "out"
    steps = ["--horizon", repr(given["horizon"]), "--step", repr(given["step"])]
    cli("sweep", "--x", x, "--y", y, "--theta", theta, *steps, *flags, "--no-plots", "--out", out)
    with open(out / "sweep.csv", newline="") as f:
        rows = list(csv.reader(f))
    # The records' keys are sweep.csv's columns without their units, in its order.
    assert [c.split("_rad")[0].removesuffix("_m") for c in rows[0]] == list(purcell.COLUMNS)
    return [dict(zip(purcell.COLUMNS, row, strict=True)) for row in rows[1:]]


def assert_equals_csv(records, rows):
    """Every record equal to its sweep.csv row (numbers exactly: the CSV's round-trip)."""
    assert len(records) == len(rows)
    for mine, theirs in zip(records, rows, strict=True):
        assert list(mine) == list(purcell.COLUMNS) == list(theirs)
        for k in ("x", "y", "theta", "cost", "residual", "max_abs_alpha", "kkt_residual"):
            expected = float(theirs[k]) if theirs[k] else None
            assert mine[k] == expected, (k, mine, theirs)
        for k in ("admissible", "local_min"):
            expected = {"true": True, "false": False, "": None}[theirs[k]]
            assert mine[k] is expected, (k, mine, theirs)
        assert mine["status"] == theirs["status"]


@pytest.mark.parametrize(("axes", "given", "flags"), CASES)
def test_sweep_equals_the_command_line(axes, given, flags, cli, tmp_path):
    rows = cli_sweep(cli, tmp_path, axes, given, flags)
    calls = []
    records = purcell.sweep(*axes, **given, progress=lambda *a: calls.append(a))
    assert_equals_csv(records, rows)
    assert calls[-1] == (len(rows), len(rows), "refinement")
    phases = [c[2] for c in calls]
    assert phases == sorted(phases, key=["search", "neighbours", "refinement"].index)
    if flags:
        return
    # Axes as numbers give the same records as the command line's FROM:TO:COUNT.
    xs = sorted({float(r["x"]) for r in rows})
    ys = sorted({float(r["y"]) for r in rows})
    thetas = sorted({float(r["theta"]) for r in rows})
    assert purcell.sweep(xs, ys, thetas, **given) == records


def test_to_pandas():
    pd = pytest.importorskip("pandas")
    records = purcell.sweep([0.0, 0.1], 0.05, **SMALL)
    frame = records.to_pandas()
    assert isinstance(frame, pd.DataFrame)
    assert list(frame.columns) == list(purcell.COLUMNS)
    assert frame["cost"].tolist() == [r["cost"] for r in records]


@pytest.mark.parametrize(
    ("axes", "flags"),
    [
        (("1:2:0", "0"), ["--x", "1:2:0", "--y", "0"]),
        (("0", "a"), ["--x", "0", "--y", "a"]),
        (("0:1:200", "0:1:200"), ["--x", "0:1:200", "--y", "0:1:200"]),
    ],
)
def test_bad_lattice_raises_input_error_with_the_cli_message(axes, flags, cli, tmp_path):
    done = cli("sweep", *flags, "--no-plots", "--out", tmp_path / "out", code=2)
    with pytest.raises(purcell.InputError) as e:
        purcell.sweep(*axes)
    assert str(e.value) and "--" not in str(e.value)
    assert str(e.value) in in_python_words(done.stderr)


def test_bad_problem_raises_input_error():
    with pytest.raises(purcell.InputError, match="^starts must be 1 to"):
        purcell.sweep(0.1, 0.1, starts=0)
    with pytest.raises(purcell.InputError, match="finite"):
        purcell.sweep([0.1, float("nan")], 0.1)


def test_distributed_sweep_equals_the_local_one():
    distributed = pytest.importorskip("distributed")
    import purcell.distributed

    axes, given, _ = CASES[0]
    local = purcell.sweep(*axes, **given)
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    with cluster, distributed.Client(cluster) as client:
        remote = purcell.distributed.sweep(client, *axes, batch=2, **given)
        with pytest.raises(purcell.InputError, match="batch"):
            purcell.distributed.sweep(client, *axes, batch=0, **given)
    assert len(remote) == len(local)
    for mine, theirs in zip(remote, local, strict=True):
        assert abs(mine["cost"] - theirs["cost"]) <= 1e-12
        # In fact the same records, bit for bit: the same candidates reach every target.
        assert mine == theirs


@pytest.mark.parametrize("phase", ["search", "neighbours", "refinement"])
def test_an_interrupt_stops_the_sweep_within_half_a_second(phase):
    # 100 000 steps: each target's refinement takes seconds, its search a second or more;
    # the neighbour passes (Newton on the coarse grid) a fraction of a second.
    polls = []

    def stop(done, total, now):
        polls.append((time.perf_counter(), now))
        if now == phase:
            raise KeyboardInterrupt

    try:
        purcell.sweep("0:0.1:2", 0.05, step=0.001, progress=stop)
    except KeyboardInterrupt:
        raised = next(t for t, now in polls if now == phase)
        assert time.perf_counter() - raised <= 0.5
    else:
        # A phase shorter than the 0.1 s between two calls of `progress` is never current at
        # one: then it held an interrupt no longer than that gap.
        assert phase == "neighbours", f"the sweep ended before its {phase} was seen"
        before = max(t for t, now in polls if now == "search")
        after = min(t for t, now in polls if now == "refinement")
        assert after - before <= 0.5
