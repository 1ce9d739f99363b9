"""Fixed-guided beams in a PRB network at their own end-load ratio (``[methods.prbm] rules.fixed_guided_fits``):
each level's model rebuilt at the ratio n its solve gives, until n settles.

The parallel guide of ``cases/segments/parallel_guided_mechanism.toml`` (two equal beams from the ground up to a
coupler loaded at its middle M) under a force F (1, -1/2):
* the ratios are read from the pins' solved forces: the forces the coupler applies to the two PRB links sum to F
  (the coupler's balance; a sign or a pin mixed up would not);
* the guide carries the force's moment by a tension/compression couple in its beams: pushed to +x at the top,
  the left beam is pulled (n < 0) and the right one pushed (n > 0);
* at the settled ratios, each beam's gamma and K_Theta are the Pauly-Midha fits at its own n [bapat2015, eqs
  41, 43], and solving that model once more gives those ratios back (the fixed point the option asks for)."""

import math

import numpy as np
import pytest

from prbm.fits import PAULY_MIDHA
from validation.case.method_options import options_of
from validation.case.schema import Case
from validation.methods import prbm_network
from validation.methods.prbm_network import guided_ratios
from validation.run import coverage
from validation.run.runner import run_method

F = np.array([1.0, -0.5])
LOADS = (0.5, 2.0)  # the force's size over (1, -1/2), per level


def _case(fits: bool) -> Case:
    data = coverage.minimal_case("force", "parallel-guided mechanism", "prbm")
    load = data["loads"][0]
    load["direction"] = list(F)
    load["values"] = [s * math.hypot(*F) for s in LOADS]
    data["outputs"] = [{"quantity": q, "point": "M"} for q in ("dx", "dy")]
    data["methods"] = {"prbm": {"rules": {"fixed_guided_fits": fits}}}
    return Case.model_validate(data)


def test_the_ratios_come_from_pin_forces_that_balance_the_coupler():
    case = _case(False)
    model = prbm_network.built_model(case.mechanism, None, case.loads)
    result = prbm_network.solve_case(case, model)
    for level, size in enumerate(LOADS):
        left, right = (np.array(result.pin_force(level, f"{b} pivot 2")) for b in ("left", "right"))
        assert np.allclose(left + right, size * F, atol=1e-9)
        ratios = guided_ratios(case, model, result, level)
        # pushed to +x at the top, the guide's base moment pulls the left beam (tension: n < 0) and pushes the
        # right one (compression: n > 0), (-nP, P) with n > 0 compressive
        assert ratios["left"] < -1.0 and ratios["right"] > 1.0


def test_each_guided_beam_settles_at_the_fits_of_its_own_ratio():
    case = _case(True)
    run = run_method(case, "prbm")
    assert run.ok, run.message
    assert "did not settle" not in run.message
    last = len(LOADS) - 1
    rules = options_of("prbm", case.methods["prbm"]).rules
    base = prbm_network.built_model(case.mechanism, rules, case.loads)
    model, result, ratios, settled = prbm_network._fitted_level(
        case, rules, last, base, prbm_network.solve_case(case, base)
    )
    assert settled
    for record in model.beams:
        n = ratios[record.beam]
        assert record.gamma == pytest.approx(PAULY_MIDHA.gamma(n), rel=1e-12)
        assert record.K_theta == pytest.approx(PAULY_MIDHA.K_theta(n), rel=1e-12)
    again = guided_ratios(case, model, result, last)
    assert again == pytest.approx(ratios, rel=1e-8, abs=1e-8)


def test_the_fits_move_the_answer_from_the_constant_model():
    fitted, constant = run_method(_case(True), "prbm"), run_method(_case(False), "prbm")
    assert fitted.ok and constant.ok
    moved = [abs(fitted.values[r] - constant.values[r]) for r in constant.values if r.quantity == "dx"]
    assert max(moved) > 1e-4
