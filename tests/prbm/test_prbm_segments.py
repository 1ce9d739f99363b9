"""Invariants of the segment PRBMs: inverse of forward, vectorised = scalar, mirror symmetry, limits."""

import math
import time

import numpy as np
import pytest

import prbm


def test_fixed_pinned_equilibrium_and_kinematics_hold():
    r = prbm.fixed_pinned_tip(np.array([0.5, 2.0, 3.0]), 0.5, length=2.0, EI=3.0)
    g, c, K = (r.constants[k] for k in ("gamma", "c_theta", "K_theta"))
    Th = r["Theta"]
    F = r["P"] * math.sqrt(1 + 0.25)
    phi = math.atan2(1, -0.5)
    assert np.allclose(F * 4.0 / 3.0 * np.sin(phi - Th), K * Th, atol=1e-12)  # eqs (46)-(47)
    assert np.allclose(r["a"], 2.0 - g * 2.0 * (1 - np.cos(Th)))  # eq (48)
    assert np.allclose(r["b"], g * 2.0 * np.sin(Th))  # eq (49)
    assert np.allclose(r["theta0"], c * Th)  # eq (44)
    assert r.converged and r.wall_time > 0


@pytest.mark.parametrize("n", [-3.5, -1.0, 0.0, 0.896, 4.0])
def test_fixed_pinned_inverse_recovers_the_load(n):
    P = np.array([0.1, 1.0, 2.5])
    fwd = prbm.fixed_pinned_tip(P, n, length=1.0, EI=1.0)
    for kw in ({"a": fwd["a"], "b": fwd["b"]}, {"theta0": fwd["theta0"]}):
        inv = prbm.fixed_pinned_from_tip(n=n, length=1.0, EI=1.0, **kw)
        assert np.allclose(inv["P"], P, rtol=1e-9)
    below = fwd["Theta"] < math.pi / 2  # b alone fixes Theta only up to 90 deg (asin)
    inv = prbm.fixed_pinned_from_tip(n=n, length=1.0, EI=1.0, b=fwd["b"][below])
    assert np.allclose(inv["P"], P[below], rtol=1e-9)


def test_vectorised_sweep_equals_scalar_solves():
    P = np.linspace(0.0, 5.0, 50)
    vec = prbm.fixed_pinned_tip(P, -0.673, length=10.0, EI=486.65)
    for i in (0, 7, 49):
        sc = prbm.fixed_pinned_tip(float(P[i]), -0.673, length=10.0, EI=486.65)
        assert vec["b"][i] == pytest.approx(float(sc["b"]), abs=1e-12)


def test_negative_force_mirrors_the_configuration():
    up = prbm.fixed_pinned_tip(2.0, 0.5, length=1.0, EI=1.0)
    down = prbm.fixed_pinned_tip(-2.0, -0.5, length=1.0, EI=1.0)  # same axial force -nP = -1
    assert float(down["b"]) == pytest.approx(-float(up["b"]))
    assert float(down["a"]) == pytest.approx(float(up["a"]))


# notes seed-ch2-4 section 4.4 (the notes' independent re-implementation of eqs 41-47, PRBM column):
# (n, P l^2/EI) -> (a/l, b/l, theta0 in degrees), printed to 4 and 2 decimals
NOTES_4_4 = [
    (-1.0, 1.5, (0.9510, 0.2880, 23.79)),
    (0.0, 0.5, (0.9854, 0.1571, 13.17)),
    (0.0, 3.0, (0.7453, 0.6075, 56.36)),
    (1.0, 1.5, (0.7363, 0.6094, 58.31)),
    (1.0, 3.0, (0.3337, 0.8187, 97.55)),
    (3.0, 1.5, (0.0871, 0.8183, 120.64)),
]


@pytest.mark.parametrize("n, load, expected", NOTES_4_4)
def test_fixed_pinned_against_independent_prbm_evaluation(n, load, expected):
    r = prbm.fixed_pinned_tip(load, n, length=1.0, EI=1.0)
    assert float(r["a"]) == pytest.approx(expected[0], abs=5e-5)
    assert float(r["b"]) == pytest.approx(expected[1], abs=5e-5)
    assert math.degrees(float(r["theta0"])) == pytest.approx(expected[2], abs=5e-3)


