"""A tip force toward a fixed point (a rope over a pulley, ``toward`` with an ``angle`` offset) in the
exact elastica (``elastica.PointedForce``) and its adapter.

The force at equilibrium is F = T R(a) (P - r_tip)/|P - r_tip|. Expected values are not our own output:
* the far-point limit: with P at 1e6 L along a unit vector d from the unloaded tip, the force turns by
  at most |r_tip - r_tip0|/(1e6 L) ~ 1e-6 rad from d, so the tip is the dead force T d's within ~1e-6 L;
* the FEM of the same case (64 elements, corotational, with its own pointed-force law and Richardson
  error estimate |u_2n - u_n|/3): an independent discretisation, so |elastica - FEM| <= 3 x estimate
  plus the elastica's accuracy;
* equilibrium: the converged tip force has magnitude T and points along R(a)(P - r_tip).
"""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest

from elastica import ElasticaProblem, PointedForce, TipConstraint, pointing_error, solve_path, unloaded_tip
from validation.case.schema import Case
from validation.methods import elastica as adapter
from validation.methods.base import NotApplicable, Request, RunStatus
from validation.run.runner import run_method
from validation.case.method_options import options_of

ELASTICA_TOL = {"x": 1e-9, "y": 1e-9, "rotation": 1e-7}  # length L = 1; degrees


def _case(
    load: str, values: list[float], boundary: str = "fixed-free", curvature: float = 0.0, loads_out: bool = False
) -> Case:
    """A unit segment (L = 1, EI = 1, EA = 1e8: the FEM's beam all but inextensible) with one force;
    the tip's x, y, rotation, and with ``loads_out`` the tip force (the elastica's only: the FEM gives
    no components of a force toward a point)."""
    forces = '[[outputs]]\nquantity = "force_x"\n[[outputs]]\nquantity = "force_y"' if loads_out else ""
    text = f"""
[case]
id = "pointed_probe"
title = "Unit segment, tip force toward a fixed point"
group = "tests"
units = "dimensionless"
[segment]
boundary = "{boundary}"
length = 1.0
E = 1.0
curvature = {curvature}
section = {{ kind = "inertia", I = 1.0, A = 1.0e8 }}
[[loads]]
kind = "force"
{load}
values = {values}
[[outputs]]
quantity = "x"
[[outputs]]
quantity = "y"
[[outputs]]
quantity = "rotation"
{forces}
[methods.fem]
elements = 64
[methods.elastica]
"""
    return Case.model_validate(tomllib.loads(text))


def _values(run, quantity: str) -> dict[int, float]:
    return {r.level: v for r, v in run.values.items() if r.quantity == quantity and r.point == "tip"}


@pytest.mark.parametrize("direction", [(0.0, 1.0), (-0.6, 0.8), (0.28, -0.96)])
def test_far_point_is_the_dead_force_of_its_direction(direction):
    """P = r_tip0 + 1e6 L d: the rope's pull is the dead force T d, up to the turn |dr|/1e6 L."""
    d = np.array(direction)
    P = [float(v) for v in np.array([1.0, 0.0]) + 1e6 * d]
    levels = [0.0, 1.0, 3.0, 6.0]
    rope = run_method(_case(f"toward = [{P[0]!r}, {P[1]!r}]", levels), "elastica")
    dead = run_method(_case(f"direction = [{direction[0]!r}, {direction[1]!r}]", levels), "elastica")
    assert rope.status is RunStatus.OK, rope.message
    assert dead.status is RunStatus.OK, dead.message
    for q in ("x", "y"):
        a, b = _values(rope, q), _values(dead, q)
        for level in range(1, len(levels)):
            assert abs(a[level] - b[level]) < 1e-5, (q, level, a[level], b[level])
    moved = math.hypot(_values(dead, "x")[3] - 1.0, _values(dead, "y")[3])
    assert moved > 0.3  # a large deflection, not a trivial limit


# (label, load, values, boundary, curvature): rope (angle 0) and a force at 90 deg to the line, on
# straight and initially curved segments and the boundaries that take a tip force
FEM_CASES = [
    ("straight rope", "toward = [1.0, 1.2]", [0.0, 2.0, 5.0, 8.0], "fixed-free", 0.0),
    ("straight 90 deg", "toward = [1.2, 0.0]\nangle = 90.0", [0.0, 2.0, 5.0, 8.0], "fixed-free", 0.0),
    ("curved rope", "toward = [0.2, 1.5]", [0.0, 2.0, 5.0], "fixed-free", 0.8),
    ("curved 90 deg", "toward = [0.2, 1.5]\nangle = 90.0", [0.0, 0.5, 1.0, 1.5, 2.0], "fixed-free", 0.8),
    ("curved -90 deg", "toward = [1.5, 0.0]\nangle = -90.0", [0.0, 2.0, 4.0, 7.0], "fixed-free", -0.6),
    ("fixed-pinned rope", "toward = [1.5, 1.0]", [0.0, 2.0, 5.0], "fixed-pinned", 0.0),
    ("fixed-guided rope", "toward = [1.0, 1.5]", [0.0, 5.0, 15.0], "fixed-guided", 0.0),
]


