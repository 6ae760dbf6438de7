"""Type stubs of the native module (src/*.rs). Units: metres, radians, seconds.

The public functions are the package's (purcell/_solve.py, _model.py, _sweep.py), which check
their arguments' types and counts and call these; the classes are the native module's.
Arrays are read-only.
"""

import os
from collections.abc import Callable, Sequence
from typing import Any, Literal, TypeAlias

import numpy as np
import numpy.typing as npt

F64: TypeAlias = npt.NDArray[np.float64]

__version__: str
COSTS: tuple[str, ...]
"""The running costs' names, the values of `cost=` ("effort", "power", ...)."""

class Connection:
    """The local connection at a shape: body velocity xi = -A(alpha) @ alpha_dot."""

    A: F64
    """A(alpha), shape (3, 2): rows x, y, theta; columns alpha1, alpha2."""
    dA: F64
    """[dA/dalpha1, dA/dalpha2], shape (2, 3, 2), per radian."""

class Extremal:
    """One extremal on the problem's grid with its certificates (arrays built per access)."""

    @property
    def cost(self) -> float:
        """J = sum_k h/2 |u_k|^2, rad^2/s."""
    @property
    def mu(self) -> F64:
        """Spatial momentum mu, shape (3,)."""
    @property
    def xi0(self) -> F64:
        """Initial shape costate xi^{-1}, shape (2,)."""
    @property
    def t(self) -> F64:
        """Times k h, seconds, shape (N+1,)."""
    @property
    def alpha(self) -> F64:
        """Shapes (alpha1, alpha2), radians, shape (N+1, 2)."""
    @property
    def u(self) -> F64:
        """Controls (shape velocities), rad/s, shape (N, 2)."""
    @property
    def g(self) -> F64:
        """Positions (x, y, theta), metres and radians, shape (N+1, 3)."""
    @property
    def xi(self) -> F64:
        """Costate path xi^{k-1}, k = 0..N, shape (N+1, 2)."""
    @property
    def arcs(self) -> list[dict[str, int]]:
        """Joint-limit arcs: {joint, sign, first, last}."""
    @property
    def max_abs_alpha(self) -> float:
        """Largest |alpha_i| along the path, radians."""
    @property
    def admissible(self) -> bool: ...
    @property
    def local_min(self) -> bool:
        """Second-order check: a strict local minimum."""
    @property
    def residual(self) -> float:
        """Terminal defect of the solver's trajectory, m / rad."""
    @property
    def terminal_residual(self) -> float | None:
        """Terminal defect of the controls re-integrated through the core, m / rad."""
    @property
    def kkt_residual(self) -> float | None:
        """KKT residual by reverse mode through the core, rad/s."""
    @property
    def law_residual(self) -> float | None:
        """Relative deviation of the core's law from the controls."""
    @property
    def min_eta(self) -> float | None:
        """Smallest joint-limit multiplier over the arcs."""
    @property
    def stationarity(self) -> float:
        """The solver's own stationarity residual, rad/s."""
    @property
    def uncertified(self) -> str | None:
        """Why the certificates do not vouch for it (None if they do)."""
    @property
    def newton_iterations(self) -> int: ...
    @property
    def start(self) -> int: ...
    @property
    def hits(self) -> int: ...
    @property
    def twin_of(self) -> int | None: ...

class Solution(Extremal):
    """The returned extremal (its attributes), every extremal found, the report, the gait."""

    best: int
    """Index of the returned extremal in `extremals`."""
    extremals: list[Extremal]
    """Every extremal carried to the problem's grid, cheapest first."""
    report: dict[str, Any]
    """report.json of `purcell-sim solve` as a dict."""
    flown: int | None
    """m for a gait flown m times (a tight joint limit where the search led to no gait:
    the loop to the target's m-th root flown m times, refined); None otherwise."""
    recentred: bool
    """Whether the gait (under a joint limit) was reached by walking one of the refinement's
    admissible gaits back up the central path and down again, then refining it."""
    def gait(self) -> bytes:
        """The binary gait file (`purcell-sim export`'s bytes)."""
    def costate(self) -> str:
        """The costate file (costate.json), JSON text."""
    def save(
        self,
        out: str | os.PathLike[str],
        *,
        force: bool = False,
        plots: bool = True,
        degrees: bool = False,
    ) -> None:
        """Writes `purcell-sim solve --out`'s files to `out`, with its safety rules."""

