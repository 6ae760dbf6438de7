"""Sweeps beyond one machine, on Dask distributed: `sweep(client, xs, ys, ...)`.

The sweep runs in the three phases of the local `purcell.sweep`, with the same results:
1. the global searches (one per orbit of the swimmer's symmetries), in batches of `batch`
   targets, one task each, on the cluster;
2. the neighbour passes (Newton on the coarse grid from each target's neighbours' cheapest
   extremals, until nothing changes), on the calling machine: they need the whole lattice,
   and cost a fraction of the searches;
3. each target's candidates refined on the fine grid, in batches of `batch` targets, one task
   each, on the cluster.
The coarse extremals travel between the phases as bytes (exact f64s), so every target ends
with the same candidates and the same extremal as in the local sweep, bit for bit.

Dask rather than Ray: a pure-Python install (`pip install "dask[distributed]"`), a
`LocalCluster` for a laptop or a test, and the same code on a batch cluster through
dask-jobqueue (`SLURMCluster`, `PBSCluster`, ...) or on Kubernetes. The package itself does
not import Dask: pass any `distributed.Client`; its workers need `purcell` installed.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from . import _keywords, _purcell
from ._errors import InputError
from ._sweep import Axis, Sweep

if TYPE_CHECKING:
    from typing_extensions import Unpack


def _search(targets: list[tuple[float, float, float]], problem: dict[str, Any]) -> list:
    """Phase 1 on a worker: each target's coarse extremals (bytes) and smallest defect."""
    return _purcell.sweep_search(targets, problem)


def _refine(cells: list, problem: dict[str, Any]) -> list[dict[str, Any]]:
    """Phase 3 on a worker: each cell's record."""
    return _purcell.sweep_refine(cells, problem)


def _batches(items: list, size: int) -> list[list]:
    return [items[i : i + size] for i in range(0, len(items), size)]


@_keywords.takes_problem
def sweep(
    client: Any,
    xs: Axis,
    ys: Axis,
    thetas: Axis = (0.0,),
    *,
    batch: int = 8,
    **problem: Unpack[_keywords.Problem],
) -> Sweep:
    """`purcell.sweep` on a Dask cluster: the same records, in the same order.

    Parameters
    ----------
    client : distributed.Client
        The cluster's client; its workers need `purcell` installed.
    xs, ys, thetas
        The lattice, as in `purcell.sweep`.
    batch : int, default 8
        Targets per task (searches and refinements). A task uses all of its worker's cores
        (the solver's threads): one worker per machine with one thread is the usual layout.
    horizon, step, alpha0, alpha_end, links, drag, ratio, alpha_max, cost, starts
        The problem, as in `purcell.sweep` (metres, radians, seconds).

    Returns
    -------
    Sweep
        The records of `purcell.sweep`, bit for bit.

    Raises
    ------
    InputError
        Bad input, before anything is submitted.
    """
    if isinstance(batch, bool) or not isinstance(batch, int) or batch < 1:
        raise InputError(f"batch must be a whole number of targets, 1 or more (got {batch!r})")
    kw = dict(problem)
    plan = _purcell.SweepPlan(xs, ys, thetas, kw)
    targets = plan.targets
    searched = plan.searched()
    chunks = _batches(searched, batch)
    futures = client.map(_search, [[targets[i] for i in c] for c in chunks], problem=kw, pure=False)
    found = [
        (i, own, residual)
        for c, results in zip(chunks, client.gather(futures), strict=True)
        for i, (own, residual) in zip(c, results, strict=True)
    ]
    cells = list(zip(targets, plan.passes(found), strict=True))
    futures = client.map(_refine, _batches(cells, batch), problem=kw, pure=False)
    return Sweep(r for records in client.gather(futures) for r in records)
