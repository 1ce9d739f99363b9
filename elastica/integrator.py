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
(m0, Fx, Fy) row-major (indices 5-16), then their sensitivities to (wx, wy) row-major (17-24). The
first FORCE_STATE_SIZE = 17 entries are a state of their own: the same equations without the
sensitivities to the distributed load, integrated when the continuation does not change (wx, wy)
(the tangent predictor is the only user of those sensitivities).

``beam_rhs`` is the plain beam (x, y, theta, m, U) (BEAM_STATE_SIZE = 5), no sensitivities: a beam of
a mechanism (`mechanism` explains it; physical units, optionally axially extensible, EA > 0; EA = 0
stands for inextensible) and the elastica's shape samples and section moments (EI = 1, EA = 0). With
the section force N(s) = F + w (l - s) (a uniform dead load w per unit length over the length l
outboard of s; 0 for a mechanism beam), Nt = N . t the axial force and e = Nt/EA:

    x' = (1 + e) cos(theta),  y' = (1 + e) sin(theta),  theta' = kappa0 + m/EI,
    m' = (1 + e) (Nx sin(theta) - Ny cos(theta)),   U' = m^2/(2 EI) + Nt^2/(2 EA).

The integrator picks the equations by the state's length (25 or 17: the elastica with its
sensitivities, 5: the plain beam); the loads travel in one parameter array
P = (Fx, Fy, kappa0, wx, wy, EI, EA, l) (the elastica's sensitivities ignore EI, EA and l: L = EI = 1).

``dop853`` is scipy's ``solve_ivp(method="DOP853")`` (Hairer, Norsett & Wanner, Solving ODEs I,
sec. II.5 and II.4 for the first step) step for step: the same coefficients (scipy's own tables),
the same first-step choice, error norm (the 5th- and 3rd-order estimates combined) and step-size
factors (safety 0.9, between 0.2 and 10, exponent -1/8), so the end state agrees with scipy's to
rounding, without the Python cost of each stage.

The shooting on these integrations (``shooting`` sets it up and reads the result): residual,
Jacobian, Newton corrector and the whole continuation (``follow_path``) are in this one module
because numba's cache only notices changes to the file that defines a cached function, not to the
files of the compiled functions it calls.

Compile cost: numba compiles every jitted function on its own and links a copy of each callee into
its caller, where LLVM optimises it again, so a chain follow_path -> newton -> residual -> dop853
optimised the integrator once per level of the chain. Here only two functions are
entry points (``follow_path`` and ``_samples``); the large functions they call once are inlined
into them by numba (``inline='always'``: typed and optimised only as part of the caller), and the
code uses loops instead of whole-array expressions, whose broadcasting checks drag numba's string
formatting of error messages into every function that has one. Small helpers called from several
places (``_combine``, ``_trial``) stay separate functions (LLVM inlines them anyway; numba's inlining
would type a copy per call site). ``error_model="numpy"``: a float division by zero gives inf/nan
instead of raising, so no exception branch per division is generated (every division here has a
nonzero divisor by construction). ``no_cpython_wrapper=True`` on the helpers only compiled code calls
(not on ``tip_force``, which `shooting` calls, nor ``_reach``, which a test calls): numba builds and
optimises no Python-callable wrapper for them (LLVM time saved on each helper).

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
carries (``elastica_rhs``). The Jacobian of the residual r(z, q) w.r.t. z and its derivative w.r.t. q
(the tangent predictor dz/dlambda = -J^-1 (dr/dq) dq) come from the same sensitivities.

Newton: full step, halved (down to 1/1000) until the residual norm falls by the Armijo factor
1 - 1e-4 t (the start and the final corrector; a corrector along the path is not damped and stays
within its trust region, ``_newton``); a point z is converged when |r(z)| < tol and the Newton step from z, J(z)^-1 r(z), is
below ``step_tol`` (1 + |z|) (1e-9 for the final corrector, the path tolerance for the points along
the path, which only start the next step), or |r| < 1e-3 tol.
A singular Jacobian or a failed integration ends it (status codes below).

Angles are in radians (degrees appear only in case files and reports).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit
from scipy.integrate._ivp import dop853_coefficients as _coef   # the tables scipy's DOP853 uses

__all__ = ["STATE_SIZE", "FORCE_STATE_SIZE", "BEAM_STATE_SIZE", "ANGLE", "elastica_rhs", "beam_rhs",
           "integrate_samples", "integrate_beam", "beam_samples", "plain_samples", "tip_force",
           "follow_path"]

STATE_SIZE = 25
FORCE_STATE_SIZE = 17
BEAM_STATE_SIZE = 5
_N_STAGES = _coef.N_STAGES
_A = np.ascontiguousarray(_coef.A[:_N_STAGES, :_N_STAGES])
_B = np.ascontiguousarray(_coef.B)
_C = np.ascontiguousarray(_coef.C[:_N_STAGES])
_E3 = np.ascontiguousarray(_coef.E3)
_E5 = np.ascontiguousarray(_coef.E5)
_AB = np.ascontiguousarray(np.vstack([_A, _B]))     # the stage rows of A, then B (one stage-sum site)
SAFETY, MIN_FACTOR, MAX_FACTOR, ERROR_EXPONENT = 0.9, 0.2, 10.0, -1.0 / 8.0


@njit(cache=True, inline="always", error_model="numpy")
def elastica_rhs(s, Y, Fx, Fy, k0, out, wx=0.0, wy=0.0):
    """dY/ds into ``out`` (layout in the module docstring: STATE_SIZE entries, or FORCE_STATE_SIZE
    without the sensitivities to the distributed load); tip force (Fx, Fy), initial curvature k0,
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
    if Y.size < STATE_SIZE:
        return
    for k in range(2):                      # sensitivities to (wx, wy)
        t_k = Y[21 + k]
        out[17 + k] = -sn * t_k
        out[19 + k] = c * t_k
        out[21 + k] = Y[23 + k]
        out[23 + k] = g * t_k
    out[23] += outboard * sn
    out[24] -= outboard * c


@njit(cache=True, inline="always", error_model="numpy")
def beam_rhs(s, Y, Fx, Fy, k0, EI, EA, out, wx=0.0, wy=0.0, length=0.0):
    """dY/ds into ``out`` for the plain beam (module docstring): tip force (Fx, Fy), initial
    curvature k0, bending stiffness EI, axial stiffness EA (0: inextensible), a uniform dead load
    (wx, wy) per unit length over [s, length]."""
    th, m = Y[2], Y[3]
    c, sn = math.cos(th), math.sin(th)
    outboard = length - s
    Nx, Ny = Fx + wx * outboard, Fy + wy * outboard
    N = Nx * c + Ny * sn
    stretch = 1.0 + (N / EA if EA != 0.0 else 0.0)
    out[0] = stretch * c
    out[1] = stretch * sn
    out[2] = k0 + m / EI
    out[3] = stretch * (Nx * sn - Ny * c)
    out[4] = m * m / (2 * EI) + (N * N / (2 * EA) if EA != 0.0 else 0.0)


@njit(cache=True, error_model="numpy", no_cpython_wrapper=True)
def _rhs(s, Y, P, out):
    """The equations the state's length names (BEAM_STATE_SIZE: the plain beam, else the elastica
    with its sensitivities)."""
    if Y.size == BEAM_STATE_SIZE:
        beam_rhs(s, Y, P[0], P[1], P[2], P[5], P[6], out, P[3], P[4], P[7])
    else:
        elastica_rhs(s, Y, P[0], P[1], P[2], out, P[3], P[4])


@njit(cache=True, inline="always", error_model="numpy")
def _first_step(y0, f, t0, interval, P, rtol, atol):
    """scipy's select_initial_step (order 7); rms norms as plain loops."""
    n = y0.size
    f1 = np.empty(n)
    y1 = np.empty(n)
    d0 = d1 = 0.0
    for i in range(n):
        sc = atol + abs(y0[i]) * rtol
        d0 += (y0[i] / sc) ** 2
        d1 += (f[i] / sc) ** 2
    d0, d1 = math.sqrt(d0 / n), math.sqrt(d1 / n)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, interval)
    for i in range(n):
        y1[i] = y0[i] + h0 * f[i]
    _rhs(t0 + h0, y1, P, f1)
    d2 = 0.0
    for i in range(n):
        sc = atol + abs(y0[i]) * rtol
        d2 += ((f1[i] - f[i]) / sc) ** 2
    d2 = math.sqrt(d2 / n) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    return min(100 * h0, h1, interval)


