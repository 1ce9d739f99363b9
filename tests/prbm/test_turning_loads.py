"""Turning end forces on the PRBMs (prbm.turning_loads) on configurations no case file holds.

Every expected number is a derivation, not our own output:
* the fixed-pinned PRBM's equilibrium about the characteristic pivot, k Theta = gamma K_Theta (EI/l) Theta =
  gamma l (F_y cos Theta - F_x sin Theta), with gamma, K_Theta evaluated independently from the fits at
  the load ratio of the force returned (mirrored for F_y < 0, seed 000 notes to Tables 3.2-3.6), and
  the tip of eqs (48)-(49);
* the load law at that tip: the force points at the pulley (or keeps its angle to the end tangent);
* the small-load limit: the dead force at the unloaded tip, b = (gamma/K_Theta) F_perp l^3/EI, the
  linear beam's F_perp l^3/(3 EI) times 3 gamma/K_Theta (derived from eqs 46-49 linearised);
* on a PRB four-bar, the virtual-work balance dU/dtheta2 = Im(conj(A) F) with dU/dtheta2 from a
  central difference of the spring energy (eq 181), and the perpendicular force's moment F R2 equal to
  a couple F R2 solved by the network's own torque path.
"""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

import prbm
from prbm.fits import FitRangeError, fit_family
from prbm.turning_loads import (
    DeadDirection,
    FollowerDirection,
    TipPose,
    TowardPoint,
    fixed_pinned_turning_tip,
    input_angle_under_turning_forces,
)

L, EI = 3.0, 7.5  # a segment no case file has
FAMILY = fit_family("pauly-midha")


def _check_equilibrium(res, level: int) -> None:
    """gamma K_Theta (EI/l) Theta = gamma l (F_y cos Theta - F_x sin Theta), gamma, K_Theta from the fits at n."""
    o = {k: float(np.asarray(v)[level]) for k, v in res.outputs.items()}
    sign = -1.0 if o["Fy"] < 0 else 1.0
    n = -o["Fx"] / o["Fy"]
    gamma, c_theta, K = FAMILY.parameters(sign * n)
    Theta = o["Theta"]
    assert gamma * K * EI / L * Theta == pytest.approx(
        gamma * L * (o["Fy"] * math.cos(Theta) - o["Fx"] * math.sin(Theta)), rel=1e-9, abs=1e-12
    )
    assert o["a"] == pytest.approx(L - gamma * L * (1 - math.cos(Theta)), rel=1e-12)  # eq (48)
    assert o["b"] == pytest.approx(gamma * L * math.sin(Theta), rel=1e-12, abs=1e-15)  # eq (49)
    assert o["theta0"] == pytest.approx(c_theta * Theta, rel=1e-12, abs=1e-15)  # eq (44)


@pytest.mark.parametrize(
    "pulley",
    [
        complex(2.0, 5.0),  # above and behind the tip: compressive pull
        complex(6.0, 2.0),  # ahead and above: tensile
        complex(1.0, -4.0),  # below: the tip bends down (F_y < 0, mirrored fits)
        complex(-2.0, 3.0),
    ],
)  # behind the clamp
def test_rope_is_in_equilibrium_and_points_at_the_pulley(pulley):
    F = np.array([0.0, 0.5, 2.0, 4.0])
    res = fixed_pinned_turning_tip(F, TowardPoint(pulley), length=L, EI=EI)
    assert res.converged, res.message
    assert res.outputs["a"][0] == L and res.outputs["b"][0] == 0.0
    for level in range(1, len(F)):
        _check_equilibrium(res, level)
        tip = complex(res.outputs["a"][level], res.outputs["b"][level])
        force = complex(res.outputs["Fx"][level], res.outputs["Fy"][level])
        assert abs(force) == pytest.approx(F[level], rel=1e-12)
        assert cmath.phase(force / (pulley - tip)) == pytest.approx(0.0, abs=1e-9)


def test_rope_force_turns_the_way_the_tip_moves():
    """A pulley straight above the unloaded tip: as the tip swings back (toward the clamp), the rope leans
    forward, so the force gains a tensile x-component (F_x > 0), which grows with the load."""
    res = fixed_pinned_turning_tip([1.0, 3.0], TowardPoint(complex(L, 4.0)), length=L, EI=EI)
    assert np.all(res.outputs["a"] < L)
    assert 0.0 < res.outputs["Fx"][0] < res.outputs["Fx"][1]
    for level in range(2):  # and each state is the PRBM's equilibrium with the rope aimed at the pulley
        _check_equilibrium(res, level)
        tip = complex(res.outputs["a"][level], res.outputs["b"][level])
        force = complex(res.outputs["Fx"][level], res.outputs["Fy"][level])
        assert cmath.phase(force / (complex(L, 4.0) - tip)) == pytest.approx(0.0, abs=1e-9)


def test_angle_to_the_line_keeps_the_force_perpendicular():
    """angle = -90 deg from the line to a point on the segment's axis behind the tip: the force stays
    perpendicular to the line from that point to the tip."""
    hub = complex(0.5, 0.0)
    res = fixed_pinned_turning_tip([1.5], TowardPoint(hub, math.radians(-90.0)), length=L, EI=EI)
    tip = complex(res.outputs["a"][0], res.outputs["b"][0])
    force = complex(res.outputs["Fx"][0], res.outputs["Fy"][0])
    assert (force * (tip - hub).conjugate()).real == pytest.approx(0.0, abs=1e-9)
    _check_equilibrium(res, 0)


