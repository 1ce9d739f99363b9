"""Verification of fem/ on cantilevers against exact solutions.

References are computed here from first principles, never from fem/ output:
* tip load of fixed direction: elliptic integrals (Mattiasson 1981 / Bisshopp &
  Drucker 1945; anchors section 2.1), checked against the published table;
* pure end moment: closed form x = sin(kappa s)/kappa, y = (1 - cos(kappa s))/kappa;
* follower tip load: shooting on EI theta'' = -P cos(theta - theta_L).

EA/EI = 1e10 makes the beam inextensible to 1e-10, below every tolerance here.
Tolerances: the fine-mesh error must be within the Richardson estimate
(|Q_2n - Q_n|/3, up to a safety factor 1.5), and the extrapolated value within
a small multiple of the next-order term.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.special import ellipe, ellipeinc, ellipk, ellipkinc

import fem

EA, EI, L = 1e10, 1.0, 1.0


def elastica_tip_load(alpha):
    """(u/L shortening, w/L deflection, tip rotation) for P L^2/EI = alpha."""

    def residual(theta0):
        k = np.sqrt((1 + np.sin(theta0)) / 2)
        phi1 = np.arcsin(1 / (np.sqrt(2) * k))
        return ellipk(k * k) - ellipkinc(phi1, k * k) - np.sqrt(alpha)

    theta0 = brentq(residual, 1e-12, np.pi / 2 - 1e-14, xtol=1e-15)
    k = np.sqrt((1 + np.sin(theta0)) / 2)
    phi1 = np.arcsin(1 / (np.sqrt(2) * k))
    w = 1 - 2 / np.sqrt(alpha) * (ellipe(k * k) - ellipeinc(phi1, k * k))
    x = np.sqrt(2 * np.sin(theta0) / alpha)
    return 1 - x, w, theta0


TABLE = {
    1: (0.056433, 0.301721, 0.461352),
    2: (0.160642, 0.493457, 0.781750),
    3: (0.254420, 0.603253, 0.986017),
    4: (0.328941, 0.669964, 1.121239),
    5: (0.387628, 0.713792, 1.215368),
    6: (0.434589, 0.744571, 1.283697),
    7: (0.472927, 0.767369, 1.334960),
    8: (0.504828, 0.784982, 1.374432),
    9: (0.531821, 0.799056, 1.405465),
    10: (0.554996, 0.810609, 1.430286),
}


def cantilever(n_elements, fx, fy, follower=False):
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", L, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(EA, EI), n_elements=n_elements)
    m.add_support("root", "fixed")
    m.add_force("tip", fx, fy, follower=follower)
    return m


def test_elliptic_reference_reproduces_table():
    for alpha, row in TABLE.items():
        assert np.allclose(elastica_tip_load(alpha), row, atol=6e-7)


def test_tip_load_table_with_error_estimate():
    alphas = np.arange(1.0, 11.0)
    est = fem.solve_with_error_estimate(cantilever(8, 0 * alphas, alphas))
    assert est.converged and est.result.converged
    for i, a in enumerate(alphas):
        u, w, th = elastica_tip_load(a)
        exact = np.array([L - u, w])
        fine = est.result.position("tip", i)
        p_ext, p_err = est.position("tip", i)
        # the estimate bounds the true error of the fine mesh (16 elements) ...
        assert np.linalg.norm(fine - exact) <= 1.5 * np.linalg.norm(p_err) + 1e-12
        assert np.max(np.abs(fine - exact)) < 5e-4 * L
        # ... and extrapolation removes at least 90 % of it (the rest is O(h^4))
        assert np.linalg.norm(p_ext - exact) <= 0.1 * np.linalg.norm(p_err) + 1e-9
        th_ext, th_err = est.rotation("tip", i)
        assert abs(est.result.rotation("tip", i) - th) <= 1.5 * th_err + 1e-12
        assert abs(th_ext - th) <= 0.1 * th_err + 1e-9
        # reactions: exact equilibrium of the whole beam
        R = est.result.reaction("root", i)
        tip = est.result.position("tip", i)
        # (rounding noise in f_int is about eps * EA = 2e-6 here)
        assert np.allclose(R, [0.0, -a, -a * tip[0]], rtol=1e-8, atol=1e-5)


def test_observed_order_is_two():
    errs = []
    for n in (4, 8, 16):
        r = fem.solve(cantilever(n, 0.0, 5.0))
        u, w, _ = elastica_tip_load(5.0)
        errs.append(np.linalg.norm(r.position("tip") - [L - u, w]))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(np.abs(orders - 2.0) < 0.1), orders


def test_tolerance_driven_refinement():
    est = fem.solve_with_error_estimate(cantilever(2, 0.0, 2.0), tol=1e-5)
    assert est.converged and est.max_position_error <= 1e-5
    u, w, _ = elastica_tip_load(2.0)
    assert np.max(np.abs(est.result.position("tip") - [L - u, w])) <= 1.5e-5


@pytest.mark.parametrize("n_levels", [1, 2, 4, 10])
@pytest.mark.parametrize("as_history", [False, True])
def test_full_circle_any_number_of_levels(n_levels, as_history):
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", L, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(EA, EI), n_elements=20)
    m.add_support("root", "fixed")
    phis = 2 * np.pi * np.arange(1, n_levels + 1) / n_levels
    if as_history:  # one moment value per level
        m.add_moment("tip", phis * EI / L)
        r = fem.solve(m)
    else:  # a single value, applied in n_levels equal levels
        m.add_moment("tip", 2 * np.pi * EI / L)
        r = fem.solve(m, n_levels=n_levels)
    assert r.converged, r.message
    assert r.n_levels == n_levels
    assert abs(r.rotation("tip") - 2 * np.pi) < 1e-6
    assert np.linalg.norm(r.position("tip") - [0.0, 0.0]) < 1e-6 * L
    n = 20
    for k, phi in enumerate(phis):  # closed form at every level
        exact = np.array([np.sin(phi), 1 - np.cos(phi)]) * L / phi
        # straight elements of length L/n put the nodes on a circle of radius
        # R_h = (L/n) / (2 sin(phi/2n)) instead of R = L/phi: relative error eps
        eps = (phi / (2 * n)) / np.sin(phi / (2 * n)) - 1.0
        bound = eps * (L / phi) * 2 * abs(np.sin(phi / 2))
        # (+ 1e-10 L: the Newton tolerance rtol = 1e-10)
        assert np.linalg.norm(r.position("tip", k) - exact) <= 1.001 * bound + 1e-10 * L
        assert abs(r.rotation("tip", k) - phi) < 1e-9
        assert abs(r.strain_energy[k] - 0.5 * EI * phi**2 / L) < 1e-8


def test_spurious_branch_is_rejected_not_returned():
    """Without the per-step rotation limit the 2 pi jump check must still hold."""
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", L, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(EA, EI), n_elements=10)
    m.add_support("root", "fixed")
    m.add_moment("tip", [2 * np.pi * EI / L])
    r = fem.solve(m, max_rotation_increment=1e3)
    if r.converged:
        assert abs(r.rotation("tip") - 2 * np.pi) < 1e-6
        assert np.all(np.abs(np.diff(r.mesh_rotations[-1][r.connectivity], axis=1)) < np.pi)


def follower_reference(alpha):
    """Tip (x, y) and rotation for a follower tip load, by shooting + continuation."""

    def shoot(theta_L):
        sol = solve_ivp(
            lambda s, y: [y[1], -alpha * np.cos(y[0] - theta_L), np.cos(y[0]), np.sin(y[0])],
            (1.0, 0.0),
            [theta_L, 0.0, 0.0, 0.0],
            rtol=1e-12,
            atol=1e-13,
        )
        return sol.y[:, -1]

    theta_L = 0.0
    for a in np.linspace(0.0, alpha, 41)[1:]:
        alpha_saved, alpha = alpha, a
        lo, hi = theta_L - 0.05, theta_L + 0.6
        theta_L = brentq(lambda t: shoot(t)[0], lo, hi, xtol=1e-14)
        alpha = alpha_saved
    end = shoot(theta_L)  # integrated from the tip: x(0)-x(L), y(0)-y(L)
    return np.array([-end[2], -end[3]]), theta_L


@pytest.mark.parametrize("alpha", [2.0, 6.0])
def test_follower_load(alpha):
    exact_tip, exact_rot = follower_reference(alpha)
    est = fem.solve_with_error_estimate(cantilever(8, 0.0, alpha, follower=True))
    assert est.converged
    fine = est.result.position("tip")
    p_ext, p_err = est.position("tip")
    assert np.linalg.norm(fine - exact_tip) <= 1.5 * np.linalg.norm(p_err) + 1e-12
    assert np.linalg.norm(p_ext - exact_tip) <= 0.1 * np.linalg.norm(p_err) + 1e-9
    th_ext, th_err = est.rotation("tip")
    assert abs(th_ext - exact_rot) <= 0.1 * th_err + 1e-9


def test_three_level_romberg_estimate_and_order():
    alphas = np.array([1.0, 5.0, 10.0])
    est = fem.solve_with_error_estimate(cantilever(4, 0 * alphas, alphas), levels=3, tol=1e-6)
    assert est.converged, est.message
    assert abs(est.observed_order - 2.0) < 0.1
    for i, a in enumerate(alphas):
        u, w, th = elastica_tip_load(a)
        p_ext, _ = est.position("tip", i)
        assert np.linalg.norm(p_ext - [L - u, w]) <= max(
            1e-6, 2 * np.linalg.norm(est.extrapolated_error["positions"][i, 1])
        )


def test_displacement_control_recovers_load():
    """Tip deflection w(alpha) from the elastica prescribed; the load factor is alpha."""
    alphas = [1.0, 5.0, 9.0]
    targets = [elastica_tip_load(a)[1] for a in alphas]
    est = fem.solve_with_error_estimate(
        cantilever(8, 0.0, 1.0), control="displacement", control_dof=("tip", "uy"), targets=targets
    )
    assert est.converged, est.message
    lam_fine = est.result.load_factor
    lam_ext, lam_err = est.extrapolated["load_factor"], est.error["load_factor"]
    for a, lf, le, lx in zip(alphas, lam_fine, lam_err, lam_ext):
        assert abs(lf - a) <= 1.5 * le + 1e-9
        assert abs(lx - a) <= 0.1 * le + 1e-9


def test_every_level_is_first_tried_in_one_step():
    """Load control tries each level in one step, cut only on failure: a level that needed cuts (the
    roll-up's first half-circle, past a 0.5 rad cap on the rotation increment of a step) does not
    shorten the first try of the next, which turns the tip by 0.01 rad and is taken in one step.
    (Carrying the shortened step over took the small second level in as many steps as the first.)"""
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", L, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(EA, EI), n_elements=12)
    m.add_support("root", "fixed")
    m.add_moment("tip", [np.pi * EI / L, (np.pi + 0.01) * EI / L])
    r = fem.solve(m, max_rotation_increment=0.5)
    assert r.converged, r.message
    steps = np.asarray(r.extra["step_load_factor"])
    first, second = steps[steps <= 0.0], steps[steps > 0.0]  # the level parameter k - 1 + t
    assert len(first) >= 7 and first[-1] == 0.0  # pi rad in steps of at most 0.5
    assert list(second) == [1.0]
    assert abs(r.rotation("tip", 1) - (np.pi + 0.01)) < 1e-9