@njit(cache=True, inline="always", error_model="numpy")
def _combine(K, w, count, out):
    """out[i] = sum_{j < count} K[j, i] w[j], summed in the order of j (as the loop over j inside
    the loop over i that scipy's dot products amount to), but with the components i in the inner
    loop: independent sums the processor overlaps, instead of one chain of dependent additions.
    Zero weights (a third of DOP853's table) are skipped: adding 0 K[j, i] changes no sum."""
    for i in range(out.size):
        out[i] = 0.0
    for j in range(count):
        wj = w[j]
        if wj == 0.0:
            continue
        for i in range(out.size):
            out[i] += K[j, i] * wj


@njit(cache=True, inline="always", error_model="numpy")
def _error_norm(K, y, y_new, h, rtol, atol):
    """scipy's DOP853 error norm of a step from y to y_new with the stage derivatives K."""
    n = y.size
    e5, e3 = 0.0, 0.0
    for i in range(n):
        sc = atol + max(abs(y[i]), abs(y_new[i])) * rtol
        a5, a3 = 0.0, 0.0
        for j in range(K.shape[0]):
            a5 += K[j, i] * _E5[j]
            a3 += K[j, i] * _E3[j]
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)


@njit(cache=True, inline="always", error_model="numpy")
def _dop853(y0, t0, t1, P, rtol, atol, h_start):
    """State at t1 from y0 at t0, success, and the step size the controller proposes next.
    ``h_start`` > 0: the first step to try (a previous interval's proposal) instead of scipy's
    initial-step selection."""
    AB, C = _AB, _C     # global arrays: compile-time constants for numba
    n = y0.size
    K = np.empty((AB.shape[0], n))
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
    acc = np.empty(n)
    last = K.shape[0] - 1
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
            for i in range(n):
                K[0, i] = f[i]
            for s in range(1, AB.shape[0]):     # the stages, then (the last row, B) the new state
                _combine(K, AB[s], s, acc)
                if s < last:
                    for i in range(n):
                        stage[i] = y[i] + acc[i] * h
                    _rhs(t + C[s] * h, stage, P, K[s])
                else:
                    for i in range(n):
                        y_new[i] = y[i] + h * acc[i]
            _rhs(t + h, y_new, P, K[last])
            error_norm = _error_norm(K, y, y_new, h, rtol, atol)
            if error_norm < 1.0:
                factor = MAX_FACTOR if error_norm == 0.0 else min(MAX_FACTOR, SAFETY * error_norm ** ERROR_EXPONENT)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            h_abs *= max(MIN_FACTOR, SAFETY * error_norm ** ERROR_EXPONENT)
            rejected = True
        t = t_new
        for i in range(n):
            y[i] = y_new[i]
            f[i] = K[last, i]
    return y, True, h_abs


