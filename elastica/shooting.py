"""Exact planar elastica of an inextensible, shear-free beam, solved by shooting with continuation.

The beam is clamped at s = 0 with its tangent along +x; s in [0, L] is the arc length and
kappa0 the initial (stress-free) curvature. Equilibrium of the part outboard of s under the tip
force F = (Fx, Fy) and tip moment M gives the bending moment

    m(s) = EI (theta'(s) - kappa0) = M + (x_L - x(s)) Fy - (y_L - y(s)) Fx,

and, differentiating, the first-order system integrated here (normalised by L and EI):

    x' = cos(theta),   y' = sin(theta),   theta' = kappa0 + m,   m' = Fx sin(theta) - Fy cos(theta),
    U' = m^2 / 2   (strain energy density, so U(L) is the strain energy).

Shooting unknowns z: the root moment m(0); one force multiplier mu_k per prescribed tip-position
component (the force along that direction is unknown); the tip angle tau when a follower force
acts (its direction depends on the unknown tip angle, F = F_dead + R(tau) f_follower). The end
conditions are: m(L) = M (or theta(L) = prescribed angle, then M is an output), d_k . r(L) = c_k,
and theta(L) = tau. The Jacobian comes from the variational equations integrated alongside
(sensitivities of the state to m(0), Fx, Fy), so each Newton iteration costs one integration.

Continuation: every load and prescribed value is interpolated linearly from a start state (the
unloaded beam, or a previous result) to the target, with a secant predictor, adaptive steps and a
step rejection when the tip rotation jumps by more than ``max_rotation_step`` rad. This follows the
physically connected branch (the full-circle roll-up returns a tip rotation of 2 pi, not 4 pi).

Sign conventions: x along the undeformed (straight) beam from the clamp, y transverse, angles and
moments counter-clockwise positive. The seeds' (Bapat 2015) P, nP, M for a tip are Fx = -nP,
Fy = +P and a CCW moment -M (their tabulated M > 0 is clockwise, "opposing" P).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["TipConstraint", "ElasticaProblem", "ElasticaResult", "solve_elastica", "solve_path",
           "unloaded_tip"]


@dataclass(frozen=True)
class TipConstraint:
    """Prescribed tip position component: ``direction . r_tip = value`` (length units).

    The force component along ``direction`` becomes an unknown (solved for); ``direction`` is
    normalised internally.
    """

    direction: tuple[float, float]
    value: float


@dataclass(frozen=True)
class ElasticaProblem:
    """A clamped beam with tip loads and/or prescribed tip positions (plain data, physical units).

    force: dead tip force (Fx, Fy) in the global frame (its components along constrained
        directions are added to the unknown reactions, so they may be left 0).
    moment: applied tip moment (CCW), ignored when ``tip_angle`` is given.
    follower: follower tip force (tangential, normal) components in the deformed tip frame.
    constraints: prescribed tip position components (fixed-guided, fixed-fixed, inverse problems).
    tip_angle: prescribed absolute tip angle theta(L) in rad (fixed-guided: 0 for a straight beam).
    """

    length: float = 1.0
    EI: float = 1.0
    curvature: float = 0.0
    force: tuple[float, float] = (0.0, 0.0)
    moment: float = 0.0
    follower: tuple[float, float] = (0.0, 0.0)
    constraints: tuple[TipConstraint, ...] = ()
    tip_angle: float | None = None


@dataclass
class ElasticaResult:
    """Outcome of one solve; loads and positions in the problem's units, angles in rad."""

    converged: bool
    message: str
    x: float
    y: float
    theta: float
    force: tuple[float, float]          # total tip force (Fx, Fy) acting on the beam
    moment: float                       # tip moment acting on the beam (CCW)
    reaction: tuple[float, float, float]  # support reaction (Rx, Ry, M_root) on the beam at s = 0
    strain_energy: float
    s: np.ndarray
    shape: np.ndarray                   # (3, n): x(s), y(s), theta(s)
    nit: int = 0                        # Newton iterations, all continuation steps together
    nsteps: int = 0                     # accepted continuation steps
    wall_time: float = 0.0
    residual: float = math.nan
    problem: ElasticaProblem | None = None
    z: np.ndarray = field(default_factory=lambda: np.zeros(0))  # shooting unknowns (warm start)


