"""Each library-constant plant of ``validation.stress.plants`` reaches the value it names.

A plant that patches a name nobody reads plants nothing, and the audit would report the method's
cases as 'not exercised' or, worse, count a caught error that another patch caused. Checked in one
throw-away interpreter (plants have no undo), against the seeds' constants:

* the rule builder's defaults gamma = 0.85, K_Theta = 2.65 (prbm.builder, seed 004 sec. 3.1): a
  ``Rules()`` made after the plant carries 0.935 / 2.915 (a dataclass bakes its defaults into
  ``__init__``, so re-binding the module constant alone would leave 0.85);
* the pure-moment constants gamma = 0.7346, k = 1.5164 EI/L (seed 004);
* the Chain Algorithm's element stiffness EI (seed 000 eqs 32-33) x 1.10;
* the BCM's K0 = [[12, -6], [-6, 4]] and C0 = [[1/3, 1/2], [1/2, 1]] (seed 003 Table 1, eq (16)),
  read through bcm.mechanisms as well;
* the elastica mechanism model's beam EI (validation.methods.elastica_network) x 1.10;
* the n-fits (seed 000 eqs 41-43 at n = 0: gamma 0.851892, c_theta 1.238845 (not planted), K_Theta
  2.648834; seed 004 at n = -3: gamma 0.912364 - 3 x 0.0145928, K_Theta 3.024112 - 3 x 0.121290 +
  9 x 0.003169) as the inflection model reads them (plain-float Horner twins that bypass
  ``PiecewiseFit.__call__``: a plant on ``__call__`` alone left every inflection case unplanted) and
  section 3.6's loop average gamma(0).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest

from validation.case.loader import find_case_files, load_case
from validation.stress import plants

# the probe's tests share one xdist worker, so its interpreter starts once, not once per worker
PLANTED = pytest.mark.xdist_group("planted_probe")

PROBE = r"""
import json
from validation.stress import plants
for name in ("prbm-gamma-x1.10", "prbm-K_theta-x1.10", "prbm-chain-EI-x1.10", "bcm-K0-x1.10", "elastica-EI-x1.10"):
    plants.apply(name)
import bcm.mechanisms, prbm.builder, prbm.chain, prbm.feasible_l1, prbm.fits, prbm.inflection
from validation.case.loader import find_case_files, load_case
from validation.methods import elastica_network
rules = prbm.builder.Rules()
beam = prbm.chain.ChainBeam(20.0, 306.0, 4)
case = load_case(find_case_files(["bapat2015_test2_perpendicular"])[0]).case
mech, _ = elastica_network.model(case)
E, t, w = 550000.0, 0.121, 1.5
print(json.dumps(dict(
    gamma=rules.gamma, K_theta=rules.K_theta,
    pm_gamma=prbm.fits.PURE_MOMENT_GAMMA, pm_spring=prbm.fits.PURE_MOMENT_SPRING,
    chain=[float(v) for v in beam.stiffness()],
    K0=bcm.mechanisms.K0.tolist(), C0=bcm.mechanisms.C0.tolist(),
    beam_EI=mech.beams[0].EI, section_EI=E * w * t**3 / 12.0,
    inflection=list(prbm.inflection.InflectionBeam(20.0, 306.0).fits(0.0)),
    howell=[prbm.fits.HOWELL.gamma(-3.0), prbm.fits.HOWELL.K_theta(-3.0)],
    loop_gamma=prbm.feasible_l1.GAMMA_AVERAGE,
    loop_theta=prbm.feasible_l1.loop_closure(length=20.0, b=6.0, theta0=0.0, l1=10.0).Theta1)))
"""


@pytest.fixture(scope="module")
def planted() -> dict:
    out = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


@PLANTED
def test_the_rule_builder_defaults_are_planted(planted):
    # seed 004 sec. 3.1 / seed 000 ch. 2: gamma = 0.85, K_Theta = 2.65
    assert planted["gamma"] == pytest.approx(0.85 * 1.10, rel=1e-12)
    assert planted["K_theta"] == pytest.approx(2.65 * 1.10, rel=1e-12)


@PLANTED
def test_the_pure_moment_constants_are_planted(planted):
    # seed 004, pure end moment: gamma = 0.7346, k = 1.5164 EI/L
    assert planted["pm_gamma"] == pytest.approx(0.7346 * 1.10, rel=1e-12)
    assert planted["pm_spring"] == pytest.approx(1.5164 * 1.10, rel=1e-12)


@PLANTED
def test_the_chain_stiffness_is_planted(planted):
    assert planted["chain"] == pytest.approx([306.0 * 1.10] * 4, rel=1e-12)


@PLANTED
def test_the_bcm_linear_coefficients_are_planted_where_the_mechanisms_read_them(planted):
    assert sum(planted["K0"], []) == pytest.approx([13.2, -6.6, -6.6, 4.4], rel=1e-12)
    assert sum(planted["C0"], []) == pytest.approx([1 / 3.3, 1 / 2.2, 1 / 2.2, 1 / 1.1], rel=1e-12)


@PLANTED
def test_the_elastica_mechanism_beams_are_planted(planted):
    # Test 2's segment: E = 550 ksi, 1.5 x 0.121 in (seed 000 section 9.3.5)
    assert planted["beam_EI"] == pytest.approx(1.10 * planted["section_EI"], rel=1e-9)


def test_every_method_a_case_runs_has_output_and_sign_plants():
    run = {method for path in find_case_files(None) for method in load_case(path).case.methods}
    for method in run:
        assert f"{method}-outputs-x1.10" in plants.PLANTS and f"{method}-sign-flip" in plants.PLANTS, method
        assert any(
            p.method == method and "-x1.10" in p.name and "outputs" not in p.name for p in plants.PLANTS.values()
        ), f"{method}: no library-constant plant"


@PLANTED
def test_the_fits_are_planted_on_every_evaluation_path(planted):
    # printed constant terms of seed 000 eqs (41)-(43) at n = 0 and seed 004's Howell fits at n = -3
    assert planted["inflection"] == pytest.approx([0.851892 * 1.10, 1.238845, 2.648834 * 1.10], rel=1e-12)
    assert planted["howell"] == pytest.approx(
        [(0.912364 - 3 * 0.0145928) * 1.10, (3.024112 - 3 * 0.121290 + 9 * 0.003169) * 1.10], rel=1e-12
    )
    assert planted["loop_gamma"] == pytest.approx(0.851892 * 1.10, rel=1e-12)
    # the loop as the adapter calls it (no gamma given): the symmetric loop b = gamma l sin Theta
    # (tests/prbm/test_prbm_feasible_l1.py) with l = 20, b = 6 gives the planted gamma back
    assert 6.0 / (20.0 * math.sin(planted["loop_theta"])) == pytest.approx(0.851892 * 1.10, rel=1e-9)
