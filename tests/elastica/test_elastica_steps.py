"""The continuation's step control and the integrator's stage sums (elastica.integrator).

* ``_combine`` (the DOP853 stage sums, components in the inner loop) adds the terms in the same
  order as the plain dot product sum_j K[j, i] w[j], so it is equal to it to the last bit.
* ``_reach`` is the step h at which the second-order estimate of the tip motion, speed h +
  accel h^2 / 2, reaches the limit.
* The step-size rule (steps capped by the tip's predicted motion, an undamped corrector inside its
  trust region) may change the path's steps but not the equilibrium reached: the same loads solved
  with steps twenty times shorter (max_position_step, max_rotation_step = 0.025 instead of 0.25 L and
  0.5 rad) give the same tip to 1e-10. Loads: Table 3.3 (Bapat 2015, section 3.5.2) Ex. 2 and Ex. 3,
  normalised by the case's EI = E I = 30e6 x 1.02e-5 lb in^2 and L = 20 in (F L^2/EI, M L/EI; seeds'
  signs: Fx = -nP, Fy = P, CCW moment -M): the long high-load forward level of that case, and the
  same level reached from the unloaded beam.
"""

import math

import numpy as np
import pytest

from elastica import solve_elastica, solve_path
from elastica.integrator import _combine, _reach
from elastica.shooting import ElasticaProblem

EI, L = 30e6 * 1.02e-5, 20.0
EX2 = ((-1.559, 1.248), 7.128)  # (nP, P), M of Table 3.3 Ex. 2 (printed PRBM loads)
EX3 = ((-35.635, 19.577), 130.23)  # Ex. 3


def _problem(loads):
    (nP, P), M = loads
    scale = L**2 / EI
    return ElasticaProblem(force=(-nP * scale, P * scale), moment=-M * L / EI)


def test_stage_sums_are_the_plain_dot_product_to_the_bit():
    rng = np.random.default_rng(3)
    K = rng.normal(size=(13, 17))
    w = rng.normal(size=13)
    w[[1, 2, 5]] = 0.0  # DOP853's tables have zero weights, which are skipped
    out = np.empty(17)
    for count in (1, 7, 13):
        _combine(K, w, count, out)
        for i in range(17):
            plain = 0.0
            for j in range(count):
                plain += K[j, i] * w[j]
            assert out[i] == plain


@pytest.mark.parametrize("speed, accel, limit", [(2.0, 0.0, 0.5), (2.0, 30.0, 0.5), (0.0, 4.0, 0.5), (1e-3, 1e3, 0.25)])
def test_reach_is_where_the_predicted_motion_meets_the_limit(speed, accel, limit):
    h = _reach(speed, accel, limit)
    assert speed * h + 0.5 * accel * h * h == pytest.approx(limit, rel=1e-12)


def test_reach_is_unbounded_without_motion():
    assert math.isinf(_reach(0.0, 0.0, 0.5))


@pytest.mark.parametrize("start_loads", [None, EX2], ids=["from rest", "from Ex. 2"])
def test_step_rule_reaches_the_same_equilibrium_as_short_steps(start_loads):
    start = None if start_loads is None else solve_path(_problem(start_loads), n_samples=2)
    target = _problem(EX3)
    default = solve_path(target, start=start, n_samples=2)
    short = solve_path(target, start=start, n_samples=2, max_position_step=0.025, max_rotation_step=0.025)
    assert default.converged and short.converged, (default.message, short.message)
    assert short.nsteps > 3 * default.nsteps  # the short steps really are a different path
    for a, b in (
        (default.x, short.x),
        (default.y, short.y),
        (default.theta, short.theta),
        (default.reaction[2], short.reaction[2]),
    ):
        assert a == pytest.approx(b, rel=1e-10, abs=1e-12)


def test_forward_solve_matches_its_public_entry():
    """solve_elastica with the same loads is the same solve (guards the normalisation above)."""
    (nP, P), M = EX3
    scale = L**2 / EI
    a = solve_elastica(1.0, 1.0, force=(-nP * scale, P * scale), moment=-M * L / EI, n_samples=2)
    b = solve_path(_problem(EX3), n_samples=2)
    assert a.converged and (a.x, a.y, a.theta) == pytest.approx((b.x, b.y, b.theta), rel=1e-14)
