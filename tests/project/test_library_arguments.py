"""Every library refuses what it should (NaN, infinite, zero or negative stiffness or length) with a
ValueError naming the argument; a zero load gives the undeformed state and a negative load the
mirror image (about the undeformed axis) of the positive one: both follow from the equations'
symmetry y -> -y, not from a stored answer."""

from __future__ import annotations

import math

import numpy as np
import pytest

import bcm
import elastica
import fem
import prbm

REFUSALS = {
    "prbm NaN load": (lambda: prbm.fixed_pinned_tip(math.nan, length=1.0, EI=1.0), "P"),
    "prbm negative EI": (lambda: prbm.fixed_pinned_tip(5.0, length=1.0, EI=-1.0), "EI"),
    "prbm zero length": (lambda: prbm.fixed_guided_tip(1.0, length=0.0, EI=1.0), "length"),
    "prbm infinite EI": (lambda: prbm.pure_moment_tip(1.0, length=1.0, EI=math.inf), "EI"),
    # load levels as a list of numbers (argcheck's plain-Python path) and as a nested list (numpy's)
    "prbm NaN level in a list": (lambda: prbm.fixed_pinned_tip([1.0, math.nan, 2.0], length=1.0, EI=1.0), "P"),
    "prbm infinite ratio in a list": (
        lambda: prbm.fixed_pinned_tip([1.0, 2.0], [0.0, -math.inf], length=1.0, EI=1.0),
        "n",
    ),
    "prbm NaN in a nested list": (lambda: prbm.fixed_pinned_tip([[1.0], [math.nan]], length=1.0, EI=1.0), "P"),
    "prbm zero length in a list": (lambda: prbm.fixed_pinned_tip(1.0, length=[1.0, 0.0], EI=1.0), "length"),
    "elastica negative EI": (lambda: elastica.solve_elastica(0.1, -1.0, force=(0.0, 5.0)), "EI"),
    "elastica NaN force": (lambda: elastica.solve_elastica(1.0, 1.0, force=(0.0, math.nan)), "force"),
    "elastica NaN load": (lambda: elastica.cantilever_tip_load(math.nan), "load"),
    "fem negative EI": (lambda: fem.Section.from_EI(1e6, -1.0), "EI"),
    "fem zero EA": (lambda: fem.Section.from_EI(0.0, 1.0), "EA"),
    "fem NaN node": (lambda: fem.Model().add_node("a", math.nan, 0.0), "x"),
    "bcm negative ka": (lambda: bcm.deflections_from_loads(0.0, 1.0, 0.0, -5.0), "ka"),
    "bcm NaN force": (lambda: bcm.deflections_from_loads(0.0, math.nan, 0.0, 1e4), "fy"),
}


@pytest.mark.parametrize("name", sorted(REFUSALS))
def test_bad_arguments_are_refused_naming_the_argument(name):
    call, argument = REFUSALS[name]
    with pytest.raises(ValueError, match=rf"\b{argument} must be finite"):
        call()


def test_fem_refuses_a_zero_length_member():
    model = fem.Model()
    model.add_node("a", 0.0, 0.0)
    model.add_node("b", 0.0, 0.0)
    with pytest.raises(ValueError, match="zero length"):
        model.add_member("a", "b", fem.Section.from_EI(1e6, 1.0))


def fem_cantilever_tip(P: float) -> tuple[float, float, float]:
    model = fem.Model()
    model.add_node("root", 0.0, 0.0)
    model.add_node("tip", 1.0, 0.0)
    model.add_member("root", "tip", fem.Section.from_EI(1e7, 1.0), n_elements=4)
    model.add_support("root", "fixed")
    model.add_force("tip", 0.0, [P])
    result = fem.solve(model)
    assert result.converged
    x, y = result.positions[-1, result.node_names.index("tip")]
    return float(x), float(y), float(result.rotations[-1, result.node_names.index("tip")])


def tips(P: float) -> dict[str, tuple[float, float, float]]:
    """(x, y, rotation) of a unit cantilever's tip under a transverse load P L^2/EI, every library."""
    p = prbm.fixed_pinned_tip(P, length=1.0, EI=1.0).outputs
    e = elastica.cantilever_tip_load(P)
    s = elastica.solve_elastica(1.0, 1.0, force=(0.0, P))
    ux, uy, th = bcm.deflections_from_loads(0.0, P, 0.0, 1e7)
    return {
        "prbm": (float(p["a"]), float(p["b"]), float(p["theta0"])),
        "elliptic": (e.a, e.b, e.theta0),
        "shooting": (s.x, s.y, s.theta),
        "fem": fem_cantilever_tip(P),
        "bcm": (1.0 + ux, uy, th),
    }


