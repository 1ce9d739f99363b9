"""A prescribed displacement of a body point in the BCM's rigid body on beams (``RigidBodyOnBeams``): the
force it needs, applied as a dead force instead, must give that displacement back (the same equilibrium
read the other way), for a free parallel guide and a crank pinned to the ground."""

import numpy as np
import pytest

from bcm.mechanisms import BCMBeam, Displacement, RigidBodyOnBeams
from validation.case.schema import Case
from validation.run import coverage
from validation.run.runner import run_method

L, EI = 1.0, 1.0


def _guide() -> RigidBodyOnBeams:
    beams = [BCMBeam((0.0, 0.0), (0.0, L), EI, 1e4), BCMBeam((0.5, 0.0), (0.5, L), EI, 1e4)]
    return RigidBodyOnBeams(beams, (0.0, L))


def _crank() -> RigidBodyOnBeams:
    beams = [BCMBeam((0.0, 0.0), (1.0, 0.0), EI, 1e4)]
    return RigidBodyOnBeams(beams, (0.128, 0.0), pinned=True)


@pytest.mark.parametrize(
    "body, point, axis, value",
    [
        (_guide(), (0.25, L), 0, 0.06),  # the guide's coupler pushed sideways
        (_guide(), (0.5, L), 1, -0.004),  # pulled down along the beams (the axial stiffness)
        (_crank(), (1.0, 0.0), 1, 0.05),  # the crank's end lifted: it turns about its pin
    ],
)
def test_the_force_a_displacement_needs_gives_that_displacement_back(body, point, axis, value):
    q, pull = body.solve(displacement=Displacement(point, axis, value))
    assert (body.displacement(point, q)[axis]) == pytest.approx(value, abs=1e-12)
    assert abs(pull) > 1e-3
    force = np.zeros(2)
    force[axis] = pull
    q_back, _ = body.solve(forces=[(point, force)])
    assert np.allclose(q_back, q, atol=1e-9)


def test_a_rotation_and_a_displacement_at_once_are_refused():
    with pytest.raises(ValueError, match="one prescribed motion at a time"):
        _guide().solve(rotation=0.01, displacement=Displacement((0.0, L), 0, 0.01))


@pytest.mark.parametrize("boundary", ["parallel-guided mechanism", "circular-guided mechanism"])
def test_the_bcm_adapter_gives_the_force_a_mechanism_point_needs_as_the_elastica_does(boundary):
    """The force a prescribed displacement of 0.02 L needs, by the BCM adapter and by the exact elastica:
    the BCM is accurate to second order inside |u_y|, |theta| <= 0.1 [chen2021, §3], so at 0.02 L they agree
    to well under 1 % (a sign or an axis mixed up would not)."""
    data = coverage.minimal_case("prescribed displacement", boundary, "bcm")
    data["loads"][0]["values"] = [0.02]
    data["methods"] = {"bcm": {}, "elastica": {}}
    case = Case.model_validate(data)
    bcm, exact = run_method(case, "bcm"), run_method(case, "elastica")
    assert bcm.ok and exact.ok, (bcm.message, exact.message)
    for req, value in exact.values.items():
        assert abs(value) > 1e-3
        assert bcm.values[req] == pytest.approx(value, rel=0.01)
