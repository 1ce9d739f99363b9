"""The PRBM on a load along a segment without a ``model`` option: the adapter chooses the Chain Algorithm
and its number of elements for the target ``chain_tol`` x L (validation.methods.prbm_readings.chain_count).

Expected tips are independent of the chain:

* small loads, linear beam theory: a cantilever under a uniform load w per unit length deflects at its tip
  by w L^4 / (8 EI) (integrate EI v'' = w (L - x)^2 / 2 twice with v(0) = v'(0) = 0); the nonlinear
  correction at w L^3/EI = 0.1 is of order 1e-6 L, far below the targets checked;
* large loads, the elastica solved by collocation (scipy.integrate.solve_bvp), in units L = EI = 1:

      x' = cos(theta), y' = sin(theta), theta' = m, m' = Nx sin(theta) - Ny cos(theta), N' = -(0, w),

  with x(0) = y(0) = theta(0) = 0 at the clamp and m(1) = N(1) = 0 at the free end.

The segment is L = 2, E = 3, a unit square section (EI = 0.25), so a value off by a factor L or EI shows.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy.integrate import solve_bvp

from validation.case.loader import CaseError, load_case
from validation.methods import prbm as prbm_adapter
from validation.methods.base import NotApplicable, Request
from validation.case.method_options import options_of

LENGTH, EI = 2.0, 3.0 / 12.0
TARGET = 1e-3  # chain_tol's default, a fraction of L


def elastica_tip(load_parameters: list[float]) -> np.ndarray:
    """Tip (x, y) / L of the cantilever under a dead uniform load w L^3/EI along +y, per value, continued
    from the previous one."""

    def rhs(s, Y, w):
        x, y, th, m, nx, ny = Y
        return np.vstack([np.cos(th), np.sin(th), m, nx * np.sin(th) - ny * np.cos(th), 0.0 * s, -w + 0.0 * s])

    def bc(Ya, Yb):
        return np.array([Ya[0], Ya[1], Ya[2], Yb[3], Yb[4], Yb[5]])

    s = np.linspace(0.0, 1.0, 101)
    Y = np.zeros((6, s.size))
    Y[0] = s
    tips = []
    for target in load_parameters:
        for w in np.linspace(0.0, target, 6)[1:]:
            sol = solve_bvp(lambda s, Y: rhs(s, Y, w), bc, s, Y, tol=1e-8, max_nodes=100000)
            assert sol.success, sol.message
            s, Y = sol.x, sol.y
        tips.append(sol.y[:2, -1].copy())
    return np.array(tips)


def _case(tmp_path, loads: str, prbm_options: str = "", weight_density: float | None = None):
    density = "" if weight_density is None else f", weight_density = {weight_density!r}"
    text = f"""
[case]
id = "auto_chain"
title = "cantilever with a load along it"
group = "tests"
units = "dimensionless"

[segment]
boundary = "fixed-free"
length = {LENGTH}
E = 3.0
section = {{ kind = "rectangle", width = 1.0, thickness = 1.0{density} }}

{loads}

[[outputs]]
quantity = "x"
[[outputs]]
quantity = "y"

[methods.prbm]
{prbm_options}
"""
    path = tmp_path / "auto_chain.toml"
    path.write_text(text)
    return load_case(path).case


def _run(case):
    requests = [Request(q, "tip", lv) for lv in range(case.n_levels()) for q in ("x", "y")]
    run = prbm_adapter.run(case, requests, options_of("prbm", case.methods["prbm"]))
    tips = np.array(
        [[run.values[Request("x", "tip", lv)], run.values[Request("y", "tip", lv)]] for lv in range(case.n_levels())]
    )
    return tips, run


def _chain_count(run) -> int:
    """The element count the run's message states (and its model record repeats)."""
    found = re.search(r"Chain Algorithm \(seed 000 eqs 26-40\), (\d+) elements", run.message)
    assert found, run.message
    count = int(found.group(1))
    assert f"{count} elements" in run.extras["model"] and run.extras["model"].startswith("Chain Algorithm")
    return count


