"""The compiled DOP853 of the elastica against scipy's solve_ivp(DOP853) on the same right-hand side,
and whole shooting solves against the same solves integrated by scipy (the solver before #15)."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from elastica import shooting
from elastica.integrator import STATE_SIZE, elastica_rhs, integrate_dop853


def _rhs(k0):
    def f(s, Y, Fx, Fy):
        out = np.empty(STATE_SIZE)
        elastica_rhs(s, Y, Fx, Fy, k0, out)
        return out
    return f


@pytest.mark.parametrize("m0, Fx, Fy, k0, a, b", [
    (-10.0, 0.0, 10.0, 0.0, 0.0, 1.0),         # cantilever, PL^2/EI = 10
    (6.283, 0.0, 0.0, 0.0, 0.0, 1.0),          # roll-up moment
    (2.0, -3.0, 1.5, 0.4, 0.3, 0.9),           # curved, compressed, a piece between two sites
])
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
        fd = (plus[:4] - minus[:4]) / (2 * h)      # x, y, theta, m
        np.testing.assert_allclose(S[:, k], fd, rtol=1e-6, atol=1e-7)


class _ScipyShooter(shooting._Shooter):
    """Today's shooter before the compiled integrator: every integration by solve_ivp(DOP853)."""

    def integrate(self, z, q, dense=False):
        return super().integrate(z, q, dense=True)


@pytest.mark.parametrize("kwargs", [
    dict(force=(0.0, 10.0)),                                   # cantilever PL^2/EI = 10
    dict(force=(-2.0, 3.0), moment=-1.0, curvature=0.5),      # curved, combined loads
    dict(moment=2 * np.pi),                                    # full roll-up
    dict(follower=(0.0, 4.0)),                                 # follower force
])
def test_shooting_with_the_compiled_integrator_agrees_with_scipy_to_1e10(kwargs, monkeypatch):
    fast = shooting.solve_elastica(**kwargs)
    monkeypatch.setattr(shooting, "_Shooter", _ScipyShooter)
    slow = shooting.solve_elastica(**kwargs)
    assert fast.converged and slow.converged
    for key in ("x", "y", "theta", "strain_energy"):
        assert abs(getattr(fast, key) - getattr(slow, key)) <= 1e-10, key
    np.testing.assert_allclose(fast.force + (fast.moment,), slow.force + (slow.moment,), rtol=0, atol=1e-10)


def test_sampled_shape_matches_scipys_dense_output():
    from elastica.integrator import integrate_samples

    y0 = np.zeros(STATE_SIZE)
    y0[3], y0[14] = -4.0, 1.0
    s = np.linspace(0.0, 1.0, 41)
    ref = solve_ivp(_rhs(0.3), (0.0, 1.0), y0, method="DOP853", rtol=1e-12, atol=1e-13, args=(1.0, 4.0),
                    dense_output=True)
    got, ok = integrate_samples(y0, s, 1.0, 4.0, 0.3, 1e-12, 1e-13)
    assert ok
    np.testing.assert_allclose(got.T, ref.sol(s), rtol=0, atol=1e-10)
