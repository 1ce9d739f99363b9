"""Discretisation error estimate by Richardson extrapolation.

The corotational Euler-Bernoulli element converges as O(h^2) in the
displacements, rotations, reactions and energy at the model nodes, with an
expansion in even powers of h on uniformly refined meshes.  With the outputs
Q_n, Q_2n (and Q_4n) on n, 2n (and 4n) elements per member:

    R_2 = Q_2n + (Q_2n - Q_n)/3           extrapolated, error O(h^4)
    e   = |Q_2n - Q_n|/3                  estimated error of Q_2n
    R_3 = R_2' + (R_2' - R_2)/15          Romberg step with three meshes, O(h^6)
    e_3 = |R_3 - R_2'|                    estimated error of R_2' (bounds R_3's)
    p   = log2(|Q_n - Q_2n| / |Q_2n - Q_4n|)   observed order (about 2)

``levels=2`` (default) solves on n and 2n elements, ``levels=3`` adds 4n.
``tol`` (consistent length units) applies to the position estimate of the
best value returned: e of the fine mesh for levels=2, e_3 for levels=3; the
meshes are doubled until it is met.  Load or displacement control only (the
levels of every mesh must mean the same loads).

Angles are in radians (degrees appear only in case files and reports).
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from .result import FemResult
from .solver import solve

__all__ = ["ErrorEstimate", "solve_with_error_estimate"]

OUTPUTS = ("positions", "rotations", "reactions", "strain_energy", "load_factor")


@dataclass
class ErrorEstimate:
    """Finest result, estimated errors and extrapolated outputs.

    ``error[name]``: estimated error of the finest result's field ``name``;
    ``extrapolated[name]``: Richardson (levels=2) or Romberg (levels=3) value;
    ``extrapolated_error[name]``: its estimated error (levels=3 only, else None);
    fields: positions, rotations, reactions, strain_energy, load_factor.
    """

    result: FemResult
    results: list
    error: dict
    extrapolated: dict
    extrapolated_error: dict | None
    observed_order: float | None
    refine: int
    converged: bool
    message: str
    history: list = field(default_factory=list)
    wall_time: float = 0.0

    @property
    def max_position_error(self) -> float:
        errs = self.extrapolated_error if self.extrapolated_error else self.error
        return float(np.max(errs["positions"], initial=0.0)) if errs else np.inf

    def _pick(self, name, node, level):
        i = self.result.node_index(node)
        return self.extrapolated[name][level, i], self.error[name][level, i]

    def position(self, node, level=-1):
        """(extrapolated position, estimated error of the finest position)."""
        return self._pick("positions", node, level)

    def rotation(self, node, level=-1):
        return self._pick("rotations", node, level)

    def reaction(self, node, level=-1):
        return self._pick("reactions", node, level)


def richardson(coarse, fine, order: float = 2.0):
    """(extrapolated, error estimate of fine) for arrays on meshes h and h/2."""
    f = 2.0**order - 1.0
    diff = np.asarray(fine) - np.asarray(coarse)
    return np.asarray(fine) + diff / f, np.abs(diff) / f


class _Estimates:
    """The Richardson (or Romberg) step of every output field, taken when a field is first read: the
    estimated errors, the extrapolated values and (levels=3) their errors, as three mappings
    ``error``, ``extrapolated``, ``extrapolated_error`` (a run that reads positions never computes the
    meshes' reactions and energies)."""

    def __init__(self, results, levels):
        self.results, self.levels = results[-levels:], levels
        self.error, self.extrapolated = _Lazy(self), _Lazy(self)
        self.extrapolated_error = _Lazy(self) if levels == 3 else None

    def fill(self, name: str) -> None:
        if name not in OUTPUTS:
            raise KeyError(name)
        vals = [getattr(r, name) for r in self.results]
        ext, err = richardson(vals[-2], vals[-1])
        self.error.values_[name] = err
        if self.levels == 3:
            r2a, _ = richardson(vals[0], vals[1])
            r3, _ = richardson(r2a, ext, order=4.0)
            self.extrapolated_error.values_[name] = np.abs(r3 - ext)
            ext = r3
        self.extrapolated.values_[name] = ext


class _Lazy(Mapping):
    """One mapping of `_Estimates`: every field of OUTPUTS by name, each field's step taken when it is
    first read (iterating, ``dict(...)`` or ``len`` see every field)."""

    def __init__(self, owner: _Estimates):
        self._owner, self.values_ = owner, {}

    def __getitem__(self, name):
        if name not in self.values_:
            self._owner.fill(name)
        return self.values_[name]

    def __iter__(self):
        return iter(OUTPUTS)

    def __len__(self) -> int:
        return len(OUTPUTS)


def _estimate(results, levels):
    """(error, extrapolated, extrapolated error or None, observed order); the positions' step taken
    now (the tolerance reads it), every other field's when read."""
    est = _Estimates(results, levels)
    est.fill("positions")
    order = None
    if len(results) >= 3:
        p = [r.positions for r in results[-3:]]
        d1, d2 = np.max(np.abs(p[1] - p[0])), np.max(np.abs(p[2] - p[1]))
        order = float(np.log2(d1 / d2)) if d2 > 0 and d1 > 0 else None
    return est.error, est.extrapolated, est.extrapolated_error, order


def solve_with_error_estimate(model, *args, tol: float | None = None, refine: int = 1,
                              levels: int = 2, max_refine: int = 64, **kwargs) -> ErrorEstimate:
    """Solve on refine x (1, 2[, 4]) elements per member and extrapolate.

    With ``tol`` the meshes are doubled until the position error estimate
    (see module docstring) is <= tol.  Other arguments go to `fem.solve`.
    """
    if levels not in (2, 3):
        raise ValueError("levels must be 2 or 3")
    if kwargs.get("control", args[1] if len(args) > 1 else "load") == "arclength":
        raise ValueError("error estimates need load or displacement control")
    warm = kwargs.pop("warm_start", True) and kwargs.get("control", "load") == "load"

    def solve_refined(r, coarser):
        guess = coarser if (warm and coarser is not None and coarser.converged) else None
        # a coarser mesh of this model converged, so it passed the free-motion test: not made again
        held = coarser is not None and coarser.converged
        return solve(model, *args, refine=r, initial_guess=guess, held=held, **kwargs)
    results = []
    for k in range(levels - 1):
        results.append(solve_refined(refine * 2**k, results[-1] if results else None))
    history = []
    fine_refine = refine * 2 ** (levels - 2)
    while True:
        fine_refine *= 2
        results.append(solve_refined(fine_refine, results[-1]))
        wall = sum(r.wall_time for r in results)
        bad = [r for r in results[-levels:] if not r.converged]
        if bad or len({r.n_levels for r in results[-levels:]}) != 1:
            msg = f"refine={bad[0].refine}: {bad[0].message}" if bad else "meshes reached different levels"
            return ErrorEstimate(results[-1], results, {}, {}, None, None, fine_refine, False,
                                 msg, history, wall)
        err, ext, ext_err, order = _estimate(results, levels)
        emax = float(np.max((ext_err or err)["positions"], initial=0.0))
        history.append((fine_refine, emax))
        done = tol is None or emax <= tol
        if done or fine_refine >= max_refine:
            msg = (f"estimated position error {emax:.3g} with refine={fine_refine}" if done else
                   f"tol={tol:g} not reached: estimate {emax:.3g} at refine={fine_refine}")
            return ErrorEstimate(results[-1], results, err, ext, ext_err, order, fine_refine, done,
                                 msg, history, wall)
