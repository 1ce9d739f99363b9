"""Fixed-guided compliant beam with one inflection point: the chapter-3 PRBM of [bapat2015].

The inflection point P_i carries no moment, so it is an instantaneous pin splitting the beam into
segment 1 (clamp O to P_i, length l1, frame O-X-Y) and segment 2 (guided end E back to P_i, length
l2, frame E-x-y), each a fixed-pinned PRBM with the Pauly-Midha fits [bapat2015, eqs 83-104]:

  gamma_i, c_theta_i, K_theta_i = fits(n_i)                                   (83)-(92), (41)-(43)
  n_i = -1/tan(phi_i)                                                          (93), (94)
  (F l1^2/EI) sin(phi1 - theta10/c1) - K1 theta10/c1 = 0                        (95)
  (F l2^2/EI) sin(phi2 - theta20/c2) - K2 theta20/c2 = 0                        (96)
  nP + F cos(phi2 + theta0) = 0,   P - F sin(phi2 + theta0) = 0                (97), (98)
  M - [nP cos th0 - P sin th0] g2 l2 sin(Th2) - [P cos th0 + nP sin th0][(1-g2) l2 + g2 l2 cos Th2] = 0   (99)
  l1 + l2 = l (100);  theta10 = theta20 + theta0 (101);  phi1 = phi2 + theta0 (102)
  b = g1 l1 sin Th1 + g2 l2 sin(Th2 + th0) + (1-g2) l2 sin th0                  (103)
  a = (1-g1) l1 + g1 l1 cos Th1 + g2 l2 cos(Th2 + th0) + (1-g2) l2 cos th0      (104)

with Th_i = theta_i0 / c_theta_i.  Sign conventions (fixed by reproducing Tables 3.2-3.6, see
notes seed-ch2-4 section 0): the end force is (-nP, P) (nP > 0 compressive), M > 0 is the moment
*opposing* P (clockwise for P > 0), theta0 CCW.  (97), (98), (102) give n1 = n and
phi1 = atan2(P, -nP), F = sqrt(P^2 + (nP)^2).  No correction to eqs (83)-(104) was needed.

The 18 equations are reduced to 2 or 3 residuals per problem, F being explicit from (95) whenever
the load is unknown:

==========================  ==========================  ===================  ====================
problem                     given                       unknowns             residuals
==========================  ==========================  ===================  ====================
``solve_loads`` (T 3.2)      P, nP, M                    theta0, l1, theta10  (95), (96), (99)
``solve_displacements``      a, b, theta0 (T 3.3)        phi1, l1, theta10    (96), (103), (104)
  (case 1)
  (case 2a/2b)               b, theta0, n (T 3.4, 3.5)   l1, theta10          (96), (103)
  (case 2c)                  b, theta0, l1 (T 3.6)       phi1, theta10        (96), (103)
==========================  ==========================  ===================  ====================

Each problem is solved by MINPACK's hybrid method from the ``starts`` (default 20) grid points of
smallest residual (the grid residual is evaluated vectorised); every distinct root is kept.  A root is valid when 0 < l1 < l, Theta1 > 0, Theta2 > 0, 0 < phi2 < pi,
|theta0| < 90 deg and n, n2 lie in the fits' range -4 < n <= 10 (outside it the fits are only
extrapolated during the iteration, and such roots are reported as rejected, never as answers).
Roots with 0 < phi2 < pi come first (there the fits' n2 = -1/tan(phi2) describes a segment-2 load
with positive transverse component, as the fits assume; other roots are flagged in their status),
then by the PRBM strain energy (1/2) sum k_i Theta_i^2, k_i = g_i K_i EI/l_i (minimum total
potential energy, [bapat2015, ch. 8]), lowest first; ``prefer=(key, target)`` orders by closeness
of ``key`` to ``target`` instead.  Example: Table 3.3 Ex. 3 has two valid roots, the printed one
(nP = -35.635, U = 47.15 in-lb) and nP = 8.566, P = 3.328, M = 60.249, l1 = 7.232 (phi2 = 203.8 deg,
U = 44.42 in-lb); the ordering reports the printed one first.
Displacement problems search P > 0 (phi1 in (0, pi)), as in every table of the dissertation; for P < 0
mirror the boundary conditions (b, theta0 -> -b, -theta0).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import functools
import math
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Generic, Literal, TypeAlias, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import root

from prbm.fits import PAULY_MIDHA, FitFamily, PiecewiseFit, fit_family
from prbm.result import Levels, PRBMResult

__all__ = ["InflectionBeam", "inflection_state", "solve_loads", "solve_displacements"]

DEG = math.pi / 180.0

#: a variable of eqs (83)-(104) at one point (a float) or at the columns of a grid of points (an array)
Value: TypeAlias = float | NDArray[np.float64]
#: the unknowns of a problem at one point (MINPACK's, as floats) or at a grid of points (one row an unknown)
Point: TypeAlias = Sequence[float] | NDArray[np.float64]
#: the opposing end moment M as a function of the end angle theta0 (rad), at one or many theta0
Moment: TypeAlias = Callable[[Value], Value]
#: the ordering of valid roots: "energy" (lowest first), (key, target) (closest first), or None (as found)
Prefer: TypeAlias = Literal["energy"] | tuple[str, float] | None


class InflectionBeam:
    """The beam: length l, bending stiffness EI, fit family (default Pauly-Midha, as in chapter 3)."""

    def __init__(self, length: float, EI: float, family: str | FitFamily = PAULY_MIDHA) -> None:
        self.length = float(length)
        self.EI = float(EI)
        self.family = fit_family(family)
        self.fits = _plain_parameters(self.family)  # (gamma, c_theta, K_theta) at one float n


def inflection_state(
    beam: InflectionBeam, F: ArrayLike, phi1: ArrayLike, theta0: ArrayLike, l1: ArrayLike, theta10: ArrayLike
) -> dict[str, NDArray[np.float64]]:
    """Every variable of eqs (83)-(104) from F, phi1, theta0, l1, theta10 (vectorised).

    Returns the residuals r95, r96 (dimensionless) and the outputs M (eq 99, opposing-positive),
    a, b (eqs 103, 104), P, nP, n, n2, gammas, c's, K's, Theta1, Theta2, l2, U (spring energy).
    """
    fam, l, EI = beam.family, beam.length, beam.EI
    F, phi1, theta0, l1, theta10 = np.broadcast_arrays(*(np.asarray(v, float) for v in (F, phi1, theta0, l1, theta10)))
    with np.errstate(divide="ignore", invalid="ignore"):
        n = -np.cos(phi1) / np.sin(phi1)
        phi2 = phi1 - theta0
        n2 = -np.cos(phi2) / np.sin(phi2)
    g1, c1, K1 = fam.parameters(np.nan_to_num(n, nan=0.0, posinf=1e3, neginf=-1e3), "allow")
    g2, c2, K2 = fam.parameters(np.nan_to_num(n2, nan=0.0, posinf=1e3, neginf=-1e3), "allow")
    l2 = l - l1
    theta20 = theta10 - theta0
    Th1 = theta10 / c1
    Th2 = theta20 / c2
    P = F * np.sin(phi1)
    nP = -F * np.cos(phi1)
    r95 = F * l1**2 / EI * np.sin(phi1 - Th1) - K1 * Th1
    r96 = F * l2**2 / EI * np.sin(phi2 - Th2) - K2 * Th2
    ct, st = np.cos(theta0), np.sin(theta0)
    M = (nP * ct - P * st) * g2 * l2 * np.sin(Th2) + (P * ct + nP * st) * ((1 - g2) * l2 + g2 * l2 * np.cos(Th2))
    b = g1 * l1 * np.sin(Th1) + g2 * l2 * np.sin(Th2 + theta0) + (1 - g2) * l2 * st
    a = (1 - g1) * l1 + g1 * l1 * np.cos(Th1) + g2 * l2 * np.cos(Th2 + theta0) + (1 - g2) * l2 * ct
    with np.errstate(divide="ignore", invalid="ignore"):
        U = 0.5 * (g1 * K1 * EI / l1 * Th1**2 + g2 * K2 * EI / l2 * Th2**2)
    return {
        "F": F,
        "phi1": phi1,
        "phi2": phi2,
        "theta0": theta0,
        "l1": l1,
        "l2": l2,
        "theta10": theta10,
        "theta20": theta20,
        "Theta1": Th1,
        "Theta2": Th2,
        "n": n,
        "n2": n2,
        "gamma1": g1,
        "gamma2": g2,
        "c_theta1": c1,
        "c_theta2": c2,
        "K_theta1": K1,
        "K_theta2": K2,
        "P": P,
        "nP": nP,
        "M": M,
        "a": a,
        "b": b,
        "r95": r95,
        "r96": r96,
        "U": U,
    }


def _force_from_95(beam: InflectionBeam, phi1: Value, l1: Value, theta10: Value) -> Value:
    """F explicit from eq (95) (with c1, K1 at n = n(phi1))."""
    with np.errstate(divide="ignore", invalid="ignore"):
        n = -np.cos(phi1) / np.sin(phi1)
    _, c1, K1 = beam.family.parameters(np.nan_to_num(n, nan=0.0, posinf=1e3, neginf=-1e3), "allow")
    Th1 = theta10 / c1
    with np.errstate(divide="ignore", invalid="ignore"):
        F: Value = K1 * Th1 * beam.EI / (l1**2 * np.sin(phi1 - Th1))
        return F


def _ratio(cos_phi: float, sin_phi: float) -> float:
    """n = -cos(phi)/sin(phi) (eqs 93, 94) in plain floats, infinite or NaN where numpy's division is."""
    if sin_phi != 0.0 or math.isnan(sin_phi):
        return -cos_phi / sin_phi
    if cos_phi == 0.0 or math.isnan(cos_phi):
        return math.nan
    return math.copysign(math.inf, -cos_phi) * math.copysign(1.0, sin_phi)


