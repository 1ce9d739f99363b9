"""The compiled DOP853 of the elastica and of a mechanism beam against scipy's solve_ivp(DOP853) on the
same right-hand side, and the elastica's variational equations against finite differences. (Whole
compiled shooting solves against closed forms and a slow scipy reference: test_elastica_compiled.py.)"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from elastica.integrator import (
    STATE_SIZE,
    Loads,
    beam_samples,
    elastica_beam,
    elastica_rhs,
    integrate_beam,
    integrate_samples,
)


def integrate_dop853(y0, a, b, Fx, Fy, k0, rtol, atol, wx=0.0, wy=0.0):
    """The compiled integration from s = a to s = b (one interval of ``integrate_samples``)."""
    states, ok = integrate_samples(y0, [a, b], Fx, Fy, k0, rtol, atol, wx, wy)
    return states[-1], ok


def _rhs(k0):
    def f(s, Y, Fx, Fy):
        out = np.empty(STATE_SIZE)
        elastica_rhs(s, Y, elastica_beam(k0), Loads(Fx=Fx, Fy=Fy, wx=0.0, wy=0.0), out)
        return out

    return f


@pytest.mark.parametrize(
    "m0, Fx, Fy, k0, a, b",
    [
        (-10.0, 0.0, 10.0, 0.0, 0.0, 1.0),  # cantilever, PL^2/EI = 10
        (6.283, 0.0, 0.0, 0.0, 0.0, 1.0),  # roll-up moment
        (2.0, -3.0, 1.5, 0.4, 0.3, 0.9),  # curved, compressed, a piece between two sites
    ],
)
def test_compiled_dop853_matches_scipy_to_rounding(m0, Fx, Fy, k0, a, b):
    y0 = np.zeros(STATE_SIZE)
    y0[3], y0[14], y0[2] = m0, 1.0, 0.2
    for rtol in (1e-7, 1e-12):
        ref = solve_ivp(_rhs(k0), (a, b), y0, method="DOP853", rtol=rtol, atol=0.1 * rtol, args=(Fx, Fy))
        got, ok = integrate_dop853(y0, a, b, Fx, Fy, k0, rtol, 0.1 * rtol)
        assert ok and ref.success
        np.testing.assert_allclose(got, ref.y[:, -1], rtol=1e-12, atol=1e-12)


def test_rhs_matches_finite_differences_of_its_own_state():
    """The variational rows of elastica_rhs are the derivatives of its state rows w.r.t. (m0, Fx, Fy)
    and the distributed load (wx, wy): integrate, perturb each, and compare the end-state differences
    with the sensitivities."""
    y0 = np.zeros(STATE_SIZE)
    m0, Fx, Fy, wx, wy, h = -3.0, 1.0, 4.0, 0.5, -2.0, 1e-6
    y0[3], y0[14] = m0, 1.0
    base, _ = integrate_dop853(y0, 0.0, 1.0, Fx, Fy, 0.2, 1e-12, 1e-13, wx, wy)
    S = np.hstack([base[5:17].reshape(4, 3), base[17:].reshape(4, 2)])
    for k, step in enumerate(np.eye(5) * h):
        dm, dfx, dfy, dwx, dwy = step
        yp, ym = y0.copy(), y0.copy()
        yp[3] += dm
        ym[3] -= dm
        plus, _ = integrate_dop853(yp, 0.0, 1.0, Fx + dfx, Fy + dfy, 0.2, 1e-12, 1e-13, wx + dwx, wy + dwy)
        minus, _ = integrate_dop853(ym, 0.0, 1.0, Fx - dfx, Fy - dfy, 0.2, 1e-12, 1e-13, wx - dwx, wy - dwy)
        fd = (plus[:4] - minus[:4]) / (2 * h)  # x, y, theta, m
        np.testing.assert_allclose(S[:, k], fd, rtol=1e-6, atol=1e-7)


def _beam_rhs(Fx, Fy, k0, EI, EA):
    """The mechanism beam's equations as elastica/mechanism.py wrote them for scipy before issue 15."""

    def rhs(s, Y):
        th, m = Y[2], Y[3]
        c, sn = math.cos(th), math.sin(th)
        N = Fx * c + Fy * sn
        stretch = 1.0 + (N / EA if EA else 0.0)
        return [
            stretch * c,
            stretch * sn,
            k0 + m / EI,
            stretch * (Fx * sn - Fy * c),
            m * m / (2 * EI) + (N * N / (2 * EA) if EA else 0.0),
        ]

    return rhs


