"""The Jacobian of the mechanism elastica's residual (``elastica.mechanism``, ``_System.jacobian``) is the
derivative of that residual: on mechanisms that between them exercise every block (beams clamped and
pinned at either end or free, starts on the ground and on moving bodies, pins, prescribed rotations and
displacements, follower forces and forces toward a fixed point at a body's node and at a free beam end,
couples, a distributed load, extensible, inextensible and curved beams) it agrees with central finite
differences of the residual, at a state away from the unloaded one (nonzero forces, turned bodies, where
every lever and rotation term counts). A wrong sign planted in one block is caught."""

import numpy as np
import pytest

import planar
from elastica import mechanism as em

G = em.GROUND
RTOL = 1e-13  # the beams' integrations, tight: the central differences divide their rounding by h
TOLERANCE = 1e-5  # on the largest entry: the beams' own blocks hold to their integration's 1e-8


def _parallel_guide():
    nodes = {"G1": (0.0, 0.0), "G2": (0.5, 0.0), "C1": (0.0, 1.0), "C2": (0.5, 1.0), "M": (0.25, 1.0)}
    beams = [
        em.ElasticBeam("left", "G1", "C1", 1.0, G, "coupler", EA=1e6),
        em.ElasticBeam("right", "G2", "C2", 1.0, G, "coupler", EA=1e6),
    ]
    loads = [planar.Force("M", (1.0, 5.0), (0.0, -1.0)), planar.Couple("coupler", (0.1, 0.3))]
    return em.Mechanism(nodes, beams, [em.RigidBody("coupler", ("C1", "C2", "M"))]), loads


def _parallel_guide_pulled():
    """The parallel guide with a follower force and a force toward a fixed point at the coupler's nodes."""
    mech, _ = _parallel_guide()
    return mech, [
        planar.Force("M", (1.0, 3.0), (0.5, 1.0), follower=True),
        planar.PointedForce("C2", (0.5, 2.0), (2.0, 3.0), 0.3),
    ]


def _crank():
    """A clamped-pinned beam on a crank turned about a ground pin: the beam clamped to the crank, pinned
    to the ground at its end (a couple on its side of that pin), the crank's rotation prescribed."""
    nodes = {"O": (0.0, 0.0), "C": (0.3, 0.4), "P": (1.2, 0.6)}
    beams = [em.ElasticBeam("b", "C", "P", 0.8, "crank", G, "clamped", "pinned", EA=200.0)]
    mech = em.Mechanism(nodes, beams, [em.RigidBody("crank", ("O", "C"))], [em.Pin("crank", G, (0.0, 0.0), "O")])
    return mech, [em.PrescribedRotation("crank", (0.2, 0.5)), em.EndCouple("P", (0.05, 0.1))]


def _rocker():
    """A beam pinned at its start to a rocker (its start angle an unknown) and clamped to the ground, the
    rocker pinned to the ground, one of its points driven along x and another pushed."""
    nodes = {"O": (0.0, 0.0), "R": (0.0, 0.5), "Q": (0.2, 0.3), "E": (1.0, 0.5)}
    beams = [em.ElasticBeam("b", "R", "E", 1.5, "rocker", G, "pinned", "clamped")]
    mech = em.Mechanism(nodes, beams, [em.RigidBody("rocker", ("O", "R", "Q"))], [em.Pin("rocker", G, (0.0, 0.0), "O")])
    return mech, [em.PrescribedDisplacement("Q", "x", (0.02, 0.05)), planar.Force("R", (0.5, 1.0), (-0.3, -1.0))]


def _pinned_bodies():
    """Two bodies pinned to each other, one of them to the ground, held by a beam from the ground clamped
    to the outer one and by a beam from the inner one pinned to the outer one."""
    nodes = {"O": (0.0, 0.0), "P": (0.5, 0.1), "Q": (1.0, 0.3), "G": (1.1, -0.8), "S": (0.2, 0.0)}
    beams = [
        em.ElasticBeam("holder", "G", "Q", 1.0, G, "outer", EA=1e3),
        em.ElasticBeam("link", "S", "Q", 0.5, "inner", "outer", "clamped", "pinned", curvature=-0.3),
    ]
    bodies = [em.RigidBody("inner", ("O", "P", "S")), em.RigidBody("outer", ("P", "Q"))]
    pins = [em.Pin("inner", G, (0.0, 0.0), "O"), em.Pin("inner", "outer", (0.5, 0.1), "P")]
    return em.Mechanism(nodes, beams, bodies, pins), [
        planar.Force("P", (0.3, 1.0), (-0.5, -1.5)),
        planar.Couple("inner", (0.2, 0.4)),
    ]


