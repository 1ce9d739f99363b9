"""A force toward a fixed point (``planar.PointedForce``, a rope over a pulley) in the PRB network solver.

* One rigid link of length a pinned to the ground at the origin, a torsion spring k, a rope at its tip
  pulling with T toward P, turned by an angle: equilibrium k phi = (p - O) x F(p), p = a (cos phi, sin phi),
  F = T R(angle) (P - p)/|P - p|, one scalar equation solved here by brentq (derived here, independent of
  the network's Lagrange/Newton solve).
* The generalised force's derivative dQ/dq the Newton step uses, against central differences of Q: a sign
  or a missing term in it would slow or stop the Newton iteration without changing a converged answer.
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import planar
import prbm
from prbm.network import _Problem
from validation.case.schema import Case
from validation.run import coverage
from validation.run.runner import run_method

A_LEN, K = 1.5, 4.0


def _link() -> prbm.Network:
    return prbm.Network(
        bodies=["link"],
        points={"tip": ("link", (A_LEN, 0.0))},
        pins=[planar.Pin("link", planar.GROUND, (0.0, 0.0))],
        springs=[prbm.TorsionSpring("link", planar.GROUND, K)],
        origins={"link": (0.0, 0.0)},
    )


def _exact_phi(T: float, toward: tuple[float, float], angle: float) -> float:
    def moment(phi: float) -> float:
        p = A_LEN * np.array([math.cos(phi), math.sin(phi)])
        d = np.asarray(toward) - p
        c, s = math.cos(angle), math.sin(angle)
        F = T * np.array([c * d[0] - s * d[1], s * d[0] + c * d[1]]) / np.hypot(*d)
        return K * phi - (p[0] * F[1] - p[1] * F[0])

    return brentq(moment, -1.5, 1.5, xtol=1e-14)


@pytest.mark.parametrize(
    "T, toward, angle",
    [
        (3.0, (0.0, 2.0), 0.0),  # a rope up to a pulley above the pivot
        (2.0, (3.0, -1.0), 0.0),  # ahead and below
        (1.5, (0.5, 1.0), 0.4),  # turned from the line
    ],
)
def test_a_pinned_link_pulled_by_a_rope_turns_as_its_moment_balance_says(T, toward, angle):
    exact = _exact_phi(T, toward, angle)
    values = tuple(T * (k + 1) / 4 for k in range(4))
    res = prbm.solve(_link(), [planar.PointedForce("tip", values, toward, angle)], 4)
    assert res.converged, res.message
    phi = res.states[-1].q[2]
    assert abs(exact) > 0.1
    assert phi == pytest.approx(exact, abs=1e-10)


def test_the_derivative_of_the_pull_is_that_of_its_generalised_force():
    net = _link()
    pf = planar.PointedForce("tip", (2.0,), (0.7, 1.9), 0.3)
    problem = _Problem(net, [pf], 1)
    q = np.array([0.05, -0.03, 0.4])
    _, dQ = problem.generalised_forces(q, 0.0)
    h = 1e-6
    numeric = np.column_stack(
        [
            (problem.generalised_forces(q + h * e, 0.0)[0] - problem.generalised_forces(q - h * e, 0.0)[0]) / (2 * h)
            for e in np.eye(3)
        ]
    )
    assert np.allclose(dQ, numeric, atol=1e-8)


@pytest.mark.parametrize("boundary", ["parallel-guided mechanism", "circular-guided mechanism"])
def test_the_prbm_adapter_pulls_a_mechanism_point_along_its_solved_line(boundary):
    """Through the adapter (the PRB network built from the geometry): the force received at the pulled point
    is T (P - p)/|P - p| with p the PRB model's own solved position of that point, and the point moved."""
    data = coverage.minimal_case("force toward a point", boundary, "prbm")
    load = data["loads"][0]
    point, toward, T = load["point"], np.array(load["toward"]), load["values"][0]
    data["outputs"] = [{"quantity": q, "point": point} for q in ("x", "y", "dx", "dy", "force_x", "force_y")]
    run = run_method(Case.model_validate(data), "prbm")
    assert run.ok, run.message
    got = {req.quantity: v for req, v in run.values.items()}
    p = np.array([got["x"], got["y"]])
    assert np.hypot(got["dx"], got["dy"]) > 0.01
    expected = T * (toward - p) / np.linalg.norm(toward - p)
    assert np.allclose([got["force_x"], got["force_y"]], expected, atol=1e-9)
