"""Characteristic deflection domains of seed 000 chapter 4: every segment type's cloud is non-empty and
physically bounded, follows the segment PRBMs of ``prbm.segments``, has the limits and equivalences the
seed states (sections 4.5-4.7), enforces the fit ranges, and is fast (timed, not asserted)."""

import math
import time

import numpy as np
import pytest

import prbm

N_GRID = np.linspace(-3.9, 10.0, 15)

DOMAINS = {
    "fixed-pinned": lambda: prbm.fixed_pinned_domain(n_values=N_GRID, n_theta=31),
    "curved fixed-pinned": lambda: prbm.curved_fixed_pinned_domain(
        [-1.0, 0.3, 1.0, 2.5, 5.0], n_values=N_GRID, n_theta=31
    ),
    "fixed-guided": lambda: prbm.fixed_guided_domain(n_values=N_GRID, n_theta=31),
    "fixed-fixed monotonic": lambda: prbm.fixed_fixed_monotonic_domain(
        np.linspace(-4.0, 4.0, 9), n_values=N_GRID, n_theta=31
    ),
    "straight SLFP": lambda: prbm.slfp_domain(0.05, n_values=N_GRID, n_theta=31),
    "curved SLFP": lambda: prbm.slfp_domain(0.05, n_values=N_GRID, curvature=1.2, n_theta=31),
}


@pytest.mark.parametrize("kind", DOMAINS)
def test_domain_is_non_empty_and_within_reach_of_the_arc_length(kind):
    d = DOMAINS[kind]()
    a, b = d["a"], d["b"]
    assert a.size > 100 and np.all(np.isfinite(a)) and np.all(np.isfinite(b))
    # an inextensible segment of length l cannot put its end farther than l from the fixed end
    assert np.all(np.hypot(a, b) <= 1.0 + 1e-12)
    assert np.all(d["alpha2"] >= 0.0)  # P > 0 throughout
    if "boundary_lower" in d:
        assert d["boundary_b"].size > 10 and np.all(d["boundary_lower"] <= d["boundary_upper"])


def test_curved_fixed_pinned_points_are_curved_prbm_solutions():
    d = prbm.curved_fixed_pinned_domain(np.array([0.5, 2.0]), n_values=N_GRID, n_theta=21)
    for i in range(0, d["a"].size, 97):
        r = prbm.curved_fixed_pinned_tip(d["alpha2"][i], d["n"][i], length=1.0, EI=1.0, curvature=d["kappa0"][i])
        assert (float(r["a"]), float(r["b"]), float(r["theta0"])) == pytest.approx(
            (d["a"][i], d["b"][i], d["theta0"][i]), abs=1e-9
        )


def test_straight_fixed_pinned_is_the_zero_curvature_limit():
    straight = prbm.fixed_pinned_domain(n_values=N_GRID, n_theta=41)
    for kappa0, tol in ((1e-3, 2e-3), (1e-5, 2e-5)):
        curved = prbm.curved_fixed_pinned_domain(kappa0, n_values=N_GRID, n_theta=41)
        assert np.max(np.abs(curved["a"] - straight["a"])) < tol
        assert np.max(np.abs(curved["b"] - straight["b"])) < tol
    # and the curvature matters: a curved beam starts off the axis
    bent = prbm.curved_fixed_pinned_domain(1.0, n_values=N_GRID, n_theta=41)
    assert np.min(bent["b"]) > 0.1


def test_fixed_guided_points_are_two_spring_solutions():
    d = prbm.fixed_guided_domain(n_values=N_GRID, n_theta=21)
    for i in range(0, d["a"].size, 53):
        r = prbm.fixed_guided_tip(d["alpha2"][i], d["n"][i], length=1.0, EI=1.0)
        assert (float(r["a"]), float(r["b"]), float(r["M"])) == pytest.approx(
            (d["a"][i], d["b"][i], d["moment"][i]), abs=1e-9
        )


