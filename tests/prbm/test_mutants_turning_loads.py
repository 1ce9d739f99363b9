"""prbm.turning_loads: what the mutation run found unchecked (issue 25 item 6), each with a derived value.

* ``_unit``: a load law's direction is the unit vector of the one given: (3 + 4i)/5 = 0.6 + 0.8i (the
  3-4-5 triangle); the tests elsewhere gave unit or near-unit vectors and read the direction back
  through the same law, so u * |u| survived in place of u / |u|. A zero or infinite vector is refused,
  naming the law.
* The four-bar's input angle under a couple alone: with the only spring k1 at the ground pivot O2 of
  link 2 (springs = (k1, 0, 0, 0)) the spring torque is k1 (theta2 - theta20) (eq 181), so a couple T
  gives theta2 = theta20 + T/k1 exactly, in either direction (the sign of T decides the search side).
* The fit family reaches the segment model: with Howell's fits (seed 004, 'arbitrary tip-load' slide)
  and a transverse dead force (n = 0), gamma = 0.852144 and K_Theta = 2.654855 (the printed constant
  terms), not Pauly-Midha's 0.851892 / 2.648834 (seed 000 eqs 41, 43).
* A level without load is the unloaded tip exactly (a = l, b = theta0 = Theta = Fx = Fy = 0); a level
  whose equilibrium direction is not found in the scanned span is NaN, never the unloaded tip.
"""

from __future__ import annotations

import cmath
import math
import warnings

import numpy as np
import pytest

import prbm
from prbm.fits import FitRangeError, FitRangeWarning, fit_family
from prbm.turning_loads import (
    DeadDirection,
    FollowerDirection,
    TipPose,
    TowardPoint,
    _SegmentModel,
    fixed_pinned_turning_tip,
    input_angle_under_turning_forces,
)

POSE = TipPose(complex(2.0, 0.5), 0.5)


def test_a_law_gives_the_unit_vector_of_its_direction():
    assert DeadDirection(complex(3.0, 4.0)).direction(POSE) == pytest.approx(complex(0.6, 0.8), abs=1e-15)
    turned = complex(0.6, 0.8) * cmath.exp(0.5j)  # kept at its angle to the end tangent, turned by 0.5 rad
    assert FollowerDirection(complex(3.0, 4.0)).direction(POSE) == pytest.approx(turned, abs=1e-15)


@pytest.mark.parametrize("law, name", [(DeadDirection, "DeadDirection"), (FollowerDirection, "FollowerDirection")])
@pytest.mark.parametrize("u0", [0j, complex(math.inf, 0.0)])
def test_a_law_refuses_a_zero_or_infinite_direction(law, name, u0):
    with pytest.raises(ValueError, match=f"^{name}: the direction must be a finite non-zero vector"):
        law(u0).direction(POSE)


def test_a_follower_needs_the_end_rotation():
    with pytest.raises(ValueError, match="^FollowerDirection: the end tangent's rotation is not available"):
        FollowerDirection(1j).direction(TipPose(complex(1.0, 0.0), math.nan))


@pytest.mark.parametrize("torque", [0.3, -0.3])
def test_a_couple_alone_turns_link_2_by_T_over_k1(torque):
    A, O4, B = 1.5 * cmath.exp(1j * math.radians(60.0)), complex(4.0, 0.0), complex(3.5, 2.5)
    k1 = 2.0
    fb = prbm.FourBar(O4, A, B - A, B - O4, 0.5 * (B - A), springs=(k1, 0.0, 0.0, 0.0))
    theta20 = math.radians(60.0)
    theta2 = input_angle_under_turning_forces(fb, [], theta20=theta20, c_theta=1.238845, torque=torque)
    assert theta2 == pytest.approx(theta20 + torque / k1, abs=1e-12)


