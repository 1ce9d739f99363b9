"""Section 3.6's vector loop (seed 000 eqs 105-107): closure, constraints and accuracy against the
exact inflection problem."""

import math

import pytest

from prbm.feasible_l1 import C_THETA_AVERAGE, GAMMA_AVERAGE, approximate_domain, feasible_l1, loop_closure

L = 20.0


def test_symmetric_loop_is_howells_guided_beam():
    # theta0 = 0, l1 = l/2: slope continuity gives Theta1 = Theta2 = Theta and the loop is the guided
    # beam b = gamma l sin Theta, a = l - gamma l (1 - cos Theta) (two half beams, eq 63's kinematics)
    s = loop_closure(length=L, b=6.0, theta0=0.0, l1=L / 2)
    assert s.feasible
    assert s.Theta1 == pytest.approx(s.Theta2, abs=1e-12)
    assert GAMMA_AVERAGE * L * math.sin(s.Theta1) == pytest.approx(6.0, abs=1e-10)
    assert s.a == pytest.approx(L - GAMMA_AVERAGE * L * (1 - math.cos(s.Theta1)), abs=1e-10)


def test_loop_meets_its_constraints_and_closes():
    # ii) c Theta1 = c Theta2 + theta0; the chain (103) returns b
    theta0 = math.radians(40.0)
    s = loop_closure(length=L, b=12.0, theta0=theta0, l1=13.5)
    g, c, l2 = GAMMA_AVERAGE, C_THETA_AVERAGE, L - 13.5
    assert s.feasible and s.Theta2 > 0
    assert c * s.Theta1 == pytest.approx(c * s.Theta2 + theta0, abs=1e-12)
    b = g * 13.5 * math.sin(s.Theta1) + g * l2 * math.sin(s.Theta2 + theta0) + (1 - g) * l2 * math.sin(theta0)
    assert b == pytest.approx(12.0, abs=1e-10)


def test_short_first_segment_is_infeasible_for_a_positive_end_angle():
    # theta0 = 40 deg, b = 12 in: a short first segment cannot reach b with Theta2 > 0 (theta3 > theta0)
    s = loop_closure(length=L, b=12.0, theta0=math.radians(40.0), l1=3.0)
    assert not s.feasible and "Theta2 > 0" in s.reason
    states = feasible_l1(length=L, b=12.0, theta0=math.radians(40.0), samples=99)
    assert any(st.feasible for st in states) and not all(st.feasible for st in states)


@pytest.mark.parametrize(
    "b, theta0, l1, exact_a",
    [
        # exact a of the inflection problem (b, theta0, moment zero at l1): the findings of
        # cases/chapter3/table3_6_exact_inverse.toml (Table 3.6's conditions, verified there independently)
        (12.0, 40.0, 13.5, 15.4925),
        (5.0, -30.0, 8.5, 18.6970),
        (5.0, -30.0, 9.0, 18.9746),
    ],
)
def test_loop_end_position_near_the_exact_one(b, theta0, l1, exact_a):
    s = loop_closure(length=L, b=b, theta0=math.radians(theta0), l1=l1)
    assert s.feasible
    assert abs(s.a - exact_a) < 0.015 * L  # measured 0.6 %, 0.08 %, 1.2 % of l


def test_domain_points_are_feasible_loops():
    pts = approximate_domain(length=L, theta0=math.radians(20.0), b_values=[4.0, 8.0], samples=20)
    assert pts.shape[1] == 2 and len(pts) > 10
    assert set(pts[:, 1]) <= {4.0, 8.0} and (pts[:, 0] < L).all()
    # theta0 = 0 with the one trial l1 = l/2 (samples = 1): the symmetric loop, Howell's guided beam
    # b = gamma l sin Theta, a = l - gamma l (1 - cos Theta), gamma = 0.851892 (eq 41 at n = 0)
    one = approximate_domain(length=L, theta0=0.0, b_values=[4.0, 8.0], samples=1)
    for b, (a_got, b_got) in zip((4.0, 8.0), one):
        Theta = math.asin(b / (0.851892 * L))
        assert b_got == b and a_got == pytest.approx(L - 0.851892 * L * (1 - math.cos(Theta)), rel=1e-12)


def test_bad_input():
    with pytest.raises(ValueError, match="l1"):
        loop_closure(length=L, b=1.0, theta0=0.0, l1=25.0)
