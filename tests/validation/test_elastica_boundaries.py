"""The elastica on the segment boundaries its clamped-beam shooting cannot state, against the FEM.

A pinned-pinned segment and a straight fixed-fixed segment whose tip's axial motion is held are solved
as a mechanism (``validation.methods.elastica_network.run_segment``, ``elastica.mechanism``): the beam
extensible with the section's EA, as in the FEM, the tip's held freedoms those of
``quantities.boundary_held_tip``. Each answer is checked against the FEM on the same case: the two
agree within the FEM's own error estimate (|u_2n - u_n|/3, the leading error of u_2n) plus a stated
tolerance of 1e-4 of the value (the Richardson estimate's higher-order terms; the elastica is
exact to its shooting tolerance, ~1e-9) and 1e-8 absolute (values the FEM gets exactly, with an
estimate of zero). Where the elastica still refuses, the reason says why.

Independent of both: at a pin carrying no moment the resultant tip force passes through the root pin,
so r_tip x F_tip = -M_tip about the root (a chord force on the arc; F_y = -M/L for a moment on the
straight pinned-pinned beam).
"""

from __future__ import annotations

import math

import pytest

from validation.case.schema import Case
from validation.methods.base import RunStatus
from validation.run import coverage
from validation.run.runner import run_method

REL, ABS = 1e-4, 1e-8  # the stated tolerance beyond the FEM's error estimate


def segment_case(
    boundary: str,
    loads: list[dict],
    outputs: list[tuple[str, str]],
    *,
    curvature: float = 0.0,
    area: float | None = 1e4,
) -> Case:
    """A unit segment (L = 1, EI = 1, EA = ``area`` EI/L^2; no A: inextensible), the FEM on 16 elements."""
    section = {"kind": "inertia", "I": 1.0, **({"A": area} if area is not None else {})}
    return Case.model_validate(
        {
            "case": {
                "id": "elastica_boundaries",
                "title": f"{boundary} segment",
                "group": "tests",
                "units": "dimensionless",
            },
            "segment": {"boundary": boundary, "length": 1.0, "E": 1.0, "curvature": curvature, "section": section},
            "loads": loads,
            "outputs": [{"quantity": q, "point": p} for q, p in outputs],
            "methods": {"fem": {"elements": 16}, "elastica": {}},
        }
    )


def agree_with_fem(case: Case) -> dict:
    """Run both; assert every output agrees within the FEM's estimate plus the stated tolerance; return
    the elastica's values."""
    elastica, fem = run_method(case, "elastica"), run_method(case, "fem")
    assert elastica.status is RunStatus.OK, elastica.message
    assert fem.status is RunStatus.OK, fem.message
    assert "mechanism" in elastica.extras["model"]
    for req, reference in fem.values.items():
        bound = fem.error_estimate[req] + REL * abs(reference) + ABS
        assert abs(elastica.values[req] - reference) <= bound, (req, elastica.values[req], reference, bound)
    return elastica.values


def at(values: dict, quantity: str, point: str) -> list[float]:
    """The values of one output, level by level."""
    found = sorted((req.level, v) for req, v in values.items() if (req.quantity, req.point) == (quantity, point))
    return [v for _, v in found]


def test_a_pinned_pinned_arc_under_a_chord_force_agrees_with_the_fem():
    """An arc of kappa L = 1, pinned at the root, its tip pulled and pushed along x and held in y: the root
    pin and the moment-free tip make the resultant a chord force (the roller adds the F_y that turns it)."""
    case = segment_case(
        "pinned-pinned",
        [dict(kind="force", point="tip", direction=[1.0, 0.0], values=[-1.0, 0.5, 1.0, 2.0, 5.0])],
        [
            ("x", "tip"),
            ("y", "tip"),
            ("dx", "tip"),
            ("rotation", "tip"),
            ("force_y", "tip"),
            ("rotation", "root"),
            ("reaction_x", "root"),
            ("reaction_y", "root"),
        ],
        curvature=1.0,
    )
    values = agree_with_fem(case)
    x, y, fy = at(values, "x", "tip"), at(values, "y", "tip"), at(values, "force_y", "tip")
    for xi, yi, fyi, fx in zip(x, y, fy, [-1.0, 0.5, 1.0, 2.0, 5.0]):
        assert fyi == pytest.approx(fx * yi / xi, rel=1e-8)  # along the chord: through the root pin
    assert at(values, "dx", "tip")[0] < 0 < at(values, "dx", "tip")[-1]  # pushed shorter, pulled longer
    assert all(abs(r) > 1.0 for r in at(values, "rotation", "root"))  # the root pin turns (degrees)