def _free_follower():
    """A curved inextensible cantilever, a follower force at its free end (it turns with the end)."""
    nodes = {"A": (0.0, 0.0), "B": (1.0, 0.2)}
    beams = [em.ElasticBeam("b", "A", "B", 2.0, G, None, "clamped", "free", curvature=0.4)]
    return em.Mechanism(nodes, beams), [
        planar.Force("B", (1.0, 2.0), (0.5, 1.5), follower=True),
        em.EndCouple("B", (0.1, -0.2)),
    ]


def _free_pointed():
    """An extensible beam from a body pinned to the ground to a free end pulled toward a fixed point: the
    beam's start pose moves with the body, the pull's direction with the end."""
    nodes = {"O": (0.0, 0.0), "S": (0.2, 0.0), "T": (1.2, 0.1)}
    beams = [em.ElasticBeam("b", "S", "T", 1.0, "base", None, "clamped", "free", EA=30.0)]
    mech = em.Mechanism(nodes, beams, [em.RigidBody("base", ("O", "S"))], [em.Pin("base", G, (0.0, 0.0), "O")])
    return mech, [planar.PointedForce("T", (1.0, 2.5), (0.5, -1.5), 0.2), planar.Couple("base", (0.5, 1.0))]


def _distributed():
    """A beam under its own weight clamped to a one-node tip body pushed by a follower force."""
    nodes = {"A": (0.0, 0.0), "B": (1.0, 0.0)}
    beams = [em.ElasticBeam("b", "A", "B", 1.0, G, "tip", EA=500.0)]
    mech = em.Mechanism(nodes, beams, [em.RigidBody("tip", ("B",))])
    return mech, [
        planar.DistributedLoad("b", (0.2, 0.5), (-1.0, -3.0)),
        planar.Force("B", (0.0, 1.0), (0.5, 0.5), follower=True),
    ]


MECHANISMS = {
    "parallel guide": _parallel_guide,
    "parallel guide, follower and pointed forces": _parallel_guide_pulled,
    "clamped-pinned beam on a crank": _crank,
    "pinned start on a rocker": _rocker,
    "bodies pinned to each other": _pinned_bodies,
    "free end, follower force, curved": _free_follower,
    "free end, pointed force, extensible": _free_pointed,
    "distributed load": _distributed,
}


def _state(problem, seed: int = 1) -> np.ndarray:
    """A state away from the unloaded one: every unknown about a fifth of its typical size."""
    rng = np.random.default_rng(seed)
    return 0.2 * problem.typical * rng.standard_normal(problem.system.size)


def _mismatch(problem, t: float, u: np.ndarray) -> float:
    """The largest difference between the Jacobian and central differences of the residual (steps 1e-5 of
    each unknown's typical size), each column times that size, relative to the largest such entry."""
    J = problem.jacobian(t, u)
    central = np.empty_like(J)
    for j in range(u.size):
        h = 1e-5 * problem.typical[j]
        up, down = u.copy(), u.copy()
        up[j] += h
        down[j] -= h
        central[:, j] = (problem.residual(t, up) - problem.residual(t, down)) / (2 * h)
    return float(np.max(np.abs(J - central) * problem.typical) / np.max(np.abs(central) * problem.typical))


def _problem(name: str):
    mech, loads = MECHANISMS[name]()
    return em._problem(mech, loads, 2, RTOL)


@pytest.mark.parametrize("name", MECHANISMS)
def test_the_jacobian_is_the_derivative_of_the_residual(name):
    problem = _problem(name)
    assert _mismatch(problem, 0.6, _state(problem)) < TOLERANCE


