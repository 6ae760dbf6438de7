"""Exact optimal gaits of the planar three-link Purcell swimmer (MODEL.md of the repository).

`solve` finds the cheapest admissible shape loop that moves the swimmer from the origin to a
target and returns its trajectory, costate and certificates as numpy arrays (read-only);
`replay` flies a stored gait through the embedded core as firmware does; `connection` is the
local connection A(alpha) and `field` its curvature over the shape plane; `sweep` solves a
lattice of targets (`purcell.distributed.sweep` on a Dask cluster). `Solution.save` writes the
command line's files. Units: metres, radians, seconds. Defaults and checks are those of the
`purcell-sim` command line; every exception is a `PurcellError`.
"""

from ._errors import InputError, NoSolution, PurcellError, ReplayFailed
from ._model import connection, field, replay
from ._purcell import Connection, Extremal, Field, Replay, Solution, __version__
from ._solve import solve
from ._sweep import COLUMNS, Sweep, sweep

__all__ = [
    "COLUMNS",
    "Connection",
    "Extremal",
    "Field",
    "InputError",
    "NoSolution",
    "PurcellError",
    "Replay",
    "ReplayFailed",
    "Solution",
    "Sweep",
    "__version__",
    "connection",
    "field",
    "replay",
    "solve",
    "sweep",
]