@pytest.mark.parametrize("family, gamma, K", [("howell", 0.852144, 2.654855), ("pauly-midha", 0.851892, 2.648834)])
def test_the_fit_family_reaches_the_segment(family, gamma, K):
    # printed constant terms: seed 004 (Howell), seed 000 eqs 41, 43 (Pauly-Midha); n = 0 for a transverse force
    res = fixed_pinned_turning_tip([0.5], DeadDirection(1j), length=1.0, EI=1.0, family=family)
    assert res.constants["family"] == family
    assert float(res.outputs["n"][0]) == pytest.approx(0.0, abs=1e-12)
    assert float(res.constants["gamma"][0]) == pytest.approx(gamma, rel=1e-12)
    assert float(res.constants["K_theta"][0]) == pytest.approx(K, rel=1e-12)


def test_unloaded_and_unsolved_levels():
    L = 3.0
    # a span of 2e-4 rad around the unloaded direction holds no equilibrium of F = 1 toward (4, 6)
    res = fixed_pinned_turning_tip([0.0, 1.0], TowardPoint(complex(4.0, 6.0)), length=L, EI=7.5, step=1e-4, span=2e-4)
    o = res.outputs
    assert [o[k][0] for k in ("a", "b", "theta0", "Theta", "Fx", "Fy")] == [L, 0.0, 0.0, 0.0, 0.0, 0.0]
    assert all(np.isnan(o[k][1]) for k in ("a", "b", "theta0", "Theta", "Fx", "Fy", "n"))
    assert list(res.level_converged) == [True, False] and not res.converged
    assert "no equilibrium direction found" in res.message


def test_the_result_record_names_the_model_and_says_it_converged():
    res = fixed_pinned_turning_tip([0.5, 1.0], DeadDirection(1j), length=1.0, EI=1.0)
    assert res.converged and res.message == "converged" and list(res.level_converged) == [True, True]
    assert res.model == ("fixed-pinned under a turning end force, seed 000 eqs (41)-(49) at the equilibrium load ratio")
    assert res.iterations == 0 and res.wall_time > 0.0
    assert set(res.constants) == {"gamma", "c_theta", "K_theta", "k", "family"}


@pytest.mark.parametrize(
    "length, EI, F",
    [(0.0, 1.0, 1.0), (1.0, 0.0, 1.0), (math.inf, 1.0, 1.0), (1.0, math.inf, 1.0), (1.0, 1.0, math.nan)],
)
def test_bad_arguments_are_refused_by_name(length, EI, F):
    with pytest.raises(ValueError, match="^fixed_pinned_turning_tip: (length and EI|F) must be finite"):
        fixed_pinned_turning_tip([F], DeadDirection(1j), length=length, EI=EI)


def test_toward_point_names_itself_when_undefined():
    with pytest.raises(
        ValueError,
        match=r"^TowardPoint: the loaded point is at the point the force pulls toward "
        r"\(direction undefined\)$",
    ):
        TowardPoint(complex(1.0, 0.0)).direction(TipPose(complex(1.0, 0.0), 0.0))


# --- the second mutation run (session 6): which error, which message, the extrapolate option ---------------
L3, EI3 = 3.0, 7.5


def test_an_axial_dead_force_has_no_direction_inside_the_fits():
    """A dead force along the unloaded segment (u = +x): its only equilibrium direction is psi = 0, where
    n = -cos(psi)/sin(psi) is infinite (seed 000 eq 43 where-clause), outside -4 < n <= 10 (eqs 41-43).
    Scanned +-30 deg, each side leaves the fits' range and comes back into it (n = -4 at psi = 14.0 deg,
    n = 10 at psi = -5.7 deg), so a reading that forgot the directions outside the range on the way
    would report 'no equilibrium' where the answer is 'outside the fits'."""
    message = (
        r"^turning end force \|F\| = 1: no equilibrium direction inside the n-fits' range "
        r"\(seed 000 eqs 41-43\)$"
    )
    for span in (math.radians(30.0), math.pi):
        with pytest.raises(FitRangeError, match=message):
            fixed_pinned_turning_tip([1.0], DeadDirection(complex(1.0, 0.0)), length=L3, EI=EI3, span=span)


