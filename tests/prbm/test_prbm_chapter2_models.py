"""Seed 000 chapter 2's other segment models: the Chain Algorithm (eqs 26-40), the Theta-dependent
K_Theta (eqs 51, 52) and Lyon et al.'s fixed-guided PRBM (eqs 64-70).

Expected values come from small-deflection beam theory, the exact elastica (an independent shooting
solver), the printed coefficients and Table 3.1, each named at its assertion."""

import math

import pytest

import elastica
import prbm
from prbm.chain import ChainBeam, NodalLoads, chain_from_tip, chain_tip
from prbm.fits import FitRangeError
from prbm.lyon import lyon_from_tip, lyon_tip
from prbm.theta_dependent import EQ51, EQ52, theta_dependent_tip

EI_34 = 30e6 * 1.02e-5  # section 3.4 beam: E = 30e6 psi, I = 1.02e-5 in^4, l = 20 in


# --- Chain Algorithm --------------------------------------------------------------------------------
def test_chain_linear_limit_is_the_cantilever_formula():
    # small loads: the chain of small-deflection elements is exact at the nodes for end loads
    # (piecewise cubic), so the tip is P L^3/3EI + M L^2/2EI and the slope P L^2/2EI + M L/EI
    L, EI, P, M = 2.0, 5.0, 1e-4, -3e-4
    beam = ChainBeam(L, EI, 8)
    r = chain_tip(beam, NodalLoads.at_tip(beam, 0.0, P, M), steps=1)
    assert r.converged
    assert float(r["b"]) == pytest.approx(P * L**3 / (3 * EI) + M * L**2 / (2 * EI), rel=1e-3)
    assert float(r["theta0"]) == pytest.approx(P * L**2 / (2 * EI) + M * L / EI, rel=1e-3)


def test_chain_compressive_amplification_eq_30_31():
    # one element, tiny transverse load beside an axial compression C: the element deflects
    # P L^3/(3 EI) / (1 - 4 C L^2/(pi^2 EI)) (eqs 30-32, compression amplifies); tension reduces it
    L, EI, P, C = 1.0, 1.0, 1e-6, 1.0
    alpha = 4 * C * L**2 / (math.pi**2 * EI)
    beam = ChainBeam(L, EI, 1)
    for axial, expected in ((-C, 1 / (1 - alpha)), (C, 1 / (1 + alpha))):
        r = chain_tip(beam, NodalLoads.at_tip(beam, axial, P, 0.0), steps=1)
        assert float(r["b"]) == pytest.approx(P * L**3 / (3 * EI) * expected, rel=1e-6)


def test_chain_converges_to_the_elastica_at_second_order():
    # Table 3.1's Chain-output loads (P = 6.75 lb, M = 72.54 in-lb opposing) on the section 3.4 beam
    exact = elastica.solve_elastica(20.0, EI_34, force=(0.0, 6.75), moment=-72.54)
    errors = []
    for n in (20, 40):
        beam = ChainBeam(20.0, EI_34, n)
        r = chain_tip(beam, NodalLoads.at_tip(beam, 0.0, 6.75, -72.54))
        assert r.converged
        errors.append(math.hypot(float(r["a"]) - exact.x, float(r["b"]) - exact.y))
    assert errors[1] < 0.002 * 20.0  # 40 elements: within 0.2 % of l
    assert errors[0] / errors[1] > 3.5  # halving the element length divides the error by ~4


def test_chain_table3_1_chain_row():
    # seed 000 Table 3.1, Chain Algorithm row: b = 5.2305, theta0 = -43.46 (n = 0) -> a = 18.0238,
    # P = 6.75, M = 72.54 (opposing, i.e. -72.54 CCW), 40 elements (section 3.4)
    r = chain_from_tip(ChainBeam(20.0, EI_34, 40), b=5.2305, theta0=math.radians(-43.46))
    assert r.converged
    assert float(r["P"]) == pytest.approx(6.75, abs=0.005)
    assert float(r["M"]) == pytest.approx(-72.54, abs=0.005)
    assert float(r["a"]) == pytest.approx(18.0238, abs=0.0005)


def test_chain_bad_input_names_the_field():
    with pytest.raises(ValueError, match="length"):
        ChainBeam(-1.0, 1.0)
    with pytest.raises(ValueError, match="EI"):
        ChainBeam(1.0, 0.0)


# --- Theta-dependent K_Theta ---------------------------------------------------------------------------
def test_eq51_and_eq52_values_from_the_printed_coefficients():
    # eq (51) at n = 0, Theta = 0.5 rad: (0.004233 + 2.567095/2 - 0.037173/4 + 0.117997/8) / 0.5
    assert EQ51(0.0, 0.5) == pytest.approx(
        (0.004233 + 2.567095 * 0.5 - 0.037173 * 0.25 + 0.117997 * 0.125) / 0.5, rel=1e-12
    )
    # eq (52) at n = 1, Theta = 0.5: every printed term
    p = (
        0.000651
        - 0.008244
        + 2.544577 * 0.5
        - 0.004764
        + 0.071215 * 0.25
        - 0.000104
        + 0.079696 * 0.125
        + 0.069274 * 0.5
        + 0.061507 * 0.5
        - 0.347588 * 0.25
    )
    assert EQ52(1.0, 0.5) == pytest.approx(p / 0.5, rel=1e-12)


