"""Bad input raises InputError with the command line's message in Python's words (keyword
names, not flags); no solution raises NoSolution."""

import pytest
from conftest import cli_flags, in_python_words, kwargs

import purcell

BAD = [
    ({"step": -1.0}, ["--step", "-1"]),
    ({"horizon": 1.0, "step": 0.3}, ["--horizon", "1", "--step", "0.3"]),
    ({"links": (1.0, 0.0, 1.0)}, ["--links", "1,0,1"]),
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
    assert str(e.value) and "--" not in str(e.value)
    (line,) = [x for x in done.stderr.splitlines() if x.startswith("error: ")]
    assert str(e.value) == in_python_words(line.removeprefix("error: "))


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ({"target": (0.1, 0.1)}, "target must have 3 numbers (got 2)"),
        ({"links": (1.0, 1.0)}, "links must have 3 numbers (got 2)"),
        ({"starts": -1}, "starts must be 1 to 4096 (got -1)"),
        ({"seed": -1}, "seed must be 0 or more (got -1)"),
        ({"alpha_max": 3.5}, "alpha_max must be in ]0, pi[ rad"),
        ({"alpha0": (0.5, 0.0), "alpha_max": 0.4}, "must be below alpha_max = 0.4 rad"),
        ({"checkpoint_every": 20000}, "checkpoint_every=20000 is not below"),
        ({"target": (0.0, 0.0, 1e-7)}, "target=(0.0, 0.0, 1e-07): a motion this small"),
    ],
)
def test_messages_name_the_keyword_arguments(given, message):
    given = {"target": (0.1, 0.1, 0.0), **given}
    with pytest.raises(purcell.InputError) as e:
        purcell.solve(**given)
    assert message in str(e.value) and "--" not in str(e.value)


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ({"target": "0.1,0.1,0"}, "target must be a sequence of 3 numbers, not str"),
        ({"target": (0.1, "a", 0.0)}, "target[1] must be a number, not str"),
        ({"drag": "1"}, "drag must be a number, not str"),
        ({"starts": 2.5}, "starts must be a whole number, not float"),
    ],
)
def test_wrong_types_raise_type_error_naming_the_argument(given, message):
    given = {"target": (0.1, 0.1, 0.0), **given}
    with pytest.raises(TypeError) as e:
        purcell.solve(**given)
    assert str(e.value) == message


def test_unreachable_target_raises_no_solution(cli, public, tmp_path):
    problem = public["isotropic"]
    assert problem["expect"] == "exit 3"
    done = cli("solve", *cli_flags(problem), "--no-plots", "--out", tmp_path / "out", code=3)
    with pytest.raises(purcell.PurcellError) as e:
        purcell.solve(problem["target"], **kwargs(problem))
    assert isinstance(e.value, purcell.NoSolution) and isinstance(e.value, RuntimeError)
    # The command line's error, then what to try in Python's words.
    error, advice = str(e.value).split("\ntry ", 1)
    assert error in done.stderr
    assert "another seed (0 now)" in advice and "warm=" in advice and "--" not in advice
    assert e.value.best_residual > 1e-3
    assert e.value.best_alpha is None


def test_connection_bad_shape():
    with pytest.raises(purcell.InputError, match="alpha"):
        purcell.connection((3.5, 0.0))