def _fit_ratio(n: float) -> float:
    """The load ratio the fits are evaluated at (as ``np.nan_to_num(n, nan=0, posinf=1e3, neginf=-1e3)``)."""
    if math.isnan(n):
        return 0.0
    return math.copysign(1e3, n) if math.isinf(n) else n


def _horner(fit: PiecewiseFit) -> Callable[[float], float]:
    """One fit at one float, as ``PiecewiseFit`` evaluates it (branch by the printed inequalities, the
    nearest branch outside them, Horner's rule; the same arithmetic), without its per-call checks."""
    uppers = tuple(br.upper for br in fit.branches[:-1])
    coefficients = tuple(tuple(reversed(br.coefficients)) for br in fit.branches)
    last = coefficients[-1]

    def value(x: float) -> float:
        chosen = last
        for upper, cs in zip(uppers, coefficients):
            if x <= upper:
                chosen = cs
                break
        v = 0.0
        for c in chosen:
            v = v * x + c
        return v

    return value


_PLAIN_FITS: dict[int, tuple[FitFamily, Callable[[float], tuple[float, float, float]]]] = {}


def _plain_parameters(family: FitFamily) -> Callable[[float], tuple[float, float, float]]:
    """(gamma, c_theta, K_theta) at one float n, extrapolating (``family.parameters(n, 'allow')``).

    Memoised per n: a case-2 root search holds n fixed, and F from eq (95) and the state at the same
    point evaluate the fits at the same n, so most calls repeat an n already seen."""
    known = _PLAIN_FITS.get(id(family))
    if known is not None and known[0] is family:
        return known[1]
    gamma, K = _horner(family.gamma), _horner(family.K_theta)
    c: Callable[[float], float] = _horner(family.c_theta) if family.c_theta is not None else (lambda x: math.nan)

    @functools.lru_cache(maxsize=1024)
    def parameters(n: float) -> tuple[float, float, float]:
        return gamma(n), c(n), K(n)

    _PLAIN_FITS[id(family)] = (family, parameters)
    return parameters


