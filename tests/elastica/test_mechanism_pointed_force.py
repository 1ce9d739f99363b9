"""A force toward a fixed point (a rope over a pulley) in the mechanism elastica (``elastica.mechanism``)
against the same problem solved by the segment shooting (``elastica.shooting``, its own pointed-force
conditions): two independent codes, one exact elastica, so they agree to their tolerances.

A cantilever of length L, EI, clamped at the origin along x, its free tip pulled by T toward P. The
mechanism elastica holds the pointed force's direction at the current tip in its residual; the shooting
solves for the direction angle as an unknown with one extra condition."""

import math

import numpy as np
import pytest

from elastica import mechanism as em
from elastica.shooting import ElasticaProblem, PointedForce, solve_path
import planar

L, EI = 2.0, 3.0


def _mechanism_tip(T: float, toward: tuple[float, float], angle: float, levels: int = 3):
    mech = em.Mechanism(
        {"root": (0.0, 0.0), "tip": (L, 0.0)},
        [em.ElasticBeam("b", "root", "tip", EI, em.GROUND, None, "clamped", "free")],
    )
    values = tuple(T * (k + 1) / levels for k in range(levels))
    sol = em.solve_mechanism(mech, [planar.PointedForce("tip", values, toward, angle)], levels)
    assert sol.converged, sol.message
    return sol.positions[-1]["tip"]


def _shooting_tip(T: float, toward: tuple[float, float], angle: float):
    problem = ElasticaProblem(length=L, EI=EI, pointed=(PointedForce(T, toward, angle),))
    res = solve_path(problem)
    assert res.converged, res.message
    return np.array([res.x, res.y])


@pytest.mark.parametrize(
    "T, toward, angle",
    [
        (2.0, (0.5, -1.5), 0.0),  # a rope to a pulley below the beam: large deflection
        (2.5, (3.0, 2.0), 0.0),  # ahead and above
        (3.0, (0.0, -1.0), math.pi / 2),  # kept perpendicular to the line to a fixed pivot
    ],
)
def test_the_mechanism_elastica_pulls_toward_the_point_as_the_shooting_does(T, toward, angle):
    exact = _shooting_tip(T, toward, angle)
    tip = _mechanism_tip(T, toward, angle)
    assert np.hypot(*(exact - np.array([L, 0.0]))) > 0.1 * L  # a large deflection, not a linear one
    assert np.linalg.norm(tip - exact) < 1e-7 * L


def test_the_pull_is_along_the_solved_line_not_the_unloaded_one():
    """A dead force along the unloaded tip-to-point line lands elsewhere: the direction follows the tip."""
    T, toward = 2.0, (0.5, -1.5)
    tip = _mechanism_tip(T, toward, 0.0)
    d = np.array(toward) - np.array([L, 0.0])
    d = T * d / np.linalg.norm(d)
    mech = em.Mechanism(
        {"root": (0.0, 0.0), "tip": (L, 0.0)},
        [em.ElasticBeam("b", "root", "tip", EI, em.GROUND, None, "clamped", "free")],
    )
    dead = em.solve_mechanism(mech, [planar.Force("tip", (d[0],), (d[1],))], 1).positions[-1]["tip"]
    assert np.linalg.norm(dead - tip) > 1e-3 * L
