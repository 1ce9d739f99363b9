"""FEM outputs the PRBM gives: largest bending stress, inflection points, mechanical advantage.

Expected values are exact: sigma = M c / I under a uniform moment; no inflection in a cantilever
under a tip force, one in a fixed-guided beam with a transverse tip offset (antisymmetric S shape);
MA = a/b for a rigid lever with the input at a and the output at b from the pivot.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from validation.methods import fem as fem_adapter
from validation.run.runner import requests_for
from validation.case.schema import Case
from validation.case.method_options import options_of

SEGMENT = """
[case]
id = "t"
title = "t"
group = "tests"
units = "SI"
[segment]
boundary = "{boundary}"
length = 2.0
E = 2.0e11
section = {{ kind = "rectangle", width = 0.02, thickness = 0.004 }}
[[loads]]
kind = "{kind}"
direction = [0.0, 1.0]
values = [{value}]
[[outputs]]
quantity = "max_stress"
[[outputs]]
quantity = "inflection_points"
[methods.fem]
elements = 16
"""


def _run(text, options=None):
    case = Case.model_validate(tomllib.loads(text))
    options = options if options is not None else dict(case.methods["fem"])
    return fem_adapter.run(case, requests_for(case, "fem"), options_of("fem", options))


def test_max_stress_under_a_uniform_moment_is_Mc_over_I():
    M, c, I = 3.0, 0.002, 0.02 * 0.004**3 / 12
    run = _run(SEGMENT.format(boundary="fixed-free", kind="moment", value=M).replace("direction = [0.0, 1.0]\n", ""))
    assert run.values[("max_stress", "", 0)] == pytest.approx(M * c / I, rel=1e-6)
    assert run.values[("inflection_points", "", 0)] == 0.0


def test_inflection_points_count_curvature_sign_changes():
    cantilever = _run(SEGMENT.format(boundary="fixed-free", kind="force", value=50.0))
    assert cantilever.values[("inflection_points", "", 0)] == 0.0
    s_shape = _run(SEGMENT.format(boundary="fixed-guided", kind="displacement", value=0.3))
    assert s_shape.values[("inflection_points", "", 0)] == 1.0


LEVER = """
[case]
id = "lever"
title = "lever"
group = "tests"
units = "SI"
[mechanism]
E = 2.0e11
nodes = [{{ name = "B", x = -{b}, y = 0.0 }}, {{ name = "O", x = 0.0, y = 0.0 }}, {{ name = "A", x = {a}, y = 0.0 }}]
beams = [
  {{ name = "arm_b", start = "B", end = "O", section = {{ kind = "rectangle", width = 0.05, thickness = 0.05 }} }},
  {{ name = "arm_a", start = "O", end = "A", section = {{ kind = "rectangle", width = 0.05, thickness = 0.05 }} }},
]
supports = [{{ node = "O", kind = "pinned" }}, {{ node = "B", kind = "slider", direction = [1.0, 0.0] }}]
[[loads]]
kind = "force"
point = "A"
direction = [0.0, -1.0]
values = [0.0, 100.0]
[[outputs]]
quantity = "mechanical_advantage"
[methods.fem]
elements = 4
ma = {{ output = "B", direction = [0.0, 1.0] }}
"""


@pytest.mark.parametrize("a, b", [(0.3, 0.1), (0.1, 0.4)])
def test_mechanical_advantage_of_a_lever_is_a_over_b(a, b):
    run = _run(LEVER.format(a=a, b=b))
    for level in (0, 1):
        assert run.values[("mechanical_advantage", "", level)] == pytest.approx(a / b, rel=1e-5)


def test_mechanical_advantage_needs_its_output():
    from validation.methods.base import NotApplicable

    text = LEVER.format(a=0.3, b=0.1).replace('ma = { output = "B", direction = [0.0, 1.0] }', "")
    with pytest.raises(NotApplicable, match="ma = "):
        _run(text)


SPRUNG_LEVER = """
[case]
id = "sprung_lever"
title = "sprung lever"
group = "tests"
units = "SI"
[mechanism]
E = 2.0e11
nodes = [{{ name = "O", x = 0.0, y = 0.0 }}, {{ name = "B", x = {b}, y = 0.0 }}, {{ name = "A", x = {a}, y = 0.0 }}]
beams = [
  {{ name = "OB", start = "O", end = "B", section = {{ kind = "rectangle", width = 0.05, thickness = 0.05 }} }},
  {{ name = "BA", start = "B", end = "A", section = {{ kind = "rectangle", width = 0.05, thickness = 0.05 }} }},
]
joints = [{{ node = "O", members = ["OB"], spring = {k} }}]
supports = [{{ node = "O", kind = "pinned", member = "OB" }}]
[[loads]]
kind = "force"
point = "A"
direction = [0.0, -1.0]
values = [50.0, 100.0]
[[loads]]
kind = "displacement"
point = "B"
direction = [0.0, 1.0]
values = [-{delta}, -{delta}]
[[outputs]]
quantity = "mechanical_advantage"
[methods.fem]
elements = 4
ma = {{ output = "B", direction = [0.0, -1.0], definition = "{definition}" }}
"""


@pytest.mark.parametrize("definition", ["secant", "tangent"])
def test_secant_mechanical_advantage_carries_the_compliance(definition):
    """Lever O-B-A with a torsional spring k at its ground pivot O, output B held pushed down by
    delta: the input F down at a gives, by moments about O, F_out = (F a - k delta/b)/b (rotation
    delta/b = 0.01), so the secant MA is a/b - k delta/(F b^2) and the tangent one a/b."""
    a, b, k, delta = 0.3, 0.1, 200.0, 0.001
    run = _run(SPRUNG_LEVER.format(a=a, b=b, k=k, delta=delta, definition=definition))
    for level, F in enumerate((50.0, 100.0)):
        expected = a / b - k * delta / (F * b * b) if definition == "secant" else a / b
        assert run.values[("mechanical_advantage", "", level)] == pytest.approx(expected, rel=2e-3)


def test_the_error_estimate_refines_the_beams_and_not_the_stiff_bars_of_rigid_links():
    """A pinned rigid link is modelled as straight bars 1e6 times stiffer than the stiffest beam, one
    element each (`fem_adapter._mechanism_model`): a rigid body, with no discretisation error of its own.
    The error estimate's finer mesh (``refine=2`` of the n-element model) is then the mesh of the plain
    2n-element run, the beams doubled and each bar still one element, so that the estimate and the
    benchmark's Richardson on plain runs refine the same family of meshes (chapter 9's Test 2: a
    compliant beam and one bar). Splitting the bars instead adds stiff unknowns: the cold solve of such
    a mesh needed 25 load steps where the plain one needs 4."""
    from fem.discretise import discretise
    from validation.case.loader import case_by_id

    case = case_by_id("bapat2015_test2").case
    options = options_of("fem", case.methods.get("fem"))
    coarse, doubled = fem_adapter.build_model(case, 2, options), fem_adapter.build_model(case, 4, options)
    bars = [m for m in coarse.members if ":" in m.name]
    assert bars and all(not m.refined and m.n_elements == 1 for m in bars)
    fine, plain = discretise(coarse, refine=2), discretise(doubled)
    assert np.array_equal(fine.X, plain.X) and np.array_equal(fine.conn, plain.conn)
