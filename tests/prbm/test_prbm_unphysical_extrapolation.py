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

from prbm.fits import Branch, FitFamily, FitRangeError, PiecewiseFit, _unphysical, fit_family
from prbm.segments import fixed_pinned_tip, spring_angle


def _k_theta_branch(n):  # eq (43), -4 <= n < -0.5 branch, written out
    return 2.66041 - 0.069005 * n - 0.002268 * n * n


def test_the_k_theta_branch_changes_sign_where_derived():
    root = (-0.069005 - math.sqrt(0.069005**2 + 4 * 0.002268 * 2.66041)) / (2 * 0.002268)
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
    assert F * math.sin(phi - theta) == pytest.approx(K * theta, rel=1e-9)  # eq (47) with l = EI = 1


@pytest.mark.parametrize("levels", [1, 300])
def test_the_spring_solve_has_no_root_without_a_spring(levels):
    theta, ok, _ = spring_angle(np.ones(levels), np.ones(levels), np.full(levels, -0.5))
    assert not np.any(ok) and np.all(np.isnan(theta))
    theta, ok, _ = spring_angle(1.0, 1.0, 0.0)
    assert not ok and math.isnan(theta)


def _family(gamma_value: float, k_value: float) -> FitFamily:
    """A one-branch family on -1 < n <= 1 whose gamma and K_theta are the given constants everywhere
    (extrapolated as the same constants)."""

    def constant(name, value):
        return PiecewiseFit(name, "test", (Branch(-1.0, 1.0, (value,)),))

    return FitFamily("constant", constant("gamma", gamma_value), constant("K_theta", k_value), None)


def test_by_default_a_ratio_outside_the_fits_is_a_range_error_even_where_the_values_are_physical():
    with pytest.raises(FitRangeError, match="outside"):
        fit_family("pauly-midha").model_parameters(12.0)  # eq (41)-(43) published for -4 < n <= 10
    g, _, k = fit_family("pauly-midha").model_parameters(12.0, "allow")
    assert g > 0 and k > 0  # ... though their extrapolation is physical there


@pytest.mark.parametrize("gamma_value, k_value", [(0.0, 2.0), (0.8, 0.0)])
def test_a_zero_radius_or_a_zero_spring_is_no_prb_model(gamma_value, k_value):
    # the model needs gamma > 0 and K_theta > 0 strictly: a spring of zero stiffness or a zero radius is none
    with pytest.raises(FitRangeError, match="constant fits extrapolated to n = 2 .*: no PRB model"):
        _family(gamma_value, k_value).model_parameters(2.0, "allow")
    assert _family(0.8, 2.0).model_parameters(2.0, "allow")[0] == 0.8


def test_the_message_names_the_family_and_the_first_unphysical_ratio_with_its_values():
    # the first ratio is physical (gamma 0.85 and K_theta 0.5 are below 1 but positive); the second has K < 0
    message = _unphysical("pauly-midha", np.array([2.0, -60.0]), np.array([0.85, 0.9]), np.array([0.5, -1.5]))
    assert message == (
        "pauly-midha fits extrapolated to n = -60 give gamma = 0.9 and K_theta = -1.5: "
        "no PRB model there (it needs gamma > 0 and K_theta > 0)"
    )
    assert "n = 3 give gamma = 0 and" in _unphysical("x", 3.0, 0.0, 1.0)  # a zero radius counts
    assert "K_theta = 0:" in _unphysical("x", 3.0, 0.5, 0.0)  # so does a zero spring
