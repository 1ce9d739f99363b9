"""Elliptic-integral solutions (elastica.elliptic) against the cantilever table and the shooting solver.

The cantilever table is read from cases/benchmarks/cantilever_tip_load.toml (notes/anchors.md 2.1).
The other checks compare each closed form with the independent shooting solution of the same
problem, plus the check values of notes/seed-ch2-4.md sections 2.1-2.4 (computed there by shooting).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from elastica import solve_elastica
from elastica.elliptic import (
    cantilever_tip_load,
    curved_fixed_pinned_tip,
    fixed_guided_inflection_tips,
    fixed_guided_monotonic_tip,
    fixed_pinned_from_angle,
    fixed_pinned_tip,
    pure_moment_tip,
    slfp_tip,
)
from validation.case.loader import load_case

CASES = Path(__file__).resolve().parents[2] / "cases"


def cantilever_references():
    case = load_case(CASES / "benchmarks" / "cantilever_tip_load.toml").case
    loads = case.loads[0].levels()
    refs = {}
    for r in case.references:
        if r.compare == "elastica":
            refs.setdefault(r.level, {})[r.quantity] = (r.value, r.tolerance.abs)
    return [(loads[level], refs[level]) for level in sorted(refs)]


@pytest.mark.parametrize("alpha, refs", cantilever_references())
def test_cantilever_table_elliptic(alpha, refs):
    tip = cantilever_tip_load(alpha)
    got = {"x": tip.a, "y": tip.b, "rotation": math.degrees(tip.theta0)}
    assert set(refs) == {"x", "y", "rotation"}
    for q, (value, tol) in refs.items():
        assert abs(got[q] - value) <= tol, (q, got[q], value)
    # 6 digits: x, y to 5e-7 (the table is rounded to 6 decimals)
    assert abs(tip.b - refs["y"][0]) <= 5.01e-7 and abs(tip.a - refs["x"][0]) <= 5.01e-7


@pytest.mark.parametrize("alpha, refs", cantilever_references())
def test_cantilever_table_shooting(alpha, refs):
    res = solve_elastica(force=(0.0, alpha))
    assert res.converged
    assert abs(res.y - refs["y"][0]) <= 5.01e-7 and abs(res.x - refs["x"][0]) <= 5.01e-7
    assert abs(math.degrees(res.theta) - refs["rotation"][0]) <= 1e-4
    tip = cantilever_tip_load(alpha)  # the two exact methods agree far beyond the table
    assert abs(res.x - tip.a) < 1e-9 and abs(res.y - tip.b) < 1e-9 and abs(res.theta - tip.theta0) < 1e-9


@pytest.mark.parametrize(
    "n, theta_deg, alpha, a, b",
    [
        (1.0, 50.0, 1.12027, 0.807717, 0.530207),  # notes/seed-ch2-4.md section 2.2 check table
        (-1.0, 20.0, 1.02445, 0.966808, 0.234106),
        (3.0, 20.0, 0.62174, 0.968563, 0.225440),
    ],
)
def test_fixed_pinned_with_load_ratio(n, theta_deg, alpha, a, b):
    tip = fixed_pinned_from_angle(math.radians(theta_deg), n)
    assert abs(tip.alpha - alpha) < 5e-6 and abs(tip.a - a) < 5e-7 and abs(tip.b - b) < 5e-7
    res = solve_elastica(force=(-n * tip.alpha**2, tip.alpha**2))
    assert abs(res.x - tip.a) < 1e-9 and abs(res.y - tip.b) < 1e-9
    assert abs(res.theta - tip.theta0) < 1e-9
    back = fixed_pinned_tip(tip.alpha**2, n)  # the load-given form finds the same angle
    assert abs(back.theta0 - tip.theta0) < 1e-10


def test_printed_gamma_of_eq_6_fails():
    """Seed eq (6) prints gamma = asin sqrt((eta + n)/(eta + lambda)): its argument exceeds 1 for n > 0."""
    n, th = 1.0, math.radians(50.0)
    eta, lam = math.hypot(1, n), math.sin(th) - n * math.cos(th)
    assert (eta + n) / (eta + lam) > 1.0
    assert 0.0 < (eta - n) / (eta + lam) < 1.0


@pytest.mark.parametrize(
    "P, n, kappa0, a_check",
    [
        (2.0, 1.0, 0.5, 0.444085),  # case A; notes section 2.3: eq (9) needs eta^(5/2) (0.528109 with eta^2)
        (2.0, -1.0, 0.5, 0.874648),  # case B
        (0.5, 0.0, 1.0, None),
        (5.0, 0.3, 0.8, None),
    ],
)
def test_curved_fixed_pinned(P, n, kappa0, a_check):
    tip = curved_fixed_pinned_tip(P, n, kappa0)
    res = solve_elastica(curvature=kappa0, force=(-n * P, P))
    assert abs(res.x - tip.a) < 1e-9 and abs(res.y - tip.b) < 1e-9 and abs(res.theta - tip.theta0) < 1e-9
    if a_check is not None:
        assert abs(tip.a - a_check) < 5e-7


@pytest.mark.parametrize(
    "P, n, M, theta_deg, a, b",
    [
        (4.0, 0.0, 2.0, -5.018, 0.954164, 0.264122),  # notes/seed-ch2-4.md section 2.4 check table
        (4.0, 0.5, 2.0, 12.163, 0.875532, 0.450534),
        (4.0, -1.0, 2.5, -28.178, 0.981906, 0.048262),
        (10.0, -3.0, 4.0, -23.379, 0.979162, 0.134008),
        (3.0, 1.0, 1.2, 50.010, 0.676778, 0.676636),
    ],
)
def test_fixed_guided_inflection_corrected_kimball_tsai(P, n, M, theta_deg, a, b):
    tip = fixed_guided_inflection_tips(P, n, M)[0]
    assert abs(math.degrees(tip.theta0) - theta_deg) < 5e-4
    assert abs(tip.a - a) < 5e-7 and abs(tip.b - b) < 5e-7
    res = solve_elastica(force=(-n * P, P), moment=-M)  # opposing (clockwise) moment
    assert abs(res.x - tip.a) < 1e-9 and abs(res.y - tip.b) < 1e-9 and abs(res.theta - tip.theta0) < 1e-9


def test_fixed_guided_monotonic_and_curved_fixed_fixed():
    tip = fixed_guided_monotonic_tip(2.0, 0.5, 1.0)
    res = solve_elastica(force=(-1.0, 2.0), moment=1.0)
    assert abs(res.x - tip.a) < 1e-9 and abs(res.y - tip.b) < 1e-9
    tip = fixed_guided_monotonic_tip(2.0, 0.5, 0.4, initial_curvature=0.6)  # eq (17): kappa0 = Ml/EI + l/R
    res = solve_elastica(curvature=0.6, force=(-1.0, 2.0), moment=0.4)
    assert abs(res.x - tip.a) < 1e-9 and abs(res.y - tip.b) < 1e-9


def test_small_length_flexural_pivot():
    """SLFP of flexible length 1 with a rigid segment L = 4: the flexible part carries the force and
    the moment F L sin(phi - theta0) of the lever (section 2.1.6 with L, not l, as the lever)."""
    P, n, Lr = 0.5, 0.0, 4.0
    tip = slfp_tip(P, n, Lr)
    moment = P * Lr * math.sin(math.pi / 2 - tip.theta0)
    res = solve_elastica(force=(0.0, P), moment=moment)
    assert abs(res.theta - tip.theta0) < 1e-9
    assert abs(res.x + Lr * math.cos(res.theta) - tip.a) < 1e-9
    assert abs(res.y + Lr * math.sin(res.theta) - tip.b) < 1e-9


def test_pure_moment_closed_form():
    for m in (0.5, math.pi, 2 * math.pi):
        tip = pure_moment_tip(m)
        res = solve_elastica(moment=m)
        assert abs(res.x - tip.a) < 1e-10 and abs(res.y - tip.b) < 1e-10 and abs(res.theta - m) < 1e-10
