"""The exceptions `purcell` raises, one family: catch `PurcellError` for all of them."""

from __future__ import annotations


class PurcellError(Exception):
    """Base of every exception `purcell` raises."""


class InputError(PurcellError, ValueError):
    """Bad input, refused before any work (the command line's exit code 2).

    The message names the keyword argument and what it takes.
    """


class NoSolution(PurcellError, RuntimeError):
    """The search reached no admissible extremal (the command line's exit code 3).

    Attributes
    ----------
    best_residual : float or None
        Smallest terminal defect any start reached, m / rad (None: extremals were found,
        none admissible).
    best_alpha : float or None
        Smallest largest ``|alpha_i|`` of the inadmissible extremals found, rad (None: none
        found).
    """

    def __init__(
        self, message: str, *, best_residual: float | None = None, best_alpha: float | None = None
    ) -> None:
        super().__init__(message)
        self.best_residual = best_residual
        self.best_alpha = best_alpha


class ReplayFailed(PurcellError, RuntimeError):
    """A replay stopped early (the command line's exit code 3).

    Attributes
    ----------
    step : int or None
        The step it failed at (None: before its first step).
    """

    def __init__(self, message: str, *, step: int | None = None) -> None:
        super().__init__(message)
        self.step = step


# Shown, pickled and documented as members of `purcell`, where users catch them.
for _cls in (PurcellError, InputError, NoSolution, ReplayFailed):
    _cls.__module__ = "purcell"