@pytest.mark.parametrize(
    "Fx, Fy, k0, EI, EA, L, m0",
    [
        (3.0, -2.0, 0.1, 2.5, 1e4, 1.3, 0.7),  # extensible, curved, combined load
        (0.5, 40.0, 0.0, 1.0, 0.0, 1.0, -40.0),  # inextensible (EA = 0), large deflection
        (-1e3, 5.0, 0.0, 3.0e3, 1e6, 0.05, 1.2),  # short stiff beam in compression
    ],
)
def test_compiled_mechanism_beam_matches_scipy_to_rounding(Fx, Fy, k0, EI, EA, L, m0):
    y0 = [0.1, 0.2, 0.3, m0, 0.0]
    atol = 1e-14 * max(L, 1.0)
    ref = solve_ivp(
        _beam_rhs(Fx, Fy, k0, EI, EA), (0.0, L), y0, method="DOP853", rtol=1e-11, atol=atol, dense_output=True
    )
    got, ok = integrate_beam(y0, L, Fx, Fy, k0, EI, EA, 1e-11, atol)
    assert ok and ref.success
    np.testing.assert_allclose(got, ref.y[:, -1], rtol=1e-12, atol=1e-12)
    s = np.linspace(0.0, L, 9)
    samples, ok = beam_samples(y0, s, Fx, Fy, k0, EI, EA, 1e-11, atol)
    assert ok
    np.testing.assert_allclose(samples.T, ref.sol(s), rtol=0, atol=1e-9)


def test_sampled_shape_matches_scipys_dense_output():
    y0 = np.zeros(STATE_SIZE)
    y0[3], y0[14] = -4.0, 1.0
    s = np.linspace(0.0, 1.0, 41)
    ref = solve_ivp(
        _rhs(0.3), (0.0, 1.0), y0, method="DOP853", rtol=1e-12, atol=1e-13, args=(1.0, 4.0), dense_output=True
    )
    got, ok = integrate_samples(y0, s, 1.0, 4.0, 0.3, 1e-12, 1e-13)
    assert ok
    np.testing.assert_allclose(got.T, ref.sol(s), rtol=0, atol=1e-10)


def test_mechanism_end_states_kept_by_their_inputs_are_the_integrations_of_those_inputs():
    """The mechanism keeps each beam's last few end states by the beam's inputs (start pose, force): a
    finite-difference Jacobian moves one unknown at a time. Going back and forth between inputs, every
    end state returned is the compiled integration of the inputs asked for, to the bit (a key that
    missed an input, e.g. Fy, would hand back another state), and the kept states stay bounded."""
    from elastica.mechanism import _ENDS_KEPT, GROUND, ElasticBeam, Mechanism, _System

    beam = ElasticBeam("b", "A", "B", EI=2.0, start_body=GROUND, end_body=None, end_kind="free", curvature=0.3)
    system = _System(Mechanism({"A": (0.0, 0.0), "B": (1.0, 0.0)}, [beam]), [], [], [], [], 1e-11)
    angle0, _, length = system.tangent0["b"]
    states = [
        np.array([Fx, Fy, m0])
        for Fx, Fy, m0 in [
            (0.0, 1.0, 0.5),
            (0.0, 1.0 + 1e-7, 0.5),
            (1e-7, 1.0, 0.5),
            (0.0, 1.0, 0.5 + 1e-7),
            (0.0, 1.0, 0.5),
            (0.3, -2.0, 0.1),
            (0.0, 1.0 + 1e-7, 0.5),
            (0.0, 1.0, 0.5),
        ]
    ]
    for u in states:
        got = system.integrate(beam, u)
        ref, ok = integrate_beam(
            [0.0, 0.0, angle0, u[2], 0.0], length, u[0], u[1], 0.3, 2.0, 0.0, 1e-11, 1e-14 * max(length, 1.0)
        )
        assert ok
        np.testing.assert_array_equal(got, ref)
    assert len(system._ends["b"]) <= _ENDS_KEPT