def _point_force(beam: InflectionBeam, phi1: float, l1: float, theta10: float) -> float:
    """``_force_from_95`` at one point in plain floats (the root finders' inner loop)."""
    try:
        _, c1, K1 = beam.fits(_fit_ratio(_ratio(math.cos(phi1), math.sin(phi1))))
        Th1 = theta10 / c1
        return K1 * Th1 * beam.EI / (l1 * l1 * math.sin(phi1 - Th1))
    except (ValueError, ZeroDivisionError, OverflowError):  # numpy's inf/NaN arithmetic where math raises
        with np.errstate(all="ignore"):
            return float(_force_from_95(beam, phi1, l1, theta10))


def _point_state(
    beam: InflectionBeam, F: float, phi1: float, theta0: float, l1: float, theta10: float
) -> dict[str, float]:
    """``inflection_state`` at one point in plain floats: the same equations (95)-(104), the same keys.

    The root finders evaluate one point at a time, where numpy's per-call overhead is most of the cost;
    where ``math`` raises (an infinite angle, a zero length) the numpy state is returned instead."""
    try:
        return _point_equations(beam, F, phi1, theta0, l1, theta10)
    except (ValueError, ZeroDivisionError, OverflowError):
        return _numpy_point(beam, None, F, phi1, theta0, l1, theta10)