def test_pure_moment_rotation_is_exact_and_inverse_works():
    r = prbm.pure_moment_tip(np.array([0.5, 1.0, 2.0]), length=1.0, EI=1.0)
    assert np.allclose(r["theta0"], [0.5, 1.0, 2.0])
    inv = prbm.pure_moment_from_tip(length=1.0, EI=1.0, a=r["a"], b=r["b"])
    assert np.allclose(inv["M"], [0.5, 1.0, 2.0])


def test_curved_segment_unloaded_is_its_arc_and_straight_limit_matches():
    r = prbm.curved_fixed_pinned_tip(0.0, 0.0, length=1.0, EI=1.0, curvature=0.5)
    assert float(r["theta0"]) == pytest.approx(0.5)
    assert float(r["a"]) == pytest.approx(2 * math.sin(0.5))
    assert float(r["b"]) == pytest.approx(2 * (1 - math.cos(0.5)))
    s = prbm.fixed_pinned_tip(1.5, 0.3, length=1.0, EI=1.0)
    c = prbm.curved_fixed_pinned_tip(1.5, 0.3, length=1.0, EI=1.0, curvature=1e-12)
    assert float(c["b"]) == pytest.approx(float(s["b"]), abs=1e-9)


def test_fixed_guided_small_deflection_end_moment_is_minus_pl_over_two():
    """Small deflection: M -> -P l/2 (statics of the guided beam); eq (63) linearised, 4 K_Theta Theta =
    P l^2/EI, gives b = gamma l Theta = gamma/(4 K_Theta) P l^3/EI with the n = 0 constants of eqs (41),
    (43) (0.851892, 2.648834), which is within 4 % of the exact linear-theory guided deflection P l^3/(12 EI)."""
    P, length, EI = 1e-6, 2.0, 3.0
    r = prbm.fixed_guided_tip(P, 0.0, length=length, EI=EI)
    assert float(r["M"]) == pytest.approx(-P * length / 2, rel=1e-4)
    assert float(r["theta0"]) == 0.0
    derived = 0.851892 / (4 * 2.648834) * P * length**3 / EI
    assert float(r["b"]) == pytest.approx(derived, rel=1e-6)
    assert float(r["b"]) == pytest.approx(P * length**3 / (12 * EI), rel=0.04)
    assert float(prbm.fixed_guided_tip(-P, 0.0, length=length, EI=EI)["b"]) == pytest.approx(-derived, rel=1e-6)


def test_slfp_straight_geometry_and_equilibrium():
    r = prbm.slfp_tip(2.0, 0.0, flexure_length=0.1, rigid_length=1.0, EI=0.5)
    Th = float(r["Theta"])
    assert 5.0 * Th == pytest.approx(2.0 * 1.05 * math.cos(Th))  # eq (76), k = EI/l = 5
    assert float(r["a"]) == pytest.approx(0.05 + 1.05 * math.cos(Th))  # eq (74)


def test_curved_pinned_pinned_tension_opens_compression_closes():
    """Derived from eqs (53)-(58) on each half (h = l/2, kappa0 = h/R_i; gamma = 0.85, K_Theta = 2.65, the
    documented defaults): unloaded chord 2 a_i = 2 (h/kappa0) sin kappa0; for a small chord force F,
    k dTheta = -F rho h sin Theta_i with k = rho K_Theta EI/h, so d(chord)/dF = 2 (rho h sin Theta_i)^2 / k."""
    F = 1e-6
    r = prbm.curved_pinned_pinned(np.array([0.0, F, -F, 1.0, -1.0]), length=1.0, EI=1.0, curvature=1.0)
    chord = r["chord"]
    assert chord[3] > chord[0] > chord[4]
    h, kappa0, gamma, K = 0.5, 0.5, 0.85, 2.65
    a_i, b_i = h / kappa0 * math.sin(kappa0), h / kappa0 * (1 - math.cos(kappa0))
    theta_i = math.atan2(b_i, a_i - h * (1 - gamma))
    rho = math.hypot(a_i / h - (1 - gamma), b_i / h)
    assert chord[0] == pytest.approx(2 * a_i, rel=1e-12)
    slope = 2 * (rho * h * math.sin(theta_i)) ** 2 / (rho * K / h)
    assert (chord[1] - chord[2]) / (2 * F) == pytest.approx(slope, rel=1e-5)