def test_a_pinned_pinned_beam_under_an_end_moment_agrees_with_the_fem():
    """A straight beam pinned at both ends (tip x and y held), a moment at the tip: it bends, the root
    turns back, and the held tip pulls it taut."""
    case = segment_case(
        "pinned-pinned",
        [dict(kind="moment", point="tip", values=[0.5, 1.0])],
        [
            ("rotation", "tip"),
            ("rotation", "root"),
            ("force_x", "tip"),
            ("force_y", "tip"),
            ("reaction_moment", "root"),
        ],
    )
    values = agree_with_fem(case)
    assert at(values, "force_y", "tip") == pytest.approx([-0.5, -1.0], rel=1e-8)  # F_y = -M/L
    assert at(values, "reaction_moment", "root") == pytest.approx([0.0, 0.0], abs=1e-9)
    assert all(r < 0 < t for r, t in zip(at(values, "rotation", "root"), at(values, "rotation", "tip")))


def test_a_straight_fixed_fixed_beam_carries_a_transverse_force_by_stretching():
    """Clamped at both ends, the tip's x and angle held, a force across it: the membrane tension the held
    tip needs (force_x) grows faster than the load."""
    case = segment_case(
        "fixed-fixed",
        [dict(kind="force", point="tip", direction=[0.0, 1.0], values=[1.0, 5.0])],
        [("y", "tip"), ("force_x", "tip"), ("moment", "tip"), ("reaction_moment", "root")],
    )
    values = agree_with_fem(case)
    tension = at(values, "force_x", "tip")
    assert tension[0] > 1.0 and tension[1] > 3.0 * tension[0]


def test_the_inextensible_straight_fixed_fixed_refusal_says_why():
    """Without a section area the beam is inextensible: its tip held at x = L, it cannot bend at all."""
    case = segment_case(
        "fixed-fixed", [dict(kind="moment", point="tip", values=[1.0])], [("rotation", "tip")], area=None
    )
    run = run_method(case, "elastica")
    assert run.status is RunStatus.NOT_APPLICABLE
    assert "inextensible" in run.message and "cannot bend" in run.message and "chord shortens" in run.message


@pytest.mark.parametrize("w", [1.0, -3.0])
def test_a_load_along_a_pinned_pinned_bar_splits_between_its_ends(w):
    """A uniform axial load w along a straight pinned-pinned segment (both ends held in x): a bar fixed at
    both ends, so it stays straight, each end takes w L / 2, and the strain energy is w^2 L^3 / (24 EA)
    (N(s) = w (L/2 - s); derived here)."""
    EA = 1e4
    case = segment_case(
        "pinned-pinned",
        [dict(kind="distributed", point="tip", direction=[1.0, 0.0], values=[w])],
        [("reaction_x", "root"), ("reaction_y", "root"), ("strain_energy", "tip")],
        area=EA,
    )
    run = run_method(case, "elastica")
    assert run.status is RunStatus.OK, run.message
    values = {req.quantity: v for req, v in run.values.items()}
    assert values["reaction_x"] == pytest.approx(-w / 2, abs=1e-9)
    assert values["reaction_y"] == pytest.approx(0.0, abs=1e-9)
    assert values["strain_energy"] == pytest.approx(w * w / (24 * EA), rel=1e-6)


def test_a_follower_load_along_a_segment_solved_as_a_mechanism_is_refused_with_the_reason():
    case = segment_case(
        "pinned-pinned",
        [dict(kind="distributed", point="tip", direction=[0.0, 1.0], values=[1.0], follower=True)],
        [("x", "tip")],
    )
    run = run_method(case, "elastica")
    assert run.status is RunStatus.NOT_APPLICABLE and "follower distributed load" in run.message, run.message


@pytest.mark.parametrize("load", ["force", "moment", "prescribed displacement", "prescribed rotation"])
@pytest.mark.parametrize("boundary", ["pinned-pinned", "fixed-fixed"])
def test_the_coverage_matrix_cells_answer(load, boundary):
    assert coverage.cell(load, boundary, "elastica").status == "answers"


def test_the_mechanism_route_keeps_every_segment_output():
    """Tip x, y, dx, dy, rotation, forces, root reactions and rotation, strain energy: all answered."""
    outputs = [(q, "tip") for q in ("x", "y", "dx", "dy", "rotation", "force_x", "force_y", "moment")]
    outputs += [(q, "root") for q in ("rotation", "reaction_x", "reaction_y", "reaction_moment")]
    outputs += [("strain_energy", "tip")]
    case = segment_case("pinned-pinned", [dict(kind="moment", point="tip", values=[1.0])], outputs)
    run = run_method(case, "elastica")
    assert run.status is RunStatus.OK, run.message
    assert all(math.isfinite(v) for v in run.values.values()) and len(run.values) == len(outputs)