def _numpy_point(
    beam: InflectionBeam, keys: tuple[str, ...] | None, F: float, phi1: float, theta0: float, l1: float, theta10: float
) -> dict[str, float]:
    """``keys`` (None: all) of ``inflection_state`` at one point as floats, numpy's inf/NaN arithmetic
    where the plain-float kernels' ``math`` raises."""
    with np.errstate(all="ignore"):
        s = inflection_state(beam, F, phi1, theta0, l1, theta10)
    return {k: float(s[k]) for k in (s if keys is None else keys)}


def _point_ends(
    beam: InflectionBeam, F: float, phi1: float, theta0: float, l1: float, theta10: float
) -> dict[str, float]:
    """Only r96, a and b of ``_point_state`` (what the displacement problems' residuals read), the same
    floats: the root finders' inner loop, without the other 23 variables and their dictionary."""
    try:
        core = _point_core(beam, F, phi1, theta0, l1, theta10)
        return {"r96": core[-3], "a": core[-2], "b": core[-1]}
    except (ValueError, ZeroDivisionError, OverflowError):
        return _numpy_point(beam, ("r96", "a", "b"), F, phi1, theta0, l1, theta10)


def _point_core(
    beam: InflectionBeam, F: float, phi1: float, theta0: float, l1: float, theta10: float
) -> tuple[float, ...]:
    """The variables of eqs (95)-(104) in plain floats up to r96 (96), a (103) and b (104), in the order
    ``_point_equations`` unpacks them."""
    l, EI = beam.length, beam.EI
    sin1, cos1 = math.sin(phi1), math.cos(phi1)
    phi2 = phi1 - theta0
    n, n2 = _ratio(cos1, sin1), _ratio(math.cos(phi2), math.sin(phi2))
    g1, c1, K1 = beam.fits(_fit_ratio(n))
    g2, c2, K2 = beam.fits(_fit_ratio(n2))
    l2 = l - l1
    theta20 = theta10 - theta0
    Th1, Th2 = theta10 / c1, theta20 / c2
    r96 = F * (l2 * l2) / EI * math.sin(phi2 - Th2) - K2 * Th2
    ct, st = math.cos(theta0), math.sin(theta0)
    b = g1 * l1 * math.sin(Th1) + g2 * l2 * math.sin(Th2 + theta0) + (1 - g2) * l2 * st
    a = (1 - g1) * l1 + g1 * l1 * math.cos(Th1) + g2 * l2 * math.cos(Th2 + theta0) + (1 - g2) * l2 * ct
    return sin1, cos1, phi2, n, n2, g1, c1, K1, g2, c2, K2, l2, theta20, Th1, Th2, ct, st, r96, a, b


def _point_loads(
    beam: InflectionBeam, F: float, phi1: float, theta0: float, l1: float, theta10: float
) -> dict[str, float]:
    """Only r95, r96 and M of ``_point_state`` (what the load problem's residual reads), the same floats."""
    try:
        core = _point_core(beam, F, phi1, theta0, l1, theta10)
        _, _, r95, M = _point_end_loads(beam, F, phi1, l1, core)
        return {"r95": r95, "r96": core[-3], "M": M}
    except (ValueError, ZeroDivisionError, OverflowError):
        return _numpy_point(beam, ("r95", "r96", "M"), F, phi1, theta0, l1, theta10)