@njit(cache=True, error_model="numpy")
def _samples(y0, s, P, rtol, atol, restart):
    """States at the arc lengths s, integrated from sample to sample; each interval starts with the
    step the previous one proposed (the first, and every one when ``restart``, with scipy's
    initial-step selection). The one compiled entry point of the integrator besides the shooting."""
    n = y0.size
    out = np.empty((s.size, n))
    y = y0.copy()
    for i in range(n):
        out[0, i] = y0[i]
    h = 0.0
    for k in range(1, s.size):
        y, ok, h = _dop853(y, s[k - 1], s[k], P, rtol, atol, 0.0 if restart else h)
        if not ok:
            return out, False
        for i in range(n):
            out[k, i] = y[i]
    return out, True


def _parameters(Fx, Fy, k0, wx=0.0, wy=0.0, EI=1.0, EA=0.0, length=1.0):
    """The parameter array P (module docstring)."""
    return np.array([Fx, Fy, k0, wx, wy, EI, EA, length], dtype=float)


def integrate_beam(y0, length: float, Fx: float, Fy: float, k0: float, EI: float, EA: float,
                   rtol: float, atol: float):
    """A mechanism beam's state (x, y, theta, m, U) at s = length from y0 at s = 0 (physical units,
    EA = 0: inextensible), and whether the integration succeeded. (The arrays built directly: the
    mechanism's residual calls this once a beam an evaluation.)"""
    length = float(length)
    states, ok = _samples(np.asarray(y0, dtype=float), np.array([0.0, length]),
                          np.array([Fx, Fy, k0, 0.0, 0.0, EI, EA, length], dtype=float),   # `_parameters`
                          float(rtol), float(atol), True)
    return states[-1], ok


