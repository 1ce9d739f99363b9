"""The exact Case 2c inverse problem (Bapat 2015, Table 3.6): b, theta0 and the inflection location l1 given.

Unknown end loads (Fx, Fy, M) = (-nP, P, -M_seed) such that y(l) = b, theta(l) = theta0 and the
bending moment vanishes at s = l1. Checks, none of which uses the moment-constraint code:
  * a forward (load-specified) shooting solve under the exact loads returns b, theta0, and
    m(l1) = 0 both as the integrated moment and from equilibrium of the shape,
    m(s) = M + Fy (x_L - x(s)) - Fx (y_L - y(s))  (CCW M, global F);
  * the corrected Kimball-Tsai elliptic formulas (section 2.1.4) return b and theta0;
  * two forward cantilevers joined at l1 (the first loaded by F alone, i.e. zero moment at its
    tip) give the same tip, and the second one's root moment is zero.
Beam: l = 20 in, E = 30e6 psi, I = w h^3/12 = 1.0172526e-5 in^4 (the I of the seed's exact columns).
Printed PRBM loads: seed file 000_0cc428dae4265b0a.txt, Table 3.6, column "PRBM method"
(Ex. 3 prints P = 5.41, a misprint for 9.41; notes seed-ch2-4 section 5.6).
"""

from __future__ import annotations

import math
from validation.case.method_options import options_of
from pathlib import Path

import numpy as np
import pytest

from scipy.optimize import brentq

from elastica import (
    ElasticaProblem,
    MomentConstraint,
    TipConstraint,
    fixed_guided_inflection_from_angle,
    fixed_guided_inflection_tips,
    loaded_start,
    section_moment,
    solve_elastica,
    solve_path,
)

E, L = 30e6, 20.0
I_WH = 0.5 * 0.0625**3 / 12.0  # 1.0172526e-5 in^4
EI = E * I_WH
CASE = Path(__file__).resolve().parents[2] / "cases" / "chapter3" / "table3_6_exact_inverse.toml"

# example: (b in, theta0 deg, l1 in, printed PRBM (nP, P, M)); Ex. 3 with P = 9.41 (misprint 5.41)
TABLE_3_6 = {
    "Ex1": (12.0, 40.0, 13.5, (-1.972, 5.565, 15.905)),
    "Ex2": (5.0, -30.0, 8.5, (-1.985, 5.95, 60.175)),
    "Ex3": (5.0, -30.0, 9.0, (-11.995, 9.41, 74.098)),
}


def _seed_loads(nP, P, M):
    return (-nP, P), -M


def _exact(example, start_from_prbm=True):
    b, th, l1, prbm = TABLE_3_6[example]
    res = solve_elastica(
        L,
        EI,
        tip_y=b,
        tip_angle=math.radians(th),
        inflection_at=l1,
        start_loads=_seed_loads(*prbm) if start_from_prbm else None,
    )
    assert res.converged, res.message
    return res


@pytest.fixture(scope="module")
def exact():
    return {ex: _exact(ex) for ex in TABLE_3_6}


@pytest.mark.parametrize("example", sorted(TABLE_3_6))
def test_forward_solve_reproduces_b_theta0_and_zero_moment(exact, example):
    b, th, l1, _ = TABLE_3_6[example]
    inv = exact[example]
    # 2 s samples of the 20 in beam hit every l1 of the table (13.5, 8.5, 9.0)
    fwd = solve_elastica(L, EI, force=inv.force, moment=inv.moment, n_samples=41)
    assert fwd.converged
    assert abs(fwd.y - b) < 1e-9 and abs(fwd.theta - math.radians(th)) < 1e-9
    assert abs(fwd.x - inv.x) < 1e-9
    assert abs(section_moment(fwd, l1)) < 1e-9
    # the same zero from equilibrium of the shape outboard of l1 (CCW M, global F)
    k = int(np.argmin(abs(fwd.s - l1)))
    assert abs(fwd.s[k] - l1) < 1e-12
    (Fx, Fy), M = fwd.force, fwd.moment
    lever_x, lever_y = fwd.x - fwd.shape[0, k], fwd.y - fwd.shape[1, k]
    assert abs(M + Fy * lever_x - Fx * lever_y) < 1e-8
    # the brief's form M_end + Fx dy - Fy dx vanishes with the seed's clockwise M_seed = -M only
    assert abs(-M + Fx * lever_y - Fy * lever_x) < 1e-8
    assert abs(M + Fx * lever_y - Fy * lever_x) > 1.0


