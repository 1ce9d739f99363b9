"""Chapter 7 mechanical advantage through the harness: the PRBM adapter on prbm.compliance
(validation.methods.prbm_ma) and the FEM's Type 1 MA of the SLFP mechanisms (fem_outputs, slfp).

Expected values: eq (192) with MA_R of eq (199) evaluated by the existing slider-crank model on a
geometry where both apply (seed 000 Example 1); the energy-free pose, where the compliance torque is
zero by eq (181); and the SLFP PRBM as the l -> 0 limit of the flexures (seed 000 eq 186)."""

import numpy as np
import pytest

import prbm
from validation.case.loader import case_by_id
from validation.run.runner import run_method
from validation.methods.slfp import with_flexures
from validation.case.method_options import options_of


def _values(run) -> list[float]:
    return [run.values[r] for r in sorted(run.values, key=lambda r: r.level)]


def test_prbm_ma_slider_equals_eq192_with_eq199():
    """Example 1 geometry (coupler at -40 deg, where SliderCrank is right): the adapter's Type 1 MA equals
    MA_R (1 - |T_c| / (F_i d_i)) from prbm.SliderCrank at the same work-piece locations."""
    case = case_by_id("bapat2015_ch7_ex1_ma").case
    options = dict(case.methods["prbm"])
    options["ma"] = dict(options["ma"], model="compliance")
    from validation.methods import prbm_ma

    values, _ = prbm_ma.run(case, [r for r in _requests(case)], options_of("prbm", options))
    sc = prbm.SliderCrank.from_vectors(3.779 + 0j, 1.1083 + 2.2409j, 2.6704 - 2.2408j, springs=(0.0, 8.4515, 7.5193))
    theta2 = np.array([sc.theta2_at(dx) for dx in (0.0, 0.3, 0.6, 0.9, 1.2, 1.5)])
    expected = sc.compliant_ma(theta2, 10.0, 4.0)
    assert [values[r] for r in sorted(values, key=lambda r: r.level)] == pytest.approx(expected, rel=1e-9)


def _requests(case):
    from validation.methods.base import Request

    return [Request("mechanical_advantage", "", lv) for lv in range(case.n_levels())]


def test_crimper_compliance_is_zero_at_the_measured_pose():
    """Example 4a: at dx = 0 (the energy-free pose) T_c = 0, so MA = MA_R = d_i/|I12 I24| (eq 206)."""
    case = case_by_id("bapat2015_ch7_ex4a").case
    run = run_method(case, "prbm")
    sc = prbm.SliderCrank.from_vectors(2.0585 + 0j, 3.7043 + 0.8443j, -1.6457 - 0.9924j)
    assert _values(run)[0] == pytest.approx(float(sc.rigid_ma(sc.theta2_ref, 3.85)), rel=1e-9)


def test_fem_type1_ma_tends_to_the_prbm_as_the_flexure_shrinks():
    """Example 1, held slider at dx = 1.5 in: |FEM - PRBM| falls about linearly with the flexure length
    (the SLFP PRBM is the l -> 0 limit): at l = 0.125 in it is under half of that at l = 0.5 in and under 2 %."""
    case = case_by_id("bapat2015_ch7_ex1_ma").case
    prbm_ma = _values(run_method(case, "prbm"))[-1]
    gaps = []
    for length in (0.5, 0.125):
        options = dict(case.methods["fem"], slfp={"length": length, "E": 450000.0})
        fem_case = case.model_copy(update={"methods": dict(case.methods, fem=options)})
        gaps.append(abs(_values(run_method(fem_case, "fem"))[-1] - prbm_ma) / prbm_ma)
    assert gaps[1] < 0.5 * gaps[0] and gaps[1] < 0.02


def test_held_slider_becomes_a_block_with_three_prescribed_freedoms():
    case = case_by_id("bapat2015_ch7_ex1_ma").case
    built = with_flexures(case, 0.5, 450000.0)
    assert not any(s.node == "S-" for s in built.mechanism.supports)
    held = {(ld.kind, tuple(ld.direction or ())) for ld in built.loads if ld.point == "S-"}
    assert held == {("displacement", (1.0, 0.0)), ("displacement", (0.0, 1.0)), ("rotation", ())}
    alone = case.model_copy(update={"loads": [case.loads[0]]})  # a travel alone: the guided block stays
    assert any(s.node == "S-" and s.kind == "guided" for s in with_flexures(alone, 0.5, 450000.0).mechanism.supports)
