"""One long load level of the FEM stays on the connected path (fem.solver load control).

A cantilever (L = 1, EI = 1, square section, L/h = 100: EA/EI = 1.2e5 / L^2) under a tip dead
load of P L^2/EI = alpha pointing back towards the clamp with a small transverse component.
The path from the unloaded beam has no bifurcation (the transverse component is an imperfection):
it bends the way that component pushes and curls back. One load level must give what 40 levels
give: a long step that lands on an unstable state is retried shorter, a step that jumps to the
far side is rejected, and no branch is switched (found by `prbm-validate stress --long`; before,
alpha = 29 at 177 deg switched to a buckled state at y = -0.34 instead of y = +0.40).
References: the FEM in 40 levels (same mesh: the same equilibrium to the Newton tolerance) and
the exact elastica in 40 levels (differs by the FEM's O(h^2) error and the axial stretch).
"""

import numpy as np
import pytest

from validation.run.runner import run_method
from validation.stress.checks import cantilever, tip

EXAMPLES = [(29.0, 177.0), (40.0, 170.0), (10.0, 190.0)]  # (alpha, load angle in degrees)
H = 0.01


def case(alpha, angle, levels, methods=("fem",)):
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
def test_one_level_equals_forty_levels(alpha, angle):
    one = run_method(case(alpha, angle, 1), "fem")
    many = run_method(case(alpha, angle, 40), "fem")
    assert one.converged and many.converged, (one.message, many.message)
    assert "branch switch" not in one.message and "branch switch" not in many.message
    a, b = tip(one), tip(many)
    assert np.hypot(*(a[:2] - b[:2])) < 1e-7
    assert abs(a[2] - b[2]) < 1e-5  # degrees


@pytest.mark.parametrize("alpha, angle", EXAMPLES)
def test_one_level_agrees_with_the_elastica_in_forty_levels(alpha, angle):
    one = run_method(case(alpha, angle, 1), "fem")
    exact = run_method(case(alpha, angle, 40, methods=("elastica",)), "elastica")
    assert exact.converged
    stretch = alpha / 1.2e5  # P L / EA with L = EI = 1
    assert np.hypot(*(tip(one)[:2] - tip(exact)[:2])) < 1e-3 + stretch
    assert abs(tip(one)[2] - tip(exact)[2]) < 0.1