# --------------------------------------------------------------------------------------------
# normalised problem data (L = 1, EI = 1)

def _unit(d):
    d = np.asarray(d, float)
    return d / math.hypot(*d)


def _load_vector(p: ElasticaProblem) -> np.ndarray:
    """All continuation parameters of a problem, normalised: [Fx, Fy, M, ft, fn, c_1..c_k, angle]."""
    f = p.L2_EI = None  # noqa: F841 (placeholder to keep dataclass frozen-friendly)
    scale_f = p.length**2 / p.EI
    q = [p.force[0] * scale_f, p.force[1] * scale_f, p.moment * p.length / p.EI,
         p.follower[0] * scale_f, p.follower[1] * scale_f]
    q += [c.value / p.length for c in p.constraints]
    q.append(p.tip_angle if p.tip_angle is not None else 0.0)
    return np.array(q)


def unloaded_tip(length: float, curvature: float) -> tuple[float, float, float]:
    """Tip (x, y, theta) of the stress-free beam of initial curvature ``curvature``."""
    k = curvature * length
    if abs(k) < 1e-8:
        return length * (1 - k * k / 6), length * (k / 2 - k**3 / 24), k
    return length * math.sin(k) / k, length * (1 - math.cos(k)) / k, k


def _start_vector(p: ElasticaProblem) -> np.ndarray:
    """Continuation parameters of the unloaded beam (zero loads, prescribed values where it sits)."""
    x0, y0, th0 = unloaded_tip(1.0, p.curvature * p.length)
    q = [0.0] * 5
    for c in p.constraints:
        d = _unit(c.direction)
        q.append(d[0] * x0 + d[1] * y0)
    q.append(th0)
    return np.array(q)


class _Shooter:
    """Residual and Jacobian of the end conditions for one problem structure (normalised)."""

    def __init__(self, p: ElasticaProblem, rtol: float, atol: float):
        self.k0 = p.curvature * p.length
        self.dirs = [_unit(c.direction) for c in p.constraints]
        self.nc = len(self.dirs)
        self.angle_given = p.tip_angle is not None
        self.has_follower = p.follower != (0.0, 0.0)
        self.n = 1 + self.nc + (1 if self.has_follower else 0)
        self.rtol, self.atol = rtol, atol

    def forces(self, z, q):
        """Tip force (Fx, Fy) and its derivative d(Fx, Fy)/dz (2 x n)."""
        F = np.array([q[0], q[1]])
        dF = np.zeros((2, self.n))
        for k, d in enumerate(self.dirs):
            F = F + z[1 + k] * d
            dF[:, 1 + k] = d
        if self.has_follower:
            tau = z[-1]
            c, s = math.cos(tau), math.sin(tau)
            ft, fn = q[3], q[4]
            F = F + np.array([c * ft - s * fn, s * ft + c * fn])
            dF[:, -1] = [-s * ft - c * fn, c * ft - s * fn]
        return F, dF

    def rhs(self, s, Y, Fx, Fy):
        th, m = Y[2], Y[3]
        c, sn = math.cos(th), math.sin(th)
        dY = np.empty(17)
        dY[0] = c
        dY[1] = sn
        dY[2] = self.k0 + m
        dY[3] = Fx * sn - Fy * c
        dY[4] = 0.5 * m * m
        S = Y[5:].reshape(4, 3)      # rows: d x, d y, d theta, d m ; columns: d/d(m0, Fx, Fy)
        dS = dY[5:].reshape(4, 3)
        dS[0] = -sn * S[2]
        dS[1] = c * S[2]
        dS[2] = S[3]
        dS[3] = (Fx * c + Fy * sn) * S[2]
        dS[3, 1] += sn
        dS[3, 2] -= c
        return dY

    def integrate(self, z, q, dense=False):
        F, dF = self.forces(z, q)
        Y0 = np.zeros(17)
        Y0[3] = z[0]
        Y0[5 + 9] = 1.0              # d m(0) / d m0
        sol = solve_ivp(self.rhs, (0.0, 1.0), Y0, method="DOP853", rtol=self.rtol, atol=self.atol,
                        args=(F[0], F[1]), dense_output=dense)
        return sol, F, dF

    def residual(self, z, q):
        sol, F, dF = self.integrate(z, q)
        if not sol.success:
            return None, None, sol
        Y = sol.y[:, -1]
        S = Y[5:].reshape(4, 3)
        # d(state at L)/dz = S[:, 0] e_0^T + S[:, 1:] dF
        dYdz = np.outer(S[:, 0], np.eye(self.n)[0]) + S[:, 1:] @ dF
        r = np.empty(self.n)
        J = np.empty((self.n, self.n))
        if self.angle_given:
            r[0] = Y[2] - q[-1]
            J[0] = dYdz[2]
        else:
            r[0] = Y[3] - q[2]
            J[0] = dYdz[3]
        for k, d in enumerate(self.dirs):
            r[1 + k] = d[0] * Y[0] + d[1] * Y[1] - q[5 + k]
            J[1 + k] = d[0] * dYdz[0] + d[1] * dYdz[1]
        if self.has_follower:
            r[-1] = Y[2] - z[-1]
            J[-1] = dYdz[2]
            J[-1, -1] -= 1.0
        return r, J, sol