def test_follower_keeps_its_angle_to_the_end_tangent():
    u0 = cmath.exp(1j * math.radians(110.0))  # a compressive follower, n = 0.36 at rest
    res = fixed_pinned_turning_tip([0.7, 1.2], FollowerDirection(u0), length=L, EI=EI)
    for level in range(2):
        _check_equilibrium(res, level)
        force = complex(res.outputs["Fx"][level], res.outputs["Fy"][level])
        assert cmath.phase(force / (u0 * cmath.exp(1j * res.outputs["theta0"][level]))) == pytest.approx(0.0, abs=1e-9)


def test_dead_direction_is_the_dead_force_prbm():
    u = complex(0.6, 0.8)  # n = -0.75, tensile
    res = fixed_pinned_turning_tip([1.0, 3.0], DeadDirection(u), length=L, EI=EI)
    dead = prbm.fixed_pinned_tip(np.array([0.8, 2.4]), -0.75, length=L, EI=EI)
    np.testing.assert_allclose(res.outputs["b"], dead.outputs["b"], rtol=1e-10)
    np.testing.assert_allclose(res.outputs["a"], dead.outputs["a"], rtol=1e-12)


def test_small_load_limit_is_the_linear_beam_times_three_gamma_over_K():
    pulley = complex(4.0, 6.0)
    F = 1e-6
    res = fixed_pinned_turning_tip([F], TowardPoint(pulley), length=L, EI=EI)
    u = (pulley - L) / abs(pulley - L)  # the rope's direction at the unloaded tip
    n = -u.real / u.imag
    gamma, _, K = FAMILY.parameters(n)
    linear = F * u.imag * L**3 / (3 * EI)  # Euler-Bernoulli tip deflection under F_perp
    assert res.outputs["b"][0] == pytest.approx(linear * 3 * gamma / K, rel=1e-5)


def test_negative_magnitude_reverses_the_law():
    pulley = complex(1.0, 5.0)
    pushed = fixed_pinned_turning_tip([-2.0], TowardPoint(pulley), length=L, EI=EI)
    turned = fixed_pinned_turning_tip([2.0], TowardPoint(pulley, math.pi), length=L, EI=EI)
    for key in ("a", "b", "Fx", "Fy"):
        assert pushed.outputs[key][0] == pytest.approx(turned.outputs[key][0], rel=1e-10, abs=1e-12)
    assert pushed.outputs["b"][0] < 0.0  # pushed away from a pulley above: the tip goes down


def test_a_nearly_axial_rope_is_outside_the_fits():
    """A pulley far ahead on the axis: the pull is almost axial tension, n far below -4."""
    with pytest.raises(FitRangeError):
        fixed_pinned_turning_tip([1.0], TowardPoint(complex(40.0, 0.5)), length=L, EI=EI)


def test_toward_point_refuses_an_undefined_direction():
    with pytest.raises(ValueError, match="direction undefined"):
        TowardPoint(complex(L, 0.0)).direction(TipPose(complex(L, 0.0), 0.0))


# --- the PRB four-bar's input link --------------------------------------------------------------------
def _fourbar():
    """A crank-rocker no case file has: O2 = 0, A = 1.5 e^{i 60 deg}, O4 = 4, B = 3.5 + 2.5i, P on A-B."""
    A, O4, B = 1.5 * cmath.exp(1j * math.radians(60.0)), complex(4.0, 0.0), complex(3.5, 2.5)
    fb = prbm.FourBar(O4, A, B - A, B - O4, 0.5 * (B - A), springs=(2.0, 0.0, 0.0, 0.0))
    return fb, math.radians(60.0)


def _spring_torque(fb, theta2: float, h: float = 1e-6) -> float:
    return (float(fb.strain_energy(theta2 + h)) - float(fb.strain_energy(theta2 - h))) / (2 * h)


@pytest.mark.parametrize(
    "law",
    [
        FollowerDirection(cmath.exp(1j * math.radians(150.0))),
        TowardPoint(complex(-1.0, 4.0)),
        DeadDirection(complex(-0.5, 1.0)),
    ],
)
def test_fourbar_input_link_balance_by_virtual_work(law):
    fb, t20 = _fourbar()
    c_theta = 1.238845
    F = 0.6
    theta2 = input_angle_under_turning_forces(fb, [(F, law)], theta20=t20, c_theta=c_theta)
    assert math.isfinite(theta2) and theta2 != t20
    A = fb.R2 * cmath.exp(1j * theta2)
    moment = (A.conjugate() * F * law.direction(TipPose(A, c_theta * (theta2 - t20)))).imag
    assert _spring_torque(fb, theta2) == pytest.approx(moment, rel=1e-5)


def test_perpendicular_force_is_the_couple_F_R2():
    fb, t20 = _fourbar()
    F = 0.8
    theta2 = input_angle_under_turning_forces(
        fb, [(F, TowardPoint(0j, math.radians(-90.0)))], theta20=t20, c_theta=1.238845
    )
    couple = fb.positions_under_torque(np.array([F * fb.R2]))
    assert theta2 == pytest.approx(float(couple.outputs["theta2"][0]), abs=1e-7)
