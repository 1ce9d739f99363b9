"""Inverse end problems: the loads that put a member end (the "tip") at a prescribed pose.

Some of the tip's DOFs (ux, uy, rz) are prescribed in the model (``Model.prescribe``): they are
displacement-controlled and their reactions R are the loads needed to hold them. Each remaining
tip DOF carries either the model's own load there (a fixed load, e.g. a given axial force, or
none), or one *tied* load F whose value is an unknown of the problem, fixed by one scalar
condition g(F) = 0 per load level:

* ``LoadRatio``: the load on the free DOF is a given multiple of the total load on a prescribed
  DOF, F = ratio * P with P = R_ref + (fixed load on the reference DOF), so g = F - ratio * P.
  [bapat2015, §3.5.2, Table 3.5], Case 2b: b and theta_0 prescribed, F_x = -n P.
* ``ZeroMoment``: the bending moment vanishes at a node (an inflection point). With no load
  between the node and the tip, equilibrium of that part gives (CCW moments, global forces)

      m(node) = M + F_y (x_tip - x_node) - F_x (y_tip - y_node),

  with (F_x, F_y, M) the total tip load; g = m(node). [bapat2015, Table 3.6], Case 2c: b, theta_0
  and the inflection location l1 prescribed, nP along x unknown.

* ``Position``: the load on the free DOF is what brings the tip (or another node) to a given
  position along x or y, g = x_node - value (the same problem as prescribing that DOF, by another path: useful where
  displacement control of every tip DOF meets a singular state on its way, e.g. a beam pushed
  past a buckling load of its clamped-clamped configuration).

The tied load is found by a secant iteration on g (the outer solve), one load-controlled
``fem.solve`` of all levels per evaluation; levels are independent scalar equations, so the
secant is applied level by level (a diagonal secant). A solve that fails is retried with the
step towards the last converged loads halved. Convergence: |g| <= ``tie_rtol`` times the scale of
g at the level (a load: max(|F_x|, |F_y|) + |M|/L_char; a position: L_char), checked on the
converged FEM state (the default 1e-7 sits well above the noise of the reactions of a
solve converged to its own rtol, 1e-10 by default, even for a nearly inextensible section).

The result says how it was obtained (scipy style): ``converged``, ``message``, ``nit`` outer
iterations, ``nfev`` FEM solves, the final ``FemResult`` (``result``), the total tip loads per
level ``tip_loads`` (n_levels, 3) = (F_x, F_y, M) acting on the tip, the tied load per level and
its residual.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import copy
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .model import DOF_NAMES, Model
from .result import FemResult
from .solver import solve
from .types import FloatArray

__all__ = ["LoadRatio", "ZeroMoment", "Position", "TipInverseResult", "solve_tip_inverse", "tip_loads"]


@dataclass(frozen=True)
class LoadRatio:
    """The load on ``free_dof`` is ``ratio`` (one per level, or one for all) times the total load
    on the prescribed ``reference_dof`` of the same node."""

    free_dof: str
    reference_dof: str
    ratio: FloatArray | float


@dataclass(frozen=True)
class ZeroMoment:
    """The load on ``free_dof`` is what makes the bending moment vanish at ``node`` (no loads may
    act between that node and the tip)."""

    free_dof: str
    node: str


@dataclass(frozen=True)
class Position:
    """The load on ``free_dof`` of the tip is what puts ``node`` (default: the tip) at ``value``
    (absolute coordinate, one per level or one for all) along ``direction`` ('ux' or 'uy'; default:
    the free DOF itself). E.g. the input torque of a mechanism that brings its slider to a position."""

    free_dof: str
    value: FloatArray | float
    node: str | None = None
    direction: str | None = None


@dataclass
class TipInverseResult:
    converged: bool
    message: str
    result: FemResult
    tip_loads: FloatArray  # (n_levels, 3): F_x, F_y, M acting on the tip
    tied: FloatArray  # (n_levels,): the tied load (0 without a tie)
    residual: FloatArray  # (n_levels,): g at the solution (0 without a tie)
    nit: int
    nfev: int
    wall_time: float


def tip_loads(model: Model, result: FemResult, tip: str) -> FloatArray:
    """Total load (F_x, F_y, M) on the tip per level: reactions at its held DOFs plus the dead
    forces and moments applied there (a follower force at the tip is not allowed)."""
    node = model.node(tip)
    total = np.array(result.reactions[:, node, :], dtype=float)
    for load in model.loads:
        if load.node != node or load.member is not None:
            continue
        if load.kind == "force":
            if load.follower:
                raise ValueError("an inverse tip problem takes dead tip forces only")
            total[:, :2] += np.broadcast_to(load.values, (result.n_levels, 2))
        else:
            total[:, 2] += np.broadcast_to(load.values, (result.n_levels,))
    return total


def _with_tied(model: Model, tip: str, dof: str, values: FloatArray) -> Model:
    trial = copy.copy(model)
    trial.loads = list(model.loads)
    if dof == "rz":
        trial.add_moment(tip, values)
    else:
        zero = np.zeros_like(values)
        trial.add_force(tip, *((values, zero) if dof == "ux" else (zero, values)))
    return trial


def _residual(
    model: Model, result: FemResult, tip: str, tie: LoadRatio | ZeroMoment | Position, tied: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """(g, the scale |g| is measured against) per level for a converged solve: a load scale
    max(|F_x|, |F_y|) + |M|/L_char, or for a position L_char."""
    loads = tip_loads(model, result, tip)
    scale = np.max(np.abs(loads[:, :2]), axis=1) + np.abs(loads[:, 2]) / model.characteristic_length()
    if isinstance(tie, LoadRatio):
        ref = loads[:, DOF_NAMES[tie.reference_dof]]
        return tied - np.broadcast_to(tie.ratio, tied.shape) * ref, scale
    if isinstance(tie, Position):
        x = result.positions[:, model.node(tie.node or tip), DOF_NAMES[tie.direction or tie.free_dof]]
        return x - np.broadcast_to(tie.value, tied.shape), np.full(len(x), model.characteristic_length())
    i, k = model.node(tip), model.node(tie.node)
    lever = result.positions[:, i, :] - result.positions[:, k, :]
    m = loads[:, 2] + loads[:, 1] * lever[:, 0] - loads[:, 0] * lever[:, 1]
    return m, scale


def solve_tip_inverse(
    model: Model,
    tip: str,
    tie: LoadRatio | ZeroMoment | Position | None = None,
    *,
    guess: ArrayLike | None = None,
    tie_rtol: float = 1e-7,
    maxiter: int = 40,
    n_levels: int | None = None,
    **solve_options: Any,
) -> TipInverseResult:
    """Solve the inverse tip problem of ``model`` (its prescribed tip DOFs are the pose).

    ``tie``: the condition fixing the load on the one tip DOF that is neither prescribed nor
    loaded by the model (None: no such load). ``guess``: the tied load per level to start from
    (default 0). ``n_levels``: the number of levels when the model's own loads do not set it (a
    model whose only load is the tied one). Other keyword arguments go to ``fem.solve``.
    """
    t0 = time.perf_counter()
    n = n_levels or model.n_levels
    if tie is None:
        result = solve(model, n_levels=n, **solve_options)
        done = result.converged and result.n_levels == n
        zeros = np.zeros(n)
        return TipInverseResult(
            done,
            result.message,
            result,
            tip_loads(model, result, tip) if done else np.full((n, 3), np.nan),
            zeros,
            zeros,
            0,
            1,
            time.perf_counter() - t0,
        )
    if tie.free_dof not in DOF_NAMES or (isinstance(tie, Position) and (tie.direction or tie.free_dof) == "rz"):
        raise ValueError(f"free_dof must be one of {sorted(DOF_NAMES)}; a Position is measured along 'ux' or 'uy'")
    prescribed = {(p.node, p.dof) for p in model.prescribed}
    if (model.node(tip), DOF_NAMES[tie.free_dof]) in prescribed:
        raise ValueError(f"the tied DOF {tie.free_dof!r} of {tip!r} is prescribed")
    if isinstance(tie, LoadRatio) and (model.node(tip), DOF_NAMES[tie.reference_dof]) not in prescribed:
        raise ValueError(f"the reference DOF {tie.reference_dof!r} of {tip!r} must be prescribed")

    nfev = 0

    def evaluate(tied: FloatArray) -> tuple[FemResult, FloatArray | None, FloatArray | None, Model]:
        nonlocal nfev
        nfev += 1
        trial = _with_tied(model, tip, tie.free_dof, tied)
        res = solve(trial, n_levels=n, **solve_options)
        if not res.converged or res.n_levels < n:
            return res, None, None, trial
        g, scale = _residual(trial, res, tip, tie, tied)
        return res, g, scale, trial

    f0 = np.zeros(n) if guess is None else np.broadcast_to(np.asarray(guess, float), (n,)).copy()
    res0, g0, scale0, trial0 = evaluate(f0)
    if g0 is None:
        return _failed(res0, f0, 0, nfev, t0, f"the start loads do not converge: {res0.message}")
    if isinstance(tie, LoadRatio):
        f1 = f0 - g0  # one fixed-point step: F = ratio * P(F0)
    else:
        loads0 = tip_loads(trial0, res0, tip)
        load_scale = np.max(np.abs(loads0[:, :2]), axis=1) + np.abs(loads0[:, 2]) / model.characteristic_length()
        f1 = f0 + 1e-3 * np.where(load_scale > 0, load_scale, 1.0)
    f_prev, g_prev = f0, g0
    f, res, scale, trial = f1, res0, scale0, trial0
    g: FloatArray | None = None
    for it in range(1, maxiter + 1):
        step = f - f_prev
        for _ in range(8):
            res, g, scale, trial = evaluate(f)
            if g is not None:
                break
            step = step / 2.0
            f = f_prev + step
        else:
            return _failed(
                res,
                f,
                it,
                nfev,
                t0,
                f"the FEM did not converge near tied loads [{', '.join(f'{v:.4g}' for v in f)}]: {res.message}",
            )
        assert g is not None and scale is not None  # a converged solve's (the loop above)
        settled = np.abs(g) <= tie_rtol * np.where(scale > 0, scale, 1.0)
        if settled.all():
            return TipInverseResult(
                True,
                f"tied load converged in {it} secant iterations ({nfev} FEM solves); " + res.message,
                res,
                tip_loads(trial, res, tip),
                f.copy(),
                g,
                it,
                nfev,
                time.perf_counter() - t0,
            )
        slope = (g - g_prev) / np.where(f != f_prev, f - f_prev, np.nan)
        f_next = np.where(settled | ~np.isfinite(slope) | (slope == 0), f, f - g / slope)
        f_prev, g_prev, f = f, g, f_next
    assert g is not None, "maxiter must be at least 1"
    return _failed(
        res,
        f,
        maxiter,
        nfev,
        t0,
        f"tied load not converged in {maxiter} secant iterations: residual {np.abs(g).max():.3g}",
    )


def _failed(result: FemResult, tied: FloatArray, nit: int, nfev: int, t0: float, message: str) -> TipInverseResult:
    n = len(tied)
    return TipInverseResult(
        False,
        message,
        result,
        np.full((n, 3), np.nan),
        np.asarray(tied, float),
        np.full(n, np.nan),
        nit,
        nfev,
        time.perf_counter() - t0,
    )
