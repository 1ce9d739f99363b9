"""The PRBM fits and the spring-angle solver against independent evaluations (issue 25, mutation run).

Fits: every branch of every published fit, away from n = 0, against the printed polynomial evaluated
here term by term from the coefficients as printed: seed 000 eqs (41) gamma, (42) c_theta, (43)
K_Theta (Pauly-Midha, transcript lines 1025-1036); seed 004 slide 'arbitrary tip-load' (Howell, lines
44-46). Scalar, few-level and
many-level inputs take different code paths; all must give the printed polynomial.

Spring angle: F R sin(phi - Theta) = k (Theta - Theta_i) (seed 000 eq 47 with an initial angle),
against scipy's brentq on the same residual, bracketed by Theta_i and phi.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

import prbm
from prbm import HOWELL, PAULY_MIDHA, FitRangeError, FitRangeWarning
from prbm.segments import _spring_angle_reference, spring_angle

# (fit, [(lower, upper, printed coefficients c0, c1, ...)]) as printed in the seeds
PRINTED = {
    ("pauly-midha", "gamma"): [
        (-4.0, -1.5, (0.855651, -0.016438)),
        (-1.5, -0.5, (0.852138, -0.018615)),
        (-0.5, 10.0, (0.851892, -0.020805, 0.005867, -0.000895, 0.000069, -0.000002)),
    ],
    ("pauly-midha", "c_theta"): [
        (-4.0, -0.5, (1.238945, 0.012035, 0.00454)),
        (-0.5, 10.0, (1.238845, 0.009113, -0.001929, 0.000191, -0.000007)),
    ],
    ("pauly-midha", "K_theta"): [
        (-4.0, -0.5, (2.66041, -0.069005, -0.002268)),
        (-0.5, 10.0, (2.648834, -0.074727, 0.026328, -0.004609, 0.000390, -0.000013)),
    ],
    ("howell", "gamma"): [
        (-5.0, -1.8316, (0.912364, 0.0145928)),
        (-1.8316, 0.5, (0.852144, -0.0182867)),
        (0.5, 9.99, (0.841655, -0.0067807, 0.000438)),
    ],
    ("howell", "K_theta"): [
        (-5.0, -2.5, (3.024112, 0.121290, 0.003169)),
        (-2.5, -1.0, (1.967647, -2.616021, -3.738166, -2.649437, -0.891906, -0.113063)),
        (-1.0, 10.0, (2.654855, -0.0509896, 0.0126749, -0.00142039, 0.0000584525)),
    ],
}
FAMILY = {"pauly-midha": PAULY_MIDHA, "howell": HOWELL}


def printed(coefficients, n):
    return sum(c * n**i for i, c in enumerate(coefficients))


def inner_points(lower, upper):
    """Three points inside (lower, upper] including the closed upper end."""
    return [lower + 0.25 * (upper - lower), lower + 0.7 * (upper - lower), upper]


CASES = [(family, name, lo, hi, coeffs) for (family, name), branches in PRINTED.items() for lo, hi, coeffs in branches]


@pytest.mark.parametrize("family, name, lo, hi, coeffs", CASES, ids=lambda v: str(v) if isinstance(v, str) else None)
def test_every_branch_is_the_printed_polynomial(family, name, lo, hi, coeffs):
    fit = getattr(FAMILY[family], name)
    points = inner_points(lo, hi)
    expected = [printed(coeffs, n) for n in points]
    for n, want in zip(points, expected):
        assert fit(n) == pytest.approx(want, rel=1e-13, abs=1e-15)  # scalar path
    assert fit(np.array(points)) == pytest.approx(expected, rel=1e-13)  # few levels
    many = np.linspace(points[0], points[1], 200)  # the array path (> 64)
    assert fit(many) == pytest.approx([printed(coeffs, n) for n in many], rel=1e-12)


def test_family_parameters_are_gamma_c_theta_k_theta_in_that_order():
    n = 2.0
    g, c, k = PAULY_MIDHA.parameters(n)
    assert g == pytest.approx(printed(PRINTED["pauly-midha", "gamma"][2][2], n), rel=1e-13)
    assert c == pytest.approx(printed(PRINTED["pauly-midha", "c_theta"][1][2], n), rel=1e-13)
    assert k == pytest.approx(printed(PRINTED["pauly-midha", "K_theta"][1][2], n), rel=1e-13)
    g, c, k = HOWELL.parameters(np.array([2.0, -3.0]))
    assert np.isnan(c).all() and c.shape == (2,)  # seed 004 prints no c_theta
    assert k[1] == pytest.approx(printed(PRINTED["howell", "K_theta"][0][2], -3.0), rel=1e-13)
    assert g[0] == pytest.approx(printed(PRINTED["howell", "gamma"][2][2], 2.0), rel=1e-13)


def test_out_of_range_message_names_the_fit_and_its_range_and_bad_mode_is_refused():
    with pytest.raises(FitRangeError, match=r"gamma\(n\): load ratio n = 12 outside the fitted range -4.0 < n <= 10.0"):
        PAULY_MIDHA.gamma(12.0)
    with pytest.raises(FitRangeError, match="n = -6"):
        PAULY_MIDHA.K_theta(np.array([1.0, -6.0] + [0.0] * 100))
    with pytest.raises(ValueError, match="extrapolate must be"):
        PAULY_MIDHA.gamma(12.0, extrapolate="quietly")
    # 'allow' evaluates the nearest branch's printed polynomial
    assert PAULY_MIDHA.gamma(12.0, extrapolate="allow") == pytest.approx(
        printed(PRINTED["pauly-midha", "gamma"][2][2], 12.0), rel=1e-13
    )
    assert PAULY_MIDHA.gamma(-6.0, extrapolate="allow") == pytest.approx(
        printed(PRINTED["pauly-midha", "gamma"][0][2], -6.0), rel=1e-13
    )


def brentq_angle(FR, phi, k, theta_i):
    if FR == 0.0:
        return theta_i
    return brentq(
        lambda t: FR * math.sin(phi - t) - k * (t - theta_i),
        min(theta_i, phi),
        max(theta_i, phi),
        xtol=1e-15,
        rtol=1e-15,
    )


# (F R, phi, k, Theta_i): tension/compression sides, a stiff and a soft spring, an initial angle, phi < Theta_i
PROBLEMS = [
    (1.0, 0.5 * math.pi, 2.65 * 0.85, 0.0),
    (8.0, 2.0, 2.0, 0.0),
    (0.3, 0.2, 5.0, 0.0),
    (20.0, 2.9, 1.0, 0.0),
    (4.0, 1.2, 2.0, 0.4),
    (3.0, -1.0, 2.5, 0.3),
    (0.0, 1.0, 2.0, 0.25),
]


@pytest.mark.parametrize(
    "solver, most", [(spring_angle, 8), (_spring_angle_reference, 60)], ids=["spring_angle", "reference"]
)
def test_spring_angle_is_the_root_of_the_moment_balance(solver, most):
    """``most``: the Newton iterations allowed; spring_angle starts on the monotone side of a concave
    residual (its docstring), so it converges quadratically; the old reference may bisect."""
    expected = [brentq_angle(*p) for p in PROBLEMS]
    for p, want in zip(PROBLEMS, expected):  # scalars
        theta, ok, iterations = solver(*p)
        assert ok and theta == pytest.approx(want, abs=1e-12)
        assert iterations <= most and (p[0] == 0.0) == (iterations == 0)
    columns = [np.array(c) for c in zip(*PROBLEMS)]  # a few levels at once
    theta, ok, _ = solver(*columns)
    assert ok.all() and theta == pytest.approx(expected, abs=1e-12)
    reps = 60  # > 256 levels: the array path
    theta, ok, _ = solver(*(np.tile(c, reps) for c in columns))
    assert ok.all() and theta == pytest.approx(np.tile(expected, reps), abs=1e-12)
    theta, ok, _ = solver(np.linspace(0.1, 30.0, 300), 2.0, 2.0)  # broadcast scalars
    assert ok.all() and theta == pytest.approx(
        [brentq_angle(f, 2.0, 2.0, 0.0) for f in np.linspace(0.1, 30.0, 300)], abs=1e-12
    )


def test_spring_angle_reports_no_convergence_when_out_of_iterations():
    theta, ok, iterations = spring_angle(20.0, 2.9, 1.0, maxiter=1)
    assert not ok and iterations == 1


@pytest.mark.parametrize("family, name", sorted(PRINTED), ids=lambda v: str(v))
def test_breakpoints_and_nearest_branch_on_every_path(family, name):
    """A breakpoint belongs to the lower branch (lower < n <= upper, as printed) on the scalar, the
    few-level and the array path; outside the range 'allow' evaluates the
    nearest branch's printed polynomial on every path."""
    fit = getattr(FAMILY[family], name)
    branches = PRINTED[family, name]
    for (_, upper, coeffs), (_, _, above) in zip(branches[:-1], branches[1:]):
        many = np.full(100, upper)
        assert fit(upper) == pytest.approx(printed(coeffs, upper), rel=1e-13)
        assert fit(many) == pytest.approx(np.full(100, printed(coeffs, upper)), rel=1e-12)
        just_above = np.full(100, upper + 1e-3)
        assert fit(just_above) == pytest.approx(np.full(100, printed(above, upper + 1e-3)), rel=1e-12)
    below, above = branches[0][0] - 0.5, branches[-1][1] + 0.5
    outside = np.array([below, above] * 40)
    want = np.array([printed(branches[0][2], below), printed(branches[-1][2], above)] * 40)
    assert fit(outside, extrapolate="allow") == pytest.approx(want, rel=1e-12)
    assert fit(outside[:2], extrapolate="allow") == pytest.approx(want[:2], rel=1e-12)


