"""Cells of the coverage matrix that failed instead of answering or refusing: a method that cannot
answer says why, before it tries.

- The PRBM of the parallel-guided mechanism is a parallelogram: its coupler cannot rotate, so a
  prescribed rotation of it is refused from the network's kinematics (the prescription's row adds no
  rank to the joints' Jacobian at the unloaded pose), not after Newton's step halvings.
- A pinned-pinned segment whose tip is free across the chord (a follower force or a force toward a
  point frees both tip components) swings about its root pin: the case's mobility check rejects it
  before any method runs, as it does a mechanism that can move as a rigid body.
"""

import pytest

import prbm
from prbm.network import UnreachableMotion
from validation.case.loader import check_case
from validation.case.schema import Case
from validation.run import coverage
from validation.run.runner import run_method


# --- the parallelogram's coupler -------------------------------------------------------------------
def parallelogram(scale: float) -> prbm.Network:
    """Two cranks of length ``scale`` pinned to the ground at (0, 0) and (scale/2, 0), and to a coupler
    at (0, scale) and (scale/2, scale); springs at the four pins."""
    h, w = scale, scale / 2
    pins = [
        prbm.Pin("left", prbm.GROUND, (0.0, 0.0)),
        prbm.Pin("left", "coupler", (0.0, h)),
        prbm.Pin("right", prbm.GROUND, (w, 0.0)),
        prbm.Pin("right", "coupler", (w, h)),
    ]
    springs = [prbm.TorsionSpring("left", prbm.GROUND, 1.0), prbm.TorsionSpring("right", "coupler", 1.0)]
    return prbm.Network(
        ["left", "right", "coupler"], {"M": ("coupler", (w / 2, h)), "B": ("left", (0.0, h))}, pins, springs=springs
    )


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_a_parallelograms_coupler_cannot_be_turned_at_any_scale(scale):
    net = parallelogram(scale)
    with pytest.raises(UnreachableMotion, match="translates body 'coupler' without turning it") as info:
        prbm.solve(net, [prbm.PrescribedRotation("coupler", (0.1,))], 1)
    assert info.value.by_joints and info.value.moves
    assert isinstance(info.value, prbm.LockedNetwork)  # callers that refuse a locked network refuse this too


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_a_parallelograms_coupler_translates_and_its_crank_turns(scale):
    net = parallelogram(scale)
    moved = prbm.solve(net, [prbm.PrescribedDisplacement("M", "x", (0.1 * scale,))], 1)
    turned = prbm.solve(net, [prbm.PrescribedRotation("left", (0.1,))], 1)
    assert moved.converged and turned.converged
    assert moved.rotation("coupler", 0) == pytest.approx(0.0, abs=1e-12)


def test_a_point_the_joints_hold_along_an_axis_cannot_be_displaced_along_it():
    """Point B (the left crank's top) moves only along x at the unloaded pose: a y-displacement is refused."""
    with pytest.raises(UnreachableMotion, match="'B'.*along y") as info:
        prbm.solve(parallelogram(1.0), [prbm.PrescribedDisplacement("B", "y", (0.01,))], 1)
    assert info.value.moves


def test_the_prbm_refuses_to_turn_the_parallel_guided_coupler():
    """Was: 'fails: Newton did not converge after 12 step halvings (load parameter -1 of 0)'."""
    found = coverage.cell("prescribed rotation", "parallel-guided mechanism", "prbm")
    assert found.status == "refuses", found
    assert found.reason == "the PRB model's coupler cannot rotate: its joints keep its angle"
    case = Case.model_validate(coverage.minimal_case("prescribed rotation", "parallel-guided mechanism", "prbm"))
    run = run_method(case, "prbm")
    assert "prescribe a translation" in run.message and "Newton" not in run.message


def test_the_prbm_still_turns_the_circular_guided_crank():
    assert coverage.cell("prescribed rotation", "circular-guided mechanism", "prbm").status == "answers"


# --- the pinned-pinned segment that swings -------------------------------------------------------
@pytest.mark.parametrize("load", ["follower force", "force toward a point"])
@pytest.mark.parametrize("method", coverage.METHODS)
def test_a_pinned_pinned_segment_free_across_its_chord_is_rejected_for_every_method(load, method):
    """Was, for the FEM: 'fails: the model can move without deforming (a rigid-body motion ...)'."""
    found = coverage.cell(load, "pinned-pinned", method)
    assert found.status == "invalid case", found
    assert "swings about its root pin" in found.reason


def segment_case(load: dict, length: float = 1.0, curvature: float = 0.0) -> Case:
    data = coverage.minimal_case("force", "pinned-pinned", "fem")
    data["segment"].update(length=length, curvature=curvature)
    data["loads"] = [dict(load, values=[1.0 / length**2])]  # P L^2/EI = 1 at every length
    return Case.model_validate(data)


@pytest.mark.parametrize("length", [1e-3, 1.0, 1e3])
def test_the_swing_is_found_at_any_scale(length):
    follower = dict(kind="force", point="tip", direction=[1.0, 0.0], values=[1.0], follower=True)
    problems = check_case(segment_case(follower, length))
    assert len(problems) == 1
    field, problem = problems[0]
    assert field == "segment"
    assert problem.startswith(
        "a pinned-pinned segment swings about its root pin, its tip free across the chord: "
        "hold the tip or load it along the chord; loads.0 (a follower force)"
    )
    across = dict(kind="force", point="tip", direction=[0.0, 1.0], values=[1.0])
    assert check_case(segment_case(across, length))  # a dead force across the chord frees uy
    along = dict(kind="force", point="tip", direction=[1.0, 0.0], values=[1.0])
    assert check_case(segment_case(along, length)) == []  # along the chord: uy held, no swing


def test_a_curved_pinned_pinned_segment_held_along_x_does_not_swing():
    """Its chord leans: the boundary's hold on the tip's y and a force along x keep it from turning."""
    along_x = dict(kind="force", point="tip", direction=[1.0, 0.0], values=[1.0])
    assert check_case(segment_case(along_x, curvature=1.0)) == []
    toward = dict(kind="force", point="tip", toward=[2.0, 0.0], values=[1.0])
    assert check_case(segment_case(toward, curvature=1.0))  # both tip components free: it swings


def test_the_other_boundaries_are_held_whatever_the_tip_load():
    for boundary in ("fixed-free", "fixed-pinned", "fixed-guided", "fixed-fixed", "curved fixed-free"):
        for load in ("follower force", "force toward a point"):
            case = Case.model_validate(coverage.minimal_case(load, boundary, "fem"))
            assert check_case(case) == [], (boundary, load)
