"""Every method held to the quantity contract (validation/case/quantities.py) on generated configurations.

The reference is linear beam theory from the textbook unit-load method (validation/stress/linear_beam.py),
itself checked here against the closed forms of Gere & Timoshenko (Mechanics of Materials, table of
cantilever and guided-beam deflections) and a Castigliano derivation for the quarter circle:

    quarter circle, radius R, clamped at s = 0 with its tangent along +x, tip load F_y at (R, R):
    M(phi) = F_y (x_t - x) = F_y R (1 - sin phi), phi = s/R in [0, pi/2];
    theta_tip = int M ds / EI = F_y R^2/EI int_0^{pi/2} (1 - sin phi) dphi = F_y R^2 (pi/2 - 1)/EI,
    u_y = int M (x_t - x) ds / EI = F_y R^3/EI int (1 - sin phi)^2 dphi = F_y R^3 (3 pi/4 - 2)/EI.
"""

import math
import random

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from validation.stress import contract
from validation.stress.contract import (
    BOUNDARIES,
    LOADS,
    PINNED_PINNED_LOADS,
    Configuration,
    build_case,
    large_deflection_check,
    linear_limit_check,
    random_configuration,
)
from validation.stress.linear_beam import flexibility, solve_tip
from validation.methods.base import Request
from validation.run.runner import run_method
from validation.case.schema import Case

