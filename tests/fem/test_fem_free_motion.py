"""A model that can move without deforming is refused before any Newton iteration, by a named error
(`fem.FreeMotion`) that says which node and DOF nothing holds. The decision is kinematic
(`fem.free_motion`: the null space of the rigid-body constraint matrix by SVD), so it is the same on
every CPU, for either corrector, and under relative noise of 1e-12 in coordinates and stiffnesses."""

import numpy as np
import pytest

import fem


def _beam(support: str | None, joint_at_tip: bool = False) -> fem.Model:
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("mid", 0.5, 0.0)
    m.add_node("tip", 1.0, 0.0)
    sec = fem.Section.from_EI(EA=1e4, EI=1.0)
    m.add_member("root", "mid", sec, n_elements=4)
    m.add_member("mid", "tip", sec, n_elements=4)
    if support:
        m.add_support("root", support)
    m.add_force("tip", 0.0, 0.1)
    return m


def test_held_cantilever_solves():
    """The same beam clamped at the root is held: it solves (the check does not refuse it)."""
    assert fem.solve(_beam("fixed")).converged


@pytest.mark.parametrize("control", ["load", "arclength"])
def test_unsupported_beam_is_refused_naming_a_dof(control):
    """No support at all: three rigid-body motions; the error names a node and a DOF."""
    with pytest.raises(fem.FreeMotion, match=r"(root|mid|tip|interior node).*(ux|uy|rz)"):
        fem.solve(_beam(None), control=control, lambda_max=1.0)


def test_pinned_root_turns_freely():
    """A single pin leaves the rigid rotation about it: refused."""
    with pytest.raises(fem.FreeMotion, match="can move without deforming"):
        fem.solve(_beam("pinned"))


def test_free_hinge_in_the_span():
    """Clamped root, but a revolute joint without a spring at 'mid': the outer half swings freely.
    The error names the joint node."""
    m = _beam("fixed")
    m.add_joint("mid", k=0.0)
    with pytest.raises(fem.FreeMotion, match="mid|tip|interior node of member 'm1'"):
        fem.solve(m)
    m2 = _beam("fixed")
    m2.add_joint("mid", k=5.0)  # the same hinge with a spring: held
    r = fem.solve(m2)
    assert r.converged and np.isfinite(r.position("tip")).all()


def _linked(support: str | None, k: float, slave_force: float = 0.0) -> fem.Model:
    """A beam, a rigid link to a second beam's start, a joint spring k there (k = 0: a free hinge);
    the link's slave 'b' carries a force ``slave_force`` besides the one at the tip."""
    m = fem.Model()
    for name, x, y in (("root", 0.0, 0.0), ("a", 1.0, 0.0), ("b", 1.3, 0.4), ("c", 2.2, 0.4)):
        m.add_node(name, x, y)
    sec = fem.Section.from_EI(EA=1e4, EI=1.0)
    m.add_member("root", "a", sec, n_elements=20)
    m.add_member("b", "c", sec, n_elements=20)
    m.add_rigid_link("a", "b")
    m.add_joint("b", k=k)
    if support:
        m.add_support("root", support)
    m.add_force("c", 0.0, 0.1)
    if slave_force:
        m.add_force("b", slave_force, 0.0)
    return m


MODELS = {
    "cantilever": lambda: _beam("fixed"),
    "free beam": lambda: _beam(None),
    "pinned beam": lambda: _beam("pinned"),
    "slider beam": lambda: _beam("slider"),
    "free hinge": lambda: _hinged(0.0),
    "sprung hinge": lambda: _hinged(5.0),
    "linked, clamped": lambda: _linked("fixed", 2.0),
    "linked, free hinge": lambda: _linked("fixed", 0.0),
    "linked, pinned": lambda: _linked("pinned", 2.0),
    "linked, free": lambda: _linked(None, 2.0),
    "linked, clamped, slave loaded": lambda: _linked("fixed", 2.0, 0.05),
    "prescribed tip": lambda: _prescribed_tip(),
    "four-bar, free hinges": lambda: _four_bar(0.0),
    "four-bar, sprung hinges": lambda: _four_bar(3.0),
    "closed frame, pinned": lambda: _closed_frame(),
    "closed frame on a pin only": lambda: _closed_frame(slider=False),
    "hinged triangle": lambda: _hinged_polygon(((0.0, 0.0), (1.0, 0.0), (0.4, 0.7))),
    "hinged square": lambda: _hinged_polygon(((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))),
}
FREE = {
    "free beam": 3,
    "pinned beam": 1,
    "slider beam": 2,
    "free hinge": 1,
    "linked, free hinge": 1,
    "linked, pinned": 1,
    "linked, free": 3,
    "four-bar, free hinges": 1,
    "hinged square": 1,
    "closed frame on a pin only": 1,
}