def _point_end_loads(
    beam: InflectionBeam, F: float, phi1: float, l1: float, core: tuple[float, ...]
) -> tuple[float, float, float, float]:
    """P, nP, r95 (95) and M (99) in plain floats from ``_point_core``'s variables."""
    sin1, cos1, _, _, _, _, _, K1, g2, _, _, l2, _, Th1, Th2, ct, st, _, _, _ = core
    P, nP = F * sin1, -F * cos1
    r95 = F * (l1 * l1) / beam.EI * math.sin(phi1 - Th1) - K1 * Th1
    sT2, cT2 = math.sin(Th2), math.cos(Th2)
    M = (nP * ct - P * st) * g2 * l2 * sT2 + (P * ct + nP * st) * ((1 - g2) * l2 + g2 * l2 * cT2)
    return P, nP, r95, M


def _point_equations(
    beam: InflectionBeam, F: float, phi1: float, theta0: float, l1: float, theta10: float
) -> dict[str, float]:
    core = _point_core(beam, F, phi1, theta0, l1, theta10)
    _, _, phi2, n, n2, g1, c1, K1, g2, c2, K2, l2, theta20, Th1, Th2, _, _, r96, a, b = core
    EI = beam.EI
    P, nP, r95, M = _point_end_loads(beam, F, phi1, l1, core)
    U = 0.5 * (g1 * K1 * EI / l1 * Th1 * Th1 + g2 * K2 * EI / l2 * Th2 * Th2)
    return {
        "F": F,
        "phi1": phi1,
        "phi2": phi2,
        "theta0": theta0,
        "l1": l1,
        "l2": l2,
        "theta10": theta10,
        "theta20": theta20,
        "Theta1": Th1,
        "Theta2": Th2,
        "n": n,
        "n2": n2,
        "gamma1": g1,
        "gamma2": g2,
        "c_theta1": c1,
        "c_theta2": c2,
        "K_theta1": K1,
        "K_theta2": K2,
        "P": P,
        "nP": nP,
        "M": M,
        "a": a,
        "b": b,
        "r95": r95,
        "r96": r96,
        "U": U,
    }


_V = TypeVar("_V", float, NDArray[np.float64])  # a kernel's variables: at one point, or over a grid


@dataclass(frozen=True)
class _Kernel(Generic[_V]):
    """The state of eqs (95)-(104) and F from eq (95): vectorised (numpy) or at one point (floats)."""

    state: Callable[[InflectionBeam, _V | float, _V | float, _V | float, _V | float, _V | float], Mapping[str, _V]]
    force: Callable[[InflectionBeam, _V | float, _V | float, _V | float], _V | float]


VECTOR: _Kernel[NDArray[np.float64]] = _Kernel(inflection_state, _force_from_95)
POINT: _Kernel[float] = _Kernel(_point_state, _point_force)
ENDS: _Kernel[float] = _Kernel(_point_ends, _point_force)  # r96, a and b only: the displacement problems' residuals
LOADS: _Kernel[float] = _Kernel(_point_loads, _point_force)  # r95, r96 and M only: the load problem's residual

#: a problem's residuals at a point (or a grid of points) evaluated with a kernel
Residual: TypeAlias = Callable[[Point, _Kernel[Any]], list[Value]]


def _valid(beam: InflectionBeam, s: Mapping[str, float], tol: float = 1e-8) -> tuple[bool, str]:
    l, fam = beam.length, beam.family
    checks = [
        (np.isfinite(s["F"]) and s["F"] > 0, "F <= 0"),
        (0 < s["phi1"] < math.pi, "P <= 0 (search is for P > 0; mirror the BCs for P < 0)"),
        (0 < s["l1"] < l, "l1 outside (0, l)"),
        (s["Theta1"] > 0, "Theta1 <= 0"),
        (s["Theta2"] > 0, "Theta2 <= 0"),
        (abs(s["theta0"]) < math.pi / 2, "|theta0| >= 90 deg"),
        (fam.lower < s["n"] <= fam.upper, f"n = {s['n']:.4g} outside the fits' range"),
        (fam.lower < s["n2"] <= fam.upper, f"n2 = {s['n2']:.4g} outside the fits' range"),
    ]
    for ok, why in checks:
        if not ok:
            return False, why
    if not 0 < s["phi2"] < math.pi:
        return True, "valid (phi2 outside (0, pi): the force on segment 2 has a negative transverse component)"
    return True, "valid"


