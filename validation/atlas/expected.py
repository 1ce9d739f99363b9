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
from dataclasses import dataclass
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

    def _coordinates(self) -> list[np.ndarray]:
        return [np.log(v) if name == "load" else v for name, v in zip(self.axes, self.values)]

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
        coords = self._coordinates()
        if any(not (c[0] - 1e-9 <= x <= c[-1] + 1e-9) for x, c in zip(q, coords)):
            return math.nan
        return _multilinear(coords, self.error, q)

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


def _multilinear(coords: list[np.ndarray], table: np.ndarray, q: list[float]) -> float:
    """Linear interpolation on a regular grid (axis by axis, the 2^d corners of the cell holding q);
    NaN when any corner with a non-zero weight is NaN."""
    index, weight = [], []
    for c, x in zip(coords, q):
        if c.size == 1:
            index.append((0, 0))
            weight.append((1.0, 0.0))
            continue
        i = int(np.clip(np.searchsorted(c, x, side="right") - 1, 0, c.size - 2))
        t = float(np.clip((x - c[i]) / (c[i + 1] - c[i]), 0.0, 1.0))
        index.append((i, i + 1))
        weight.append((1.0 - t, t))
    total = 0.0
    for corner in range(2 ** len(coords)):
        w, at = 1.0, []
        for axis in range(len(coords)):
            bit = (corner >> axis) & 1
            w *= weight[axis][bit]
            at.append(index[axis][bit])
        if w > 0.0:
            total += w * float(table[tuple(at)])
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
    where = ", ".join(f"{k} = {v:.4g}" for k, v in inputs.items())
    if not math.isfinite(e):
        return Expectation(model, math.nan, True, f"outside the {model} atlas ({where}): its error is not mapped")
    if e > VALIDITY_LIMIT:
        return Expectation(
            model,
            e,
            True,
            f"the {model} atlas expects a tip error of {e:.3g} % of L here ({where}), "
            f"above its {VALIDITY_LIMIT:g} % validity limit",
        )
    return Expectation(model, e, False, "")
