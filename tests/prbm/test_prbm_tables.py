"""The PRBM reproduces the published PRBM columns (read from the case files) of Tables 3.1-3.6, 9.4,
6.1/6.2 (chapter-6 cases) and the seed-004 constants; known misprints are checked to be what
their findings say, never hidden by a looser tolerance."""

import math
from pathlib import Path

import pytest

import prbm
from validation.case.capabilities import QUANTITIES
from validation.case.loader import load_case
from validation.methods.base import Request
from validation.run.runner import run_method

CASES = Path(__file__).resolve().parents[2] / "cases"
# Table 9.5 (Test 3) is not here: its specimens are not in the seed, and stand-in geometries chosen to
# give the printed DOF would make agreement circular (cases/chapter9/README.md).
TABLE_FILES = sorted(p for p in (CASES / "chapter3").glob("*.toml") if 'compare = "prbm"' in p.read_text()) + [
    CASES / "chapter9" / "test2_partially_compliant_fourbar.toml"
]
_RUNS = {}


def _run(path):
    if path not in _RUNS:
        case = load_case(path).case
        _RUNS[path] = (case, run_method(case, "prbm"))
    return _RUNS[path]


def _value(run, ref):
    point = ref.point if QUANTITIES[ref.quantity].at_point else ""
    return run.values[Request(ref.quantity, point, ref.level)]


def _within(ref, value):
    tol = ref.tolerance
    limit = max(tol.abs or 0.0, (tol.rel or 0.0) * abs(ref.value))
    return abs(value - ref.value) <= limit


@pytest.mark.parametrize("path", TABLE_FILES, ids=lambda p: p.stem)
def test_prbm_reproduces_printed_prbm_columns(path):
    case, run = _run(path)
    assert run.converged, run.message
    refs = [r for r in case.references if r.compare == "prbm"]
    assert refs
    for ref in refs:
        v = _value(run, ref)
        if ref.finding is None:
            assert _within(ref, v), f"{ref.source.label()}: printed {ref.value}, computed {v}"
        else:  # a documented misprint/discrepancy: it must really be outside the tolerance
            assert not _within(ref, v), f"{ref.source.label()}: finding recorded but value reproduced"


def test_documented_discrepancies_have_the_stated_values():
    _, run32 = _run(CASES / "chapter3" / "table3_2_load_specified.toml")
    assert run32.values[Request("y", "tip", 1)] == pytest.approx(
        6.0833, abs=5e-5
    )  # printed 6.082; notes seed-ch2-4 5.2 (independent code): 6.0833
    _, run33 = _run(CASES / "chapter3" / "table3_3_case1_a_b_theta0.toml")
    assert run33.values[Request("force_y", "tip", 0)] == pytest.approx(
        5.4017, abs=5e-5
    )  # printed 5.403; notes seed-ch2-4 5.3 (independent code): 5.4017
    _, run36 = _run(CASES / "chapter3" / "table3_6_case2c_b_theta0_l1.toml")
    assert run36.values[Request("force_y", "tip", 2)] == pytest.approx(9.41, abs=5e-4)  # printed 5.41 (misprint)


def test_table3_3_example3_every_root_is_found_and_is_an_equilibrium():
    """Table 3.3 Ex. 3 with I = 1.02e-5 (the case's beam): the default multistart returns every valid
    root that an exhaustive scan (all 1836 grid points as starts, 3 minutes) finds: two. The printed
    root comes first; each root is an equilibrium with the specified end pose, checked independently
    by the load-specified solver under that root's loads (a, b, theta0 come back)."""
    case, run = _run(CASES / "chapter3" / "table3_3_case1_a_b_theta0.toml")
    roots = run.extras["roots"][2]
    assert len(roots) == 2
    printed = [r for r in case.references if r.compare == "prbm" and r.level == 2 and r.quantity == "force_x"][0]
    assert -roots[0]["nP"] == pytest.approx(printed.value, abs=1e-3)  # the printed root first
    beam = prbm.InflectionBeam(20.0, 30e6 * 1.02e-5)
    for root in roots:
        forward = prbm.solve_loads(beam, root["P"], root["nP"], root["M"], prefer=("l1", root["l1"]))
        back = [s for s in forward.roots[0] if abs(s["l1"] - root["l1"]) < 1e-6]
        assert back, root
        assert back[0]["a"] == pytest.approx(18.5, abs=1e-7) and back[0]["b"] == pytest.approx(5.0, abs=1e-7)
        assert math.degrees(back[0]["theta0"]) == pytest.approx(-45.0, abs=1e-6)