def test_parameters_pass_the_extrapolation_choice_to_every_fit():
    g, c, k = PAULY_MIDHA.parameters(12.0, extrapolate="allow")
    assert (g, c, k) == pytest.approx(
        (
            printed(PRINTED["pauly-midha", "gamma"][2][2], 12.0),
            1.238845 + 0.009113 * 12 - 0.001929 * 144 + 0.000191 * 12**3 - 0.000007 * 12**4,
            printed(PRINTED["pauly-midha", "K_theta"][1][2], 12.0),
        ),
        rel=1e-12,
    )
    with pytest.warns(UserWarning, match="nearest branch extrapolated"):
        PAULY_MIDHA.parameters(12.0, extrapolate="warn")


def test_unknown_family_names_the_known_ones():
    from prbm.fits import fit_family

    with pytest.raises(ValueError, match="unknown fit family 'midha'; known: pauly-midha, howell"):
        fit_family("midha")
    assert fit_family("howell") is HOWELL and fit_family(PAULY_MIDHA) is PAULY_MIDHA


def test_spring_angle_array_path_counts_its_iterations():
    """The numpy path (> 256 levels) reports the iterations it took, as the scalar path does.  Derivation:
    with F R = 1e-12 the linear start Theta_i + F R sin(phi - Theta_i)/(F R cos(phi - Theta_i) + k) is
    within ~1e-24 of the root, so the first Newton step is below xtol: one iteration.  Problem 4 of
    PROBLEMS needs more than two (from its linear start), so two allowed iterations end unconverged."""
    many = 300
    theta, ok, iterations = spring_angle(np.full(many, 1e-12), 1.0, 2.0)
    assert ok.all() and iterations == 1
    assert theta == pytest.approx(np.full(many, 1e-12 * math.sin(1.0) / 2.0), rel=1e-9, abs=0.0)
    stiff = [np.full(many, v) for v in PROBLEMS[3]]
    for maxiter in (1, 2):
        theta, ok, iterations = spring_angle(*stiff, maxiter=maxiter)
        assert not ok.any() and iterations == maxiter
    theta, ok, iterations = spring_angle(*stiff)
    assert ok.all() and 2 < iterations <= 8


