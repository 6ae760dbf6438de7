"""`purcell.sweep`: a lattice of targets solved by continuation from neighbours, as records."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from . import _purcell

#: sweep.csv's columns without their units (x for x_m, cost for cost_rad2_per_s, ...), in its
#: order: target x (m), y (m), theta (rad); J (rad^2/s); terminal
#: defect (m / rad); largest |alpha_i| (rad); admissible; strict local minimum; KKT residual
#: (rad/s); "ok" where the certificates vouch for the extremal, else which one does not, or
#: why the target has no extremal (then the numbers are None).
COLUMNS = (
    "x",
    "y",
    "theta",
    "cost",
    "residual",
    "max_abs_alpha",
    "admissible",
    "local_min",
    "kkt_residual",
    "status",
)

Axis = float | str | Sequence[float]


class Sweep(list):
    """A sweep's records (dicts with the keys of COLUMNS), x slowest, theta fastest."""

    def to_pandas(self) -> Any:
        """The records as a pandas DataFrame with the columns of COLUMNS (needs pandas)."""
        import pandas as pd

        return pd.DataFrame.from_records(list(self), columns=list(COLUMNS))


def problem_kwargs(
    horizon: float,
    step: float,
    alpha0: Sequence[float],
    links: Sequence[float],
    drag: float,
    ratio: float,
    alpha_max: float | None,
    starts: int,
) -> dict[str, Any]:
    """The problem's arguments as the native module takes them."""
    return {
        "horizon": horizon,
        "step": step,
        "alpha0": list(alpha0),
        "links": list(links),
        "drag": drag,
        "ratio": ratio,
        "alpha_max": alpha_max,
        "starts": starts,
    }


def sweep(
    xs: Axis,
    ys: Axis,
    thetas: Axis = (0.0,),
    *,
    horizon: float = 100.0,
    step: float = 0.01,
    alpha0: Sequence[float] = (0.0, 0.0),
    links: Sequence[float] = (1.0, 1.0, 1.0),
    drag: float = 1.0,
    ratio: float = 2.0,
    alpha_max: float | None = None,
    starts: int = 512,
    progress: Callable[[int, int, str], object] | None = None,
) -> Sweep:
    """Every target of a lattice solved as `purcell-sim sweep` solves it: the same records as
    its sweep.csv (see COLUMNS), x slowest, theta fastest. `.to_pandas()` gives a DataFrame.

    xs, ys: target x and y, metres; thetas: target theta, radians. Each axis is a number, a
    sequence of numbers, or the command line's text "FROM:TO:COUNT" (COUNT evenly spaced
    values, exactly as `--x FROM:TO:COUNT` spaces them); at most 10 000 targets in all.
    The problem's arguments are `solve`'s (horizon and step in seconds, alpha0 and alpha_max
    in radians, links in metres); `starts` is the budget of each target's global search.

    Each target's own global search (one per orbit of the swimmer's symmetries), then passes
    in which each target starts Newton from its neighbours' cheapest extremals until nothing
    changes, then each target's candidates refined on the fine grid: every target solved at
    least as well as `solve` would. The GIL is released while it runs (on all cores);
    progress(done, total, phase) is called every 0.1 s with the command line's count, and at
    the end with (total, total, phase): the phases "search" (one per target), "neighbours"
    (one) and "refinement" (one per target); Ctrl-C or an exception in progress cancels.
    Raises InputError with the command line's message for bad input.
    """
    kw = problem_kwargs(horizon, step, alpha0, links, drag, ratio, alpha_max, starts)
    return Sweep(_purcell.sweep(xs, ys, thetas, kw, progress))
