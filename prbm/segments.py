"""Single-spring pseudo-rigid-body models of compliant segments, over any number of load levels.

Every model here is a rigid PRB link of radius R from a characteristic pivot, held by one torsional
spring k (or two equal springs in series, for the fixed-guided beam), loaded by an end force
F (cos phi, sin phi).  Equilibrium about the pivot (virtual work on the one coordinate Theta) is

    F R sin(phi - Theta) = k (Theta - Theta_i),                                           (*)

solved for the PRB angle Theta by a safeguarded Newton iteration on the bracket between Theta_i and
phi, started from the linear solution (analytic derivative -F R cos(phi - Theta) - k; quadratic
convergence, at most ~8 iterations).  With Theta_i = 0 the residual is concave on (0, phi), so the
root is unique.

Structure: each model's level equations have one implementation, a plain-float kernel for one load
level (``_fixed_pinned_level``, ``_pure_moment_level``, ``_curved_level``, ``_fixed_guided_level``), fed
the constants of its load ratio (the n-fits and what follows from them, evaluated once per distinct
ratio); the public functions loop it over the levels (a case has a few; a numpy call's fixed
overhead, whatever its length, exceeds a level's arithmetic).  ``spring_angle`` itself keeps a numpy
iteration for long arrays given to it directly (``slfp_tip``, ``curved_pinned_pinned``).

Conventions: x along the undeformed segment from the fixed end, y transverse, CCW-positive angles;
the end force is (-nP, P), so n > 0 is compressive ([bapat2015], notes to Tables 3.2-3.6);
phi = atan2(1, -n).  For P < 0 the model is mirrored about x (b, theta0, Theta change sign) and the
fits are evaluated at the mirrored ratio -n, so that the axial component -nP is preserved.
Angles in radians; lengths, forces and EI in any consistent units.

Models and their source equations:
* ``fixed_pinned_tip`` / ``fixed_pinned_from_tip``: initially straight fixed-pinned (fixed-free)
  segment under an end force, [bapat2015, eqs 41-50] (Howell-Midha, Pauly-Midha fits), or the Howell fits
  of [ananthasuresh_l18, 05:41] with ``family="howell"`` (no c_theta there: theta0 is then not available).
* ``pure_moment_tip`` / ``pure_moment_from_tip``: end moment, [ananthasuresh_l18, 16:59-21:58]
  (gamma = 0.7346, k = 1.5164 EI/L).
* ``curved_fixed_pinned_tip``: initially curved fixed-pinned, [bapat2015, eqs 53-61].  The dissertation omits
  the load relation, any dependence of gamma, K_Theta, c_theta on the initial curvature, and the
  theta0 map; assumed here (and stated in the result): k = rho K_Theta EI/l with the straight-beam
  K_Theta(n), equilibrium (*) with R = rho l, and theta0 = kappa0 + c_theta (Theta - Theta_i).  The
  dependence on the initial curvature is geometric only (Theta_i and rho from kappa0 = l/R_i).
* ``fixed_guided_tip``: initially straight fixed-guided segment (end slope held at zero), [bapat2015,
  eq 63] (k = 2 gamma K_Theta EI/l, two springs) and [ananthasuresh_l18, 07:13-12:05] (two half-PRBMs,
  middle link gamma l, end links (1-gamma) l/2); the end moment that holds the slope is returned.
* ``fixed_guided_monotonic_tip``: fixed-guided (or fixed-fixed) segment with monotonic curvature:
  the curved fixed-pinned PRBM with the end moment as an equivalent initial curvature
  kappa0 = M l / EI (+ l/R_i if initially curved), [bapat2015, eqs 62, 14, 17, 119].
* ``slfp_tip``: small-length flexural pivot (straight, or initially curved), [bapat2015, eqs 71-82],
  k = EI/l, pivot at the middle of the flexure, PRB link L + l/2.  Eq (76)'s moment arm is
  L + l/2 (the printed F l sin(phi - theta0) of section 2.1.6 is a misprint, notes seed-ch2-4 s. 2.6).
* ``curved_pinned_pinned``: initially curved pinned-pinned segment as two initially curved
  fixed-pinned halves fixed at mid-span (Edwards et al., [bapat2015, §2.3.5], which prints no
  equations).  The force along the chord is a pure axial load on each half (n infinite), outside
  every published n-fit, so constant gamma and K_Theta are used (default the averages of
  [ananthasuresh_l18], 0.85 and 2.65) and reported.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from math import cos, sin
from typing import Any, Generic, NamedTuple, TypeGuard, TypeVar, cast, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from prbm.fits import PURE_MOMENT_C_THETA, PURE_MOMENT_GAMMA, PURE_MOMENT_SPRING, FitFamily, fit_family
from prbm.result import Levels, PRBMResult
from argcheck import checked
from prbm.lazy import LazyModule

optimize = LazyModule("scipy.optimize")  # brentq: imported at its first use

__all__ = [
    "spring_angle",
    "fixed_pinned_tip",
    "fixed_pinned_from_tip",
    "pure_moment_tip",
    "pure_moment_from_tip",
    "curved_fixed_pinned_tip",
    "fixed_guided_tip",
    "fixed_guided_monotonic_tip",
    "slfp_tip",
    "slfp_end_tip",
    "curved_pinned_pinned",
]


@overload
def spring_angle(
    FR: float, phi: float, k: float, theta_i: float = 0.0, *, xtol: float = 1e-13, maxiter: int = 60
) -> tuple[float, bool, int]: ...


@overload
def spring_angle(
    FR: ArrayLike, phi: ArrayLike, k: ArrayLike, theta_i: ArrayLike = 0.0, *, xtol: float = 1e-13, maxiter: int = 60
) -> tuple[float | NDArray[np.float64], bool | NDArray[np.bool_], int]: ...


def spring_angle(
    FR: ArrayLike, phi: ArrayLike, k: ArrayLike, theta_i: ArrayLike = 0.0, *, xtol: float = 1e-13, maxiter: int = 60
) -> tuple[float | NDArray[np.float64], bool | NDArray[np.bool_], int]:
    """Solve F R sin(phi - Theta) = k (Theta - Theta_i) for Theta, vectorised.

    FR >= 0 (force times PRB link), phi the absolute force angle, k > 0 the spring.  The root lies
    between Theta_i and phi (when |phi - Theta_i| < pi).  The residual g(Theta) is concave on
    (Theta_i, phi) when phi > Theta_i (convex when phi < Theta_i), so Newton started on the phi side
    of the root converges monotonically and quadratically.  The start is the linear solution
    Theta_i + F R sin(phi - Theta_i) / (F R cos(phi - Theta_i) + k) (one Newton step from Theta_i,
    which lies on the phi side by concavity) when it falls inside the bracket, else phi; a step
    leaving the bracket is replaced by bisection.  Converged when the Newton step is below
    xtol (1 + |Theta|).  Returns (Theta, converged, iterations); arrays of a few hundred levels are
    solved level by level in plain floats (cheaper than numpy's per-call overhead).
    """
    args = [np.asarray(v, dtype=float) for v in (FR, phi, k, theta_i)]
    shapes = {a.shape for a in args if a.ndim}
    if not shapes:
        return _spring_angle_scalar(float(args[0]), float(args[1]), float(args[2]), float(args[3]), xtol, maxiter)
    if len(shapes) > 1:
        args = list(np.broadcast_arrays(*args))
    shape = args[0].shape if len(shapes) > 1 else shapes.pop()
    size = math.prod(shape)
    if size <= _SCALAR_LOOP_MAX:
        columns = [a.ravel().tolist() if a.ndim else [float(a)] * size for a in args]
        solved = [
            _spring_angle_scalar(FR_l, phi_l, k_l, theta_l, xtol, maxiter)
            for FR_l, phi_l, k_l, theta_l in zip(*columns)
        ]
        Theta = np.array([s[0] for s in solved], dtype=float).reshape(shape)
        ok = np.array([s[1] for s in solved], dtype=bool).reshape(shape)
        return Theta, ok, max((s[2] for s in solved), default=0)
    FR_b, phi_b, k_b, theta_b = np.broadcast_arrays(*args)
    return _spring_angle_vector(FR_b, phi_b, k_b, theta_b, xtol, maxiter)


_SCALAR_LOOP_MAX = 256  # up to this many levels the plain-float loop beats the numpy iteration
_PLAIN = (float, int, np.float64)  # one load level given as a number


def _spring_angle_scalar(
    FR: float, phi: float, k: float, theta_i: float, xtol: float = 1e-13, maxiter: int = 60
) -> tuple[float, bool, int]:
    """``spring_angle`` for one level in plain floats (called once per load level by
    every segment model's level kernel, so it is written for CPython: module-global math functions,
    each quantity computed once per iteration, no helper calls).

    Start: the linear solution of (*) about Theta_i, Theta_i + F R sin(phi - Theta_i) / (F R cos(phi -
    Theta_i) + k) (the first Newton step from Theta_i), when inside the bracket, else phi.  The residual
    g decreases through the root in the bracket, so g > 0 puts x below the root (lo = x), g < 0 above.
    A spring k <= 0 (or NaN) has no such root: not converged, Theta NaN."""
    if not k > 0.0:
        return math.nan, False, 0
    if FR == 0.0 or phi == theta_i:
        return theta_i, True, 0
    if theta_i < phi:
        lo, hi = theta_i, phi
    else:
        lo, hi = phi, theta_i
    x = phi
    d = FR * cos(phi - theta_i) + k
    if d > 0.0:
        x0 = theta_i + FR * sin(phi - theta_i) / d
        if lo < x0 < hi:
            x = x0
    for it in range(1, maxiter + 1):
        e = phi - x
        s = sin(e)
        fx = FR * s - k * (x - theta_i)
        if fx == 0.0:
            return x, True, it
        if fx > 0.0:  # shrink the bracket
            lo = x
        else:
            hi = x
        dfx = -FR * cos(e) - k
        step = fx / dfx if dfx != 0.0 else math.inf
        x_new = x - step
        tol = xtol * (1.0 + abs(x))
        size = abs(step)
        # done when the step is below tol, or when the quadratic error left after it,
        # |g''| step^2 / (2 |g'|) with g'' = -F R sin(phi - x), is ten times below tol
        if size <= tol or (size < 1e-4 and 5.0 * FR * abs(s) * step * step <= tol * abs(dfx)):
            return x_new, True, it
        if not (lo < x_new < hi):
            x_new = 0.5 * (lo + hi)
            if hi - lo <= xtol * (1.0 + abs(x_new)):
                return x_new, True, it
        x = x_new
    return x, False, maxiter


def _spring_angle_vector(
    FR: NDArray[np.float64],
    phi: NDArray[np.float64],
    k: NDArray[np.float64],
    theta_i: NDArray[np.float64],
    xtol: float,
    maxiter: int,
) -> tuple[NDArray[np.float64], NDArray[np.bool_], int]:
    """``spring_angle`` over many levels at once (numpy), the same iteration as the scalar version."""
    lo = np.minimum(theta_i, phi)
    hi = np.maximum(theta_i, phi)
    toward_phi = phi > theta_i
    d = FR * np.cos(phi - theta_i) + k
    with np.errstate(divide="ignore", invalid="ignore"):
        lin = theta_i + FR * np.sin(phi - theta_i) / d
    x = np.where((d > 0.0) & (lo < lin) & (lin < hi), lin, phi)
    no_spring = ~(k > 0.0)  # no root (scalar version): not converged, NaN
    done = (FR == 0.0) | (phi == theta_i) | no_spring
    x = np.where(no_spring, np.nan, np.where(done, theta_i, x))
    if done.all():  # no level loaded: Theta = Theta_i without an iteration (as the scalar path reports)
        return x, done & ~no_spring, 0
    it = 0
    for it in range(1, maxiter + 1):
        fx = FR * np.sin(phi - x) - k * (x - theta_i)
        dfx = -FR * np.cos(phi - x) - k
        near_side = (fx > 0.0) == toward_phi  # x between Theta_i and the root
        move_lo = near_side == toward_phi
        lo = np.where(move_lo, x, lo)
        hi = np.where(move_lo, hi, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(dfx != 0.0, fx / np.where(dfx != 0.0, dfx, 1.0), np.inf)
        x_new = x - step
        small = (np.abs(step) <= xtol * (1.0 + np.abs(x))) | (fx == 0.0)
        x_new = np.where(fx == 0.0, x, x_new)
        outside = ~((lo < x_new) & (x_new < hi)) & ~small
        x_new = np.where(outside, 0.5 * (lo + hi), x_new)
        small |= outside & (hi - lo <= xtol * (1.0 + np.abs(x_new)))
        x = np.where(done, x, x_new)
        done = done | small
        if done.all():
            break
    return x, done & np.isfinite(x), it


def _spring_angle_reference(
    FR: float | NDArray[np.float64],
    phi: float | NDArray[np.float64],
    k: float | NDArray[np.float64],
    theta_i: float | NDArray[np.float64] = 0.0,
    *,
    xtol: float = 1e-13,
    maxiter: int = 60,
) -> tuple[float | NDArray[np.float64], bool | NDArray[np.bool_], int]:
    """Reference (previous) solver of (*): safeguarded Newton from phi; kept to test ``spring_angle``.

    FR >= 0 (force times PRB link), phi the absolute force angle, k > 0 the spring.  The root lies
    between Theta_i and phi (when |phi - Theta_i| < pi): safeguarded Newton on that bracket.
    Returns (Theta, converged, iterations).
    """
    if all(np.ndim(v) == 0 for v in (FR, phi, k, theta_i)):
        return _spring_angle_reference_scalar(float(FR), float(phi), float(k), float(theta_i), xtol, maxiter)
    FR, phi, k, theta_i = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (FR, phi, k, theta_i)))
    lo = np.minimum(theta_i, phi).astype(float)
    hi = np.maximum(theta_i, phi).astype(float)

    def f(t: NDArray[np.float64]) -> NDArray[np.float64]:
        return FR * np.sin(phi - t) - k * (t - theta_i)

    f_lo = f(lo)
    x = np.where(phi >= theta_i, hi, lo).copy()  # start at phi: monotone Newton for the concave case
    done = FR == 0.0
    x = np.where(done, theta_i, x)
    it = 0
    for it in range(1, maxiter + 1):
        fx = f(x)
        dfx = -FR * np.cos(phi - x) - k
        # shrink the bracket with the sign of f
        same = np.sign(fx) == np.sign(f_lo)
        lo = np.where(same, x, lo)
        f_lo = np.where(same, fx, f_lo)
        hi = np.where(same, hi, x)
        step = np.where(dfx != 0.0, fx / np.where(dfx != 0.0, dfx, 1.0), 0.0)
        x_new = x - step
        outside = (x_new <= np.minimum(lo, hi)) | (x_new >= np.maximum(lo, hi)) | ~np.isfinite(x_new)
        x_new = np.where(outside, 0.5 * (lo + hi), x_new)
        delta = np.abs(x_new - x)
        x = np.where(done, x, x_new)
        done = done | (delta < xtol * (1.0 + np.abs(x)))
        if np.all(done):
            break
    converged = done & np.isfinite(x)
    return x, converged, it


def _spring_angle_reference_scalar(
    FR: float, phi: float, k: float, theta_i: float, xtol: float, maxiter: int
) -> tuple[float, bool, int]:
    """Scalar version of ``_spring_angle_reference``."""
    if FR == 0.0:
        return theta_i, True, 0
    lo, hi = min(theta_i, phi), max(theta_i, phi)
    f_lo = FR * math.sin(phi - lo) - k * (lo - theta_i)
    x = hi if phi >= theta_i else lo
    for it in range(1, maxiter + 1):
        fx = FR * math.sin(phi - x) - k * (x - theta_i)
        dfx = -FR * math.cos(phi - x) - k
        if (fx > 0) == (f_lo > 0):
            lo, f_lo = x, fx
        else:
            hi = x
        x_new = x - fx / dfx if dfx != 0.0 else 0.5 * (lo + hi)
        if not (min(lo, hi) < x_new < max(lo, hi)):
            x_new = 0.5 * (lo + hi)
        if abs(x_new - x) < xtol * (1.0 + abs(x_new)):
            return x_new, True, it
        x = x_new
    return x, False, maxiter


# --- the level kernels --------------------------------------------------------------------------
# Each model below has ONE implementation of its level equations: a plain-float kernel for one load
# level (``_fixed_pinned_level``, ``_pure_moment_level``, ``_curved_level``, ``_fixed_guided_level``),
# given the constants of its load ratio (the n-fits and what follows from them, evaluated once per
# distinct ratio: ``_fixed_pinned_ratio``, ``_curved_ratio``, ``_fixed_guided_ratio``).  The public
# functions loop the kernel over the levels whatever their number (a single float, a few levels of a
# case, or a long sweep).


def _level_lists(
    P: list[float] | ArrayLike, n: list[float] | ArrayLike
) -> tuple[list[float], list[float], tuple[int, ...]]:
    """P and n over the levels as two equally long lists of floats, and the levels' shape."""
    if (
        type(P) is list
        and type(n) is list
        and len(P) == len(n)
        and all(type(v) is float for v in P)
        and all(type(v) is float for v in n)
    ):  # already that (a case's levels)
        return P, n, (len(P),)
    P_arr, n_arr = np.asarray(P, float), np.asarray(n, float)
    if P_arr.shape != n_arr.shape:
        P_arr, n_arr = np.broadcast_arrays(P_arr, n_arr)
    return P_arr.ravel().tolist(), n_arr.ravel().tolist(), P_arr.shape


def _arrays(columns: dict[str, list[float]], shape: tuple[int, ...]) -> dict[str, NDArray[np.float64]]:
    """Each column of floats as an array of the levels' shape (a 0-d array for one scalar level)."""
    if len(shape) == 1:
        return {key: np.array(column, dtype=float) for key, column in columns.items()}
    return {key: np.array(column, dtype=float).reshape(shape) for key, column in columns.items()}


def _table(
    rows: Sequence[tuple[float, ...]], names: tuple[str, ...], shape: tuple[int, ...]
) -> dict[str, NDArray[np.float64]]:
    """Per-level rows (one tuple of floats a level) -> one array of the levels' shape a name (the rows'
    first len(names) entries)."""
    if not rows:
        return {name: np.empty(shape) for name in names}
    if len(shape) == 1:  # one array a column (numpy is slow to read a list of tuples as one 2-d array)
        return {name: np.array(column, dtype=float) for name, column in zip(names, zip(*rows))}
    return {name: np.array(column, dtype=float).reshape(shape) for name, column in zip(names, zip(*rows))}


def _columns(rows: Sequence[tuple[float, ...]], names: tuple[str, ...]) -> dict[str, list[float]]:
    """Per-level rows (one tuple a level) -> one list a name (the rows' first len(names) entries)."""
    if not rows:
        return {name: [] for name in names}
    return dict(zip(names, (list(column) for column in zip(*rows))))


def _scalar_or_array(d: dict[str, ArrayLike]) -> dict[str, Levels]:
    return {key: np.asarray(v, dtype=float) for key, v in d.items()}


_L = TypeVar("_L", float, NDArray[np.float64])  # a quantity at one level (a float) or at all levels (an array)
_B = TypeVar("_B", bool, NDArray[np.bool_])  # a level's convergence (a bool) or all levels' (an array)
_R = TypeVar("_R")  # the constants of one load ratio (``_mirrored_levels``)
_Row = TypeVar("_Row")  # one level's row (``_mirrored_levels``)


@dataclass(frozen=True, slots=True)
class _Ops(Generic[_L, _B]):
    """What a level kernel evaluates with: ``FLOATS`` for one level in plain floats (math, the scalar
    spring solve), ``ARRAYS`` for all the levels at once (numpy, the vectorised spring solve)."""

    sin: Callable[[_L], _L]
    cos: Callable[[_L], _L]
    sqrt: Callable[[_L], _L]
    atan2: Callable[[_L | float, _L | float], _L]
    hypot: Callable[[_L | float, _L | float], _L]
    where: Callable[[bool | NDArray[np.bool_], _L | float, _L | float], _L]
    # spring(FR, phi, k, Theta_i) -> (Theta, converged, iterations) of (*)
    spring: Callable[[_L, _L, _L | float, _L | float], tuple[_L, _B, int]]


def _pick(condition: object, yes: float, no: float) -> float:
    return yes if condition else no


def _is_number(value: object) -> TypeGuard[float]:
    """One load level given as a number (a float, an int or an np.float64; not a bool or an array)."""
    return type(value) in _PLAIN


def _spring_levels(
    FR: ArrayLike, phi: ArrayLike, k: ArrayLike, theta_i: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.bool_], int]:
    FR_b, phi_b, k_b, theta_b = np.broadcast_arrays(*(np.asarray(v, float) for v in (FR, phi, k, theta_i)))
    return _spring_angle_vector(FR_b, phi_b, k_b, theta_b, 1e-13, 60)


