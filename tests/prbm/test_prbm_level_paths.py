"""The segment models' level kernels (``prbm.segments``: one implementation of each model's level
equations, evaluated level by level in plain floats for a case's few levels, once on numpy arrays past
``_SCALAR_LOOP_MAX`` levels) on both paths against an independent array evaluation of the same seed
equations written here with numpy, the spring equation (*) solved by the independent reference solver
``_spring_angle_reference`` (safeguarded Newton from phi, the previous solver).

* fixed-pinned: seed 000 eqs (41)-(49), mirrored about x for P < 0 with the fits at -n;
* two-spring fixed-guided: seed 000 eq (63) / seed 004, (F l^2/EI) sin(phi - Theta) = 4 K_Theta Theta,
  M = -(k Theta + (1 - gamma) l P/2);
* initially curved fixed-pinned: seed 000 eqs (53)-(61) with the assumptions of the module docstring;
* pure moment: seed 004's closed form and the exact arc.

Both solvers stop at a Newton step below 1e-13 (1 + |Theta|), so Theta and what follows agree to 1e-12
relative; a planted error in any equation (a sign, a factor) fails by far more.  The loads cover both
signs of P, P = 0, several load ratios (the per-ratio caches see more than one entry); a level solved
alone (plain floats) equals the same level among 300 (arrays) to 1e-12 (the two spring iterations may
stop one Newton step apart), and ``fixed_guided_monotonic_tip`` is the curved solve with
kappa0 = M l/EI + l/R_i level by level (seed 000 eq (62)).
"""

import math

import numpy as np
import pytest

import prbm
from prbm.segments import _SCALAR_LOOP_MAX, _spring_angle_reference

P10 = np.array([0.0, 0.3, 1.0, 2.5, -1.7, 4.0, 7.5, -0.2, 10.0, 3.3])
N10 = np.array([0.0, 0.0, 0.5, -0.4, 0.5, 2.0, 0.0, -1.2, 0.5, 9.0])
P, N = P10, N10
RTOL = 1e-12
# the level loop (10 levels) and the array evaluation (past the loop's limit) of the same kernels
COUNTS = [10, _SCALAR_LOOP_MAX + 14]


def _levels(count: int) -> tuple[np.ndarray, np.ndarray]:
    return np.resize(P10, count), np.resize(N10, count)


def _close(got, expected) -> bool:
    """Equal to RTOL (relative, absolute below 1); NaN only where the expectation is NaN (Howell's fits
    publish no c_theta, so theta0 is not available)."""
    got, expected = np.asarray(got, float), np.asarray(expected, float)
    both_nan = np.isnan(got) & np.isnan(expected)
    near = np.abs(got - expected) <= RTOL * np.maximum(np.abs(expected), 1.0)
    return got.shape == expected.shape and bool(np.all(both_nan | near))


def _mirrored(P, n, family):
    sign = np.where(P < 0.0, -1.0, 1.0)
    n_eff = sign * n
    gamma, c_theta, K = prbm.fit_family(family).parameters(n_eff)
    return sign, n_eff, gamma, c_theta, K


@pytest.mark.parametrize("count", COUNTS)
@pytest.mark.parametrize("family", ["pauly-midha", "howell"])
def test_fixed_pinned_kernel_equals_the_seed_equations(family, count):
    P, N = _levels(count)
    n = np.clip(N, -0.9, 9.0)  # inside both families' ranges
    length, EI = 2.0, 3.0
    r = prbm.fixed_pinned_tip(P, n, length=length, EI=EI, family=family)
    sign, n_eff, gamma, c_theta, K = _mirrored(P, n, family)
    F = np.abs(P) * np.sqrt(1.0 + n_eff**2)  # eq (46)
    Theta, ok, _ = _spring_angle_reference(F * length**2 / EI, np.arctan2(1.0, -n_eff), K)  # eq (47)
    assert ok.all() and r.converged and np.array_equal(r.level_converged, np.ones(len(P), bool))
    expected = {
        "a": length - gamma * length * (1.0 - np.cos(Theta)),  # eq (48)
        "b": sign * gamma * length * np.sin(Theta),  # eq (49)
        "theta0": sign * c_theta * Theta,
        "Theta": sign * Theta,
        "F": F,
    }  # eq (44)
    for key, value in expected.items():
        assert _close(r[key], value), key
    assert _close(r.constants["gamma"], gamma) and _close(r.constants["K_theta"], K)
    assert _close(r.constants["k"], gamma * K * EI / length)  # eq (45)


@pytest.mark.parametrize("count", COUNTS)
@pytest.mark.parametrize("family", ["pauly-midha", "howell"])
def test_fixed_guided_kernel_equals_the_seed_equations(family, count):
    P, N = _levels(count)
    n = np.clip(N, -0.9, 9.0)
    length, EI = 2.0, 3.0
    r = prbm.fixed_guided_tip(P, n, length=length, EI=EI, family=family)
    sign, n_eff, gamma, _, K = _mirrored(P, n, family)
    k = 2.0 * gamma * K * EI / length  # eq (63): each spring
    F = np.abs(P) * np.sqrt(1.0 + n_eff**2)
    Theta, ok, _ = _spring_angle_reference(F * gamma * length, np.arctan2(1.0, -n_eff), 2.0 * k)
    assert ok.all() and r.converged
    expected = {
        "a": length - gamma * length * (1.0 - np.cos(Theta)),
        "b": sign * gamma * length * np.sin(Theta),
        "theta0": np.zeros(len(P)),
        "Theta": sign * Theta,
        "M": -sign * (k * Theta + (1.0 - gamma) * length * np.abs(P) / 2.0),
    }
    for key, value in expected.items():
        assert _close(r[key], value), key
    assert _close(r.constants["k_each"], k)
    # the spring equation in the seed's form: (F l^2/EI) sin(phi - Theta) = 4 K_Theta Theta
    residual = F * length**2 / EI * np.sin(np.arctan2(1.0, -n_eff) - Theta) - 4.0 * K * Theta
    assert np.all(np.abs(residual) <= 1e-10 * (1.0 + F * length**2 / EI))