@functools.lru_cache(maxsize=None)
def _start_grid(*axes: tuple[float, float, int, bool]) -> NDArray[np.float64]:
    """The multistart grid of a problem: every combination of the axes' points, each axis
    ``(first, last, count, angle)`` = np.linspace(first, last, count) (in degrees turned to radians
    when ``angle``), the first axis slowest; a constant of the problem, built once (read-only), not again
    for every solve."""
    points = [
        np.linspace(first, last, count) * DEG if angle else np.linspace(first, last, count)
        for first, last, count, angle in axes
    ]
    grid = np.stack(np.meshgrid(*points, indexing="ij"), axis=-1).reshape(-1, len(axes))
    grid.flags.writeable = False
    return grid


def _multistart(
    residual: Residual, grid: NDArray[np.float64], keep: int, xtol: float, point_kernel: _Kernel[float] = POINT
) -> tuple[list[NDArray[np.float64]], int]:
    """Solve residual(x) = 0 from the `keep` grid points of smallest residual; return distinct roots.

    ``residual(x, kernel)`` gives the residual list: with ``VECTOR`` over the grid's columns at once,
    with ``point_kernel`` (``POINT``; ``ENDS`` or ``LOADS`` where the residual reads only r96, a and b, or
    r95, r96 and M) at one point in plain floats (MINPACK's calls)."""
    with np.errstate(all="ignore"):
        norms = np.linalg.norm(np.stack(residual(grid.T, VECTOR)), axis=0)
    norms = np.where(np.isfinite(norms), norms, np.inf)
    order = np.argsort(norms)[:keep]

    def point(x: NDArray[np.float64]) -> NDArray[np.float64]:  # MINPACK's point as plain floats: numpy
        return np.array(residual(x.tolist(), point_kernel), dtype=float)  # scalar arithmetic is slower than float's

    roots: list[NDArray[np.float64]] = []
    nfev = 0
    for i in order:
        if not np.isfinite(norms[i]):
            continue
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sol = root(point, grid[i], method="hybr", options={"xtol": xtol})
        nfev += sol.nfev
        if not np.all(np.isfinite(sol.x)):
            continue
        with np.errstate(all="ignore"):
            r = point(sol.x)
        if np.all(np.isfinite(r)) and np.linalg.norm(r) < 1e-9:
            if not any(np.allclose(sol.x, x0, rtol=1e-6, atol=1e-7) for x0 in roots):
                roots.append(sol.x)
    return roots, nfev


