"""The PRBM's expected error from the atlas: error maps on the atlas's grid, interpolated at any input.

An ``ErrorMap`` holds, for one model, the tip error at equal load (% of L) at every node of its grid
(the shape inputs x the load levels; NaN where the exact segment went beyond the atlas or a method gave
no answer).  ``expected(inputs)`` interpolates it linearly (in the logarithm of the load, which is how the
levels are spaced); a query outside the grid, or next to a NaN node, has no expected error (NaN): the
atlas does not know, and says so.

The maps the PRBM adapter reads are ``validation/atlas/error_maps.json``, written from the full atlas
by ``prbm-validate atlas --write-maps`` (``validation.atlas.maps.write_maps``) with the code version they
came from, on a grid thinned from the atlas's.  The test suite builds the coarse atlas and checks these
maps predict it (tests/validation/test_atlas.py).  This module imports numpy only: the PRBM adapter
reads it on every run.
"""

from __future__ import annotations

import json
import math
from bisect import bisect_right
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

MAPS_FILE = Path(__file__).with_name("error_maps.json")
VALIDITY_LIMIT = 5.0  # % of L: the region outside which a level is flagged ``outside validity``
REGION_LEVELS = (0.5, 1.0, 3.0, 5.0)


@dataclass(frozen=True)
class ErrorMap:
    """Tip error (% of L) of one model on a regular grid of its inputs (shape axes, then load)."""

    model: str
    axes: tuple[str, ...]
    values: tuple[np.ndarray, ...]
    error: np.ndarray
    version: str = ""
    # the grid as the interpolation reads it, in plain floats (a lookup is a few scalar operations per
    # axis, cheaper on floats than through numpy calls): per axis its coordinates (the logarithm of the
    # load) and its stride in the error table, flattened in C order
    _coords: tuple[list[float], ...] = field(init=False, repr=False, compare=False)
    _strides: tuple[int, ...] = field(init=False, repr=False, compare=False)
    _table: list[float] = field(init=False, repr=False, compare=False)
    _two_axes: bool = field(init=False, repr=False, compare=False)  # two axes of two nodes or more

    def __post_init__(self) -> None:
        coords = tuple(
            (np.log(v) if name == "load" else np.asarray(v, float)).tolist() for name, v in zip(self.axes, self.values)
        )
        sizes = [len(c) for c in coords]
        object.__setattr__(self, "_coords", coords)
        object.__setattr__(self, "_strides", tuple(math.prod(sizes[axis + 1 :]) for axis in range(len(sizes))))
        object.__setattr__(self, "_table", np.asarray(self.error, float).ravel().tolist())
        object.__setattr__(self, "_two_axes", len(sizes) == 2 and min(sizes) > 1)

    def expected(self, inputs: dict[str, float]) -> float:
        """The interpolated tip error at ``inputs`` (every axis named), NaN where the map does not know.
        Below the smallest mapped load the error at that load is returned (the error falls with the load)."""
        q = []
        for name, v in zip(self.axes, self.values):
            x = float(inputs[name])
            if name == "load":
                if x == 0.0:
                    return 0.0
                if not x > 0.0:
                    return math.nan
                x = max(math.log(x), math.log(v[0]))
            q.append(x)
        for x, c in zip(q, self._coords):
            if not (c[0] - 1e-9 <= x <= c[-1] + 1e-9):
                return math.nan
        if self._two_axes:
            return _bilinear(self._coords, self._strides[0], self._table, q)
        return _multilinear(self._coords, self._strides, self._table, q)

    def to_json(self) -> dict:
        return {
            "axes": list(self.axes),
            "values": [[float(f"{x:.6g}") for x in v] for v in self.values],
            "error": [None if not math.isfinite(e) else float(f"{e:.3g}") for e in self.error.ravel()],
            "version": self.version,
        }

    @classmethod
    def from_json(cls, model: str, data: dict) -> "ErrorMap":
        values = tuple(np.asarray(v, float) for v in data["values"])
        error = np.array([math.nan if e is None else e for e in data["error"]], float).reshape([v.size for v in values])
        return cls(model, tuple(data["axes"]), values, error, data.get("version", ""))


