"""`purcell.field`, `Solution.save` and `solve(warm=...)` against the command line."""

import json
import warnings

import numpy as np
import pytest
from test_solve import close

import purcell

TARGET = (0.05, 0.05, 0.1)
ALPHA0 = (0.3, 0.3)


def test_field_equals_field_csv(cli, tmp_path):
    cli("field", "--links", "1,1.5,1.5", "--ratio", "3", "--out", tmp_path / "f")
    csv = np.loadtxt(tmp_path / "f" / "field.csv", delimiter=",", skiprows=1)
    f = purcell.field(links=(1, 1.5, 1.5), ratio=3.0)
    n = f.centres.shape[0]
    assert n == 180 and f.F.shape == (3, n, n)
    a1, a2 = np.meshgrid(f.centres, f.centres)
    mine = np.column_stack([a1.ravel(), a2.ravel(), *(f.F[r].ravel() for r in range(3))])
    np.testing.assert_array_equal(mine, csv)
    assert f.cell == pytest.approx(2 * np.pi / 180)


def test_field_integral_is_the_small_loop_motion():
    f = purcell.field(cells=360)
    s = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    loop = 0.1 * np.column_stack([np.cos(s), np.sin(s)])
    i = f.integral_over(loop)
    # F near the origin times the disc's area (counter-clockwise: positive).
    c = f.F[:, 179, 179] + f.F[:, 180, 180]
    np.testing.assert_allclose(i, c / 2 * np.pi * 0.01, rtol=0.1, atol=1e-9)
    with pytest.raises(purcell.InputError, match="cells"):
        purcell.field(cells=0)


@pytest.fixture(scope="module")
def solved():
    return purcell.solve(TARGET, alpha0=ALPHA0)


def test_save_writes_the_command_line_files(solved, cli, tmp_path):
    flags = ["--target", "0.05,0.05,0.1", "--alpha0", "0.3,0.3"]
    cli("solve", *flags, "--out", tmp_path / "cli")
    solved.save(tmp_path / "py")
    names = sorted(p.name for p in (tmp_path / "cli").iterdir())
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == names
    for name in ("trajectory.csv", "costate.json"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    mine, theirs = (json.loads((tmp_path / d / "report.json").read_text()) for d in ("py", "cli"))
    close(dict(mine, solve_seconds=None), dict(theirs, solve_seconds=None))
    # The same rules as --out: a previous result is replaced, anything else refused.
    solved.save(tmp_path / "py", plots=False)
    assert not (tmp_path / "py" / "shape_loop.svg").exists()
    other = tmp_path / "other"
    other.mkdir()
    (other / "notes.txt").write_text("mine")
    cli("solve", *flags, "--no-plots", "--out", other, code=2)
    with pytest.raises(purcell.InputError, match=r"pass force=True to replace it anyway\)$"):
        solved.save(other)
    assert (other / "notes.txt").read_text() == "mine"
    solved.save(other, force=True, plots=False)
    assert (other / "costate.json").exists()


def test_warm_equals_from(solved, cli, tmp_path):
    (tmp_path / "costate.json").write_text(solved.costate())
    target = (0.06, 0.05, 0.1)
    flags = ["--target", "0.06,0.05,0.1", "--alpha0", "0.3,0.3", "--no-plots"]
    cli("solve", *flags, "--from", tmp_path / "costate.json", "--out", tmp_path / "out")
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for warm in (solved, tmp_path / "costate.json", str(tmp_path / "costate.json")):
            s = purcell.solve(target, alpha0=ALPHA0, warm=warm)
            close(dict(s.report, solve_seconds=None), dict(report, solve_seconds=None))
    assert len(s.extremals) == 1
    # Another swimmer: the same gait continued to a drag ratio 10 % larger, as --from does.
    cli(
        "solve",
        *flags,
        "--ratio",
        "2.2",
        "--from",
        tmp_path / "costate.json",
        "--out",
        tmp_path / "r22",
    )
    report = json.loads((tmp_path / "r22" / "report.json").read_text())
    s = purcell.solve(target, alpha0=ALPHA0, ratio=2.2, warm=solved)
    close(dict(s.report, solve_seconds=None), dict(report, solve_seconds=None))
    with pytest.raises(purcell.InputError, match="warm takes"):
        purcell.solve(target, warm=3)