def _newton(shooter, z, q, tol, maxiter):
    """Damped Newton on the end conditions. Returns (z, converged, iterations, residual norm)."""
    r, J, _ = shooter.residual(z, q)
    if r is None:
        return z, False, 0, math.inf
    norm = np.linalg.norm(r)
    for it in range(1, maxiter + 1):
        try:
            dz = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            return z, False, it, norm
        t = 1.0
        while True:
            z_new = z + t * dz
            r_new, J_new, _ = shooter.residual(z_new, q)
            if r_new is not None and np.linalg.norm(r_new) < max(norm, 1e-300) * (1 - 1e-4 * t) + 1e-14:
                break
            t *= 0.5
            if t < 1e-3:
                return z, False, it, norm
        z, r, J, norm = z_new, r_new, J_new, np.linalg.norm(r_new)
        step = np.linalg.norm(t * dz)
        if norm < tol and step < 1e-9 * (1.0 + np.linalg.norm(z)):
            return z, True, it, norm
        if norm < 1e-3 * tol:
            return z, True, it, norm
    return z, False, maxiter, norm


def solve_path(problem: ElasticaProblem, start: ElasticaResult | None = None, *,
               rtol: float = 1e-12, atol: float = 1e-13, tol: float = 1e-11,
               initial_step: float = 0.25, min_step: float = 1e-5, max_rotation_step: float = 0.5,
               maxiter: int = 25, n_samples: int = 101) -> ElasticaResult:
    """Continue from ``start`` (default: the unloaded beam) to ``problem`` and return the end state.

    ``start`` must have the same structure (same constraints, follower or not, angle given or
    not, same length/EI/curvature); its loads and prescribed values are interpolated to the
    target's. Tolerances: ``rtol``/``atol`` of the DOP853 integration, ``tol`` on the residual
    of the normalised end conditions.
    """
    t0 = time.perf_counter()
    shooter = _Shooter(problem, rtol, atol)
    q1 = _load_vector(problem)
    if start is not None and start.z.size == shooter.n and start.problem is not None:
        q0, z = _load_vector(start.problem), np.array(start.z, float)
    else:
        q0, z = _start_vector(problem), np.zeros(shooter.n)
        if shooter.has_follower:
            z[-1] = problem.curvature * problem.length
    lam, dlam = 0.0, min(initial_step, 1.0)
    z_prev, lam_prev = None, None
    nit = nsteps = 0
    message = "converged"
    converged = True
    norm = 0.0
    tip_angle = _tip_angle(shooter, z, q0)
    while lam < 1.0:
        lam_try = min(1.0, lam + dlam)
        q = q0 + lam_try * (q1 - q0)
        if z_prev is not None:                      # secant predictor
            z_guess = z + (z - z_prev) * (lam_try - lam) / (lam - lam_prev)
        else:
            z_guess = z
        z_new, ok, it, norm = _newton(shooter, z_guess, q, tol, maxiter)
        nit += it
        if ok:
            new_angle = _tip_angle(shooter, z_new, q)
            ok = abs(new_angle - tip_angle) <= max_rotation_step
        if ok:
            z_prev, lam_prev, z, lam, tip_angle = z, lam, z_new, lam_try, new_angle
            nsteps += 1
            if it <= 4:
                dlam = min(2.0 * dlam, 1.0)
        else:
            dlam *= 0.5
            if dlam < min_step:
                converged = False
                message = f"continuation stalled at load fraction {lam:.6g} (residual {norm:.3g})"
                break
    result = _result(problem, shooter, z, q0 + lam * (q1 - q0), n_samples)
    result.converged = converged
    result.message = message
    result.nit, result.nsteps = nit, nsteps
    result.wall_time = time.perf_counter() - t0
    result.residual = norm
    return result


