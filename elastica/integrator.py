"""Everything numba compiles (``cache=True``) for the elastica: the right-hand sides, the DOP853
integrator, and the shooting on it (residual, Jacobian, Newton corrector, continuation).

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

The shooting on these integrations (``shooting`` sets it up and reads the result): residual,
Jacobian, Newton corrector and the whole continuation (``follow_path``) are in this one module
because numba's cache only notices changes to the file that defines a cached function, not to the
files of the compiled functions it calls. One problem structure (normalised by L and EI, ``shooting`` derives the equations) is plain arrays:

* ``dirs`` (nc, 2): unit directions d_k of the prescribed tip-position components, end condition
  d_k . r(1) = c_k; ``fdirs`` (nc, 2): the directions of their unknown forces (multipliers mu_k);
* ``mdirs`` (nm, 2): the directions of the unknown forces of the prescribed section moments
  (multipliers nu_j), end condition m(s_j) = m_j; ``bounds``: the integration piece boundaries
  0 < knots < 1 (the interior sites s_j), ``site_at`` (nm,): the boundary index of each s_j;
* ``angle_given``: theta(1) = q[ANGLE] replaces m(1) = M; ``follower``: the last unknown is the tip
  angle tau and F = F_dead + R(tau) (ft, fn), with the end condition theta(1) = tau.

Unknowns z = [m(0), mu_1..mu_nc, nu_1..nu_nm, (tau)]; continuation parameters q = [Fx, Fy, M, ft, fn,
c_1..c_nc, m_1..m_nm, angle, wx, wy]. The tip force is F(z, q) = (Fx, Fy) + sum mu_k f_k + sum nu_j g_j
(+ R(tau) (ft, fn)), so d(state)/dz = S_m0 e_0^T + S_F dF/dz with S the sensitivities the integrator
carries (``elastica_rhs``). The Jacobian of the residual r(z, q) w.r.t. z and its derivative w.r.t. q
(the tangent predictor dz/dlambda = -J^-1 (dr/dq) dq) come from the same sensitivities.

Newton: full step, halved (down to 1/1000) until the residual norm falls by the Armijo factor
1 - 1e-4 t; converged when |r| < tol and the step is below 1e-9 (1 + |z|), or |r| < 1e-3 tol.
A singular Jacobian or a failed integration ends it (status codes below).

Angles are in radians (degrees appear only in case files and reports).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit
from scipy.integrate._ivp import dop853_coefficients as _coef   # the tables scipy's DOP853 uses

__all__ = ["STATE_SIZE", "BEAM_STATE_SIZE", "ANGLE", "elastica_rhs", "beam_rhs",
           "integrate_samples", "integrate_beam", "beam_samples", "residual", "follow_path"]

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
def _first_step(y0, f, t0, interval, P, rtol, atol):
    """scipy's select_initial_step (order 7)."""
    n = y0.size
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
    return min(100 * h0, h1, interval)


@njit(cache=True)
def _dop853(y0, t0, t1, P, rtol, atol, h_start=0.0):
    """State at t1 from y0 at t0, success, and the step size the controller proposes next.
    ``h_start`` > 0: the first step to try (a previous interval's proposal) instead of scipy's
    initial-step selection."""
    A, B, C, E3, E5 = _A, _B, _C, _E3, _E5     # global arrays: compile-time constants for numba
    n = y0.size
    K = np.empty((A.shape[0] + 1, n))
    f = np.empty(n)
    _rhs(t0, y0, P, f)
    y = y0.copy()
    interval = t1 - t0
    if interval <= 0.0:
        return y, True, h_start
    h_abs = _first_step(y0, f, t0, interval, P, rtol, atol) if h_start <= 0.0 else h_start
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
                return y, False, h_abs
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
    return y, True, h_abs


def integrate_beam(y0, length: float, Fx: float, Fy: float, k0: float, EI: float, EA: float,
                   rtol: float, atol: float):
    """A mechanism beam's state (x, y, theta, m, U) at s = length from y0 at s = 0 (physical units,
    EA = 0: inextensible), and whether the integration succeeded."""
    y, ok, _ = _dop853(np.asarray(y0, dtype=float), 0.0, float(length),
                       np.array([Fx, Fy, k0, 0.0, 0.0, EI, EA], dtype=float), float(rtol), float(atol))
    return y, ok


