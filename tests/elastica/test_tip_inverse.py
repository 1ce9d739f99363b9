"""The inverse tip problem (prescribed tip y and slope, x fixed by a, n, an axial load or l1) in
the FEM (``fem.solve_tip_inverse`` through the FEM adapter) and the exact elastica.

Configurations no case file contains: an initially curved dimensionless segment (kappa0 L = 0.4)
under two chosen sets of tip loads (one with an axial compression, one with tension), nearly
inextensible (EA L^2/EI = 1e9: near the taut state a prescribed x is stiff, dF_x/dx ~ 1e4 EI/L^3,
so an axial strain of 1e-6 would already move F_x by 1 %). A forward
elastica solve under them gives the tip (x, y, slope) and the arc length where the bending moment
vanishes; posing each of the four inverse problems on that tip (a = x; n = -F_x/F_y; the axial load
F_x; l1) must give the chosen loads back:
* the elastica's inverse, to 1e-7;
* the FEM's (Richardson-extrapolated from 16 and 32 elements; one level per tie), to 1e-3 of the load scale (a 10 %
  error or a flipped tie sign moves them by more than 1e-2).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pydantic import ValidationError
from scipy.optimize import brentq

from elastica.shooting import ElasticaProblem, section_moment, solve_path
from validation.methods import elastica as elastica_adapter
from validation.methods import fem as fem_adapter
from validation.methods.base import Request
from validation.case.loader import describe_all
from validation.case.schema import Case
from validation.case.method_options import options_of

KAPPA = 0.4
LOADS = ("force_x", "force_y", "moment")
# The tip loads (F_x, F_y, M CCW) of the two levels; the prescribed tips are where a forward
# elastica solve under them puts the tip, so the inverse problems must return these loads.
CHOSEN = np.array([[-0.5, 2.0, -0.6], [1.0, 3.0, -1.2]])


def _forward(loads):
    fx, fy, m = loads
    return solve_path(ElasticaProblem(length=1.0, EI=1.0, curvature=KAPPA, force=(fx, fy), moment=m))


def _ties() -> dict:
    states = [_forward(loads) for loads in CHOSEN]
    common = {"b": [st.y for st in states], "theta0_deg": [math.degrees(st.theta) for st in states]}
    zero_moment = [brentq(lambda s, st=st: section_moment(st, s), 0.05, 0.95) for st in states]
    return {
        "a": common | {"a": [st.x for st in states]},
        "n": common | {"n": list(-CHOSEN[:, 0] / CHOSEN[:, 1])},
        "axial_load": common | {"axial_load": list(CHOSEN[:, 0])},
        "l1": common | {"l1": zero_moment},
    }


TIES = _ties()
LEVEL = {"a": 1, "n": 0, "axial_load": 1, "l1": 0}  # one level each (cost); both loadings covered


def _case(inverse: dict, fem_options: dict | None = None) -> Case:
    return Case.model_validate(
        {
            "case": {"id": "inverse_probe", "title": "t", "group": "g", "units": "dimensionless"},
            "segment": {
                "boundary": "fixed-guided",
                "length": 1.0,
                "E": 1.0,
                "curvature": KAPPA,
                "section": {"kind": "inertia", "I": 1.0, "A": 1.0e9},
            },
            "loads": [{"kind": "force", "direction": [1.0, 0.0], "values": [0.0, 0.0]}],
            "outputs": [{"quantity": q} for q in LOADS],
            "methods": {
                "fem": {"elements": 16, "richardson": True, "inverse": inverse, **(fem_options or {})},
                "elastica": {"inverse": inverse},
            },
        }
    )


def _loads(run, level):
    return np.array([run.values[Request(q, "tip", level)] for q in LOADS])


@pytest.fixture(scope="module", params=list(TIES))
def solved(request):
    case = _case(TIES[request.param])
    requests = [Request(q, "tip", lv) for lv in range(2) for q in LOADS]
    exact = elastica_adapter.run(case, requests, options_of("elastica", case.methods["elastica"]))
    fem = fem_adapter.run(
        case, [r for r in requests if r.level == LEVEL[request.param]], options_of("fem", case.methods["fem"])
    )
    assert exact.converged, exact.message
    assert fem.converged, fem.message
    return request.param, case, exact, fem


def test_exact_loads_are_the_chosen_loads(solved):
    tie, _, exact, _ = solved
    for level in range(2):
        assert _loads(exact, level) == pytest.approx(CHOSEN[level], abs=1e-7), tie


def test_fem_loads_agree_with_the_exact_loads(solved):
    tie, _, exact, fem = solved
    for level in (LEVEL[tie],):
        want, got = CHOSEN[level], _loads(fem, level)
        scale = np.abs(want[:2]).max() + abs(want[2])
        assert np.abs(got - want).max() <= 1e-3 * scale, (tie, level, got, want)


def test_fem_keeps_the_tie_and_reports_an_error_estimate(solved):
    tie, _, _, fem = solved
    for level in (LEVEL[tie],):
        fx, fy, _ = _loads(fem, level)
        if tie == "n":
            assert fx == pytest.approx(-TIES["n"]["n"][level] * fy, rel=1e-6)  # F_x = -n P
        if tie == "axial_load":
            assert fx == pytest.approx(TIES["axial_load"]["axial_load"][level], abs=1e-12)
        estimate = [fem.error_estimate[Request(q, "tip", level)] for q in LOADS]
        assert all(np.isfinite(estimate))


def test_forward_outputs_stay_forward():
    """Outputs other than the tip loads come from the forward solve under the case's loads."""
    case = _case(TIES["n"])
    requests = [Request("y", "tip", 1)]
    run = elastica_adapter.run(case, requests, options_of("elastica", case.methods["elastica"]))
    assert run.values[requests[0]] == pytest.approx((1 - math.cos(KAPPA)) / KAPPA, rel=1e-9)  # unloaded arc


@pytest.mark.parametrize(
    "inverse, needle",
    [
        ({"b": [0.1, 0.1], "theta0_deg": [1.0, 1.0]}, "exactly one of"),
        ({"b": [0.1, 0.1], "theta0_deg": [1.0, 1.0], "n": [0.0, 0.0], "a": [0.9, 0.9]}, "exactly one of"),
        ({"b": [0.1], "theta0_deg": [1.0, 1.0], "n": [0.0, 0.0]}, "inverse.b: 1 values for 2"),
        ({"b": [0.1, 0.1], "theta0_deg": [1.0, 1.0], "l1": [1.5, 0.5]}, "inverse.l1"),
        ({"b": [0.1, 0.1], "theta0": [1.0, 1.0], "n": [0.0, 0.0]}, "unknown field 'theta0'; nearest: theta0_deg"),
    ],
)
def test_bad_inverse_options_are_named(inverse, needle):
    """Refused when the case is read (before any solve), naming the option's field."""
    with pytest.raises(ValidationError) as info:
        _case(inverse)
    lines = [f"{field}: {problem}" for field, problem in describe_all(info.value)]
    assert any(line.startswith("methods.fem.inverse") and needle in line for line in lines), lines
