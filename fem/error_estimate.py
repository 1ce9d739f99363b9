"""Discretisation error estimate by Richardson extrapolation, with a test of the asymptotic range.

The corotational Euler-Bernoulli element converges as O(h^2) in the
displacements, rotations, reactions and energy at the model nodes, with an
expansion in even powers of h on uniformly refined meshes.  With the outputs
Q_n, Q_2n (and Q_4n) on n, 2n (and 4n) elements per member:

    R_2 = Q_2n + (Q_2n - Q_n)/3           extrapolated, error O(h^4)
    e   = |Q_2n - Q_n|/3                  estimated error of Q_2n
    R_3 = R_2' + (R_2' - R_2)/15          Romberg step with three meshes, O(h^6)
    e_3 = |R_3 - R_2'|                    estimated error of R_2' (bounds R_3's)
    p   = log2(|Q_n - Q_2n| / |Q_2n - Q_4n|)   observed order (about 2)

``levels=2`` (default) estimates from the two finest meshes, ``levels=3`` from the three finest.
``tol`` (consistent length units) applies to the position estimate of the
best value returned: e of the fine mesh for levels=2, e_3 for levels=3; the
meshes are doubled until it is met.  Load or displacement control only (the
levels of every mesh must mean the same loads).

The asymptotic range (`AsymptoticCheck`).  e is the error of Q_2n only where the expansion's
leading terms dominate: on a coarse mesh of a large deflection an output's error can still turn or
change sign between meshes, and e is then no bound (the tip of a cantilever under an inclined
compressive force on 2 and 4 elements: true error up to 11 e).  Every value of the checked fields
is therefore judged on the three finest meshes M0 < M1 < M2 (each twice the last):

    r = (Q_M1 - Q_M0) / (Q_M2 - Q_M1)     4 in the asymptotic range (r = 2^p, p = 2)

A value is in the asymptotic range when 2^(2 - band) <= r <= 2^(2 + band) (a negative r, a change
of sign, never is), or when its last difference |Q_M2 - Q_M1| is at round-off level: below
``floor`` times the field's scale (the model's mean member length for positions, 1 rad for
rotations, the field's largest value for reactions (forces and moments apart), energy and load
factor), and for reactions below ``ROUNDING_EA`` eps EA too (the rounding of the internal forces).
Where Q_h = Q + a h^2 + b h^4 explains the three meshes, r in the default band (p in [1.5, 2.5])
keeps the error of Q_M2 below 1.08 e.  Until every checked value passes, the meshes are doubled (up
to ``max_refine``); the values still outside are then marked in ``unreliable`` and ``reliable`` is
False: their estimate is no bound.  With levels=2 the third mesh is the coarser M0 = n/2 when every
refined member's element count (or ``refine``) is even: the n/2 solve warm-starts the n solve, and
while the first three meshes pass, Q_2n and e are those of the n/2n pair (to the Newton
tolerance); else it is the finer 4n (and Q_4n is reported).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .result import FemResult
from .model import Model, NodeRef
from .solver import solve
from .types import BoolArray, FloatArray

__all__ = ["AsymptoticCheck", "ErrorEstimate", "solve_with_error_estimate"]

OUTPUTS = ("positions", "rotations", "reactions", "strain_energy", "load_factor")


@dataclass(frozen=True)
class AsymptoticCheck:
    """Which fields must be in the asymptotic range before their estimate is trusted (module docstring).

    ``fields``: names of `OUTPUTS` whose every value is judged and refined for; other fields are judged
    when first read, without refining. ``band``: accepted |p - 2| of the observed order (r within
    [2^(2 - band), 2^(2 + band)]). ``floor``: a last difference below floor x the field's scale has
    converged (round-off level).
    """

    fields: tuple[str, ...] = ("positions", "rotations")
    band: float = 0.5
    floor: float = 1e-8

    def __post_init__(self) -> None:
        unknown = [f for f in self.fields if f not in OUTPUTS]
        if unknown:
            raise ValueError(f"AsymptoticCheck.fields: unknown {unknown}; choose from {OUTPUTS}")
        if not (self.band > 0 and self.floor >= 0):
            raise ValueError("AsymptoticCheck: band must be > 0 and floor >= 0")


@dataclass
class ErrorEstimate:
    """Finest result, estimated errors and extrapolated outputs.

    ``error[name]``: estimated error of the finest result's field ``name``;
    ``extrapolated[name]``: Richardson (levels=2) or Romberg (levels=3) value;
    ``extrapolated_error[name]``: its estimated error (levels=3 only, else None);
    fields: positions, rotations, reactions, strain_energy, load_factor.
    ``unreliable[name]``: boolean array of the field's shape, True where the value was not in the
    asymptotic range on the three finest meshes (its estimate is no bound); ``reliable``: no value of
    a checked field is (``check.fields``; True when no check was asked for, False when no estimate
    was made); ``observed_order``: p of the largest position differences of the three finest meshes;
    ``refine``: the finest mesh's element count over the model's.
    """

    result: FemResult
    results: list[FemResult]
    error: Mapping[str, NDArray[Any]]
    extrapolated: Mapping[str, NDArray[Any]]
    extrapolated_error: Mapping[str, NDArray[Any]] | None
    observed_order: float | None
    refine: int
    converged: bool
    message: str
    history: list[tuple[int, float]] = field(default_factory=list)  # (refine, position error estimate)
    wall_time: float = 0.0
    unreliable: Mapping[str, NDArray[Any]] = field(default_factory=dict)
    reliable: bool = True
    check: AsymptoticCheck | None = None

    @property
    def max_position_error(self) -> float:
        errs = self.extrapolated_error if self.extrapolated_error else self.error
        return float(np.max(errs["positions"], initial=0.0)) if errs else np.inf

    def _pick(self, name: str, node: NodeRef, level: int) -> tuple[Any, Any]:
        i = self.result.node_index(node)
        return self.extrapolated[name][level, i], self.error[name][level, i]

    def position(self, node: NodeRef, level: int = -1) -> tuple[FloatArray, FloatArray]:
        """(extrapolated position, estimated error of the finest position)."""
        return self._pick("positions", node, level)

    def rotation(self, node: NodeRef, level: int = -1) -> tuple[float, float]:
        return self._pick("rotations", node, level)

    def reaction(self, node: NodeRef, level: int = -1) -> tuple[FloatArray, FloatArray]:
        return self._pick("reactions", node, level)


def richardson(coarse: ArrayLike, fine: ArrayLike, order: float = 2.0) -> tuple[NDArray[Any], NDArray[Any]]:
    """(extrapolated, error estimate of fine) for arrays on meshes h and h/2."""
    f = 2.0**order - 1.0
    diff = np.asarray(fine) - np.asarray(coarse)
    return np.asarray(fine) + diff / f, np.abs(diff) / f


# Round-off of a reaction: the internal forces carry about eps EA (an element's axial force is EA times a
# strain computed from coordinates rounded to eps: 0.1 to 1.4 eps EA between meshes of 32 to 512 elements,
# EA L^2/EI from 1e5 to 1e10), so differences below ROUNDING_EA eps EA are round-off.
ROUNDING_EA = 100.0


def _floor(name: str, values: FloatArray, model_scale: tuple[float, float], floor: float) -> FloatArray:
    """The round-off level of each value of a field: ``floor`` times its scale (the model's mean
    member length for positions, 1 rad for rotations, the field's largest value otherwise), for
    reactions at least ``ROUNDING_EA`` eps EA (forces; moments that times the length)."""
    length, axial = model_scale
    if name == "positions":
        return np.full(values.shape, floor * length)
    if name == "rotations":
        return np.full(values.shape, floor)
    if name == "reactions":  # forces and moments apart, each at least the other's over the length
        forces = float(np.max(np.abs(values[..., :2]), initial=0.0))
        moments = float(np.max(np.abs(values[..., 2]), initial=0.0))
        force = max(floor * max(forces, moments / length), ROUNDING_EA * np.finfo(float).eps * axial)
        forces_and_moments: FloatArray = np.broadcast_to(np.array([force, force, force * length]), values.shape)
        return forces_and_moments
    return np.full(np.shape(values), floor * float(np.max(np.abs(values), initial=0.0)))


def _axial_stiffness(model: Model) -> float:
    """The largest EA of the model's members (a tapered member's at its ends and middle)."""
    sections = [m.section(xi) for m in model.members if callable(m.section) for xi in (0.0, 0.5, 1.0)]
    sections += [m.section for m in model.members if not callable(m.section)]
    return max((float(s.EA) for s in sections), default=0.0)


def asymptotic_ratio(coarse: ArrayLike, middle: ArrayLike, fine: ArrayLike) -> FloatArray:
    """r = (Q_M1 - Q_M0)/(Q_M2 - Q_M1) of every value (inf where the last difference is 0)."""
    d1 = np.asarray(middle) - np.asarray(coarse)
    d2 = np.asarray(fine) - np.asarray(middle)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(d2 != 0, d1 / np.where(d2 != 0, d2, 1.0), np.inf)


class _Estimates:
    """The Richardson (or Romberg) step of every output field, taken when a field is first read: the
    estimated errors, the extrapolated values and (levels=3) their errors, as three mappings
    ``error``, ``extrapolated``, ``extrapolated_error``, and with a check the values outside the
    asymptotic range, ``unreliable`` (a run that reads positions never computes the meshes' reactions
    and energies)."""

    def __init__(
        self, results: list[FemResult], levels: int, check: AsymptoticCheck | None, model_scale: tuple[float, float]
    ):
        self.results, self.levels = results[-levels:], levels
        last3 = results[-3:]
        comparable = len(last3) == 3 and all(r.converged for r in last3) and len({r.n_levels for r in last3}) == 1
        self.judged = last3 if check is not None and comparable else None
        self.check, self.model_scale = check, model_scale
        self.error, self.extrapolated = _Lazy(self), _Lazy(self)
        self.extrapolated_error = _Lazy(self) if levels == 3 else None
        self.unreliable = _Lazy(self)
        self.ratio: dict[str, FloatArray] = {}

    def fill(self, name: str) -> None:
        if name not in OUTPUTS:
            raise KeyError(name)
        vals = [getattr(r, name) for r in self.results]
        ext, err = richardson(vals[-2], vals[-1])
        self.error.values_[name] = err
        if self.levels == 3:
            r2a, _ = richardson(vals[0], vals[1])
            r3, _ = richardson(r2a, ext, order=4.0)
            assert self.extrapolated_error is not None  # made for levels=3
            self.extrapolated_error.values_[name] = np.abs(r3 - ext)
            ext = r3
        self.extrapolated.values_[name] = ext
        self.unreliable.values_[name] = self._outside(name)

    def _outside(self, name: str) -> BoolArray:
        """True where a value is not in the asymptotic range (all False without a check)."""
        fine = np.asarray(getattr(self.results[-1], name))
        if self.check is None:
            return np.zeros(fine.shape, bool)
        if self.judged is None:  # fewer than three comparable meshes: nothing could be judged
            self.ratio[name] = np.full(fine.shape, np.nan)
            return np.ones(fine.shape, bool)
        q0, q1, q2 = (np.asarray(getattr(r, name)) for r in self.judged)
        ratio = asymptotic_ratio(q0, q1, q2)
        self.ratio[name] = ratio
        converged = np.abs(q2 - q1) <= _floor(name, q2, self.model_scale, self.check.floor)
        band = self.check.band
        inside = (ratio >= 2.0 ** (2.0 - band)) & (ratio <= 2.0 ** (2.0 + band))
        outside: BoolArray = ~(converged | inside)
        return outside

    def worst(self, names: Iterable[str]) -> str:
        """Where the checked fields leave the asymptotic range, in words (empty when nowhere)."""
        parts: list[str] = []
        for name in names:
            bad = np.asarray(self.unreliable[name])
            if bad.any():
                ratio = self.ratio[name][bad]
                # the ratio farthest from 4 (a change of sign first) names the worst value
                far = np.where(ratio > 0, np.abs(np.log2(np.where(ratio > 0, ratio, 1.0)) - 2.0), np.inf)
                r = float(ratio[int(np.argmax(far))])
                p = (
                    f"p = {math.log2(r):.2f}"
                    if r > 0
                    else "the differences change sign"
                    if r <= 0
                    else "fewer than three meshes"
                )
                parts.append(f"{name} {int(bad.sum())} of {bad.size} ({p})")
        return ", ".join(parts)


class _Lazy(Mapping[str, NDArray[Any]]):
    """One mapping of `_Estimates`: every field of OUTPUTS by name, each field's step taken when it is
    first read (iterating, ``dict(...)`` or ``len`` see every field)."""

    def __init__(self, owner: _Estimates):
        self._owner = owner
        self.values_: dict[str, NDArray[Any]] = {}

    def __getitem__(self, name: str) -> NDArray[Any]:
        if name not in self.values_:
            self._owner.fill(name)
        return self.values_[name]

    def __iter__(self) -> Iterator[str]:
        return iter(OUTPUTS)

    def __len__(self) -> int:
        return len(OUTPUTS)


def _halved(model: Model) -> Model | None:
    """The model with every refined member's element count halved (None if one is odd): its meshes
    refine the model's by 1/2, 1, 2, ... (the same nodes, members and loads)."""
    members = model.members
    if any(m.refined and m.n_elements % 2 for m in members):
        return None
    return replace(model, members=[replace(m, n_elements=m.n_elements // 2) if m.refined else m for m in members])


def solve_with_error_estimate(
    model: Model,
    *args: Any,
    tol: float | None = None,
    refine: int = 1,
    levels: int = 2,
    max_refine: int = 64,
    check: AsymptoticCheck | None = AsymptoticCheck(),
    **kwargs: Any,
) -> ErrorEstimate:
    """Solve on refine x (1, 2[, 4]) elements per member and extrapolate.

    With ``tol`` the meshes are doubled until the position error estimate
    (see module docstring) is <= tol.  With ``check`` (default: positions and rotations) the meshes
    are doubled until every value of ``check.fields`` is in the asymptotic range, up to
    ``max_refine`` (the finest mesh's refine); the values still outside are then marked
    ``unreliable``.  ``check=None``: two meshes (levels=2), no test.  Other arguments go to `fem.solve`.
    """
    if levels not in (2, 3):
        raise ValueError("levels must be 2 or 3")
    if kwargs.get("control", args[1] if len(args) > 1 else "load") == "arclength":
        raise ValueError("error estimates need load or displacement control")
    warm = kwargs.pop("warm_start", True) and kwargs.get("control", "load") == "load"
    check = check if check is not None and check.fields else None

    def solve_refined(mesh: Model, r: int, coarser: FemResult | None) -> FemResult:
        guess = coarser if (warm and coarser is not None and coarser.converged) else None
        # a coarser mesh of this model converged, so it passed the free-motion test: not made again
        held = coarser is not None and coarser.converged
        return solve(mesh, *args, refine=r, initial_guess=guess, held=held, **kwargs)

    # the meshes as (model, refine): levels=2 with a check adds the coarser n/2 when it exists
    meshes = [(model, refine * 2**k) for k in range(levels - 1)]
    fine_refine = refine * 2 ** (levels - 1)
    coarsest_judges_only = False
    if check is not None and levels == 2:
        half = model if refine % 2 == 0 else _halved(model)
        if half is not None:
            meshes.insert(0, (half, refine // 2 if refine % 2 == 0 else 1))
            coarsest_judges_only = True
        else:  # no coarser mesh of the same nodes: the finer 4n is the third
            meshes.append((model, fine_refine))
            fine_refine *= 2
    results: list[FemResult] = []
    for mesh, r in meshes:
        results.append(solve_refined(mesh, r, results[-1] if results else None))
    if coarsest_judges_only and not results[0].converged:
        results = results[1:]  # the n/2 mesh failed: the order is judged on finer meshes
    history: list[tuple[int, float]] = []
    doubled: list[str] = []
    model_scale = (model.characteristic_length(), _axial_stiffness(model))
    while True:
        results.append(solve_refined(model, fine_refine, results[-1]))
        wall = sum(r.wall_time for r in results)
        bad = [r for r in results[-levels:] if not r.converged]
        if bad or len({r.n_levels for r in results[-levels:]}) != 1:
            msg = f"refine={bad[0].refine}: {bad[0].message}" if bad else "meshes reached different levels"
            return ErrorEstimate(
                results[-1],
                results,
                {},
                {},
                None,
                None,
                fine_refine,
                False,
                msg,
                history,
                wall,
                reliable=False,
                check=check,
            )
        est = _Estimates(results, levels, check, model_scale)
        est.fill("positions")
        order = _observed_order(results) if len(results) >= 3 else None
        emax = float(np.max((est.extrapolated_error or est.error)["positions"], initial=0.0))
        history.append((fine_refine, emax))
        outside = est.worst(check.fields) if check is not None else ""
        small = tol is None or emax <= tol
        if (small and not outside) or fine_refine >= max_refine:
            msg = (
                f"estimated position error {emax:.3g} with refine={fine_refine}"
                if small
                else f"tol={tol:g} not reached: estimate {emax:.3g} at refine={fine_refine}"
            )
            if outside:
                assert check is not None  # only a check finds values outside
                msg += (
                    f"; estimate unreliable: not in the asymptotic range (observed order outside "
                    f"2 +- {check.band:g}) by refine={fine_refine}: {outside}"
                )
            elif doubled:
                msg += "; meshes doubled for the asymptotic range past " + "; ".join(doubled)
            return ErrorEstimate(
                results[-1],
                results,
                est.error,
                est.extrapolated,
                est.extrapolated_error,
                order,
                fine_refine,
                small,
                msg,
                history,
                wall,
                est.unreliable,
                reliable=not outside,
                check=check,
            )
        if outside:
            doubled.append(f"refine={fine_refine} ({outside})")
        fine_refine *= 2


def _observed_order(results: list[FemResult]) -> float | None:
    """p of the largest position differences of the three finest meshes."""
    p = [r.positions for r in results[-3:]]
    d1, d2 = np.max(np.abs(p[1] - p[0])), np.max(np.abs(p[2] - p[1]))
    return float(np.log2(d1 / d2)) if d2 > 0 and d1 > 0 else None