@njit(cache=True)
def _samples(y0, s, P, rtol, atol):
    """States at the arc lengths s, integrated from sample to sample; each interval starts with the
    step the previous one proposed (the first with scipy's initial-step selection)."""
    out = np.empty((s.size, y0.size))
    out[0] = y0
    y = y0.copy()
    h = 0.0
    for k in range(1, s.size):
        y, ok, h = _dop853(y, s[k - 1], s[k], P, rtol, atol, h)
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


# ------------------------------------------------------------------ shooting (residual, Newton, path)

ANGLE = -3          # index of the prescribed tip angle in q; the last two are (wx, wy)
# newton status: converged, not converged, integration failed at the start point
CONVERGED, NOT_CONVERGED, NO_START = 0, 1, 2


@njit(cache=True)
def _norm(v):
    """Euclidean norm (a plain loop: the systems have at most a handful of unknowns)."""
    total = 0.0
    for x in v:
        total += x * x
    return math.sqrt(total)


@njit(cache=True)
def _matmul(A, B):
    """A @ B for small dense matrices (loops, no BLAS binding to compile)."""
    C = np.zeros((A.shape[0], B.shape[1]))
    for i in range(A.shape[0]):
        for k in range(A.shape[1]):
            a = A[i, k]
            for j in range(B.shape[1]):
                C[i, j] += a * B[k, j]
    return C


@njit(cache=True)
def _solve(A, b):
    """x with A x = b by Gaussian elimination with partial pivoting, and False when a pivot is
    exactly zero (singular, as LAPACK's gesv reports it)."""
    n = b.size
    M = A.copy()
    x = b.copy()
    for k in range(n):
        p = k
        for i in range(k + 1, n):
            if abs(M[i, k]) > abs(M[p, k]):
                p = i
        if M[p, k] == 0.0:
            return x, False
        if p != k:
            for j in range(n):
                M[k, j], M[p, j] = M[p, j], M[k, j]
            x[k], x[p] = x[p], x[k]
        for i in range(k + 1, n):
            f = M[i, k] / M[k, k]
            for j in range(k, n):
                M[i, j] -= f * M[k, j]
            x[i] -= f * x[k]
    for k in range(n - 1, -1, -1):
        acc = x[k]
        for j in range(k + 1, n):
            acc -= M[k, j] * x[j]
        x[k] = acc / M[k, k]
    return x, True


@njit(cache=True)
def _forces(z, q, fdirs, mdirs, follower):
    """Tip force F (2,) and dF/dz (2, n) for the unknowns z."""
    n = z.size
    F = np.array([q[0], q[1]])
    dF = np.zeros((2, n))
    nc = fdirs.shape[0]
    for k in range(nc + mdirs.shape[0]):
        d = fdirs[k] if k < nc else mdirs[k - nc]
        F = F + z[1 + k] * d
        dF[0, 1 + k] = d[0]
        dF[1, 1 + k] = d[1]
    if follower:
        tau = z[n - 1]
        c, s = math.cos(tau), math.sin(tau)
        ft, fn = q[3], q[4]
        F = F + np.array([c * ft - s * fn, s * ft + c * fn])
        dF[0, n - 1] = -s * ft - c * fn
        dF[1, n - 1] = c * ft - s * fn
    return F, dF


@njit(cache=True)
def _sensitivities(Y):
    """(4, 5): d(x, y, theta, m)/d(m0, Fx, Fy, wx, wy) from a state vector (``integrator`` layout)."""
    S = np.empty((4, 5))
    for i in range(4):
        for j in range(3):
            S[i, j] = Y[5 + 3 * i + j]
        for j in range(2):
            S[i, 3 + j] = Y[17 + 2 * i + j]
    return S


