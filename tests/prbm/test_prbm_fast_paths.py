"""The fast paths give the reference implementations' numbers to 1e-9 (relative).

* ``spring_angle`` (Newton from the linear solution, plain floats for a few levels, numpy beyond)
  against ``_spring_angle_reference`` (the previous safeguarded Newton from phi), and both against
  the residual of F R sin(phi - Theta) = k (Theta - Theta_i) itself;
* the small-array path of the n-fits against the vectorised polyval path;
* ``FourBar.angles`` for one float against the array construction, and the closed-form inverse
  ``FourBar.input_for_output`` against the bracketed scan + Brent of the adapter;
* ``FourBar`` outputs with precomputed angles against the same outputs computing them.
"""

import math

import numpy as np
import pytest

import prbm
from prbm.segments import _spring_angle_reference, _spring_angle_vector
from validation.methods.prbm_fourbar import _theta2_for_output_scan

RTOL = 1e-9


def _random_spring_problems(count: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    FR = rng.uniform(0.0, 200.0, count) * (rng.random(count) > 0.05)
    theta_i = rng.uniform(-1.0, 1.0, count) * (rng.random(count) < 0.5)
    phi = rng.uniform(0.01, math.pi - 0.01, count) * np.where(rng.random(count) < 0.3, -1.0, 1.0)
    phi = theta_i + np.angle(np.exp(1j * (phi - theta_i)))  # the branch within pi of Theta_i
    k = rng.uniform(0.1, 10.0, count)
    return FR, phi, k, theta_i


def _close(a, b, rtol=RTOL):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return np.all(np.abs(a - b) <= rtol * np.maximum(np.abs(b), 1e-3))


def test_spring_angle_paths_agree_with_the_reference_and_solve_the_equation():
    FR, phi, k, theta_i = _random_spring_problems(3000)
    ref, ref_ok, _ = _spring_angle_reference(FR, phi, k, theta_i)
    vec, vec_ok, vec_it = _spring_angle_vector(FR, phi, k, theta_i, 1e-13, 60)
    small, small_ok, _ = prbm.spring_angle(FR[:200], phi[:200], k[:200], theta_i[:200])  # plain-float loop
    one = np.array([prbm.spring_angle(*map(float, level))[0] for level in zip(FR, phi, k, theta_i)])
    assert ref_ok.all() and vec_ok.all() and small_ok.all()
    assert vec_it <= 10  # quadratic convergence from the linear start (the reference needed ~50)
    for got in (vec, small, one):
        assert _close(got, ref[: len(got)])
    residual = FR * np.sin(phi - one) - k * (one - theta_i)
    assert np.all(np.abs(residual) <= 1e-12 * (FR + k))


@pytest.mark.parametrize("family", ["pauly-midha", "howell"])
def test_fit_small_array_path_equals_polyval(family):
    fam = prbm.fit_family(family)
    n = np.linspace(fam.lower + 1e-6, fam.upper, 200)  # 200 > the small-array limit: polyval
    n[:3] = [-0.5, 0.5, -1.5]  # breakpoints of the branches
    for fit in (fam.gamma, fam.K_theta):
        assert np.array_equal(fit(n[:20]), fit(n)[:20])
        assert fit(n[:20].reshape(4, 5)).shape == (4, 5)


def test_fixed_pinned_tip_matches_the_reference_spring_solver():
    P = np.linspace(0.0, 10.0, 11)
    for n in (-3.0, 0.0, 0.896):
        r = prbm.fixed_pinned_tip(P, n, length=1.0, EI=1.0)
        g, _, K = prbm.PAULY_MIDHA.parameters(n)
        ref, _, _ = _spring_angle_reference(P * math.sqrt(1 + n * n), math.atan2(1.0, -n), np.full_like(P, K))
        assert _close(r["Theta"], ref)
        assert _close(r["b"], g * np.sin(ref))


FOURBAR = prbm.FourBar(
    3.902 - 0.8802j,
    4.754 + 2.767j,
    6.249 - 2.176j,
    7.099 + 1.471j,
    7.929 - 0.148j,
    springs=(38.356, 1.5, 2.0, 3.0),
    theta_free=(math.radians(15.86), -0.4958, -0.1057),
)


def test_fourbar_scalar_angles_equal_the_array_construction():
    theta2 = np.linspace(-1.0, 2.0, 61)
    t3, t4 = FOURBAR.angles(theta2)
    for i, t in enumerate(theta2.tolist()):
        s3, s4 = FOURBAR.angles(t)
        assert (math.isnan(s3) and math.isnan(t3[i])) or (_close(s3, t3[i]) and _close(s4, t4[i]))


def test_fourbar_closed_form_inverse_equals_the_scan():
    t21 = FOURBAR.theta_ref[0]
    t41 = float(FOURBAR.angles(t21)[1])
    for psi in np.radians([-20.0, -5.0, 0.0, 5.0, 11.95, 19.83, 30.0, 180.0]):
        fast = FOURBAR.input_for_output(t41 + psi, t21)
        assert fast is not None
        assert _close(fast, _theta2_for_output_scan(FOURBAR, t41 + psi, t21))
        assert abs(math.remainder(float(FOURBAR.angles(fast)[1]) - (t41 + psi), 2 * math.pi)) < 1e-12
    far = FOURBAR.input_for_output(t41 + math.pi, t21 + math.pi)  # no root within 90 deg of this start
    assert far is None


def test_fourbar_outputs_with_precomputed_angles_are_unchanged():
    theta2 = np.radians([15.86, 20.0, 30.0, 41.0])
    angles = FOURBAR.angles(theta2)
    assert np.array_equal(FOURBAR.coupler_point(theta2, angles), FOURBAR.coupler_point(theta2))
    assert np.array_equal(FOURBAR.input_torque(theta2, angles), FOURBAR.input_torque(theta2))
    assert np.array_equal(FOURBAR.strain_energy(theta2, angles), FOURBAR.strain_energy(theta2))
    assert np.array_equal(
        FOURBAR.compliant_ma(theta2, 10.0, 2.0, 3.0, angles), FOURBAR.compliant_ma(theta2, 10.0, 2.0, 3.0)
    )


def test_slider_crank_closed_form_inverse_equals_the_scan():
    t2 = math.radians(60.0)
    sc = prbm.SliderCrank(2.5, 4.0, t2, math.asin(-2.5 * math.sin(t2) / 4.0), springs=(0.0, 1.0, 1.0))
    for dx in np.linspace(-1.5, 1.5, 13):
        assert _close(sc.theta2_at(float(dx)), sc._theta2_at_scan(float(dx)))
        assert abs(float(sc.slider_x(sc.theta2_at(float(dx)))) - (sc.x_ref + dx)) < 1e-12
    with pytest.raises(ValueError, match="cannot reach"):
        sc.theta2_at(10.0)
