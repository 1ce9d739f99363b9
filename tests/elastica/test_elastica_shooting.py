"""The general shooting solver (elastica.shooting) and the elastica adapter on the benchmark cases."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_bvp

from elastica import ElasticaProblem, TipConstraint, solve_elastica, solve_path
from validation.case.loader import load_case
from validation.methods import elastica as adapter
from validation.methods.base import NotApplicable, Request
from validation.case.method_options import options_of

CASES = Path(__file__).resolve().parents[2] / "cases"


def test_full_circle_is_two_pi_not_four_pi():
    """The roll-up trap (notes/anchors.md 2.2): the tip returns to the root with rotation 2 pi."""
    res = solve_elastica(moment=2 * math.pi)
    assert res.converged
    assert abs(res.x) < 1e-10 and abs(res.y) < 1e-10
    assert abs(res.theta - 2 * math.pi) < 1e-10
    assert abs(res.strain_energy - 2 * math.pi**2) < 1e-9  # U = M^2 L / (2 EI)
    assert np.all(np.diff(res.shape[2]) > 0)  # theta(s) monotone, no 2 pi jumps


def _follower_bvp(P):
    """Independent formulation: theta'' = -P cos(theta - theta_L), theta_L an unknown parameter."""
    s = np.linspace(0.0, 1.0, 60)
    y, p = np.zeros((4, s.size)), np.array([0.0])
    y[2] = s
    for load in np.linspace(0.5, P, int(4 * P) + 1):

        def f(_s, y, p, load=load):
            return np.vstack([y[1], -load * np.cos(y[0] - p[0]), np.cos(y[0]), np.sin(y[0])])

        def bc(ya, yb, p):
            return np.array([ya[0], yb[1], ya[2], ya[3], yb[0] - p[0]])

        sol = solve_bvp(f, bc, s, y, p=p, tol=1e-10, max_nodes=100000)
        assert sol.status == 0
        y, p = sol.sol(s), sol.p
    return sol.sol(1.0), sol.p[0]


def test_follower_case_file_against_independent_bvp():
    case = load_case(CASES / "benchmarks" / "follower_tip_load.toml").case
    loads = case.loads[0].levels()
    refs = {(r.quantity, r.level): r.value for r in case.references}
    for level in (0, 2):
        (th, _, x, y), th_L = _follower_bvp(loads[level])
        assert abs(x - refs[("x", level)]) < 1e-8 and abs(y - refs[("y", level)]) < 1e-8
        assert abs(math.degrees(th_L) - refs[("rotation", level)]) < 1e-6


def test_inverse_problem_round_trip():
    """Table 3.3 style: given the tip a, b, theta0 find (Fx, Fy, M); the forward solve returns them.
    The loads are Table 3.2 Ex. 1's (seed 000; EI = 30e6 x 1.02e-5 = 306), whose elliptic-integral
    column prints the forward tip a = 12.336, b = 14.422, theta0 = 58.231 deg."""
    fwd = solve_elastica(20.0, 306.0, force=(-1.5, 3.5), moment=-15.0)
    assert fwd.x == pytest.approx(12.336, abs=5e-4) and fwd.y == pytest.approx(14.422, abs=5e-4)
    assert math.degrees(fwd.theta) == pytest.approx(58.231, abs=5e-4)
    inv = solve_elastica(20.0, 306.0, tip_x=fwd.x, tip_y=fwd.y, tip_angle=fwd.theta)
    assert inv.converged
    assert np.allclose(inv.force, (-1.5, 3.5), atol=1e-8) and abs(inv.moment + 15.0) < 1e-8


def test_inverse_with_given_load_ratio():
    """Table 3.5 style: b and theta0 given with n fixed; unknown P along (-n, 1) and the moment."""
    n = 1.25
    fwd = solve_elastica(force=(-n * 1.2, 1.2), moment=-0.3)
    assert fwd.converged and 0.0 < fwd.theta < 1.0
    inv = solve_elastica(
        tip_angle=fwd.theta, constraints=(TipConstraint((0.0, 1.0), fwd.y, force_direction=(-n, 1.0)),)
    )
    assert inv.converged
    assert np.allclose(inv.force, (-n * 1.2, 1.2), atol=1e-8) and abs(inv.moment + 0.3) < 1e-8
    assert abs(inv.x - fwd.x) < 1e-9


def test_fixed_guided_and_warm_start():
    """A guided tip (theta_L = 0) under a transverse force: the moment is the reaction; then continue."""
    p1 = ElasticaProblem(force=(0.0, 5.0), tip_angle=0.0)
    r1 = solve_path(p1)
    assert r1.converged and abs(r1.theta) < 1e-12
    # symmetry of the guided beam: the tip moment is half the force times the chord
    assert abs(r1.moment + 0.5 * 5.0 * r1.x) < 1e-8
    r2 = solve_path(ElasticaProblem(force=(0.0, 10.0), tip_angle=0.0), start=r1)
    assert r2.converged and r2.y > r1.y


def test_initially_curved_unloaded_and_timing():
    res = solve_elastica(curvature=1.0)
    assert abs(res.x - math.sin(1.0)) < 1e-12 and abs(res.y - (1 - math.cos(1.0))) < 1e-12
    res = solve_elastica(force=(0.0, 1.0))
    assert res.converged and res.wall_time < 1.0  # typically 20-60 ms on the project VM


def test_adapter_runs_the_cantilever_case():
    case = load_case(CASES / "benchmarks" / "cantilever_tip_load.toml").case
    requests = [Request(r.quantity, r.point, r.level) for r in case.references if r.compare == "elastica"]
    run = adapter.run(case, requests, options_of("elastica", case.methods["elastica"]))
    assert run.converged
    for r in case.references:
        if r.compare == "elastica":
            assert abs(run.values[Request(r.quantity, r.point, r.level)] - r.value) <= r.tolerance.abs


@pytest.mark.parametrize("name", ["pure_moment_roll_up", "seed004_strip_moment", "seed004_strip_tip_force"])
def test_adapter_meets_case_references(name):
    case = load_case(CASES / "benchmarks" / f"{name}.toml").case
    refs = [r for r in case.references if r.compare == "elastica"]
    run = adapter.run(
        case, [Request(r.quantity, r.point, r.level) for r in refs], options_of("elastica", case.methods["elastica"])
    )
    for r in refs:
        tol = r.tolerance.abs if r.tolerance.abs is not None else r.tolerance.rel * abs(r.value)
        assert abs(run.values[Request(r.quantity, r.point, r.level)] - r.value) <= tol, r


def test_adapter_displacement_specified_gives_needed_loads():
    """Prescribed tip displacement/rotation: force_y and moment outputs are the loads needed."""
    text = """
