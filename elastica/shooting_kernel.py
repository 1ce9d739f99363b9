"""Compiled (numba, ``cache=True``) shooting residual, Jacobian and Newton corrector of ``shooting``.

One problem structure (normalised by L and EI, ``shooting`` derives the equations) is plain arrays:

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
carries (``integrator``). The Jacobian of the residual r(z, q) w.r.t. z and its derivative w.r.t. q
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

from .integrator import STATE_SIZE, _dop853

__all__ = ["ANGLE", "forces", "integrate", "residual", "newton", "tangent"]

ANGLE = -3          # index of the prescribed tip angle in q; the last two are (wx, wy)
# newton status: converged, not converged, integration failed at the start point
CONVERGED, NOT_CONVERGED, NO_START = 0, 1, 2


@njit(cache=True)
def forces(z, q, fdirs, mdirs, follower):
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
def integrate(z, q, k0, fdirs, mdirs, follower, bounds, rtol, atol):
    """States (len(bounds), STATE_SIZE) at the piece boundaries (row 0: s = 0, last: s = 1), the tip
    force, and whether every piece integrated."""
    F, _ = forces(z, q, fdirs, mdirs, follower)
    states = np.zeros((bounds.size, STATE_SIZE))
    states[0, 3] = z[0]
    states[0, 5 + 9] = 1.0              # d m(0) / d m0
    P = np.array([F[0], F[1], k0, q[q.size - 2], q[q.size - 1], 1.0, 0.0])
    for i in range(bounds.size - 1):
        y, ok = _dop853(states[i], bounds[i], bounds[i + 1], P, rtol, atol)
        if not ok:
            return states, F, False
        states[i + 1] = y
    return states, F, True


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
    """End-condition residual r (n,), Jacobian dr/dz (n, n), boundary states and tip force dF/dz;
    ok False when the integration failed."""
    n = z.size
    nc, nm = dirs.shape[0], mdirs.shape[0]
    states, F, ok = integrate(z, q, k0, fdirs, mdirs, follower, bounds, rtol, atol)
    _, dF = forces(z, q, fdirs, mdirs, follower)
    r = np.zeros(n)
    J = np.zeros((n, n))
    if not ok:
        return r, J, states, dF, False
    Y = states[bounds.size - 1]
    S = _sensitivities(Y)
    dYdz = np.ascontiguousarray(S[:, 1:3]) @ dF
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
        J[i] = np.ascontiguousarray(Sj[3, 1:3]) @ dF
        J[i, 0] += Sj[3, 0]
    if follower:
        r[n - 1] = Y[2] - z[n - 1]
        J[n - 1] = dYdz[2]
        J[n - 1, n - 1] -= 1.0
    return r, J, states, dF, True


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
    dYdq = np.ascontiguousarray(S[:, 1:3]) @ dFdq
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
        D[i] = np.ascontiguousarray(Sj[3, 1:3]) @ dFdq
        D[i, nq - 2:] += Sj[3, 3:5]
        D[i, 5 + nc + j] -= 1.0
    if follower:
        D[n - 1] = dYdq[2]
    return D


@njit(cache=True)
def tangent(z, q, dq, k0, dirs, fdirs, mdirs, site_at, angle_given, follower, bounds, rtol, atol):
    """dz/dlambda along q(lambda) with dq/dlambda = dq, and the tip (x, y, theta) at z.
    Status: 0 both, 1 tip only (singular Jacobian), 2 neither (the integration failed)."""
    r, J, states, _, ok = residual(z, q, k0, dirs, fdirs, mdirs, site_at, angle_given, follower,
                                   bounds, rtol, atol)
    tip = states[states.shape[0] - 1, :3].copy()
    if not ok:
        return np.zeros(z.size), tip, 2
    D = _load_derivative(z, states, dirs, mdirs, site_at, angle_given, follower, q.size)
    try:
        return np.linalg.solve(J, -(D @ dq)), tip, 0
    except Exception:   # numba's LinAlgError: the Jacobian is singular
        return np.zeros(z.size), tip, 1


@njit(cache=True)
def newton(z, q, tol, maxiter, k0, dirs, fdirs, mdirs, site_at, angle_given, follower, bounds, rtol,
           atol):
    """Damped Newton on the end conditions (module docstring). Returns (z, status, iterations,
    residual norm, tip (x, y, theta) of the last accepted point)."""
    r, J, states, _, ok = residual(z, q, k0, dirs, fdirs, mdirs, site_at, angle_given, follower,
                                   bounds, rtol, atol)
    last = bounds.size - 1
    if not ok:
        return z, NO_START, 0, math.inf, states[last, :3].copy()
    norm = np.linalg.norm(r)
    for it in range(1, maxiter + 1):
        try:
            dz = np.linalg.solve(J, -r)
        except Exception:   # numba's LinAlgError: the Jacobian is singular
            return z, NOT_CONVERGED, it, norm, states[last, :3].copy()
        t = 1.0
        while True:
            z_new = z + t * dz
            r_new, J_new, states_new, _, ok = residual(z_new, q, k0, dirs, fdirs, mdirs, site_at,
                                                       angle_given, follower, bounds, rtol, atol)
            if ok and np.linalg.norm(r_new) < max(norm, 1e-300) * (1 - 1e-4 * t) + 1e-14:
                break
            t *= 0.5
            if t < 1e-3:        # no descent left: converged only if already at the noise floor
                return z, CONVERGED if norm < tol else NOT_CONVERGED, it, norm, states[last, :3].copy()
        z, r, J, states, norm = z_new, r_new, J_new, states_new, np.linalg.norm(r_new)
        step = np.linalg.norm(t * dz)
        if norm < tol and step < 1e-9 * (1.0 + np.linalg.norm(z)):
            return z, CONVERGED, it, norm, states[last, :3].copy()
        if norm < 1e-3 * tol:
            return z, CONVERGED, it, norm, states[last, :3].copy()
    return z, NOT_CONVERGED, maxiter, norm, states[last, :3].copy()
