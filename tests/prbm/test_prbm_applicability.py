"""Model applicability (issue 14 item 3): the PRBM says, level by level and as a structured flag
(``MethodRun.applicability``, the ``applicability`` column of the results table), when its model was not
made for the load. Expected levels are derived here, not read from our output:

* PRB angle past the fits' printed range (seed 000 eqs (51)-(52): 0 < Theta <= 65 deg): a transverse tip
  force on a straight cantilever (n = 0, phi = 90 deg) gives K_Theta Theta = alpha^2 cos Theta (eq 47),
  so Theta = 65 deg at alpha^2 = K_Theta(0) (65 deg in rad) / cos 65 deg = 7.110 with K_Theta(0) =
  2.648834 (eq 43): 7.0 is inside, 7.2 outside.
* Load ratio outside the fit (Pauly-Midha: -4 < n <= 10): n = 12 is outside; it is refused with
  ``extrapolate = 'raise'`` (the default) and flagged with 'allow'.
* Inflection (Table 2.1, eq (12)): a transverse force P and an end moment M of the opposite sense
  with |M| < P L make the bending moment change sign along the beam (tip M, root M + P a > 0); the
  same sense cannot (Table 2.1).
"""

import math
import tomllib

import pytest

from validation.case.loader import LoadedCase
from validation.case.schema import Case
from validation.methods.base import Applicability, Request
from validation.run.outcome import tabulate
from validation.run.case_run import run_case
from validation.run.runner import run_method

CANTILEVER = """
[case]
id = "applicability"
title = "a straight cantilever, tip loads"
group = "test"
units = "dimensionless"
description = "applicability flags"
[segment]
boundary = "fixed-free"
length = 1.0
E = 1.0
section = { kind = "inertia", I = 1.0, A = 1.0e10 }
[[loads]]
kind = "force"
point = "tip"
direction = DIRECTION
values = FORCES
MOMENT
[[outputs]]
quantity = "y"
point = "tip"
[methods.prbm]
OPTIONS
"""


def _case(forces, direction=(0.0, 1.0), moments=None, options="") -> Case:
    moment = "" if moments is None else f'[[loads]]\nkind = "moment"\npoint = "tip"\nvalues = {list(moments)}'
    text = (
        CANTILEVER.replace("DIRECTION", str(list(direction)))
        .replace("FORCES", str(list(forces)))
        .replace("MOMENT", moment)
        .replace("OPTIONS", options)
    )
    return Case.model_validate(tomllib.loads(text))


def test_theta_past_65_degrees_is_flagged_from_eq_47():
    alpha2 = 2.648834 * math.radians(65.0) / math.cos(math.radians(65.0))
    assert 7.0 < alpha2 < 7.2
    run = run_method(_case([1.0, 7.0, 7.2, 10.0]), "prbm")
    assert run.ok, run.message
    assert [run.applicability.get(level, []) for level in range(4)] == [
        [],
        [],
        [Applicability.DEFLECTION],
        [Applicability.DEFLECTION],
    ]


def test_load_ratio_outside_the_fit_is_refused_or_flagged():
    direction = (-12.0 / math.hypot(12.0, 1.0), 1.0 / math.hypot(12.0, 1.0))  # n = -F_x/F_y = 12
    refused = run_method(_case([0.01, 0.02], direction), "prbm")
    assert refused.status.value == "not applicable" and "fit range" in refused.message
    allowed = run_method(_case([0.01, 0.02], direction, options='extrapolate = "allow"'), "prbm")
    assert allowed.ok, allowed.message
    assert all(Applicability.LOAD_RATIO in allowed.applicability.get(level, []) for level in (0, 1))


@pytest.mark.parametrize("sign, inflected", [(-1.0, True), (1.0, False)])
def test_force_and_opposing_moment_flag_an_inflection(sign, inflected):
    run = run_method(_case([1.0], moments=[sign * 0.3]), "prbm")
    assert run.ok, run.message
    assert (Applicability.INFLECTION in run.applicability.get(0, [])) == inflected


def test_the_results_table_carries_the_flag():
    case = _case([1.0, 7.2])
    loaded = LoadedCase(path=None, case=case, text="")
    table = tabulate(run_case(loaded, ["prbm"], use_cache=False))
    flags = dict(zip(table["level"], table["applicability"]))
    assert flags[0] == "" and flags[1] == Applicability.DEFLECTION.value
    assert run_case(loaded, ["prbm"], use_cache=False).runs["prbm"].values[Request("y", "tip", 1)] > 0