@pytest.mark.parametrize("label,load,values,boundary,curvature", FEM_CASES, ids=[c[0] for c in FEM_CASES])
def test_against_the_fem_within_its_error_estimate(label, load, values, boundary, curvature):
    case = _case(load, values, boundary, curvature)
    ela, fem = run_method(case, "elastica"), run_method(case, "fem")
    assert ela.status is RunStatus.OK, ela.message
    assert fem.status is RunStatus.OK, fem.message
    checked = 0
    for req, v in ela.values.items():
        if req.quantity not in ELASTICA_TOL or req.level == 0:
            continue
        bound = 3.0 * fem.error_estimate[req] + ELASTICA_TOL[req.quantity]
        assert abs(v - fem.values[req]) <= bound, (label, req, v, fem.values[req], fem.error_estimate[req])
        checked += 1
    assert checked == 3 * (len(values) - 1)
    moved = max(
        math.hypot(
            ela.values[Request("x", "tip", lv)] - ela.values[Request("x", "tip", 0)],
            ela.values[Request("y", "tip", lv)] - ela.values[Request("y", "tip", 0)],
        )
        for lv in range(len(values))
    )
    assert moved > 0.1  # large deflections, where the pull turns


def test_long_load_steps_stay_on_the_connected_branch():
    """A force at 90 deg to the line swings the curved tip round below the axis between T = 1 and 3;
    levels [0, 1, 3] must land where the finely stepped FEM path (0.1 apart) does, not on the other
    equilibrium a single long step can reach."""
    load = "toward = [0.2, 1.5]\nangle = 90.0"
    coarse = run_method(_case(load, [0.0, 1.0, 3.0], curvature=0.8), "elastica")
    fine = [round(0.1 * k, 10) for k in range(31)]
    fem = run_method(_case(load, fine, curvature=0.8), "fem")
    assert coarse.status is RunStatus.OK and fem.status is RunStatus.OK
    for q in ("x", "y"):
        e, f = coarse.values[Request(q, "tip", 2)], fem.values[Request(q, "tip", 30)]
        assert abs(e - f) <= 3.0 * fem.error_estimate[Request(q, "tip", 30)] + 1e-9, (q, e, f)
    assert coarse.values[Request("y", "tip", 2)] < -0.2  # below the axis, the connected branch


@pytest.mark.parametrize(
    "load,curvature",
    [
        ("toward = [1.0, 1.2]", 0.0),
        ("toward = [1.2, 0.0]\nangle = 90.0", 0.0),
        ("toward = [0.2, 1.5]\nangle = 90.0", 0.8),
        ("toward = [-0.5, 0.4]\nangle = 30.0", 0.8),
    ],
)
def test_converged_force_points_at_the_target(load, curvature):
    """F = T R(a)(P - r_tip)/|P - r_tip| at every level: the tip force's direction within 1e-9 rad."""
    values = [0.0, 0.7, 1.5, 2.5]
    case = _case(load, values, curvature=curvature, loads_out=True)
    run = run_method(case, "elastica")
    assert run.status is RunStatus.OK, run.message
    spec = case.loads[0]
    P, a = np.array(spec.toward), math.radians(spec.angle)
    for level in range(1, len(values)):
        r = np.array([run.values[Request("x", "tip", level)], run.values[Request("y", "tip", level)]])
        F = np.array([run.values[Request("force_x", "tip", level)], run.values[Request("force_y", "tip", level)]])
        line = P - r
        want = np.array([math.cos(a) * line[0] - math.sin(a) * line[1], math.sin(a) * line[0] + math.cos(a) * line[1]])
        turn = math.atan2(want[0] * F[1] - want[1] * F[0], want @ F)
        assert abs(turn) < 1e-9, (level, turn)
        assert math.hypot(*F) == pytest.approx(values[level], rel=1e-12)


def test_library_pointed_force_on_a_pinned_tip():
    """The library's own condition g = wrap(atan2(P - r_L) + a - phi) = 0 with the tip's y held (a
    pin: its reaction takes the y part of the tip force), and a warm start from a converged pull
    reaching the same state as the solve from rest."""
    k0 = 0.8
    x0, y0, th0 = unloaded_tip(1.0, k0)
    pin = (TipConstraint((0.0, 1.0), y0),)
    pulled = solve_path(ElasticaProblem(curvature=k0, pointed=(PointedForce(4.0, (1.5, 1.0)),), constraints=pin))
    assert pulled.converged, pulled.message
    assert np.max(np.abs(pointing_error(pulled))) < 1e-9
    assert abs(pulled.y - y0) < 1e-10 and abs(pulled.theta - th0) > 0.03
    target = ElasticaProblem(curvature=k0, pointed=(PointedForce(7.0, (1.5, 1.0)),), constraints=pin)
    more, rest = solve_path(target, start=pulled), solve_path(target)
    assert more.converged and rest.converged
    assert abs(more.x - rest.x) < 1e-9 and abs(more.theta - rest.theta) < 1e-9


def test_fixed_fixed_is_refused_with_the_reason():
    case = _case("toward = [1.0, 1.0]", [0.0, 1.0], boundary="fixed-fixed")
    with pytest.raises(NotApplicable, match="fixed-fixed.*turns"):
        adapter.level_problems(case, options_of("elastica", {}))
