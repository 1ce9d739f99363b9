"""The PRB four-bar under a dead force at the end of PRB link 2 (case bapat2015_test2_tip_force):
the input angle it returns must make the total potential U(theta2) - F . r_A(theta2) stationary,
checked with a central difference of the spring energy (eq 181, not the torque formula the solver
uses) and of the force's work; and the coupler point must be the four-bar's at that angle."""

from __future__ import annotations

import cmath
import math
from pathlib import Path

import numpy as np

import prbm
from validation.case.loader import load_case
from validation.methods import prbm as prbm_adapter
from validation.methods.base import Request
from validation.case.method_options import options_of

CASE = Path(__file__).resolve().parents[2] / "cases" / "chapter9" / "test2_tip_force_variant.toml"


def _fourbar(options):
    Z = {k: complex(*v) for k, v in options["links"].items()}
    fb = prbm.FourBar(Z["r1"], Z["r2"], Z["r3"], Z["r4"], Z["r5"], springs=(options["springs"]["k1"], 0.0, 0.0, 0.0))
    t20 = math.radians(options["energy_free"]["theta2"])
    fb.theta_free = (
        t20,
        math.radians(options["energy_free"]["theta3"]),
        math.radians(options["energy_free"]["theta4"]),
    )
    return fb, t20


def test_force_at_link2_end_is_an_energy_stationary_point():
    case = load_case(CASE).case
    options = dict(case.methods["prbm"])
    fb, t20 = _fourbar(options)
    (load,) = [ld for ld in case.loads if ld.kind == "force"]
    requests = [Request(q, "P", lv) for lv in range(case.n_levels()) for q in ("dx", "dy")]
    run = prbm_adapter.run(case, requests, options_of("prbm", options))
    assert run.converged, run.message
    for level, value in enumerate(load.levels()):
        if value == 0.0:
            continue
        F = value * complex(*load.direction)
        dy = run.values[Request("dy", "P", level)]
        # recover theta2 from the coupler point, then check stationarity there
        grid = t20 + np.radians(np.linspace(0.0, 90.0, 9001))
        P0 = complex(fb.coupler_point(t20))
        theta2 = grid[np.argmin(np.abs((np.asarray(fb.coupler_point(grid)) - P0).imag - dy))]
        h = 1e-6

        def potential(t):
            return float(fb.strain_energy(t)) - (np.conj(F) * fb.R2 * cmath.exp(1j * t)).real

        slope = (potential(theta2 + h) - potential(theta2 - h)) / (2 * h)
        spring_torque = (float(fb.strain_energy(theta2 + h)) - float(fb.strain_energy(theta2 - h))) / (2 * h)
        assert abs(slope) <= 2e-3 * abs(spring_torque), (level, slope, spring_torque)
