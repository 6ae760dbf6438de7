"""`purcell.solve` against `purcell-sim solve` on the paper's problem and two public ones."""

import json
import threading
import time

import numpy as np
import pytest
from conftest import cli_flags, kwargs

import purcell

TOL = 1e-12


def close(a, b, path="report"):
    """Asserts that two JSON values are equal, numbers to TOL relative (absolute below 1)."""
    if isinstance(a, dict):
        assert a.keys() == b.keys(), path
        for k in a:
            close(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            close(x, y, f"{path}[{i}]")
    elif isinstance(a, float) and not isinstance(b, bool):
        assert abs(a - b) <= TOL * max(1.0, abs(a)), (path, a, b)
    else:
        assert a == b, (path, a, b)


@pytest.mark.parametrize("name", ["paper", "bent-start", "joint-limit-1.5"])
def test_solve_equals_the_command_line(name, cli, public, tmp_path):
    problem = public[name]
    out = tmp_path / "out"
    cli("solve", *cli_flags(problem), "--no-plots", "--out", out)
    report = json.loads((out / "report.json").read_text())
    s = purcell.solve(problem["target"], **kwargs(problem))
    assert abs(s.cost - report["cost"]) <= TOL
    np.testing.assert_allclose(s.mu, report["mu"], rtol=0, atol=TOL)
    np.testing.assert_allclose(s.xi0, report["xi0"], rtol=0, atol=TOL)
    mine = dict(s.report, solve_seconds=None)
    close(mine, dict(report, solve_seconds=None))
    assert s.arcs == report["arcs"]
    assert [x.cost for x in s.extremals] == [x["cost"] for x in report["extremals"]]
    assert s.uncertified is None
    assert s.flown is None and report["flown"] is None
    assert s.recentred is False and report["recentred"] is False
    assert s.costate() == (out / "costate.json").read_text()
    # The trajectory as trajectory.csv has it (k, t, alpha, u with a last row of 0, g, xi,
    # the arc flags).
    csv = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    u = np.vstack([s.u, np.zeros(2)])
    np.testing.assert_array_equal(csv[:, 0], np.arange(len(s.t)))
    np.testing.assert_array_equal(np.column_stack([s.t, s.alpha, u, s.g, s.xi]), csv[:, 1:11])
    n = round(report["problem"]["steps"])
    assert s.alpha.shape == (n + 1, 2) and s.u.shape == (n, 2) and s.g.shape == (n + 1, 3)
    assert s.xi.shape == (n + 1, 2)
    np.testing.assert_array_equal(s.xi[0], s.xi0)


def test_gait_is_the_exported_file(cli, tmp_path):
    s = purcell.solve((0.05, 0.05, 0.1), alpha0=(0.3, 0.3))
    (tmp_path / "costate.json").write_text(s.costate())
    cli("export", "--costate", tmp_path / "costate.json", "--out", tmp_path / "gait.bin")
    assert s.gait() == (tmp_path / "gait.bin").read_bytes()


def test_progress_counts_each_phase_to_its_total():
    calls = []
    purcell.solve((0.05, 0.05, 0.1), alpha0=(0.3, 0.3), progress=lambda *a: calls.append(a))
    assert calls, "progress is called at least at the end"
    done, total, phase = calls[-1]
    assert phase == "refinement" and done == total > 0
    assert all(c[2] in ("search", "refinement") for c in calls)
    search = [c for c in calls if c[2] == "search"]
    # The default budget without a joint limit (1 024 starts) and the zero loop.
    assert all(c[1] == 1025 for c in search)
    assert [c[0] for c in search] == sorted(c[0] for c in search)
    assert all(0 <= c[0] <= c[1] for c in calls)


@pytest.fixture(scope="module")
def warm():
    """A quick solution to start a continuation from."""
    return purcell.solve((0.05, 0.05, 0.1), alpha0=(0.3, 0.3))


@pytest.mark.parametrize(
    ("phase", "given"),
    [
        ("search", {}),
        ("refinement", {}),
        # A joint-limited refinement: its barrier path and active-set rounds (homotopy.rs).
        ("refinement", {"alpha_max": 1.5}),
        # A warm start's Newton and continuation (continue_to).
        ("continuation", {"warm": True}),
    ],
    ids=["search", "refinement", "limited-refinement", "continuation"],
)
def test_an_interrupt_stops_the_solve_within_half_a_second(phase, given, request):
    # 100 000 steps: the refinement and a continuation take seconds, the search a few tenths.
    if given.get("warm"):
        given = {"warm": request.getfixturevalue("warm"), "alpha0": (0.3, 0.3)}
    raised = []

    def stop(done, total, now):
        if now == phase:
            raised.append(time.perf_counter())
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        purcell.solve((0.1, 0.1, 0.0), step=0.001, progress=stop, **given)
    assert raised, f"the solve ended before its {phase} was seen"
    assert time.perf_counter() - raised[0] <= 0.5


def test_another_thread_runs_during_a_solve():
    ticks = []
    running = threading.Event()
    running.set()

    def count():
        while running.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.002)

    worker = threading.Thread(target=count)
    worker.start()
    time.sleep(0.02)
    t0 = time.perf_counter()
    purcell.solve((0.1, 0.1, 0.0))
    t1 = time.perf_counter()
    running.clear()
    worker.join()
    during = [t for t in ticks if t0 <= t <= t1]
    # At most a few ms between ticks: the GIL is released while the solver runs.
    assert len(during) >= 0.25 * (t1 - t0) / 0.002, (len(during), t1 - t0)