@pytest.mark.parametrize("n, alpha2", [(0.0, 0.5), (0.0, 1.0), (0.5, 1.0), (1.0, 0.5), (1.0, 1.0)])
def test_eq51_beats_the_constant_k_at_moderate_angles(n, alpha2):
    # the seed's claim for eq (51) ("significantly reduce the relative error"), checked against the
    # exact elastica where the PRB angle is below about 30 deg
    exact = elastica.solve_elastica(1.0, 1.0, force=(-n * alpha2, alpha2))
    r51 = theta_dependent_tip(alpha2, n, length=1.0, EI=1.0, fit="51")
    r43 = prbm.fixed_pinned_tip(alpha2, n, length=1.0, EI=1.0)
    e51 = math.hypot(float(r51["a"]) - exact.x, float(r51["b"]) - exact.y)
    e43 = math.hypot(float(r43["a"]) - exact.x, float(r43["b"]) - exact.y)
    assert e51 < 0.002 and e51 < e43


@pytest.mark.parametrize("n, alpha2", [(-0.5, 1.0), (-1.0, 2.0), (-2.0, 1.0), (-1.0, 4.0)])
def test_eq52_read_for_tension_is_accurate(n, alpha2):
    exact = elastica.solve_elastica(1.0, 1.0, force=(-n * alpha2, alpha2))
    r = theta_dependent_tip(alpha2, n, length=1.0, EI=1.0, fit="52-tension")
    assert math.hypot(float(r["a"]) - exact.x, float(r["b"]) - exact.y) < 0.0025


def test_eq52_in_its_printed_range_misses_at_large_n():
    # the finding behind the tension reading: at n = 5 eq (52) puts the tip 30 % of l off the elastica
    exact = elastica.solve_elastica(1.0, 1.0, force=(-2.5, 0.5))
    r = theta_dependent_tip(0.5, 5.0, length=1.0, EI=1.0, fit="52")
    assert math.hypot(float(r["a"]) - exact.x, float(r["b"]) - exact.y) > 0.2


def test_theta_dependent_ranges():
    with pytest.raises(FitRangeError, match="load ratio"):
        theta_dependent_tip(1.0, -0.5, length=1.0, EI=1.0, fit="51")
    with pytest.raises(FitRangeError, match="PRB angle"):
        theta_dependent_tip(3.0, 1.0, length=1.0, EI=1.0, fit="51")  # Theta about 76 deg > 65 deg
    with pytest.raises(ValueError, match="fit"):
        theta_dependent_tip(1.0, 0.0, length=1.0, EI=1.0, fit="53")


# --- Lyon et al. ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("n, P", [(0.0, 5.0), (0.5, 5.0), (-1.0, 5.0)])
def test_lyon_under_an_end_force_is_howells_guided_beam(n, P):
    # end force alone: eqs (64)-(70) are solved by l_A = l_B = l/2, theta_A = theta_B, theta_E = 0,
    # which is Howell's guided beam with k = 2 gamma K_Theta EI/l (eq 63, prbm.fixed_guided_tip)
    r = lyon_tip(-n * P, P, length=1.0, EI=1.0)
    g = prbm.fixed_guided_tip(P, n, length=1.0, EI=1.0)
    assert r.converged
    assert float(r["l_A"]) == pytest.approx(0.5, abs=1e-9)
    assert float(r["theta0"]) == pytest.approx(0.0, abs=1e-9)
    assert float(r["a"]) == pytest.approx(float(g["a"]), abs=1e-9)
    assert float(r["b"]) == pytest.approx(float(g["b"]), abs=1e-9)


def test_lyon_moment_is_the_guided_beams_held_moment():
    # n = 0: the end moment of the model, -(l/2)(gamma cos Theta + 1 - gamma) P, equals the moment that
    # holds the guided end of eq (63)'s model (prbm.fixed_guided_tip's M); against the FEM and the
    # elastica: cases/chapter2/lyon_fixed_guided.toml
    r = lyon_tip(0.0, 5.0, length=1.0, EI=1.0)
    g = prbm.fixed_guided_tip(5.0, 0.0, length=1.0, EI=1.0)
    assert float(r["M"]) == pytest.approx(float(g["M"]), rel=1e-9)


def test_lyon_two_condition_problem_leaves_the_fits_on_table_3_5():
    # the finding recorded in cases/chapter2/lyon_fixed_guided.toml: with b = 12 in, theta0 = 40 deg
    # (Table 3.5's conditions) the equal-torque condition (69) needs a load ratio outside -4 < n <= 10
    with pytest.raises(FitRangeError):
        lyon_from_tip(b=12.0, theta0=math.radians(40.0), length=20.0, EI=EI_34)


@pytest.mark.parametrize("n", [0.5, -2.0])
def test_chain_inverse_recovers_the_elastica_loads(n):
    # the exact tip (b, theta0) under P = 4, nP, M = -30 (one inflection point); the Chain Algorithm's
    # inverse for that b, theta0 and n returns P and M within its 40-element discretisation error
    P, M = 4.0, -30.0
    exact = elastica.solve_elastica(20.0, EI_34, force=(-n * P, P), moment=M)
    r = chain_from_tip(ChainBeam(20.0, EI_34, 40), b=exact.y, theta0=exact.theta, n=n)
    assert r.converged
    assert float(r["P"]) == pytest.approx(P, rel=0.01)
    assert float(r["M"]) == pytest.approx(M, rel=0.01)
    assert float(r["a"]) == pytest.approx(exact.x, abs=0.002 * 20.0)


def test_chain_inverse_converges_where_the_inverse_is_ill_conditioned():
    # n = 1.5: the exact end is at theta0 = 90 deg, where the loads for given (b, theta0) are sensitive
    # (40 elements: P off by 1.2 %); the error still falls at second order with the element count
    P, M, n = 4.0, -30.0, 1.5
    exact = elastica.solve_elastica(20.0, EI_34, force=(-n * P, P), moment=M)
    err = [
        abs(float(chain_from_tip(ChainBeam(20.0, EI_34, N), b=exact.y, theta0=exact.theta, n=n)["P"]) - P)
        for N in (40, 80)
    ]
    assert err[0] / err[1] > 3.0
