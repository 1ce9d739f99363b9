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

``beam_rhs`` is the plain beam (x, y, theta, m, U) (BEAM_STATE_SIZE = 5): a beam of a mechanism
(`mechanism` explains it; physical units, optionally axially extensible, EA > 0; EA = 0 stands for
inextensible) and the elastica's shape samples and section moments (EI = 1, EA = 0). With the
section force N(s) = F + w (l - s) (a uniform dead load w per unit length over the length l outboard
of s; 0 for a mechanism beam), Nt = N . t the axial force and e = Nt/EA:

    x' = (1 + e) cos(theta),  y' = (1 + e) sin(theta),  theta' = kappa0 + m/EI,
    m' = (1 + e) (Nx sin(theta) - Ny cos(theta)),   U' = m^2/(2 EI) + Nt^2/(2 EA).

With a state of BEAM_SENSITIVITY_STATE_SIZE = 21 entries ``beam_rhs`` adds the plain beam's
variational equations: beside (x, y, theta, m, U), the derivatives of (x, y, theta, m) with respect
to the start angle, the start moment and the end force, p = (theta0, m0, Fx, Fy), row-major (index
5 + 4 i + j: row i of (x, y, theta, m), column j of p). With Q = Nx sin(theta) - Ny cos(theta) (so
m' = (1 + e) Q) and dN = (dFx, dFy) (constant along the beam: the distributed load does not depend
on p):

    dNt = -Q dtheta + cos(theta) dNx + sin(theta) dNy,   de = dNt/EA,
    (dx)' = de cos(theta) - (1 + e) sin(theta) dtheta,   (dy)' = de sin(theta) + (1 + e) cos(theta) dtheta,
    (dtheta)' = dm/EI,   (dm)' = de Q + (1 + e) (Nt dtheta + sin(theta) dNx - cos(theta) dNy),

from d(theta, m)(0) = the unit vectors of theta0 and m0, d(x, y)(0) = 0. A mechanism's Newton takes a
beam's block of its Jacobian from them (one integration instead of one per input).

The integrator picks the equations by the state's length (25 or 17: the elastica with its
sensitivities, 21: the plain beam with its variational equations, 5: the plain beam).

``_samples`` integrates by scipy's ``solve_ivp(method="DOP853")`` (Hairer, Norsett & Wanner, Solving
ODEs I, sec. II.5 and II.4 for the first step) step for step: the same coefficients (scipy's own
tables), the same first-step choice, error norm (the 5th- and 3rd-order estimates combined) and
step-size factors (safety 0.9, between 0.2 and 10, exponent -1/8), so the end state agrees with
scipy's to rounding, without the Python cost of each stage.

The shooting on these integrations (``shooting`` sets it up and reads the result): residual,
Jacobian, Newton corrector and the whole continuation (``follow_path``) are in this one module
because numba's cache only notices changes to the file that defines a cached function, not to the
files of the compiled functions it calls.

The compiled functions take their arguments in a few named groups (``typing.NamedTuple``: numba
passes one as a struct of its fields, so reading a field costs what a scalar argument does), every
one built with each field named (``Beam(length=..., EI=..., ...)``), never by position:

* ``Beam``: what is integrated (length, EI, EA, initial curvature; ``elastica_beam`` for the
  normalised elastica);
* ``Loads``: the end force and the distributed load on it;
* ``Tolerances``: the DOP853 tolerances (rtol, atol);
* ``Structure``: the shooting problem's structure (the normalised elastica ``Beam``, the directions of
  the prescribed tip-position components, the ``UnknownForces``, the integration pieces), built by
  ``shooting``;
* ``UnknownForces``: how the tip force depends on the unknowns z (the directions of the unknown
  forces; a follower force or not), all that ``tip_force`` reads;
* ``Corrector``: the controls of one Newton run, built by ``follow_path`` for each;
* ``PathControls``: the controls of the whole continuation, built by ``shooting.solve_path``.

The continuation parameters q and the unknowns z stay plain vectors: they are interpolated and
solved for as a whole (q(lambda) = q0 + lambda (q1 - q0)).

