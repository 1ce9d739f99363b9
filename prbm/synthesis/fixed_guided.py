"""Two-position synthesis of a fixed-guided segment with one inflection point [bapat2015, §3.8].

The chapter-3 PRBM ([bapat2015, eqs 83-104], identical to 131-152) splits the beam at its inflection point
into two fixed-pinned segments of lengths l1, l2 = l - l1 with the Pauly-Midha fits gamma_i, c_theta_i,
K_Theta_i at load ratios n1 = n and n2 = -1/tan(phi2) (``prbm.fits.PAULY_MIDHA``, eqs 41-43).
With the beam-frame end load (-nP, P) (n > 0 compressive), F = P sqrt(1 + n^2), phi1 = atan2(1, -n),
phi2 = phi1 - theta0, theta20 = theta10 - theta0 and Theta_i = theta_i0 / c_theta_i:

    (F l1^2 / EI) sin(phi1 - Theta1) - K1 Theta1 = 0                                     (95)
    (F l2^2 / EI) sin(phi2 - Theta2) - K2 Theta2 = 0                                     (96)
    M = [nP cos th0 - P sin th0] g2 l2 sin Theta2 + [P cos th0 + nP sin th0][(1-g2) l2 + g2 l2 cos Theta2]   (99)
    b = g1 l1 sin Theta1 + g2 l2 sin(Theta2 + th0) + (1 - g2) l2 sin th0                 (108)
    l - a = l - [(1-g1) l1 + g1 l1 cos Theta1 + g2 l2 cos(Theta2 + th0) + (1-g2) l2 cos th0]   (109)

Specified (section 3.8): E, P, n, theta0 and the end displacements; unknown: l, I, M, l1, theta10.
M is explicit in (99), so four residuals (95), (96), (108), (109) in (l, I, l1, theta10) are solved by
``scipy.optimize.least_squares`` from a grid of starts.  The dissertation's end displacements dX', dY' are in a
frame rotated by the beam orientation alpha; the transverse deflection and axial shortening are
b = dX' sin(alpha) + dY' cos(alpha) and delta = dX' cos(alpha) - dY' sin(alpha) (for alpha = 45 deg:
b = (dX' + dY')/sqrt 2, delta = (dX' - dY')/sqrt 2; notes/seed-ch2-4.md section 5.9).
The l-I pair is ill-conditioned (a family of nearly equivalent designs): the result reports the
residual and the spread of the roots found.

Angles are in degrees here, as in the dissertation's synthesis tables (chapters 3, 5, 6); the PRBM library they feed works in radians.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TypeAlias

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from prbm import inflection as prbm_inflection
from prbm.fits import PAULY_MIDHA
from prbm.synthesis.dyads import DEG, SynthesisError

#: one design: (l, I, M, l1, theta10, the state of ``inflection_state``)
TwoPositionRoot: TypeAlias = tuple[float, float, float, float, float, dict[str, float]]


def pauly_midha(n: float) -> tuple[float, float, float]:
    """(gamma, c_theta, K_Theta) at load ratio n, [bapat2015, eqs 41-43]."""
    return PAULY_MIDHA.parameters(n, extrapolate="allow")


def inflection_state(
    *, E: float, I: float, l: float, l1: float, theta10: float, P: float, n: float, theta0: float
) -> dict[str, float]:
    """Every quantity of the chapter-3 PRBM for a trial (l, I, l1, theta10); angles in radians.
    The equations are ``prbm.inflection.inflection_state`` (eqs 83-104); this names them for the
    synthesis residuals (floats, the end force (-nP, P) from P and n)."""
    state = prbm_inflection.inflection_state(
        prbm_inflection.InflectionBeam(l, E * I), math.hypot(P, n * P), math.atan2(P, -n * P), theta0, l1, theta10
    )
    names = {
        "F": "F",
        "phi1": "phi1",
        "phi2": "phi2",
        "n2": "n2",
        "gamma1": "gamma1",
        "gamma2": "gamma2",
        "c1": "c_theta1",
        "c2": "c_theta2",
        "K1": "K_theta1",
        "K2": "K_theta2",
        "l2": "l2",
        "Theta1": "Theta1",
        "Theta2": "Theta2",
        "r95": "r95",
        "r96": "r96",
        "M": "M",
        "b": "b",
        "a": "a",
    }
    return {mine: float(state[theirs]) for mine, theirs in names.items()}


def solve_two_position(
    *, E: float, P: float, n: float, theta0_deg: float, b: float, delta: float, guess: Sequence[float] | None = None
) -> list[TwoPositionRoot]:
    """(l, I, M, l1, theta10, state, roots) meeting b and delta = l - a; ``SynthesisError`` if none."""
    theta0 = theta0_deg * DEG
    if b == 0:
        raise SynthesisError("zero transverse deflection: the fixed-guided segment is not deflected")

    def residual(x: NDArray[np.float64]) -> list[float]:
        l, logI, s, theta10 = x
        st = inflection_state(E=E, I=math.exp(logI), l=l, l1=s * l, theta10=theta10, P=P, n=n, theta0=theta0)
        return [st["r95"], st["r96"], (st["b"] - b) / abs(b), (l - st["a"] - delta) / abs(b)]

    # a cantilever-like first guess: l from b ~ P l^3 / (12 EI) with a moderate slenderness
    starts: list[list[float]] = []
    lengths = [guess[0]] if guess else list(np.geomspace(abs(b) * 3, abs(b) * 60, 8))
    for l in lengths:
        I0 = guess[1] if guess else abs(P) * l**3 / (12 * E * abs(b))
        for s in (0.3, 0.5, 0.7):
            starts.append([l, math.log(I0), s, math.copysign(0.1, b)])
    roots: list[TwoPositionRoot] = []
    for x0 in starts:
        try:
            res = least_squares(
                residual,
                x0,
                bounds=([1e-9, -80, 1e-3, -1.5], [np.inf, 10, 1 - 1e-3, 1.5]),
                xtol=1e-15,
                ftol=1e-15,
                gtol=1e-15,
                max_nfev=4000,
            )
        except (ValueError, ZeroDivisionError, OverflowError):
            continue
        if res.success and max(abs(v) for v in res.fun) < 1e-9:
            l, logI, s, theta10 = res.x
            st = inflection_state(E=E, I=math.exp(logI), l=l, l1=s * l, theta10=theta10, P=P, n=n, theta0=theta0)
            if -4 < n <= 10 and -4 < st["n2"] <= 10 and st["Theta1"] > 0 and st["Theta2"] > 0:
                roots.append((l, math.exp(logI), st["M"], s * l, theta10, st))
    if not roots:
        raise SynthesisError(
            "no fixed-guided segment with one inflection point meets these end displacements "
            "under the specified load (no valid root of eqs 95, 96, 108, 109)"
        )
    roots.sort(key=lambda r: r[0])
    return roots
