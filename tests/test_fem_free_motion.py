"""A model that can move without deforming is refused before any Newton iteration, by a named error
(`fem.FreeMotion`) that says which node and DOF nothing holds (issue 22, item 2: the zero pivot of the
unloaded stiffness as the last line of defence)."""
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
    m2.add_joint("mid", k=5.0)          # the same hinge with a spring: held
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


@pytest.mark.parametrize("model", [
    lambda: _beam("fixed"), lambda: _beam(None), lambda: _beam("pinned"), lambda: _beam("slider"),
    lambda: _linked("fixed", 2.0), lambda: _linked("fixed", 0.0), lambda: _linked("pinned", 2.0),
    lambda: _linked(None, 2.0)])
def test_the_compiled_check_names_what_the_numpy_check_names(model):
    """The check on the compiled corrector's factors of the unloaded tangent (dense and banded, with
    and without rigid links) refuses exactly the models the NumPy check refuses, naming the same DOF."""
    from fem.free_motion import check_held
    from fem.solver import discretise, System

    def verdict(system):
        try:
            check_held(system)
            return "held"
        except fem.FreeMotion as exc:
            return str(exc)

    m = model()
    system = System(m, discretise(m))
    assert system.compiled is not None
    compiled = verdict(system)
    system.compiled = None          # the NumPy check (`assembly.System.evaluate`, `linear_solver`)
    assert compiled == verdict(system)
    held = bool(m.supports) and m.supports[0].kind == "fixed" and all(j.k > 0 for j in m.joints)
    assert (compiled == "held") == held, compiled


def _verdict(run) -> str:
    try:
        run()
        return "held"
    except fem.FreeMotion as exc:
        return str(exc)


@pytest.mark.parametrize("model", [
    lambda: _beam("fixed"), lambda: _beam(None), lambda: _beam("pinned"), lambda: _beam("slider"),
    lambda: _hinged(0.0), lambda: _hinged(5.0), lambda: _linked("fixed", 2.0), lambda: _linked("fixed", 0.0),
    lambda: _linked("pinned", 2.0), lambda: _linked(None, 2.0)])
def test_a_load_run_tests_the_factors_of_its_first_iteration_and_names_the_same_dof(model, monkeypatch):
    """A load-controlled run from the unloaded state, nothing prescribed, no force on a rigid link's
    slave, makes the free-motion test on its first Newton factors (whose tangent is the unloaded one)
    instead of a check of its own beforehand: it refuses exactly the models `check_held` refuses,
    naming the same DOF, and solves the others as before."""
    from fem import solver
    from fem.free_motion import check_held

    m = model()
    system = solver.System(m, solver.discretise(m))
    before = _verdict(lambda: check_held(system))
    monkeypatch.setattr(solver, "check_held", lambda s: pytest.fail("checked beforehand"))
    during = _verdict(lambda: fem.solve(m))
    assert during == before
    held = bool(m.supports) and m.supports[0].kind == "fixed" and all(j.k > 0 for j in m.joints)
    assert (during == "held") == held, during


@pytest.mark.parametrize("model, options", [(lambda: _linked("fixed", 0.0, 0.05), {}),
                                            (lambda: _linked("fixed", 2.0, 0.05), {}),
                                            (lambda: _prescribed_tip(), {}), (lambda: _beam(None), {"maxiter": 0})])
def test_a_run_whose_first_tangent_is_not_the_unloaded_one_is_checked_beforehand(model, options, monkeypatch):
    """With a force on a rigid link's slave (it enters the first tangent), a prescribed motion at the
    first level, or no Newton iteration allowed (Newton would stop before it factorises), the test is
    made beforehand on the unloaded tangent (`check_held`): a free beam is refused even with maxiter 0."""
    from fem import solver
    calls = []
    original = solver.check_held
    monkeypatch.setattr(solver, "check_held", lambda s: calls.append(1) or original(s))
    verdict = _verdict(lambda: fem.solve(model(), **options))
    assert calls == [1]
    if options:
        assert "can move without deforming" in verdict


def _hinged(k: float) -> fem.Model:
    m = _beam("fixed")
    m.add_joint("mid", k=k)
    return m


def _prescribed_tip() -> fem.Model:
    m = _beam("fixed")
    m.loads.clear()
    m.prescribe("tip", "uy", [0.05])
    return m


@pytest.mark.parametrize("slave_force", [0.0, 0.05])
def test_only_a_force_on_a_slave_makes_the_first_tangent_differ_from_the_unloaded_one(slave_force):
    """The premise of the rule above: at the unloaded state (q = 0) the tangent under the first level's
    loads equals the unloaded tangent unless a rigid link's slave carries a force (its geometric term
    reads the residual there); the tip force, on a beam node, changes nothing."""
    from fem.solver import System, _slaves_loaded, discretise

    m = _linked("fixed", 2.0, slave_force)
    system = System(m, discretise(m))
    q0, beta0 = np.zeros(system.n), system.disc.beta0.copy()
    loaded = system.evaluate(q0, beta0, 1.0, *system.loads_at(-1, 0, 1.0), need_K=True)["K"]
    unloaded = system.evaluate(q0, beta0, 0.0, *system.loads_at(-1, 0, 0.0), need_K=True)["K"]
    assert _slaves_loaded(system) == bool(slave_force)
    assert np.array_equal(loaded, unloaded) == (not slave_force)


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
    assert calls == [] and est.converged and len(est.results) == 3
    coarse, fine = est.results[0], est.results[1]
    again = fem.solve(model, refine=2, initial_guess=coarse)        # the same solve, tested
    assert len(calls) == 1 and np.array_equal(again.mesh_positions, fine.mesh_positions)
    free = _beam("pinned")
    free.add_force("tip", 0.0, 0.1, follower=True)     # a follower: the NumPy corrector, tested beforehand
    with pytest.raises(fem.FreeMotion):
        fem.solve_with_error_estimate(free, levels=3)
