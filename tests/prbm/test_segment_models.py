"""Segment PRBMs that had no case (cases/segments/): their conventions against independent solutions."""

import math

import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

import prbm
from validation.case.loader import case_by_id
from validation.methods.base import Request
from validation.run.runner import run_method


def test_curved_pinned_pinned_has_no_offset_and_the_arch_compliance():
    """Arc L = 1, R = 1 (half-angle alpha = 1/2) pinned at both ends of its chord, force F along the chord.
    At F = 0 the PRBM chord must be the arc's chord 2 R sin(alpha) (on main it was 3 % long: the halves'
    force and chord were taken along each half's own chord instead of the mid-span tangent). Small F:
    Castigliano with M = F y(s), y the height over the chord, gives d chord = F/EI int y^2 ds
    (Timoshenko & Gere, thin curved bar); the two-half PRBM with constant gamma, K_Theta is within 20 %."""
    alpha = 0.5
    chord0 = 2 * math.sin(alpha)
    r = prbm.curved_pinned_pinned([0.0, 1e-4, -1e-4], length=1.0, EI=1.0, curvature=1.0)
    chord = r.outputs["chord"]
    assert chord[0] == pytest.approx(chord0, abs=1e-12)
    compliance = quad(lambda phi: (math.cos(phi) - math.cos(alpha)) ** 2, -alpha, alpha)[0]
    assert (chord[1] - chord0) / 1e-4 == pytest.approx(compliance, rel=0.2)
    assert (chord[2] - chord0) / -1e-4 == pytest.approx(compliance, rel=0.2)


def test_slfp_case_follows_eq_76():
    """The SLFP case's PRBM tip (cases/segments/slfp_alone.toml): k Theta = F (L + l/2) sin(phi - Theta),
    k = EI/l, pivot at l/2 (seed 000 eqs (71)-(76)), solved here independently."""
    case = case_by_id("segment_slfp_alone").case
    run = run_method(case, "prbm")
    l, L, EI = 0.25, 2.0, 1.0
    for level, F in enumerate(case.loads[0].levels()):
        Theta = brentq(lambda t: EI / l * t - F * (L + l / 2) * math.cos(t), 0.0, math.pi / 2)
        assert run.values[Request("x", "B", level)] == pytest.approx(l / 2 + (L + l / 2) * math.cos(Theta), abs=1e-9)
        assert run.values[Request("y", "B", level)] == pytest.approx((L + l / 2) * math.sin(Theta), abs=1e-9)
        assert run.values[Request("rotation", "B", level)] == pytest.approx(math.degrees(Theta), abs=1e-7)
