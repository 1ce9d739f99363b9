"""Chapter 4 deflection domains from the exact elliptic solutions (elastica.domains), the printed PRB
bounds (prbm.domain_bounds) and the study that holds them together (validation.sweep.domain_study).

Expected values: seed 000 eqs (112), (116), (123), (127) evaluated by hand, the shooting solver
(elastica.solve_elastica, an independent integration), and the first integral of the elastica
theta'^2 = 2P [lambda - (sin theta - n cos theta)] (elastica.elliptic's docstring)."""

import math

import numpy as np
import pytest

import elastica
from elastica.domains import (
    curved_fixed_pinned_cloud,
    fixed_guided_inflection_cloud,
    fixed_pinned_cloud,
    kappa_min,
    kappa_range,
    su_theta0_max,
)
from prbm.domain import fit_radius
from validation.sweep.domain_study import run_study
from prbm.domain_bounds import clamp_arc, inflection_lower_bound, prbm_arc, slfp_arc_radius

DEG = math.pi / 180


def test_su_theta0max_eq112_by_hand():
    # n = 0: phi = 90 deg; kappa_F = 1 -> acos(0) = 90 deg -> 180 deg; kappa_F > 2 -> unbounded
    assert float(su_theta0_max(0.0, 1.0)) == pytest.approx(math.pi)
    assert float(su_theta0_max(1.0, 0.5)) == pytest.approx(math.atan2(1, -1) + math.acos(0.5))
    assert np.isinf(su_theta0_max(0.0, 2.5))


@pytest.mark.parametrize("n, kappa", [(1.0, 0.6), (-1.0, 0.4), (3.0, 1.0)])
def test_su_bound_is_where_the_curvature_stops_being_real(n, kappa):
    """Just inside eq (112) with kappa_F = kappa/eta the least theta'^2 over [0, theta0] is >= 0; just
    beyond it, and at the printed reading kappa_F = kappa (M^2/(2 P EI)) for n != 0, it is < 0."""
    eta = math.hypot(1, n)
    phi = math.atan2(1, -n)

    def least_curvature2(theta0):
        th = np.linspace(0, theta0, 2001)
        lam = kappa + math.sin(theta0) - n * math.cos(theta0)
        return float(np.min(lam - (np.sin(th) - n * np.cos(th))))

    bound = float(su_theta0_max(n, kappa / eta))
    assert phi < bound
    assert least_curvature2(bound - 1e-3) >= -1e-9
    assert least_curvature2(bound + 1e-2) < 0
    printed_reading = float(su_theta0_max(n, kappa))
    assert printed_reading > bound and least_curvature2(printed_reading) < 0


def test_fixed_pinned_cloud_matches_shooting():
    cloud = fixed_pinned_cloud([-1.0, 2.0], np.array([20.0, 60.0]) * DEG)
    assert cloud.size == 3  # n = -1: phi = 45 deg, theta0 = 60 deg is left out
    for a, b, n, alpha in zip(cloud.a, cloud.b, cloud.n, cloud.alpha):
        P = alpha**2
        tip = elastica.solve_elastica(1.0, 1.0, force=(-n * P, P))
        assert (a, b) == pytest.approx((tip.x, tip.y), abs=1e-6)


def test_fixed_pinned_cloud_leaves_out_theta0_beyond_phi():
    # n = 10: phi = atan2(1, -10) = 174.3 deg, every theta0 kept; n = -4: phi = 14.04 deg
    cloud = fixed_pinned_cloud([-4.0], np.array([10.0, 20.0]) * DEG)
    assert cloud.size == 1 and cloud.excluded["theta0 outside (0, phi)"] == 1


def test_curved_cloud_matches_shooting_with_the_end_moment():
    """A point of the (n, theta0, kappa) grid is the elastica under P, nP and end moment M = alpha
    sqrt(2 kappa) (kappa0 = M l/EI, eq 115)."""
    cloud = curved_fixed_pinned_cloud([1.0], [40.0 * DEG], [0.5])
    a, b, alpha = cloud.a[0], cloud.b[0], cloud.alpha[0]
    P, M = alpha**2, alpha * math.sqrt(2 * 0.5)
    tip = elastica.solve_elastica(1.0, 1.0, force=(-P, P), moment=M)
    assert (a, b) == pytest.approx((tip.x, tip.y), abs=1e-6)


def test_inflection_cloud_point_is_an_equilibrium_under_its_loads():
    cloud = fixed_guided_inflection_cloud([0.0], [-10.0 * DEG], [0.8])
    a, b, alpha = cloud.a[0], cloud.b[0], cloud.alpha[0]
    P, M = alpha**2, alpha * math.sqrt(2 * 0.8)
    tip = elastica.solve_elastica(1.0, 1.0, force=(0.0, P), moment=-M)  # M opposes P
    assert (a, b) == pytest.approx((tip.x, tip.y), abs=1e-6)


def test_kappa_min_eq123_and_the_routine():
    n, theta0 = 0.0, 10 * DEG  # phi = 90 deg
    assert float(kappa_min(theta0, n, 15 * DEG)) == pytest.approx(math.cos(-75 * DEG) - math.cos(-80 * DEG))
    lo, hi = kappa_range(theta0, n)
    assert lo == pytest.approx(math.cos(-75 * DEG) - math.cos(-80 * DEG))
    assert hi == pytest.approx(math.cos(-5 * DEG) - math.cos(-80 * DEG))
    lo_neg, _ = kappa_range(-20 * DEG, n)  # theta0 < 0: theta_i = 5 deg
    assert lo_neg == pytest.approx(math.cos(-85 * DEG) - math.cos(-110 * DEG))