_FLOATS: _Ops[float, bool] = _Ops(
    math.sin, math.cos, math.sqrt, math.atan2, lambda x, y: float(np.hypot(x, y)), _pick, _spring_angle_scalar
)
_ARRAYS: _Ops[NDArray[np.float64], NDArray[np.bool_]] = _Ops(
    np.sin, np.cos, np.sqrt, np.arctan2, np.hypot, np.where, _spring_levels
)


def _mirrored_levels(
    P_list: list[float], n_list: list[float], ratio: Callable[[float], _R], level: Callable[[float, float, _R], _Row]
) -> tuple[list[_Row], list[_R]]:
    """The level rows of a straight segment model under the end force (-nP, P), in plain floats: each load
    mirrored to P >= 0 (n_eff = sign n, sign restoring it), the per-ratio constants ``ratio(n_eff)`` worked
    out once per distinct mirrored ratio, ``level(|P|, sign, constants)`` at each level.
    Returns (rows, the constants of each level)."""
    per_ratio: dict[float, _R] = {}
    rows: list[_Row] = []
    fits: list[_R] = []
    for p, m in zip(P_list, n_list):
        sign = -1.0 if p < 0.0 else 1.0
        n_eff = sign * m
        c = per_ratio.get(n_eff)
        if c is None:
            c = per_ratio[n_eff] = ratio(n_eff)
        rows.append(level(abs(p), sign, c))
        fits.append(c)
    return rows, fits


