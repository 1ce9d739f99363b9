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

import numpy as np


def _values(value) -> np.ndarray:
    """The value as a numeric array (complex loads stay complex: finite means both parts finite)."""
    values = np.asarray(value)
    return values if np.issubdtype(values.dtype, np.number) else values.astype(float)


def checked(positive: tuple[str, ...] = (), finite: tuple[str, ...] = ()):
    """Decorator: the named arguments (when given and not None) must be finite and > 0 (positive)
    or finite (finite); scalars, sequences and arrays alike."""
    def wrap(func):
        signature = inspect.signature(func)

        @functools.wraps(func)
        def inner(*args, **kwargs):
            given = signature.bind_partial(*args, **kwargs).arguments
            for name in positive:
                value = given.get(name)
                if value is not None and not (np.all(np.isfinite(_values(value))) and np.all(_values(value) > 0)):
                    raise ValueError(f"{func.__name__}: {name} must be finite and > 0, got {value!r}")
            for name in finite:
                value = given.get(name)
                if value is not None and not np.all(np.isfinite(_values(value))):
                    raise ValueError(f"{func.__name__}: {name} must be finite, got {value!r}")
            return func(*args, **kwargs)
        return inner
    return wrap