def test_an_axial_force_is_refused_by_the_segment_model_itself():
    model = _SegmentModel(L3, EI3, "pauly-midha", "raise")
    with pytest.raises(
        FitRangeError,
        match=r"^end force along the segment \(direction 180\.000 deg\): "
        r"n infinite, outside every n-fit$",
    ):
        model.tip(1.0, math.pi)


def test_the_failure_message_lists_only_the_levels_that_failed():
    """Level 0 carries no load (converged by definition, the unloaded tip); level 1 has no equilibrium
    in the scanned 2e-4 rad: the message names level 1's failure and nothing else (it once read
    'no load; ...')."""
    res = fixed_pinned_turning_tip([0.0, 1.0], TowardPoint(complex(4.0, 6.0)), length=L3, EI=EI3, step=1e-4, span=2e-4)
    assert res.message == "turning end force |F| = 1: no equilibrium direction found"
    loaded_only = fixed_pinned_turning_tip([0.0, 1.0], TowardPoint(complex(4.0, 6.0)), length=L3, EI=EI3)
    assert loaded_only.converged and loaded_only.message == "converged"


PULLEY_AHEAD = complex(13.0, 1.2)  # ahead on the axis: the rope pulls nearly axially, n ~ -9 to -10


def _extrapolated_equilibrium(res):
    """The fixed-pinned PRBM at the returned force, with the fits evaluated past their range by the
    nearest branch (what 'allow' and 'warn' mean, prbm.fits): eq (47) k Theta = gamma l (F_y cos Theta -
    F_x sin Theta), eqs (44), (48), (49).  (Past n = -52.7 the extrapolated K_Theta of eq (43) turns
    negative and the spring equation has no root: a pulley that far out would test nothing.)"""
    for level in range(len(res.outputs["a"])):
        o = {k: float(v[level]) for k, v in res.outputs.items()}
        n = -o["Fx"] / o["Fy"]
        gamma, c_theta, K = fit_family("pauly-midha").parameters(n, extrapolate="allow")
        Theta = o["Theta"]
        assert -52.0 < n < -4.0  # outside the range: the option mattered
        assert gamma * K * EI3 / L3 * Theta == pytest.approx(
            gamma * L3 * (o["Fy"] * math.cos(Theta) - o["Fx"] * math.sin(Theta)), rel=1e-9
        )
        assert o["a"] == pytest.approx(L3 - gamma * L3 * (1 - math.cos(Theta)), rel=1e-12)
        assert o["b"] == pytest.approx(gamma * L3 * math.sin(Theta), rel=1e-12)
        assert o["theta0"] == pytest.approx(c_theta * Theta, rel=1e-12)
        tip = complex(o["a"], o["b"])
        assert cmath.phase(complex(o["Fx"], o["Fy"]) / (PULLEY_AHEAD - tip)) == pytest.approx(0.0, abs=1e-9)


def test_extrapolate_allow_reaches_the_fits():
    """The rope needs n ~ -9: outside the fits, refused by default; with extrapolate='allow' the segment
    model evaluates the fits there instead, silently."""
    with pytest.raises(FitRangeError):
        fixed_pinned_turning_tip([1.0, 3.0], TowardPoint(PULLEY_AHEAD), length=L3, EI=EI3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = fixed_pinned_turning_tip([1.0, 3.0], TowardPoint(PULLEY_AHEAD), length=L3, EI=EI3, extrapolate="allow")
    assert res.converged
    _extrapolated_equilibrium(res)


def test_extrapolate_warn_warns_and_gives_the_same_tip():
    with pytest.warns(
        FitRangeWarning,
        match=r"outside the fitted range -4\.0 < n <= 10\.0 .*nearest branch "
        r"extrapolated$",
    ):
        res = fixed_pinned_turning_tip([1.0, 3.0], TowardPoint(PULLEY_AHEAD), length=L3, EI=EI3, extrapolate="warn")
    _extrapolated_equilibrium(res)
