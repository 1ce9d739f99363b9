"""Fixed-pinned PRBM with the Theta-dependent stiffness coefficient of Midha et al. [bapat2015, eqs 51, 52].

The initially straight fixed-pinned segment under the end force F (cos phi, sin phi), F = P sqrt(1+n^2),
phi = atan2(1, -n) (n > 0 compressive, [bapat2015, eq 43] where-clause), is the Pauly-Midha PRBM of
eqs (41)-(50) with the constant K_Theta(n) of eq (43) replaced by

    K_Theta(n, Theta) = p(n, Theta) / Theta                                        (51) / (52)

with p a cubic polynomial in (n, Theta) and Theta in radians (in degrees the printed coefficients give
nonsense).  The torque balance (46)-(47), alpha_t^2 = K_Theta Theta with alpha_t^2 = F l^2 sin(phi -
Theta)/EI, therefore reads

    (F l^2 / EI) sin(phi - Theta) = p(n, Theta),

solved for Theta on (0, phi) by bracketing; then a = l - gamma l (1 - cos Theta) (48), b = gamma l
sin Theta (49), theta0 = c_theta Theta (44), with gamma (41) and c_theta (42) of Pauly-Midha.

Ranges (as printed): both (51) and (52) are labelled "for 0 <= n <= 10, 0 < Theta <= 65 deg".  The
two fits differ strongly at large n (eq 52 gives K_Theta = 5-6.4 at n = 10, where every other fit
gives about 2.5), so the printed range of (52) is probably a transcription slip (notes seed-ch2-4
section 4.1); this module evaluates each inside its printed range only and raises ``FitRangeError``
outside it.  ``fit = "52-tension"`` evaluates eq (52) for -4 <= n <= 0 instead (our reading, measured
against the elastica, see ``EQ52_TENSION``).  p(n, 0) is not zero (0.004233 - 0.012972 n + ... in eq 51), so the fit is not meant for
vanishing loads: a solution below ``THETA_MIN`` is refused as outside the fit as well.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from prbm.fits import PAULY_MIDHA, FitRangeError
from prbm.result import PRBMResult

THETA_MAX = math.radians(65.0)  # printed upper end of both fits
THETA_MIN = math.radians(1.0)  # below this the fit's constant term dominates (see docstring)


@dataclass(frozen=True)
class ThetaStiffnessFit:
    """K_Theta(n, Theta) = p(n, Theta)/Theta with p = sum c_ij n^i Theta^j (Theta in radians)."""

    name: str
    source: str
    n_range: tuple[float, float]
    coefficients: dict[tuple[int, int], float]  # (power of n, power of Theta) -> coefficient

    def torque_polynomial(self, n: float, Theta: float) -> float:
        """p(n, Theta) = K_Theta Theta, the non-dimensional spring torque alpha_t^2."""
        return self.torque_at_ratio(n)(Theta)

    def torque_at_ratio(self, n: float) -> Callable[[float], float]:
        """p(n, .) at one load ratio n (a root search in Theta evaluates it many times): each term's
        c n^i worked out once, then the sum of c n^i Theta^j term by term, in the coefficients' order."""
        terms = [(c * n**i, j) for (i, j), c in self.coefficients.items()]

        def p(Theta: float) -> float:
            total = 0.0
            for cn, j in terms:
                total += cn * Theta**j
            return total

        return p

    def __call__(self, n: float, Theta: float) -> float:
        """K_Theta at load ratio n and PRB angle Theta (rad), inside the printed ranges only."""
        self.check(n, Theta)
        return self.torque_polynomial(n, Theta) / Theta

    def check(self, n: float, Theta: float) -> None:
        lo, hi = self.n_range
        if not lo <= n <= hi:
            raise FitRangeError(f"{self.name}: load ratio n = {n:.6g} outside {lo} <= n <= {hi} ({self.source})")
        if not THETA_MIN <= Theta <= THETA_MAX:
            raise FitRangeError(
                f"{self.name}: PRB angle {math.degrees(Theta):.4g} deg outside "
                f"{math.degrees(THETA_MIN):.0f}-65 deg ({self.source})"
            )


