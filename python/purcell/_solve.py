"""`purcell.solve`: the cheapest admissible gait to a target."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from . import _keywords, _purcell
from ._purcell import Solution

if TYPE_CHECKING:
    from typing_extensions import Unpack


@_keywords.takes_problem
def solve(
    target: Sequence[float],
    *,
    seed: int = 0,
    checkpoint_every: int | None = None,
    warm: Solution | str | os.PathLike[str] | None = None,
    progress: Callable[[int, int, str], object] | None = None,
    **problem: Unpack[_keywords.Problem],
) -> Solution:
    """The cheapest admissible gait that moves the swimmer from the origin to `target`.

    The optimal control problem of MODEL.md §4, solved as ``purcell-sim solve`` solves it,
    with the same defaults and checks: a global search over start loops, its minima refined
    on the problem's grid and certified (MODEL.md §5).

    Parameters
    ----------
    target : sequence of 3 floats
        The final position (x, y, theta), metres and radians (theta taken modulo 2 pi into
        ]-pi, pi]).
    horizon : float, default 100.0
        The duration T, seconds: a whole number of steps.
    step : float, default 0.01
        The time step h, seconds.
    alpha0 : sequence of 2 floats, default (0.0, 0.0)
        The start shape (alpha1, alpha2), radians.
    alpha_end : sequence of 2 floats or None, default None
        The end shape, radians (None: `alpha0`, a closed loop).
    links : sequence of 3 floats, default (1.0, 1.0, 1.0)
        Link lengths (L0 middle, L1 front, L2 rear), metres.
    drag : float, default 1.0
        The drag coefficient k.
    ratio : float, default 2.0
        Normal over tangential drag.
    alpha_max : float or None, default None
        Joint limit ``|alpha_i| <= alpha_max``, radians, below pi (None: only the links'
        overlap at pi).
    cost : {"effort", "power"}, default "effort"
        The running cost minimised: "effort", the joints' ``sum h/2 |u_k|^2`` (the
        paper's), or "power", what the fluid dissipates, ``sum h/2 u_k^T G(alpha_k) u_k``
        (MODEL.md §11). The report gives the returned gait's cost under both
        (``report["costs"]``).
    starts : int or None, default None
        Budget of start loops of the global search, 1 to 4096 (None: 1024, 160 with
        ``alpha_max``, the 96 rim loops riding the limit first); the search may stop sooner,
        by its stopping rule (after at least 128 starts, 64 with ``alpha_max``).
    seed : int, default 0
        Orders the starts after the first 128, which are seed 0's for every seed (with
        ``alpha_max`` every seed runs seed 0's order, so the seed does not change the gait).
    checkpoint_every : int or None, default None
        Costate checkpoint spacing in steps in the costate file (None: 100; 0: none).
    warm : Solution, str, os.PathLike or None, default None
        A Solution, or the path of a costate file (costate.json), whose extremal (replayed)
        starts the solve (the command line's ``--from``): continuation from its target to
        this one, of any swimmer; the global search, with a UserWarning, if that reaches no
        admissible extremal.
    progress : callable or None, default None
        Called as ``progress(done, total, phase)`` every 0.1 s and at the end with
        ``(total, total, phase)``, from the calling thread. Phases: "search" (start loops
        finished of starts + 1, the zero loop included; the search may stop sooner),
        "refinement" (candidates carried to the problem's grid); with `warm`,
        "continuation" first. An exception it raises cancels the solve.

    Returns
    -------
    Solution
        The returned extremal (its attributes are the Solution's), every extremal found,
        the report (report.json) and the costate and gait files.

    Raises
    ------
    InputError
        Bad input, before any work (a ValueError): the message names the keyword.
    NoSolution
        No admissible extremal (the command line's exit code 3).
    TypeError
        An argument of the wrong type.
    KeyboardInterrupt
        Ctrl-C, honoured within 0.5 s in every phase.

    Warns
    -----
    UserWarning
        The search spent its budget before its stopping rule was met, or left unrefined a
        minimum that may be cheaper; `warm` reached no admissible extremal.

    Notes
    -----
    The GIL is released while the solver runs (on all cores).

    Examples
    --------
    >>> s = purcell.solve((0.1, 0.1, 0.0))  # doctest: +SKIP
    >>> s.cost, s.alpha.shape  # doctest: +SKIP
    (0.0179..., (10001, 2))
    """
    problem["seed"] = _keywords.count("seed", seed)
    if checkpoint_every is not None:
        problem["checkpoint_every"] = _keywords.count("checkpoint_every", checkpoint_every)
    target = _keywords.numbers_of("target", target, 3)
    return _purcell.solve(target, dict(problem), warm, progress)