def _expected_verdict(name: str) -> bool:
    return name not in FREE


def _verdict(run) -> str:
    try:
        run()
        return "held"
    except fem.FreeMotion as exc:
        return str(exc)


@pytest.mark.parametrize("name", MODELS)
def test_the_compiled_and_the_numpy_corrector_get_the_same_verdict(name):
    """Both correctors refuse exactly the models that can move (a fixed support and springs at every
    joint: held; the pinned linked beam, which swings about its pin, is free in both), naming the same
    DOF: the decision is made once, from the kinematics, before either corrector runs."""
    from fem.free_motion import check_held
    from fem.solver import System, discretise

    m = MODELS[name]()
    system = System(m, discretise(m))
    compiled = _verdict(lambda: check_held(system))
    system.compiled = None
    assert _verdict(lambda: check_held(system)) == compiled
    assert (compiled == "held") == _expected_verdict(name), compiled
    follower = MODELS[name]()  # a follower force: the NumPy corrector in fem.solve
    follower.add_force(follower.node_names[-1], 0.0, 1e-3, follower=True)
    for run in (_verdict(lambda: fem.solve(m)), _verdict(lambda: fem.solve(follower))):
        assert run == compiled if compiled != "held" else "can move" not in run


@pytest.mark.parametrize("name", MODELS)
def test_the_count_of_free_motions_is_the_nullity_of_the_unloaded_stiffness(name):
    """Against the definition: the number of free motions is the number of zero eigenvalues of the
    unloaded reduced stiffness K_0 (dense, symmetric; these models' stiffness ratios keep a held
    model's smallest eigenvalue above 1e-9 of the largest, rounding leaves a free one below 1e-13)."""
    from fem.free_motion import free_motions
    from fem.solver import System, discretise

    m = MODELS[name]()
    system = System(m, discretise(m))
    system.compiled = None
    zero = system.loads_at(-1, 0, 0.0)
    K = system.evaluate(np.zeros(system.n), system.disc.beta0.copy(), 0.0, *zero, need_K=True)["K"]
    K = system.layout.to_dense(K)
    eig = np.linalg.eigvalsh(0.5 * (K + K.T))
    nullity = int(np.sum(np.abs(eig) <= 1e-11 * np.abs(eig).max()))
    assert not np.any((np.abs(eig) > 1e-13 * np.abs(eig).max()) & (np.abs(eig) < 1e-9 * np.abs(eig).max()))
    assert free_motions(system).count == nullity == FREE.get(name, 0)


def _perturbed(model: fem.Model, rng, noise: float = 1e-12) -> fem.Model:
    """The model with node coordinates, section stiffnesses and joint springs each multiplied by
    1 + noise * N(0, 1) (a coordinate at 0 moved by noise times the model's length)."""
    scale = model.characteristic_length()
    model.coords = [
        (
            x * (1 + noise * rng.standard_normal()) + noise * scale * rng.standard_normal(),
            y * (1 + noise * rng.standard_normal()) + noise * scale * rng.standard_normal(),
        )
        for x, y in model.coords
    ]
    for member in model.members:
        s = member.section
        member.section = fem.Section(
            s.EA * (1 + noise * rng.standard_normal()), s.EI * (1 + noise * rng.standard_normal()), s.stress_layers
        )
    for joint in model.joints:
        joint.k *= 1 + noise * rng.standard_normal()
    return model


