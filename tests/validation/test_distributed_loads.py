"""Distributed loads and loads attached to bodies, against independent solutions.

The reference for a large uniform load is the elastica solved by a different method from the
project's shooting: collocation (scipy.integrate.solve_bvp) of

    x' = cos(theta), y' = sin(theta), theta' = m, m' = Nx sin(theta) - Ny cos(theta),
    N' = -q(s)   (N the force carried across the section from the outboard part),

with x(0) = y(0) = theta(0) = 0 at the clamp and m(1) = 0, N(1) = 0 at the free end (L = EI = 1).
A dead load has q constant; a follower load q(s) = R(theta(s)) q0 turns with the beam.
"""

from __future__ import annotations

import math
import numpy as np
import pytest
from scipy.integrate import solve_bvp

import fem
from fem.assembly import System
from fem.discretise import discretise
from validation.case.loader import case_by_id
from validation.methods import elastica as elastica_adapter
from validation.methods import fem as fem_adapter
from validation.run.runner import requests_for
from validation.case.schema import Case, SectionSpec
from validation.case.method_options import options_of


def collocation_elastica(loads, follower=False):
    """Tip (x, y, theta) of the unit cantilever under a uniform load (0, w) per unit length, for each
    w in ``loads`` (continued from the previous one), by collocation."""

    def rhs(s, Y, w):
        x, y, th, m, nx, ny = Y
        c, sn = np.cos(th), np.sin(th)
        qx, qy = (-sn * w, c * w) if follower else (0.0 * s, w + 0.0 * s)
        return np.vstack([c, sn, m, nx * sn - ny * c, -qx, -qy])

    def bc(Ya, Yb):
        return np.array([Ya[0], Ya[1], Ya[2], Yb[3], Yb[4], Yb[5]])

    s = np.linspace(0.0, 1.0, 101)
    Y = np.zeros((6, s.size))
    Y[0] = s
    tips = []
    for w in loads:
        sol = solve_bvp(lambda s, Y: rhs(s, Y, w), bc, s, Y, tol=1e-8, max_nodes=100000)
        assert sol.success, sol.message
        s, Y = sol.x, sol.y
        tips.append(sol.y[:3, -1].copy())
    return np.array(tips)


def test_uniform_dead_load_cantilever_matches_collocation():
    """Done-means of issue 16: q L^3/EI up to 30 in the case syntax; elastica to 1e-6, FEM within its
    own Richardson estimate (the estimate of the 2n-element value, asymptotically exact: allowed 1.5x)."""
    loaded = case_by_id("cantilever_uniform_load")
    case = loaded.case
    q = case.loads[0].levels()
    exact = collocation_elastica(q)
    ela = elastica_adapter.run(case, requests_for(case, "elastica"), options_of("elastica", case.methods["elastica"]))
    res = fem_adapter.run(case, requests_for(case, "fem"), options_of("fem", case.methods["fem"]))
    assert ela.converged and res.converged
    for level, (x, y, th) in enumerate(exact):
        for quantity, value in (("x", x), ("y", y), ("rotation", math.degrees(th))):
            req = (quantity, "tip", level)
            scale = 1.0 if quantity != "rotation" else 180 / math.pi
            assert abs(ela.values[req] - value) <= 1e-6 * scale, (req, ela.values[req], value)
            err = abs(res.values[req] - value)
            assert err <= 1.5 * res.error_estimate[req] + 1e-12 * scale, (req, err, res.error_estimate[req])
    # large load: really large deflection (the tip turned past 80 degrees)
    assert math.degrees(exact[-1, 2]) > 80.0


def test_small_uniform_load_linear_theory():
    """q L^4/8EI and q L^3/6EI, the tip deflection and rotation of linear beam theory."""
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", 2.0, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(1e10, 3.0), n_elements=4)
    m.add_support("root", "fixed")
    m.add_distributed(0.0, -1e-5)
    r = fem.solve(m)
    w, EI, L = -1e-5, 3.0, 2.0
    assert r.displacement("tip")[1] == pytest.approx(w * L**4 / (8 * EI), rel=1e-6)
    assert r.rotation("tip") == pytest.approx(w * L**3 / (6 * EI), rel=1e-6)
    assert r.reaction("root") == pytest.approx([0.0, -w * L, -w * L**2 / 2], abs=1e-9)


def test_follower_uniform_load_matches_collocation():
    """A load that stays normal to the beam (a pressure), q L^3/EI = 4 and 8."""
    loads = [4.0, 8.0]
    exact = collocation_elastica(loads, follower=True)
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", 1.0, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(1e10, 1.0), n_elements=16)
    m.add_support("root", "fixed")
    m.add_distributed(0.0, loads, follower=True)
    est = fem.solve_with_error_estimate(m)
    assert est.converged
    for level, (x, y, th) in enumerate(exact):
        xy, err = est.position("tip", level)
        assert np.all(np.abs(xy - [x, y]) <= 2 * err + 1e-9), (xy, [x, y], err)
    # not the dead-load answer: the follower load turns the beam further
    dead = collocation_elastica(loads)
    assert exact[-1, 2] > dead[-1, 2] + 0.3