def _package(
    beam: InflectionBeam,
    states: list[dict[str, NDArray[np.float64]]],
    problem: str,
    given: Mapping[str, object],
    t0: float,
    nfev: int,
    prefer: Prefer,
) -> PRBMResult:
    valid: list[dict[str, float | str]] = []
    rejected: list[dict[str, float | str]] = []
    seen: list[NDArray[np.float64]] = []
    for state in states:
        if state["F"] < 0:  # the same state written with (-F, phi1 + pi)
            state = inflection_state(
                beam, -state["F"], state["phi1"] + math.pi, state["theta0"], state["l1"], state["theta10"]
            )
        s = {k: float(v) for k, v in state.items()}
        s["phi1"] = math.atan2(math.sin(s["phi1"]), math.cos(s["phi1"]))
        s["phi2"] = s["phi1"] - s["theta0"]
        identity = np.array([s["P"], s["nP"], s["l1"], s["theta10"], s["theta0"]])
        if any(np.allclose(identity, k0, rtol=1e-6, atol=1e-6) for k0 in seen):
            continue
        seen.append(identity)
        ok, why = _valid(beam, s)
        (valid if ok else rejected).append({**s, "status": why})
    if prefer == "energy":
        valid.sort(key=lambda s: (s["status"] != "valid", s["U"]))
    elif prefer is not None:
        key, target = prefer
        valid.sort(key=lambda s: abs(float(s[key]) - target))
    wall = time.perf_counter() - t0
    constants: dict[str, Any] = {"family": beam.family.name, "length": beam.length, "EI": beam.EI}
    if not valid:
        reasons = "; ".join(str(r["status"]) for r in rejected[:3])
        msg = f"{problem}: no valid root found" + (f" ({len(rejected)} rejected: {reasons})" if rejected else "")
        nan = {k: np.nan for k in ("a", "b", "theta0", "P", "nP", "M", "l1", "theta10", "n", "n2")}
        return PRBMResult(
            False,
            msg,
            {k: np.asarray(v) for k, v in nan.items()},
            constants,
            "fixed-guided with one inflection point, seed 000 eqs (83)-(104)",
            wall,
            nfev,
            np.array([False]),
            roots=[[]],
            extras={"rejected": rejected, "given": given},
        )
    best = valid[0]
    msg = f"{problem}: {len(valid)} valid root(s)" + (f", {len(rejected)} rejected" if rejected else "")
    for key in ("gamma1", "gamma2", "c_theta1", "c_theta2", "K_theta1", "K_theta2"):
        constants[key] = best[key]
    outputs: dict[str, Levels] = {k: np.asarray(v) for k, v in best.items() if k != "status"}
    return PRBMResult(
        True,
        msg,
        outputs,
        constants,
        "fixed-guided with one inflection point, seed 000 eqs (83)-(104)",
        wall,
        nfev,
        np.array([True]),
        roots=[valid],
        extras={"rejected": rejected, "given": given},
    )


def _constant_moment(M: float) -> Moment:
    """The moment function of a constant M: M at every theta0 (a float, or an array of theta0's shape)."""
    return lambda theta0: M + 0.0 * np.asarray(theta0)


def solve_loads(
    beam: InflectionBeam,
    P: float,
    nP: float,
    M: float | Moment,
    *,
    prefer: Prefer = "energy",
    xtol: float = 1e-12,
    starts: int = 20,
) -> PRBMResult:
    """Load-specified problem [bapat2015, §3.5.1, Table 3.2]: P, nP, M (M opposing) -> a, b, theta0.

    Unknowns theta0, l1, theta10; residuals (95), (96), (99).  P < 0 is handled by mirroring.
    ``M`` may also be a vectorised function of the end angle theta0 (radians), e.g. the moment of
    loads carried by a rigid body on the end (``prbm.coupled_segment``); (99) then reads
    M(theta0) - M_state = 0 and the three equations are solved together.
    """
    t0 = time.perf_counter()
    moment: Moment = M if callable(M) else _constant_moment(float(M))
    if P < 0:
        mirrored: float | Moment = (lambda theta0: -moment(-np.asarray(theta0))) if callable(M) else -M
        res = solve_loads(beam, -P, nP, mirrored, prefer=prefer, xtol=xtol, starts=starts)
        for key in ("b", "theta0", "P", "M", "theta10", "theta20", "Theta1", "Theta2"):
            if key in res.outputs:
                res.outputs[key] = -res.outputs[key]
        res.message += " (mirrored, P < 0)"
        return res
    l, EI = beam.length, beam.EI
    F = math.hypot(P, nP)
    phi1 = math.atan2(P, -nP)

    def residual(x: Point, kernel: _Kernel[Any] = VECTOR) -> list[Value]:
        s = kernel.state(beam, F, phi1, x[0], x[1] * l, x[2])
        return [s["r95"], s["r96"], (moment(x[0]) - s["M"]) * l / EI]

    grid = _start_grid((-80, 80, 17, True), (0.15, 0.85, 8, False), (5, 85, 9, True))
    roots, nfev = _multistart(residual, grid, starts, xtol, LOADS)
    states = [inflection_state(beam, F, phi1, x[0], x[1] * l, x[2]) for x in roots]
    given = {"P": P, "nP": nP, "M": "a function of theta0" if callable(M) else M}
    return _package(beam, states, "load BCs", given, t0, nfev, prefer)