class Replay:
    """One replay of a gait through the core, as firmware flies it."""

    precision: Literal["f32", "f64"]
    checkpoints: bool
    digest: str
    """Trajectory digest, 0x and 16 hex digits (as `purcell-sim replay` prints)."""
    final_state_bits: list[str]
    alpha_error: float
    """max |alpha_N - alpha_end|, radians (alpha_end: alpha0 for a loop)."""
    g_error: float
    """max |log(g_bar^-1 g_N)|, metres / radians."""
    t: F64
    alpha: F64
    u: F64
    g: F64

# The native calls behind the package's functions: `problem` is the dict of
# purcell/_keywords.py's `problem` (with `seed` and `checkpoint_every` for a solve).

def solve(
    target: Sequence[float],
    problem: dict[str, Any],
    warm: Solution | str | os.PathLike[str] | None,
    progress: Callable[[int, int, str], object] | None,
) -> Solution: ...
def replay(
    costate_or_gait: Solution | bytes | bytearray | str | os.PathLike[str],
    precision: str = "f32",
    checkpoints: bool = True,
) -> Replay: ...
def connection(
    alpha: Sequence[float], links: Sequence[float], drag: float, ratio: float
) -> Connection: ...
def field(links: Sequence[float], drag: float, ratio: float, cells: int) -> Field: ...

class Field:
    """The curvature F of the connection on cells covering ]-pi, pi[^2 (MODEL.md §8)."""

    @property
    def centres(self) -> F64:
        """Cell centres along each axis (alpha1 and alpha2), radians, shape (n,)."""
    @property
    def cell(self) -> float:
        """Width of one cell, radians."""
    @property
    def F(self) -> F64:
        """F, shape (3, n, n): rows x, y (m/rad^2), theta (1/rad); [row, j, i] at
        (alpha1, alpha2) = (centres[i], centres[j])."""
    def integral_over(self, path: npt.ArrayLike) -> F64:
        """Integral of F over the area the closed shape path (M, 2), radians, encloses:
        the leading-order net motion (x m, y m, theta rad)."""

# The sweep's native parts; `purcell.sweep` and `purcell.distributed.sweep` (Python) are the
# documented calls.

_Axis: TypeAlias = float | str | Sequence[float]
_Target: TypeAlias = tuple[float, float, float]

def sweep(
    xs: _Axis,
    ys: _Axis,
    thetas: _Axis,
    problem: dict[str, Any],
    progress: Callable[[int, int, str], object] | None = None,
) -> list[dict[str, Any]]:
    """The local sweep: one record per target (the columns of sweep.csv)."""

class SweepPlan:
    """A sweep's lattice and problem, its phases one by one (purcell.distributed)."""

    def __init__(self, xs: _Axis, ys: _Axis, thetas: _Axis, problem: dict[str, Any]) -> None: ...
    @property
    def targets(self) -> list[_Target]:
        """The targets (x m, y m, theta rad), x slowest, theta fastest."""
    def searched(self) -> list[int]:
        """Indices of the targets whose global search runs (one per symmetry orbit)."""
    def passes(self, searched: list[tuple[int, bytes, float]]) -> list[tuple[bytes, bytes, float]]:
        """Phase 2: each target's (own extremals, extremals brought, smallest defect)."""

def sweep_search(targets: Sequence[_Target], problem: dict[str, Any]) -> list[tuple[bytes, float]]:
    """Phase 1 for a batch: each target's coarse extremals (bytes) and smallest defect, m / rad."""

def sweep_refine(
    cells: Sequence[tuple[_Target, tuple[bytes, bytes, float]]], problem: dict[str, Any]
) -> list[dict[str, Any]]:
    """Phase 3 for a batch: each target's record."""
