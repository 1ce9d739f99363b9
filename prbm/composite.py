"""Composite (sliding-layer) fixed-pinned beam of [bapat2015, §9.2-9.3] (Test 1), with the rope
friction and follower-load options of section 9.2.

* Bending stiffness of unbonded, freely sliding layers that share one deflected shape: each layer
  bends about its own neutral axis, EI_eq = sum E_i w_i t_i^3 / 12 (the dissertation states "no bonding
  between layers" and "negligible friction that allows sliding between layers"; the composite PRBM
  of its ref. [100] is not printed, so this combination rule is the assumption here).
* Capstan friction, [bapat2015, eq 211]: T2 = T1 exp(mu beta).  The force delivered to the beam end
  by a hanger of weight W over pulleys of total contact angle beta is W exp(-mu beta) (the rope
  slides toward the beam while the load is applied); ``capstan_factor`` returns exp(-mu beta).
  The dissertation gives mu = 0.01 and "may contain three such pulleys", not the angles.
* Follower option: the end force keeps its angle relative to the end tangent theta0 = c_theta Theta,
  so phi = phi_nominal + c_theta Theta and equilibrium (46)-(47) becomes
  (F l^2/EI) sin(phi_nominal + (c_theta - 1) Theta) = K_Theta Theta (solved by Brent's method on
  [0, (F l^2/EI + 1)/K_Theta]).  The fits are evaluated at the nominal n (an assumption; the dissertation
  gives no equation).

Finding (notes seed-ch5-9 section 8.1, re-checked here): Tables 9.1-9.3's PRBM columns are not
reproduced by any fixed-direction, follower or constant-friction variant with constant EI; the EI
back-solved from eq (47) row by row drifts with load (438 -> 462 lb in^2 for Test 1(a)).  What does
hold is that Test 1(a)'s printed PRBM points lie on the PRBM circle of gamma(0) (eq 48-50).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
import time
from typing import Iterable

import numpy as np
from numpy.typing import ArrayLike

from prbm.fits import FitFamily, fit_family
from prbm.result import PRBMResult
from prbm.segments import fixed_pinned_tip
from prbm.lazy import LazyModule

optimize = LazyModule("scipy.optimize")  # brentq: imported at its first use

__all__ = ["layered_bending_stiffness", "capstan_factor", "composite_beam_tip"]


def layered_bending_stiffness(layers: Iterable[tuple[float, float, float]]) -> float:
    """EI_eq = sum E w t^3/12 over (E, width, thickness) layers that slide freely on each other."""
    return float(sum(E * w * t**3 / 12.0 for E, w, t in layers))


def capstan_factor(mu: float, contact_angle: float) -> float:
    """exp(-mu beta): beam-end force over hanger weight across a total rope contact angle beta (rad)."""
    return math.exp(-mu * contact_angle)


def composite_beam_tip(
    force: ArrayLike,
    n: float = 0.0,
    *,
    length: float,
    layers: Iterable[tuple[float, float, float]] | None = None,
    EI: float | None = None,
    force_is: str = "transverse",
    friction_mu: float = 0.0,
    contact_angle: float = 0.0,
    follower: bool = False,
    family: str | FitFamily = "pauly-midha",
    extrapolate: str = "raise",
) -> PRBMResult:
    """Tip (a, b, theta0) of the Test-1 composite fixed-pinned beam under the 'Applied Force' levels.

    force: applied force levels; force_is = 'transverse' (the force is P) or 'resultant' (F = P eta).
    n: load ratio, end force (-nP, P) (Test 1(b) n = 0.896 compressive, 1(c) n = -0.673 tensile).
    layers: (E, width, thickness) tuples, or EI directly.  friction_mu, contact_angle: capstan
    reduction exp(-mu beta) of the delivered force.  follower: see the module docstring.
    """
    t0 = time.perf_counter()
    if EI is None:
        if layers is None:
            raise ValueError("give layers or EI")
        EI = layered_bending_stiffness(layers)
    force = np.asarray(force, dtype=float) * capstan_factor(friction_mu, contact_angle)
    eta = math.sqrt(1.0 + float(n) ** 2)
    P = force if force_is == "transverse" else force / eta
    if not follower:
        res = fixed_pinned_tip(P, n, length=length, EI=EI, family=family, extrapolate=extrapolate)
        res.constants.update(EI=EI, capstan=capstan_factor(friction_mu, contact_angle), follower=False)
        res.model = "composite fixed-pinned, seed 000 section 9.3 with eqs (41)-(49), (211)"
        return res
    fam = fit_family(family)
    # P < 0: the model mirrored about x (b, theta0, Theta change sign), fits at -n so that -nP is kept
    sign = np.where(np.asarray(P) < 0, -1.0, 1.0)
    n_eff = np.atleast_1d(float(n) * sign)
    gamma_n, c_theta_n, K_n = fam.model_parameters(n_eff, extrapolate)  # arrays of n_eff's shape
    phi = np.arctan2(1.0, -n_eff)
    beta = np.atleast_1d(np.abs(P) * eta * length**2 / EI)
    brentq = optimize.brentq
    # one root per level, in plain floats (the residual is called some ten times a level)
    Theta = np.array(
        [
            0.0
            if bb == 0
            else brentq(lambda t: bb * math.sin(ph + (c - 1) * t) - k * t, 0.0, (bb + 1.0) / k, xtol=1e-14)
            for bb, ph, c, k in zip(beta.tolist(), phi.tolist(), c_theta_n.tolist(), K_n.tolist())
        ]
    )
    ok, nit = np.ones(Theta.shape, bool), 0
    converged = bool(ok.all())
    Theta = Theta.reshape(np.shape(P)) * sign
    gamma, c_theta, K = (v.reshape(np.shape(P)) if np.ndim(P) else float(v[0]) for v in (gamma_n, c_theta_n, K_n))
    out = {
        "a": length - gamma * length * (1 - np.cos(Theta)),
        "b": gamma * length * np.sin(Theta),
        "theta0": c_theta * Theta,
        "Theta": Theta,
        "P": P,
    }
    return PRBMResult(
        converged,
        "converged" if converged else "not converged",
        {k: np.asarray(v) for k, v in out.items()},
        {
            "gamma": gamma,
            "c_theta": c_theta,
            "K_theta": K,
            "EI": EI,
            "follower": True,
            "capstan": capstan_factor(friction_mu, contact_angle),
        },
        "composite fixed-pinned with follower end force, seed 000 section 9.2",
        time.perf_counter() - t0,
        nit,
        np.atleast_1d(ok),
    )
