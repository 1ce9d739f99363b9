"""Fits of gamma, c_theta, K_Theta (seed 000 eqs 41-43; seed 004 Howell fits): values, ranges, jumps."""

import math
import warnings

import numpy as np
import pytest

from prbm import HOWELL, PAULY_MIDHA, FitRangeError, FitRangeWarning, load_angle, load_ratio


def test_pauly_midha_constant_terms_are_the_printed_coefficients():
    # at n = 0 each fit is its printed constant coefficient (eqs 41-43, branch -0.5 < n <= 10)
    assert PAULY_MIDHA.parameters(0.0) == (0.851892, 1.238845, 2.648834)


def test_howell_constant_terms_are_the_printed_coefficients():
    g, c, k = HOWELL.parameters(0.0)
    assert (g, k) == (0.852144, 2.654855) and math.isnan(c)


@pytest.mark.parametrize("family", [PAULY_MIDHA, HOWELL])
def test_out_of_range_raises_warns_or_allows(family):
    for n in (family.lower, family.upper + 1.0, -50.0):
        with pytest.raises(FitRangeError):
            family.gamma(n)
        with pytest.raises(FitRangeError):
            family.K_theta(np.array([0.0, n]))
        with pytest.warns(FitRangeWarning):
            family.gamma(n, extrapolate="warn")
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            family.gamma(n, extrapolate="allow")


def test_range_endpoints_follow_the_printed_inequalities():
    # -4 < n <= 10: n = 10 is inside, n = -4 outside
    PAULY_MIDHA.parameters(10.0)
    with pytest.raises(FitRangeError):
        PAULY_MIDHA.parameters(-4.0)


def test_breakpoint_jumps_are_those_of_the_published_fits():
    jumps = {f: dict(getattr(PAULY_MIDHA, f).breakpoint_jumps()) for f in ("gamma", "c_theta", "K_theta")}
    assert jumps["gamma"][-1.5] == pytest.approx(
        -0.0002475, abs=1e-9
    )  # derived from the printed coefficients of eqs (41)-(43) at the breakpoints
    assert jumps["gamma"][-0.5] == pytest.approx(
        0.002432, abs=1e-9
    )  # derived from the printed coefficients of eq (41)-(43)
    assert jumps["c_theta"][-0.5] == pytest.approx(
        -0.0002805625, abs=1e-12
    )  # derived from the printed coefficients of eq (41)-(43)
    assert jumps["K_theta"][-0.5] == pytest.approx(
        -0.00096509375, abs=1e-12
    )  # derived from the printed coefficients of eq (41)-(43)
    h = dict(HOWELL.gamma.breakpoint_jumps())
    assert h[0.5] == pytest.approx(-0.0046265, abs=1e-9)
    assert abs(h[-1.8316]) < 3e-6  # continuous to the printed digits
    hk = dict(HOWELL.K_theta.breakpoint_jumps())
    assert hk[-2.5] == pytest.approx(0.00215234375, abs=1e-10)
    assert hk[-1.0] == pytest.approx(0.00390234250, abs=1e-10)


def test_breakpoint_belongs_to_the_lower_branch_and_jump_is_visible():
    below = PAULY_MIDHA.gamma(-0.5)
    above = PAULY_MIDHA.gamma(-0.5 + 1e-12)
    assert below == pytest.approx(
        0.852138 + 0.018615 * 0.5, abs=1e-12
    )  # derived from the printed coefficients of eq (41)-(43)
    assert above - below == pytest.approx(0.002432, abs=1e-9)  # derived from the printed coefficients of eq (41)-(43)


def test_vectorised_equals_scalar():
    n = np.linspace(-3.99, 10.0, 101)
    vec = PAULY_MIDHA.parameters(n)
    for i in (0, 17, 50, 100):
        sc = PAULY_MIDHA.parameters(float(n[i]))
        for v, s in zip(vec, sc):
            assert v[i] == pytest.approx(s, abs=1e-15)


def test_every_evaluation_path_gives_the_printed_polynomials():
    """The scalar path, the few-levels loop (<= 64 ratios) and the array path (101 ratios) against the
    printed polynomials of eqs (41)-(43) written out at n = 1 (the sum of the upper branch's
    coefficients) and n = -2 (the lower branches): equal paths alone would pass any common error."""
    gamma_1 = 0.851892 - 0.020805 + 0.005867 - 0.000895 + 0.000069 - 0.000002  # eq (41), n = 1
    c_1 = 1.238845 + 0.009113 - 0.001929 + 0.000191 - 0.000007  # eq (42), n = 1
    K_1 = 2.648834 - 0.074727 + 0.026328 - 0.004609 + 0.000390 - 0.000013  # eq (43), n = 1
    gamma_m2 = 0.855651 - 0.016438 * -2.0  # eq (41), -4 < n <= -1.5
    c_m2 = 1.238945 + 0.012035 * -2.0 + 0.00454 * 4.0  # eq (42), -4 < n <= -0.5
    K_m2 = 2.66041 - 0.069005 * -2.0 - 0.002268 * 4.0  # eq (43), -4 < n <= -0.5
    expected = {1.0: (gamma_1, c_1, K_1), -2.0: (gamma_m2, c_m2, K_m2)}
    for n, values in expected.items():
        few = np.array([n, 0.0, n])
        many = np.full(101, n)
        for path in (n, few, many):
            got = PAULY_MIDHA.parameters(path)
            for fit, want in zip(got, values):
                assert np.ravel(fit)[0] == pytest.approx(want, rel=1e-12)
                assert np.ravel(fit)[-1] == pytest.approx(want, rel=1e-12)


def test_load_angle_and_ratio_are_inverse():
    n = np.array([-3.0, -0.5, 0.0, 0.896, 7.0])
    assert np.allclose(load_ratio(load_angle(n)), n)
    assert load_angle(0.0) == pytest.approx(math.pi / 2)
    assert load_angle(1.0) == pytest.approx(3 * math.pi / 4)  # n > 0 compressive: force points back


def test_load_ratio_of_a_direction_is_minus_cot_phi():
    """Seed 000 eqs 93/94: n = -1/tan(phi). A force at 60 deg (forward, tensile) has n = -1/sqrt(3); at
    135 deg (pointing back, compressive) n = +1; the array path agrees; and load_angle(-1) = 45 deg."""
    assert load_ratio(math.pi / 3) == pytest.approx(-1.0 / math.sqrt(3.0), rel=1e-12)
    assert load_ratio(np.array([math.pi / 3, 3 * math.pi / 4])) == pytest.approx(
        [-1.0 / math.sqrt(3.0), 1.0], rel=1e-12
    )
    assert load_angle(-1.0) == pytest.approx(math.pi / 4, rel=1e-12)
    assert load_angle(np.array([-1.0, 1.0])) == pytest.approx([math.pi / 4, 3 * math.pi / 4], rel=1e-12)