def integrate_samples(y0, s, Fx: float, Fy: float, k0: float, rtol: float, atol: float,
                      wx: float = 0.0, wy: float = 0.0):
    """The elastica states (len(s), len(y0): STATE_SIZE or FORCE_STATE_SIZE) at the increasing arc
    lengths ``s`` (s[0]: the start of y0), integrated from sample to sample, and whether every
    interval succeeded."""
    return _samples(np.asarray(y0, dtype=float), np.ascontiguousarray(s, dtype=float),
                    _parameters(Fx, Fy, k0, wx, wy), float(rtol), float(atol), False)


def plain_samples(y0, s, Fx: float, Fy: float, k0: float, rtol: float, atol: float,
                  wx: float = 0.0, wy: float = 0.0, restart: bool = False):
    """The elastica's plain states (x, y, theta, m, U) (normalised, L = EI = 1, no sensitivities) at
    the increasing arc lengths ``s`` from y0 at s[0]; ``restart``: every interval starts with
    scipy's initial-step selection (as the shooting's pieces do). And whether every interval
    succeeded."""
    return _samples(np.asarray(y0, dtype=float)[:BEAM_STATE_SIZE], np.ascontiguousarray(s, dtype=float),
                    _parameters(Fx, Fy, k0, wx, wy), float(rtol), float(atol), bool(restart))


def beam_samples(y0, s, Fx: float, Fy: float, k0: float, EI: float, EA: float, rtol: float, atol: float):
    """A mechanism beam's states (len(s), BEAM_STATE_SIZE) at the increasing arc lengths ``s``
    (s[0]: the start of y0), integrated from sample to sample, and whether every interval succeeded."""
    s = np.ascontiguousarray(s, dtype=float)
    return _samples(np.asarray(y0, dtype=float), s, _parameters(Fx, Fy, k0, EI=EI, EA=EA, length=s[-1]),
                    float(rtol), float(atol), False)


# ------------------------------------------------------------------ shooting (residual, Newton, path)

ANGLE = -3          # index of the prescribed tip angle in q; the last two are (wx, wy)
# newton status: converged, not converged, integration failed at the start point
CONVERGED, NOT_CONVERGED, NO_START = 0, 1, 2


@njit(cache=True, error_model="numpy", no_cpython_wrapper=True)
def _norm(v):
    """Euclidean norm (a plain loop: the systems have at most a handful of unknowns)."""
    total = 0.0
    for x in v:
        total += x * x
    return math.sqrt(total)


@njit(cache=True, error_model="numpy", no_cpython_wrapper=True)
def _distance(a, b):
    """Euclidean distance |a - b| (a plain loop)."""
    total = 0.0
    for i in range(a.size):
        total += (a[i] - b[i]) ** 2
    return math.sqrt(total)


@njit(cache=True, error_model="numpy", no_cpython_wrapper=True)
def _axpy(x, a, d):
    """x + a d as a new array (a loop: no broadcasting checks to compile)."""
    out = np.empty(x.size)
    for i in range(x.size):
        out[i] = x[i] + a * d[i]
    return out


@njit(cache=True, error_model="numpy", no_cpython_wrapper=True)
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


@njit(cache=True, error_model="numpy")
def tip_force(z, q, fdirs, mdirs, follower):
    """Tip force F (2,) and dF/dz (2, n) for the unknowns z (normalised)."""
    n = z.size
    F = np.zeros(2)
    F[0], F[1] = q[0], q[1]
    dF = np.zeros((2, n))
    nc = fdirs.shape[0]
    for k in range(nc + mdirs.shape[0]):
        d0, d1 = (fdirs[k, 0], fdirs[k, 1]) if k < nc else (mdirs[k - nc, 0], mdirs[k - nc, 1])
        F[0] += z[1 + k] * d0
        F[1] += z[1 + k] * d1
        dF[0, 1 + k] = d0
        dF[1, 1 + k] = d1
    if follower:
        tau = z[n - 1]
        c, s = math.cos(tau), math.sin(tau)
        ft, fn = q[3], q[4]
        F[0] += c * ft - s * fn
        F[1] += s * ft + c * fn
        dF[0, n - 1] = -s * ft - c * fn
        dF[1, n - 1] = c * ft - s * fn
    return F, dF