def _cell(c: list[float], x: float) -> tuple[int, float]:
    """The cell of the axis ``c`` (ascending) holding x, as its first node i and x's fraction t in [0, 1]
    of the way to node i + 1 (the end cells extended, t clipped)."""
    i = min(max(bisect_right(c, x) - 1, 0), len(c) - 2)
    return i, min(max((x - c[i]) / (c[i + 1] - c[i]), 0.0), 1.0)


def _multilinear(
    coords: tuple[list[float], ...], strides: tuple[int, ...], table: list[float], q: list[float]
) -> float:
    """Linear interpolation on a regular grid (axis by axis, the 2^d corners of the cell holding q; ``table``
    the values flattened, ``strides`` each axis's step in it); NaN when any corner with a non-zero weight
    is NaN."""
    index, weight = [], []
    for c, x, stride in zip(coords, q, strides):
        if len(c) == 1:
            index.append((0, 0))
            weight.append((1.0, 0.0))
            continue
        i, t = _cell(c, x)
        index.append((i * stride, (i + 1) * stride))
        weight.append((1.0 - t, t))
    total = 0.0
    d = len(coords)
    for corner in range(1 << d):
        w, at = 1.0, 0
        for axis in range(d):
            bit = (corner >> axis) & 1
            w *= weight[axis][bit]
            at += index[axis][bit]
        if w > 0.0:
            total += w * table[at]
    return total


def _bilinear(coords: tuple[list[float], ...], stride: int, table: list[float], q: list[float]) -> float:
    """``_multilinear`` on a grid of two axes (each of two nodes or more; ``stride`` the first axis's step
    in ``table``): the same four corners, weights and sum, in the same order."""
    (i, t), (j, u) = _cell(coords[0], q[0]), _cell(coords[1], q[1])
    at = i * stride + j
    total = 0.0
    for w, k in (
        ((1.0 - t) * (1.0 - u), at),
        (t * (1.0 - u), at + stride),
        ((1.0 - t) * u, at + 1),
        (t * u, at + stride + 1),
    ):
        if w > 0.0:
            total += w * table[k]
    return total


@lru_cache(maxsize=1)
def load_maps(path: Path = MAPS_FILE) -> dict[str, ErrorMap]:
    """The committed maps by model (empty when the file is absent)."""
    if not path.exists():
        return {}
    data = json.loads(path.read_text())
    return {name: ErrorMap.from_json(name, d) for name, d in data["models"].items()}


@dataclass(frozen=True)
class Expectation:
    """The atlas's word on one PRBM level: its expected tip error (% of L; NaN: not mapped) and whether
    the level lies outside the model's ``VALIDITY_LIMIT`` region (or outside the map)."""

    model: str
    expected_error: float
    outside: bool
    reason: str


def expectation(model: str, inputs: dict[str, float]) -> Expectation | None:
    """The expectation of a level of ``model`` at ``inputs``; None when no map of the model is shipped."""
    maps = load_maps()
    if model not in maps:
        return None
    e = maps[model].expected(inputs)
    if -math.inf < e <= VALIDITY_LIMIT:  # inside the region: the reason below is written only outside it
        return Expectation(model, e, False, "")
    where = ", ".join(f"{k} = {v:.4g}" for k, v in inputs.items())
    if not math.isfinite(e):
        return Expectation(model, math.nan, True, f"outside the {model} atlas ({where}): its error is not mapped")
    return Expectation(
        model,
        e,
        True,
        f"the {model} atlas expects a tip error of {e:.3g} % of L here ({where}), "
        f"above its {VALIDITY_LIMIT:g} % validity limit",
    )