def test_printed_bound_curves():
    assert float(prbm_arc(0.8, 0.0)) == pytest.approx(1.0)
    assert float(prbm_arc(0.8, 0.8)) == pytest.approx(0.2)
    assert np.isnan(prbm_arc(0.8, 0.9))
    assert float(clamp_arc(0.8945, 0.0)) == pytest.approx(0.8945)
    assert float(inflection_lower_bound(0.0)) == pytest.approx(0.934)
    # eq (116) at b = 0.5 by hand: 0.934 - 0.02955 - 0.405275 + 0.6206125 - 0.710375 + 0.4295625 - 0.110561
    assert float(inflection_lower_bound(0.5)) == pytest.approx(0.7284136, abs=1e-6)
    assert slfp_arc_radius(0.5, 4.0) == pytest.approx(4.25)


def test_fit_radius_recovers_an_arc():
    b = np.linspace(0.05, 0.7, 30)
    assert fit_radius(prbm_arc(0.83, b), b) == pytest.approx(0.83, abs=1e-9)
    assert fit_radius(clamp_arc(0.89, b), b, centre="clamp") == pytest.approx(0.89, abs=1e-9)


def test_extreme_n_trajectories_against_the_printed_gammas():
    """Seed 000 eqs (110), (111): gamma_l = 0.8053, gamma_u = 0.8829. The seed's extraction rule (Fig. 4.1)
    is missing; read as the PRB arcs of the extreme load ratios n = 10 and n = -4 of its grid, the exact
    trajectories (theta0 = 1..90 deg, within phi) give them within 1 %."""
    th = np.arange(1.0, 90.5, 0.5) * DEG
    for n, printed in ((10.0, 0.8053), (-4.0, 0.8829)):
        cloud = fixed_pinned_cloud([n], th)
        assert fit_radius(cloud.a, cloud.b) == pytest.approx(printed, rel=0.01)


def test_domain_study_on_a_small_grid(tmp_path):
    """The study reads its printed values and grids from the data file and writes every number."""
    data = tmp_path / "small.toml"
    data.write_text("""
[beam]
length = 20.0
width = 0.5
thickness = 0.0625
E = 30.0e6
[fixed_pinned]
gamma_l = 0.8053
gamma_u = 0.8829
n = { start = -4.0, stop = 10.0, step = 2.0 }
theta0_deg = { start = 5.0, stop = 85.0, step = 10.0 }
[curved_fixed_pinned]
gamma_l = 0.7431
gamma_u = 0.8148
n = { start = -2.0, stop = 4.0, step = 2.0 }
theta0_deg = { start = 10.0, stop = 80.0, step = 10.0 }
kappa = { start = 0.5, stop = 2.5, step = 1.0 }
[fixed_guided_inflection]
gamma_bar_l = 0.8945
gamma_u = 0.9035
lower_fit_claim = 0.01
lower_fit_range = [0.4, 0.85]
n = { start = -2.0, stop = 2.0, step = 1.0 }
P = [1.0, 10.0]
kappa = { start = 0.2, stop = 1.6, step = 0.2 }
theta0_deg = { start = -50.0, stop = 50.0, step = 10.0 }
""")
    study = run_study(tmp_path / "out", data, plot=False)
    assert (tmp_path / "out" / "summary.json").exists()
    names = [[b.name for b in r.bounds] for r in study.results]
    assert names[0] == ["gamma_l", "gamma_u", "gamma_l", "gamma_u"] and names[2] == ["gamma_bar_l", "gamma_u"]
    assert study.results[0].bounds[0].printed == 0.8053
    for r in study.results:
        assert r.points > 0 and r.prbm_error.samples > 0


def test_the_array_forms_are_the_scalar_elliptic_solutions_point_by_point():
    """The clouds are computed on arrays (elastica.domains.*_arrays); each point must be the scalar
    closed form of elastica.elliptic (same formulas), NaN exactly where the scalar form has no solution."""
    from elastica.elliptic import (
        curved_fixed_pinned_from_angle,
        fixed_guided_inflection_from_angle,
        fixed_pinned_from_angle,
    )
    from elastica.domains import curved_fixed_pinned_arrays, fixed_guided_inflection_arrays, fixed_pinned_arrays

    rng = np.random.default_rng(7)
    n, th, kappa = rng.uniform(-4.0, 10.0, 600), rng.uniform(-1.2, 2.2, 600), rng.uniform(0.0, 5.0, 600)
    pinned_th = rng.uniform(0.01, 1.5, 600)
    pairs = [
        (curved_fixed_pinned_arrays, curved_fixed_pinned_from_angle, (th, n, kappa)),
        (fixed_guided_inflection_arrays, fixed_guided_inflection_from_angle, (th, n, kappa)),
        (fixed_pinned_arrays, fixed_pinned_from_angle, (pinned_th, n)),
    ]
    for arrays, scalar, args in pairs:
        with np.errstate(invalid="ignore", divide="ignore"):
            got = np.column_stack(arrays(*args))
            inside = [i for i in range(600) if arrays is not fixed_pinned_arrays or pinned_th[i] < math.atan2(1, -n[i])]
            expected = np.array([scalar(*(float(a[i]) for a in args))[:4] for i in inside])[:, [0, 1, 3]]
        got = got[inside]
        assert (np.isfinite(got) == np.isfinite(expected)).all(), arrays.__name__
        finite = np.isfinite(expected)
        assert finite.sum() > 300, arrays.__name__  # the comparison is not empty
        assert np.abs(got[finite] - expected[finite]).max() < 1e-12 * np.abs(expected[finite]).max()