def test_a_transition_ends_in_its_own_shape():
    s = purcell.solve((0.1, 0.1, 0.0), alpha0=(1.0, 0.8), alpha_end=(0.0, 0.0))
    np.testing.assert_array_equal(s.alpha[0], (1.0, 0.8))
    assert np.abs(s.alpha[-1]).max() < 1e-12
    r = purcell.replay(s)
    assert r.alpha_error < 1e-6 and r.g_error < 1e-6
    assert '"alpha_end"' in s.costate() and s.gait()[8] == 4


def test_power_solve_equals_the_command_line(cli, tmp_path):
    """`cost="power"` (issue 37): the paper's problem for the power the fluid dissipates, as
    `purcell-sim solve --cost power` solves it; the returned cost is report["costs"]'s power,
    below the effort-optimal gait's 0.183631 (docs/MEASUREMENTS.md, "Effort against power")."""
    out = tmp_path / "out"
    cli("solve", "--cost", "power", "--no-plots", "--out", out)
    report = json.loads((out / "report.json").read_text())
    s = purcell.solve((0.1, 0.1, 0.0), cost="power")
    assert s.report["problem"]["cost"] == report["problem"]["cost"] == "power"
    assert s.cost == s.report["cost"] == s.report["costs"]["power"]
    close(dict(s.report, solve_seconds=None), dict(report, solve_seconds=None))
    assert s.costate() == (out / "costate.json").read_text()
    assert json.loads(s.costate())["cost"] == "power"
    assert s.uncertified is None
    assert 0.1306 < s.cost < 0.183631


def test_sweep_takes_the_cost_and_checks_it():
    small = {"horizon": 10.0, "starts": 64}
    swept = purcell.sweep(0.001, 0.0, cost="power", **small)
    # 64 starts are below the search's stopping rule on this target: it says so.
    with pytest.warns(UserWarning, match="budget of 64 starts"):
        solved = purcell.solve((0.001, 0.0, 0.0), cost="power", **small)
    effort = purcell.sweep(0.001, 0.0, **small)
    assert abs(swept[0]["cost"] - solved.cost) <= 1e-9 * solved.cost
    assert effort[0]["cost"] != swept[0]["cost"]
    with pytest.raises(purcell.InputError, match="cost must be one of 'effort', 'power'"):
        purcell.solve((0.1, 0.1, 0.0), cost="Power")
    with pytest.raises(TypeError, match="cost must be a str"):
        purcell.sweep(0.1, 0.1, cost=1)
