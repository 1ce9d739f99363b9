"""The per-level shortcuts of the library do the arithmetic of their definitions, bit for bit.

* ``ThetaStiffnessFit.torque_at_ratio`` (each term's c n^i worked out once per load ratio) against the
  printed polynomial p(n, Theta) = sum c_ij n^i Theta^j summed term by term;
* ``loop_closure``'s upward scan, which evaluates the loop equation only as far as its first accepted
  root, against the scan of the whole grid of Theta1 it replaces;
* ``composite_beam_tip`` with a follower force over several levels against the same call level by level.
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import prbm
from prbm.feasible_l1 import C_THETA_AVERAGE, GAMMA_AVERAGE, loop_closure
from prbm.theta_dependent import THETA_FITS


def _printed_polynomial(coefficients: dict[tuple[int, int], float], n: float, Theta: float) -> float:
    return sum(c * n**i * Theta**j for (i, j), c in coefficients.items())


@pytest.mark.parametrize("fit", sorted(THETA_FITS))
def test_torque_at_a_ratio_is_the_printed_polynomial_bit_for_bit(fit):
    kfit = THETA_FITS[fit]
    rng = np.random.default_rng(3)
    for n in [0.0, -0.0, 1.0, *rng.uniform(-4.0, 10.0, 40).tolist()]:
        torque = kfit.torque_at_ratio(n)
        for Theta in [0.0, 1e-9, *rng.uniform(-0.5, 2.0, 25).tolist()]:
            expected = _printed_polynomial(kfit.coefficients, n, Theta)
            assert torque(Theta) == expected and kfit.torque_polynomial(n, Theta) == expected


def _loop_closure_whole_grid(length, b, theta0, l1, gamma=GAMMA_AVERAGE, c_theta=C_THETA_AVERAGE):
    """Eqs (105)-(107) by the loop equation evaluated on the whole grid first: (feasible, Theta1, Theta2, a)."""
    l2 = length - l1
    R1, R2, R3, R4 = (1 - gamma) * l1, gamma * l1, gamma * l2, (1 - gamma) * l2
    shift = theta0 - theta0 / c_theta

    def g(T1):
        return R2 * math.sin(T1) + R3 * math.sin(T1 + shift) + R4 * math.sin(theta0) - b

    grid = np.linspace(max(0.0, theta0 / c_theta), math.pi / 2, 181)
    values = [g(t) for t in grid]
    for k in range(len(grid) - 1):
        if values[k] == 0.0 or values[k] * values[k + 1] < 0:
            T1 = grid[k] if values[k] == 0.0 else brentq(g, grid[k], grid[k + 1], xtol=1e-14)
            T2 = T1 - theta0 / c_theta
            if T1 <= 0 or T2 <= 0:
                continue
            R5 = length - (R1 + R2 * math.cos(T1) + R3 * math.cos(T2 + theta0) + R4 * math.cos(theta0))
            return True, T1, T2, length - R5
    return False, math.nan, math.nan, math.nan


def test_loop_closure_scan_finds_the_whole_grid_scan_root_bit_for_bit():
    rng = np.random.default_rng(11)
    feasible = 0
    for _ in range(400):
        length = rng.uniform(5.0, 25.0)
        l1 = rng.uniform(0.02, 0.98) * length
        b = rng.uniform(-0.2, 1.0) * length
        theta0 = math.radians(rng.uniform(-80.0, 80.0))
        state = loop_closure(length=length, b=b, theta0=theta0, l1=l1)
        ok, T1, T2, a = _loop_closure_whole_grid(length, b, theta0, l1)
        feasible += ok
        assert state.feasible == ok
        got, want = np.array([state.Theta1, state.Theta2, state.a]), np.array([T1, T2, a])
        assert np.array_equal(got, want, equal_nan=True)
    assert 50 < feasible < 350  # both outcomes exercised


@pytest.mark.parametrize("n", [0.0, 0.896, -0.673])
def test_follower_levels_together_equal_the_levels_one_by_one(n):
    P = [0.0, 1.5, -2.0, 4.0, 8.5]
    together = prbm.composite_beam_tip(P, n, length=10.0, EI=40.0, follower=True)
    for level, p in enumerate(P):
        alone = prbm.composite_beam_tip([p], n, length=10.0, EI=40.0, follower=True)
        for key in ("a", "b", "theta0", "Theta"):
            assert together.outputs[key][level] == alone.outputs[key][0]
        for key in ("gamma", "c_theta", "K_theta"):
            assert together.constants[key][level] == alone.constants[key][0]
    assert together.converged and together.level_converged.all()