@njit(cache=True, error_model="numpy", no_cpython_wrapper=True)
def _through_force(Y, dF):
    """(4, m): d(x, y, theta, m)/d(parameters) of the state Y (``integrator`` layout) when the tip
    force depends on them by dF = dF/d(parameters) (2, m)."""
    D = np.zeros((4, dF.shape[1]))
    for i in range(4):
        sx, sy = Y[5 + 3 * i + 1], Y[5 + 3 * i + 2]      # d(row i)/dFx, d(row i)/dFy
        for j in range(dF.shape[1]):
            D[i, j] = sx * dF[0, j] + sy * dF[1, j]
    return D


@njit(cache=True, error_model="numpy", no_cpython_wrapper=True)
def _unknowns_derivative(Y, dF):
    """(4, n): d(x, y, theta, m)/dz of the state Y: through the tip force (dF = dF/dz) and, in
    column 0, through m(0) = z[0]."""
    D = _through_force(Y, dF)
    for i in range(4):
        D[i, 0] += Y[5 + 3 * i]
    return D


@njit(cache=True, inline="always", error_model="numpy")
def _integrate_pieces(z, F, q, k0, bounds, n_state, rtol, atol):
    """The states at the piece boundaries (bounds.size, STATE_SIZE; the first ``n_state`` entries
    integrated, the rest 0) from m(0) = z[0] under the tip force F, and whether all succeeded."""
    y = np.zeros(n_state)
    y[3] = z[0]
    y[5 + 9] = 1.0              # d m(0) / d m0
    P = np.zeros(8)
    P[0], P[1], P[2], P[3], P[4], P[5], P[7] = F[0], F[1], k0, q[q.size - 2], q[q.size - 1], 1.0, 1.0
    restart = bounds.size > 1   # every piece from scipy's first step (a run-time bool, as Python passes it)
    pieces, ok = _samples(y, bounds, P, rtol, atol, restart)
    states = np.zeros((bounds.size, STATE_SIZE))
    for i in range(bounds.size):
        for j in range(n_state):
            states[i, j] = pieces[i, j]
    return states, ok


@njit(cache=True, inline="always", error_model="numpy")
def _residual(z, q, k0, dirs, fdirs, mdirs, site_at, angle_given, follower, bounds, n_state, rtol, atol):
    """End-condition residual r (n,), Jacobian dr/dz (n, n), the states at the piece boundaries
    (row 0: s = 0, the last: s = 1) and the tip force F; ok False when the integration failed."""
    n = z.size
    nc, nm = dirs.shape[0], mdirs.shape[0]
    F, dF = tip_force(z, q, fdirs, mdirs, follower)
    r = np.zeros(n)
    J = np.zeros((n, n))
    states, ok = _integrate_pieces(z, F, q, k0, bounds, n_state, rtol, atol)
    if not ok:
        return r, J, states, F, False
    Y = states[bounds.size - 1]
    dYdz = _unknowns_derivative(Y, dF)
    row = 3
    if angle_given:
        r[0] = Y[2] - q[q.size + ANGLE]
        row = 2
    else:
        r[0] = Y[3] - q[2]
    for j in range(n):
        J[0, j] = dYdz[row, j]
    for k in range(nc):
        d0, d1 = dirs[k, 0], dirs[k, 1]
        r[1 + k] = d0 * Y[0] + d1 * Y[1] - q[5 + k]
        for j in range(n):
            J[1 + k, j] = d0 * dYdz[0, j] + d1 * dYdz[1, j]
    for i in range(nm):
        Yi = states[site_at[i]]
        dYi = _unknowns_derivative(Yi, dF)
        r[1 + nc + i] = Yi[3] - q[5 + nc + i]
        for j in range(n):
            J[1 + nc + i, j] = dYi[3, j]
    if follower:
        r[n - 1] = Y[2] - z[n - 1]
        for j in range(n):
            J[n - 1, j] = dYdz[2, j]
        J[n - 1, n - 1] -= 1.0
    return r, J, states, F, True