@pytest.mark.parametrize("example", sorted(TABLE_3_6))
def test_kimball_tsai_under_the_exact_loads(exact, example):
    """theta0 solves alpha(theta0) = sqrt(P l^2/EI) of the elliptic form; bracketed locally,
    because Ex. 3's root lies 7e-4 rad from the edge of the formula's domain (modulus k -> 1),
    where alpha is steep and the sampling of ``fixed_guided_inflection_tips`` misses it."""
    b, th, _, _ = TABLE_3_6[example]
    inv = exact[example]
    nP, P, M_seed = -inv.force[0], inv.force[1], -inv.moment
    assert P > 0 and M_seed > 0  # the opposing-moment (inflection) case
    n, load = nP / P, P * L * L / EI
    kappa = (M_seed * L / EI) ** 2 / (2.0 * load)

    def residual(theta0):
        return fixed_guided_inflection_from_angle(theta0, n, kappa).alpha - math.sqrt(load)

    th_rad = math.radians(th)
    root = brentq(residual, th_rad - 1e-4, th_rad + 1e-4, xtol=1e-15)
    tip = fixed_guided_inflection_from_angle(root, n, kappa)
    assert abs(root - th_rad) < 1e-9
    assert abs(tip.b * L - b) < 1e-8 and abs(tip.a * L - inv.x) < 1e-8
    if example != "Ex3":  # the library's sampled root finder agrees
        tips = fixed_guided_inflection_tips(load, n, M_seed * L / EI)
        assert any(abs(t.theta0 - root) < 1e-9 for t in tips)


@pytest.mark.parametrize("example", sorted(TABLE_3_6))
def test_two_cantilevers_joined_at_the_inflection(exact, example):
    """[0, l1] under F with no end moment, then [l1, l] clamped to its tip under F and M."""
    b, th, l1, _ = TABLE_3_6[example]
    inv = exact[example]
    F = np.array(inv.force)
    first = solve_elastica(l1, EI, force=tuple(F))
    c, s = math.cos(first.theta), math.sin(first.theta)
    local_F = (c * F[0] + s * F[1], -s * F[0] + c * F[1])
    second = solve_elastica(L - l1, EI, force=local_F, moment=inv.moment)
    assert first.converged and second.converged
    assert abs(second.reaction[2]) < 1e-8  # root moment of the outboard part: m(l1) = 0
    x = first.x + c * second.x - s * second.y
    y = first.y + s * second.x + c * second.y
    assert abs(x - inv.x) < 1e-9 and abs(y - b) < 1e-9
    assert abs(first.theta + second.theta - math.radians(th)) < 1e-9


@pytest.mark.parametrize("example", sorted(TABLE_3_6))
def test_start_from_prbm_loads_or_from_the_problem_without_inflection(exact, example):
    """Both continuation starts end on the same solution (the problem is ill-conditioned in
    nP, so the agreement is ~1e-9 relative, not 1e-12)."""
    other = _exact(example, start_from_prbm=False)
    inv = exact[example]
    assert np.allclose(other.force, inv.force, rtol=1e-8, atol=1e-8)
    assert abs(other.moment - inv.moment) < 1e-8 * abs(inv.moment)


@pytest.mark.parametrize("example", sorted(TABLE_3_6))
def test_prbm_loads_are_exact_for_their_own_inflection_location(example):
    """Round trip from a forward solve: the PRBM loads put the exact inflection near, not at, the
    specified l1; the inverse with that location (and the b, theta0 they reach) returns them."""
    b, th, l1, prbm = TABLE_3_6[example]
    force, moment = _seed_loads(*prbm)
    fwd = solve_elastica(L, EI, force=force, moment=moment)
    l1_fwd = brentq(lambda s: section_moment(fwd, s), l1 - 1.0, l1 + 1.0, xtol=1e-13)
    assert abs(l1_fwd - l1) > 0.01  # not at l1: the printed loads are the PRBM's, not exact
    inv = solve_elastica(L, EI, tip_y=fwd.y, tip_angle=fwd.theta, inflection_at=l1_fwd, start_loads=(force, moment))
    assert inv.converged
    assert np.allclose(inv.force, force, atol=1e-7) and abs(inv.moment - moment) < 1e-7