def _one_number(name: str, value: float) -> float:
    """``value`` as a Python float; a ValueError naming the argument when it is not one number."""
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"solve_displacements: {name} must be one number, got {value!r}") from None


def solve_displacements(
    beam: InflectionBeam,
    *,
    b: float,
    theta0: float,
    a: float | None = None,
    n: float | None = None,
    l1: float | None = None,
    prefer: Prefer = "energy",
    xtol: float = 1e-12,
    starts: int = 20,
) -> PRBMResult:
    """Displacement-specified problems of [bapat2015, §3.5.2] (theta0 in radians).

    Give b and theta0 and exactly one of: a (case 1, Table 3.3), n (cases 2a/2b, Tables 3.4/3.5;
    n = 0 is the tables' "n1 = 0"), l1 (case 2c, Table 3.6).  Returns P, nP, M (opposing), l1,
    theta10 and the unspecified end coordinate; every valid root is in ``result.roots[0]``.
    """
    t0 = time.perf_counter()
    if sum(v is not None for v in (a, n, l1)) != 1:
        raise ValueError("give exactly one of a (case 1), n (case 2a/2b) or l1 (case 2c)")
    # plain floats for the point kernels (a numpy scalar would turn every operation of theirs into numpy's)
    b, theta0 = _one_number("b", b), _one_number("theta0", theta0)
    a, n, l1 = (None if v is None else _one_number(name, v) for name, v in (("a", a), ("n", n), ("l1", l1)))
    l = beam.length
    scale = 1.0 / l

    if a is not None:
        problem = "case 1 (a, b, theta0)"

        def unpack(x: Point) -> tuple[Value, Value, Value]:
            return x[0], x[1] * l, x[2]

        def residual(x: Point, kernel: _Kernel[Any] = VECTOR) -> list[Value]:
            phi1, L1, q = unpack(x)
            s = kernel.state(beam, kernel.force(beam, phi1, L1, q), phi1, theta0, L1, q)
            return [s["r96"], (s["b"] - b) * scale, (s["a"] - a) * scale]

        grid = _start_grid((10, 170, 17, True), (0.1, 0.9, 9, False), (3, 88, 12, True))
    elif n is not None:
        problem = "case 2a/2b (b, theta0, n)"
        phi_fixed = math.atan2(1.0, -n)

        def unpack(x: Point) -> tuple[Value, Value, Value]:
            return phi_fixed, x[0] * l, x[1]

        def residual(x: Point, kernel: _Kernel[Any] = VECTOR) -> list[Value]:
            phi1, L1, q = unpack(x)
            s = kernel.state(beam, kernel.force(beam, phi1, L1, q), phi1, theta0, L1, q)
            return [s["r96"], (s["b"] - b) * scale]

        grid = _start_grid((0.05, 0.95, 19, False), (2, 88, 44, True))
    else:
        problem = "case 2c (b, theta0, l1)"
        assert l1 is not None  # exactly one of a, n, l1 is given (checked above)
        l1_fixed = l1

        def unpack(x: Point) -> tuple[Value, Value, Value]:
            return x[0], l1_fixed, x[1]

        def residual(x: Point, kernel: _Kernel[Any] = VECTOR) -> list[Value]:
            phi1, L1, q = unpack(x)
            s = kernel.state(beam, kernel.force(beam, phi1, L1, q), phi1, theta0, L1, q)
            return [s["r96"], (s["b"] - b) * scale]

        grid = _start_grid((5, 175, 35, True), (2, 88, 44, True))

    roots, nfev = _multistart(residual, grid, starts, xtol, ENDS)
    states: list[dict[str, NDArray[np.float64]]] = []
    for x in roots:
        phi1, L1, q = unpack(x)
        states.append(inflection_state(beam, _force_from_95(beam, phi1, L1, q), phi1, theta0, L1, q))
    given = {"b": b, "theta0": theta0, "a": a, "n": n, "l1": l1}
    return _package(beam, states, problem, given, t0, nfev, prefer)