@njit(cache=True, inline="always", error_model="numpy")
def _load_derivative(z, states, dirs, mdirs, site_at, angle_given, follower, nq):
    """d r / d q (n x nq), and d(x, y, theta, m)(1) / d q (4 x nq): the force parameters act through the sensitivities to (Fx, Fy) (and the
    follower's through the tip angle), the distributed load (the last two) through its own, the
    others enter the end conditions directly."""
    n = z.size
    nc, nm = dirs.shape[0], mdirs.shape[0]
    dFdq = np.zeros((2, nq))
    dFdq[0, 0] = dFdq[1, 1] = 1.0
    if follower:
        c, sn = math.cos(z[n - 1]), math.sin(z[n - 1])
        dFdq[0, 3], dFdq[1, 3] = c, sn
        dFdq[0, 4], dFdq[1, 4] = -sn, c
    Y = states[states.shape[0] - 1]
    dYdq = _through_force(Y, dFdq)
    for i in range(4):                              # the distributed load (wx, wy)
        dYdq[i, nq - 2] += Y[17 + 2 * i]
        dYdq[i, nq - 1] += Y[18 + 2 * i]
    D = np.zeros((n, nq))
    row = 2 if angle_given else 3
    for j in range(nq):
        D[0, j] = dYdq[row, j]
    D[0, nq + ANGLE if angle_given else 2] -= 1.0
    for k in range(nc):
        for j in range(nq):
            D[1 + k, j] = dirs[k, 0] * dYdq[0, j] + dirs[k, 1] * dYdq[1, j]
        D[1 + k, 5 + k] -= 1.0
    for i in range(nm):
        Yi = states[site_at[i]]
        dYi = _through_force(Yi, dFdq)
        for j in range(nq):
            D[1 + nc + i, j] = dYi[3, j]
        D[1 + nc + i, nq - 2] += Yi[17 + 6]
        D[1 + nc + i, nq - 1] += Yi[18 + 6]
        D[1 + nc + i, 5 + nc + i] -= 1.0
    if follower:
        for j in range(nq):
            D[n - 1, j] = dYdq[2, j]
    return D, dYdq


@njit(cache=True, inline="always", error_model="numpy")
def _tangent(z, q, J, states, dq, dirs, fdirs, mdirs, site_at, angle_given, follower):
    """dz/dlambda along q(lambda) with dq/dlambda = dq, from the Jacobian J and the states of the
    residual at z; False when J is singular; and the tip's rate d(x, y, theta)(1)/dlambda =
    (dY/dz) dz/dlambda + (dY/dq) dq (normalised)."""
    D, dYdq = _load_derivative(z, states, dirs, mdirs, site_at, angle_given, follower, dq.size)
    rhs = np.zeros(z.size)
    for i in range(z.size):
        for j in range(dq.size):
            rhs[i] -= D[i, j] * dq[j]
    dz, regular = _solve(J, rhs)
    return dz, regular, _tip_rate(z, q, states[states.shape[0] - 1], dz, dYdq, dq, fdirs, mdirs, follower)


@njit(cache=True, error_model="numpy", no_cpython_wrapper=True)
def _tip_rate(z, q, Y, dz, dYdq, dq, fdirs, mdirs, follower):
    """d(x, y, theta)(1)/dlambda = (dY/dz) dz/dlambda + (dY/dq) dq at the tip state Y."""
    _, dF = tip_force(z, q, fdirs, mdirs, follower)
    dYdz = _unknowns_derivative(Y, dF)
    rate = np.zeros(3)
    for i in range(3):
        for j in range(z.size):
            rate[i] += dYdz[i, j] * dz[j]
        for j in range(dq.size):
            rate[i] += dYdq[i, j] * dq[j]
    return rate


@njit(cache=True, error_model="numpy", no_cpython_wrapper=True)
def _trial(z, t, dz, center, radius):
    """The trial point z + t dz, t halved until it lies within ``radius`` of ``center`` (or t < 1e-3)."""
    z_try = _axpy(z, t, dz)
    while _distance(z_try, center) > radius and t >= 1e-3:
        t *= 0.5
        z_try = _axpy(z, t, dz)
    return z_try, t