Compile cost: numba compiles every jitted function on its own and links a copy of each callee into
its caller, where LLVM optimises it and generates its machine code again: code reached through a
chain of separately compiled functions (follow_path -> newton -> residual -> the integrator) is
optimised again at each level of the chain. So only two functions are entry points (``follow_path``
and ``_samples``), and a function that compiled code calls from one place only (``_newton``,
``_residual``, ``_tangent``, ``_tip_rate``, ``_step_cap``, ``_first_step``, ...) is inlined by numba
(``inline='always'``: typed, lowered and optimised only as part of its caller). numba's inlining
copies the callee's IR block by block, each block with all the callee's variables, so the DOP853 step
loop is written out in ``_samples`` rather than inlined into it. A function called from several
places (``_axpy``, ``_norm``, ``_distance``, ``_solve``, ``_trial``, ``_rhs``, ``tip_force``,
``_condition_rows``) stays separate and is compiled once (inlined, it would be typed and lowered once
per call site; LLVM still inlines the small ones). What is the same mathematics is written once: the
end conditions' derivative through the states (``_condition_rows``) serves the Jacobian w.r.t. the
unknowns and the tangent's derivative w.r.t. the continuation parameters, ``beam_rhs`` has the plain
beam's equations and their variations in one body, and the DOP853 stages and the new state are
evaluated at one ``_rhs`` call site. numba compiles a function once per argument types and a literal
``True`` or ``False`` argument is a type of its own, so a choice between derivatives travels as a
group (``Parameters``), whose fields are plain bools. numba compiles each of its own overloads
(``np.zeros``, ``np.empty``, ``min``, ...) once per argument types and per compile options of the
calling function (a helper without the Python wrapper and an entry point each compile their own), so
the code keeps to few of them: ``np.zeros(n)`` rather than ``np.zeros_like``, ``x * x`` rather than
``x ** 2`` (a compiled integer power; the product is the same number), ``len(a)`` rather than
``a.shape[0]`` (an index into the shape is an overload of its own without numba's rewrites, below).
The code uses loops instead of whole-array expressions, whose broadcasting checks drag numba's string
formatting of error messages into every function that has one, and keeps its multiple assignments
short (four or more names at once are packed into a tuple and unpacked again in the compiled code).
Options, each on every function: ``error_model="numpy"``, a float division by zero gives inf/nan
instead of raising, so no exception branch per division is generated (every division here has a
nonzero divisor by construction); ``no_rewrites=True``, numba skips its rewrite passes (for
whole-array expressions and raises with constant arguments, none here; a constant index stays an
ordinary index, compiled to the same machine code); ``no_cfunc_wrapper=True``, no C-callable wrapper
is built (nothing takes a compiled function's address). ``no_cpython_wrapper=True`` on the helpers
only compiled code calls (not on ``tip_force``, which `shooting` calls, nor ``_reach``, which a test
calls): numba builds and optimises no Python-callable wrapper for them (LLVM time saved on each
helper).

One problem structure (``Structure``, normalised by L and EI, ``shooting`` derives the equations):

* ``dirs`` (nc, 2): unit directions d_k of the prescribed tip-position components, end condition
  d_k . r(1) = c_k; ``forces.force_dirs`` (nc, 2): the directions f_k of their unknown forces
  (multipliers mu_k);
* ``forces.moment_dirs`` (nm, 2): the directions g_j of the unknown forces of the prescribed section
  moments (multipliers nu_j), end condition m(s_j) = m_j; ``bounds``: the integration piece
  boundaries 0 < knots < 1 (the interior sites s_j), ``site_at`` (nm,): the boundary index of each s_j;
* ``angle_given``: theta(1) = q[ANGLE] replaces m(1) = M; ``forces.follower``: the last unknown is the
  tip angle tau and F = F_dead + R(tau) (ft, fn), with the end condition theta(1) = tau.

Unknowns z = [m(0), mu_1..mu_nc, nu_1..nu_nm, (tau)]; continuation parameters q = [Fx, Fy, M, ft, fn,
c_1..c_nc, m_1..m_nm, angle, wx, wy]. The tip force is F(z, q) = (Fx, Fy) + sum mu_k f_k + sum nu_j g_j
(+ R(tau) (ft, fn)), so d(state)/dz = S_m0 e_0^T + S_F dF/dz with S the sensitivities the integrator
carries (``elastica_rhs``). The Jacobian of the residual r(z, q) w.r.t. z and its derivative w.r.t. q
(the tangent predictor dz/dlambda = -J^-1 (dr/dq) dq) come from the same sensitivities.

Newton: full step, halved (down to 1/1000) until the residual norm falls by the Armijo factor
1 - 1e-4 t (the start and the final corrector; a corrector along the path is not damped and stays
within its trust region, ``_newton``); a point z is converged when |r(z)| < tol and the Newton step from z,
J(z)^-1 r(z), is below ``step_tol`` (1 + |z|) (1e-9 for the final corrector, the path tolerance for
the points along the path, which only start the next step), or |r| < 1e-3 tol.
A singular Jacobian or a failed integration ends it (status codes below).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray
from scipy.integrate._ivp import dop853_coefficients as _coef  # the tables scipy's DOP853 uses

__all__ = [
    "STATE_SIZE",
    "FORCE_STATE_SIZE",
    "BEAM_STATE_SIZE",
    "BEAM_SENSITIVITY_STATE_SIZE",
    "ANGLE",
    "Beam",
    "Loads",
    "Tolerances",
    "UnknownForces",
    "Structure",
    "Corrector",
    "PathControls",
    "elastica_beam",
    "elastica_rhs",
    "beam_rhs",
    "integrate_samples",
    "integrate_beam",
    "beam_sensitivities",
    "beam_samples",
    "plain_samples",
    "tip_force",
    "follow_path",
]

Vector = NDArray[np.float64]
Matrix = NDArray[np.float64]

STATE_SIZE = 25
FORCE_STATE_SIZE = 17
BEAM_STATE_SIZE = 5
BEAM_SENSITIVITY_STATE_SIZE = BEAM_STATE_SIZE + 16
_N_STAGES: int = _coef.N_STAGES
_A: Matrix = np.ascontiguousarray(_coef.A[:_N_STAGES, :_N_STAGES])
_B: Vector = np.ascontiguousarray(_coef.B)
_C: Vector = np.ascontiguousarray(_coef.C[: _N_STAGES + 1])  # the stages' times, then the new state's: c = 1
_E3: Vector = np.ascontiguousarray(_coef.E3)
_E5: Vector = np.ascontiguousarray(_coef.E5)
_AB: Matrix = np.ascontiguousarray(np.vstack([_A, _B]))  # the stage rows of A, then B (one stage-sum site)
SAFETY, MIN_FACTOR, MAX_FACTOR, ERROR_EXPONENT = 0.9, 0.2, 10.0, -1.0 / 8.0


# ------------------------------------------------------------------ the argument groups


class Beam(NamedTuple):
    """The beam integrated from s = 0: a mechanism beam in physical units, or the elastica
    normalised by L and EI, ``Beam(length=1.0, EI=1.0, EA=0.0, curvature=kappa0 L)`` (``elastica_beam``;
    ``elastica_rhs`` reads only its curvature, ``beam_rhs`` on the elastica's plain state all four)."""

    length: float  # l, the beam's length: the distributed load acts on [s, l] (length)
    EI: float  # bending stiffness (force length^2)
    EA: float  # axial stiffness (force); 0: inextensible
    curvature: float  # kappa0, the initial (stress-free) curvature (1/length)


class Loads(NamedTuple):
    """The loads on the beam, global frame: the end force F = (Fx, Fy) at its outboard end (force;
    the elastica's: F L^2/EI) and a uniform dead load w = (wx, wy) per unit length over the whole
    beam (force/length, per unit reference length; the elastica's: w L^3/EI)."""

    Fx: float
    Fy: float
    wx: float
    wy: float


class Tolerances(NamedTuple):
    """DOP853's relative and absolute tolerances, as scipy's ``rtol`` and ``atol``: a step is accepted
    when its error estimate, component by component over atol + rtol |y|, has an rms norm below 1."""

    rtol: float
    atol: float


class UnknownForces(NamedTuple):
    """How the tip force depends on the unknowns z (normalised, module docstring):

        F(z, q) = (q[0], q[1]) + sum_k mu_k f_k + sum_j nu_j g_j (+ R(tau) (q[3], q[4])),

    mu_k = z[1 + k], nu_j = z[1 + nc + j] and, with a follower force, tau = z[-1] the tip angle."""

    force_dirs: Vector  # f_k (nc, 2) unit vectors: the unknown force of tip condition k
    moment_dirs: Vector  # g_j (nm, 2) unit vectors: the unknown force of section moment j
    follower: bool  # a follower force (ft, fn) = (q[3], q[4]) in the tip frame, tau unknown


class Structure(NamedTuple):
    """One shooting problem's structure, normalised by L and EI (module docstring, ``shooting``):
    ``dirs`` (nc, 2) unit vectors, ``bounds`` the piece boundaries [0, s_j..., 1] (arc length / L,
    increasing), ``site_at`` (nm,) the index in ``bounds`` of each prescribed-moment site s_j."""

    beam: Beam  # the elastica: length = EI = 1, EA = 0, curvature kappa0 L
    dirs: Vector  # d_k: end condition d_k . r(1) = c_k
    forces: UnknownForces  # the unknown forces of the end conditions
    bounds: Vector  # integration piece boundaries, 0 and 1 included
    site_at: NDArray[np.int64]  # bounds[site_at[j]] = s_j
    angle_given: bool  # the end condition theta(1) = q[ANGLE] replaces m(1) = M


class Corrector(NamedTuple):
    """The controls of one Newton run (``_newton``): converged when |r| < ``tol`` and the step is below
    ``step_tol`` (1 + |z|), or |r| < 1e-3 tol; ``ahead``: the step tested is the one from the point
    (J^-1 r) instead of the one that led to it; at most ``maxiter`` iterations; ``radius``: the
    trust region about the start point (inf: none, the step damped instead)."""

    tol: float  # on the norm of the normalised residual
    step_tol: float  # on |dz| / (1 + |z|)
    ahead: bool
    maxiter: int
    radius: float  # on |z - z_start|


class PathControls(NamedTuple):
    """The controls of a continuation (``follow_path``; ``shooting.solve_path`` explains each): the
    final corrector's integration tolerances and residual tolerance, the path's integration
    tolerances (the corrector of a path point stops at 10 path.rtol), and the step control."""

    final: Tolerances  # DOP853 tolerances of the final corrector
    tol: float  # residual tolerance of the final corrector
    path: Tolerances  # DOP853 tolerances along the path
    initial_step: float  # first step in the load fraction lambda
    min_step: float  # smallest step in lambda before the path is declared stalled
    max_rotation_step: float  # tip rotation a step may make (rad)
    max_position_step: float  # tip motion a step may make (of L)
    max_corrector: float  # corrector distance allowed, in predicted changes of z
    max_step_iterations: int  # Newton iterations a path point may take
    maxiter: int  # Newton iterations of the final corrector


class Parameters(NamedTuple):
    """The parameters p of a derivative of the state, d(x, y, theta, m)/dp (``_state_derivative``):
    beside the tip force, through which they all act (dF/dp), p[0] may be the start moment m(0) (the
    unknowns z, ``UNKNOWNS``) and the last two the distributed load (wx, wy) (the continuation
    parameters q, ``CONTINUATION``)."""

    start_moment: bool  # p[0] is m(0)
    distributed_load: bool  # p[-2:] is (wx, wy)


UNKNOWNS = Parameters(start_moment=True, distributed_load=False)  # p = z
CONTINUATION = Parameters(start_moment=False, distributed_load=True)  # p = q


# ------------------------------------------------------------------ the equations and DOP853


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def elastica_rhs(s: float, Y: Vector, beam: Beam, loads: Loads, out: Vector) -> None:
    """dY/ds into ``out`` (layout in the module docstring: STATE_SIZE entries, or FORCE_STATE_SIZE
    without the sensitivities to the distributed load) for the normalised elastica ``beam`` (only
    its curvature enters) under ``loads`` (normalised)."""
    th, m = Y[2], Y[3]
    c, sn = math.cos(th), math.sin(th)
    outboard = 1.0 - s
    Nx, Ny = loads.Fx + loads.wx * outboard, loads.Fy + loads.wy * outboard
    g = Nx * c + Ny * sn
    out[0] = c
    out[1] = sn
    out[2] = beam.curvature + m
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
    for k in range(2):  # sensitivities to (wx, wy)
        t_k = Y[21 + k]
        out[17 + k] = -sn * t_k
        out[19 + k] = c * t_k
        out[21 + k] = Y[23 + k]
        out[23 + k] = g * t_k
    out[23] += outboard * sn
    out[24] -= outboard * c


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def beam_rhs(s: float, Y: Vector, beam: Beam, loads: Loads, out: Vector) -> None:
    """dY/ds into ``out`` for the plain beam (module docstring) under ``loads``, the distributed
    load acting over [s, beam.length], and for its variational equations when Y has them
    (BEAM_SENSITIVITY_STATE_SIZE entries)."""
    th, m = Y[2], Y[3]
    EI, EA = beam.EI, beam.EA
    c, sn = math.cos(th), math.sin(th)
    outboard = beam.length - s
    Nx, Ny = loads.Fx + loads.wx * outboard, loads.Fy + loads.wy * outboard
    Nt, Q = Nx * c + Ny * sn, Nx * sn - Ny * c
    stretch = 1.0 + (Nt / EA if EA != 0.0 else 0.0)
    out[0] = stretch * c
    out[1] = stretch * sn
    out[2] = beam.curvature + m / EI
    out[3] = stretch * Q
    out[4] = m * m / (2 * EI) + (Nt * Nt / (2 * EA) if EA != 0.0 else 0.0)
    if Y.size < BEAM_SENSITIVITY_STATE_SIZE:
        return
    compliance = 1.0 / EA if EA != 0.0 else 0.0
    for j in range(4):  # p = (theta0, m0, Fx, Fy)
        dth, dm = Y[13 + j], Y[17 + j]
        dNx = 1.0 if j == 2 else 0.0
        dNy = 1.0 if j == 3 else 0.0
        de = (-Q * dth + c * dNx + sn * dNy) * compliance
        out[5 + j] = de * c - stretch * sn * dth
        out[9 + j] = de * sn + stretch * c * dth
        out[13 + j] = dm / EI
        out[17 + j] = de * Q + stretch * (Nt * dth + sn * dNx - c * dNy)


@njit(cache=True, error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _rhs(s: float, Y: Vector, beam: Beam, loads: Loads, out: Vector) -> None:
    """The equations the state's length names (BEAM_STATE_SIZE: the plain beam,
    BEAM_SENSITIVITY_STATE_SIZE: with its variational equations, else the elastica with its
    sensitivities)."""
    if Y.size == BEAM_STATE_SIZE or Y.size == BEAM_SENSITIVITY_STATE_SIZE:
        beam_rhs(s, Y, beam, loads, out)
    else:
        elastica_rhs(s, Y, beam, loads, out)


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _first_step(
    y0: Vector, f: Vector, t0: float, interval: float, beam: Beam, loads: Loads, tolerances: Tolerances
) -> float:
    """scipy's select_initial_step (order 7); rms norms as plain loops."""
    rtol, atol = tolerances.rtol, tolerances.atol
    n = y0.size
    f1 = np.empty(n)
    y1 = np.empty(n)
    d0 = d1 = 0.0
    for i in range(n):
        sc = atol + abs(y0[i]) * rtol
        u0, u1 = y0[i] / sc, f[i] / sc
        d0 += u0 * u0
        d1 += u1 * u1
    d0, d1 = math.sqrt(d0 / n), math.sqrt(d1 / n)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, interval)
    for i in range(n):
        y1[i] = y0[i] + h0 * f[i]
    _rhs(t0 + h0, y1, beam, loads, f1)
    d2 = 0.0
    for i in range(n):
        sc = atol + abs(y0[i]) * rtol
        u2 = (f1[i] - f[i]) / sc
        d2 += u2 * u2
    d2 = math.sqrt(d2 / n) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    return min(100 * h0, h1, interval)


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _combine(K: Matrix, w: Vector, count: int, out: Vector) -> None:
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


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _error_norm(K: Matrix, y: Vector, y_new: Vector, h: float, tolerances: Tolerances) -> float:
    """scipy's DOP853 error norm of a step from y to y_new with the stage derivatives K."""
    rtol, atol = tolerances.rtol, tolerances.atol
    n = y.size
    e5, e3 = 0.0, 0.0
    for i in range(n):
        sc = atol + max(abs(y[i]), abs(y_new[i])) * rtol
        a5, a3 = 0.0, 0.0
        for j in range(len(K)):
            a5 += K[j, i] * _E5[j]
            a3 += K[j, i] * _E3[j]
        a5, a3 = a5 / sc, a3 / sc
        e5 += a5 * a5
        e3 += a3 * a3
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)


@njit(cache=True, error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _samples(
    y0: Vector, s: Vector, beam: Beam, loads: Loads, tolerances: Tolerances, restart: bool
) -> tuple[Matrix, bool]:
    """States at the arc lengths s by DOP853 (module docstring), integrated from sample to sample;
    each interval starts with the step the controller proposed at the end of the previous one (the
    first, and every one when ``restart``, with scipy's initial-step selection). False when a step
    fell below scipy's minimum. The one compiled entry point of the integrator besides the shooting."""
    AB, C = _AB, _C  # global arrays: compile-time constants for numba
    n = y0.size
    out = np.empty((s.size, n))
    K = np.empty((len(AB), n))  # the stage derivatives: the first row f at y, the last f at the new state
    last = len(K) - 1
    f = K[0]
    y = y0.copy()
    y_new = np.empty(n)  # each stage's state, the new state last
    acc = np.empty(n)
    for i in range(n):
        out[0, i] = y0[i]
    h_abs = 0.0
    for k in range(1, s.size):
        t, t1 = s[k - 1], s[k]
        _rhs(t, y, beam, loads, f)
        interval = t1 - t
        if interval > 0.0 and (restart or h_abs <= 0.0):
            h_abs = _first_step(y, f, t, interval, beam, loads, tolerances)
        while t < t1:
            min_step = 10 * abs(np.nextafter(t, np.inf) - t)
            if h_abs < min_step:
                h_abs = min_step
            rejected = False
            while True:
                if h_abs < min_step:
                    return out, False
                t_new = t + h_abs
                if t_new > t1:
                    t_new = t1
                h = t_new - t
                h_abs = abs(h)
                for j in range(1, len(AB)):  # the stages, then (the last row, B) the new state at t + h
                    _combine(K, AB[j], j, acc)
                    for i in range(n):
                        y_new[i] = y[i] + acc[i] * h
                    _rhs(t + C[j] * h, y_new, beam, loads, K[j])
                error_norm = _error_norm(K, y, y_new, h, tolerances)
                if error_norm < 1.0:
                    factor = MAX_FACTOR if error_norm == 0.0 else min(MAX_FACTOR, SAFETY * error_norm**ERROR_EXPONENT)
                    if rejected:
                        factor = min(1.0, factor)
                    h_abs *= factor
                    break
                h_abs *= max(MIN_FACTOR, SAFETY * error_norm**ERROR_EXPONENT)
                rejected = True
            t = t_new
            for i in range(n):
                y[i] = y_new[i]
                f[i] = K[last, i]
        for i in range(n):
            out[k, i] = y[i]
    return out, True


def elastica_beam(curvature: float) -> Beam:
    """The elastica normalised by L and EI (inextensible): ``Beam`` of unit length and EI, initial
    curvature ``curvature`` = kappa0 L."""
    return Beam(length=1.0, EI=1.0, EA=0.0, curvature=float(curvature))


def integrate_beam(
    y0: ArrayLike,
    length: float,
    Fx: float,
    Fy: float,
    k0: float,
    EI: float,
    EA: float,
    rtol: float,
    atol: float,
    wx: float = 0.0,
    wy: float = 0.0,
) -> tuple[Vector, bool]:
    """A mechanism beam's state (x, y, theta, m, U) at s = length from y0 at s = 0 (physical units:
    end force (Fx, Fy), initial curvature k0, stiffnesses EI and EA, EA = 0: inextensible, a uniform
    dead load (wx, wy) per unit reference length along the beam), and whether the integration
    succeeded."""
    return _beam_end(np.asarray(y0, dtype=float), length, Fx, Fy, k0, EI, EA, rtol, atol, wx, wy)


def _beam_end(
    y0: Vector,
    length: float,
    Fx: float,
    Fy: float,
    k0: float,
    EI: float,
    EA: float,
    rtol: float,
    atol: float,
    wx: float,
    wy: float,
) -> tuple[Vector, bool]:
    """The state at s = length of a mechanism beam integrated from ``y0`` (the plain state, or with its
    variational equations: ``_samples`` reads which from y0's size), and whether it succeeded."""
    length = float(length)
    states, ok = _samples(
        y0,
        np.array([0.0, length]),
        Beam(length=length, EI=float(EI), EA=float(EA), curvature=float(k0)),
        Loads(Fx=float(Fx), Fy=float(Fy), wx=float(wx), wy=float(wy)),
        Tolerances(rtol=float(rtol), atol=float(atol)),
        True,
    )
    end: Vector = states[-1]
    return end, ok


def beam_sensitivities(
    y0: ArrayLike,
    length: float,
    Fx: float,
    Fy: float,
    k0: float,
    EI: float,
    EA: float,
    rtol: float,
    atol: float,
    wx: float = 0.0,
    wy: float = 0.0,
) -> tuple[Vector, Matrix, bool]:
    """A mechanism beam's state (x, y, theta, m, U) at s = length from y0 = (x0, y0, theta0, m0, U0) at
    s = 0, its derivative d(x, y, theta, m)/d(theta0, m0, Fx, Fy) (4, 4) by the variational equations
    (``beam_rhs``), and whether the integration succeeded (the arguments as
    ``integrate_beam``'s; the tolerances hold on the state and its derivatives alike)."""
    y = np.zeros(BEAM_SENSITIVITY_STATE_SIZE)
    y[:BEAM_STATE_SIZE] = np.asarray(y0, dtype=float)
    y[13] = 1.0  # d theta(0) / d theta0
    y[18] = 1.0  # d m(0) / d m0
    end, ok = _beam_end(y, length, Fx, Fy, k0, EI, EA, rtol, atol, wx, wy)
    return end[:BEAM_STATE_SIZE], end[BEAM_STATE_SIZE:].reshape(4, 4), ok


def integrate_samples(
    y0: ArrayLike,
    s: ArrayLike,
    Fx: float,
    Fy: float,
    k0: float,
    rtol: float,
    atol: float,
    wx: float = 0.0,
    wy: float = 0.0,
) -> tuple[Matrix, bool]:
    """The elastica states (len(s), len(y0): STATE_SIZE or FORCE_STATE_SIZE) at the increasing arc
    lengths ``s`` (s[0]: the start of y0), integrated from sample to sample, under the tip force
    (Fx, Fy) and distributed load (wx, wy) with initial curvature k0 (normalised), and whether every
    interval succeeded."""
    samples: tuple[Matrix, bool] = _samples(
        np.asarray(y0, dtype=float),
        np.ascontiguousarray(s, dtype=float),
        elastica_beam(k0),
        Loads(Fx=float(Fx), Fy=float(Fy), wx=float(wx), wy=float(wy)),
        Tolerances(rtol=float(rtol), atol=float(atol)),
        False,
    )
    return samples


def plain_samples(
    y0: ArrayLike, s: ArrayLike, beam: Beam, loads: Loads, tolerances: Tolerances, restart: bool = False
) -> tuple[Matrix, bool]:
    """The elastica's plain states (x, y, theta, m, U) (normalised: ``beam`` from ``elastica_beam``,
    no sensitivities) at the increasing arc lengths ``s`` from y0 at s[0]; ``restart``: every
    interval starts with scipy's initial-step selection (as the shooting's pieces do). And whether
    every interval succeeded."""
    samples: tuple[Matrix, bool] = _samples(
        np.asarray(y0, dtype=float)[:BEAM_STATE_SIZE],
        np.ascontiguousarray(s, dtype=float),
        beam,
        loads,
        tolerances,
        bool(restart),
    )
    return samples


def beam_samples(
    y0: ArrayLike,
    s: ArrayLike,
    Fx: float,
    Fy: float,
    k0: float,
    EI: float,
    EA: float,
    rtol: float,
    atol: float,
    wx: float = 0.0,
    wy: float = 0.0,
) -> tuple[Matrix, bool]:
    """A mechanism beam's states (len(s), BEAM_STATE_SIZE) at the increasing arc lengths ``s``
    (s[0]: the start of y0), integrated from sample to sample, and whether every interval succeeded
    (the arguments as ``integrate_beam``'s)."""
    arc = np.ascontiguousarray(s, dtype=float)
    samples: tuple[Matrix, bool] = _samples(
        np.asarray(y0, dtype=float),
        arc,
        Beam(length=float(arc[-1]), EI=float(EI), EA=float(EA), curvature=float(k0)),
        Loads(Fx=float(Fx), Fy=float(Fy), wx=float(wx), wy=float(wy)),
        Tolerances(rtol=float(rtol), atol=float(atol)),
        False,
    )
    return samples


# ------------------------------------------------------------------ shooting (residual, Newton, path)

ANGLE = -3  # index of the prescribed tip angle in q; the last two are (wx, wy)
# newton status: converged, not converged, integration failed at the start point
CONVERGED, NOT_CONVERGED, NO_START = 0, 1, 2


@njit(cache=True, error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _norm(v: Vector) -> float:
    """Euclidean norm (a plain loop: the systems have at most a handful of unknowns)."""
    total = 0.0
    for x in v:
        total += x * x
    return math.sqrt(total)


@njit(cache=True, error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _distance(a: Vector, b: Vector) -> float:
    """Euclidean distance |a - b| (a plain loop)."""
    total = 0.0
    for i in range(a.size):
        d = a[i] - b[i]
        total += d * d
    return math.sqrt(total)


@njit(cache=True, error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _axpy(x: Vector, a: float, d: Vector) -> Vector:
    """x + a d as a new array (a loop: no broadcasting checks to compile)."""
    out = np.empty(x.size)
    for i in range(x.size):
        out[i] = x[i] + a * d[i]
    return out


@njit(cache=True, error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _solve(A: Matrix, b: Vector) -> tuple[Vector, bool]:
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


@njit(cache=True, error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def tip_force(z: Vector, q: Vector, forces: UnknownForces) -> tuple[Vector, Matrix]:
    """Tip force F (2,) and dF/dz (2, n) at the unknowns z and parameters q (normalised; ``forces``
    says how F depends on them)."""
    fdirs, mdirs = forces.force_dirs, forces.moment_dirs
    n = z.size
    F = np.zeros(2)
    F[0], F[1] = q[0], q[1]
    dF = np.zeros((2, n))
    nc = len(fdirs)
    for k in range(nc + len(mdirs)):
        d0, d1 = (fdirs[k, 0], fdirs[k, 1]) if k < nc else (mdirs[k - nc, 0], mdirs[k - nc, 1])
        F[0] += z[1 + k] * d0
        F[1] += z[1 + k] * d1
        dF[0, 1 + k] = d0
        dF[1, 1 + k] = d1
    if forces.follower:
        tau = z[n - 1]
        c, s = math.cos(tau), math.sin(tau)
        ft, fn = q[3], q[4]
        F[0] += c * ft - s * fn
        F[1] += s * ft + c * fn
        dF[0, n - 1] = -s * ft - c * fn
        dF[1, n - 1] = c * ft - s * fn
    return F, dF


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _state_derivative(Y: Vector, dF: Matrix, parameters: Parameters) -> Matrix:
    """(4, m): d(x, y, theta, m)/dp of the state Y (``integrator`` layout) for the parameters p
    (``Parameters``): through the tip force, dF = dF/dp (2, m), and as ``parameters`` says through
    m(0) (column 0) and the distributed load (the last two columns)."""
    _, m = dF.shape
    D = np.zeros((4, m))
    for i in range(4):
        sx, sy = Y[5 + 3 * i + 1], Y[5 + 3 * i + 2]  # d(row i)/dFx, d(row i)/dFy
        for j in range(m):
            D[i, j] = sx * dF[0, j] + sy * dF[1, j]
        if parameters.start_moment:
            D[i, 0] += Y[5 + 3 * i]
        if parameters.distributed_load:
            D[i, m - 2] += Y[17 + 2 * i]
            D[i, m - 1] += Y[18 + 2 * i]
    return D


@njit(cache=True, error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _condition_rows(
    states: Matrix, dF: Matrix, parameters: Parameters, structure: Structure, n: int
) -> tuple[Matrix, Matrix]:
    """(n, m): the derivative of the n end conditions (``_residual``) w.r.t. the parameters p through
    the states at the piece boundaries (``_state_derivative``: dF = dF/dp), without the conditions'
    own dependence on p; and the tip state's derivative d(x, y, theta, m)(1)/dp (4, m)."""
    dirs, site_at = structure.dirs, structure.site_at
    nc, nm = len(dirs), len(structure.forces.moment_dirs)
    _, m = dF.shape
    rows = np.zeros((n, m))
    for i in range(nm + 1):  # dY/dp at each moment site s_j, then at the tip (the dY used below)
        dY = _state_derivative(states[site_at[i] if i < nm else len(states) - 1], dF, parameters)
        if i < nm:
            for j in range(m):
                rows[1 + nc + i, j] = dY[3, j]
    row = 2 if structure.angle_given else 3  # theta(1) or m(1)
    for j in range(m):
        rows[0, j] = dY[row, j]
    for k in range(nc):
        d0, d1 = dirs[k, 0], dirs[k, 1]
        for j in range(m):
            rows[1 + k, j] = d0 * dY[0, j] + d1 * dY[1, j]
    if structure.forces.follower:
        for j in range(m):
            rows[n - 1, j] = dY[2, j]
    return rows, dY


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _integrate_pieces(
    z: Vector, F: Vector, q: Vector, structure: Structure, tolerances: Tolerances, n_state: int
) -> tuple[Matrix, bool]:
    """The states at the piece boundaries (bounds.size, STATE_SIZE; the first ``n_state`` entries
    integrated, the rest 0) from m(0) = z[0] under the tip force F, and whether all succeeded."""
    bounds = structure.bounds
    y = np.zeros(n_state)
    y[3] = z[0]
    y[5 + 9] = 1.0  # d m(0) / d m0
    loads = Loads(Fx=F[0], Fy=F[1], wx=q[q.size - 2], wy=q[q.size - 1])
    restart = bounds.size > 1  # every piece from scipy's first step (a run-time bool, as Python passes it)
    pieces, ok = _samples(y, bounds, structure.beam, loads, tolerances, restart)
    states = np.zeros((bounds.size, STATE_SIZE))
    for i in range(bounds.size):
        for j in range(n_state):
            states[i, j] = pieces[i, j]
    return states, ok


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _residual(
    z: Vector, q: Vector, structure: Structure, tolerances: Tolerances, n_state: int
) -> tuple[Vector, Matrix, Matrix, Vector, bool]:
    """End-condition residual r (n,), Jacobian dr/dz (n, n), the states at the piece boundaries
    (row 0: s = 0, the last: s = 1) and the tip force F; ok False when the integration failed."""
    dirs, site_at, bounds = structure.dirs, structure.site_at, structure.bounds
    n = z.size
    nc, nm = len(dirs), len(structure.forces.moment_dirs)
    F, dF = tip_force(z, q, structure.forces)
    r = np.zeros(n)
    states, ok = _integrate_pieces(z, F, q, structure, tolerances, n_state)
    if not ok:
        return r, np.zeros((n, n)), states, F, False
    Y = states[bounds.size - 1]
    r[0] = Y[2] - q[q.size + ANGLE] if structure.angle_given else Y[3] - q[2]
    for k in range(nc):
        r[1 + k] = dirs[k, 0] * Y[0] + dirs[k, 1] * Y[1] - q[5 + k]
    for i in range(nm):
        r[1 + nc + i] = states[site_at[i], 3] - q[5 + nc + i]
    J, _ = _condition_rows(states, dF, UNKNOWNS, structure, n)
    if structure.forces.follower:
        r[n - 1] = Y[2] - z[n - 1]
        J[n - 1, n - 1] -= 1.0  # the condition theta(1) = tau
    return r, J, states, F, True


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _load_derivative(z: Vector, states: Matrix, structure: Structure, nq: int) -> tuple[Matrix, Matrix]:
    """d r / d q (n x nq), and d(x, y, theta, m)(1) / d q (4 x nq): the force parameters act through
    the sensitivities to (Fx, Fy) (and the follower's through the tip angle), the distributed load
    (the last two) through its own, the others enter the end conditions directly."""
    n = z.size
    nc, nm = len(structure.dirs), len(structure.forces.moment_dirs)
    dFdq = np.zeros((2, nq))
    dFdq[0, 0] = dFdq[1, 1] = 1.0
    if structure.forces.follower:
        c, sn = math.cos(z[n - 1]), math.sin(z[n - 1])
        dFdq[0, 3], dFdq[1, 3] = c, sn
        dFdq[0, 4], dFdq[1, 4] = -sn, c
    D, dYdq = _condition_rows(states, dFdq, CONTINUATION, structure, n)
    D[0, nq + ANGLE if structure.angle_given else 2] -= 1.0  # the prescribed tip angle or moment
    for k in range(nc):
        D[1 + k, 5 + k] -= 1.0  # the prescribed tip-position components c_k
    for i in range(nm):
        D[1 + nc + i, 5 + nc + i] -= 1.0  # the prescribed section moments m_j
    return D, dYdq


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _tangent(
    z: Vector, q: Vector, J: Matrix, states: Matrix, dq: Vector, structure: Structure
) -> tuple[Vector, bool, Vector]:
    """dz/dlambda along q(lambda) with dq/dlambda = dq, from the Jacobian J and the states of the
    residual at z; False when J is singular; and the tip's rate d(x, y, theta)(1)/dlambda =
    (dY/dz) dz/dlambda + (dY/dq) dq (normalised)."""
    D, dYdq = _load_derivative(z, states, structure, dq.size)
    rhs = np.zeros(z.size)
    for i in range(z.size):
        for j in range(dq.size):
            rhs[i] -= D[i, j] * dq[j]
    dz, regular = _solve(J, rhs)
    return dz, regular, _tip_rate(z, q, states, dz, dYdq, dq, structure)


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _tip_rate(
    z: Vector, q: Vector, states: Matrix, dz: Vector, dYdq: Matrix, dq: Vector, structure: Structure
) -> Vector:
    """d(x, y, theta)(1)/dlambda = (dY/dz) dz/dlambda + (dY/dq) dq at the tip, from the states of the
    residual at z (dY/dz: ``_condition_rows``)."""
    _, dF = tip_force(z, q, structure.forces)
    _, dYdz = _condition_rows(states, dF, UNKNOWNS, structure, z.size)
    rate = np.zeros(3)
    for i in range(3):
        for j in range(z.size):
            rate[i] += dYdz[i, j] * dz[j]
        for j in range(dq.size):
            rate[i] += dYdq[i, j] * dq[j]
    return rate


@njit(cache=True, error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True, no_cpython_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _trial(z: Vector, t: float, dz: Vector, center: Vector, radius: float) -> tuple[Vector, float]:
    """The trial point z + t dz, t halved until it lies within ``radius`` of ``center`` (or t < 1e-3)."""
    z_try = _axpy(z, t, dz)
    while _distance(z_try, center) > radius and t >= 1e-3:
        t *= 0.5
        z_try = _axpy(z, t, dz)
    return z_try, t


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _newton(
    z: Vector, q: Vector, corrector: Corrector, structure: Structure, tolerances: Tolerances, n_state: int
) -> tuple[Vector, int, int, float, Matrix, Matrix, Vector]:
    """Damped Newton on the end conditions (module docstring) under the controls ``corrector``,
    integrating the first ``n_state`` state entries at ``tolerances``. Converged: |r| < 1e-3 tol, or
    |r| < tol and a step below ``step_tol`` (1 + |z|): the step that led to z, or with ``ahead`` the
    step from z (J^-1 r, known before integrating again: a path point stops one integration earlier).
    A path corrector (finite ``radius``) is not damped: a trial point farther than ``radius`` from
    the start point z (the continuation rejects a corrector that leaves this ball anyway) counts as
    a failed trial, the step halved without integrating it, and a full step whose residual does not
    fall ends the corrector, not converged: a corrector that needs damping is a sign of a step
    too long for the predictor, which the continuation then halves (the integrations of a corrector
    wandering off the path are not paid).
    Returns (z, status, iterations, residual norm, Jacobian, boundary states and tip force at z): z
    is the last accepted point (with maxiter = 0 the start point, evaluated). One residual call site
    (the start point, then every trial point), so the compiled code holds one copy of the integrator,
    and one return (numba releases the arrays it holds at each)."""
    tol, step_tol, maxiter, radius = corrector.tol, corrector.step_tol, corrector.maxiter, corrector.radius
    it, t, status = 0, 1.0, NOT_CONVERGED
    norm, started = math.inf, False
    dz = np.zeros(z.size)
    z_try = center = z
    while True:
        r_new, J_new, states_new, F_new, ok = _residual(z_try, q, structure, tolerances, n_state)
        if not started:
            started = True
            r, J, states, F = r_new, J_new, states_new, F_new
            if not ok:
                status = NO_START
                break
            norm = _norm(r)
            if maxiter == 0:
                break
        elif ok and _norm(r_new) < max(norm, 1e-300) * (1 - 1e-4 * t) + 1e-14:
            z, r, J = z_try, r_new, J_new
            states, F, norm = states_new, F_new, _norm(r_new)
            if (norm < tol and t * _norm(dz) < step_tol * (1.0 + _norm(z))) or norm < 1e-3 * tol:
                status = CONVERGED
                break
        elif radius < math.inf:  # a path corrector that needs damping: the step is too long
            break
        else:
            z_try, t = _trial(z, 0.5 * t, dz, center, radius)
            if t < 1e-3:  # no descent left: converged only if already at the noise floor
                status = CONVERGED if norm < tol else NOT_CONVERGED
                break
            continue
        minus_r = np.empty(r.size)
        for i in range(r.size):
            minus_r[i] = -r[i]
        dz, regular = _solve(J, minus_r)
        if corrector.ahead and regular and norm < tol and _norm(dz) < step_tol * (1.0 + _norm(z)):
            status = CONVERGED
            break
        it += 1
        if it > maxiter or not regular:
            it = min(it, maxiter)
            break
        z_try, t = _trial(z, 1.0, dz, center, radius)
        if t < 1e-3:  # every descent step leaves the trust region
            break
    return z, status, it, norm, J, states, F


@njit(cache=True, inline="always", error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _step_cap(
    rate: Vector, rate_prev: Vector, dlam: float, max_rotation_step: float, max_position_step: float
) -> float:
    """The longest step whose predicted tip motion stays within both limits: the tip's rate and,
    when ``dlam`` > 0, its change (rate - rate_prev)/dlam since the previous point."""
    accel = np.zeros(3)
    if dlam > 0.0:
        for i in range(3):
            accel[i] = (rate[i] - rate_prev[i]) / dlam
    rotation: float = _reach(abs(rate[2]), abs(accel[2]), max_rotation_step)
    position: float = _reach(math.hypot(rate[0], rate[1]), math.hypot(accel[0], accel[1]), max_position_step)
    return min(rotation, position)


@njit(cache=True, error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def _reach(speed: float, accel: float, limit: float) -> float:
    """The largest step h whose predicted tip motion, speed h + accel h^2 / 2 (a second-order
    Taylor bound along the path), stays within ``limit``."""
    if speed <= 0.0 and accel <= 0.0:
        return math.inf
    return 2.0 * limit / (speed + math.sqrt(speed * speed + 2.0 * accel * limit))


# follow_path status: converged, continuation stalled, integration failed at the start, final
# corrector failed
PATH_CONVERGED, PATH_STALLED, PATH_NO_START, PATH_FINAL_FAILED = 0, 1, 2, 3


@njit(cache=True, error_model="numpy", no_rewrites=True, no_cfunc_wrapper=True)  # type: ignore[call-overload]  # options numba's annotations omit
def follow_path(
    z: Vector, q0: Vector, q1: Vector, structure: Structure, controls: PathControls
) -> tuple[Vector, int, float, int, int, float, Matrix, Vector]:
    """Continuation from (z, q0) to q1 (``shooting`` module docstring): tangent predictor (from the
    Jacobian of the last accepted point), Newton corrector at the path tolerances with the step
    rejections, then the final corrector at the final ones. One Newton call site (the start point is
    evaluated by a Newton of 0 iterations; the final corrector is the last call): one compiled copy
    of it. The sensitivities to the distributed load are integrated only when the path changes it.
    Returns (z, status, load fraction reached, Newton iterations, accepted steps, residual norm,
    and when converged the boundary states and tip force at z)."""
    max_rotation_step, max_position_step = controls.max_rotation_step, controls.max_position_step
    max_step_iterations = controls.max_step_iterations
    last = structure.bounds.size - 1
    dq = _axpy(q1, -1.0, q0)
    n_state = STATE_SIZE if (dq[dq.size - 2] != 0.0 or dq[dq.size - 1] != 0.0) else FORCE_STATE_SIZE
    lam = lam_try = lam_prev = curvature = 0.0
    dlam = min(controls.initial_step, 1.0)
    nit = nsteps = 0
    norm = 0.0
    started, regular = False, True
    dz, step = np.zeros(z.size), np.zeros(z.size)
    tip, rate = np.zeros(3), np.zeros(3)
    reach = math.inf
    while True:
        final = started and lam >= 1.0
        radius = math.inf
        tolerances = controls.path
        if not started:
            q, z_guess = q0, z
            ntol, nmax = 0.0, 0
        elif final:  # final corrector at full accuracy
            q, z_guess = _axpy(q0, lam, dq), z
            ntol, nmax = controls.tol, controls.maxiter
            tolerances = controls.final
        else:
            lam_try = min(1.0, lam + min(dlam, reach))
            q = _axpy(q0, lam_try, dq)
            step = _axpy(np.zeros(z.size), lam_try - lam, dz) if regular else np.zeros(z.size)
            # a step whose corrector needs more than max_step_iterations is rejected: stop there
            z_guess, ntol = _axpy(z, 1.0, step), 10 * controls.path.rtol
            nmax = min(controls.maxiter, max_step_iterations)
            if regular:  # the corrector may move z this far from the predictor (the step test below)
                bend = curvature * ((lam_try - lam) * (lam_try - lam))  # twice the predictor's expected miss
                radius = controls.max_corrector * _norm(step) + bend + 1e-6 * (1.0 + _norm(z))
        corrector = Corrector(tol=ntol, step_tol=1e-9 if final else ntol, ahead=not final, maxiter=nmax, radius=radius)
        z_new, nstat, it, norm, J, states, F = _newton(z_guess, q, corrector, structure, tolerances, n_state)
        new_tip = states[last]  # the tip's (x, y, theta) are its first three entries
        ok = nstat == CONVERGED
        if not started:
            if nstat == NO_START:
                return z, PATH_NO_START, lam, nit, nsteps, norm, states, F
            started = ok = True
            norm = 0.0
        else:
            nit += it
            if final:
                if ok and abs(new_tip[2] - tip[2]) < 1e-3:
                    return z_new, PATH_CONVERGED, lam, nit, nsteps, norm, states, F
                return z, PATH_FINAL_FAILED, lam, nit, nsteps, norm, states, F
            if ok:
                moved = math.hypot(new_tip[0] - tip[0], new_tip[1] - tip[1])
                ok = (
                    it <= max_step_iterations
                    and abs(new_tip[2] - tip[2]) <= max_rotation_step
                    and moved <= max_position_step
                    and _distance(z_new, z_guess) <= radius
                )
            if ok:
                z, lam_prev, lam = z_new, lam, lam_try
                nsteps += 1
                if it <= 3:
                    dlam = min(2.0 * dlam, 1.0)
        if ok:  # the tangent at the new point, and the path's curvature |z''| since the last
            dz_prev, was_regular = dz, regular
            rate_prev = rate
            dz, regular, rate = _tangent(z, _axpy(q0, lam, dq), J, states, dq, structure)
            secant = nsteps > 0 and regular and was_regular  # the last two points give z'' and the tip's
            if secant:
                curvature = _norm(_axpy(dz, -1.0, dz_prev)) / (lam - lam_prev)
            reach = (
                _step_cap(rate, rate_prev, lam - lam_prev if secant else 0.0, max_rotation_step, max_position_step)
                if regular
                else math.inf
            )
            tip = new_tip  # a row of the accepted point's states, an array nothing writes again
        else:  # halve the step tried (dlam itself may reach past lambda = 1)
            dlam = 0.5 * (lam_try - lam)
            if dlam < controls.min_step:
                return z, PATH_STALLED, lam, nit, nsteps, norm, states, F
