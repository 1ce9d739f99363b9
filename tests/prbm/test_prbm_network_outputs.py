"""Reactions and mechanical advantage of the PRB network built by rule (issue 23), against statics
derived here.

* Parallel-guided mechanism (two beams L = 1 clamped at G1 = (0, 0) and G2 = (0, h), h = 0.5, a
  coupler at x = L, a force F along +y at M = (L, h/2)): each beam becomes seed 004's two-pivot PRBM
  with equal springs k. At small F, by the symmetry of that PRBM the two springs of a beam carry the
  same moment k Theta, and the middle link's equilibrium gives 2 k Theta = (F/2) gamma L; the root
  moment is then -(k Theta + (F/2)(1 - gamma) L/2) = -F L/4 at each clamp, R_y = -F/2 at each, and
  moments about G1 give R_x(G2) = -R_x(G1) = (F L - F L/2)/h = F. At any load, the reactions and the
  applied force are in equilibrium (forces and moments about the origin, the force at its deformed
  point).
* A rigid lever pinned to the ground at O, an input force F at A (distance a from O) perpendicular
  to it, the output B (distance b on the other side) held by a slider across the lever: the force the
  lever exerts on the output support is F a / b, so MA = a/b, tangent and secant alike.
"""

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from validation.case.loader import load_case
from validation.case.schema import Case
from validation.methods import prbm as adapter
from validation.methods import prbm_network as pn
from validation.methods.base import Request
from validation.run.runner import run_method
from validation.case.method_options import options_of

ROOT = Path(__file__).resolve().parents[2]


def _parallel_guided(force: list[float]) -> Case:
    case = load_case(ROOT / "cases/seed004/parallel_guided.toml").case
    load = case.loads[0].model_copy(update={"values": force, "ramp": None})
    return case.model_copy(update={"loads": [load], "level_labels": None})


def test_parallel_guided_reactions_at_small_load_match_statics():
    F = 1e-5
    case = _parallel_guided([F])
    requests = [Request(q, p, 0) for p in ("G1", "G2") for q in ("reaction_x", "reaction_y", "reaction_moment")]
    case = case.model_copy(update={"outputs": []})
    run = adapter.run(case, requests, options_of("prbm", {}))
    v = {(r.point, r.quantity): run.values[r] for r in requests}
    assert v[("G1", "reaction_y")] == pytest.approx(-F / 2, rel=1e-4)
    assert v[("G2", "reaction_y")] == pytest.approx(-F / 2, rel=1e-4)
    assert v[("G1", "reaction_moment")] == pytest.approx(-F / 4, rel=1e-4)
    assert v[("G2", "reaction_moment")] == pytest.approx(-F / 4, rel=1e-4)
    assert v[("G2", "reaction_x")] == pytest.approx(F, rel=1e-4)
    assert v[("G1", "reaction_x")] == pytest.approx(-F, rel=1e-4)


def test_parallel_guided_reactions_balance_the_load_at_large_deflection():
    case = _parallel_guided([2.0, 9.0, 16.0])
    model = pn.built_model(case.mechanism, None)
    result = pn.solve_case(case, model)
    nodes = {n.name: np.array([n.x, n.y]) for n in case.mechanism.nodes}
    for level, F in enumerate((2.0, 9.0, 16.0)):
        M_at = result.position("M", level)
        force = np.array([0.0, F])
        moment = M_at[0] * F
        for node in ("G1", "G2"):
            R = pn.reaction(case, model, result, node, level)
            force += R[:2]
            moment += R[2] + nodes[node][0] * R[1] - nodes[node][1] * R[0]
        assert np.abs(force).max() <= 1e-9 * F and abs(moment) <= 1e-9 * F
        assert pn.reaction(case, model, result, "G1", level)[1] < 0  # the ground pulls the beams down


LEVER = """
[case]
id = "lever_ma"
title = "a rigid lever, pinned at O, input at A, output held at B"
group = "test"
units = "dimensionless"
description = "MA = a/b by statics"
[mechanism]
E = 1.0
nodes = [ { name = "A", x = -2.0, y = 0.0 }, { name = "O", x = 0.0, y = 0.0 }, { name = "B", x = 0.5, y = 0.0 } ]
links = [ { name = "lever", nodes = ["A", "O", "B"] } ]
supports = [ { node = "O", kind = "pinned" }, { node = "B", kind = "slider", direction = [1.0, 0.0] } ]
[[loads]]
kind = "force"
point = "A"
direction = [0.0, -1.0]
values = [1.0, 3.0]
[[outputs]]
quantity = "mechanical_advantage"
[methods.prbm]
ma = { output = "B", direction = [0.0, 1.0], definition = "DEFINITION" }
"""


