"""Sprung joints realised as small-length flexural pivots (validation/methods/slfp.py) for the FEM.

A rigid link pinned to the ground with a torsional spring k, turned by a prescribed rotation at its
far end and otherwise free: the flexure (k = E I / l, seed 000 eq 186) carries a pure end moment,
under which a beam bends into an arc with end rotation M l / (E I) exactly, so the FEM's input
torque must be k * theta for any flexure length, at any angle (a 10 % error in I, or a flexure of
the wrong length, fails). Also: the construction (node placement, supports) and bad sizes.
"""

from __future__ import annotations

import math

import pytest
from pydantic import ValidationError

from validation.methods import fem as fem_adapter
from validation.methods.base import NotApplicable, Request
from validation.case.loader import describe_all
from validation.case.schema import Case
from validation.methods.slfp import with_flexures
from validation.case.method_options import options_of

K = 12.5  # in-lb/rad
E = 450000.0  # psi


BAR = {  # a rigid bar O -> T pinned at O to the ground with a torsional spring K
    "nodes": [{"name": "O", "x": 0.0, "y": 0.0}, {"name": "T", "x": 3.0, "y": 4.0}],
    "links": [{"name": "bar", "nodes": ["O", "T"]}],
    "joints": [{"node": "O", "members": ["bar"], "spring": K}],
    "supports": [{"node": "O", "kind": "pinned", "member": "bar"}],
}


def _case(rotations_deg, slfp):
    return Case.model_validate(
        {
            "case": {"id": "slfp_probe", "title": "t", "group": "g", "units": "in-lb"},
            "mechanism": BAR,
            "loads": [{"kind": "rotation", "point": "T", "body": "bar", "values": rotations_deg}],
            "outputs": [{"quantity": "input_torque"}],
            "methods": {"fem": {"elements": 4, "error_estimate": False, "slfp": slfp}},
        }
    )


@pytest.mark.parametrize("length", [0.1, 0.8])
def test_flexure_under_pure_moment_gives_the_spring_torque(length):
    rotations = [10.0, 60.0]
    case = _case(rotations, {"length": length, "E": E})
    requests = [Request("input_torque", "", lv) for lv in range(2)]
    run = fem_adapter.run(case, requests, options_of("fem", case.methods["fem"]))
    assert run.converged, run.message
    for lv, theta in enumerate(rotations):
        assert run.values[requests[lv]] == pytest.approx(K * math.radians(theta), rel=1e-6)


def test_construction():
    case = with_flexures(_case([10.0], {"length": 0.5, "E": E}), 0.5, E, thickness_ratio=0.1)
    mech = case.mechanism
    nodes = {n.name: (n.x, n.y) for n in mech.nodes}
    assert "O" not in nodes  # the pivot is no material point
    assert nodes["O-"] == pytest.approx((-0.15, -0.2))  # centred on O, along O -> T
    assert nodes["O+"] == pytest.approx((0.15, 0.2))
    (flexure,) = mech.beams
    EI = E * flexure.section.inertia()
    assert EI / 0.5 == pytest.approx(K)  # k = E I / l
    assert flexure.section.thickness == pytest.approx(0.05)
    assert [(s.node, s.kind) for s in mech.supports] == [("O-", "fixed")]
    assert mech.links[0].nodes == ["O+", "T"]
    assert mech.joints == []


def test_bad_sizes_are_named():
    case = _case([10.0], {"length": 20.0, "E": E})
    with pytest.raises(NotApplicable, match="methods.fem.slfp: flexure at 'O'"):
        fem_adapter.run(case, [Request("input_torque", "", 0)], options_of("fem", case.methods["fem"]))
    with pytest.raises(ValidationError) as info:  # a missing size is refused when the case is read
        _case([10.0], {"E": E})
    assert ("methods.fem.slfp.length", "Field required") in describe_all(info.value)


def test_position_reached_by_an_input_moment():
    """methods.fem.input_moment_at: the bar's far end T is sent to the x a pure-moment flexure reaches
    at rotation theta (exact arc: the flexure end at O- + (l/theta)(sin theta u + (1 - cos theta) v),
    the bar then along the rotated u); the moment found must be k theta (to the O(h^2) error of the
    chord elements' arc, about 2e-6 with 16 elements)."""
    length, theta = 0.4, math.radians(35.0)
    u, v = (0.6, 0.8), (-0.8, 0.6)  # along O -> T, and its normal
    base = (-0.5 * length * u[0], -0.5 * length * u[1])
    arc = (length / theta * math.sin(theta), length / theta * (1 - math.cos(theta)))
    bar = 5.0 - 0.5 * length  # |T - O+|
    along = (math.cos(theta), math.sin(theta))
    x_T = base[0] + (arc[0] + bar * along[0]) * u[0] + (arc[1] + bar * along[1]) * v[0]
    case = Case.model_validate(
        {
            "case": {"id": "slfp_drive", "title": "t", "group": "g", "units": "in-lb"},
            "mechanism": BAR,
            "loads": [{"kind": "displacement", "point": "T", "direction": [1.0, 0.0], "values": [0.0, x_T - 3.0]}],
            "outputs": [{"quantity": "input_torque"}, {"quantity": "y", "point": "T"}],
            "methods": {
                "fem": {
                    "elements": 16,
                    "error_estimate": False,
                    "input_moment_at": "O+",
                    "slfp": {"length": length, "E": E},
                }
            },
        }
    )
    requests = [Request("input_torque", "", 1), Request("y", "T", 1)]
    run = fem_adapter.run(case, requests, options_of("fem", case.methods["fem"]))
    assert run.converged, run.message
    assert run.values[requests[0]] == pytest.approx(K * theta, rel=2e-5)
    y_T = base[1] + (arc[0] + bar * along[0]) * u[1] + (arc[1] + bar * along[1]) * v[1]
    assert run.values[requests[1]] == pytest.approx(y_T, abs=1e-4)  # 2e-5 in theta times the 5 in lever
