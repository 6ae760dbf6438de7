"""The swimmer's geometry and stored gaits: `connection`, `field`, `replay`."""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Literal

from . import _purcell
from ._keywords import number, numbers_of, whole
from ._purcell import Connection, Field, Replay, Solution


def connection(
    alpha: Sequence[float],
    *,
    links: Sequence[float] = (1.0, 1.0, 1.0),
    drag: float = 1.0,
    ratio: float = 2.0,
) -> Connection:
    """The local connection A(alpha) of the swimmer and its derivatives (MODEL.md §2).

    Parameters
    ----------
    alpha : sequence of 2 floats
        The shape (alpha1, alpha2), radians, each ``|alpha_i| < pi``.
    links, drag, ratio
        The swimmer, as in `solve`: link lengths (L0 middle, L1 front, L2 rear, metres),
        the drag coefficient k and normal over tangential drag.

    Returns
    -------
    Connection
        ``A`` (3, 2) and ``dA`` (2, 3, 2) at `alpha`, as ``purcell-sim connection`` prints
        them; the body velocity is ``xi = -A @ alpha_dot``.

    Raises
    ------
    InputError
        A shape or swimmer the command line refuses.
    """
    return _purcell.connection(
        numbers_of("alpha", alpha, 2),
        numbers_of("links", links, 3),
        number("drag", drag),
        number("ratio", ratio),
    )


def field(
    *,
    links: Sequence[float] = (1.0, 1.0, 1.0),
    drag: float = 1.0,
    ratio: float = 2.0,
    cells: int = 180,
) -> Field:
    """The curvature of the local connection over the shape plane (MODEL.md §8).

    ``F(alpha) = -(dA2/dalpha1 - dA1/dalpha2) + [A1, A2]``, sampled at the centres of
    `cells` x `cells` cells covering ]-pi, pi[^2: ``purcell-sim field``'s field.csv (180
    cells, 2-degree cells) as arrays.

    Parameters
    ----------
    links, drag, ratio
        The swimmer, as in `solve`: link lengths (L0 middle, L1 front, L2 rear, metres),
        the drag coefficient k and normal over tangential drag.
    cells : int, default 180
        Cells per axis, 1 to 4096.

    Returns
    -------
    Field
        ``centres`` (n,), ``F`` (3, n, n) and ``integral_over(path)``.

    Raises
    ------
    InputError
        A swimmer the command line refuses, or `cells` outside 1 to 4096.
    """
    return _purcell.field(
        numbers_of("links", links, 3),
        number("drag", drag),
        number("ratio", ratio),
        whole("cells", cells),
    )


def replay(
    costate_or_gait: Solution | bytes | bytearray | str | os.PathLike[str],
    precision: Literal["f32", "f64"] = "f32",
    checkpoints: bool = True,
) -> Replay:
    """Replays a stored gait through the core in f32 or f64, as firmware flies it.

    The same checks, digest and terminal error as ``purcell-sim replay --precision``
    (MODEL.md §6), and the trajectory as arrays.

    Parameters
    ----------
    costate_or_gait : Solution, bytes, bytearray, str or os.PathLike
        A Solution, the bytes of a gait file or of a costate file, or the path of either.
    precision : {"f32", "f64"}, default "f32"
        The scalar type: "f32" is the Cortex-M4F's.
    checkpoints : bool, default True
        Apply the gait's costate checkpoints (without: only those at the joint-limit arcs'
        exits).

    Returns
    -------
    Replay
        ``digest``, ``final_state_bits``, ``alpha_error``, ``g_error`` and the trajectory
        ``t``, ``alpha``, ``u``, ``g``.

    Raises
    ------
    InputError
        A file the command line refuses, or an unknown `precision`.
    ReplayFailed
        The replay stopped early (its ``step``).
    """
    return _purcell.replay(costate_or_gait, precision, bool(checkpoints))