class _FixedPinnedRatio(NamedTuple, Generic[_L]):
    """The constants of one (mirrored) load ratio n of the fixed-pinned model: gamma, c_theta, K_theta
    from the fits (41)-(43), the spring k = gamma K_theta EI/l (45), eta = sqrt(1 + n^2) and the force
    angle phi = atan2(1, -n) (46)-(47), the PRB link gamma l."""

    gamma: _L
    c_theta: _L
    K: _L
    k: _L
    eta: _L
    phi: _L
    gl: _L


def _fixed_pinned_ratio(
    xp: _Ops[_L, _B], n_eff: _L, length: float, EI: float, fam: FitFamily, extrapolate: str
) -> _FixedPinnedRatio[_L]:
    gamma, c_theta, K = fam.model_parameters(n_eff, extrapolate)
    return _FixedPinnedRatio(
        gamma, c_theta, K, gamma * K * EI / length, xp.sqrt(1.0 + n_eff * n_eff), xp.atan2(1.0, -n_eff), gamma * length
    )


def _fixed_pinned_level(
    xp: _Ops[_L, _B], Pabs: _L, sign: _L, c: _FixedPinnedRatio[_L], length: float, EI: float
) -> tuple[_L, _L, _L, _L, _L, _B, int]:
    """The fixed-pinned model at a level (floats) or at all levels (arrays) [bapat2015, eqs 44-49], the
    load mirrored to P >= 0 (sign restores it): F = P eta, (F l^2/EI) sin(phi - Theta) = K_theta Theta,
    a = l - gamma l (1 - cos Theta), b = gamma l sin Theta, theta0 = c_theta Theta.
    Returns (a, b, theta0, Theta, F, converged, iterations)."""
    _, c_theta, K, _, eta, phi, gl = c
    F = Pabs * eta
    T, ok, nit = xp.spring(F * length**2 / EI, phi, K, 0.0)
    return length - gl * (1.0 - xp.cos(T)), sign * gl * xp.sin(T), sign * c_theta * T, sign * T, F, ok, nit


