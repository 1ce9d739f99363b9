"""Sourced expected values for PRBM segment tests that were round trips or mirrors only.

A round trip (forward then inverse) or a mirror (P -> -P) passes with a 10 % error in K_Theta or gamma,
since both directions carry it. Here each direction is pinned to numbers from outside the code:

* notes seed-ch2-4 section 4.4: an independent evaluation of seed 000 eqs 41-47 (PRBM column),
  (n, P l^2/EI) -> (a/l, b/l, theta0 deg) printed to 4 and 2 decimals (also used by
  tests/prbm/test_prbm_segments.py for the forward direction): the inverse must return the printed load;
* seed 004 pure end moment: gamma = 0.7346, k = 1.5164 EI/L, Theta = M/k, a = l - gamma l (1 - cos Theta),
  b = gamma l sin Theta, and the exact theta0 = M l/EI.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import prbm
from prbm.theta_dependent import theta_dependent_tip

# (n, P l^2/EI, (a/l, b/l, theta0 deg)), notes seed-ch2-4 section 4.4
NOTES_4_4 = [
    (-1.0, 1.5, (0.9510, 0.2880, 23.79)),
    (0.0, 0.5, (0.9854, 0.1571, 13.17)),
    (0.0, 3.0, (0.7453, 0.6075, 56.36)),
    (1.0, 1.5, (0.7363, 0.6094, 58.31)),
    (1.0, 3.0, (0.3337, 0.8187, 97.55)),
]


@pytest.mark.parametrize("n, load, printed", NOTES_4_4)
def test_the_inverse_of_a_printed_tip_is_the_printed_load(n, load, printed):
    """(a, b) printed to 5e-5 fix Theta to about 1e-4 rad, so the load comes back within 0.5 %
    (dP/P = dTheta (cot(phi - Theta) + 1/Theta)); a 10 % error in K_Theta would return P 10 % off."""
    a, b, theta0_deg = printed
    inv = prbm.fixed_pinned_from_tip(n=n, a=a, b=b, length=1.0, EI=1.0)
    assert float(inv["P"]) == pytest.approx(load, rel=5e-3)
    inv = prbm.fixed_pinned_from_tip(n=n, theta0=math.radians(theta0_deg), length=1.0, EI=1.0)
    assert float(inv["P"]) == pytest.approx(load, rel=5e-3)


def test_a_downward_force_gives_the_printed_tip_mirrored():
    """P -> -P with n -> -n keeps the axial force -nP and mirrors the tip: notes 4.4's (n = 1, P = 1.5)
    row (0.7363, 0.6094) becomes (0.7363, -0.6094)."""
    down = prbm.fixed_pinned_tip(-1.5, -1.0, length=1.0, EI=1.0)
    assert float(down["a"]) == pytest.approx(0.7363, abs=5e-5)
    assert float(down["b"]) == pytest.approx(-0.6094, abs=5e-5)
    assert math.degrees(float(down["theta0"])) == pytest.approx(-58.31, abs=5e-3)


def test_pure_moment_tip_and_its_inverse_use_seed_004s_constants():
    length, EI = 2.0, 3.0
    M = np.array([0.5, 1.0, 2.0])
    r = prbm.pure_moment_tip(M, length=length, EI=EI)
    Theta = M / (1.5164 * EI / length)  # seed 004: k = 1.5164 EI/L
    np.testing.assert_allclose(r["a"], length - 0.7346 * length * (1 - np.cos(Theta)), rtol=1e-12)
    np.testing.assert_allclose(r["b"], 0.7346 * length * np.sin(Theta), rtol=1e-12)
    np.testing.assert_allclose(r["theta0"], M * length / EI, rtol=1e-12)  # exact end rotation
    inv = prbm.pure_moment_from_tip(length=length, EI=EI, a=r["a"], b=r["b"])
    np.testing.assert_allclose(inv["M"], M, rtol=1e-12)
    # an (a, b) built from seed 004's constants alone gives back its moment
    inv = prbm.pure_moment_from_tip(
        length=length, EI=EI, a=length - 0.7346 * length * (1 - math.cos(0.4)), b=0.7346 * length * math.sin(0.4)
    )
    assert float(inv["M"]) == pytest.approx(0.4 * 1.5164 * EI / length, rel=1e-12)


def test_theta_dependent_tip_solves_eq_51_as_printed_and_mirrors():
    """Seed 000 eq (51) as printed: K_Theta Theta = p(n, Theta) = 0.004233 - 0.012972 n + 2.567095 Theta
    + 0.003993 n^2 - 0.037173 Theta^2 - 0.000297 n^3 + 0.117997 Theta^3 - 0.034678 n Theta
    + 0.003467 n^2 Theta - 0.009474 n Theta^2, and the torque balance (46)-(47)
    (P l^2/EI) sqrt(1 + n^2) sin(phi - Theta) = p(n, Theta), phi = atan2(1, -n); then b = gamma l sin Theta
    (49) with gamma of eq (41). The mirrored load (-P, -n) gives the mirrored tip (the mirror alone would
    pass with any error in p)."""
    n, P = 0.5, 1.0
    up = theta_dependent_tip(P, n, length=1.0, EI=1.0)
    T = float(up["Theta"])
    p = (
        0.004233
        - 0.012972 * n
        + 2.567095 * T
        + 0.003993 * n**2
        - 0.037173 * T**2
        - 0.000297 * n**3
        + 0.117997 * T**3
        - 0.034678 * n * T
        + 0.003467 * n**2 * T
        - 0.009474 * n * T**2
    )
    assert P * math.sqrt(1 + n * n) * math.sin(math.atan2(1.0, -n) - T) == pytest.approx(p, rel=1e-9)
    gamma = 0.851892 - 0.020805 * n + 0.005867 * n**2 - 0.000895 * n**3 + 0.000069 * n**4 - 0.000002 * n**5  # eq (41)
    assert float(up["b"]) == pytest.approx(gamma * math.sin(T), rel=1e-12)
    down = theta_dependent_tip(-P, -n, length=1.0, EI=1.0)
    assert float(down["a"]) == pytest.approx(float(up["a"]), abs=1e-12)
    assert float(down["b"]) == pytest.approx(-float(up["b"]), abs=1e-12)
