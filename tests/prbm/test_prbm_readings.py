"""The PRBM adapter for loads along the segment and turning end forces (validation.methods.prbm_readings)
on cases no case file holds, and the Chain Algorithm's lumped uniform load against linear theory.

Expected numbers are derivations: the cantilever under a uniform load q, w(L) = q L^4/(8 EI),
w'(L) = q L^3/(6 EI), plus the trapezoid rule's exact error h^2/12 [f'(L) - f'(0)] on the influence
integrands f = x^2 (3L - x)/(6 EI) and x^2/(2 EI) (cubic and quadratic: the Euler-Maclaurin series
stops there); the chain is exact in linear theory for loads at its nodes (eqs 32-33 are the exact
end-loaded cantilever).  The adapter's values are checked against the library called directly and
against the load law; refusals name their reason.
"""

from __future__ import annotations

import cmath
import math
from pathlib import Path

import pytest

from prbm import chain as chain_model
from prbm.turning_loads import TowardPoint, fixed_pinned_turning_tip
from validation.case.loader import load_case
from validation.methods import prbm as prbm_adapter
from validation.methods.base import NotApplicable, Request
from validation.case.method_options import options_of

CH9 = Path(__file__).resolve().parents[2] / "cases" / "chapter9"


@pytest.mark.parametrize("length, EI, elements", [(2.0, 3.0, 10), (0.7, 0.2, 25)])
def test_lumped_uniform_load_linear_limit(length, EI, elements):
    q = 1e-7 * EI / length**3
    beam = chain_model.ChainBeam(length, EI, elements)
    loads = chain_model.lumped_uniform_load(beam, 0.0, q)
    assert loads.fy.sum() == pytest.approx(q * length, rel=1e-12)
    res = chain_model.chain_tip(beam, loads, steps=1)
    h = length / elements
    w = q * length**4 / (8 * EI) + q * h**2 * length**2 / (24 * EI)
    slope = q * length**3 / (6 * EI) + q * h**2 * length / (12 * EI)
    assert float(res.outputs["b"]) == pytest.approx(w, rel=1e-6, abs=0.0)  # w ~ 1e-8: no abs floor
    assert float(res.outputs["theta0"]) == pytest.approx(slope, rel=1e-6, abs=0.0)


def _segment_case(tmp_path, loads: str, prbm_options: str = "", boundary: str = "fixed-free"):
    text = f"""
[case]
id = "synthetic"
title = "synthetic segment"
group = "tests"
units = "dimensionless"

[segment]
boundary = "{boundary}"
length = 2.0
E = 3.0
section = {{ kind = "rectangle", width = 1.0, thickness = 1.0, weight_density = 0.4 }}

{loads}

[[outputs]]
quantity = "x"
[[outputs]]
quantity = "y"
[[outputs]]
quantity = "force_x"
[[outputs]]
quantity = "force_y"

[methods.prbm]
{prbm_options}
"""
    path = tmp_path / "synthetic.toml"
    path.write_text(text)
    return load_case(path).case


def _run(case, quantities=("x", "y", "force_x", "force_y")):
    requests = [Request(q, "tip", lv) for lv in range(case.n_levels()) for q in quantities]
    run = prbm_adapter.run(case, requests, options_of("prbm", case.methods["prbm"]))
    return {(r.quantity, r.level): v for r, v in run.values.items()}, run


ROPE = """
[[loads]]
kind = "force"
toward = [0.5, -3.0]
values = [0.0, 0.3, 0.9]
"""


def test_adapter_rope_below_the_tip_matches_the_library_and_the_law(tmp_path):
    case = _segment_case(tmp_path, ROPE)
    values, run = _run(case)
    assert run.converged, run.message
    EI = 3.0 / 12.0
    lib = fixed_pinned_turning_tip([0.0, 0.3, 0.9], TowardPoint(complex(0.5, -3.0)), length=2.0, EI=EI)
    for lv in range(1, 3):
        tip = complex(values[("x", lv)], values[("y", lv)])
        force = complex(values[("force_x", lv)], values[("force_y", lv)])
        assert tip == pytest.approx(complex(lib.outputs["a"][lv], lib.outputs["b"][lv]), rel=1e-12)
        assert cmath.phase(force / (complex(0.5, -3.0) - tip)) == pytest.approx(0.0, abs=1e-9)
        assert values[("y", lv)] < 0.0