def test_spring_angle_array_path_warns_of_nothing_when_the_linear_start_divides_by_zero():
    """F R cos(phi - Theta_i) + k = 0 exactly (k = -cos 2, F R = 1, phi = 2): the linear start is
    undefined, the solver starts at phi instead, silently, and finds the root."""
    many = 300
    k = -math.cos(2.0)
    assert 1.0 * math.cos(2.0) + k == 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        theta, ok, _ = spring_angle(np.ones(many), 2.0, k)
    assert ok.all() and theta == pytest.approx(np.full(many, brentq_angle(1.0, 2.0, k, 0.0)), abs=1e-12)


def test_extrapolation_warning_says_what_was_done_and_points_at_the_caller():
    """'warn' (prbm.fits docstring): a FitRangeWarning saying the nearest branch was extrapolated, reported
    at the line that called the fit (not inside prbm/fits.py)."""
    with pytest.warns(FitRangeWarning) as record:
        value = PAULY_MIDHA.gamma(12.0, extrapolate="warn")
    [warning] = record
    assert "outside the fitted range" in str(warning.message) and "nearest branch extrapolated" in str(warning.message)
    # at the caller, not inside the library (exactly this file in a plain run; mutmut's trampoline adds a frame)
    assert not Path(warning.filename).resolve().is_relative_to(Path(prbm.__file__).resolve().parent)
    last = PAULY_MIDHA.gamma.branches[-1].coefficients  # eq (41), branch -0.5 < n <= 10
    assert value == pytest.approx(sum(c * 12.0**i for i, c in enumerate(last)), rel=1e-14)