CHEAP = dict(
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


def test_linear_theory_is_the_textbook():
    L, EI, P, M = 2.0, 3.0, 0.7, 0.4
    C = flexibility(L, 0.0, EI)
    assert C[1, 1] == pytest.approx(L**3 / (3 * EI))  # P L^3/3EI
    assert C[2, 1] == pytest.approx(L**2 / (2 * EI))  # P L^2/2EI
    assert C[1, 2] == pytest.approx(L**2 / (2 * EI))  # M L^2/2EI
    assert C[2, 2] == pytest.approx(L / EI)  # M L/EI
    guided = solve_tip(L, 0.0, EI, math.inf, root_pinned=False, given_load={"uy": P}, given_motion={"rz": 0.0})
    assert guided.motion[1] == pytest.approx(P * L**3 / (12 * EI))  # guided beam P L^3/12EI
    assert guided.load[2] == pytest.approx(-P * L / 2)  # holding moment P L/2, clockwise
    pinned = solve_tip(L, 0.0, EI, 1e12, root_pinned=True, given_load={"rz": M}, given_motion={"ux": 0.0, "uy": 0.0})
    assert pinned.motion[2] == pytest.approx(M * L / (3 * EI))  # simply supported, end moment M L/3EI
    R = 2 * L / math.pi
    quarter = flexibility(L, 1 / R, EI)
    assert quarter[2, 1] == pytest.approx(R**2 * (math.pi / 2 - 1) / EI)
    assert quarter[1, 1] == pytest.approx(R**3 * (3 * math.pi / 4 - 2) / EI)


def _segment_case(boundary, loads, radius=None, outputs=("rotation", "moment", "x", "y")):
    segment = dict(boundary=boundary, length=1.0, E=1.0, section=dict(kind="inertia", I=1.0, A=1e6))
    if radius:
        segment["radius"] = radius
    return Case.model_validate(
        dict(
            case=dict(id="t", title="t", group="t", units="dimensionless"),
            segment=segment,
            loads=loads,
            outputs=[dict(quantity=q) for q in outputs],
            methods={"fem": {"elements": 16}, "elastica": {}, "prbm": {}},
        )
    )


def test_curved_rotation_is_the_change_from_the_unloaded_tangent():
    """Quarter circle (R = 2L/pi), small tip load F_y = -1e-4 EI/L^2: Castigliano (module docstring)
    gives theta = F_y R^2 (pi/2 - 1)/EI; on main the PRBM reported the absolute angle (about +90 deg)."""
    R, F = 2 / math.pi, -1e-4
    case = _segment_case("fixed-free", [dict(kind="force", direction=[0.0, 1.0], values=[F])], radius=R)
    expected = math.degrees(F * R**2 * (math.pi / 2 - 1))
    for method, rel in (("fem", 1e-3), ("elastica", 1e-3), ("prbm", 0.6)):
        value = run_method(case, method).values[Request("rotation", "tip", 0)]
        assert value == pytest.approx(expected, rel=rel), method
        assert value * expected > 0, method


def test_fixed_guided_moment_is_the_guiding_moment():
    """A guided tip reports the moment that holds its slope: -P L/2 in the small-load limit
    (Gere & Timoshenko, guided beam); at F = 5 EI/L^2 FEM and elastica agree (-2.296 EI/L), and the
    PRBM's two-spring holding moment (seed 000 eq (63)) is within 2 % of it; on main the PRBM gave 0."""
    small = _segment_case("fixed-guided", [dict(kind="force", direction=[0.0, 1.0], values=[1e-4])])
    value = run_method(small, "prbm").values[Request("moment", "tip", 0)]
    assert value == pytest.approx(-0.5e-4, rel=0.05)
    large = _segment_case("fixed-guided", [dict(kind="force", direction=[0.0, 1.0], values=[5.0])])
    exact = run_method(large, "elastica").values[Request("moment", "tip", 0)]
    assert run_method(large, "fem").values[Request("moment", "tip", 0)] == pytest.approx(exact, rel=1e-3)
    assert run_method(large, "prbm").values[Request("moment", "tip", 0)] == pytest.approx(exact, rel=0.02)


def test_prbm_follower_force_downwards_bends_downwards():
    """A follower force with P < 0 deflects the tip to -y (on main the composite model took |P|)."""
    case = _segment_case(
        "fixed-free",
        [dict(kind="force", direction=[0.0, -1.0], values=[1e-4], follower=True)],
        outputs=("y", "rotation"),
    )
    run = run_method(case, "prbm")
    assert run.values[Request("y", "tip", 0)] == pytest.approx(-1e-4 / 3, rel=0.1)


def test_fem_resolves_a_load_below_the_rounding_floor():
    """A load of 1e-12 EI/L^2 (below 4 eps EA): the FEM must still deflect by P L^3/3EI, not stop at 0."""
    case = _segment_case("fixed-free", [dict(kind="force", direction=[0.0, 1.0], values=[1e-12])], outputs=("y",))
    assert run_method(case, "fem").values[Request("y", "tip", 0)] == pytest.approx(1e-12 / 3, rel=1e-6, abs=0.0)


def _assert_conforms(results, label):
    failures = [f for r in results for f in r.failures]
    assert not failures, label + "\n" + "\n".join(failures)


def every_class(seed: int) -> list[Configuration]:
    """A small-load configuration of every boundary with every load it takes (``contract.BOUNDARIES``,
    ``LOADS``; pinned-pinned only ``PINNED_PINNED_LOADS``), straight and curved: 90 configurations, the
    rest of each (unit system, length, modulus, slenderness, curvature's sign, magnitude, angles) drawn by
    ``random_configuration`` from a generator seeded by ``seed`` and the class."""
    return [
        random_configuration(
            random.Random(f"{seed}-{boundary}-{load}-{curved}"),
            small=True,
            boundaries=(boundary,),
            loads=(load,),
            curved=curved,
        )
        for boundary in BOUNDARIES
        for load in LOADS
        if boundary != "pinned-pinned" or load in PINNED_PINNED_LOADS
        for curved in (False, True)
    ]


def test_every_method_meets_linear_theory_in_the_small_load_limit():
    """Every class of configuration once (``every_class``), not 300 drawn at random: the random draws
    (hypothesis, derandomized) met 33 of the 45 boundary-load pairs, and a planted 10 % error or rotation
    sign flip in one method on one pair was caught on 158 of the 450 (method, pair, plant) combinations
    against 270 of 450 here (and none caught there is missed here; 272 are caught by some set of
    configurations tried, the others change nothing the contract's tolerances see).
    ``prbm-validate stress --long`` draws 10,000 at random."""
    failures = []
    for c in every_class(0):
        results = linear_limit_check(c)
        failures += [f"{c.label()}: {f}" for r in results for f in r.failures]
        assert next(r for r in results if r.method == "fem").compared >= 8, c.label()  # the FEM claims every quantity
    assert not failures, "\n".join(failures)


@settings(max_examples=40, **CHEAP)
@given(st.randoms(use_true_random=False))
def test_fem_meets_the_elastica_and_the_prbm_keeps_the_conventions_at_large_deflection(rng):
    c = random_configuration(
        rng,
        small=False,
        boundaries=("fixed-free", "fixed-pinned", "fixed-guided"),
        loads=("transverse", "oblique", "moment", "force_moment", "follower", "displacement_y", "rotation"),
    )
    _assert_conforms(large_deflection_check(c), c.label())


def test_the_generator_covers_every_boundary_load_and_unit_system():
    rng = random.Random(0)
    seen = [random_configuration(rng, small=True) for _ in range(300)]
    assert {c.boundary for c in seen} == {"fixed-free", "fixed-pinned", "fixed-guided", "fixed-fixed", "pinned-pinned"}
    assert {c.load for c in seen} >= {
        "transverse",
        "oblique",
        "tension",
        "compression",
        "moment",
        "force_moment",
        "follower",
        "displacement_x",
        "displacement_y",
        "rotation",
    }
    assert {c.units for c in seen} == {"SI", "mm-N", "in-lb", "dimensionless"}
    assert any(c.kappa_L for c in seen) and any(not c.kappa_L for c in seen)


def test_a_planted_sign_error_is_caught():
    """The check fails when a method's rotation has the wrong sign (a 'method' that negates it)."""
    c = Configuration(
        boundary="fixed-free",
        units="dimensionless",
        length=1.0,
        E=1.0,
        slenderness=100.0,
        kappa_L=0.0,
        load="transverse",
        magnitude=1e-5,
    )
    case = build_case(c, ("fem",))
    assert all(r.passed for r in linear_limit_check(c, ("fem",)))
    run = run_method(case, "fem")

    flipped = {r: (-v if r.quantity == "rotation" else v) for r, v in run.values.items()}
    original = contract.run_contract_method
    try:
        contract.run_contract_method = lambda case, method: type(run)(values=flipped, error_estimate=run.error_estimate)
        assert not all(r.passed for r in linear_limit_check(c, ("fem",)))
    finally:
        contract.run_contract_method = original
    assert np.isfinite(run.values[Request("rotation", "tip", 0)])