@checked(positive=("length", "EI"), finite=("P", "n"))
def fixed_pinned_tip(
    P: ArrayLike,
    n: ArrayLike = 0.0,
    *,
    length: float,
    EI: float,
    family: str | FitFamily = "pauly-midha",
    extrapolate: str = "raise",
) -> PRBMResult:
    """Tip of an initially straight fixed-pinned (fixed-free) segment under the end force (-nP, P).

    [bapat2015, eqs 41-49]: gamma, c_theta, K_theta from the n-fits; F = P sqrt(1+n^2);
    (F l^2/EI) sin(phi - Theta) = K_theta Theta (46)-(47), i.e. (*) with R = gamma l and
    k = gamma K_theta EI/l (45); a = l - gamma l (1 - cos Theta) (48); b = gamma l sin Theta (49);
    theta0 = c_theta Theta (44).  Over P (and n): the level kernel ``_fixed_pinned_level`` level by
    level, the fits once per distinct load ratio.  Outputs a, b, theta0 (rad), Theta (rad), F; scalars
    (np.float64 outputs, float constants) for scalar P and n, else arrays of the levels' shape.
    """
    t0 = time.perf_counter()
    fam = fit_family(family)
    shape: tuple[int, ...]
    if _is_number(P) and _is_number(n):  # one level given as numbers: no array round trip
        P_list, n_list, shape = [float(P)], [float(n)], ()
    else:
        P_list, n_list, shape = _level_lists(P, n)
        if len(P_list) > _SCALAR_LOOP_MAX:  # many levels: the kernel once over arrays
            return _fixed_pinned_arrays(P, n, length, EI, fam, extrapolate, t0)
    rows, fits = _mirrored_levels(
        P_list,
        n_list,
        lambda n_eff: _fixed_pinned_ratio(_FLOATS, n_eff, length, EI, fam, extrapolate),
        lambda Pabs, sign, c: _fixed_pinned_level(_FLOATS, Pabs, sign, c, length, EI),
    )
    ok_levels = [row[5] for row in rows]
    ok_all = all(ok_levels)
    names, constant_names = ("a", "b", "theta0", "Theta", "F"), ("gamma", "c_theta", "K_theta", "k")
    out: dict[str, Levels]
    constants: dict[str, Any]
    if shape == ():  # one level given as scalars
        out = {key: np.float64(v) for key, v in zip(names, rows[0])}
        out.update({"P": np.float64(P_list[0]), "n": np.float64(n_list[0])})
        constants = dict(zip(constant_names, fits[0]))
    else:
        out = {**_table(rows, names, shape), "P": np.asarray(P, float), "n": np.asarray(n, float)}
        constants = {**_table(fits, constant_names, shape)}
    constants["family"] = fam.name
    return PRBMResult(
        ok_all,
        "converged" if ok_all else "spring equation did not converge",
        out,
        constants,
        "fixed-pinned, seed 000 eqs (41)-(49)",
        time.perf_counter() - t0,
        max((row[6] for row in rows), default=0),
        np.array(ok_levels, dtype=bool).reshape(shape or (1,)),
    )


def _fixed_pinned_arrays(
    P: ArrayLike, n: ArrayLike, length: float, EI: float, fam: FitFamily, extrapolate: str, t0: float
) -> PRBMResult:
    """``fixed_pinned_tip`` over many levels: the same kernel evaluated once on numpy arrays."""
    P_arr, n_arr = np.broadcast_arrays(np.asarray(P, float), np.asarray(n, float))
    sign = np.where(P_arr < 0.0, -1.0, 1.0)
    c = _fixed_pinned_ratio(_ARRAYS, sign * n_arr, length, EI, fam, extrapolate)
    a, b, theta0, Theta, F, ok, nit = _fixed_pinned_level(_ARRAYS, np.abs(P_arr), sign, c, length, EI)
    out: dict[str, Levels] = {
        "a": a,
        "b": b,
        "theta0": theta0,
        "Theta": Theta,
        "F": F,
        "P": np.asarray(P, float),
        "n": np.asarray(n, float),
    }
    constants = {"gamma": c.gamma, "c_theta": c.c_theta, "K_theta": c.K, "k": c.k, "family": fam.name}
    ok_all = bool(np.all(ok))
    return PRBMResult(
        ok_all,
        "converged" if ok_all else "spring equation did not converge",
        out,
        constants,
        "fixed-pinned, seed 000 eqs (41)-(49)",
        time.perf_counter() - t0,
        nit,
        ok,
    )


