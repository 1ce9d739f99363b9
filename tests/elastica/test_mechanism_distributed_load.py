"""A uniform dead load along a mechanism beam (``planar.DistributedLoad``) in the mechanism elastica,
against the segment shooting (``elastica.shooting``, ``distributed``): the same cantilever, two codes with
their own unknowns and end conditions (the mechanism: the end force, the start moment and the body
balances; the shooting: the root's loads), one exact elastica, so tip and root reaction agree to their
tolerances. The root reaction also checks the force the beam applies at its start, F + w L."""

import numpy as np
import pytest

import planar
from elastica import mechanism as em
from elastica.shooting import ElasticaProblem, solve_path

L, EI = 2.0, 3.0


@pytest.mark.parametrize("w", [(0.0, -2.5), (1.0, 1.5), (-0.8, -0.6)])
def test_a_cantilever_under_a_uniform_load_as_the_shooting_solves_it(w):
    mech = em.Mechanism(
        {"root": (0.0, 0.0), "tip": (L, 0.0)},
        [em.ElasticBeam("b", "root", "tip", EI, em.GROUND, None, "clamped", "free")],
    )
    levels = 3
    wx = tuple(w[0] * (k + 1) / levels for k in range(levels))
    wy = tuple(w[1] * (k + 1) / levels for k in range(levels))
    sol = em.solve_mechanism(mech, [planar.DistributedLoad("b", wx, wy)], levels)
    assert sol.converged, sol.message
    exact = solve_path(ElasticaProblem(length=L, EI=EI, distributed=w))
    assert exact.converged, exact.message
    tip = sol.positions[-1]["tip"]
    assert np.hypot(exact.x - L, exact.y) > 0.1 * L  # a large deflection
    assert np.linalg.norm(tip - [exact.x, exact.y]) < 1e-7 * L
    Fx, Fy, M0 = sol.start_loads[-1]["b"]  # what the beam applies to the clamp
    assert np.allclose([-Fx, -Fy], exact.reaction[:2], atol=1e-8 * np.hypot(*w) * L)
    assert -M0 == pytest.approx(exact.reaction[2], abs=1e-8 * np.hypot(*w) * L * L)
    assert np.allclose([-Fx, -Fy], -np.asarray(w) * L, atol=1e-12)  # R = -w L: nothing else loads it


def test_a_load_on_an_unknown_beam_is_refused_by_name():
    mech = em.Mechanism(
        {"root": (0.0, 0.0), "tip": (L, 0.0)},
        [em.ElasticBeam("b", "root", "tip", EI, em.GROUND, None, "clamped", "free")],
    )
    with pytest.raises(ValueError, match="'c', which is no beam"):
        em.solve_mechanism(mech, [planar.DistributedLoad("c", (1.0,), (0.0,))], 1)


@pytest.mark.parametrize("w", [(3.0, 0.0), (1.0, -2.0)])
def test_a_beam_loaded_along_it_gives_the_same_guide_whichever_end_it_starts_from(w):
    """A parallel guide (two beams from the ground to a coupler) under a uniform load along both beams,
    once with both beams defined from the ground and once with one defined from the coupler: the same
    mechanism, so the same coupler pose. The second puts the load along the beam on the body at the beam's
    start (F + w L), which the first never exercises."""
    nodes = {"G1": (0.0, 0.0), "G2": (0.5, 0.0), "C1": (0.0, 1.0), "C2": (0.5, 1.0)}
    coupler = [em.RigidBody("coupler", ("C1", "C2"))]

    def beam(name, start, end, start_body, end_body):
        return em.ElasticBeam(name, start, end, 1.0, start_body, end_body, "clamped", "clamped", 1e4)

    levels = 2
    loads = [
        planar.DistributedLoad(
            b,
            tuple(w[0] * (k + 1) / levels for k in range(levels)),
            tuple(w[1] * (k + 1) / levels for k in range(levels)),
        )
        for b in ("b1", "b2")
    ]
    from_ground = em.Mechanism(
        nodes, [beam("b1", "G1", "C1", em.GROUND, "coupler"), beam("b2", "G2", "C2", em.GROUND, "coupler")], coupler
    )
    from_coupler = em.Mechanism(
        nodes, [beam("b1", "G1", "C1", em.GROUND, "coupler"), beam("b2", "C2", "G2", "coupler", em.GROUND)], coupler
    )
    a = em.solve_mechanism(from_ground, loads, levels)
    b = em.solve_mechanism(from_coupler, loads, levels)
    assert a.converged and b.converged, (a.message, b.message)
    moved = a.positions[-1]["C1"] - np.array(nodes["C1"])
    assert np.hypot(*moved) > 0.02  # the guide moves
    for node in ("C1", "C2"):
        assert np.linalg.norm(a.positions[-1][node] - b.positions[-1][node]) < 1e-8
    assert a.strain_energy[-1] == pytest.approx(b.strain_energy[-1], rel=1e-7)
