"""Seed 004's PRBM constants: pure-moment gamma and spring, the 1.98 N m/rad remark, the cases run."""

from pathlib import Path

import numpy as np
import pytest

import prbm
from validation.case.loader import load_case
from validation.methods.base import Request
from validation.run.runner import run_method

CASES = Path(__file__).resolve().parents[2] / "cases" / "seed004"


def test_pure_moment_constants():
    """Printed in seed 004 (PRB lecture, pure-moment slide): gamma = 0.7346, k = 1.5164 EI/L."""
    assert prbm.PURE_MOMENT_GAMMA == 0.7346
    assert prbm.PURE_MOMENT_SPRING == 1.5164
    assert prbm.PURE_MOMENT_K_THETA == pytest.approx(2.0643, abs=1e-4)  # Howell's K_Theta = k/(gamma EI/L)
    r = prbm.pure_moment_tip(np.array([1.0]), length=1.0, EI=0.875)
    assert r.constants["k"] == pytest.approx(1.5164 * 0.875)
    assert r.constants["gamma"] == 0.7346


def test_spring_of_the_strip_is_1_98_with_seed004_fits():
    case = load_case(CASES / "strip_tip_force_prbm.toml").case
    EI = case.segment.bending_stiffness()
    g, _, K = prbm.HOWELL.parameters(0.0)
    assert round(g * K * EI / case.segment.length, 2) == 1.98  # "1.98 newton meter per radian"


def test_strip_moment_case_rotation_is_exact():
    case = load_case(CASES / "strip_moment_prbm.toml").case
    run = run_method(case, "prbm")
    assert run.converged
    for ref in case.references:
        if ref.quantity == "rotation":
            assert run.values[Request("rotation", "tip", ref.level)] == pytest.approx(ref.value, abs=1e-6)


def test_strip_force_case_prbm_near_exact():
    case = load_case(CASES / "strip_tip_force_prbm.toml").case
    run = run_method(case, "prbm")
    assert run.converged
    ref = [r for r in case.references if r.level == 0 and r.quantity == "y"][0]
    # the PRBM is an approximation: within 3 % of the exact deflection at PL^2/EI = 1 (anchors.md 2.7)
    assert run.values[Request("y", "tip", 0)] == pytest.approx(ref.value, rel=0.03)