@checked(positive=("length", "EI"), finite=("n", "a", "b", "theta0"))
def fixed_pinned_from_tip(
    *,
    n: ArrayLike = 0.0,
    a: ArrayLike | None = None,
    b: ArrayLike | None = None,
    theta0: ArrayLike | None = None,
    length: float,
    EI: float,
    family: str | FitFamily = "pauly-midha",
    extrapolate: str = "raise",
) -> PRBMResult:
    """Inverse fixed-pinned problem: tip position (a, b), or b alone, or theta0 -> P (force (-nP, P)).

    Theta from eq (50) Theta = atan(b / (a - (1 - gamma) l)) when a and b are given, from eq (49)
    when only b is (then Theta <= 90 deg is assumed: asin), from eq (44) when only theta0 is; then P = K_theta Theta EI / (l^2 eta sin(phi - Theta))
    from (46)-(47).  Only P > 0 configurations (Theta in (0, phi)) are meaningful.
    """
    t0 = time.perf_counter()
    fam = fit_family(family)
    n = np.asarray(n, dtype=float)
    gamma, c_theta, K = fam.model_parameters(n, extrapolate)
    if a is not None and b is not None:
        Theta = np.arctan2(np.asarray(b, float), np.asarray(a, float) - (1.0 - gamma) * length)
    elif b is not None:
        Theta = np.arcsin(np.asarray(b, float) / (gamma * length))
    elif theta0 is not None:
        Theta = np.asarray(theta0, float) / c_theta
    else:
        raise ValueError("give a and b, or b, or theta0")
    phi = np.arctan2(1.0, -n)
    eta = np.sqrt(1.0 + n**2)
    P = K * Theta * EI / (length**2 * eta * np.sin(phi - Theta))
    ok = np.isfinite(P) & (P > 0)
    out = _scalar_or_array(
        {
            "P": P,
            "Theta": Theta,
            "a": length - gamma * length * (1 - np.cos(Theta)),
            "b": gamma * length * np.sin(Theta),
            "theta0": c_theta * Theta,
            "n": n,
        }
    )
    return PRBMResult(
        bool(np.all(ok)),
        "solved" if np.all(ok) else "no positive load reaches this position",
        out,
        {"gamma": gamma, "c_theta": c_theta, "K_theta": K, "family": fam.name},
        "fixed-pinned inverse, seed 000 eqs (44), (46)-(50)",
        time.perf_counter() - t0,
        level_converged=np.atleast_1d(ok),
    )


@checked(positive=("length", "EI"), finite=("M",))
def pure_moment_tip(M: ArrayLike, *, length: float, EI: float) -> PRBMResult:
    """Cantilever under an end moment M (CCW): the PRBM of [ananthasuresh_l18, 16:59-21:58],
    gamma = 0.7346, k = 1.5164 EI/L.

    Theta = M / k; a = l - gamma l (1 - cos Theta); b = gamma l sin Theta; theta0 = 1.5164 Theta
    (= M l/EI, exact).  The exact arc is in the outputs too (a_exact, b_exact) for comparison.  Level by
    level with ``_pure_moment_level``.
    """
    t0 = time.perf_counter()
    M = np.asarray(M, dtype=float)
    k = PURE_MOMENT_SPRING * EI / length
    names = ("a", "b", "theta0", "Theta", "M", "a_exact", "b_exact")
    out: dict[str, Levels]
    if M.size > _SCALAR_LOOP_MAX:  # many levels: the kernel once over the array
        out = dict(zip(names, _pure_moment_level(_ARRAYS, M, length, EI, k)))
    else:
        out = {**_table([_pure_moment_level(_FLOATS, m, length, EI, k) for m in M.ravel().tolist()], names, M.shape)}
    return PRBMResult(
        True,
        "closed form",
        out,
        {"gamma": PURE_MOMENT_GAMMA, "k": k, "spring_coefficient": PURE_MOMENT_SPRING, "c_theta": PURE_MOMENT_C_THETA},
        "pure end moment, seed 004",
        time.perf_counter() - t0,
        level_converged=np.ones(np.atleast_1d(M).shape, bool),
    )


def _pure_moment_level(
    xp: _Ops[_L, _B], m: _L, length: float, EI: float, k: float
) -> tuple[_L, _L, _L, _L, _L, _L, _L]:
    """``pure_moment_tip`` at a level (floats) or at all levels (arrays): (a, b, theta0, Theta, M, a_exact,
    b_exact); the exact circular arc of curvature M/EI: rho = EI/M, a = rho sin(M l/EI),
    b = rho (1 - cos(M l/EI)) (a = l, b = 0 without a moment)."""
    g = PURE_MOMENT_GAMMA
    Theta = m / k
    theta_exact = m * length / EI
    bent = theta_exact != 0
    rho = length / xp.where(bent, theta_exact, 1.0)
    a_exact = xp.where(bent, rho * xp.sin(theta_exact), length)
    b_exact = xp.where(bent, rho * (1 - xp.cos(theta_exact)), 0.0)
    return (
        length - g * length * (1 - xp.cos(Theta)),
        g * length * xp.sin(Theta),
        PURE_MOMENT_C_THETA * Theta,
        Theta,
        m,
        a_exact,
        b_exact,
    )


@checked(positive=("length", "EI"), finite=("a", "b", "theta0"))
def pure_moment_from_tip(
    *, length: float, EI: float, a: ArrayLike | None = None, b: ArrayLike | None = None, theta0: ArrayLike | None = None
) -> PRBMResult:
    """Inverse of ``pure_moment_tip``: Theta from (a, b), b, or theta0, then M = k Theta."""
    g = PURE_MOMENT_GAMMA
    if a is not None and b is not None:
        Theta = np.arctan2(np.asarray(b, float), np.asarray(a, float) - (1 - g) * length)
    elif b is not None:
        Theta = np.arcsin(np.asarray(b, float) / (g * length))
    elif theta0 is not None:
        Theta = np.asarray(theta0, float) / PURE_MOMENT_C_THETA
    else:
        raise ValueError("give a and b, or b, or theta0")
    M = PURE_MOMENT_SPRING * EI / length * Theta
    return PRBMResult(
        True,
        "closed form",
        _scalar_or_array({"M": M, "Theta": Theta}),
        {"gamma": g, "k": PURE_MOMENT_SPRING * EI / length},
        "pure end moment inverse, seed 004",
    )


@checked(positive=("length", "EI"), finite=("P", "n", "curvature"))
def curved_fixed_pinned_tip(
    P: ArrayLike,
    n: ArrayLike = 0.0,
    *,
    length: float,
    EI: float,
    curvature: float,
    family: str | FitFamily = "pauly-midha",
    extrapolate: str = "raise",
) -> PRBMResult:
    """Initially curved fixed-pinned segment (initial curvature 1/R_i, CCW positive), end force (-nP, P).

    [bapat2015, eqs 53-61]: kappa0 = l/R_i (53); a_i, b_i (55)-(56); Theta_i (54); rho (57);
    k = rho K_Theta EI/l (58); a = l - gamma l + rho l cos Theta (59); b = rho l sin Theta (60).
    Assumed (not in the dissertation): equilibrium (*) with R = rho l, gamma/K_Theta/c_theta from the straight
    fits at n, theta0 = kappa0 + c_theta (Theta - Theta_i).  Level by level with ``_curved_level``.
    """
    t0 = time.perf_counter()
    fam = fit_family(family)
    P, n = np.broadcast_arrays(np.asarray(P, dtype=float), np.asarray(n, dtype=float))
    P, n = P.copy(), n.copy()
    kappa0 = curvature * length
    if P.size > _SCALAR_LOOP_MAX:  # many levels: the kernel once over arrays
        return _curved_arrays(P, n, kappa0, length, EI, fam, extrapolate, t0)
    columns, constant_columns, ok, nit = _curved_levels(
        P.ravel().tolist(), n.ravel().tolist(), [kappa0] * P.size, length, EI, fam, extrapolate
    )
    out: dict[str, Levels] = {**_arrays(columns, P.shape), "P": P, "n": n}
    constants: dict[str, Any] = {
        **_arrays(constant_columns, P.shape),
        "kappa0": kappa0,
        "family": fam.name,
        "assumptions": CURVED_ASSUMPTIONS,
    }
    return PRBMResult(
        all(ok),
        "converged" if all(ok) else "not converged",
        out,
        constants,
        "initially curved fixed-pinned, seed 000 eqs (53)-(61)",
        time.perf_counter() - t0,
        nit,
        level_converged=np.array(ok, dtype=bool).reshape(P.shape),
    )