def test_composite_layers_and_capstan():
    EI = prbm.layered_bending_stiffness([(550e3, 2.5, 0.125), (30e6, 1.0, 0.025), (550e3, 2.5, 0.125)])
    assert EI == pytest.approx(486.6536, abs=1e-4)  # derived: 2 x 550e3 x 2.5 x 0.125^3/12 + 30e6 x 1 x 0.025^3/12
    assert prbm.capstan_factor(0.01, 3 * math.pi / 2) == pytest.approx(math.exp(-0.01 * 3 * math.pi / 2))
    dead = prbm.composite_beam_tip([4.0], 0.0, length=10.0, EI=EI)
    fol = prbm.composite_beam_tip([4.0], 0.0, length=10.0, EI=EI, follower=True)
    assert float(fol["b"][0]) > float(dead["b"][0])  # a follower force stays more transverse


def test_domain_cloud_and_boundaries():
    d = prbm.fixed_pinned_domain(n_values=np.array([-3.9, 0.0, 10.0]), n_theta=21)
    bc = prbm.boundary_curves(d["a"], d["b"], bins=10)
    assert np.all(bc["lower"] <= bc["upper"])
    m = d["n"] == 10.0
    assert prbm.fit_radius(d["a"][m], d["b"][m]) == pytest.approx(prbm.PAULY_MIDHA.gamma(10.0), abs=1e-6)


def test_four_bar_ma_by_coefficients_equals_instant_centres():
    fb = prbm.FourBar(2.8759 + 3.0196j, 2.3244 + 4.9847j, 6.2946 + 2.0370j, 5.7432 + 4.0020j)
    th = np.radians([60.0, 65.0, 85.0, 105.0])
    assert np.allclose(fb.rigid_ma(th, 5.0, 1.5), fb.rigid_ma(th, 5.0, 1.5, via="ic"), rtol=1e-10)


def test_four_bar_torque_is_the_energy_derivative():
    fb = prbm.FourBar(
        2.8759 + 3.0196j,
        2.3244 + 4.9847j,
        6.2946 + 2.0370j,
        5.7432 + 4.0020j,
        springs=(1.1204, 1.1204, 9.7441, 9.7441),
        theta_free=tuple(np.radians([55.0, -2.16, 10.17])),
    )
    th = math.radians(80.0)
    h = 1e-6
    dU = (fb.strain_energy(th + h) - fb.strain_energy(th - h)) / (2 * h)
    assert float(fb.input_torque(th)) == pytest.approx(float(dU), rel=1e-6)
    res = fb.positions_under_torque([5.0, 10.0])
    assert np.allclose(fb.input_torque(res["theta2"]), [5.0, 10.0], atol=1e-9)


def test_grubler_and_mode_table():
    assert prbm.grubler(4, 4) == 1
    topo = prbm.PRBMTopology(2, 0, [prbm.Segment("fixed-guided"), prbm.Segment("fixed-guided")])
    assert topo.min_dof() == 1 and topo.max_dof() == 3
    assert topo.expected_mode()["modes"] == (1, 1)


# the three code paths of fixed_pinned_tip: one level (plain floats), a few levels (plain floats level by
# level), many levels (numpy); 300 > segments._SCALAR_LOOP_MAX
PATHS = {"one": 1, "few": 3, "many": 300}


