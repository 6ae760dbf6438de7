"""`purcell.sweep`: a lattice of targets solved by continuation from neighbours, as records."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from . import _keywords, _purcell

if TYPE_CHECKING:
    from typing_extensions import Unpack

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

    def __repr__(self) -> str:
        return f"Sweep({len(self)} records)"

    def to_pandas(self) -> Any:
        """The records as a pandas DataFrame with the columns of COLUMNS (needs pandas)."""
        import pandas as pd

        return pd.DataFrame.from_records(list(self), columns=list(COLUMNS))


@_keywords.takes_problem
def sweep(
    xs: Axis,
    ys: Axis,
    thetas: Axis = (0.0,),
    *,
    progress: Callable[[int, int, str], object] | None = None,
    **problem: Unpack[_keywords.Problem],
) -> Sweep:
    """Every target of a lattice solved as ``purcell-sim sweep`` solves it.

    Each target's own global search (one per orbit of the swimmer's symmetries), then passes
    in which each target starts Newton from its neighbours' cheapest extremals until nothing
    changes, then each target's candidates refined on the fine grid: every target solved at
    least as well as `solve` would.

    Parameters
    ----------
    xs, ys : float, str or sequence of floats
        Target x and y, metres: a number, a sequence of numbers, or the command line's text
        "FROM:TO:COUNT" (COUNT evenly spaced values, exactly as ``--x FROM:TO:COUNT`` spaces
        them). At most 10 000 targets in all.
    thetas : float, str or sequence of floats, default (0.0,)
        Target theta, radians, as `xs`.
    horizon, step, alpha0, alpha_end, links, drag, ratio, alpha_max, cost
        The problem, as in `solve` (seconds, radians, metres).
    starts : int or None, default None
        Budget of each target's global search, 1 to 4096 (None: 1024, 160 with
        ``alpha_max``).
    progress : callable or None, default None
        Called as ``progress(done, total, phase)`` every 0.1 s with the command line's count
        and at the end with ``(total, total, phase)``: the phases "search" (one per target),
        "neighbours" (one) and "refinement" (one per target). An exception it raises cancels.

    Returns
    -------
    Sweep
        The records of sweep.csv (see COLUMNS), x slowest, theta fastest;
        ``.to_pandas()`` gives a DataFrame.

    Raises
    ------
    InputError
        Bad input, before any work: the message names the keyword.
    KeyboardInterrupt
        Ctrl-C, honoured within 0.5 s in every phase.

    Notes
    -----
    The GIL is released while it runs (on all cores).
    """
    return Sweep(_purcell.sweep(xs, ys, thetas, dict(problem), progress))