@njit(cache=True, inline="always", error_model="numpy")
def _newton(z, q, tol, step_tol, ahead, maxiter, radius, k0, dirs, fdirs, mdirs, site_at, angle_given,
            follower, bounds, n_state, rtol, atol):
    """Damped Newton on the end conditions (module docstring). Converged: |r| < 1e-3 tol, or |r| <
    tol and a step below ``step_tol`` (1 + |z|): the step that led to z, or with ``ahead`` the step
    from z (J^-1 r, known before integrating again: a path point stops one integration earlier).
    A path corrector (finite ``radius``) is not damped: a trial point farther than ``radius`` from
    the start point z (the continuation rejects a corrector that leaves this ball anyway) counts as
    a failed trial, the step halved without integrating it, and a full step whose residual does not
    fall ends the corrector, not converged: a corrector that needs damping is a sign of a step
    too long for the predictor, which the continuation then halves (the integrations of a corrector
    wandering off the path are not paid).
    Returns (z, status, iterations, residual norm, Jacobian, boundary states and tip force at z): z
    is the last accepted point (with maxiter = 0 the start point, evaluated). One residual call site
    (the start point, then every trial point), so the compiled code holds one copy of the integrator."""
    it, t, norm, started = 0, 1.0, math.inf, False
    dz = np.zeros_like(z)
    z_try, center = z, z
    while True:
        r_new, J_new, states_new, F_new, ok = _residual(z_try, q, k0, dirs, fdirs, mdirs, site_at,
                                                        angle_given, follower, bounds, n_state, rtol, atol)
        if not started:
            if not ok:
                return z, NO_START, 0, math.inf, J_new, states_new, F_new
            started = True
            r, J, states, F, norm = r_new, J_new, states_new, F_new, _norm(r_new)
            if maxiter == 0:
                return z, NOT_CONVERGED, 0, norm, J, states, F
        elif ok and _norm(r_new) < max(norm, 1e-300) * (1 - 1e-4 * t) + 1e-14:
            z, r, J, states, F, norm = z_try, r_new, J_new, states_new, F_new, _norm(r_new)
            if (norm < tol and t * _norm(dz) < step_tol * (1.0 + _norm(z))) or norm < 1e-3 * tol:
                return z, CONVERGED, it, norm, J, states, F
        elif radius < math.inf:     # a path corrector that needs damping: the step is too long
            return z, NOT_CONVERGED, it, norm, J, states, F
        else:
            z_try, t = _trial(z, 0.5 * t, dz, center, radius)
            if t < 1e-3:        # no descent left: converged only if already at the noise floor
                return z, CONVERGED if norm < tol else NOT_CONVERGED, it, norm, J, states, F
            continue
        minus_r = np.empty(r.size)
        for i in range(r.size):
            minus_r[i] = -r[i]
        dz, regular = _solve(J, minus_r)
        if ahead and regular and norm < tol and _norm(dz) < step_tol * (1.0 + _norm(z)):
            return z, CONVERGED, it, norm, J, states, F
        it += 1
        if it > maxiter or not regular:
            return z, NOT_CONVERGED, min(it, maxiter), norm, J, states, F
        z_try, t = _trial(z, 1.0, dz, center, radius)
        if t < 1e-3:            # every descent step leaves the trust region
            return z, NOT_CONVERGED, it, norm, J, states, F


@njit(cache=True, error_model="numpy", no_cpython_wrapper=True)
def _step_cap(rate, rate_prev, dlam, max_rotation_step, max_position_step):
    """The longest step whose predicted tip motion stays within both limits: the tip's rate and,
    when ``dlam`` > 0, its change (rate - rate_prev)/dlam since the previous point."""
    accel = np.zeros(3)
    if dlam > 0.0:
        for i in range(3):
            accel[i] = (rate[i] - rate_prev[i]) / dlam
    return min(_reach(abs(rate[2]), abs(accel[2]), max_rotation_step),
               _reach(math.hypot(rate[0], rate[1]), math.hypot(accel[0], accel[1]), max_position_step))


@njit(cache=True, error_model="numpy")
def _reach(speed, accel, limit):
    """The largest step h whose predicted tip motion, speed h + accel h^2 / 2 (a second-order
    Taylor bound along the path), stays within ``limit``."""
    if speed <= 0.0 and accel <= 0.0:
        return math.inf
    return 2.0 * limit / (speed + math.sqrt(speed * speed + 2.0 * accel * limit))


# follow_path status: converged, continuation stalled, integration failed at the start, final
# corrector failed
PATH_CONVERGED, PATH_STALLED, PATH_NO_START, PATH_FINAL_FAILED = 0, 1, 2, 3