@pytest.mark.parametrize("name", MODELS)
def test_relative_noise_of_1e_12_does_not_change_the_decision_or_the_named_dof(name):
    """Rounding-level changes of the data (20 draws of relative noise 1e-12 in every coordinate and
    stiffness, about 4500 ulps) leave the verdict and the named DOF as they were: the decision has a
    margin (RCOND = 1e-10 against singular values ~1e-15 or O(1)), not a threshold rounding can cross."""
    from fem.free_motion import check_held
    from fem.solver import System, discretise

    def verdict(m):
        return _verdict(lambda: check_held(System(m, discretise(m))))

    base = verdict(MODELS[name]())
    rng = np.random.default_rng(7)
    for _ in range(20):
        assert verdict(_perturbed(MODELS[name](), rng)) == base


def test_a_nearly_singular_geometry_is_decided_with_its_margin_stated():
    """Three hinges 1e-3 of the span off a line (a shallow toggle) are held, their smallest singular
    value about 1e-3 of the largest (far above RCOND); exactly in line they are an infinitesimal
    mechanism (one free motion): the same rule, the margin in `FreeMotions.relative_sigma`."""
    from fem.free_motion import RCOND, free_motions
    from fem.solver import System, discretise

    for rise, count in ((1e-3, 0), (0.0, 1)):
        m = fem.Model()
        for name, x, y in (("a", 0.0, 0.0), ("b", 1.0, rise), ("c", 2.0, 0.0)):
            m.add_node(name, x, y)
        sec = fem.Section.from_EI(EA=1e4, EI=1.0)
        m.add_member("a", "b", sec, n_elements=4)
        m.add_member("b", "c", sec, n_elements=4)
        m.add_support("a", "pinned")
        m.add_support("c", "pinned")
        m.add_joint("a", k=0.0)
        m.add_joint("b", k=0.0)
        m.add_joint("c", k=0.0)
        motions = free_motions(System(m, discretise(m)))
        assert motions.count == count
        smallest = motions.relative_sigma[0]
        assert (smallest <= RCOND) if count else (1e-4 < smallest < 1e-2)


@pytest.mark.parametrize("EA_over_EI, n_elements", [(1e12, 2000), (1e4, 2)])
def test_slenderness_does_not_enter_the_decision(EA_over_EI, n_elements):
    """A very slender clamped member (EA / EI = 1e12, 2000 elements: K_0's condition ~1e22, beyond any
    pivot test) is held; the same member pinned is free: the kinematics have no stiffness in them."""
    from fem.free_motion import free_motions
    from fem.solver import System, discretise

    for support, count in (("fixed", 0), ("pinned", 1)):
        m = fem.Model()
        m.add_node("root", 0.0, 0.0)
        m.add_node("tip", 1.0, 0.0)
        m.add_member("root", "tip", fem.Section.from_EI(EA=EA_over_EI, EI=1.0), n_elements=n_elements)
        m.add_support("root", support)
        assert free_motions(System(m, discretise(m))).count == count


def test_a_very_soft_spring_holds_and_the_solve_says_what_it_found():
    """A hinge with a spring 1e-12 times as stiff as the beam is held (a spring is a spring): the solve
    either converges (the spring carries the tip moment with a large turn) or says why it stopped."""
    r = fem.solve(_hinged(1e-12))
    assert r.converged or ("convergence" in r.message or "singular" in r.message), r.message
    assert _verdict(lambda: fem.solve(_hinged(0.0))) != "held"


def _hinged(k: float) -> fem.Model:
    m = _beam("fixed")
    m.add_joint("mid", k=k)
    return m


def _prescribed_tip() -> fem.Model:
    m = _beam("fixed")
    m.loads.clear()
    m.prescribe("tip", "uy", [0.05])
    return m


