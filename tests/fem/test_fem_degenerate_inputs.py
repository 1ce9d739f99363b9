"""The FEM library on inputs at the edge of its formulas: each gives the answer of the limit it tends
to, or one clear message, never a division by zero or a numpy warning."""

import warnings

import numpy as np
import pytest

import fem


def _cantilever(curvature: float) -> fem.Model:
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", 1.0, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(EA=1e4, EI=1.0), n_elements=8, curvature=curvature)
    m.add_support("root", "fixed")
    m.add_force("tip", 0.0, 0.01)
    return m


@pytest.mark.parametrize("curvature", [5e-324, 1e-300, 1e-17])
def test_a_curvature_below_rounding_of_the_chord_is_a_straight_member(curvature):
    """A sagitta |kappa| c / 8 below eps c (here 5e-324 to 1e-17 on a unit chord) is no arc in double
    precision: the member is the straight one, to the same numbers (the arc's formulas divide by kappa
    and would give zero-length elements)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        bent = fem.solve(_cantilever(curvature))
    straight = fem.solve(_cantilever(0.0))
    assert bent.converged
    np.testing.assert_array_equal(bent.mesh_positions, straight.mesh_positions)


def test_a_curvature_above_rounding_is_still_an_arc():
    """At |kappa| c = 1e-6 the arc is kept: its mid node sits kappa c^2 / 8 off the chord."""
    from fem.discretise import discretise

    X = discretise(_cantilever(1e-6)).X
    mid = X[np.argmin(np.abs(X[:, 0] - 0.5))]
    assert abs(mid[1]) == pytest.approx(1e-6 / 8, rel=1e-3)


def test_arc_length_on_a_zero_load_pattern_says_so():
    """Arc-length control scales the loads of the last level: all zero, there is no path, and the run
    says so in one line instead of dividing by the pattern's zero norm."""
    m = _cantilever(0.0)
    m.loads.clear()
    m.add_force("tip", 0.0, 0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = fem.solve(m, control="arclength", lambda_max=1.0)
    assert not r.converged
    assert r.message == "arc-length control needs a load pattern: the loads at the last level are all zero"