@njit(cache=True, error_model="numpy")
def follow_path(z, q0, q1, k0, dirs, fdirs, mdirs, site_at, angle_given, follower, bounds, rtol, atol,
                tol, path_rtol, initial_step, min_step, max_rotation_step, max_position_step,
                max_corrector, max_step_iterations, maxiter):
    """Continuation from (z, q0) to q1 (``shooting`` module docstring): tangent predictor (from the
    Jacobian of the last accepted point), Newton corrector at ``path_rtol`` with the step rejections,
    then the final corrector at ``rtol``/``tol``. One Newton call site (the start point is evaluated by
    a Newton of 0 iterations; the final corrector is the last call): one compiled copy of it.
    The sensitivities to the distributed load are integrated only when the path changes it.
    Returns (z, status, load fraction reached, Newton iterations, accepted steps, residual norm,
    and when converged the boundary states and tip force at z)."""
    path_atol = path_rtol * 0.1
    last = bounds.size - 1
    dq = _axpy(q1, -1.0, q0)
    n_state = STATE_SIZE if (dq[dq.size - 2] != 0.0 or dq[dq.size - 1] != 0.0) else FORCE_STATE_SIZE
    lam, dlam, lam_try, lam_prev, curvature = 0.0, min(initial_step, 1.0), 0.0, 0.0, 0.0
    nit, nsteps, norm = 0, 0, 0.0
    started, regular = False, True
    dz, tip, step, rate = np.zeros_like(z), np.zeros(3), np.zeros_like(z), np.zeros(3)
    reach = math.inf
    while True:
        final = started and lam >= 1.0
        radius = math.inf
        if not started:
            q, z_guess, ntol, nrtol, natol, nmax = q0, z, 0.0, path_rtol, path_atol, 0
        elif final:       # final corrector at full accuracy
            q, z_guess, ntol, nrtol, natol, nmax = _axpy(q0, lam, dq), z, tol, rtol, atol, maxiter
        else:
            lam_try = min(1.0, lam + min(dlam, reach))
            q = _axpy(q0, lam_try, dq)
            step = _axpy(np.zeros_like(z), lam_try - lam, dz) if regular else np.zeros_like(z)
            # a step whose corrector needs more than max_step_iterations is rejected: stop there
            z_guess, ntol, nrtol, natol = _axpy(z, 1.0, step), 10 * path_rtol, path_rtol, path_atol
            nmax = min(maxiter, max_step_iterations)
            if regular:     # the corrector may move z this far from the predictor (the step test below)
                bend = curvature * (lam_try - lam) ** 2         # twice the predictor's expected miss
                radius = max_corrector * _norm(step) + bend + 1e-6 * (1.0 + _norm(z))
        z_new, nstat, it, norm, J, states, F = _newton(z_guess, q, ntol, 1e-9 if final else ntol, not final, nmax,
                                                       radius, k0, dirs, fdirs, mdirs, site_at, angle_given,
                                                       follower, bounds, n_state, nrtol, natol)
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
                ok = (it <= max_step_iterations and abs(new_tip[2] - tip[2]) <= max_rotation_step
                      and moved <= max_position_step and _distance(z_new, z_guess) <= radius)
            if ok:
                z, lam_prev, lam = z_new, lam, lam_try
                nsteps += 1
                if it <= 3:
                    dlam = min(2.0 * dlam, 1.0)
        if ok:                  # the tangent at the new point, and the path's curvature |z''| since the last
            dz_prev, was_regular = dz, regular
            rate_prev = rate
            dz, regular, rate = _tangent(z, _axpy(q0, lam, dq), J, states, dq, dirs, fdirs, mdirs, site_at,
                                         angle_given, follower)
            secant = nsteps > 0 and regular and was_regular   # the last two points give z'' and the tip's
            if secant:
                curvature = _norm(_axpy(dz, -1.0, dz_prev)) / (lam - lam_prev)
            reach = _step_cap(rate, rate_prev, lam - lam_prev if secant else 0.0, max_rotation_step,
                              max_position_step) if regular else math.inf
            tip = new_tip.copy()
        else:                   # halve the step tried (dlam itself may reach past lambda = 1)
            dlam = 0.5 * (lam_try - lam)
            if dlam < min_step:
                return z, PATH_STALLED, lam, nit, nsteps, norm, states, F
