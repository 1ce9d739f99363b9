"""Argument checks at the public entry points of the libraries (prbm, fem, elastica, bcm).

A NaN or infinite value, or a zero or negative stiffness, length or section, is a ValueError naming
the function and the argument, never a result that says it converged. A leaf package: it imports
nothing of the project, so the libraries stay independent of each other.

>>> from argcheck import checked
>>> @checked(positive=("length",), finite=("load",))
... def tip(load, *, length):
...     return load * length
>>> tip(2.0, length=-1.0)
Traceback (most recent call last):
...
ValueError: tip: length must be finite and > 0, got -1.0
"""

from __future__ import annotations

import functools
import inspect
import math
from collections.abc import Callable
from typing import Any, ParamSpec, TypeVar

import numpy as np
import numpy.typing as npt

_P = ParamSpec("_P")
_R = TypeVar("_R")


def _values(value: object) -> npt.NDArray[Any]:
    """The value as a numeric array (complex loads stay complex: finite means both parts finite)."""
    values = np.asarray(value)
    return values if np.issubdtype(values.dtype, np.number) else values.astype(float)


def _ok(value: Any, positive: bool) -> bool:
    """The value finite (and > 0 when ``positive``): a plain float or int, or a flat list of them, in
    plain Python (the common cases at a library's entry point, where numpy's per-call overhead would
    exceed the check itself), anything else through numpy."""
    if type(value) in _PLAIN:
        return math.isfinite(value) and (not positive or value > 0)
    if type(value) is list:  # the load levels of a case as plain numbers: a Python loop beats numpy's set-up
        try:
            return all(math.isfinite(v) and v > 0 for v in value) if positive else all(map(math.isfinite, value))
        except TypeError:  # not a flat list of real numbers (nested, complex, None): numpy below decides
            pass
    if type(value) is np.ndarray and value.dtype.kind in "fiu":  # a real array: ndarray methods, no dispatch
        return bool(np.isfinite(value).all()) and (not positive or bool((value > 0).all()))
    values = _values(value)
    return bool(np.all(np.isfinite(values))) and (not positive or bool(np.all(values > 0)))


_PLAIN = (float, int, np.float64)


def checked(
    positive: tuple[str, ...] = (), finite: tuple[str, ...] = ()
) -> Callable[[Callable[_P, _R]], Callable[_P, _R]]:
    """Decorator: the named arguments (when given and not None) must be finite and > 0 (positive)
    or finite (finite); scalars, sequences and arrays alike."""

    def wrap(func: Callable[_P, _R]) -> Callable[_P, _R]:
        signature = inspect.signature(func)
        # where each checked argument sits when given positionally (None: keyword-only)
        slots = {
            p.name: i
            for i, p in enumerate(signature.parameters.values())
            if p.kind in (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
        }
        checks = [(name, True, slots.get(name)) for name in positive] + [
            (name, False, slots.get(name)) for name in finite
        ]

        @functools.wraps(func)
        def inner(*args: _P.args, **kwargs: _P.kwargs) -> _R:
            for name, positive_, slot in checks:
                value = kwargs.get(name) if slot is None or slot >= len(args) else args[slot]
                if value is not None and not _ok(value, positive_):
                    kind = "finite and > 0" if positive_ else "finite"
                    raise ValueError(f"{func.__name__}: {name} must be {kind}, got {value!r}")
            return func(*args, **kwargs)

        return inner

    return wrap