@pytest.mark.parametrize("count", [5, 300], ids=["few", "many"])
def test_spring_angle_broadcasts_its_arguments(count):
    """Vectorised like numpy: any argument may be a scalar or an array, arrays of different shapes broadcast;
    each level is the root of its own moment balance (brentq on the bracket, as above)."""
    FR = np.linspace(0.5, 20.0, count)
    theta, ok, _ = spring_angle(3.0, np.linspace(0.3, 2.8, count), 2.0)  # a scalar F R, an array phi
    assert ok.all() and theta.shape == (count,)
    assert theta == pytest.approx([brentq_angle(3.0, p, 2.0, 0.0) for p in np.linspace(0.3, 2.8, count)], abs=1e-12)
    phis = np.array([0.4, 1.5, 2.7])
    theta, ok, _ = spring_angle(FR[:, None], phis, 2.0)  # (count, 1) with (3,)
    assert ok.shape == theta.shape == (count, 3) and ok.all()
    want = [[brentq_angle(f, p, 2.0, 0.0) for p in phis] for f in FR]
    assert theta == pytest.approx(np.array(want), abs=1e-12)


def test_spring_angle_of_no_levels_is_empty():
    theta, ok, iterations = spring_angle(np.array([]), 1.0, 2.0)
    assert theta.shape == ok.shape == (0,) and iterations == 0


@pytest.mark.parametrize("count", [1, 5, 300], ids=["one", "few", "many"])
def test_spring_angle_iteration_limit_is_the_number_of_newton_steps_allowed(count):
    """Derivation as above: F R = 1e-12 converges in one Newton step from the linear start, so maxiter = 1
    suffices and the solver says it took 1; maxiter = 0 allows no step, so a loaded level is not converged
    and 0 iterations are reported."""
    FR = 1e-12 if count == 1 else np.full(count, 1e-12)
    theta, ok, iterations = spring_angle(FR, 1.0, 2.0, maxiter=1)
    assert np.all(ok) and iterations == 1
    assert theta == pytest.approx(
        np.full(count, 1e-12 * math.sin(1.0) / 2.0) if count > 1 else 1e-12 * math.sin(1.0) / 2.0, rel=1e-9, abs=0.0
    )  # the values are 4e-13: the default abs = 1e-12 would pass 0
    theta, ok, iterations = spring_angle(FR, 1.0, 2.0, maxiter=0)
    assert not np.any(ok) and iterations == 0


def test_fits_of_integer_ratios_are_the_fits_of_the_same_floats():
    """An integer n (one, or an integer array on either array path) gives the printed polynomials' values,
    a Python float for one n (eq 41 at n = 0 is its constant 0.851892)."""
    assert PAULY_MIDHA.gamma(0) == 0.851892 and type(PAULY_MIDHA.gamma(0)) is float
    for count in (8, 200):  # the small-array and polyval paths
        ints = np.arange(count) % 10 - 3  # -3 ... 6, inside -4 < n <= 10
        for fit in (PAULY_MIDHA.gamma, PAULY_MIDHA.K_theta, PAULY_MIDHA.c_theta, HOWELL.K_theta):
            assert np.array_equal(fit(ints), fit(ints.astype(float)))