@pytest.mark.parametrize("EA, curvature, w", [(None, 0.0, (0.0, 0.0)), (40.0, 0.5, (1.0, -2.0))])
def test_a_beams_block_is_the_derivative_of_its_end_state(EA, curvature, w):
    """One beam's block d(x, y, theta, m)(L)/d(theta0, m0, Fx, Fy) (``_System.end_derivative``) against
    central differences of its own integration: inextensible and straight; extensible, curved and under
    a distributed load. The beam starts clamped on a turning body, so every column is computed."""
    nodes = {"O": (0.0, 0.0), "S": (0.2, 0.0), "T": (1.1, 0.4)}
    beam = em.ElasticBeam("b", "S", "T", 1.3, "base", None, "clamped", "free", EA=EA, curvature=curvature)
    mech = em.Mechanism(nodes, [beam], [em.RigidBody("base", ("O", "S"))], [em.Pin("base", G, (0.0, 0.0), "O")])
    problem = em._problem(
        mech, [planar.Force("T", (1.0,), (2.0,)), planar.DistributedLoad("b", (w[0],), (w[1],))], 1, RTOL
    )
    u = _state(problem)
    problem.path(0.0, u)  # the loads of the level: the distributed load along the beam
    system, ul = problem.system, u.tolist()
    end, D = system.end_derivative(beam, u, ul)
    x, y, *inputs = system._start(beam, ul)
    sizes = (1.0, problem.typical[2], problem.typical[0], problem.typical[1])  # theta0, m0, Fx, Fy
    central = np.empty((4, 4))
    for col, size in enumerate(sizes):
        h = 1e-5 * size
        up, down = list(inputs), list(inputs)
        up[col] += h
        down[col] -= h
        central[:, col] = (
            system._integrate_from(beam, x, y, *up)[:4] - system._integrate_from(beam, x, y, *down)[:4]
        ) / (2 * h)
    np.testing.assert_array_equal(end, system.integrate(beam, u))
    scaled = np.abs(D - central) * np.array(sizes)
    assert np.max(scaled) < TOLERANCE * np.max(np.abs(central) * np.array(sizes))


def test_the_unknowns_move_every_block():
    """The states tested are not degenerate: every unknown moves the residual, and the load-dependent
    forces' derivatives (follower, pointed) are not zero there."""
    for name in MECHANISMS:
        problem = _problem(name)
        u = _state(problem)
        J = problem.jacobian(0.6, u)
        assert np.all(np.max(np.abs(J), axis=0) > 0), name
    for name in (
        "parallel guide, follower and pointed forces",
        "free end, follower force, curved",
        "free end, pointed force, extensible",
        "distributed load",
    ):
        problem = _problem(name)
        u = _state(problem)
        problem.path(0.6, u)
        rates = problem.path.force_rates(0.6, u)
        assert rates and all(np.max(np.abs(a)) > 0 for a in rates.values()), name


def _flip_force_column(original):
    def flipped(*args):
        end, D = original(*args)
        D = D.copy()
        D[:, 3] *= -1.0  # d(end)/dFy with the wrong sign
        return end, D

    return flipped


def _flip_turn(original):
    def flipped(ul, place):
        dx, dy = original(ul, place)
        return [(c, -v if c == place[0] + 2 else v) for c, v in dx], dy  # d x/d phi with the wrong sign

    return staticmethod(flipped)


def _flip_follower(original):
    def flipped(self, t, u):
        rates = original(self, t, u)
        return {node: [a[0], a[1], -a[2], a[3], a[4], -a[5]] for node, a in rates.items()}  # dF/dphi

    return flipped


@pytest.mark.parametrize(
    "attribute, plant, name",
    [
        ("end_derivative", _flip_force_column, "parallel guide"),
        ("_place_rate", _flip_turn, "clamped-pinned beam on a crank"),
        ("force_rates", _flip_follower, "free end, follower force, curved"),
    ],
)
def test_a_wrong_sign_in_one_block_is_caught(monkeypatch, attribute, plant, name):
    owner = em._LoadPath if attribute == "force_rates" else em._System
    original = owner.__dict__[attribute]
    monkeypatch.setattr(owner, attribute, plant(original.__func__ if isinstance(original, staticmethod) else original))
    problem = _problem(name)
    assert _mismatch(problem, 0.6, _state(problem)) > 100 * TOLERANCE