CURVED_ASSUMPTIONS = (
    "load relation k(Theta-Theta_i) = F rho l sin(phi-Theta); "
    "theta0 = kappa0 + c_theta (Theta - Theta_i); straight-beam fits"
)


def _curved_arrays(
    P: NDArray[np.float64],
    n: NDArray[np.float64],
    kappa0: float,
    length: float,
    EI: float,
    fam: FitFamily,
    extrapolate: str,
    t0: float,
) -> PRBMResult:
    """``curved_fixed_pinned_tip`` over many levels: the same kernel evaluated once on numpy arrays."""
    c = _curved_ratio(_ARRAYS, kappa0, fam.model_parameters(np.where(P < 0, -n, n), extrapolate), length, EI)
    a, b, theta0, Theta, ok, nit = _curved_level(_ARRAYS, P, n, kappa0, c, length)
    ok_all = bool(np.all(ok))
    return PRBMResult(
        ok_all,
        "converged" if ok_all else "not converged",
        {"a": a, "b": b, "theta0": theta0, "Theta": Theta, "P": P, "n": n},
        {
            "gamma": c.gamma,
            "c_theta": c.c_theta,
            "K_theta": c.K,
            "rho": c.rho,
            "k": c.k,
            "Theta_i": c.Theta_i,
            "kappa0": kappa0,
            "family": fam.name,
            "assumptions": CURVED_ASSUMPTIONS,
        },
        "initially curved fixed-pinned, seed 000 eqs (53)-(61)",
        time.perf_counter() - t0,
        nit,
        level_converged=ok,
    )


class _CurvedRatio(NamedTuple, Generic[_L]):
    """The constants of one (kappa0, mirrored load ratio n) of the curved model: the fits gamma, c_theta,
    K_theta (41)-(43), rho (57), the spring k = rho K_theta EI/l (58) and Theta_i (54)."""

    gamma: _L
    c_theta: _L
    K: _L
    rho: _L
    k: _L
    Theta_i: _L


def _curved_ratio(
    xp: _Ops[_L, _B], kappa0: float, fit: tuple[_L, _L, _L], length: float, EI: float
) -> _CurvedRatio[_L]:
    """Eqs (54)-(58) for the initial curvature kappa0 = l/R_i and the fits ``fit`` = (gamma, c_theta, K)
    (floats, or arrays over the levels)."""
    gamma, c_theta, K = fit
    if abs(kappa0) < 1e-12:
        a_i, b_i = length, 0.0
    else:
        a_i = length / kappa0 * math.sin(kappa0)
        b_i = length / kappa0 * (1.0 - math.cos(kappa0))
    rho = xp.hypot(a_i / length - (1.0 - gamma), b_i / length)  # numpy's hypot on both paths: one value on both
    return _CurvedRatio(gamma, c_theta, K, rho, rho * K * EI / length, xp.atan2(b_i, a_i - length * (1.0 - gamma)))


def _curved_level(
    xp: _Ops[_L, _B], p: _L, m: _L, kappa0: float, c: _CurvedRatio[_L], length: float
) -> tuple[_L, _L, _L, _L, _B, int]:
    """The curved model at a level (floats) or at all levels (arrays): phi the direction of (-nP, P) on
    its branch within pi of Theta_i, F rho l sin(phi - Theta) = k (Theta - Theta_i),
    a = l - gamma l + rho l cos Theta (59), b = rho l sin Theta (60), theta0 = kappa0 + c_theta (Theta - Theta_i).
    Returns (a, b, theta0, Theta, converged, iterations)."""
    gamma, c_theta, _, rho, k, Theta_i = c
    F = abs(p) * xp.sqrt(1.0 + m * m)
    phi = xp.where(p == 0, Theta_i, xp.atan2(p, -m * p))  # absolute direction of (-nP, P)
    d = phi - Theta_i
    phi = Theta_i + xp.atan2(xp.sin(d), xp.cos(d))  # the branch of phi within pi of Theta_i
    Theta, ok, nit = xp.spring(F * rho * length, phi, k, Theta_i)
    return (
        length - gamma * length + rho * length * xp.cos(Theta),
        rho * length * xp.sin(Theta),
        kappa0 + c_theta * (Theta - Theta_i),
        Theta,
        ok,
        nit,
    )


def _curved_levels(
    P: list[float], n: list[float], kappa0: list[float], length: float, EI: float, fam: FitFamily, extrapolate: str
) -> tuple[dict[str, list[float]], dict[str, list[float]], list[bool], int]:
    """``_curved_level`` over the levels, each with its own kappa0 = l/R_i (``fixed_guided_monotonic_tip``
    adds M l/EI); the fits once per distinct load ratio, the geometry once per distinct (kappa0, ratio).
    Returns the output columns (a, b, theta0, Theta), the constants' columns, each level's convergence
    and the iterations."""
    fits: dict[float, tuple[float, float, float]] = {}
    geometry: dict[tuple[float, float], _CurvedRatio[float]] = {}
    rows: list[tuple[float, float, float, float, bool, int]] = []
    per_level: list[_CurvedRatio[float]] = []
    for p, m, k0 in zip(P, n, kappa0):
        key = (k0, -m if p < 0 else m)
        c = geometry.get(key)
        if c is None:
            fit = fits.get(key[1])
            if fit is None:
                fit = fits[key[1]] = fam.model_parameters(key[1], extrapolate)
            c = geometry[key] = _curved_ratio(_FLOATS, k0, fit, length, EI)
        rows.append(_curved_level(_FLOATS, p, m, k0, c, length))
        per_level.append(c)
    names = ("gamma", "c_theta", "K_theta", "rho", "k", "Theta_i")
    return (
        _columns(rows, ("a", "b", "theta0", "Theta")),
        _columns(per_level, names),
        [row[4] for row in rows],
        max((row[5] for row in rows), default=0),
    )