# w L^3/EI = 0.1 (linear theory) and 10 (the elastica; the tip turns about 70 degrees)
UNIFORM_PARAMETERS = [0.1, 10.0]
UNIFORM = f"""
[[loads]]
kind = "distributed"
direction = [0.0, 1.0]
values = {[p * EI / LENGTH**3 for p in UNIFORM_PARAMETERS]!r}
"""


def test_uniform_load_without_options_runs_the_chosen_chain(tmp_path):
    tips, run = _run(_case(tmp_path, UNIFORM))
    assert run.converged, run.message
    assert "chosen for the load along the segment" in run.message
    assert _chain_count(run) >= 20  # at least one doubling from 10
    linear = UNIFORM_PARAMETERS[0] * LENGTH / 8.0  # w L^4 / (8 EI) = (w L^3/EI) L / 8
    assert abs(tips[0, 1] - linear) < TARGET * LENGTH, (tips[0, 1], linear)
    exact = elastica_tip(UNIFORM_PARAMETERS)[1] * LENGTH
    assert np.hypot(*(tips[1] - exact)) < TARGET * LENGTH, (tips[1], exact)


def test_uniform_load_meets_a_tighter_target(tmp_path):
    """chain_tol = 1e-5: the small load's tip within 1e-5 L of linear theory (1e-3 of its deflection)."""
    small = UNIFORM.replace(
        f"values = {[p * EI / LENGTH**3 for p in UNIFORM_PARAMETERS]!r}", f"values = [{0.1 * EI / LENGTH**3!r}]"
    )
    assert small != UNIFORM
    tips, run = _run(_case(tmp_path, small, "chain_tol = 1e-5"))
    assert run.converged, run.message
    assert "target 1e-05" in run.message
    linear = 0.1 * LENGTH / 8.0
    assert abs(tips[0, 1] - linear) < 1e-5 * LENGTH, (tips[0, 1], linear)


# self-weight: density x unit area = w; gravity -y scaled by the level's value: w L^3/EI = 0.1 and 5
WEIGHT_DENSITY = 5.0 * EI / LENGTH**3
WEIGHT = """
[[loads]]
kind = "self_weight"
direction = [0.0, -1.0]
values = [0.02, 1.0]
"""


def test_self_weight_without_options_runs_the_chosen_chain(tmp_path):
    tips, run = _run(_case(tmp_path, WEIGHT, weight_density=WEIGHT_DENSITY))
    assert run.converged, run.message
    assert "chosen for the load along the segment" in run.message
    _chain_count(run)
    linear = -0.1 * LENGTH / 8.0
    assert abs(tips[0, 1] - linear) < TARGET * LENGTH, (tips[0, 1], linear)
    exact = elastica_tip([5.0])[0] * np.array([1.0, -1.0]) * LENGTH  # the mirror image of a load along +y
    assert np.hypot(*(tips[1] - exact)) < TARGET * LENGTH, (tips[1], exact)


def test_chain_elements_alone_fixes_the_count(tmp_path):
    """chain_elements without a model is read (the option-use check accepts it) and fixes the count."""
    tips, run = _run(_case(tmp_path, UNIFORM, "chain_elements = 20"))
    assert run.converged, run.message
    assert _chain_count(run) == 20 and "(chain_elements)" in run.message


@pytest.mark.parametrize("options", ['chain_tol = 1e-4\nmodel = "chain"', "chain_tol = 1e-4\nchain_elements = 20"])
def test_chain_tol_where_the_count_is_fixed_is_an_error(tmp_path, options):
    with pytest.raises(CaseError, match="chain_tol: the prbm does not use this option here"):
        _case(tmp_path, UNIFORM, options)


@pytest.mark.parametrize("model", ["theta-dependent", "lyon"])
def test_an_explicit_one_spring_model_still_refuses(tmp_path, model):
    case = _case(tmp_path, UNIFORM, f'model = "{model}"')
    with pytest.raises(NotApplicable, match=f"model = '{model}' takes end loads only"):
        _run(case)
