"""`purcell.replay` and `purcell.connection` against the command line."""

import json

import numpy as np
import pytest

import purcell


@pytest.fixture(scope="module")
def solved(tmp_path_factory, cli):
    """A solution, its costate file written by the command line, and the CLI's replays."""
    out = tmp_path_factory.mktemp("solve") / "out"
    cli("solve", "--target", "0.05,0.05,0.1", "--alpha0", "0.3,0.3", "--no-plots", "--out", out)
    s = purcell.solve((0.05, 0.05, 0.1), alpha0=(0.3, 0.3))
    return s, out / "costate.json"


@pytest.mark.parametrize("precision", ["f32", "f64"])
@pytest.mark.parametrize("checkpoints", [True, False])
def test_replay_digest_equals_the_cli(solved, cli, tmp_path, precision, checkpoints):
    s, costate = solved
    flags = ["--precision", precision] + ([] if checkpoints else ["--no-checkpoints"])
    cli("replay", "--costate", costate, *flags, "--out", tmp_path / "r.json")
    (theirs,) = json.loads((tmp_path / "r.json").read_text())["replays"]
    for source in (s, s.gait(), costate, str(costate), costate.read_bytes()):
        r = purcell.replay(source, precision, checkpoints=checkpoints)
        assert r.digest == theirs["digest"]
        assert r.final_state_bits == theirs["final_state_bits"]
        assert (r.alpha_error, r.g_error) == (theirs["alpha_error"], theirs["g_error"])
    n = s.u.shape[0]
    assert r.alpha.shape == (n + 1, 2) and r.u.shape == (n, 2) and r.g.shape == (n + 1, 3)
    # A replay without checkpoints drifts from the solution (f32: 3.5e-4 here).
    tol = {"f32": 1e-4 if checkpoints else 1e-2, "f64": 1e-8}[precision]
    np.testing.assert_allclose(r.alpha, s.alpha, atol=tol)
    np.testing.assert_allclose(r.g, s.g, atol=tol)


def test_replay_refuses_a_corrupted_gait(solved):
    s, _ = solved
    gait = bytearray(s.gait())
    gait[40] ^= 1
    with pytest.raises(purcell.InputError):
        purcell.replay(bytes(gait))
    with pytest.raises(purcell.InputError, match="precision"):
        purcell.replay(s, "f16")


def test_connection_equals_the_cli(cli):
    theirs = json.loads(cli("connection", "--alpha", "0.5,-0.3", "--links", "1,1.5,1.5").stdout)
    c = purcell.connection((0.5, -0.3), links=(1, 1.5, 1.5))
    np.testing.assert_array_equal(c.A, theirs["A"])
    np.testing.assert_array_equal(c.dA, [theirs["dA_dalpha1"], theirs["dA_dalpha2"]])
