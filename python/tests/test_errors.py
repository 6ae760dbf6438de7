"""Bad input raises InputError with the command line's message; no solution raises NoSolution."""

import pytest
from conftest import cli_flags, kwargs

import purcell

BAD = [
    ({"step": -1.0}, ["--step", "-1"]),
    ({"horizon": 1.0, "step": 0.3}, ["--horizon", "1", "--step", "0.3"]),
    ({"links": (1.0, 0.0, 1.0)}, ["--links", "1,0,1"]),
    ({"links": (1.0, 1.0)}, ["--links", "1,1"]),
    ({"alpha0": (3.2, 0.0)}, ["--alpha0", "3.2,0"]),
    ({"alpha_max": 3.5}, ["--alpha-max", "3.5"]),
    ({"ratio": float("nan")}, ["--ratio", "NaN"]),
    ({"starts": 0}, ["--starts", "0"]),
    ({"drag": 1e39}, ["--drag", "1e39"]),
]


@pytest.mark.parametrize(("given", "flags"), BAD)
def test_bad_input_raises_input_error_with_the_cli_message(given, flags, cli, tmp_path):
    done = cli("solve", *flags, "--out", tmp_path / "out", code=2)
    with pytest.raises(purcell.InputError) as e:
        purcell.solve((0.1, 0.1, 0.0), **given)
    assert isinstance(e.value, ValueError)
    assert str(e.value) and str(e.value) in done.stderr


def test_wrong_target_length():
    with pytest.raises(purcell.InputError, match="takes 3 comma-separated numbers"):
        purcell.solve((0.1, 0.1))


def test_unreachable_target_raises_no_solution(cli, public, tmp_path):
    problem = public["isotropic"]
    assert problem["expect"] == "exit 3"
    done = cli("solve", *cli_flags(problem), "--no-plots", "--out", tmp_path / "out", code=3)
    with pytest.raises(purcell.NoSolution) as e:
        purcell.solve(problem["target"], **kwargs(problem))
    assert str(e.value) in done.stderr
    assert e.value.best_residual > 1e-3
    assert e.value.best_alpha is None


def test_connection_bad_shape():
    with pytest.raises(purcell.InputError, match="alpha"):
        purcell.connection((3.5, 0.0))
