"""Load control past a bifurcation: the solver leaves the unstable branch.

Fixed-free column, L = EI = 1, EA = 1e6, tip load P (direction (-1, e)) through
the Euler load P_cr = pi^2 EI / (4 L^2) to 1.5 P_cr.  The post-buckled elastica
(tip angle a, k = sin(a/2)):  P / P_cr = (2 K(k) / pi)^2,  lateral tip deflection
delta = 2 k / K(k) L  (Timoshenko & Gere sec. 2.7).  The near-straight state
above P_cr is an equilibrium too, but unstable: it must not be returned.
"""

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipk

import fem

P_CR = np.pi**2 / 4
FRACTIONS = np.array([0.5, 0.9, 0.98, 1.02, 1.1, 1.25, 1.4, 1.5])
EA = 1e6


def elastica_deflection(ratio):
    """Lateral tip deflection / L of the post-buckled fixed-free elastica at P = ratio P_cr."""
    k = brentq(lambda k: (2 * ellipk(k * k) / np.pi) ** 2 - ratio, 1e-9, 1 - 1e-12)
    return 2 * k / ellipk(k * k)


def column(n, imperfection):
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", 1.0, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(EA, 1.0), n_elements=n)
    m.add_support("root", "fixed")
    P = P_CR * FRACTIONS
    m.add_force("tip", -P, imperfection * P)
    return m


@pytest.fixture(scope="module")
def runs():
    return {(n, e): fem.solve(column(n, e)) for n in (32, 64) for e in (1e-5, -1e-5)}


@pytest.mark.parametrize("imperfection", [1e-5, -1e-5])
def test_imperfect_column_reaches_post_buckled_elastica(runs, imperfection):
    exact = elastica_deflection(1.5)  # 0.78858
    r32, r64 = runs[32, imperfection], runs[64, imperfection]
    for r in (r32, r64):
        assert r.converged, r.message
        # an imperfect path has no bifurcation: the long step 0.98 -> 1.02 P_cr that lands on
        # the unstable near-straight state is retried shorter, not switched, and a step that
        # jumps to the buckled state on the far side is rejected (`solver._turned_back`)
        assert "branch switch" not in r.message and r.critical_points == []
        assert r.cutbacks > 0
        assert np.all(r.det_sign > 0)  # every returned state is stable
    d32, d64 = (r.position("tip")[1] for r in (r32, r64))
    # buckled towards the imperfection
    assert np.sign(d32) == np.sign(d64) == np.sign(imperfection)
    # O(h^2): the error of the 32-element value is ~ 4/3 |d32 - d64| (Richardson);
    # plus the axial shortening P L / EA the inextensible elastica lacks
    mesh_err = 4.0 / 3.0 * abs(d32 - d64)
    stretch = 1.5 * P_CR / EA
    assert 1e-6 < mesh_err < 1e-4
    assert abs(abs(d32) - exact) <= 1.5 * mesh_err + stretch
    assert abs(abs(d64) - exact) <= 1.5 * mesh_err / 4 + stretch
    # every level: near-straight below P_cr (imperfection amplified by 1/(1 - P/P_cr)),
    # on the elastica above it (looser at 1.02 P_cr, where d delta/dP is large and the
    # discrete P_cr differs from pi^2/4 by O(h^2))
    for lev, ratio in enumerate(FRACTIONS):
        expected = elastica_deflection(ratio) if ratio > 1 else 0.0
        assert abs(abs(r32.position("tip", lev)[1]) - expected) < 3e-3


def test_mirrored_imperfection_mirrors_the_answer(runs):
    a, b = runs[32, 1e-5], runs[32, -1e-5]
    assert np.allclose(a.positions[:, :, 0], b.positions[:, :, 0], atol=1e-9)
    assert np.allclose(a.positions[:, :, 1], -b.positions[:, :, 1], atol=1e-9)


def test_perfect_column_switches_to_a_buckled_branch():
    r = fem.solve(column(32, 0.0))
    assert r.converged, r.message
    assert "bifurcation" in r.message and "branch switch" in r.message
    assert [c.kind for c in r.critical_points] == ["bifurcation"]
    assert r.critical_points[0].branch_switch
    assert abs(abs(r.position("tip")[1]) - elastica_deflection(1.5)) < 2e-4
    assert np.all(np.abs(r.positions[:3, 1, 1]) < 1e-12)  # straight below P_cr