@checked(positive=("length", "EI"), finite=("P", "n"))
def fixed_guided_tip(
    P: ArrayLike,
    n: ArrayLike = 0.0,
    *,
    length: float,
    EI: float,
    family: str | FitFamily = "pauly-midha",
    extrapolate: str = "raise",
) -> PRBMResult:
    """Initially straight fixed-guided segment, end slope held at 0, end force (-nP, P).

    [bapat2015, eq 63] and [ananthasuresh_l18, 07:13-12:05]: two half-beams of l/2, each a
    fixed-pinned PRBM, so a middle link gamma l between two springs k = 2 gamma K_Theta EI/l.  Virtual work:
    2 k Theta = F gamma l sin(phi - Theta), i.e. (F l^2/EI) sin(phi - Theta) = 4 K_Theta Theta;
    a = l - gamma l (1 - cos Theta); b = gamma l sin Theta; theta0 = 0.  The end moment holding the
    slope (CCW, reaction applied to the beam) is M = -k Theta - (1 - gamma) l P / 2 (-> -P l/2 for
    small deflection).  Level by level with ``_fixed_guided_level``, the fits once per distinct ratio.
    """
    t0 = time.perf_counter()
    fam = fit_family(family)
    P_list, n_list, shape = _level_lists(P, n)
    if len(P_list) > _SCALAR_LOOP_MAX:  # many levels: the kernel once over arrays
        return _fixed_guided_arrays(P, n, length, EI, fam, extrapolate, t0)
    rows, fits = _mirrored_levels(
        P_list,
        n_list,
        lambda n_eff: _fixed_guided_ratio(_FLOATS, n_eff, length, EI, fam, extrapolate),
        lambda Pabs, sign, c: _fixed_guided_level(_FLOATS, Pabs, sign, c, length),
    )
    out: dict[str, Levels] = {
        **_table(rows, ("a", "b", "theta0", "Theta", "M"), shape),
        "P": np.asarray(P, float),
        "n": np.asarray(n, float),
    }
    constants: dict[str, Any] = {**_table(fits, ("gamma", "K_theta", "k_each"), shape), "family": fam.name}
    ok_levels = [row[5] for row in rows]
    ok_all = all(ok_levels)
    return PRBMResult(
        ok_all,
        "converged" if ok_all else "not converged",
        out,
        constants,
        "fixed-guided (two springs), seed 000 eq (63), seed 004",
        time.perf_counter() - t0,
        max((row[6] for row in rows), default=0),
        level_converged=np.array(ok_levels, dtype=bool).reshape(shape),
    )


class _FixedGuidedRatio(NamedTuple, Generic[_L]):
    """The constants of one (mirrored) load ratio n of the two-spring fixed-guided model: gamma and
    K_theta from the fits, the spring of each half k = 2 gamma K_theta EI/l (63), eta = sqrt(1 + n^2),
    phi = atan2(1, -n)."""

    gamma: _L
    K: _L
    k: _L
    eta: _L
    phi: _L


def _fixed_guided_ratio(
    xp: _Ops[_L, _B], n_eff: _L, length: float, EI: float, fam: FitFamily, extrapolate: str
) -> _FixedGuidedRatio[_L]:
    gamma, _, K = fam.model_parameters(n_eff, extrapolate)
    return _FixedGuidedRatio(
        gamma, K, 2.0 * gamma * K * EI / length, xp.sqrt(1.0 + n_eff * n_eff), xp.atan2(1.0, -n_eff)
    )


def _fixed_guided_level(
    xp: _Ops[_L, _B], Pabs: _L, sign: _L, c: _FixedGuidedRatio[_L], length: float
) -> tuple[_L, _L, _L, _L, _L, _B, int]:
    """The two-spring fixed-guided model at a level (floats) or at all levels (arrays), the load mirrored
    to P >= 0 (sign restores it): F gamma l sin(phi - Theta) = 2 k Theta, a = l - gamma l (1 - cos Theta),
    b = gamma l sin Theta, theta0 = 0, M = -(k Theta + (1 - gamma) l P/2).
    Returns (a, b, theta0, Theta, M, converged, iterations)."""
    gamma, _, k, eta, phi = c
    Theta, ok, nit = xp.spring(Pabs * eta * gamma * length, phi, 2.0 * k, 0.0)
    theta0 = xp.where(True, 0.0, Theta)  # the end slope held at 0 (0.0, or zeros of the levels' shape)
    return (
        length - gamma * length * (1.0 - xp.cos(Theta)),
        sign * (gamma * length * xp.sin(Theta)),
        theta0,
        sign * Theta,
        sign * -(k * Theta + (1.0 - gamma) * length * Pabs / 2.0),
        ok,
        nit,
    )


def _fixed_guided_arrays(
    P: ArrayLike, n: ArrayLike, length: float, EI: float, fam: FitFamily, extrapolate: str, t0: float
) -> PRBMResult:
    """``fixed_guided_tip`` over many levels: the same kernel evaluated once on numpy arrays."""
    P_arr, n_arr = np.broadcast_arrays(np.asarray(P, float), np.asarray(n, float))
    sign = np.where(P_arr < 0.0, -1.0, 1.0)
    c = _fixed_guided_ratio(_ARRAYS, sign * n_arr, length, EI, fam, extrapolate)
    a, b, theta0, Theta, M, ok, nit = _fixed_guided_level(_ARRAYS, np.abs(P_arr), sign, c, length)
    ok_all = bool(np.all(ok))
    return PRBMResult(
        ok_all,
        "converged" if ok_all else "not converged",
        {
            "a": a,
            "b": b,
            "theta0": theta0,
            "Theta": Theta,
            "M": M,
            "P": np.asarray(P, float),
            "n": np.asarray(n, float),
        },
        {"gamma": c.gamma, "K_theta": c.K, "k_each": c.k, "family": fam.name},
        "fixed-guided (two springs), seed 000 eq (63), seed 004",
        time.perf_counter() - t0,
        nit,
        level_converged=ok,
    )


@checked(positive=("length", "EI"), finite=("P", "n", "M", "curvature"))
def fixed_guided_monotonic_tip(
    P: ArrayLike,
    n: ArrayLike = 0.0,
    M: ArrayLike = 0.0,
    *,
    length: float,
    EI: float,
    curvature: float = 0.0,
    family: str | FitFamily = "pauly-midha",
    extrapolate: str = "raise",
) -> PRBMResult:
    """Fixed-guided / fixed-fixed segment with monotonic curvature under end force (-nP, P) and end
    moment M (CCW): the curved fixed-pinned PRBM with kappa0 = M l/EI + l/R_i
    [bapat2015, eqs 62, 14, 17, 119].  Valid only without an inflection point (Table 2.1: P and M of the same
    rotational sense); otherwise use ``prbm.inflection``.
    """
    t0 = time.perf_counter()
    M = np.asarray(M, dtype=float)
    P = np.asarray(P, dtype=float)
    levels = [v.ravel().tolist() for v in np.broadcast_arrays(np.atleast_1d(P), np.atleast_1d(n), np.atleast_1d(M))]
    P_list, n_list = levels[0], levels[1]
    # kappa0 = M l/EI + l/R_i, through the curvature kappa0/l and back, as the per-level solve receives it
    kappa0 = [(m * length / EI + curvature * length) / length * length for m in levels[2]]
    columns, _, ok, _ = _curved_levels(P_list, n_list, kappa0, length, EI, fit_family(family), extrapolate)
    arrays = _arrays({**columns, "P": P_list, "n": n_list}, (len(P_list),))
    out: dict[str, Levels] = {**arrays, "M": np.broadcast_to(M, arrays["a"].shape).copy()}
    return PRBMResult(
        all(ok),
        "monotonic curvature, kappa0 = M l/EI",
        out,
        {"kappa0": np.array(kappa0)},
        "fixed-guided monotonic, seed 000 eq (62)",
        time.perf_counter() - t0,
        level_converged=np.array(ok, dtype=bool),
    )