@njit(cache=True)
def residual(z, q, k0, dirs, fdirs, mdirs, site_at, angle_given, follower, bounds, rtol, atol):
    """End-condition residual r (n,), Jacobian dr/dz (n, n), the states at the piece boundaries
    (row 0: s = 0, the last: s = 1) and the tip force F; ok False when the integration failed."""
    n = z.size
    nc, nm = dirs.shape[0], mdirs.shape[0]
    F, dF = _forces(z, q, fdirs, mdirs, follower)
    r = np.zeros(n)
    J = np.zeros((n, n))
    states = np.zeros((bounds.size, STATE_SIZE))
    states[0, 3] = z[0]
    states[0, 5 + 9] = 1.0              # d m(0) / d m0
    P = np.array([F[0], F[1], k0, q[q.size - 2], q[q.size - 1], 1.0, 0.0])
    for i in range(bounds.size - 1):
        y, ok, _ = _dop853(states[i], bounds[i], bounds[i + 1], P, rtol, atol)
        if not ok:
            return r, J, states, F, False
        states[i + 1] = y
    Y = states[bounds.size - 1]
    S = _sensitivities(Y)
    dYdz = _matmul(S[:, 1:3], dF)
    dYdz[:, 0] += S[:, 0]
    if angle_given:
        r[0] = Y[2] - q[q.size + ANGLE]
        J[0] = dYdz[2]
    else:
        r[0] = Y[3] - q[2]
        J[0] = dYdz[3]
    for k in range(nc):
        d = dirs[k]
        r[1 + k] = d[0] * Y[0] + d[1] * Y[1] - q[5 + k]
        J[1 + k] = d[0] * dYdz[0] + d[1] * dYdz[1]
    for j in range(nm):
        Yj = states[site_at[j]]
        Sj = _sensitivities(Yj)
        i = 1 + nc + j
        r[i] = Yj[3] - q[5 + nc + j]
        J[i] = _matmul(Sj[3:4, 1:3], dF)[0]
        J[i, 0] += Sj[3, 0]
    if follower:
        r[n - 1] = Y[2] - z[n - 1]
        J[n - 1] = dYdz[2]
        J[n - 1, n - 1] -= 1.0
    return r, J, states, F, True


@njit(cache=True)
def _load_derivative(z, states, dirs, mdirs, site_at, angle_given, follower, nq):
    """d r / d q (n x nq): the force parameters act through the sensitivities to (Fx, Fy) (and the
    follower's through the tip angle), the others enter the end conditions directly."""
    n = z.size
    nc, nm = dirs.shape[0], mdirs.shape[0]
    S = _sensitivities(states[states.shape[0] - 1])
    dFdq = np.zeros((2, nq))
    dFdq[0, 0] = dFdq[1, 1] = 1.0
    if follower:
        c, sn = math.cos(z[n - 1]), math.sin(z[n - 1])
        dFdq[0, 3], dFdq[1, 3] = c, sn
        dFdq[0, 4], dFdq[1, 4] = -sn, c
    dYdq = _matmul(S[:, 1:3], dFdq)
    dYdq[:, nq - 2:] += S[:, 3:5]                       # the distributed load (wx, wy)
    D = np.zeros((n, nq))
    if angle_given:
        D[0] = dYdq[2]
        D[0, nq + ANGLE] -= 1.0
    else:
        D[0] = dYdq[3]
        D[0, 2] -= 1.0
    for k in range(nc):
        d = dirs[k]
        D[1 + k] = d[0] * dYdq[0] + d[1] * dYdq[1]
        D[1 + k, 5 + k] -= 1.0
    for j in range(nm):
        Sj = _sensitivities(states[site_at[j]])
        i = 1 + nc + j
        D[i] = _matmul(Sj[3:4, 1:3], dFdq)[0]
        D[i, nq - 2:] += Sj[3, 3:5]
        D[i, 5 + nc + j] -= 1.0
    if follower:
        D[n - 1] = dYdq[2]
    return D


@njit(cache=True)
def _tangent(z, J, states, dq, dirs, mdirs, site_at, angle_given, follower):
    """dz/dlambda along q(lambda) with dq/dlambda = dq, from the Jacobian J and the states of the
    residual at z; False when J is singular."""
    D = _load_derivative(z, states, dirs, mdirs, site_at, angle_given, follower, dq.size)
    return _solve(J, -_matmul(D, dq.reshape(-1, 1))[:, 0])


@njit(cache=True)
def _newton(z, q, tol, maxiter, k0, dirs, fdirs, mdirs, site_at, angle_given, follower, bounds, rtol,
            atol):
    """Damped Newton on the end conditions (module docstring). Returns (z, status, iterations,
    residual norm, Jacobian, boundary states and tip force at z): z is the last accepted point (with maxiter = 0
    the start point, evaluated). One residual call site (the start point, then every trial point), so
    the compiled code holds one copy of the integrator."""
    it, t, norm, started = 0, 1.0, math.inf, False
    dz = np.zeros_like(z)
    z_try = z
    while True:
        r_new, J_new, states_new, F_new, ok = residual(z_try, q, k0, dirs, fdirs, mdirs, site_at,
                                                   angle_given, follower, bounds, rtol, atol)
        if not started:
            if not ok:
                return z, NO_START, 0, math.inf, J_new, states_new, F_new
            started = True
            r, J, states, F, norm = r_new, J_new, states_new, F_new, _norm(r_new)
        elif ok and _norm(r_new) < max(norm, 1e-300) * (1 - 1e-4 * t) + 1e-14:
            z, r, J, states, F, norm = z_try, r_new, J_new, states_new, F_new, _norm(r_new)
            step = _norm(t * dz)
            if (norm < tol and step < 1e-9 * (1.0 + _norm(z))) or norm < 1e-3 * tol:
                return z, CONVERGED, it, norm, J, states, F
        else:
            t *= 0.5
            if t < 1e-3:        # no descent left: converged only if already at the noise floor
                return z, CONVERGED if norm < tol else NOT_CONVERGED, it, norm, J, states, F
            z_try = z + t * dz
            continue
        it += 1
        if it > maxiter:
            return z, NOT_CONVERGED, maxiter, norm, J, states, F
        dz, regular = _solve(J, -r)
        if not regular:
            return z, NOT_CONVERGED, it, norm, J, states, F
        t = 1.0
        z_try = z + t * dz