@pytest.mark.parametrize("example", ["Ex1", "Ex2"])
def test_printed_prbm_loads_against_the_exact_loads(exact, example):
    """A finding, not a tolerance: the PRBM loads of Table 3.6 Ex. 1 and 2 are not the exact loads
    for the specified l1 (the exact ones are verified above by independent forward solves): each of
    nP, P, M differs from the printed value by more than 5 % of it, far beyond the printed digits
    (3 decimals), while the load directions agree."""
    _, _, _, (nP, P, M) = TABLE_3_6[example]
    inv = exact[example]
    nP_exact, P_exact, M_exact = -inv.force[0], inv.force[1], -inv.moment
    for exact_value, printed in ((nP_exact, nP), (P_exact, P), (M_exact, M)):
        assert abs(exact_value - printed) > 0.05 * abs(printed)
    assert nP_exact < 0 and P_exact > 0 and M_exact > 0  # same load directions as the PRBM


def test_inflection_sensitivity():
    """The loads depend steeply on l1: moving l1 of Ex. 1 by 0.2 in either way changes the sign of
    the axial load nP. Each solution is checked independently: a forward solve under its loads
    returns b and theta0 and a zero moment at its l1."""
    b, th, l1, prbm = TABLE_3_6["Ex1"]
    nPs = []
    for l in (l1 - 0.2, l1 + 0.2):
        res = solve_elastica(
            L, EI, tip_y=b, tip_angle=math.radians(th), inflection_at=l, start_loads=_seed_loads(*prbm)
        )
        assert res.converged
        fwd = solve_elastica(L, EI, force=res.force, moment=res.moment)
        assert abs(fwd.y - b) < 1e-8 and abs(fwd.theta - math.radians(th)) < 1e-8
        assert abs(section_moment(fwd, l)) < 1e-7
        nPs.append(-res.force[0])
    assert nPs[0] * nPs[1] < 0


def test_moment_constraint_api_and_loaded_start():
    """The same problem built by hand; the start state carries the structure of the target."""
    b, th, l1, prbm = TABLE_3_6["Ex2"]
    problem = ElasticaProblem(
        length=L,
        EI=EI,
        constraints=(TipConstraint((0.0, 1.0), b),),
        tip_angle=math.radians(th),
        moment_constraints=(MomentConstraint(l1),),
    )
    start = loaded_start(problem, *_seed_loads(*prbm))
    # Table 3.6 Ex. 2, elliptic-integral theta0 = -29.81 deg under the PRBM loads, computed with I = w h^3/12
    # (this file's EI): the loaded start is the forward solution under those loads, to the printed digits
    assert start.converged and start.problem.tip_angle == pytest.approx(math.radians(-29.81), abs=math.radians(0.005))
    assert start.problem.moment_constraints[0].value != 0.0
    res = solve_path(problem, start=start)
    ref = _exact("Ex2")
    assert res.converged and np.allclose(res.force, ref.force, atol=1e-8)
    with pytest.raises(ValueError):
        solve_path(ElasticaProblem(moment_constraints=(MomentConstraint(2.0),)))


def test_adapter_on_the_case_file(exact):
    from validation.case.loader import load_case
    from validation.methods import elastica as adapter
    from validation.methods.base import NotApplicable, Request

    case = load_case(CASE).case
    reqs = [Request(q, "tip", lv) for lv in range(3) for q in ("force_x", "force_y", "moment", "x")]
    run = adapter.run(case, reqs, options_of("elastica", case.methods["elastica"]))
    assert run.converged, run.message
    for lv, ex in enumerate(sorted(TABLE_3_6)):
        inv = exact[ex]
        got = [run.values[Request(q, "tip", lv)] for q in ("force_x", "force_y", "moment", "x")]
        assert np.allclose(got, [*inv.force, inv.moment, inv.x], rtol=1e-8, atol=1e-8)
    options = {k: v for k, v in case.methods["elastica"].items() if k != "l1"}
    with pytest.raises(NotApplicable):
        adapter.run(case, reqs, options_of("elastica", options))
