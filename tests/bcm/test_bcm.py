"""Beam constraint model (seed 003): energy identities, corrected misprints, the two example mechanisms.

Numbers quoted from notes/seed-003-004.md are derived there (the seed prints results in figures
only); the identities are checked here numerically by finite differences.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from bcm import (
    C0,
    K0,
    K1,
    K2,
    axial_stiffness_parameter,
    bcm_residual,
    circular_guided_torque,
    circular_guided_torque_eq20,
    complementary_energy,
    deflections_from_complementary,
    deflections_from_loads,
    eq32_corrected,
    eq32_printed,
    exact_compliance,
    loads_from_deflections,
    slant_parallelogram,
    solve_mixed,
    strain_energy,
)
from validation.case.loader import load_case
from validation.methods import bcm as adapter
from validation.methods.base import NotApplicable, Request
from validation.case.method_options import options_of

CASES = Path(__file__).resolve().parents[2] / "cases"
KA = axial_stiffness_parameter(25.0, 0.25)  # 120000, Table 2 / Table 3 beam


def _grad(f, x, h=1e-6):
    x = np.asarray(x, float)
    g = np.zeros_like(x)
    for i in range(x.size):
        e = np.zeros_like(x)
        e[i] = h
        g[i] = (f(*(x + e)) - f(*(x - e))) / (2 * h)
    return g


STATES = [(-0.002, 0.05, 0.03), (-0.004, 0.08, -0.05), (0.0005, -0.03, 0.09)]


@pytest.mark.parametrize("ux, uy, th", STATES)
def test_castigliano_on_eq11_reproduces_eqs_3_and_10(ux, uy, th):
    """Q_i = dV/dU_i (eq (1)) on eq (11) gives f_x of eq (10) and [f_y, m_z] of eq (3)."""
    ka = 1e4
    fd = _grad(lambda a, b, c: strain_energy(a, b, c, ka), (ux, uy, th), h=1e-7)
    fx, fy, mz = loads_from_deflections(ux, uy, th, ka)
    assert np.allclose(fd, (fx, fy, mz), rtol=1e-6, atol=1e-6)
    assert np.allclose(bcm_residual(ux, uy, th, fx, fy, mz, ka), 0.0, atol=1e-12)  # eqs (3), (4)


@pytest.mark.parametrize("order", [2, 3])
@pytest.mark.parametrize("loads", [(0.5, 1.0, -0.3), (-1.0, 0.4, 0.2), (2.0, -0.7, 0.5)])
def test_crotti_engesser_on_eqs_16_17(order, loads):
    """U_i = dV*/dQ_i (eq (2)) on eq (16)/(17) equals the closed-form derivatives used for the loci."""
    fd = _grad(lambda a, b, c: complementary_energy(a, b, c, 1e4, order), loads)
    assert np.allclose(fd, deflections_from_complementary(*loads, 1e4, order), rtol=1e-7, atol=1e-9)


def test_eq17_is_the_series_of_the_corrected_eq15():
    """Corrected eq (15) ((r - tanh r)/r^3 and tanh r / r) matches eq (17) to O(f_x^4); printed (2,2) does not."""
    for fx in (0.05, -0.05, 0.1):
        p = np.array([1.0, 0.0]), np.array([0.0, 1.0])
        C_series = np.array([[deflections_from_complementary(fx, *q, 1e12, 3)[k] for q in p] for k in (1, 2)])
        assert np.allclose(exact_compliance(fx), C_series, atol=2 * abs(fx) ** 4)
    r = math.sqrt(0.1)
    printed_22 = r * r * math.cosh(r) / math.tanh(r)
    assert abs(printed_22 - exact_compliance(0.1)[1, 1]) > 0.1
    assert np.allclose(exact_compliance(0.0), C0)
    # compliance inverts the BCM stiffness at small f_x
    assert np.allclose(np.linalg.inv(exact_compliance(0.01)), K0 + 0.01 * K1 + 1e-4 * K2, rtol=1e-5)


def test_linear_limit_and_mixed_solves():
    q = np.array([0.01, 0.02])
    ux_free = -0.5 * q @ K1 @ q  # kinematic shortening: f_x = 0 (eq (4))
    fx, fy, mz = loads_from_deflections(ux_free, *q, 1e12)
    assert abs(fx) < 1e-9 and np.allclose(K0 @ q, (fy, mz), atol=1e-8)
    ux, uy, th, fx, fy, mz = solve_mixed(KA, fx=0.2, uy=0.05, theta=0.0)  # guided tip, given u_y
    assert np.allclose(bcm_residual(ux, uy, th, fx, fy, mz, KA), 0, atol=1e-10)
    assert np.allclose(deflections_from_loads(fx, fy, mz, KA), (ux, uy, th), atol=1e-12)
    # section 4.3 C5 fixed-guided forms
    assert abs(fy - (12 + 1.2 * fx - fx**2 / 700) * uy) < 1e-10
    assert abs(mz - (-6 - fx / 10 + fx**2 / 1400) * uy) < 1e-10


def test_circular_guided_eq20_equals_castigliano():
    R = 21.8 / 25.0
    for beta in (0.01, 0.05, 0.1):
        assert abs(circular_guided_torque_eq20(beta, R, KA) - circular_guided_torque(beta, R, KA)) < 1e-12
    # T = dv/dbeta, checked by a finite difference of eq (11) along eq (18)
    v = lambda b: strain_energy(R * (math.cos(b) - 1), R * math.sin(b), b, KA)  # noqa: E731
    assert abs((v(0.1 + 1e-6) - v(0.1 - 1e-6)) / 2e-6 - circular_guided_torque(0.1, R, KA)) < 1e-7
    assert abs(circular_guided_torque(0.1, R, KA) - 0.26368) < 5e-6  # notes 2.1 table, T_BCM normalised


def test_eq32_corrected_is_the_gradient_of_eq30_and_printed_is_not():
    ux, uy = -1.5e-4, 0.04
    v = lambda a, b: strain_energy(a, b, 0.0, KA)  # eq (30) = eq (11) with theta_z = 0  # noqa: E731
    fd = _grad(v, (ux, uy), h=1e-9)
    assert np.allclose(eq32_corrected(ux, uy, KA), fd, rtol=1e-5)
    assert not np.allclose(eq32_printed(ux, uy, KA), fd, rtol=1e-2)


def test_slant_parallelogram_loci_agree():
    """CE eq (16), CE eq (17) and Castigliano (corrected eq (32)) agree within 2e-4 mm (notes 4.4 item 8);
    the printed eq (32) gives dY = -0.365 mm at F_h = 0 instead of +0.0328 mm."""
    for F_h in (0.0, 0.5, 1.0):
        r2, r3, rc = (slant_parallelogram(F_h, method=m) for m in ("CE2", "CE3", "castigliano"))
        assert abs(r3.dY - rc.dY) < 1e-5 and abs(r3.dX - rc.dX) < 2e-5
        assert abs(r2.dY - r3.dY) < 2e-4 and abs(r2.dX - r3.dX) < 2e-4
    assert abs(slant_parallelogram(1.0, method="CE3").dY - 1.35442) < 1e-5
    assert abs(slant_parallelogram(0.0, method="castigliano").dY - 0.03282) < 1e-5
    assert abs(slant_parallelogram(0.0, method="castigliano-printed").dY - (-0.36521)) < 1e-5
    # eq (25): m_z1 closed form
    r = slant_parallelogram(0.4, method="CE2")
    assert abs(r.mz1 - (61 * r.fx1**2 - 150 * r.fx1 + 360) / (-96 * r.fx1**2 + 240 * r.fx1 - 720) * r.fy1) < 1e-12


@pytest.mark.parametrize("name", ["circular_guided", "slant_parallelogram"])
def test_bcm_adapter_meets_case_references(name):
    case = load_case(CASES / "seed003" / f"{name}.toml").case
    refs = [r for r in case.references if r.compare == "bcm"]
    run = adapter.run(
        case, [Request(r.quantity, r.point, r.level) for r in refs], options_of("bcm", case.methods["bcm"])
    )
    assert run.converged and not run.extras["outside_range"]
    for r in refs:
        tol = r.tolerance.abs if r.tolerance.abs is not None else r.tolerance.rel * abs(r.value)
        assert abs(run.values[Request(r.quantity, r.point, r.level)] - r.value) <= tol, r


def test_bcm_adapter_segment_and_range_flag():
    case = load_case(CASES / "benchmarks" / "cantilever_tip_load.toml").case
    reqs = [Request("y", "tip", 0), Request("strain_energy", "tip", 0)]
    run = adapter.run(case, reqs, options_of("bcm", {}))
    assert run.extras["outside_range"] == [0]  # PL^2/EI = 1 is far beyond u_y <= 0.1
    assert abs(run.values[reqs[0]] - 1 / 3) < 1e-3  # BCM is linear in f_y at f_x = 0
    with pytest.raises(NotApplicable):
        adapter.run(
            load_case(CASES / "benchmarks" / "arch_215_clamped_hinged.toml").case,
            [Request("force_y", "crown", 0)],
            options_of("bcm", {}),
        )
