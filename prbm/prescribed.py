"""Prescribed motion: the load a PRB model needs to reach a prescribed displacement or rotation.

Lengths and forces in any consistent units; angles in radians (Theta, theta0).

Two solves, one result type (``PRBMResult``; ``LoadForMotion`` for the scalar root):

* ``fixed_guided_displaced_tip``: the two-spring fixed-guided PRBM [bapat2015, eq 63],
  [ananthasuresh_l18, 07:13-12:05] with its tip moved a transverse distance delta, in closed form.
  Pivots (1 - gamma) l/2 from each end, middle link gamma l, two springs k = 2 gamma K_Theta EI/l (63):

      b = gamma l sin Theta = delta           ->  Theta = asin(delta / (gamma l))
      a = l - gamma l (1 - cos Theta)             (the axial shortening of the middle link)
      virtual work, dW = P db - 2 k Theta dTheta = 0 with db = gamma l cos Theta dTheta:
      P = 2 k Theta / (gamma l cos Theta) = 4 K_Theta EI Theta / (l^2 cos Theta)
      M = -(k Theta + (1 - gamma) l P / 2) = -P a / 2   (the guiding moment the tip receives, CCW)

  With no axial load the fits are those of n = 0.  |delta| > gamma l has no PRB state (the middle link
  cannot reach it): ``converged`` False at that level, NaN outputs.
* ``load_for_motion``: any forward model and a load of given direction, the load magnitude s at which
  one output of the model along it reaches a prescribed value (a 1-D bracketed root, Brent's method):
  the bracket grows geometrically from ``guess`` until the response passes the target.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import brentq

from argcheck import checked
from prbm.fits import FitFamily, fit_family
from prbm.result import PRBMResult
from prbm.segments import _FLOATS, _fixed_guided_ratio


@checked(positive=("length", "EI"), finite=("delta",))
def fixed_guided_displaced_tip(
    delta: ArrayLike, *, length: float, EI: float, family: str | FitFamily = "pauly-midha"
) -> PRBMResult:
    """Two-spring fixed-guided PRBM with a prescribed transverse tip displacement ``delta`` (length units).

    Outputs over the levels (module docstring for the equations): a, b (= delta), theta0 (= 0), Theta,
    P (the transverse force needed), n (= 0), M (the guiding moment, CCW); constants gamma, K_theta,
    k_each (the fits at n = 0 of ``family``).
    """
    t0 = time.perf_counter()
    fam = fit_family(family)
    gamma, K, k = _fixed_guided_ratio(_FLOATS, 0.0, length, EI, fam, "raise")[:3]  # [bapat2015, eq 63]
    d = np.atleast_1d(np.asarray(delta, float))
    sine = d / (gamma * length)
    ok = np.abs(sine) <= 1.0
    Theta = np.where(ok, np.arcsin(np.clip(sine, -1.0, 1.0)), np.nan)
    P = np.where(ok, 2.0 * k * Theta / (gamma * length * np.cos(Theta)), np.nan)
    a = length - gamma * length * (1.0 - np.cos(Theta))
    M = -(k * Theta + (1.0 - gamma) * length * P / 2.0)
    ok_all = bool(np.all(ok))
    message = (
        "closed form"
        if ok_all
        else (f"no PRB state: |delta| > gamma l = {gamma * length:g} at level(s) {np.flatnonzero(~ok).tolist()}")
    )
    return PRBMResult(
        ok_all,
        message,
        {
            "a": a,
            "b": np.where(ok, d, np.nan),
            "theta0": np.zeros_like(d),
            "Theta": Theta,
            "M": M,
            "P": P,
            "n": np.zeros_like(d),
        },
        {"gamma": gamma, "K_theta": K, "k_each": k, "family": fam.name},
        "fixed-guided (two springs), prescribed transverse tip displacement, seed 000 eq (63), seed 004",
        time.perf_counter() - t0,
        0,
        level_converged=ok,
    )


@dataclass
class LoadForMotion:
    """The load magnitude ``x`` at which the response meets the target; ``converged``, ``message``,
    ``nfev`` (response evaluations), ``bracket`` (the magnitudes that enclosed the root)."""

    x: float
    converged: bool
    message: str
    nfev: int
    bracket: tuple[float, float] = (math.nan, math.nan)


def load_for_motion(
    response: Callable[[float], float],
    target: float,
    *,
    guess: float,
    max_expansions: int = 60,
    xtol: float = 1e-14,
    rtol: float = 1e-12,
) -> LoadForMotion:
    """The magnitude s of a load of fixed direction at which ``response(s)`` equals ``target``.

    ``response(0)`` is the unloaded value (taken as 0: the prescribed motion is measured from the unloaded
    state), and ``response`` grows with s along the load's own direction (positive work of an elastic
    structure), so the root has the sign of ``target``. ``guess`` (> 0) is the first trial magnitude, e.g. the
    linear estimate; the bracket [lo, hi] doubles from it until the response passes the target, then Brent's
    method finds the root to ``xtol`` + ``rtol`` |s|. A response that is NaN (the model has no state there)
    or never reaches the target is a failure with a message, not a value.
    """
    if target == 0.0:
        return LoadForMotion(0.0, True, "no motion: no load", 0, (0.0, 0.0))
    sign = 1.0 if target > 0 else -1.0
    nfev = 0

    def residual(s: float) -> float:
        nonlocal nfev
        nfev += 1
        return sign * (response(sign * s) - target)

    lo, hi = 0.0, abs(guess) if guess else 1.0
    f_hi = residual(hi)
    for _ in range(max_expansions):
        if not math.isfinite(f_hi):
            return LoadForMotion(math.nan, False, f"the model has no state at load {sign * hi:g}", nfev, (lo, hi))
        if f_hi >= 0.0:
            break
        lo, hi = hi, 2.0 * hi
        f_hi = residual(hi)
    else:
        return LoadForMotion(
            math.nan, False, f"the response does not reach {target:g} up to load {sign * hi:g}", nfev, (lo, hi)
        )
    if f_hi == 0.0:
        return LoadForMotion(sign * hi, True, "converged", nfev, (sign * lo, sign * hi))
    s = brentq(residual, lo, hi, xtol=xtol, rtol=rtol)
    return LoadForMotion(sign * s, True, "converged", nfev, (sign * lo, sign * hi))
