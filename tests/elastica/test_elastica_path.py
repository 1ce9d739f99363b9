"""One requested load reached along the connected path (elastica.shooting continuation).

A cantilever (L = 1, EI = 1) under a tip dead load of P L^2/EI = alpha pointing back towards the
clamp, with a small transverse component: the connected path from the unloaded beam bends the
way that component pushes and curls back (found by `prbm-validate stress --long`). Solved in one
load level, the continuation must land on that path, not on another equilibrium of the same load
(a straight beam pushed towards its clamp has several). Reference: the same elastica reached in
40 load levels (every level a short continuation from the previous one), cross-checked against
the FEM reached in 40 levels (an independent method; differs by its O(h^2) discretisation error
and the axial stretch P L / EA the inextensible elastica lacks, here EA/EI = 1.2e5 / L^2).
"""

import numpy as np
import pytest

from validation.run.runner import run_method
from validation.stress.checks import cantilever, tip

EXAMPLES = [(29.0, 177.0), (40.0, 170.0), (10.0, 190.0)]  # (alpha, load angle in degrees)
H = 0.01  # square section, L/h = 100


def case(alpha, angle, levels, methods=("elastica",)):
    return cantilever(
        length=1.0,
        E=1e6,
        width=H,
        thickness=H,
        alpha=alpha,
        angle_deg=angle,
        levels=levels,
        methods=methods,
        elements=32,
        error_estimate=False,
    )


@pytest.mark.parametrize("alpha, angle", EXAMPLES)
def test_one_level_follows_the_connected_path(alpha, angle):
    one = run_method(case(alpha, angle, 1), "elastica")
    many = run_method(case(alpha, angle, 40), "elastica")
    assert one.converged and many.converged, (one.message, many.message)
    a, b = tip(one), tip(many)
    assert np.hypot(*(a[:2] - b[:2])) < 1e-8
    assert abs(a[2] - b[2]) < 1e-6  # degrees
    # bent the way the transverse component pushes
    assert np.sign(b[1]) == np.sign(np.sin(np.radians(angle)))


@pytest.mark.parametrize("alpha, angle", EXAMPLES)
def test_forty_levels_agree_with_the_fem(alpha, angle):
    exact = run_method(case(alpha, angle, 40), "elastica")
    fem = run_method(case(alpha, angle, 40, methods=("fem",)), "fem")
    assert exact.converged and fem.converged
    stretch = alpha / 1.2e5  # P L / EA with L = EI = 1
    diff = np.hypot(*(tip(exact)[:2] - tip(fem)[:2]))
    assert diff < 1e-3 + stretch  # 32 elements: O(h^2) ~ 1e-4 L
    assert abs(tip(exact)[2] - tip(fem)[2]) < 0.1  # degrees


def test_continuation_rejects_a_jump_to_another_branch():
    """The old acceptance test (tip rotation step < 0.5 rad only) took the first step of the
    alpha = 40, 170 deg load onto a nearly straight S-shaped equilibrium (tip at (0.977, -0.172),
    rotation 7e-5 rad); with the corrector-distance test that step is rejected and the result is
    curled back (rotation 169.25 deg)."""
    from elastica import solve_elastica

    a = np.radians(170.0)
    res = solve_elastica(force=(40.0 * np.cos(a), 40.0 * np.sin(a)))
    assert res.converged and res.theta > 2.9 and res.y > 0.4
