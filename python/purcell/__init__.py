"""Exact optimal gaits of the planar three-link Purcell swimmer (MODEL.md of the repository).

`solve` finds the cheapest admissible shape loop that moves the swimmer from the origin to a
target and returns its trajectory, costate and certificates as numpy arrays; `replay` flies a
stored gait through the embedded core as firmware does; `connection` is the local connection
A(alpha). Units: metres, radians, seconds. Defaults, checks and messages are those of the
`purcell-sim` command line.
"""

from ._purcell import (
    Connection,
    Extremal,
    InputError,
    NoSolution,
    Replay,
    ReplayFailed,
    Solution,
    connection,
    replay,
    solve,
)

__all__ = [
    "Connection",
    "Extremal",
    "InputError",
    "NoSolution",
    "Replay",
    "ReplayFailed",
    "Solution",
    "connection",
    "replay",
    "solve",
]