@pytest.mark.parametrize("path", PATHS)
def test_fixed_pinned_outputs_and_constants_on_every_path(path):
    """Seed 000 eqs (41)-(49) with the model's mirror convention (module docstring of prbm.segments): for
    P < 0 the configuration is mirrored about x and the fits are taken at the mirrored ratio -n, so the
    axial component -nP is kept; a level with P >= 0 uses n itself.  F = |P| sqrt(1 + n^2) (eq 46);
    k = gamma K_Theta EI / l (eq 45); the equilibrium (*) is solved by ``spring_angle``, whose iteration
    count the result reports (0 when no level is loaded: Theta = 0 needs none)."""
    count, n, length, EI = PATHS[path], 0.8, 2.5, 7.0
    P = np.linspace(0.3, 3.0, count)
    P_in = float(P[0]) if count == 1 else P
    up = prbm.fixed_pinned_tip(P_in, n, length=length, EI=EI)
    down = prbm.fixed_pinned_tip(-P_in, -n, length=length, EI=EI)  # the same axial force -nP
    g, c, K = prbm.PAULY_MIDHA.parameters(n)
    for r, sign in ((up, 1.0), (down, -1.0)):
        assert r.converged and r.message == "converged" and "seed 000 eqs (41)-(49)" in r.model
        assert np.allclose(r.constants["gamma"], g, rtol=0, atol=0) and np.allclose(r.constants["K_theta"], K, atol=0)
        assert np.allclose(r.constants["k"], g * K * EI / length, rtol=1e-15)  # eq (45)
        assert np.allclose(r["F"], P * math.sqrt(1 + n * n), rtol=1e-15)  # eq (46)
        assert np.array_equal(r["P"], sign * P_in) and np.array_equal(r["n"], sign * n)
        Theta, _, nit = prbm.spring_angle(P * math.sqrt(1 + n * n) * length**2 / EI, math.atan2(1, -n), K)
        assert np.allclose(r["Theta"], sign * Theta, rtol=1e-12)
        assert np.allclose(r["b"], sign * g * length * np.sin(Theta), rtol=1e-12)  # eq (49)
        assert np.allclose(r["a"], length - g * length * (1 - np.cos(Theta)), rtol=1e-12)  # eq (48)
        assert np.allclose(r["theta0"], sign * c * Theta, rtol=1e-12)  # eq (44)
        assert r.nit == nit and r.nit > 0
        assert np.array_equal(r.level_converged, np.ones(count, bool))
        assert np.asarray(r["a"]).dtype == np.float64 and np.asarray(r["P"]).dtype == np.float64


@pytest.mark.parametrize("path", ["few", "many"])
def test_fixed_pinned_unloaded_levels_take_the_fits_at_n_and_no_iteration(path):
    """P = 0 is not mirrored: the fits at the given n (eqs 41-43), Theta = 0 exactly, no iteration; integer
    loads come back as floats like every other output."""
    zeros = np.zeros(PATHS[path], dtype=int)
    r = prbm.fixed_pinned_tip(zeros, 1.0, length=1.0, EI=1.0)
    g, _, K = prbm.PAULY_MIDHA.parameters(1.0)
    assert np.all(r.constants["gamma"] == g) and np.all(r.constants["K_theta"] == K)
    assert np.all(r["Theta"] == 0.0) and np.all(r["a"] == 1.0) and r.nit == 0
    assert r["P"].dtype == r["n"].dtype == np.float64


@pytest.mark.parametrize("path", PATHS)
def test_fixed_pinned_passes_the_extrapolation_choice_on_every_path(path):
    """n = 12 is outside eqs (41)-(43)'s -4 < n <= 10: 'raise' refuses, 'warn' warns and evaluates."""
    P = 1.0 if PATHS[path] == 1 else np.linspace(0.5, 1.0, PATHS[path])
    with pytest.raises(prbm.FitRangeError):
        prbm.fixed_pinned_tip(P, 12.0, length=1.0, EI=1.0)
    with pytest.warns(prbm.FitRangeWarning):
        r = prbm.fixed_pinned_tip(P, 12.0, length=1.0, EI=1.0, extrapolate="warn")
    assert r.converged


def test_fixed_pinned_keeps_the_shape_of_the_load_and_times_itself():
    P = np.linspace(0.1, 1.2, 6).reshape(2, 3)
    t0 = time.perf_counter()
    r = prbm.fixed_pinned_tip(P, 0.0, length=1.0, EI=1.0)
    elapsed = time.perf_counter() - t0
    assert r["a"].shape == r["b"].shape == r["Theta"].shape == (2, 3)
    assert 0.0 <= r.wall_time <= elapsed
