"""The plain-float paths of the segment models (a few load levels, issue 15 item 5) give the array
paths' numbers: the same arithmetic in the same order.

Each model is called on the same levels twice: once as they are (up to 256 levels: the level loop) and
once padded past 256 levels (the numpy path); the first levels of the padded call are compared
(outputs, constants, convergence).  Closed forms (pure moment) agree to the last bit; where the spring
equation (*) is solved, the level loop's Newton iteration (``_spring_angle_scalar``) may stop one step
before the array iteration (its test of the quadratic error left), so those agree to 1e-12.  The loads cover both signs of P, P = 0, several
load ratios (so the per-ratio caches see more than one entry), and ``fixed_guided_monotonic_tip`` is
checked against the per-level ``curved_fixed_pinned_tip`` solve it is defined by (seed 000 eq (62)).
"""
import numpy as np
import pytest

import prbm
from prbm.segments import _SCALAR_LOOP_MAX

P = np.array([0.0, 0.3, 1.0, 2.5, -1.7, 4.0, 7.5, -0.2, 10.0, 3.3])
N = np.array([0.0, 0.0, 0.5, -0.4, 0.5, 2.0, 0.0, -1.2, 0.5, 9.0])


def _padded(v: np.ndarray) -> np.ndarray:
    """v followed by copies of itself: past the plain-float limit, so the numpy path runs."""
    return np.resize(v, _SCALAR_LOOP_MAX + 14)


def _equal(a, b, rtol: float) -> bool:
    a, b = np.asarray(a, float), np.asarray(b, float)
    both_nan = np.isnan(a) & np.isnan(b)
    return a.shape == b.shape and bool(np.all(both_nan | (np.abs(a - b) <= rtol * np.maximum(np.abs(b), 1.0))))


def _same(small: prbm.PRBMResult, big: prbm.PRBMResult, rtol: float = 1e-12) -> None:
    m = len(np.atleast_1d(small.outputs["a"]))
    assert small.outputs.keys() == big.outputs.keys()
    for key, value in small.outputs.items():  # P and n as given (a scalar n stays a scalar)
        other = np.asarray(big.outputs[key])
        assert _equal(value, other if other.ndim == 0 else other[:m], rtol), key
    for key, value in small.constants.items():
        if isinstance(value, str):
            continue
        other = np.asarray(big.constants[key])
        assert _equal(value, other if other.ndim == 0 else other[:m], rtol), key
    assert np.array_equal(small.level_converged, np.asarray(big.level_converged)[:m])
    assert small.converged == bool(np.all(np.asarray(big.level_converged)[:m]))


@pytest.mark.parametrize("family", ["pauly-midha", "howell"])
def test_fixed_pinned_and_fixed_guided_level_loops_equal_the_array_paths(family):
    n = np.clip(N, -0.9, 9.0)  # inside both families' ranges
    for model in (prbm.fixed_pinned_tip, prbm.fixed_guided_tip):
        small = model(P, n, length=2.0, EI=3.0, family=family)
        big = model(_padded(P), _padded(n), length=2.0, EI=3.0, family=family)
        _same(small, big)
        scalar_n = model(P, 0.5, length=2.0, EI=3.0, family=family)  # n broadcast over the levels
        _same(scalar_n, model(_padded(P), 0.5, length=2.0, EI=3.0, family=family))


def test_curved_level_loop_equals_the_array_path():
    for curvature in (0.0, 0.4, -0.9):
        small = prbm.curved_fixed_pinned_tip(P, N, length=1.5, EI=2.0, curvature=curvature)
        big = prbm.curved_fixed_pinned_tip(_padded(P), _padded(N), length=1.5, EI=2.0, curvature=curvature)
        _same(small, big)


def test_pure_moment_level_loop_equals_the_array_path():
    M = np.array([0.0, 0.5, -1.2, 3.0, 1e-9])
    _same(prbm.pure_moment_tip(M, length=1.3, EI=0.7), prbm.pure_moment_tip(_padded(M), length=1.3, EI=0.7), 0.0)


def test_monotonic_equals_the_curved_solve_level_by_level():
    M = np.array([0.2, 0.0, 1.5, -0.3, 0.8, 0.1, 2.0, -1.0, 0.4, 0.05])
    res = prbm.fixed_guided_monotonic_tip(P, N, M, length=1.2, EI=0.9, curvature=0.3)
    for i in range(len(P)):
        kappa0 = M[i] * 1.2 / 0.9 + 0.3 * 1.2
        one = prbm.curved_fixed_pinned_tip(P[i], N[i], length=1.2, EI=0.9, curvature=kappa0 / 1.2)
        for key in ("a", "b", "theta0", "Theta"):
            assert res.outputs[key][i] == float(one.outputs[key]), (i, key)
        assert res.constants["kappa0"][i] == one.constants["kappa0"]
        assert res.level_converged[i] == one.converged
    assert np.array_equal(res.outputs["M"], M)
