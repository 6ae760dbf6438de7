"""The problem's keyword arguments, one place for `solve`, `sweep` and `purcell.distributed`.

Their types and counts are checked here, in Python's words; their values by the library layer
below (the command line's checks, worded with these keyword names).
"""

from __future__ import annotations

import functools
import inspect
import numbers
import operator
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any, ParamSpec, TypedDict, TypeVar

from . import _purcell
from ._errors import InputError

P = ParamSpec("P")
R = TypeVar("R")


def number(name: str, value: Any) -> float:
    """`value` as a float: a real number (a Python or numpy one), else TypeError."""
    if isinstance(value, numbers.Real):
        return float(value)
    raise TypeError(f"{name} must be a number, not {type(value).__name__}")


def whole(name: str, value: Any) -> int:
    """`value` as an int: a whole number (a Python or numpy one), else TypeError."""
    try:
        return operator.index(value)
    except TypeError:
        raise TypeError(f"{name} must be a whole number, not {type(value).__name__}") from None


def count(name: str, value: Any) -> int:
    """`value` as an int of 0 or more, else TypeError or InputError."""
    n = whole(name, value)
    if n < 0:
        raise InputError(f"{name} must be 0 or more (got {n})")
    return n


def numbers_of(name: str, value: Any, count: int) -> list[float]:
    """`value` as `count` floats: a sequence (a tuple, list or numpy array) of real numbers."""
    if isinstance(value, str | bytes) or not isinstance(value, Iterable):
        raise TypeError(f"{name} must be a sequence of {count} numbers, not {type(value).__name__}")
    values = [number(f"{name}[{i}]", v) for i, v in enumerate(value)]
    if len(values) != count:
        raise InputError(f"{name} must have {count} numbers (got {len(values)})")
    return values


def one_of(names: Sequence[str]) -> Callable[[str, Any], str]:
    """The check of a name among `names`: a str (else TypeError), one of them (else
    InputError)."""

    def check(name: str, value: Any) -> str:
        if not isinstance(value, str):
            raise TypeError(f"{name} must be a str, not {type(value).__name__}")
        if value not in names:
            listed = ", ".join(map(repr, names))
            raise InputError(f"{name} must be one of {listed} (got {value!r})")
        return value

    return check


def optional(check: Callable[[str, Any], Any]) -> Callable[[str, Any], Any]:
    """`check`, or None for None."""
    return lambda name, value: None if value is None else check(name, value)


class Problem(TypedDict, total=False):
    """The problem's keyword arguments and their types (`Unpack[Problem]` in the signatures
    of `solve`, `sweep` and `purcell.distributed.sweep`; documented in `solve`)."""

    horizon: float
    step: float
    alpha0: Sequence[float]
    alpha_end: Sequence[float] | None
    links: Sequence[float]
    drag: float
    ratio: float
    alpha_max: float | None
    cost: str
    starts: int | None


#: Each problem keyword's default (the command line's) and check, in the native dict's
#: terms. A new keyword is a line here, one in `Problem`, its entry in `solve`'s docstring
#: and a field of the native `ProblemKw` (src/keywords.rs).
PROBLEM: dict[str, tuple[Any, Callable[[str, Any], Any]]] = {
    "horizon": (100.0, number),
    "step": (0.01, number),
    "alpha0": ((0.0, 0.0), lambda name, value: numbers_of(name, value, 2)),
    "alpha_end": (None, optional(lambda name, value: numbers_of(name, value, 2))),
    "links": ((1.0, 1.0, 1.0), lambda name, value: numbers_of(name, value, 3)),
    "drag": (1.0, number),
    "ratio": (2.0, number),
    "alpha_max": (None, optional(number)),
    "cost": ("effort", one_of(_purcell.COSTS)),
    "starts": (None, optional(whole)),
}


def problem(given: Mapping[str, Any]) -> dict[str, Any]:
    """The problem's keyword arguments among `given`, checked, as the native module takes
    them (a dict)."""
    return {name: check(name, given[name]) for name, (_, check) in PROBLEM.items()}


def takes_problem(f: Callable[P, R]) -> Callable[P, R]:
    """`f(..., **problem: Unpack[Problem])` with the problem's keywords in its signature
    (keyword-only, with their defaults, after its positional parameters, as `help` and
    `inspect.signature` show them) and Python's own TypeError for a keyword it does not
    take; `f` gets them all, checked ([`problem`])."""
    sig = inspect.signature(f)
    own = [p for p in sig.parameters.values() if p.kind is not p.VAR_KEYWORD]
    at = sum(p.kind is p.POSITIONAL_OR_KEYWORD for p in own)
    # As written in `Problem` (the text the other parameters' annotations show).
    types = {n: getattr(t, "__forward_arg__", t) for n, t in Problem.__annotations__.items()}
    shared = [
        inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=d, annotation=types[name])
        for name, (d, _) in PROBLEM.items()
    ]
    full = sig.replace(parameters=own[:at] + shared + own[at:])

    @functools.wraps(f)
    def call(*args: P.args, **kwargs: P.kwargs) -> R:
        bound = full.bind(*args, **kwargs)
        bound.apply_defaults()
        given = bound.arguments
        checked = problem(given)
        own_args = {name: value for name, value in given.items() if name not in PROBLEM}
        return f(**own_args, **checked)

    call.__signature__ = full  # type: ignore[attr-defined]
    return call
