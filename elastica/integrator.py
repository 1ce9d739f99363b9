"""Compiled (numba, ``cache=True``) right-hand sides of the elastica and the DOP853 integrator that
shooting calls once per Newton iteration.

``elastica_rhs`` is the one place the single-beam equations are written (normalised by L and EI;
`shooting` explains them), with the variational equations of the state w.r.t. (m(0), Fx, Fy) and the
uniform distributed load (wx, wy), whose outboard resultant adds to the force carried across the
section, N(s) = F + w (1 - s):

    x' = cos(theta),  y' = sin(theta),  theta' = kappa0 + m,  m' = Nx sin(theta) - Ny cos(theta),
    U' = m^2/2,
    (dx)' = -sin(theta) dtheta,  (dy)' = cos(theta) dtheta,  (dtheta)' = dm,
    (dm)' = (Nx cos(theta) + Ny sin(theta)) dtheta + [0, sin(theta), -cos(theta), (1 - s) sin(theta),
            -(1 - s) cos(theta)].

State layout (STATE_SIZE = 25): [x, y, theta, m, U], then the sensitivities of (x, y, theta, m) to
(m0, Fx, Fy) row-major (indices 5-16), then their sensitivities to (wx, wy) row-major (17-24).

``beam_rhs`` is a beam of a mechanism (`mechanism` explains it): physical units, optionally axially
extensible (EA > 0; EA = 0 stands for inextensible), no sensitivities, state (x, y, theta, m, U)
(BEAM_STATE_SIZE = 5). With N = F . t the axial force and e = N/EA:

    x' = (1 + e) cos(theta),  y' = (1 + e) sin(theta),  theta' = kappa0 + m/EI,
    m' = (1 + e) (Fx sin(theta) - Fy cos(theta)),   U' = m^2/(2 EI) + N^2/(2 EA).

The integrator picks the equations by the state's length (25: the elastica, 5: a mechanism beam);
the loads travel in one parameter array P = (Fx, Fy, kappa0, wx, wy, EI, EA) (the elastica ignores EI
and EA, a mechanism beam wx and wy).

``dop853`` is scipy's ``solve_ivp(method="DOP853")`` (Hairer, Norsett & Wanner, Solving ODEs I,
sec. II.5 and II.4 for the first step) step for step: the same coefficients (scipy's own tables),
the same first-step choice, error norm (the 5th- and 3rd-order estimates combined) and step-size
factors (safety 0.9, between 0.2 and 10, exponent -1/8), so the end state agrees with scipy's to
rounding, without the Python cost of each stage.

Angles are in radians (degrees appear only in case files and reports).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit
from scipy.integrate._ivp import dop853_coefficients as _coef   # the tables scipy's DOP853 uses

__all__ = ["STATE_SIZE", "BEAM_STATE_SIZE", "elastica_rhs", "beam_rhs", "integrate_dop853",
           "integrate_samples", "integrate_beam", "beam_samples"]

STATE_SIZE = 25
BEAM_STATE_SIZE = 5
_N_STAGES = _coef.N_STAGES
_A = np.ascontiguousarray(_coef.A[:_N_STAGES, :_N_STAGES])
_B = np.ascontiguousarray(_coef.B)
_C = np.ascontiguousarray(_coef.C[:_N_STAGES])
_E3 = np.ascontiguousarray(_coef.E3)
_E5 = np.ascontiguousarray(_coef.E5)
SAFETY, MIN_FACTOR, MAX_FACTOR, ERROR_EXPONENT = 0.9, 0.2, 10.0, -1.0 / 8.0


@njit(cache=True)
def elastica_rhs(s, Y, Fx, Fy, k0, out, wx=0.0, wy=0.0):
    """dY/ds into ``out`` (layout in the module docstring); tip force (Fx, Fy), initial curvature k0,
    distributed load (wx, wy) per unit length (all normalised)."""
    th, m = Y[2], Y[3]
    c, sn = math.cos(th), math.sin(th)
    outboard = 1.0 - s
    Nx, Ny = Fx + wx * outboard, Fy + wy * outboard
    g = Nx * c + Ny * sn
    out[0] = c
    out[1] = sn
    out[2] = k0 + m
    out[3] = Nx * sn - Ny * c
    out[4] = 0.5 * m * m
    for k in range(3):
        t_k = Y[11 + k]
        out[5 + k] = -sn * t_k
        out[8 + k] = c * t_k
        out[11 + k] = Y[14 + k]
        out[14 + k] = g * t_k
    out[15] += sn
    out[16] -= c
    for k in range(2):                      # sensitivities to (wx, wy)
        t_k = Y[21 + k]
        out[17 + k] = -sn * t_k
        out[19 + k] = c * t_k
        out[21 + k] = Y[23 + k]
        out[23 + k] = g * t_k
    out[23] += outboard * sn
    out[24] -= outboard * c


@njit(cache=True)
def beam_rhs(s, Y, Fx, Fy, k0, EI, EA, out):
    """dY/ds into ``out`` for a mechanism beam (module docstring): tip force (Fx, Fy), initial
    curvature k0, bending stiffness EI, axial stiffness EA (0: inextensible), physical units."""
    th, m = Y[2], Y[3]
    c, sn = math.cos(th), math.sin(th)
    N = Fx * c + Fy * sn
    stretch = 1.0 + (N / EA if EA != 0.0 else 0.0)
    out[0] = stretch * c
    out[1] = stretch * sn
    out[2] = k0 + m / EI
    out[3] = stretch * (Fx * sn - Fy * c)
    out[4] = m * m / (2 * EI) + (N * N / (2 * EA) if EA != 0.0 else 0.0)


@njit(cache=True)
def _rhs(s, Y, P, out):
    """The equations the state's length names (STATE_SIZE: elastica, else a mechanism beam)."""
    if Y.size == STATE_SIZE:
        elastica_rhs(s, Y, P[0], P[1], P[2], out, P[3], P[4])
    else:
        beam_rhs(s, Y, P[0], P[1], P[2], P[5], P[6], out)