def test_without_stability_check_the_unstable_state_is_returned():
    """The check is what moves the answer: without it Newton stays near-straight."""
    r = fem.solve(column(16, 1e-5), check_stability=False)
    assert r.converged
    assert abs(r.position("tip")[1]) < 1e-3


def test_follower_cantilever_untouched():
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", 1.0, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(EA, 1.0), n_elements=8)
    m.add_support("root", "fixed")
    m.add_force("tip", 0.0, [1.0, 2.0], follower=True)
    r = fem.solve(m)
    assert r.converged and "branch" not in r.message


def _column(fraction: float) -> fem.Model:
    """A straight cantilever column of 8 elements under a compressive tip force fraction * P_cr."""
    model = fem.Model()
    model.add_node("root", 0.0, 0.0)
    model.add_node("tip", 1.0, 0.0)
    model.add_member("root", "tip", fem.Section.from_EI(EA, 1.0), n_elements=8)
    model.add_support("root", "fixed")
    model.add_force("tip", [-fraction * P_CR], [0.0])
    return model


def test_a_negative_sign_from_the_last_factorisation_is_confirmed_at_the_converged_state():
    """The sign of det K comes from Newton's last factorisation, one iterate before convergence; after
    a long step that iterate can be far from the converged state (Test 2 at 128 elements: |r|/F = 3.2,
    det K < 0 there, det K > 0 at the converged state), so a negative sign is checked by a fresh
    factorisation before it counts: a stable state is never called unstable from a stale tangent.
    A positive sign is taken as it is, and a state that is really unstable stays negative."""
    from fem import solver
    from fem.newton import newton
    from fem.options import SolveOptions

    opts = SolveOptions()
    for fraction, expected in ((0.5, 1), (1.5, -1)):  # below P_cr: stable; straight above it: unstable
        system = solver._prepare(_column(fraction), opts, None)
        q0, beta0 = np.zeros(system.n), system.disc.beta0.copy()
        out = newton(system, q0, 1.0, beta0, system.loads_at(-1, 0, 1.0), opts, q_start=q0)
        for stale in (-1, 1):  # what the last factorisation may say
            out.factor = type("Stale", (), {"det_sign": stale, "final": False})()
            sign = solver._step_state(system, opts, out, beta0).sign  # through `newton.det_sign`
            assert sign == (expected if stale < 0 else 1), (fraction, stale)


def test_a_run_converged_before_any_correction_reads_the_sign_at_its_own_state():
    """A Newton run that starts on an equilibrium (a zero-load level, or a level equal to the last)
    converges with no correction and so no factorisation; the compiled corrector then factorises the
    tangent at that state for the sign of det K, which is final (no confirmation). It is the sign of
    the straight column's tangent: positive below P_cr, negative above it, as a fresh factorisation
    of the same tangent says."""
    from fem import solver
    from fem.newton import det_sign, newton
    from fem.options import SolveOptions

    opts = SolveOptions()
    for fraction, expected in ((0.5, 1), (1.5, -1)):  # below P_cr: stable; straight above it: unstable
        system = solver._prepare(_column(fraction), opts, None)
        assert system.compiled is not None
        q0, beta0 = np.zeros(system.n), system.disc.beta0.copy()
        loads = system.loads_at(-1, 0, 1.0)
        first = newton(system, q0, 1.0, beta0, loads, opts, q_start=q0)
        assert first.iterations > 0
        loose = SolveOptions(rtol=1e-6)  # the first run's state (|r|/F ~ 1e-10) is converged for it
        again = newton(system, first.q, 1.0, first.ev["el"]["beta"].copy(), loads, loose, q_start=first.q)
        assert again.iterations == 0 and again.factor is not None and again.factor.final, fraction
        assert again.factor.det_sign == expected, fraction
        assert det_sign(system, again.ev, None) == expected, fraction  # a fresh factorisation
        assert det_sign(system, again.ev, again.factor) == expected, fraction