@pytest.mark.parametrize("definition", ["tangent", "secant"])
def test_lever_mechanical_advantage_is_the_arm_ratio(definition):
    case = Case.model_validate(tomllib.loads(LEVER.replace("DEFINITION", definition)))
    run = run_method(case, "prbm")
    assert run.ok, run.message
    for level in (0, 1):
        assert run.values[Request("mechanical_advantage", "", level)] == pytest.approx(2.0 / 0.5, rel=1e-6)


CANTILEVER_BY_RULE = """
[case]
id = "cantilever_by_rule"
title = "a cantilever written as a mechanism, an oblique dead force at its free end"
group = "test"
units = "dimensionless"
description = "the builder takes gamma(n), K_Theta(n) where the end load defines n"
[mechanism]
E = 3.0
nodes = [ { name = "O", x = 0.0, y = 0.0 }, { name = "T", x = TX, y = TY } ]
beams = [ { name = "b", start = "O", end = "T", section = { kind = "inertia", I = 1.0, A = 1.0e8 } } ]
supports = [ { node = "O", kind = "fixed" } ]
[[loads]]
kind = "force"
point = "T"
direction = [DX, DY]
values = [1.0, 2.5]
[[outputs]]
quantity = "dx"
point = "T"
[[outputs]]
quantity = "dy"
point = "T"
[methods.prbm]
"""


# seed 000 eq (41) gamma and eq (43) K_Theta at n = 0.75 (branches -0.5 < n <= 10) and n = -1.2 (gamma:
# -1.5 < n <= -0.5; K_Theta: -4 < n <= -0.5), from the printed coefficients
PRINTED_FITS = {
    0.75: (
        0.851892 - 0.020805 * 0.75 + 0.005867 * 0.75**2 - 0.000895 * 0.75**3 + 0.000069 * 0.75**4 - 0.000002 * 0.75**5,
        2.648834 - 0.074727 * 0.75 + 0.026328 * 0.75**2 - 0.004609 * 0.75**3 + 0.000390 * 0.75**4 - 0.000013 * 0.75**5,
    ),
    -1.2: (0.852138 - 0.018615 * -1.2, 2.66041 - 0.069005 * -1.2 - 0.002268 * 1.44),
}


@pytest.mark.parametrize("n", [0.75, -1.2])
@pytest.mark.parametrize("path", ["segment with body", "network"])
def test_a_free_end_with_a_dead_force_takes_the_n_fits(n, path):
    """The one-beam mechanism, by the segment-with-body path and by the network built by rule, is the
    fixed-pinned PRBM (seed 000 eqs 41-49, Pauly-Midha) at the end load's ratio, written out here: gamma
    and K_Theta from the printed polynomials at n, Theta the root of (F l^2/EI) sin(phi - Theta) =
    K_Theta Theta (46)-(47), a = l - gamma l (1 - cos Theta), b = gamma l sin Theta (48)-(49)."""
    angle, L, EI = 0.5, 2.0, 3.0
    c, s = math.cos(angle), math.sin(angle)
    local = np.array([-n, 1.0]) / math.hypot(n, 1.0)  # (-nP, P) in the beam frame
    d = (c * local[0] - s * local[1], s * local[0] + c * local[1])
    text = (
        CANTILEVER_BY_RULE.replace("TX", repr(L * c))
        .replace("TY", repr(L * s))
        .replace("DX", repr(float(d[0])))
        .replace("DY", repr(float(d[1])))
    )
    if path == "network":
        text = text.replace("[methods.prbm]", '[methods.prbm]\nmodel = "network"')
    case = Case.model_validate(tomllib.loads(text))
    run = run_method(case, "prbm")
    assert run.ok, run.message
    if path == "network":
        assert f"n = {n:.4g}" in run.message
    for level, F in enumerate((1.0, 2.5)):
        gamma, K = PRINTED_FITS[n]
        phi = math.atan2(1.0, -n)
        Theta = brentq(lambda t: F * L**2 / EI * math.sin(phi - t) - K * t, 0.0, phi)
        a, b = L - gamma * L * (1.0 - math.cos(Theta)), gamma * L * math.sin(Theta)
        expected = (c * a - s * b - L * c, s * a + c * b - L * s)
        assert run.values[Request("dx", "T", level)] == pytest.approx(expected[0], abs=1e-9 * L)
        assert run.values[Request("dy", "T", level)] == pytest.approx(expected[1], abs=1e-9 * L)
