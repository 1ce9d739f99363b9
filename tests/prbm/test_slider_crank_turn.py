"""The slider-crank's coupler angle is measured in the turn of its reference angle.

A coupler angle of position 1 given as -170 deg and as +190 deg is the same pose; the spring torque
on the crank (seed 000 eq 196, T_c = dU/dTheta2) must not depend on which was written. Expected
values are derived in closed form: with only k2 (coupler-crank) and the offset slider of the class
docstring, theta3 = asin((offset - R2 sin theta2)/R3) on the branch of position 1, so
h3 = dtheta3/dtheta2 = -R2 cos theta2 / (R3 cos theta3) and
T_c = k2 (dtheta3 - dtheta2) (h3 - 1).
"""

import math

import numpy as np
import pytest

import prbm

R2, R3, T2_REF, K2 = 1.0, 3.0, math.radians(30.0), 2.0


def _slider(theta3_ref_deg: float) -> prbm.SliderCrank:
    t3 = math.radians(theta3_ref_deg)
    offset = R2 * math.sin(T2_REF) + R3 * math.sin(t3)
    return prbm.SliderCrank(R2, R3, T2_REF, t3, offset=offset, springs=(0.0, K2, 0.0))


def _closed_form_torque(theta3_ref_deg: float, theta2: float) -> float:
    t3_ref = math.radians(theta3_ref_deg)
    offset = R2 * math.sin(T2_REF) + R3 * math.sin(t3_ref)
    t3 = math.pi - math.asin((offset - R2 * math.sin(theta2)) / R3)  # cos(theta3_ref) < 0 branch
    d3 = math.remainder(t3 - t3_ref, 2.0 * math.pi)
    h3 = -R2 * math.cos(theta2) / (R3 * math.cos(t3))
    return K2 * (d3 - (theta2 - T2_REF)) * (h3 - 1.0)


@pytest.mark.parametrize("theta3_ref_deg", [-170.0, 190.0, -120.0, 240.0])
def test_coupler_angle_is_in_the_turn_of_its_reference(theta3_ref_deg):
    sc = _slider(theta3_ref_deg)
    assert float(sc.theta3(T2_REF)) == pytest.approx(math.radians(theta3_ref_deg), abs=1e-12)
    for theta2 in T2_REF + np.array([-0.3, 0.2, 0.5]):
        assert abs(float(sc.theta3(theta2)) - math.radians(theta3_ref_deg)) < math.pi


@pytest.mark.parametrize("theta3_ref_deg", [-170.0, 190.0])
@pytest.mark.parametrize("rotation", [0.01, -0.2, 0.4])
def test_spring_torque_does_not_depend_on_how_the_reference_angle_is_written(theta3_ref_deg, rotation):
    theta2 = T2_REF + rotation
    torque = float(_slider(theta3_ref_deg).compliance_torque(np.array([theta2]))[0])
    assert torque == pytest.approx(_closed_form_torque(theta3_ref_deg, theta2), rel=1e-9)
