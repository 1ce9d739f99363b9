"""What ``fixed_pinned_tip`` reports besides the tip, on each of its three code paths (mutation survivors).

The mutation run of issue 25 left two real, unchecked survivors in ``_fixed_pinned_levels`` (the path
for 2..256 load levels): the constants' "family" key and the model string's text. Both are read by
callers (the report names the model; the PRBM adapter's notes name the family), so each path is held
here to the same record:

* ``model`` = "fixed-pinned, seed 000 eqs (41)-(49)" (the equations the function implements);
* ``constants['family']`` = the fit family asked for, and the constants themselves equal the printed
  fits at n = 0, where each polynomial is its constant term:
  Pauly-Midha (seed 000 eqs 41-43): gamma = 0.851892, c_theta = 1.238845, K_theta = 2.648834;
  Howell (seed 004, 'arbitrary tip-load' slide): gamma = 0.852144, K_theta = 2.654855 (no c_theta fit);
* k = gamma K_theta EI / l (eq 45).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from prbm.segments import fixed_pinned_tip

MODEL = "fixed-pinned, seed 000 eqs (41)-(49)"
PRINTED_AT_ZERO = {"pauly-midha": (0.851892, 1.238845, 2.648834), "howell": (0.852144, math.nan, 2.654855)}
LENGTH, EI = 20.0, 306.0  # the section 3.4 beam: l = 20 in, E I = 30e6 x 1.02e-5 lb in^2
PATHS = {"one level": 1.5, "a few levels": [0.5, 1.0, 1.5], "many levels": np.linspace(0.1, 1.5, 300)}


@pytest.mark.parametrize("family", sorted(PRINTED_AT_ZERO))
@pytest.mark.parametrize("path", sorted(PATHS))
def test_model_family_and_constants_on_every_path(path, family):
    res = fixed_pinned_tip(PATHS[path], 0.0, length=LENGTH, EI=EI, family=family)
    assert res.model == MODEL
    assert res.constants["family"] == family
    gamma, c_theta, K = PRINTED_AT_ZERO[family]
    assert np.all(np.asarray(res.constants["gamma"]) == pytest.approx(gamma, rel=1e-12))
    assert np.all(np.asarray(res.constants["K_theta"]) == pytest.approx(K, rel=1e-12))
    if math.isnan(c_theta):
        assert np.all(np.isnan(res.constants["c_theta"]))
    else:
        assert np.all(np.asarray(res.constants["c_theta"]) == pytest.approx(c_theta, rel=1e-12))
    assert np.all(np.asarray(res.constants["k"]) == pytest.approx(gamma * K * EI / LENGTH, rel=1e-12))


@pytest.mark.parametrize("path", sorted(PATHS))
def test_the_tip_obeys_eqs_44_to_49_with_the_printed_constants(path):
    """Theta from (F l^2/EI) sin(phi - Theta) = K Theta at n = 0 (phi = 90 deg: cos Theta = K Theta EI/(P l^2)),
    then a = l - gamma l (1 - cos Theta), b = gamma l sin Theta, theta0 = c_theta Theta (eqs 44, 48, 49)."""
    gamma, c_theta, K = PRINTED_AT_ZERO["pauly-midha"]
    res = fixed_pinned_tip(PATHS[path], 0.0, length=LENGTH, EI=EI)
    Theta = np.asarray(res.outputs["Theta"], float)
    P = np.asarray(PATHS[path], float)
    assert np.all(np.abs(P * LENGTH**2 / EI * np.cos(Theta) - K * Theta) <= 1e-10 * np.maximum(1.0, K * Theta))
    assert np.all(
        np.asarray(res.outputs["a"]) == pytest.approx(LENGTH - gamma * LENGTH * (1 - np.cos(Theta)), rel=1e-12)
    )
    assert np.all(np.asarray(res.outputs["b"]) == pytest.approx(gamma * LENGTH * np.sin(Theta), rel=1e-12))
    assert np.all(np.asarray(res.outputs["theta0"]) == pytest.approx(c_theta * Theta, rel=1e-12))