def _tangent_error(model):
    d = discretise(model)
    s = System(model, d)
    rng = np.random.default_rng(3)
    q = 0.2 * rng.standard_normal(s.n)
    loads = s.loads_at(-1, 0, 1.0)
    beta = d.beta0.copy()
    K = s.layout.to_dense(s.evaluate(q, beta, 1.0, *loads)["K"])
    h = 1e-6
    J = np.zeros_like(K)
    for i in range(s.n):
        e = np.zeros(s.n)
        e[i] = h
        J[:, i] = (
            s.evaluate(q + e, beta, 1.0, *loads, need_K=False)["r"]
            - s.evaluate(q - e, beta, 1.0, *loads, need_K=False)["r"]
        ) / (2 * h)
    return np.abs(J - K).max() / np.abs(K).max()


@pytest.mark.parametrize("kind", ["dead", "follower", "rope", "angled", "member_follower"])
def test_load_stiffness_is_the_derivative_of_the_residual(kind):
    """The consistent tangent includes each load's stiffness (central differences of the residual)."""
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("A", 1.0, 0.3)
    m.add_node("P", 2.0, 1.5)
    m.add_member("root", "A", fem.Section.from_EI(50.0, 1.0), n_elements=3, curvature=0.3)
    m.add_member("A", "P", fem.Section.from_EI(50.0, 2.0), n_elements=2)
    m.add_support("root", "fixed")
    m.add_joint("A")
    if kind == "dead":
        m.add_distributed([0.7], [-1.3], member=0)
    elif kind == "follower":
        m.add_distributed([0.4], [0.9], member=1, follower=True)
    elif kind == "rope":
        m.add_pointed_force("P", [2.0], (3.0, 4.0))
    elif kind == "angled":
        m.add_pointed_force("P", [2.0], (3.0, 4.0), angle=0.4)
    else:
        m.add_force("A", [0.3], [0.5], follower=True, member=1)
    assert _tangent_error(m) < 1e-7


def test_rope_force_points_at_its_pulley_and_matches_the_elastica():
    """A rope from the tip over a pulley at P: in the deformed state the force points from the tip
    to P, and the elastica under that dead force reaches the same tip."""
    from elastica.shooting import solve_elastica

    P, T = np.array([0.3, 1.5]), 3.0
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", 1.0, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(1e10, 1.0), n_elements=16)
    m.add_support("root", "fixed")
    m.add_pointed_force("tip", [T], tuple(P))
    est = fem.solve_with_error_estimate(m)
    tip, err = est.position("tip", 0)
    fine_tip, reaction = est.result.position("tip", 0), est.result.reaction("root")
    e = (P - fine_tip) / np.hypot(*(P - fine_tip))
    assert np.allclose(-reaction[:2], T * e, atol=1e-6)
    ref = solve_elastica(1.0, 1.0, force=tuple(T * e))
    assert np.all(np.abs(tip - [ref.x, ref.y]) <= 2 * err + 1e-9)
    assert math.hypot(*(tip - [1.0, 0.0])) > 0.3  # a large deflection


LAYERS = (
    '{ kind = "layers", layers = [{ E = 1.0, width = 1.0, thickness = 2.0, weight_density = 0.5 }, '
    "{ E = 3.0, width = 2.0, thickness = 1.0, weight_density = 0.25 }] }"
)


def _case(loads, section=LAYERS):
    """A one-segment case (dimensionless, fixed-free, L = 1) with the given section and [[loads]] text."""
    import tomllib

    text = f"""
[case]
id = "t"
title = "t"
group = "tests"
units = "dimensionless"
[segment]
boundary = "fixed-free"
length = 1.0
E = 1.0
section = {section}
{loads}
[[outputs]]
quantity = "y"
[methods.fem]
elements = 8
error_estimate = false
"""
    return Case.model_validate(tomllib.loads(text))


def test_self_weight_is_the_section_weight_along_gravity():
    """Self-weight = sum of weight density x area per unit length (0.5*2 + 0.25*2 = 1.5) along gravity."""
    weight = _case('[[loads]]\nkind = "self_weight"\ndirection = [0.0, -2.0]\nvalues = [1.0, 2.0]')
    line = _case('[[loads]]\nkind = "distributed"\ndirection = [0.0, -1.0]\nvalues = [1.5, 3.0]')
    a = fem_adapter.run(weight, requests_for(weight, "fem"), options_of("fem", {"error_estimate": False}))
    b = fem_adapter.run(line, requests_for(line, "fem"), options_of("fem", {"error_estimate": False}))
    assert a.values == pytest.approx(b.values, rel=1e-12)
    assert all(v < 0 for v in a.values.values())