def _tip_angle(shooter, z, q):
    sol, _, _ = shooter.integrate(z, q)
    return sol.y[2, -1]


def _result(problem, shooter, z, q, n_samples):
    sol, F, _ = shooter.integrate(z, q, dense=True)
    s = np.linspace(0.0, 1.0, n_samples)
    Ys = sol.sol(s)
    Y = sol.y[:, -1]
    L, EI = problem.length, problem.EI
    fs, ms = EI / L**2, EI / L
    m_tip = Y[3]
    # support reaction on the beam: -F and the moment balancing the tip loads about the root
    reaction = (-F[0] * fs, -F[1] * fs, -z[0] * ms)
    return ElasticaResult(
        converged=True, message="", x=Y[0] * L, y=Y[1] * L, theta=Y[2],
        force=(F[0] * fs, F[1] * fs), moment=m_tip * ms, reaction=reaction,
        strain_energy=Y[4] * ms, s=s * L, shape=np.vstack([Ys[0] * L, Ys[1] * L, Ys[2]]),
        problem=replace(problem, moment=m_tip * ms) if shooter.angle_given else problem,
        z=np.array(z, float))


def solve_elastica(length: float = 1.0, EI: float = 1.0, *, curvature: float = 0.0,
                   force: tuple[float, float] = (0.0, 0.0), moment: float = 0.0,
                   follower: tuple[float, float] = (0.0, 0.0),
                   tip_x: float | None = None, tip_y: float | None = None,
                   tip_angle: float | None = None,
                   constraints: tuple[TipConstraint, ...] = (), **options) -> ElasticaResult:
    """Solve one clamped-beam elastica from the unloaded state (continuation in the load).

    Load-specified: give ``force`` (Fx, Fy), ``moment`` and/or ``follower`` (tangential, normal).
    Displacement-specified: give ``tip_x`` (the seeds' a), ``tip_y`` (b) and/or ``tip_angle``
    (theta_0, rad); the conjugate loads are then unknowns, returned in ``result.force`` and
    ``result.moment``. The remaining components of ``force`` are applied as given, e.g. the
    Table 3.5 inverse problem "b, theta_0 and n given" is not expressible this way; use
    ``TipConstraint`` with a direction (see ``inverse_fixed_ratio``).
    ``options`` go to ``solve_path`` (rtol, atol, tol, initial_step, n_samples, ...).
    """
    cons = list(constraints)
    if tip_x is not None:
        cons.append(TipConstraint((1.0, 0.0), tip_x))
    if tip_y is not None:
        cons.append(TipConstraint((0.0, 1.0), tip_y))
    problem = ElasticaProblem(length=length, EI=EI, curvature=curvature, force=tuple(force),
                              moment=moment, follower=tuple(follower), constraints=tuple(cons),
                              tip_angle=tip_angle)
    return solve_path(problem, **options)