def test_a_refined_mesh_of_a_model_found_held_is_not_tested_again(monkeypatch):
    """The error estimate's finer meshes (`solve_with_error_estimate`) are meshes of the model whose
    coarsest mesh passed the free-motion test (refining adds interior nodes only, each joined by two
    elements): they are solved without the test (``held``), to the same numbers; a solve given a coarse
    guess but not told ``held`` still tests, and a free model is still refused by the coarse mesh."""
    from fem import solver

    calls = []
    real = solver.check_held
    monkeypatch.setattr(solver, "check_held", lambda system: calls.append(system.n) or real(system))
    model = _beam("fixed")
    est = fem.solve_with_error_estimate(model, levels=3)
    assert len(calls) == 1 and est.converged and len(est.results) == 3
    coarse, fine = est.results[0], est.results[1]
    again = fem.solve(model, refine=2, initial_guess=coarse)  # the same solve, tested
    assert len(calls) == 2 and np.array_equal(again.mesh_positions, fine.mesh_positions)
    free = _beam("pinned")
    free.add_force("tip", 0.0, 0.1, follower=True)  # a follower: the NumPy corrector, tested beforehand
    with pytest.raises(fem.FreeMotion):
        fem.solve_with_error_estimate(free, levels=3)


def _four_bar(k: float) -> fem.Model:
    """A four-bar: ground pivots O2 (0, 0) and O4 (2, 0), crank O2-A, coupler A-B, rocker B-O4,
    revolute joints with springs k at all four pins (k = 0: one free motion, Gruebler)."""
    m = fem.Model()
    for name, x, y in (("O2", 0.0, 0.0), ("A", 0.3, 0.8), ("B", 1.7, 1.0), ("O4", 2.0, 0.0)):
        m.add_node(name, x, y)
    sec = fem.Section.from_EI(EA=1e4, EI=1.0)
    m.add_member("O2", "A", sec, n_elements=3)
    m.add_member("A", "B", sec, n_elements=3)
    m.add_member("B", "O4", sec, n_elements=3)
    m.add_support("O2", "pinned")
    m.add_support("O4", "pinned")
    for node in ("O2", "A", "B", "O4"):
        m.add_joint(node, k=k)
    m.add_force("A", 0.01, 0.0)
    return m


def _closed_frame(slider: bool = True) -> fem.Model:
    """A rigid triangle of three members pinned at one corner and on a slider at another: held; on the
    pin alone it turns about it (one motion)."""
    m = fem.Model()
    for name, x, y in (("p", 0.0, 0.0), ("q", 1.0, 0.0), ("r", 0.4, 0.7)):
        m.add_node(name, x, y)
    sec = fem.Section.from_EI(EA=1e4, EI=1.0)
    m.add_member("p", "q", sec, n_elements=2)
    m.add_member("q", "r", sec, n_elements=2)
    m.add_member("r", "p", sec, n_elements=2)
    m.add_support("p", "pinned")
    if slider:
        m.add_support("q", "slider", direction=(1.0, 0.0))
    m.add_force("r", 0.01, 0.0)
    return m


def _hinged_polygon(corners) -> fem.Model:
    """A closed loop of members with free hinges at every corner, pinned at the first corner and on a
    horizontal slider at the second: a triangle is a rigid truss (held), a square shears (one motion)."""
    m = fem.Model()
    names = [f"c{i}" for i in range(len(corners))]
    for name, (x, y) in zip(names, corners):
        m.add_node(name, x, y)
    sec = fem.Section.from_EI(EA=1e4, EI=1.0)
    for a, b in zip(names, names[1:] + names[:1]):
        m.add_member(a, b, sec, n_elements=2)
    m.add_support(names[0], "pinned")
    m.add_support(names[1], "slider", direction=(1.0, 0.0))
    for name in names:
        m.add_joint(name, k=0.0)
    m.add_force(names[-1], 0.01, 0.0)
    return m


def test_a_model_solved_again_gets_the_same_answer_and_a_changed_one_its_own():
    """The answer is kept per kinematic signature (`free_motion._signature`): the same geometry again
    gives the same answer without the work; a changed support, joint spring, link or coordinate is
    answered afresh (a pinned root after a clamped one is free; a hinge sprung after a free one held)."""
    from fem.free_motion import free_motions
    from fem.solver import System, discretise

    def motions(m):
        return free_motions(System(m, discretise(m)))

    assert motions(_beam("fixed")).held and motions(_beam("fixed")).held
    assert motions(_beam("pinned")).count == 1
    assert motions(_hinged(0.0)).count == 1 and motions(_hinged(5.0)).held
    moved = _linked("pinned", 2.0)
    assert motions(moved).count == 1
    moved.supports[0].kind = "fixed"
    assert motions(moved).held