# [bapat2015, eq 51]: 0.004233 - 0.012972n + 2.567095T + 0.003993n^2 - 0.037173T^2 - 0.000297n^3
#                   + 0.117997T^3 - 0.034678nT + 0.003467n^2T - 0.009474nT^2
EQ51 = ThetaStiffnessFit(
    "K_Theta(n, Theta) eq (51)",
    "seed 000 section 2.3.1 eq (51), Midha et al. [81]",
    (0.0, 10.0),
    {
        (0, 0): 0.004233,
        (1, 0): -0.012972,
        (0, 1): 2.567095,
        (2, 0): 0.003993,
        (0, 2): -0.037173,
        (3, 0): -0.000297,
        (0, 3): 0.117997,
        (1, 1): -0.034678,
        (2, 1): 0.003467,
        (1, 2): -0.009474,
    },
)
# [bapat2015, eq 52]: 0.000651 - 0.008244n + 2.544577T - 0.004764n^2 + 0.071215T^2 - 0.000104n^3
#                   + 0.079696T^3 + 0.069274nT + 0.061507n^2T - 0.347588nT^2
EQ52 = ThetaStiffnessFit(
    "K_Theta(n, Theta) eq (52)",
    "seed 000 section 2.3.1 eq (52), Midha et al. [81]",
    (0.0, 10.0),
    {
        (0, 0): 0.000651,
        (1, 0): -0.008244,
        (0, 1): 2.544577,
        (2, 0): -0.004764,
        (0, 2): 0.071215,
        (3, 0): -0.000104,
        (0, 3): 0.079696,
        (1, 1): 0.069274,
        (2, 1): 0.061507,
        (1, 2): -0.347588,
    },
)
# eq (52) read as the tension fit (-4 <= n <= 0): our reading, not printed.  Against the exact elastica
# it places the tip within 0.1-0.2 % of l for n = -0.5 ... -2, Theta up to 60 deg, where the printed
# range (n >= 0) gives errors up to 30 % of l at n = 5 (tests/test_prbm_theta_dependent.py); the lower
# end -4 is the Pauly-Midha fits' (eq 41), assumed.
EQ52_TENSION = ThetaStiffnessFit(
    "K_Theta(n, Theta) eq (52) read for tension",
    "seed 000 eq (52), range read as -4 <= n <= 0 (printed: 0 <= n <= 10)",
    (-4.0, 0.0),
    EQ52.coefficients,
)
THETA_FITS = {"51": EQ51, "52": EQ52, "52-tension": EQ52_TENSION}


def theta_dependent_tip(P: float, n: float = 0.0, *, length: float, EI: float, fit: str = "51") -> PRBMResult:
    """Tip of the fixed-pinned segment under the end force (-nP, P) with K_Theta(n, Theta) of eq (51)
    or (52) (``fit``); gamma and c_theta from Pauly-Midha eqs (41), (42).  P > 0 (the mirror image
    gives P < 0).  Outputs a, b, theta0 (rad), Theta (rad), K_theta.  Raises FitRangeError when n or
    the solution's Theta lies outside the fit's printed range."""
    t0 = time.perf_counter()
    if not (length > 0 and EI > 0 and math.isfinite(P) and math.isfinite(n)):
        raise ValueError(
            f"theta_dependent_tip: need length > 0, EI > 0 and finite P, n; got length={length}, EI={EI}, P={P}, n={n}"
        )
    if fit not in THETA_FITS:
        raise ValueError(f"theta_dependent_tip: fit must be one of {sorted(THETA_FITS)}, got {fit!r}")
    kfit = THETA_FITS[fit]
    sign = -1.0 if P < 0 else 1.0
    Pabs, n = abs(P), sign * n  # mirror image about x: the force (-nP, P) becomes (-(-n)|P|, |P|)
    kfit.check(n, THETA_MAX)  # the load ratio first, before any solve
    gamma, c_theta, _ = PAULY_MIDHA.parameters(n)
    F = Pabs * math.sqrt(1.0 + n * n)
    phi = math.atan2(1.0, -n)
    alpha2 = F * length**2 / EI
    torque = kfit.torque_at_ratio(n)

    def residual(T: float) -> float:
        return alpha2 * math.sin(phi - T) - torque(T)

    hi = min(phi, THETA_MAX * 1.5)
    if residual(1e-9) <= 0.0:
        raise FitRangeError(
            f"{kfit.name}: load too small (alpha^2 = {alpha2:.4g}) for the fit's constant term; no PRB angle above 0"
        )
    if residual(hi) > 0.0:
        raise FitRangeError(f"{kfit.name}: no PRB angle below {math.degrees(hi):.1f} deg balances the load")
    Theta, info = brentq(residual, 1e-9, hi, xtol=1e-14, full_output=True)
    kfit.check(n, Theta)
    out = {
        "a": length - gamma * length * (1.0 - math.cos(Theta)),
        "b": sign * gamma * length * math.sin(Theta),
        "theta0": sign * c_theta * Theta,
        "Theta": sign * Theta,
        "P": P,
        "n": sign * n,
        "F": F,
        "K_theta": torque(Theta) / Theta,
    }
    K = out["K_theta"]
    return PRBMResult(
        bool(info.converged),
        "converged" if info.converged else "brentq did not converge",
        {k: np.float64(v) for k, v in out.items()},
        {"gamma": gamma, "c_theta": c_theta, "K_theta": K, "k": gamma * K * EI / length, "fit": kfit.name},
        f"fixed-pinned with {kfit.name}, seed 000 eqs (41), (42), (44)-(49)",
        time.perf_counter() - t0,
        info.iterations,
        np.array([bool(info.converged)]),
    )
