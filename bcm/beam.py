"""Beam constraint model (BCM) of a uniform tip-loaded beam, with its strain and complementary energies.

Source: [chen2021, §2-3] (Chen, Ma, Bai, Zhu, Magleby, Howell, "An energy-based framework for
nonlinear kinetostatic modeling of compliant mechanisms utilizing beam flexures"), and
notes/seed-003-004.md section 1. Everything is normalised (eq (5)):

    f_x = F_x L^2/EI (tension positive), f_y = F_y L^2/EI, m_z = M_z L/EI,
    u_x = dX/L, u_y = dY/L, theta_z (rad), energies v = V L/EI, k_a = A L^2/I (= 12 L^2/T^2).

Load-displacement relations (eqs (3), (4)), with K^(j) of Table 1 (Awtar et al.):

    [f_y, m_z] = (K0 + f_x K1 + f_x^2 K2) [u_y, theta_z]
    u_x = f_x/k_a - S1/2 - f_x S2,        S_j = [u_y theta_z] K_j [u_y theta_z]^T   (eqs (7), (9)).

Strain energy in deflections (eq (11)), for Castigliano's first theorem Q_i = dV/dU_i (eq (1)):

    v = k_a (2 u_x + S1)^2 / (8 (1 - k_a S2)) + S0/2.

Complementary energy in loads (eqs (16), (17)), for Crotti-Engesser U_i = dV*/dQ_i (eq (2)):

    v* = f_x^2/(2 k_a) + p C0 p/2 - f_x p C1 p/2 + f_x^2 p C2 p/2 [- f_x^3 p C3 p/2],  p = [f_y, m_z].

Eq (15), the exact compliance behind C0..C3, is misprinted in the paper: its (1,1) entry reads
(r - tanh k)/r^3 and its (2,2) entry r^2 cosh r / tanh r; the corrected entries (notes/seed-003-004.md
section 1.6, verified by the series of eqs (16), (17)) are (r - tanh r)/r^3 and tanh r / r, r = sqrt(f_x),
implemented in ``exact_compliance`` (with the compressive form for f_x < 0).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import fsolve
from argcheck import checked

__all__ = [
    "K0",
    "K1",
    "K2",
    "C0",
    "C1",
    "C2",
    "C3",
    "quadratic_forms",
    "strain_energy",
    "loads_from_deflections",
    "bcm_residual",
    "deflections_from_loads",
    "complementary_energy",
    "deflections_from_complementary",
    "exact_compliance",
    "solve_mixed",
    "axial_stiffness_parameter",
]

Matrix = NDArray[np.float64]
Vector = NDArray[np.float64]
Six = tuple[float, float, float, float, float, float]  # (u_x, u_y, theta_z, f_x, f_y, m_z)

# Table 1 of [chen2021] (beam characteristic coefficients, after Awtar et al. 2007)
K0 = np.array([[12.0, -6.0], [-6.0, 4.0]])
K1 = np.array([[6.0 / 5.0, -1.0 / 10.0], [-1.0 / 10.0, 2.0 / 15.0]])
K2 = np.array([[-1.0 / 700.0, 1.0 / 1400.0], [1.0 / 1400.0, -11.0 / 6300.0]])

# eqs (16), (17)
C0 = np.array([[1.0 / 3.0, 1.0 / 2.0], [1.0 / 2.0, 1.0]])
C1 = np.array([[2.0 / 15.0, 5.0 / 24.0], [5.0 / 24.0, 1.0 / 3.0]])
C2 = np.array([[17.0 / 315.0, 61.0 / 720.0], [61.0 / 720.0, 2.0 / 15.0]])
C3 = np.array([[62.0 / 2835.0, 277.0 / 8064.0], [277.0 / 8064.0, 17.0 / 315.0]])


def axial_stiffness_parameter(length: float, thickness: float) -> float:
    """k_a = 12 L^2 / T^2 of a rectangular beam [chen2021, after eq 4]."""
    return 12.0 * length**2 / thickness**2


def quadratic_forms(uy: float, theta: float) -> tuple[float, float, float]:
    """S0, S1, S2 of eq (7)."""
    q = np.array([uy, theta])
    S0: float = q @ K0 @ q
    S1: float = q @ K1 @ q
    S2: float = q @ K2 @ q
    return S0, S1, S2


@checked(positive=("ka",), finite=("ux", "uy", "theta"))
def strain_energy(ux: float, uy: float, theta: float, ka: float) -> float:
    """v(u_x, u_y, theta_z) of eq (11), in EI/L."""
    S0, S1, S2 = quadratic_forms(uy, theta)
    return ka * (2.0 * ux + S1) ** 2 / (8.0 * (1.0 - ka * S2)) + 0.5 * S0


@checked(positive=("ka",), finite=("ux", "uy", "theta"))
def loads_from_deflections(ux: float, uy: float, theta: float, ka: float) -> tuple[float, float, float]:
    """Castigliano's first theorem on eq (11): (f_x, f_y, m_z) = grad v.

    f_x = k_a (2 u_x + S1) / (2 (1 - k_a S2)) is eq (10); then [f_y, m_z] follow as eq (3), which is
    exactly d v/d(u_y, theta_z) (notes/seed-003-004.md section 1.5; tested by finite differences).
    """
    S0, S1, S2 = quadratic_forms(uy, theta)
    fx = ka * (2.0 * ux + S1) / (2.0 * (1.0 - ka * S2))
    fy: float
    mz: float
    fy, mz = (K0 + fx * K1 + fx * fx * K2) @ np.array([uy, theta])
    return fx, fy, mz


def bcm_residual(ux: float, uy: float, theta: float, fx: float, fy: float, mz: float, ka: float) -> Vector:
    """Residual of eqs (3) and (4): zero on the BCM load-displacement relation."""
    q = np.array([uy, theta])
    r12 = (K0 + fx * K1 + fx * fx * K2) @ q - np.array([fy, mz])
    _, S1, S2 = quadratic_forms(uy, theta)
    return np.array([r12[0], r12[1], fx / ka - 0.5 * S1 - fx * S2 - ux])


@checked(positive=("ka",), finite=("fx", "fy", "mz"))
def deflections_from_loads(fx: float, fy: float, mz: float, ka: float) -> tuple[float, float, float]:
    """Eqs (3), (4) solved for the deflections: linear in (u_y, theta_z) once f_x is known."""
    uy: float
    theta: float
    uy, theta = np.linalg.solve(K0 + fx * K1 + fx * fx * K2, [fy, mz])
    _, S1, S2 = quadratic_forms(uy, theta)
    return fx / ka - 0.5 * S1 - fx * S2, uy, theta


@checked(positive=("ka",), finite=("fx", "fy", "mz"))
def complementary_energy(fx: float, fy: float, mz: float, ka: float, order: int = 3) -> float:
    """v*(f_x, f_y, m_z): eq (16) (order 2) or eq (17) (order 3), in EI/L."""
    p = np.array([fy, mz])
    v: float = fx * fx / (2.0 * ka) + 0.5 * p @ C0 @ p - 0.5 * fx * p @ C1 @ p + 0.5 * fx**2 * p @ C2 @ p
    if order == 3:
        v -= 0.5 * fx**3 * p @ C3 @ p
    return v


@checked(positive=("ka",), finite=("fx", "fy", "mz"))
def deflections_from_complementary(
    fx: float, fy: float, mz: float, ka: float, order: int = 3
) -> tuple[float, float, float]:
    """Crotti-Engesser on eq (16)/(17): (u_x, u_y, theta_z) = grad v* (closed-form derivatives)."""
    p = np.array([fy, mz])
    C = C0 - fx * C1 + fx**2 * C2
    dC = -C1 + 2.0 * fx * C2
    if order == 3:
        C = C - fx**3 * C3
        dC = dC - 3.0 * fx**2 * C3
    uy: float
    theta: float
    uy, theta = C @ p
    ux: float = fx / ka + 0.5 * p @ dC @ p
    return ux, uy, theta


def exact_compliance(fx: float) -> Matrix:
    """Corrected eq (15): [u_y, theta] = C(f_x) [f_y, m_z] for the linearised-curvature beam.

    Tension (f_x > 0, r = sqrt(f_x)): c11 = (r - tanh r)/r^3, c12 = (cosh r - 1)/(r^2 cosh r),
    c22 = tanh r / r. Compression (s = sqrt(-f_x)): c11 = (tan s - s)/s^3,
    c12 = (1 - cos s)/(s^2 cos s), c22 = tan s / s. f_x -> 0 gives C0.
    """
    if abs(fx) < 1e-6:
        return C0 - fx * C1
    if fx > 0:
        r = math.sqrt(fx)
        c11 = (r - math.tanh(r)) / r**3
        c12 = (math.cosh(r) - 1.0) / (r * r * math.cosh(r))
        c22 = math.tanh(r) / r
    else:
        s = math.sqrt(-fx)
        c11 = (math.tan(s) - s) / s**3
        c12 = (1.0 - math.cos(s)) / (s * s * math.cos(s))
        c22 = math.tan(s) / s
    return np.array([[c11, c12], [c12, c22]])


@checked(positive=("ka",), finite=("ux", "uy", "theta", "fx", "fy", "mz"))
def solve_mixed(
    ka: float,
    *,
    ux: float | None = None,
    uy: float | None = None,
    theta: float | None = None,
    fx: float | None = None,
    fy: float | None = None,
    mz: float | None = None,
) -> Six:
    """BCM with one quantity of each conjugate pair (u_x|f_x, u_y|f_y, theta|m_z) given.

    Returns (u_x, u_y, theta, f_x, f_y, m_z) satisfying eqs (3), (4). Pure load or pure
    displacement specifications use the closed forms; mixed ones a Newton solve (fsolve).
    """
    pairs = [(ux, fx), (uy, fy), (theta, mz)]
    if any((d is None) == (f is None) for d, f in pairs):
        raise ValueError("give exactly one of each pair (ux|fx, uy|fy, theta|mz)")
    if ux is None and uy is None and theta is None:
        assert fx is not None and fy is not None and mz is not None  # one of each pair (above)
        return (*deflections_from_loads(fx, fy, mz, ka), fx, fy, mz)
    if fx is None and fy is None and mz is None:
        assert ux is not None and uy is not None and theta is not None
        return (ux, uy, theta, *loads_from_deflections(ux, uy, theta, ka))

    def unpack(z: Vector) -> Six:
        vals = iter(z)
        d = [d if d is not None else next(vals) for d, _ in pairs]
        f = [f if f is not None else next(vals) for _, f in pairs]
        return d[0], d[1], d[2], f[0], f[1], f[2]

    def res(z: Vector) -> Vector:
        return bcm_residual(*unpack(z), ka)

    z: Vector
    z, info, ok, msg = fsolve(res, np.zeros(3), full_output=True, xtol=1e-13)
    given = max((abs(v) for pair in pairs for v in pair if v is not None), default=0.0)
    # fsolve's progress test can stall at a solution already exact to rounding (small loads): judge by the residual
    if ok != 1 and not np.max(np.abs(res(z))) <= 1e-12 * max(given, 1e-300):
        raise RuntimeError(f"BCM mixed solve failed: {msg}")
    return unpack(z)
