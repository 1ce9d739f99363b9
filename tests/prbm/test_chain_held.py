"""The Chain Algorithm with its tip held (``prbm.chain.chain_held_path``): a fixed-guided segment (tip rotation
held, translation free) under a uniform load, against the exact elastica of the same beam (``elastica``'s
shooting with the tip angle prescribed, an independent code). The chain is a discretisation of the elastica
(lumped loads, small-deflection elements): its error falls as 1/N^2, so doubling N divides it by about 4.
Small loads: the linear fixed-guided beam, tip deflection q L^4/(24 EI) and tip moment q L^2/6 (a cantilever's
q L^4/(8 EI) and q L^3/(6 EI) slope cancelled by a tip moment; derived here)."""

import numpy as np
import pytest

from elastica.shooting import ElasticaProblem, solve_path
from prbm.chain import ChainBeam, chain_held_path, lumped_uniform_load
from validation.case.method_options import options_of
from validation.case.schema import Case
from validation.run import coverage
from validation.run.runner import run_method


def _tip_error(w: float, N: int) -> tuple[float, float]:
    exact = solve_path(ElasticaProblem(length=1.0, EI=1.0, distributed=(0.0, -w), tip_angle=0.0))
    beam = ChainBeam(1.0, 1.0, N)
    (res,) = chain_held_path(beam, lumped_uniform_load(beam, 0.0, -w), ["rz"], [1.0])
    assert res.converged, res.message
    return float(np.hypot(res.outputs["a"] - exact.x, res.outputs["b"] - exact.y)), float(
        res.outputs["M"] - exact.moment
    )


@pytest.mark.parametrize("w", [10.0, 30.0])
def test_a_guided_chain_under_a_uniform_load_converges_to_the_elastica_at_second_order(w):
    coarse, _ = _tip_error(w, 40)
    fine, moment_error = _tip_error(w, 80)
    assert fine < 1e-3
    assert coarse / fine > 3.5
    assert abs(moment_error) < 1e-3 * w


def test_a_small_load_gives_the_linear_guided_beam():
    w = 0.01
    beam = ChainBeam(1.0, 1.0, 40)
    (res,) = chain_held_path(beam, lumped_uniform_load(beam, 0.0, -w), ["rz"], [1.0])
    assert res.outputs["b"] == pytest.approx(-w / 24, rel=1e-3)
    assert res.outputs["M"] == pytest.approx(w / 6, rel=1e-3)
    assert res.outputs["theta0"] == pytest.approx(0.0, abs=1e-12)


def test_a_straight_chain_held_along_its_axis_is_refused_with_the_reason():
    with pytest.raises(ValueError, match="cannot bend"):
        chain_held_path(
            ChainBeam(1.0, 1.0, 10), lumped_uniform_load(ChainBeam(1.0, 1.0, 10), 0.0, -1.0), ["ux", "uy", "rz"], [1.0]
        )


@pytest.mark.parametrize("load", ["distributed load", "self-weight"])
def test_the_prbm_adapter_chooses_the_guided_chain_for_a_load_along_a_fixed_guided_segment(load):
    """No option beyond the case's geometry and loads: the adapter chooses the chain (its count doubled until
    the tip moves by less than chain_tol L, so it is within about chain_tol L / 3 of the chain's limit, the
    elastica) and holds its tip angle; against the exact elastica of the same case, within chain_tol L."""
    data = coverage.minimal_case(load, "fixed-guided", "prbm")
    data["loads"][0]["values"] = [10.0]
    data["outputs"] = [{"quantity": q, "point": "tip"} for q in ("x", "y", "rotation", "moment")]
    data["methods"] = {"prbm": {}, "elastica": {}}
    case = Case.model_validate(data)
    prb, exact = run_method(case, "prbm"), run_method(case, "elastica")
    assert prb.ok and exact.ok, (prb.message, exact.message)
    assert prb.extras["model"].startswith("Chain Algorithm")
    tol = options_of("prbm", {}).chain_tol
    get = {r.quantity: v for r, v in prb.values.items()}
    want = {r.quantity: v for r, v in exact.values.items()}
    assert abs(want["y"]) > 0.1
    assert np.hypot(get["x"] - want["x"], get["y"] - want["y"]) < tol
    assert get["rotation"] == pytest.approx(0.0, abs=1e-9)
    assert get["moment"] == pytest.approx(want["moment"], rel=10 * tol)
