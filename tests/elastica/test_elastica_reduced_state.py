"""What the faster shooting leaves out must not change the answer (issue 15, the compiled elastica).

* The sensitivities to the distributed load (wx, wy) are integrated only when the continuation
  changes that load. A beam under self-weight and a tip force reached from the weighted beam
  (only the force continued: the reduced 17-component state) must equal the same beam reached
  from the unloaded beam (both continued: the full 25-component state), and both the slow
  reference: scipy's Python DOP853 on the plain equations m' = Nx sin(theta) - Ny cos(theta),
  N(s) = F + w (1 - s), with ``scipy.optimize.root`` on m(1) = 0 (no code shared with the kernel).
* The shape is sampled on the plain state (x, y, theta, m, U): its end must be the shooting's tip,
  and its interior scipy's dense output of the plain equations from the same root moment.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from elastica import ElasticaProblem, solve_path

TOL = 1e-10


def _plain_rhs(F, w):
    def rhs(s, Y):
        Nx, Ny = F[0] + w[0] * (1 - s), F[1] + w[1] * (1 - s)
        return [math.cos(Y[2]), math.sin(Y[2]), Y[3], Nx * math.sin(Y[2]) - Ny * math.cos(Y[2])]

    return rhs


def _slow_tip(F, w, bracket):
    """(x, y, theta) and m(0) of the cantilever (L = EI = 1, free tip: m(1) = 0) by shooting on m(0)
    with scipy's DOP853 and a bracketing root find on m(1)."""

    def m_tip(m0):
        sol = solve_ivp(_plain_rhs(F, w), (0.0, 1.0), [0.0, 0.0, 0.0, m0], method="DOP853", rtol=1e-13, atol=1e-14)
        return sol.y[3, -1]

    m0 = brentq(m_tip, *bracket, xtol=1e-14)
    sol = solve_ivp(_plain_rhs(F, w), (0.0, 1.0), [0.0, 0.0, 0.0, m0], method="DOP853", rtol=1e-13, atol=1e-14)
    return sol.y[:3, -1], m0


@pytest.mark.parametrize(
    "force, weight",
    [
        ((0.0, -2.0), (0.0, -3.0)),  # tip load and self-weight the same way
        ((1.5, 1.0), (0.0, -4.0)),  # tension and an opposing tip force
    ],
)
def test_weighted_beam_without_the_load_sensitivities_matches_with_them(force, weight):
    weighted = ElasticaProblem(distributed=weight)
    target = ElasticaProblem(distributed=weight, force=force)
    both = solve_path(target)  # w and F continued: full state
    only_force = solve_path(target, start=solve_path(weighted))  # w constant: reduced state
    assert both.converged and only_force.converged
    tip, m0 = _slow_tip(force, weight, (-20.0, 20.0))
    for res in (both, only_force):
        assert np.allclose([res.x, res.y, res.theta], tip, rtol=0, atol=TOL), ([res.x, res.y, res.theta], tip)
        assert abs(res.reaction[2] + m0) <= TOL * max(1.0, abs(m0))  # clamp moment = -m(0)


def test_shape_samples_on_the_plain_state_match_scipy_and_end_at_the_tip():
    res = solve_path(ElasticaProblem(force=(1.0, 4.0), curvature=0.0, distributed=(0.0, -1.5)), n_samples=33)
    assert res.converged
    m0 = -res.reaction[2]
    ref = solve_ivp(
        _plain_rhs(res.force, (0.0, -1.5)),
        (0.0, 1.0),
        [0.0, 0.0, 0.0, m0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-14,
        dense_output=True,
    )
    np.testing.assert_allclose(res.shape, ref.sol(res.s)[:3], rtol=0, atol=1e-10)
    np.testing.assert_allclose(res.shape[:, -1], [res.x, res.y, res.theta], rtol=0, atol=1e-11)