def test_zero_load_is_the_undeformed_state_in_every_library():
    for name, tip in tips(0.0).items():
        assert tip == pytest.approx((1.0, 0.0, 0.0), abs=1e-12), name


def test_negative_load_is_the_mirror_in_every_library():
    up, down = tips(0.5), tips(-0.5)
    for name in up:
        x, y, theta = up[name]
        assert y > 0.05 and theta > 0.05, name  # the positive load really bends it
        assert down[name] == pytest.approx((x, -y, -theta), rel=1e-9, abs=1e-12), name
    # and the upward tip itself is right (a mirror alone passes with a 10 % error on both sides):
    exact = up["elliptic"]  # closed form (elliptic integrals, Bisshopp-Drucker)
    assert up["shooting"] == pytest.approx(exact, abs=1e-9)  # the exact elastica by shooting
    assert up["fem"] == pytest.approx(exact, abs=1e-3)  # 4 elements: discretisation error ~2e-4
    # BCM with f_x = 0: eq (3) of seed 003 is linear, u_y = f_y/3, theta = f_y/2 (linear beam theory)
    assert up["bcm"][1:] == pytest.approx((0.5 / 3, 0.5 / 2), rel=1e-9)
    # PRBM: known small-deflection error 3 gamma/K_Theta - 1 = -3.8 % of b (derived, eqs 41-49)
    assert up["prbm"][1] == pytest.approx(exact[1], rel=0.05)


@pytest.mark.parametrize("module", ["prbm", "elastica", "fem", "bcm", "argcheck"])
def test_package_docstring_examples_run(module):
    import doctest
    import importlib

    result = doctest.testmod(importlib.import_module(module))
    assert result.attempted >= 3 and result.failed == 0


def test_argcheck_is_a_leaf():
    """The shared checks import nothing of the project, so the libraries stay independent."""
    from tests.project.test_independence import ROOT, imported_top_levels

    assert not imported_top_levels(ROOT / "argcheck" / "__init__.py") & {
        "prbm",
        "fem",
        "elastica",
        "bcm",
        "validation",
        "synthesis",
    }


def test_one_result_protocol_across_the_libraries():
    """Like scipy's TestOptimizeResultAttributes: every solve result answers the same questions."""
    model = fem.Model()
    model.add_node("root", 0.0, 0.0)
    model.add_node("tip", 1.0, 0.0)
    model.add_member("root", "tip", fem.Section.from_EI(1e7, 1.0), n_elements=4)
    model.add_support("root", "fixed")
    model.add_force("tip", 0.0, [1.0])
    results = {
        "prbm": prbm.fixed_pinned_tip(1.0, length=1.0, EI=1.0),
        "elastica": elastica.solve_elastica(1.0, 1.0, force=(0.0, 1.0)),
        "fem": fem.solve(model),
        "elastica elliptic": elastica.cantilever_tip_load(1.0),
        "elastica elliptic (several roots)": elastica.fixed_guided_inflection_tips(5.0, 0.0, 2.0)[0],
        "bcm closed form": bcm.slant_parallelogram(1.0, method="CE3"),
        "bcm root find": bcm.slant_parallelogram(1.0, method="castigliano"),
    }
    for name, result in results.items():
        assert result.converged is True and result.status == "ok", name
        assert isinstance(result.message, str) and result.message, name
        assert isinstance(result.iterations, (int, np.integer)) and result.iterations >= 0, name
        assert result.wall_time > 0.0, name


def test_elastica_reaction_is_the_clamp_on_the_beam_at_the_root():
    """Static equilibrium of the whole beam: R + F = 0 and M_root + M_tip + (x, y) x F = 0."""
    r = elastica.solve_elastica(1.0, 1.0, force=(0.3, 1.0), moment=0.2)
    Rx, Ry, M_root = r.reaction
    assert (Rx, Ry) == pytest.approx((-0.3, -1.0), abs=1e-12)
    assert M_root + r.moment + (r.x * 1.0 - r.y * 0.3) == pytest.approx(0.0, abs=1e-9)


def test_complex_loads_are_checked_as_numbers():
    with pytest.raises(ValueError, match="F must be finite"):
        prbm.slfp_end_tip(complex(math.nan, 1.0), 0.0, flexure_length=0.25, EI=1.0)
    assert prbm.slfp_end_tip(complex(0.0, 0.0), 0.0, flexure_length=0.25, EI=1.0).converged
