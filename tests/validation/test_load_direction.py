"""A load's ``direction`` is a unit vector and its value the magnitude (``LoadSpec``).

The case file may give any non-zero vector: it is normalised once, when the case is loaded, so
``direction = [1, 1]`` with value P is a force of magnitude P at 45 degrees, the same load as
``[0.7071..., 0.7071...]`` with P, in every method. Reference: the exact elastica of a straight
cantilever (L = EI = 1, inextensible) under a dead tip force P (cos 45, sin 45), solved by the
``elastica`` package directly (shooting, ``elastica.solve_elastica``).
"""

from __future__ import annotations

import json
import math
import tomllib

import pytest
from pydantic import ValidationError

import elastica
from validation.case.schema import Case, LoadSpec
from validation.cli.main import main
from validation.methods.base import RunStatus
from validation.run.exit_status import ExitStatus
from validation.run.runner import run_method

P = 1.0  # P L^2/EI: the tip turns by about 15 deg
UNIT = math.sqrt(0.5)

# Tip-position tolerance of each method against the exact elastica, in units of L: the FEM's
# discretisation error (16 elements, estimated 3e-5 L), the segment PRBM's fidelity error (1.4 % of L
# at most over chapter 2's fixed-pinned domain), the BCM's (a 4th-order expansion: 0.6 % of L here).
# A force of sqrt(2) P, the old reading of [1, 1], moves the tip by 0.05 L: beyond every tolerance.
TOLERANCE = {"elastica": 1e-8, "fem": 1e-4, "prbm": 0.015, "bcm": 0.01, "opensees": 1e-4}


def _case_text(direction: str, value: float = P) -> str:
    return f"""
[case]
id = "load_direction_probe"
title = "Straight cantilever, tip force along {direction}"
group = "tests"
units = "dimensionless"
description = "A dead tip force of value {value} along {direction}."

[segment]
boundary = "fixed-free"
length = 1.0
E = 1.0
section = {{ kind = "inertia", I = 1.0, A = 1.0e8 }}

[[loads]]
kind = "force"
direction = {direction}
values = [{value}]

[[outputs]]
quantity = "x"
[[outputs]]
quantity = "y"

[methods.fem]
elements = 16
[methods.elastica]
[methods.prbm]
[methods.bcm]
[methods.opensees]
"""


def _case(direction: str) -> Case:
    return Case.model_validate(tomllib.loads(_case_text(direction)))


def _tip(case: Case, method: str) -> tuple[float, float]:
    run = run_method(case, method)
    if run.status is RunStatus.NOT_APPLICABLE and "not available" in run.message:
        pytest.skip(f"{method}: {run.message}")
    assert run.status is RunStatus.OK, f"{method}: {run.message}"
    tip = {req.quantity: value for req, value in run.values.items()}
    return tip["x"], tip["y"]


@pytest.fixture(scope="module")
def exact_tip() -> tuple[float, float]:
    tip = elastica.solve_elastica(1.0, 1.0, force=(P * UNIT, P * UNIT))
    assert tip.converged
    return tip.x, tip.y


def test_a_direction_is_normalised_to_a_unit_vector_when_loaded():
    load = LoadSpec(kind="force", direction=(3.0, 4.0), values=[2.0])
    assert load.direction == pytest.approx((0.6, 0.8), abs=1e-15)
    assert load.levels() == [2.0]  # the value stays the magnitude


@pytest.mark.parametrize("method", sorted(TOLERANCE))
def test_every_method_reads_the_value_as_the_magnitude(method, exact_tip):
    """[1, 1] and [0.7071..., 0.7071...] with value P: one load, one tip, that of the exact elastica."""
    tip_11 = _tip(_case("[1.0, 1.0]"), method)
    tip_unit = _tip(_case(f"[{UNIT!r}, {UNIT!r}]"), method)
    assert tip_11 == pytest.approx(tip_unit, abs=1e-9)
    assert tip_11 == pytest.approx(exact_tip, abs=TOLERANCE[method])


def test_solve_json_states_the_magnitude_and_the_unit_direction(tmp_path, capsys):
    path = tmp_path / "case.toml"
    path.write_text(_case_text("[1.0, 1.0]", value=2.5), encoding="utf-8")
    assert main(["solve", str(path), "--method", "elastica", "--json"]) == ExitStatus.OK
    document = json.loads(capsys.readouterr().out)
    (load,) = document["levels"][0]["loads"]
    assert load["value"] == 2.5
    assert load["direction"] == pytest.approx([UNIT, UNIT], abs=1e-15)


def test_a_zero_direction_is_refused_naming_the_field(tmp_path, capsys):
    with pytest.raises(ValidationError) as caught:
        _case("[0.0, 0.0]")
    assert [error["loc"] for error in caught.value.errors()] == [("loads", 0, "direction")]
    path = tmp_path / "case.toml"
    path.write_text(_case_text("[0.0, 0.0]"), encoding="utf-8")
    assert main(["solve", str(path)]) == ExitStatus.BAD_INPUT
    assert "loads.0.direction: must not be the zero vector" in capsys.readouterr().err