@njit(cache=True)
def _rms(v):
    return math.sqrt(np.sum(v * v) / v.size)


@njit(cache=True)
def _dop853(y0, t0, t1, P, rtol, atol):
    A, B, C, E3, E5 = _A, _B, _C, _E3, _E5     # global arrays: compile-time constants for numba
    n = y0.size
    K = np.empty((A.shape[0] + 1, n))
    f = np.empty(n)
    _rhs(t0, y0, P, f)
    y = y0.copy()
    interval = t1 - t0
    if interval <= 0.0:
        return y, True
    # first step (scipy's select_initial_step, order 7)
    scale = atol + np.abs(y0) * rtol
    d0, d1 = _rms(y0 / scale), _rms(f / scale)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, interval)
    f1 = np.empty(n)
    _rhs(t0 + h0, y0 + h0 * f, P, f1)
    d2 = _rms((f1 - f) / scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    h_abs = min(100 * h0, h1, interval)
    t = t0
    stage = np.empty(n)
    y_new = np.empty(n)
    while t < t1:
        min_step = 10 * abs(np.nextafter(t, np.inf) - t)
        if h_abs < min_step:
            h_abs = min_step
        rejected = False
        while True:
            if h_abs < min_step:
                return y, False
            t_new = t + h_abs
            if t_new > t1:
                t_new = t1
            h = t_new - t
            h_abs = abs(h)
            K[0] = f
            for s in range(1, A.shape[0]):
                for i in range(n):
                    acc = 0.0
                    for j in range(s):
                        acc += K[j, i] * A[s, j]
                    stage[i] = y[i] + acc * h
                _rhs(t + C[s] * h, stage, P, K[s])
            for i in range(n):
                acc = 0.0
                for j in range(B.size):
                    acc += K[j, i] * B[j]
                y_new[i] = y[i] + h * acc
            _rhs(t + h, y_new, P, K[K.shape[0] - 1])
            e5, e3 = 0.0, 0.0
            for i in range(n):
                sc = atol + max(abs(y[i]), abs(y_new[i])) * rtol
                a5, a3 = 0.0, 0.0
                for j in range(K.shape[0]):
                    a5 += K[j, i] * E5[j]
                    a3 += K[j, i] * E3[j]
                e5 += (a5 / sc) ** 2
                e3 += (a3 / sc) ** 2
            if e5 == 0.0 and e3 == 0.0:
                error_norm = 0.0
            else:
                error_norm = abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)
            if error_norm < 1.0:
                factor = MAX_FACTOR if error_norm == 0.0 else min(MAX_FACTOR, SAFETY * error_norm ** ERROR_EXPONENT)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            h_abs *= max(MIN_FACTOR, SAFETY * error_norm ** ERROR_EXPONENT)
            rejected = True
        t = t_new
        y[:] = y_new
        f[:] = K[K.shape[0] - 1]
    return y, True


def integrate_dop853(y0, a: float, b: float, Fx: float, Fy: float, k0: float, rtol: float, atol: float,
                     wx: float = 0.0, wy: float = 0.0):
    """The elastica state (STATE_SIZE) at s = b from y0 (float array) at s = a, and whether the
    integration succeeded (False: the step fell below the rounding of s). Called once per shooting
    residual: no argument conversion here, numba's dispatch checks the types."""
    return _dop853(y0, a, b, np.array([Fx, Fy, k0, wx, wy, 1.0, 0.0]), rtol, atol)


def integrate_beam(y0, length: float, Fx: float, Fy: float, k0: float, EI: float, EA: float,
                   rtol: float, atol: float):
    """A mechanism beam's state (x, y, theta, m, U) at s = length from y0 at s = 0 (physical units,
    EA = 0: inextensible), and whether the integration succeeded."""
    return _dop853(np.asarray(y0, dtype=float), 0.0, float(length),
                   np.array([Fx, Fy, k0, 0.0, 0.0, EI, EA], dtype=float), float(rtol), float(atol))


@njit(cache=True)
def _samples(y0, s, P, rtol, atol):
    out = np.empty((s.size, y0.size))
    out[0] = y0
    y = y0.copy()
    for k in range(1, s.size):
        y, ok = _dop853(y, s[k - 1], s[k], P, rtol, atol)
        if not ok:
            return out, False
        out[k] = y
    return out, True


def integrate_samples(y0, s, Fx: float, Fy: float, k0: float, rtol: float, atol: float,
                      wx: float = 0.0, wy: float = 0.0):
    """The elastica states (len(s), STATE_SIZE) at the increasing arc lengths ``s`` (s[0]: the start
    of y0), integrated from sample to sample, and whether every interval succeeded."""
    return _samples(np.asarray(y0, dtype=float), np.ascontiguousarray(s, dtype=float),
                    np.array([Fx, Fy, k0, wx, wy, 1.0, 0.0], dtype=float), float(rtol), float(atol))


def beam_samples(y0, s, Fx: float, Fy: float, k0: float, EI: float, EA: float, rtol: float, atol: float):
    """A mechanism beam's states (len(s), BEAM_STATE_SIZE) at the increasing arc lengths ``s``
    (s[0]: the start of y0), integrated from sample to sample, and whether every interval succeeded."""
    return _samples(np.asarray(y0, dtype=float), np.ascontiguousarray(s, dtype=float),
                    np.array([Fx, Fy, k0, 0.0, 0.0, EI, EA], dtype=float), float(rtol), float(atol))