def test_two_spring_fixed_guided_cloud_lies_in_the_fixed_pinned_envelope():
    # Model property (eq 63 reuses the fixed-pinned geometry and gamma(n)): the theta0 = 0 cloud
    # coincides with the fixed-pinned cloud, at four times the load.
    fp = prbm.fixed_pinned_domain(n_values=N_GRID, n_theta=31)
    fg = prbm.fixed_guided_domain(n_values=N_GRID, n_theta=31)
    assert np.allclose(fg["a"], fp["a"]) and np.allclose(fg["b"], fp["b"])
    assert np.allclose(fg["alpha2"], 4.0 * fp["alpha2"])
    env = prbm.boundary_curves(fp["a"], fp["b"], bins=30)
    lower = np.interp(fg["b"], env["b"], env["lower"])
    upper = np.interp(fg["b"], env["b"], env["upper"])
    inner = (fg["b"] > env["b"][0]) & (fg["b"] < env["b"][-1])
    assert np.all(fg["a"][inner] >= lower[inner] - 0.02) and np.all(fg["a"][inner] <= upper[inner] + 0.02)


def test_seed_does_not_place_the_inflection_domain_inside_the_fixed_pinned_one():
    # The seed makes no containment claim; its printed constants say the opposite.  Upper bounds are
    # PRBM arcs about (1 - gamma) l: fixed-guided with an inflection gamma_u = 0.9035 (118) lies
    # outside fixed-pinned gamma_u = 0.8829 (111) for every b/l > 0 the latter reaches; the lower bound
    # 0.8945 about the clamp (117) lies below fixed-pinned gamma_l = 0.8053 (110) for b/l in 0.4..0.7.
    def prbm_arc(g, b):
        return 1.0 - g + np.sqrt(g**2 - b**2)

    b = np.linspace(0.01, 0.88, 30)
    assert np.all(prbm_arc(0.9035, b) > prbm_arc(0.8829, b))
    b = np.linspace(0.4, 0.7, 7)
    assert np.all(np.sqrt(0.8945**2 - b**2) < prbm_arc(0.8053, b))


def test_monotonic_fixed_fixed_is_the_curved_domain_with_kappa0_equal_to_Ml_over_EI():
    # section 4.6: with kappa0 = M l/EI (115) the monotonic fixed-fixed domain is that of Fig. 4.7;
    # for an initially curved segment kappa0 = M l/EI + l/R_i (119).
    m = np.array([0.4, 1.5])
    ff = prbm.fixed_fixed_monotonic_domain(m, n_values=N_GRID, n_theta=21)
    cv = prbm.curved_fixed_pinned_domain(m, n_values=N_GRID, n_theta=21)
    assert ff["excluded_inflection"] == 0
    assert np.array_equal(ff["a"], cv["a"]) and np.array_equal(ff["b"], cv["b"])
    ffc = prbm.fixed_fixed_monotonic_domain(m, n_values=N_GRID, curvature=0.3, n_theta=21)
    cvc = prbm.curved_fixed_pinned_domain(m + 0.3, n_values=N_GRID, n_theta=21)
    assert np.array_equal(ffc["a"], cvc["a"]) and np.array_equal(ffc["b"], cvc["b"])
    i = 211
    r = prbm.fixed_guided_monotonic_tip(ff["alpha2"][i], ff["n"][i], ff["moment"][i], length=1.0, EI=1.0)
    assert (float(r["a"][0]), float(r["b"][0])) == pytest.approx((ff["a"][i], ff["b"][i]), abs=1e-9)


def test_opposing_moment_kept_only_beyond_the_no_inflection_bound():
    d = prbm.fixed_fixed_monotonic_domain([-2.0, 2.0], n_values=N_GRID, n_theta=31)
    opposing = d["moment"] < 0
    assert d["excluded_inflection"] > 0 and opposing.any()
    assert np.all(d["kappa"][opposing] > 2.0)  # eq (125), kappa = M^2/(2 F EI)
    F = d["alpha2"] * np.sqrt(1 + d["n"] ** 2)
    with np.errstate(divide="ignore"):
        assert np.allclose(d["kappa"][opposing & (F > 0)], (4.0 / (2 * F))[opposing & (F > 0)])
    assert d["a"].size + d["excluded_inflection"] == 2 * N_GRID.size * 31