def test_bonded_layers_bend_as_one_section():
    """Two bonded layers of one material are a single rectangle of the total thickness:
    EI = E b (h1 + h2)^3 / 12 (here b = 1, h = 1 + 2), whatever the order of the layers."""
    layers = [{"E": 2.0, "width": 1.0, "thickness": 1.0}, {"E": 2.0, "width": 1.0, "thickness": 2.0}]
    bonded = SectionSpec(kind="layers", layers=layers, bonded=True)
    assert bonded.stiffness(None)[1] == pytest.approx(2.0 * 27.0 / 12.0, rel=1e-12)
    assert SectionSpec(kind="layers", layers=layers[::-1], bonded=True).stiffness(None)[1] == pytest.approx(4.5)
    sliding = SectionSpec(kind="layers", layers=layers)
    assert sliding.stiffness(None)[1] == pytest.approx(2.0 * (1 + 8) / 12.0)


@pytest.mark.parametrize(
    "loads, message",
    [
        ('[[loads]]\nkind = "self_weight"\ndirection = [0.0, -1.0]\nvalues = [1.0]', "weight_density"),
        ('[[loads]]\nkind = "distributed"\nvalues = [1.0]', "direction"),
        ('[[loads]]\nkind = "distributed"\nmember = "b"\ndirection = [0.0, 1.0]\nvalues = [1.0]', "member"),
        ('[[loads]]\nkind = "force"\ntoward = [0.0, 1.0]\ndirection = [0.0, 1.0]\nvalues = [1.0]', "toward"),
        ('[[loads]]\nkind = "force"\nangle = 90.0\ndirection = [0.0, 1.0]\nvalues = [1.0]', "angle"),
        ('[[loads]]\nkind = "self_weight"\nfollower = true\ndirection = [0.0, -1.0]\nvalues = [1.0]', "follower"),
    ],
)
def test_bad_distributed_or_attached_loads_are_named(loads, message):
    with pytest.raises(ValueError, match=message):
        _case(loads, section='{ kind = "inertia", I = 1.0 }')


def test_point_load_methods_refuse_loads_along_the_beam():
    from validation.methods import prbm as prbm_adapter
    from validation.methods.base import NotApplicable

    case = case_by_id("cantilever_uniform_load").case
    with pytest.raises(NotApplicable, match="distributed"):
        prbm_adapter.run(case, [("y", "tip", 0)], options_of("prbm", {"model": "theta-dependent"}))
    follower = case.model_copy(update={"loads": [case.loads[0].model_copy(update={"follower": True})]})
    with pytest.raises(NotApplicable, match="follower distributed"):
        elastica_adapter.level_problems(follower, options_of("elastica", {}))


BODY_CASE = """
[case]
id = "t"
title = "t"
group = "tests"
units = "dimensionless"
[mechanism]
E = 1.0
nodes = [{{ name = "root", x = 0.0, y = 0.0 }}, {{ name = "A", x = 1.0, y = 0.0 }}, {{ name = "P", x = 1.5, y = 0.0 }}]
beams = [{{ name = "b", start = "root", end = "A", section = {{ kind = "inertia", I = 1.0, A = 1e8 }} }}]
links = [{{ name = "ext", nodes = ["A", "P"] }}]
supports = [{{ node = "root", kind = "fixed" }}]
[[loads]]
kind = "force"
point = "{point}"
direction = [0.0, 1.0]
values = [1.0, 2.0]
{attached}
[[outputs]]
quantity = "dy"
point = "P"
[methods.fem]
elements = 8
error_estimate = false
"""


@pytest.mark.parametrize("point, body", [("P", "ext"), ("A", "b")])
def test_follower_force_on_a_named_body_turns_with_it(point, body):
    """A force kept at its angle to a rigid link (or to a beam end) is the follower force of the point
    it acts on, which turns with that body; a dead force lands elsewhere."""
    import tomllib

    def tip(attached):
        case = Case.model_validate(tomllib.loads(BODY_CASE.format(point=point, attached=attached)))
        run = fem_adapter.run(case, requests_for(case, "fem"), options_of("fem", {"error_estimate": False}))
        return np.array([run.values[("dy", "P", k)] for k in (0, 1)])

    on_body = tip(f'follower = true\nbody = "{body}"')
    assert on_body == pytest.approx(tip("follower = true"), rel=1e-9)
    assert np.abs(on_body - tip("")).max() > 0.05


def test_zero_level_measures_positions_from_that_level():
    """zero_level = 0: a scale zeroed under the self-weight; y(level) - y(0) of the plain run."""
    case = _case(
        '[[loads]]\nkind = "self_weight"\ndirection = [0.0, -1.0]\nvalues = [1.0, 1.0]\n'
        '[[loads]]\nkind = "force"\ndirection = [0.0, 1.0]\nvalues = [0.0, 2.0]'
    )
    plain = fem_adapter.run(case, requests_for(case, "fem"), options_of("fem", {"error_estimate": False}))
    zeroed = fem_adapter.run(
        case, requests_for(case, "fem"), options_of("fem", {"error_estimate": False, "zero_level": 0})
    )
    sag = plain.values[("y", "tip", 0)]
    assert sag < -0.1
    assert zeroed.values[("y", "tip", 0)] == 0.0
    assert zeroed.values[("y", "tip", 1)] == pytest.approx(plain.values[("y", "tip", 1)] - sag, rel=1e-12)
