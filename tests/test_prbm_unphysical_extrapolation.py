"""Extrapolated fits that leave the PRB model's meaning give an error, not a quiet answer.

Seed 000 eq (43)'s K_Theta(n) branch for -4 <= n < -0.5, 2.66041 - 0.069005 n - 0.002268 n^2, is
negative beyond n = -52.7 (the root of the quadratic, derived), and eq (41)'s gamma branch for
-4 <= n < -1.5, 0.855651 - 0.016438 n, exceeds 1 from n = -8.8.  With ``extrapolate='allow'`` the fixed-pinned
model used to solve the spring equation (*) with k < 0, return Theta = phi's neighbour and say
'converged' (a found defect).  Now the fits refuse a non-positive spring and the spring solve reports no
root for k <= 0 (a solver's trial point may still read the raw fits: prbm.lyon)."""
import math

import numpy as np
import pytest

from prbm.fits import FitRangeError, fit_family
from prbm.segments import fixed_pinned_tip, spring_angle


def _k_theta_branch(n):  # eq (43), -4 <= n < -0.5 branch, written out
    return 2.66041 - 0.069005 * n - 0.002268 * n * n


def test_the_k_theta_branch_changes_sign_where_derived():
    root = (-0.069005 - math.sqrt(0.069005 ** 2 + 4 * 0.002268 * 2.66041)) / (2 * 0.002268)
    assert root == pytest.approx(-52.7, abs=0.05)
    assert _k_theta_branch(root + 1) > 0 > _k_theta_branch(root - 1)
    gamma, _, K = fit_family("pauly-midha").model_parameters(root + 1, "allow")
    assert K == pytest.approx(_k_theta_branch(root + 1), rel=1e-12)


@pytest.mark.parametrize("levels", [2, 300])  # the plain-float and the array paths
def test_a_negative_extrapolated_spring_is_an_error(levels):
    with pytest.raises(FitRangeError, match="K_theta = -1.364"):
        fixed_pinned_tip(np.ones(levels), np.full(levels, -60.0), length=1.0, EI=1.0, extrapolate="allow")


def test_a_positive_extrapolated_spring_still_solves_eq_47():
    n = -9.0
    r = fixed_pinned_tip([1.0, 2.0], [n, n], length=1.0, EI=1.0, extrapolate="allow")
    assert r.converged
    K = r.constants["K_theta"][1]
    assert K == pytest.approx(_k_theta_branch(n), rel=1e-12)
    theta, F = r.outputs["Theta"][1], r.outputs["F"][1]
    phi = math.atan2(1.0, -n)  # force (-nP, P): angle of the force from the x axis
    assert F * math.sin(phi - theta) == pytest.approx(K * theta, rel=1e-9)   # eq (47) with l = EI = 1


@pytest.mark.parametrize("levels", [1, 300])
def test_the_spring_solve_has_no_root_without_a_spring(levels):
    theta, ok, _ = spring_angle(np.ones(levels), np.ones(levels), np.full(levels, -0.5))
    assert not np.any(ok) and np.all(np.isnan(theta))
    theta, ok, _ = spring_angle(1.0, 1.0, 0.0)
    assert not ok and math.isnan(theta)