# follow_path status: converged, continuation stalled, integration failed at the start, final
# corrector failed
PATH_CONVERGED, PATH_STALLED, PATH_NO_START, PATH_FINAL_FAILED = 0, 1, 2, 3


@njit(cache=True)
def follow_path(z, q0, q1, k0, dirs, fdirs, mdirs, site_at, angle_given, follower, bounds, rtol, atol,
                tol, path_rtol, initial_step, min_step, max_rotation_step, max_position_step,
                max_corrector, max_step_iterations, maxiter):
    """Continuation from (z, q0) to q1 (``shooting`` module docstring): tangent predictor (from the
    Jacobian of the last accepted point), Newton corrector at ``path_rtol`` with the step rejections,
    then the final corrector at ``rtol``/``tol``. One Newton call site (the start point is evaluated by
    a Newton of 0 iterations; the final corrector is the last call): one compiled copy of it.
    Returns (z, status, load fraction reached, Newton iterations, accepted steps, residual norm,
    and when converged the boundary states and tip force at z)."""
    path_atol = path_rtol * 0.1
    last = bounds.size - 1
    dq = q1 - q0
    lam, dlam, lam_try = 0.0, min(initial_step, 1.0), 0.0
    nit, nsteps, norm = 0, 0, 0.0
    started, regular = False, True
    dz, tip, step = np.zeros_like(z), np.zeros(3), np.zeros_like(z)
    while True:
        final = started and lam >= 1.0
        if not started:
            q, z_guess, ntol, nrtol, natol, nmax = q0, z, 0.0, path_rtol, path_atol, 0
        elif final:       # final corrector at full accuracy
            q, z_guess, ntol, nrtol, natol, nmax = q0 + lam * dq, z, tol, rtol, atol, maxiter
        else:
            lam_try = min(1.0, lam + dlam)
            q = q0 + lam_try * dq
            step = (lam_try - lam) * dz if regular else np.zeros_like(z)
            z_guess, ntol, nrtol, natol, nmax = z + step, 10 * path_rtol, path_rtol, path_atol, maxiter
        z_new, nstat, it, norm, J, states, F = _newton(z_guess, q, ntol, nmax, k0, dirs, fdirs, mdirs,
                                                       site_at, angle_given, follower, bounds, nrtol, natol)
        new_tip = states[last, :3]
        ok = nstat == CONVERGED
        if not started:
            if nstat == NO_START:
                return z, PATH_NO_START, lam, nit, nsteps, norm, states, F
            started, ok, norm = True, True, 0.0
        else:
            nit += it
            if final:
                if ok and abs(new_tip[2] - tip[2]) < 1e-3:
                    return z_new, PATH_CONVERGED, lam, nit, nsteps, norm, states, F
                return z, PATH_FINAL_FAILED, lam, nit, nsteps, norm, states, F
            if ok:
                moved = math.hypot(new_tip[0] - tip[0], new_tip[1] - tip[1])
                off = _norm(z_new - z_guess)
                ok = (it <= max_step_iterations and abs(new_tip[2] - tip[2]) <= max_rotation_step
                      and moved <= max_position_step
                      and (not regular or off <= max_corrector * _norm(step) + 1e-6 * (1.0 + _norm(z))))
            if ok:
                z, lam = z_new, lam_try
                nsteps += 1
                if it <= 3:
                    dlam = min(2.0 * dlam, 1.0)
        if ok:                  # the tangent at the new point
            dz, regular = _tangent(z, J, states, dq, dirs, mdirs, site_at, angle_given, follower)
            tip = new_tip.copy()
        else:
            dlam *= 0.5
            if dlam < min_step:
                return z, PATH_STALLED, lam, nit, nsteps, norm, states, F