@pytest.mark.parametrize("count", COUNTS)
@pytest.mark.parametrize("curvature", [0.0, 0.4, -0.9])
def test_curved_kernel_equals_the_seed_equations(curvature, count):
    P, N = _levels(count)
    length, EI = 1.5, 2.0
    r = prbm.curved_fixed_pinned_tip(P, N, length=length, EI=EI, curvature=curvature)
    gamma, c_theta, K = prbm.PAULY_MIDHA.parameters(np.where(P < 0.0, -N, N))
    kappa0 = curvature * length  # eq (53)
    if kappa0 == 0.0:
        a_i, b_i = length, 0.0
    else:
        a_i, b_i = length / kappa0 * math.sin(kappa0), length / kappa0 * (1.0 - math.cos(kappa0))  # (55)-(56)
    Theta_i = np.arctan2(b_i, a_i - length * (1.0 - gamma))  # eq (54)
    rho = np.hypot(a_i / length - (1.0 - gamma), b_i / length)  # eq (57)
    k = rho * K * EI / length  # eq (58)
    phi = np.where(P == 0.0, Theta_i, np.arctan2(P, -N * P))
    phi = Theta_i + np.angle(np.exp(1j * (phi - Theta_i)))
    F = np.abs(P) * np.sqrt(1.0 + N**2)
    Theta, ok, _ = _spring_angle_reference(F * rho * length, phi, k, Theta_i)
    assert ok.all() and r.converged
    expected = {
        "a": length - gamma * length + rho * length * np.cos(Theta),  # eq (59)
        "b": rho * length * np.sin(Theta),  # eq (60)
        "theta0": kappa0 + c_theta * (Theta - Theta_i),
        "Theta": Theta,
    }
    for key, value in expected.items():
        assert _close(r[key], value), key
    for key, value in {"Theta_i": Theta_i, "rho": rho, "k": k}.items():
        assert _close(r.constants[key], value), key


@pytest.mark.parametrize("count", [5, _SCALAR_LOOP_MAX + 5])
def test_pure_moment_kernel_equals_the_closed_form(count):
    M, length, EI = np.resize([0.0, 0.5, -1.2, 3.0, 1e-9], count), 1.3, 0.7
    r = prbm.pure_moment_tip(M, length=length, EI=EI)
    Theta = M / (1.5164 * EI / length)  # seed 004: k = 1.5164 EI/L
    assert _close(r["a"], length - 0.7346 * length * (1.0 - np.cos(Theta)))  # gamma = 0.7346
    assert _close(r["b"], 0.7346 * length * np.sin(Theta))
    assert _close(r["theta0"], 1.5164 * Theta)  # = M l/EI
    theta = M * length / EI
    safe = np.where(theta == 0.0, 1.0, theta)
    assert _close(r["a_exact"], np.where(theta == 0.0, length, length / safe * np.sin(theta)))
    assert _close(r["b_exact"], np.where(theta == 0.0, 0.0, length / safe * (1.0 - np.cos(theta))))


@pytest.mark.parametrize("model", [prbm.fixed_pinned_tip, prbm.fixed_guided_tip, prbm.curved_fixed_pinned_tip])
def test_a_level_alone_equals_the_same_level_among_many(model):
    kw = {"length": 1.1, "EI": 0.8} | ({"curvature": 0.3} if model is prbm.curved_fixed_pinned_tip else {})
    many = model(*_levels(300), **kw)
    for i in range(10):
        alone = model(float(P10[i]), float(N10[i]), **kw)
        for key in ("a", "b", "theta0", "Theta"):
            assert _close(float(alone[key]), many[key][i]) and many[key][i] == many[key][i + 10], (i, key)
        assert bool(alone.converged) and many.level_converged[i]


def test_monotonic_equals_the_curved_solve_level_by_level():
    M = np.array([0.2, 0.0, 1.5, -0.3, 0.8, 0.1, 2.0, -1.0, 0.4, 0.05])
    res = prbm.fixed_guided_monotonic_tip(P, N, M, length=1.2, EI=0.9, curvature=0.3)
    for i in range(len(P)):
        kappa0 = M[i] * 1.2 / 0.9 + 0.3 * 1.2
        one = prbm.curved_fixed_pinned_tip(P[i], N[i], length=1.2, EI=0.9, curvature=kappa0 / 1.2)
        for key in ("a", "b", "theta0", "Theta"):
            assert res.outputs[key][i] == float(one.outputs[key]), (i, key)
        assert res.constants["kappa0"][i] == one.constants["kappa0"]
        assert res.level_converged[i] == one.converged
    assert np.array_equal(res.outputs["M"], M)