@pytest.mark.parametrize("curvature", [0.0, 1.2])
def test_slfp_domain_is_the_arc_of_eq_127(curvature):
    lam = 0.05
    d = prbm.slfp_domain(lam, n_values=N_GRID, curvature=curvature, n_theta=31)
    px, py = d["pivot"]
    assert d["radius"] == pytest.approx(lam / 2 + (1 - lam))  # (l/2 + L)/(l + L)
    assert np.allclose(np.hypot(d["a"] - px, d["b"] - py), d["radius"], atol=1e-12)
    i = 301
    r = prbm.slfp_tip(
        d["alpha2"][i], d["n"][i], flexure_length=lam, rigid_length=1 - lam, EI=1.0, curvature=curvature / lam
    )
    assert (float(r["a"]), float(r["b"])) == pytest.approx((d["a"][i], d["b"][i]), abs=1e-9)


@pytest.mark.parametrize(
    "make",
    [
        lambda n: prbm.curved_fixed_pinned_domain(0.7, n_values=n, n_theta=11),
        lambda n: prbm.fixed_guided_domain(n_values=n, n_theta=11),
        lambda n: prbm.fixed_fixed_monotonic_domain([1.0], n_values=n, n_theta=11),
    ],
)
def test_load_ratios_outside_the_fit_range_are_excluded_and_counted(make):
    d = make(np.array([-6.0, -4.0, -2.0, 0.0, 10.0, 10.5]))  # Pauly-Midha: -4 < n <= 10
    assert d["excluded"] == 3 * 11
    assert set(np.unique(d["n"])) == {-2.0, 0.0, 10.0}


@pytest.mark.parametrize(
    "kind,make",
    [
        (
            "curved fixed-pinned",
            lambda: prbm.curved_fixed_pinned_domain(0.5, n_values=np.linspace(-3.9, 10, 100), n_theta=100),
        ),
        ("fixed-guided", lambda: prbm.fixed_guided_domain(n_values=np.linspace(-3.9, 10, 100), n_theta=100)),
        (
            "fixed-fixed monotonic",
            lambda: prbm.fixed_fixed_monotonic_domain(
                np.linspace(0.0, 2.0, 10), n_values=np.linspace(-3.9, 10, 100), n_theta=10
            ),
        ),
        ("SLFP", lambda: prbm.slfp_domain(0.05, n_values=np.linspace(-3.9, 10, 100), n_theta=100)),
    ],
)
def test_ten_thousand_point_domain_timing(kind, make, record_property):
    make()  # warm-up
    t0 = time.perf_counter()
    d = make()
    elapsed = time.perf_counter() - t0
    assert d["a"].size == 10_000
    record_property(f"{kind} 10k-point domain [s]", elapsed)  # measured, not asserted
    print(f"{kind}: 10,000 points in {elapsed * 1e3:.1f} ms")
    assert math.isfinite(elapsed)


def test_fixed_pinned_domain_points_are_eqs_47_to_49_with_the_printed_fits():
    """Each point of Fig. 4.3's cloud is the fixed-pinned PRBM at its (n, Theta): a = 1 - gamma (1 - cos
    Theta), b = gamma sin Theta (48, 49) and alpha^2 sqrt(1 + n^2) sin(phi - Theta) = K_Theta Theta (46-47),
    phi = atan2(1, -n); gamma and K_Theta written out from the printed eqs (41), (43) at n = 0 and n = 1."""
    printed = {
        0.0: (0.851892, 2.648834),
        1.0: (
            0.851892 - 0.020805 + 0.005867 - 0.000895 + 0.000069 - 0.000002,
            2.648834 - 0.074727 + 0.026328 - 0.004609 + 0.000390 - 0.000013,
        ),
    }
    d = prbm.fixed_pinned_domain(n_values=np.array(list(printed)), n_theta=7)
    assert d["a"].size == 14 and np.ptp(d["Theta"]) > 1.0
    for a, b, n, Theta, alpha2 in zip(d["a"], d["b"], d["n"], d["Theta"], d["alpha2"]):
        gamma, K = printed[float(n)]
        assert a == pytest.approx(1.0 - gamma * (1.0 - math.cos(Theta)), rel=1e-12)
        assert b == pytest.approx(gamma * math.sin(Theta), rel=1e-12, abs=1e-15)
        phi = math.atan2(1.0, -n)
        assert alpha2 * math.sqrt(1.0 + n * n) * math.sin(phi - Theta) == pytest.approx(K * Theta, rel=1e-9, abs=1e-14)
