"""The problem's keyword arguments, shared by `solve`, `sweep` and `purcell.distributed`.

Their types and counts are checked here, in Python's words; their values by the library layer
below (the command line's checks, worded with these keyword names).
"""

from __future__ import annotations

import numbers
import operator
from collections.abc import Callable, Iterable, Mapping
from typing import Any

from ._errors import InputError


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


def optional(check: Callable[[str, Any], Any]) -> Callable[[str, Any], Any]:
    """`check`, or None for None."""
    return lambda name, value: None if value is None else check(name, value)


#: The problem's keyword arguments and the check of each, in the native dict's terms. A new
#: keyword is a line here, a parameter of the public signatures that take it (with its
#: docstring entry) and a field of the native `ProblemKw` (src/keywords.rs).
PROBLEM: dict[str, Callable[[str, Any], Any]] = {
    "horizon": number,
    "step": number,
    "alpha0": lambda name, value: numbers_of(name, value, 2),
    "alpha_end": optional(lambda name, value: numbers_of(name, value, 2)),
    "links": lambda name, value: numbers_of(name, value, 3),
    "drag": number,
    "ratio": number,
    "alpha_max": optional(number),
    "starts": whole,
}


def problem(given: Mapping[str, Any]) -> dict[str, Any]:
    """The problem's keyword arguments among `given` (a public function's `locals()`),
    checked, as the native module takes them (a dict)."""
    return {name: check(name, given[name]) for name, check in PROBLEM.items()}
