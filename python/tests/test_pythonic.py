"""The package speaks Python: its exceptions, signatures, docstrings, arrays, version, reprs,
and an extension without the command line's crates."""

import inspect
import pickle
import re
from importlib.metadata import version
from pathlib import Path

import numpy as np
import pytest

import purcell
import purcell.distributed
from purcell import _purcell

PYTHON = Path(__file__).resolve().parents[1]
PUBLIC = [
    purcell.solve,
    purcell.sweep,
    purcell.replay,
    purcell.connection,
    purcell.field,
    purcell.distributed.sweep,
]


@pytest.fixture(scope="module")
def solved():
    return purcell.solve((0.05, 0.05, 0.1), alpha0=(0.3, 0.3))


def test_exceptions_are_one_family_in_module_purcell():
    for cls, base in [
        (purcell.InputError, ValueError),
        (purcell.NoSolution, RuntimeError),
        (purcell.ReplayFailed, RuntimeError),
    ]:
        assert issubclass(cls, purcell.PurcellError) and issubclass(cls, base)
        assert cls.__module__ == "purcell"
    assert not hasattr(_purcell, "InputError")
    with pytest.raises(purcell.PurcellError):
        purcell.solve((0.1, 0.1, 0.0), step=-1.0)
    # Pickled whole (a Dask worker's exception reaches the client with its attributes).
    e = pickle.loads(pickle.dumps(purcell.NoSolution("none", best_residual=0.5)))
    assert (str(e), e.best_residual, e.best_alpha) == ("none", 0.5, None)
    e = pickle.loads(pickle.dumps(purcell.ReplayFailed("stopped", step=7)))
    assert (type(e), e.step) == (purcell.ReplayFailed, 7)


@pytest.mark.parametrize("f", PUBLIC, ids=lambda f: f.__module__ + "." + f.__name__)
def test_signatures_show_real_defaults_and_numpydoc_documents_each_parameter(f):
    sig = inspect.signature(f)
    assert "Ellipsis" not in str(sig) and "..." not in str(sig), sig
    doc = inspect.getdoc(f)
    for section in ("Parameters", "Returns", "Raises"):
        assert f"\n{section}\n{'-' * len(section)}\n" in doc, (f, section)
    documented = set()
    params = doc.split("Parameters\n----------\n")[1].split("\n\n")[0]
    for line in params.splitlines():
        if line and not line.startswith(" "):
            documented |= {n.strip() for n in line.split(" : ")[0].split(",")}
    assert set(sig.parameters) <= documented, set(sig.parameters) - documented


def test_defaults_are_values():
    p = inspect.signature(purcell.solve).parameters
    assert p["alpha0"].default == (0.0, 0.0) and p["links"].default == (1.0, 1.0, 1.0)
    assert p["starts"].default is None and p["alpha_max"].default is None
    assert inspect.signature(purcell.field).parameters["cells"].default == 180
    save = inspect.signature(purcell.Solution.save).parameters
    assert save["force"].default is False and save["plots"].default is True


def test_result_arrays_are_read_only_and_kept(solved):
    arrays = [solved.t, solved.alpha, solved.u, solved.g, solved.xi, solved.mu, solved.xi0]
    arrays += [solved.extremals[0].alpha]
    r = purcell.replay(solved)
    arrays += [r.t, r.alpha, r.u, r.g]
    c = purcell.connection((0.1, 0.2))
    f = purcell.field(cells=8)
    arrays += [c.A, c.dA, f.centres, f.F]
    for a in arrays:
        assert isinstance(a, np.ndarray) and not a.flags.writeable
    with pytest.raises(ValueError, match="read-only"):
        solved.alpha[0, 0] = 5.0
    assert solved.alpha[0, 0] != 5.0
    # Built once: the same array at each access.
    assert solved.alpha is solved.alpha and solved.g is solved.g
    # A copy is the user's.
    mine = solved.alpha.copy()
    mine[0, 0] = 5.0


def test_version_is_the_package_and_crate_version():
    crate = re.search(r'(?m)^version = "(.*)"$', (PYTHON / "Cargo.toml").read_text())[1]
    assert purcell.__version__ == version("purcell") == crate


def test_reprs_say_what_the_object_is(solved):
    assert re.fullmatch(
        r"Solution\(cost=[0-9.]+, mu=\[.*\], xi0=\[.*\], admissible=True, extremals=\d+\)",
        repr(solved),
    )
    assert repr(solved.extremals[0]).startswith("Extremal(cost=")
    assert repr(purcell.replay(solved)).startswith("Replay(precision='f32', checkpoints=True")
    assert repr(purcell.field(cells=8)) == "Field(cells=8)"
    c = repr(purcell.connection((0.1, 0.2)))
    assert re.fullmatch(r"Connection\(A=array\(\[.*\]\)\)", c, re.DOTALL), c
    plan = _purcell.SweepPlan(
        "0:0.1:2",
        0.1,
        0.0,
        purcell._keywords.problem(
            {
                "horizon": 10.0,
                "step": 0.05,
                "alpha0": (0, 0),
                "alpha_end": None,
                "links": (1, 1, 1),
                "drag": 1.0,
                "ratio": 2.0,
                "alpha_max": None,
                "cost": "effort",
                "starts": 1,
            }
        ),
    )
    assert repr(plan) == "SweepPlan(targets=2, searched=2)"
    assert repr(purcell.Sweep([{}, {}])) == "Sweep(2 records)"


def test_the_extension_links_none_of_the_command_lines_crates():
    names = set(re.findall(r'(?m)^name = "(.*)"$', (PYTHON / "Cargo.lock").read_text()))
    assert "purcell-sim" in names and "pyo3" in names
    assert not names & {"clap", "clap_complete", "clap_mangen", "indicatif"}