@checked(positive=("flexure_length", "rigid_length", "EI"), finite=("P", "n", "curvature"))
def slfp_tip(
    P: ArrayLike, n: ArrayLike = 0.0, *, flexure_length: float, rigid_length: float, EI: float, curvature: float = 0.0
) -> PRBMResult:
    """Fixed-free segment: small-length flexural pivot (length l) then a rigid segment (length L).

    [bapat2015, eqs 71-82]: pivot at the middle of the flexure, link L + l/2 (71), k = EI/l (72),
    theta0 = Theta (73).  Straight: a = l/2 + (L + l/2) cos Theta (74), b = (L + l/2) sin Theta (75),
    k Theta = F (L + l/2) sin(phi - Theta) (76).  Curved (kappa0 = l * curvature): the pivot at the
    chord midpoint (l/(2 kappa0)) (sin kappa0, 1 - cos kappa0) (77)-(78), Theta_i from (80)-(82),
    k (Theta - Theta_i) = F (L + l/2) sin(phi - Theta) (79); theta0 = Theta - Theta_i + kappa0 (assumed).
    The load is any force (-nP, P) (no n-fit is involved, so n is unrestricted).
    """
    t0 = time.perf_counter()
    l, L = flexure_length, rigid_length
    P = np.asarray(P, dtype=float)
    # numpy's stubs type this product as Any, which would leave n typed as the argument
    n = cast(NDArray[np.float64], np.asarray(n, dtype=float) * np.ones_like(P))
    R = L + l / 2.0
    k = EI / l
    kappa0 = curvature * l
    if abs(kappa0) < 1e-12:
        px, py, Theta_i = l / 2.0, 0.0, 0.0
    else:
        px, py = l / (2 * kappa0) * math.sin(kappa0), l / (2 * kappa0) * (1 - math.cos(kappa0))
        a_i = l / kappa0 * math.sin(kappa0) + L * math.cos(kappa0)
        b_i = l / kappa0 * (1 - math.cos(kappa0)) + L * math.sin(kappa0)
        Theta_i = math.atan2(b_i - py, a_i - px)
    F = np.abs(P) * np.sqrt(1.0 + n**2)
    phi = np.arctan2(P, -n * P)
    phi = Theta_i + np.angle(np.exp(1j * (phi - Theta_i)))
    Theta, ok, nit = spring_angle(F * R, phi, k, Theta_i)
    out = _scalar_or_array(
        {
            "a": px + R * np.cos(Theta),
            "b": py + R * np.sin(Theta),
            "theta0": Theta - Theta_i + kappa0,
            "Theta": Theta,
            "P": P,
            "n": n,
        }
    )
    return PRBMResult(
        bool(np.all(ok)),
        "converged" if np.all(ok) else "not converged",
        out,
        {"k": k, "R": R, "Theta_i": Theta_i, "pivot": (px, py)},
        "small-length flexural pivot, seed 000 eqs (71)-(82)",
        time.perf_counter() - t0,
        nit,
        level_converged=np.atleast_1d(ok),
    )


@checked(positive=("flexure_length", "EI"), finite=("F", "M"))
def slfp_end_tip(F: complex, M: float, *, flexure_length: float, EI: float, xtol: float = 1e-13) -> PRBMResult:
    """Small-length flexural pivot alone, loaded at its end E by a force F (complex, Fx + i Fy) and a
    couple M (CCW): [bapat2015, eqs 71-76] with whatever the flexure carries folded into (F, M) at E.

    Pivot at the middle of the flexure (l/2, 0), link l/2 to E, spring k = EI/l (72), theta0 = Theta (73);
    equilibrium about the pivot: k Theta = M + (l/2) (F_y cos Theta - F_x sin Theta), which with M the
    moment of a force F at a rigid arm L is eq (76), k Theta = F (L + l/2) sin(phi - Theta).  Root by
    Brent in the bracket [(M - R|F|)/k, (M + R|F|)/k], R = l/2 (the right side lies between them).
    Outputs a = l/2 (1 + cos Theta), b = (l/2) sin Theta, theta0 = Theta, Theta.
    """
    t0 = time.perf_counter()
    l = flexure_length
    R, k = l / 2.0, EI / l

    def residual(theta: float) -> float:
        return k * theta - M - R * (F.imag * math.cos(theta) - F.real * math.sin(theta))

    lo, hi = (M - R * abs(F)) / k, (M + R * abs(F)) / k
    Theta = lo if lo == hi else optimize.brentq(residual, lo, hi, xtol=xtol)
    out: dict[str, Levels] = {
        "a": R * (1.0 + math.cos(Theta)),
        "b": R * math.sin(Theta),
        "theta0": Theta,
        "Theta": Theta,
    }
    return PRBMResult(
        True,
        "converged",
        out,
        {"k": k, "R": R, "Theta_i": 0.0},
        "small-length flexural pivot, end loads, seed 000 eqs (71)-(76)",
        time.perf_counter() - t0,
    )


@checked(positive=("length", "EI", "gamma", "K_theta"), finite=("F_axial", "curvature"))
def curved_pinned_pinned(
    F_axial: ArrayLike, *, length: float, EI: float, curvature: float, gamma: float = 0.85, K_theta: float = 2.65
) -> PRBMResult:
    """Initially curved pinned-pinned segment (arc of length l, curvature 1/R_i) under a force F_axial
    along its chord (positive = tension, pulling the pins apart).

    Two initially curved fixed-pinned halves of l/2 fixed at the mid-span (Edwards et al.,
    [bapat2015, §2.3.5]), each with the PRBM geometry of eqs (53)-(57), spring rho K_Theta EI/(l/2) (58)
    and equilibrium (*).  The chord force is axial in the half's frame (n infinite, outside every
    n-fit), so constant gamma, K_Theta are used.  Outputs: chord length, Theta of each half.
    """
    t0 = time.perf_counter()
    F_axial = np.asarray(F_axial, dtype=float)
    h = length / 2.0
    kappa0 = curvature * h
    if abs(kappa0) < 1e-12:
        raise ValueError("a straight pinned-pinned segment carries a chord force axially; nothing bends")
    a_i = h / kappa0 * math.sin(kappa0)
    b_i = h / kappa0 * (1 - math.cos(kappa0))
    Theta_i = math.atan2(b_i, a_i - h * (1 - gamma))
    rho = math.hypot(a_i / h - (1 - gamma), b_i / h)
    k = rho * K_theta * EI / h
    # In the half's frame the tangent at mid-span is along +x and, by the symmetry of the arc, parallel
    # to the full chord: the force is along +x (tension) or -x (compression), and the chord is 2 a.
    phi = np.where(F_axial >= 0, 0.0, math.pi)
    phi = Theta_i + np.angle(np.exp(1j * (phi - Theta_i)))
    Theta, ok, nit = spring_angle(np.abs(F_axial) * rho * h, phi, k, Theta_i)
    a = h - gamma * h + rho * h * np.cos(Theta)
    chord = 2.0 * a  # the half's end point projected on the chord (the mid-span tangent)
    out = _scalar_or_array({"chord": chord, "Theta": Theta, "F": F_axial})
    return PRBMResult(
        bool(np.all(ok)),
        "converged" if np.all(ok) else "not converged",
        out,
        {"gamma": gamma, "K_theta": K_theta, "rho": rho, "k_half": k, "Theta_i": Theta_i, "chord0": 2 * a_i},
        "curved pinned-pinned, seed 000 section 2.3.5",
        time.perf_counter() - t0,
        nit,
        level_converged=np.atleast_1d(ok),
    )