def test_adapter_capstan_scales_the_rope(tmp_path):
    case = _segment_case(tmp_path, ROPE, "friction_mu = 0.1\ncontact_angle_deg = 180.0")
    values, _ = _run(case)
    factor = math.exp(-0.1 * math.pi)
    force = complex(values[("force_x", 2)], values[("force_y", 2)])
    assert abs(force) == pytest.approx(0.9 * factor, rel=1e-12)


WEIGHT = """
[[loads]]
kind = "force"
direction = [0.0, 1.0]
values = [0.0, 0.2, 0.5]
[[loads]]
kind = "self_weight"
direction = [0.0, -2.0]
values = [1.0, 1.0, 1.0]
"""


def test_adapter_chain_self_weight_is_the_lumped_chain_zeroed_at_level_0(tmp_path):
    case = _segment_case(tmp_path, WEIGHT, 'model = "chain"\nchain_elements = 20\nzero_level = 0')
    values, run = _run(case, ("x", "y"))
    assert run.converged, run.message
    beam = chain_model.ChainBeam(2.0, 0.25, 20)
    weight = chain_model.lumped_uniform_load(beam, 0.0, -0.4)  # density 0.4 x area 1, gravity -y (unit)
    tips = []
    for P in (0.0, 0.2, 0.5):
        res = chain_model.chain_tip(beam, weight.plus(chain_model.NodalLoads.at_tip(beam, 0.0, P)))
        tips.append(complex(float(res.outputs["a"]), float(res.outputs["b"])))
    assert tips[0].imag < 0.0  # the weight alone sags the beam
    for lv, tip in enumerate(tips):
        expected = tip - (tips[0] - 2.0)  # positions from the level-0 state
        assert values[("x", lv)] == pytest.approx(expected.real, rel=1e-9)
        assert values[("y", lv)] == pytest.approx(expected.imag, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize(
    "loads, options, reason",
    [
        (WEIGHT, 'model = "theta-dependent"', "model = 'theta-dependent' takes end loads only"),
        (
            WEIGHT.replace('kind = "self_weight"', 'kind = "distributed"\nfollower = true').replace(
                "[0.0, -2.0]", "[0.0, -1.0]"
            ),
            'model = "chain"',
            "follower distributed",
        ),
        (ROPE + '\n[[loads]]\nkind = "moment"\nvalues = [0.0, 0.1, 0.1]\n', "", "other end loads"),
        (WEIGHT.replace("direction = [0.0, 1.0]", "toward = [2.0, 3.0]"), 'model = "chain"', "turning end force"),
    ],
)
def test_adapter_refuses_what_it_cannot_model(tmp_path, loads, options, reason):
    case = _segment_case(tmp_path, loads, options)
    with pytest.raises(NotApplicable, match=reason):
        _run(case)


def test_adapter_refuses_a_rope_on_a_fixed_guided_segment(tmp_path):
    case = _segment_case(tmp_path, ROPE, boundary="fixed-guided")
    with pytest.raises(NotApplicable, match="fixed-guided"):
        _run(case)


def test_fourbar_force_perpendicular_to_O2_A_is_the_design_torque():
    """Test 2's perpendicular reading with the printed k1: the force T/R2 kept perpendicular to O2-A has the
    moment T about O2 at every pose, so the PRB four-bar must land where the base case's couple T puts it
    (solved there by the network's torque path, drive = 'torque')."""
    base = load_case(CH9 / "test2_partially_compliant_fourbar.toml").case
    reading = load_case(CH9 / "test2_perpendicular.toml").case
    options = dict(reading.methods["prbm"])
    options["springs"] = dict(base.methods["prbm"]["springs"])
    requests = [Request(q, "P", lv) for lv in range(4) for q in ("dx", "dy")]
    turned = prbm_adapter.run(reading, requests, options_of("prbm", options))
    couple = prbm_adapter.run(base, requests, options_of("prbm", base.methods["prbm"]))
    assert turned.converged and couple.converged
    for req in requests:
        assert turned.values[req] == pytest.approx(couple.values[req], abs=2e-4), req


def test_fourbar_follower_on_the_coupler_is_refused():
    case = load_case(CH9 / "test2_follower.toml").case
    (load,) = [ld for ld in case.loads if ld.kind == "force"]
    case = case.model_copy(update={"loads": [load.model_copy(update={"body": "coupler"})]})
    requests = [Request("dy", "P", 1)]
    with pytest.raises(NotApplicable, match="coupler"):
        prbm_adapter.run(case, requests, options_of("prbm", case.methods["prbm"]))