[case]
id = "t"
title = "t"
group = "test"
units = "dimensionless"
[segment]
boundary = "fixed-guided"
length = 1.0
E = 1.0
section = { kind = "inertia", I = 1.0 }
[[loads]]
kind = "displacement"
direction = [0.0, 1.0]
values = [0.05, 0.3]
[[outputs]]
quantity = "force_y"
[methods.elastica]
"""
    from validation.case.schema import Case
    import tomllib

    case = Case.model_validate(tomllib.loads(text))
    reqs = [
        Request("force_y", "tip", 0),
        Request("moment", "tip", 0),
        Request("force_y", "tip", 1),
        Request("reaction_moment", "root", 1),
    ]
    run = adapter.run(case, reqs, options_of("elastica", {}))
    # small deflection: guided beam stiffness 12 EI/L^3, end moment -6 EI delta/L^2
    assert abs(run.values[reqs[0]] - 12 * 0.05) < 0.01 * 12 * 0.05
    assert abs(run.values[reqs[1]] + 6 * 0.05) < 0.02 * 6 * 0.05
    assert run.values[reqs[2]] > 12 * 0.3  # geometric stiffening of the guided beam


def test_adapter_refuses_mechanisms():
    case = load_case(CASES / "benchmarks" / "lee_frame.toml").case
    with pytest.raises(NotApplicable):
        adapter.run(case, [Request("force_y", "P", 0)], options_of("elastica", {}))