def test_inflection_forward_and_inverse_agree():
    """Table 3.2 Ex. 1 (seed 000, PRBM column): P = 3.5, nP = 1.5, M = 15 give a = 12.287,
    b = 14.523, theta0 = 58.60 deg; the inverse (displacement-specified) solve of that pose returns
    the loads."""
    beam = prbm.InflectionBeam(20.0, 30e6 * 1.02e-5)
    fwd = prbm.solve_loads(beam, 3.5, 1.5, 15.0)
    o = fwd.outputs
    assert float(o["a"]) == pytest.approx(12.287, abs=5e-4)  # Table 3.2 Ex. 1, printed digits
    assert float(o["b"]) == pytest.approx(14.523, abs=5e-4)
    assert math.degrees(float(o["theta0"])) == pytest.approx(58.60, abs=5e-3)
    inv = prbm.solve_displacements(beam, a=float(o["a"]), b=float(o["b"]), theta0=float(o["theta0"]))
    assert float(inv.outputs["P"]) == pytest.approx(3.5, abs=1e-7)
    assert float(inv.outputs["nP"]) == pytest.approx(1.5, abs=1e-7)
    assert float(inv.outputs["M"]) == pytest.approx(15.0, abs=1e-6)
    s = prbm.inflection_state(beam, o["F"], o["phi1"], o["theta0"], o["l1"], o["theta10"])
    assert abs(float(s["r95"])) < 1e-9 and abs(float(s["r96"])) < 1e-9


def test_test1a_printed_prbm_points_lie_on_the_gamma0_circle():
    """What can be reproduced of Table 9.1: the kinematics (eqs 48-50) with gamma(0)."""
    case = load_case(CASES / "chapter9" / "test1a_composite_beam.toml").case
    l = case.segment.length
    g0 = prbm.PAULY_MIDHA.gamma(0.0)
    pts = {}
    for ref in case.references:
        if ref.label == "PRBM" and ref.level > 0:
            pts.setdefault(ref.level, {})[ref.quantity] = ref.value
    for lv, p in pts.items():
        implied = ((l - p["x"]) ** 2 + p["y"] ** 2) / (2 * l * (l - p["x"])) if p["x"] != l else None
        # (a - (1-g) l)^2 + b^2 = (g l)^2  ->  g = ((l-a)^2 + b^2) / (2 l (l-a))
        assert implied == pytest.approx(g0, abs=2e-3), lv


def test_chapter6_prbm_columns():
    for name in ("example1", "example3"):
        path = CASES / "chapter6" / f"{name}.toml"
        if not path.exists():
            pytest.skip("chapter-6 cases not present")
        case, run = _run(path)
        for ref in case.references:
            if ref.compare == "prbm" and ref.finding is None:
                assert _within(ref, _value(run, ref)), ref.source.label()


def test_a_displacement_problem_given_several_values_says_which_argument():
    """solve_displacements takes one pose (b, theta0 and one of a, n, l1): an array of several b is a
    ValueError naming b (not numpy's broadcasting error deep in the multistart); a numpy scalar is one
    number and gives the same roots as the float (Table 3.3 Ex. 3's pose, I = 1.02e-5)."""
    import numpy as np

    beam = prbm.InflectionBeam(20.0, 30e6 * 1.02e-5)
    with pytest.raises(ValueError, match="solve_displacements: b must be one number"):
        prbm.solve_displacements(beam, a=18.5, b=np.array([5.0, 6.0]), theta0=math.radians(-45))
    with pytest.raises(ValueError, match="solve_displacements: l1 must be one number"):
        prbm.solve_displacements(beam, b=5.0, theta0=math.radians(-30), l1=[9.0, 8.0])
    plain = prbm.solve_displacements(beam, a=18.5, b=5.0, theta0=math.radians(-45))
    scalar = prbm.solve_displacements(beam, a=np.float64(18.5), b=np.float32(5.0), theta0=np.float64(math.radians(-45)))
    assert [r["nP"] for r in scalar.roots[0]] == [r["nP"] for r in plain.roots[0]]
