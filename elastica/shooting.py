"""Exact planar elastica of an inextensible, shear-free beam, solved by shooting with continuation.

The beam is clamped at s = 0 with its tangent along +x; s in [0, L] is the arc length and
kappa0 the initial (stress-free) curvature. Equilibrium of the part outboard of s under the tip
force F = (Fx, Fy) and tip moment M gives the bending moment

    m(s) = EI (theta'(s) - kappa0) = M + (x_L - x(s)) Fy - (y_L - y(s)) Fx,

and, differentiating, the first-order system integrated here (normalised by L and EI):

    x' = cos(theta),   y' = sin(theta),   theta' = kappa0 + m,   m' = Fx sin(theta) - Fy cos(theta),
    U' = m^2 / 2   (strain energy density, so U(L) is the strain energy).

A uniform dead distributed load w = (wx, wy) per unit length (e.g. self-weight) adds its outboard
resultant to the force carried across the section, N(s) = F + w (L - s), so m' = Nx sin(theta) -
Ny cos(theta) with N in place of F; its components are two more continuation parameters, with
their own variational equations (d m'/d wx = (L - s) sin(theta) + ..., d m'/d wy = -(L - s) cos(theta) + ...).

Shooting unknowns z: the root moment m(0); one force multiplier mu_k per prescribed tip-position
component (the force along that direction is unknown); one force multiplier nu_j per prescribed
section moment (below); the tip angle tau when a follower force acts (its direction depends on
the unknown tip angle, F = F_dead + R(tau) f_follower). The end conditions are: m(L) = M (or
theta(L) = prescribed angle, then M is an output), d_k . r(L) = c_k, m(s_j) = m_j, and
theta(L) = tau. The Jacobian comes from the variational equations integrated alongside
(sensitivities of the state to m(0), Fx, Fy), so each Newton iteration costs one integration
(split at the sections s_j, where the state and its sensitivities are read).

Force toward a fixed point (``PointedForce``, a rope over a pulley): a tip force of magnitude T
whose direction is the line from the tip r_L to a fixed point P, turned by a fixed angle a (CCW),

    F = T R(a) (P - r_L) / |P - r_L|,    i.e. its direction angle phi = atan2(P - r_L) + a.

For a given phi it is a dead force T (cos phi, sin phi), so the pointed problem is the dead-force
problem that the shooting above solves, plus one condition per pointed force at the converged tip:

    g(phi) = wrap(atan2(P - r_L(phi)) + a - phi) = 0      (wrap to (-pi, pi]).

g is solved by Newton's method on phi (one or a few unknowns), dg/dphi by forward differences of
the warm-started dead solves (each a short continuation from the last state); its exact value is
-I + (d atan2/d r_L)(dr_L/dphi), so it is regular whenever the tip's motion under a turn of the
force is less than its distance to P (always for a far pulley, where g -> phi_0 - phi). The
magnitudes are continued from the start state's (0 from the unloaded beam) to the targets with
adaptive steps (halved when Newton fails or the step moved the tip by more than
``max_position_step`` L or turned a force by more than ``max_rotation_step`` rad, doubled after a
success), each Newton started from the last accepted phi, so the path follows the physically
connected branch as the dead continuation does (a force at an angle to the line can carry the
tip round to another side of the point: a long step could land on another equilibrium). Far from the tip (|P - r_L| >> L) the pointed force tends to the dead force of direction
R(a)(P - r_L0) of the unloaded tip.

Prescribed section moment (``MomentConstraint``): m(s_j) = m_j at an arc length s_j, the
unknown being the force along a given direction. With m_j = 0 this is the dissertation's inflection
point ([bapat2015, §3.5.2, Table 3.6], Case 2c: b, theta_0 and the inflection location l1
given, nP, P, M unknown): the moment of the tip loads about r(s_j),

    m(s_j) = M + Fy (x_L - x(s_j)) - Fx (y_L - y(s_j))      (CCW M, global F),

vanishes. In the dissertation's signs (Fx = -nP, Fy = P, clockwise M_seed = -M) the same condition
reads M_seed + Fx (y_L - y) - Fy (x_L - x) = 0. The straight beam is singular for it (the axial
force has no lever arm), so its path starts from a loaded state: the problem without the
moment conditions (their forces 0), or the state under given start loads (``loaded_start``),
from which the section moments are continued to their targets.

Continuation: every load and prescribed value is interpolated linearly from a start state (the
unloaded beam, or a previous result) to the target, q(lambda) = q0 + lambda (q1 - q0), with a
tangent predictor dz/dlambda = -J^-1 (dr/dq)(q1 - q0) (both from the variational equations of
the accepted state), adaptive steps, and a step rejection (the step halved) when the corrector
left the path: the tip moved by more than ``max_position_step`` L or rotated by more than
``max_rotation_step`` rad, the corrector moved the shooting unknowns z further from the
predictor than ``max_corrector`` times the predicted change plus the predictor's expected miss
|z''| dlambda^2 (|z''| from the tangents at the last two accepted points, so an unknown that is
stationary along the path does not shrink the step) and a small floor, or Newton needed more
than ``max_step_iterations`` iterations. Step size: doubled after a corrector of at most 3
iterations, halved on a rejection, and never longer than the tip's predicted motion allows: the tip
rate d(x, y, theta)/dlambda (from the tangent and the sensitivities) and its change since the last
point give a second-order estimate of the motion, held within ``max_position_step`` and
``max_rotation_step``, so the limits cap the step before the corrector runs rather than reject it
after. The corrector is not damped along the path: a trial point outside the ball the step test
accepts is not integrated, and a full Newton step that does not lower the residual rejects the step. A first-order predictor misses the path by
O(dlambda^2), so halving the step always satisfies the corrector test on a smooth path; a
Newton solution on another branch (a straight beam pushed back towards its clamp has several
equilibria at the same load) is far from the predictor whatever the step. So one requested load
is reached along the physically connected path from the start state, however large: the beam
under a tip load pointing back towards the clamp bends the way the load's transverse component
pushes and curls back; the full-circle roll-up returns a tip rotation of 2 pi, not 4 pi; Table
3.5 Ex. 2 stays on the branch of the unloaded beam. The elastica's own stability is not
checked: the path is followed, stable or not. Intermediate steps are integrated at
``path_rtol`` and their corrector stops once the Newton step from the point is below the path
tolerance; the final corrector runs at ``rtol`` (1e-12), so the end conditions hold to ``tol`` =
1e-11 and tip values are accurate to about 1e-10 relative. The shape samples are integrated on the
plain state (x, y, theta, m, U), without the sensitivities the shooting needs.

This module sets the problem up (normalised structure arrays, start states, staging) and reads the
result; the continuation itself, with its Newton corrector and the integrations, runs compiled
(``integrator.follow_path``).

Sign conventions: x along the undeformed (straight) beam from the clamp, y transverse, angles and
moments counter-clockwise positive. The dissertation's [bapat2015] P, nP, M for a tip are Fx = -nP,
Fy = +P and a CCW moment -M (their tabulated M > 0 is clockwise, "opposing" P).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import TypedDict, Unpack, cast

import numpy as np
from argcheck import checked
from numpy.typing import ArrayLike, NDArray

from . import integrator as kernel
from .integrator import plain_samples

__all__ = [
    "TipConstraint",
    "MomentConstraint",
    "PointedForce",
    "ElasticaProblem",
    "ElasticaResult",
    "solve_elastica",
    "solve_path",
    "loaded_start",
    "section_moment",
    "unloaded_tip",
    "dead_equivalent",
    "line_angles",
    "pointing_error",
    "SolveOptions",
]

Vector = NDArray[np.float64]
Matrix = NDArray[np.float64]


@dataclass(frozen=True)
class TipConstraint:
    """Prescribed tip position component: ``direction . r_tip = value`` (length units).

    A tip force of unknown magnitude along ``force_direction`` (default: ``direction``) is added
    to the applied loads and solved for. Directions are normalised internally. Example, the
    dissertation's "b, theta_0 and n given" [bapat2015, Table 3.5]: direction (0, 1), force_direction (-n, 1).
    """

    direction: tuple[float, float]
    value: float
    force_direction: tuple[float, float] | None = None


@dataclass(frozen=True)
class MomentConstraint:
    """Prescribed bending moment ``m(at) = value`` (CCW, moment units) at arc length ``at``.

    A tip force of unknown magnitude along ``force_direction`` is added to the applied loads and
    solved for. ``value = 0`` makes ``at`` an inflection point of a straight beam (zero curvature
    change). Example, the dissertation's Case 2c (Table 3.6, b, theta_0 and l1 given): a
    ``TipConstraint((0, 1), b)`` (unknown P), ``tip_angle = theta_0`` (unknown M) and
    ``MomentConstraint(l1)`` (unknown nP along (1, 0)).
    """

    at: float
    value: float = 0.0
    force_direction: tuple[float, float] = (1.0, 0.0)


@dataclass(frozen=True)
class PointedForce:
    """Tip force of magnitude ``magnitude`` toward the fixed point ``toward`` (x, y; length units).

    Its direction is the line from the deformed tip to ``toward``, turned by ``angle`` rad
    counter-clockwise: F = T R(angle) (P - r_L)/|P - r_L| (a rope over a pulley: angle 0; a force
    kept perpendicular to the line to a fixed point: angle pi/2). A negative magnitude pushes away.
    """

    magnitude: float
    toward: tuple[float, float]
    angle: float = 0.0


@dataclass(frozen=True)
class ElasticaProblem:
    """A clamped beam with tip loads and/or prescribed tip positions (plain data, physical units).

    force: dead tip force (Fx, Fy) in the global frame (its components along constrained
        directions are added to the unknown reactions, so they may be left 0).
    distributed: uniform dead load (wx, wy) per unit length along the whole beam, global frame.
    moment: applied tip moment (CCW), ignored when ``tip_angle`` is given.
    follower: follower tip force (tangential, normal) components in the deformed tip frame.
    constraints: prescribed tip position components (fixed-guided, fixed-fixed, inverse problems).
    tip_angle: prescribed absolute tip angle theta(L) in rad (fixed-guided: 0 for a straight beam).
    moment_constraints: prescribed bending moments inside the beam (inflection points).
    pointed: tip forces toward fixed points (their directions depend on the tip position).
    """

    length: float = 1.0
    EI: float = 1.0
    curvature: float = 0.0
    force: tuple[float, float] = (0.0, 0.0)
    moment: float = 0.0
    follower: tuple[float, float] = (0.0, 0.0)
    constraints: tuple[TipConstraint, ...] = ()
    tip_angle: float | None = None
    moment_constraints: tuple[MomentConstraint, ...] = ()
    distributed: tuple[float, float] = (0.0, 0.0)
    pointed: tuple[PointedForce, ...] = ()


@dataclass
class ElasticaResult:
    """Outcome of one solve; loads and positions in the problem's units, angles in rad.

    ``force`` and ``moment`` act on the beam at its tip (s = L); ``reaction`` = (Rx, Ry, M) is what
    the clamp exerts on the beam at its root (s = 0), counter-clockwise positive, so that
    reaction + force = 0 for the forces. (The FEM's ``FemResult.reaction(node)`` is what the supports
    and prescriptions exert at the node asked for.) With pointed forces, ``pointed_angles`` are
    their converged direction angles phi_k (rad, global frame) and ``force`` includes them.
    """

    converged: bool
    message: str
    x: float
    y: float
    theta: float
    force: tuple[float, float]  # total tip force (Fx, Fy) acting on the beam
    moment: float  # tip moment acting on the beam (CCW)
    reaction: tuple[float, float, float]  # support reaction (Rx, Ry, M_root) on the beam at s = 0
    strain_energy: float
    s: Vector
    shape: Matrix  # (3, n): x(s), y(s), theta(s)
    nit: int = 0  # Newton iterations, all continuation steps together
    nsteps: int = 0  # accepted continuation steps
    wall_time: float = 0.0
    residual: float = math.nan
    problem: ElasticaProblem | None = None
    z: Vector = field(default_factory=lambda: np.zeros(0))  # shooting unknowns (warm start)
    pointed_angles: tuple[float, ...] = ()  # direction angles of the pointed forces (rad)

    # the result protocol every library's solve result shares: converged, status, message,
    # iterations, wall_time
    @property
    def status(self) -> str:
        return "ok" if self.converged else "not converged"

    @property
    def iterations(self) -> int:
        return self.nit


# --------------------------------------------------------------------------------------------
# normalised problem data (L = 1, EI = 1)


def _pair(v: Sequence[float]) -> tuple[float, float]:
    """A given pair (a tuple, list or array of two components) as the tuple a problem holds."""
    return cast(tuple[float, float], tuple(v))  # tuple() forgets the length the signature promises


def _unit(d: ArrayLike) -> Vector:
    """The direction d scaled to unit length."""
    v = np.asarray(d, np.float64)
    unit: Vector = v / math.hypot(*v)
    return unit


ANGLE = kernel.ANGLE  # index of the prescribed tip angle in a load vector; the last two are (wx, wy)


def _load_vector(p: ElasticaProblem) -> Vector:
    """All continuation parameters of a problem, normalised:
    [Fx, Fy, M, ft, fn, c_1..c_k, m_1..m_j, angle, wx, wy]."""
    scale_f = p.length**2 / p.EI
    q = [
        p.force[0] * scale_f,
        p.force[1] * scale_f,
        p.moment * p.length / p.EI,
        p.follower[0] * scale_f,
        p.follower[1] * scale_f,
    ]
    q += [c.value / p.length for c in p.constraints]
    q += [c.value * p.length / p.EI for c in p.moment_constraints]
    q.append(p.tip_angle if p.tip_angle is not None else 0.0)
    q += [p.distributed[0] * p.length**3 / p.EI, p.distributed[1] * p.length**3 / p.EI]
    return np.array(q)


def unloaded_tip(length: float, curvature: float) -> tuple[float, float, float]:
    """Tip (x, y, theta) of the stress-free beam of initial curvature ``curvature``."""
    k = curvature * length
    if abs(k) < 1e-8:
        return length * (1 - k * k / 6), length * (k / 2 - k**3 / 24), k
    return length * math.sin(k) / k, length * (1 - math.cos(k)) / k, k


def _start_vector(p: ElasticaProblem) -> Vector:
    """Continuation parameters of the unloaded beam (zero loads, prescribed values where it sits)."""
    x0, y0, th0 = unloaded_tip(1.0, p.curvature * p.length)
    q = [0.0] * 5
    for c in p.constraints:
        d = _unit(c.direction)
        q.append(d[0] * x0 + d[1] * y0)
    q += [0.0] * len(p.moment_constraints)  # the unloaded beam carries no moment
    q += [th0, 0.0, 0.0]
    return np.array(q)


class _Shooter:
    """One problem structure (normalised) as the arrays of ``integrator``, and its compiled
    residual, Newton corrector and tangent predictor at integration tolerances ``rtol``/``atol``."""

    def __init__(self, p: ElasticaProblem, rtol: float, atol: float):
        self.k0 = float(p.curvature * p.length)
        self.dirs: Matrix = np.array([_unit(c.direction) for c in p.constraints], np.float64).reshape(-1, 2)
        self.fdirs: Matrix = np.array(
            [_unit(c.force_direction if c.force_direction is not None else c.direction) for c in p.constraints],
            np.float64,
        ).reshape(-1, 2)
        self.nc = len(self.dirs)
        sites = [c.at / p.length for c in p.moment_constraints]  # s_j / L
        if any(not 0.0 <= s <= 1.0 for s in sites):
            raise ValueError("a moment constraint lies outside the beam (0 <= at <= length)")
        self.mdirs: Matrix = np.array([_unit(c.force_direction) for c in p.moment_constraints], np.float64).reshape(
            -1, 2
        )
        self.nm = len(sites)
        knots = sorted({s for s in sites if 0.0 < s < 1.0})
        self.bounds = np.array([0.0] + knots + [1.0])
        self.site_at = np.array(
            [0 if s == 0.0 else len(self.bounds) - 1 if s == 1.0 else 1 + knots.index(s) for s in sites], dtype=np.int64
        )
        self.angle_given = p.tip_angle is not None
        self.has_follower = p.follower != (0.0, 0.0)
        self.n = 1 + self.nc + self.nm + (1 if self.has_follower else 0)
        self.rtol, self.atol = float(rtol), float(atol)
        self.tolerances = kernel.Tolerances(rtol=self.rtol, atol=self.atol)
        self.structure = kernel.Structure(
            beam=kernel.elastica_beam(self.k0),
            dirs=self.dirs,
            forces=kernel.UnknownForces(force_dirs=self.fdirs, moment_dirs=self.mdirs, follower=self.has_follower),
            bounds=self.bounds,
            site_at=self.site_at,
            angle_given=self.angle_given,
        )

    def unknown_force_directions(self) -> list[Vector]:
        """Unit directions of the force multipliers, in the order of z[1:1 + nc + nm]."""
        return list(self.fdirs) + list(self.mdirs)

    def integrate(self, z: ArrayLike, q: ArrayLike) -> tuple[Matrix, Vector, bool]:
        """(plain states (x, y, theta, m, U) at the piece boundaries: row 0 at s = 0, the last at
        s = 1; tip force; ok): the shooting's pieces, without sensitivities."""
        zv, qv = np.asarray(z, np.float64), np.asarray(q, np.float64)
        F, _ = kernel.tip_force(zv, qv, self.structure.forces)
        y0 = np.zeros(kernel.BEAM_STATE_SIZE)
        y0[3] = zv[0]
        states, ok = plain_samples(
            y0, self.bounds, self.structure.beam, self.loads(F, qv), self.tolerances, restart=True
        )
        return states, F, ok

    def loads(self, F: Vector, q: Vector) -> kernel.Loads:
        """The loads on the normalised elastica: the tip force F and the distributed load (q's last
        two entries)."""
        return kernel.Loads(Fx=float(F[0]), Fy=float(F[1]), wx=float(q[-2]), wy=float(q[-1]))


class _PathOptions(TypedDict, total=False):
    """The options of ``solve_path``'s continuation by name (``solve_path`` says what each means):
    the ones a pointed-force solve hands on to each of its dead-force solves."""

    rtol: float
    atol: float
    tol: float
    initial_step: float
    min_step: float
    max_rotation_step: float
    max_position_step: float
    max_corrector: float
    max_step_iterations: int
    maxiter: int
    path_rtol: float


class SolveOptions(_PathOptions, total=False):
    """Every option of ``solve_path`` by name, as the functions that hand them on take them
    (``**options``)."""

    n_samples: int
    angle_tol: float


def solve_path(
    problem: ElasticaProblem,
    start: ElasticaResult | None = None,
    *,
    rtol: float = 1e-12,
    atol: float = 1e-13,
    tol: float = 1e-11,
    initial_step: float = 0.25,
    min_step: float = 1e-5,
    max_rotation_step: float = 0.5,
    max_position_step: float = 0.25,
    max_corrector: float = 0.5,
    max_step_iterations: int = 8,
    maxiter: int = 25,
    n_samples: int = 101,
    path_rtol: float = 1e-7,
    angle_tol: float = 1e-10,
) -> ElasticaResult:
    """Continue from ``start`` (default: the unloaded beam) to ``problem`` and return the end state.

    ``start`` must have the same structure (same constraints, follower or not, angle given or
    not, same length/EI/curvature); its loads and prescribed values are interpolated to the
    target's. Tolerances: ``rtol``/``atol`` of the final DOP853 integration, ``tol`` on the
    residual of the normalised end conditions; intermediate continuation steps use ``path_rtol``.
    Step control (module docstring): ``max_position_step`` (of L), ``max_rotation_step`` (rad),
    ``max_corrector`` (corrector distance / predicted change), ``max_step_iterations``.
    With prescribed tip positions along the tip tangent the path is staged (``_staged_start``).
    Pointed forces (module docstring): Newton on their direction angles until every
    |g_k| <= ``angle_tol`` (rad), their magnitudes continued from the start's.
    """
    options = _PathOptions(
        rtol=rtol,
        atol=atol,
        tol=tol,
        initial_step=initial_step,
        min_step=min_step,
        max_rotation_step=max_rotation_step,
        max_position_step=max_position_step,
        max_corrector=max_corrector,
        max_step_iterations=max_step_iterations,
        maxiter=maxiter,
        path_rtol=path_rtol,
    )
    if problem.pointed:
        return _solve_pointed(problem, start, n_samples, options, angle_tol)
    if start is not None and start.problem is not None and start.problem.pointed:
        start = replace(start, problem=dead_equivalent(start.problem, start.pointed_angles))
    t0 = time.perf_counter()
    final = _Shooter(problem, rtol, atol)
    path = _Shooter(problem, path_rtol, path_rtol * 0.1)
    q1 = _load_vector(problem)
    nit = nsteps = 0
    if start is not None and start.z.size == final.n and start.problem is not None:
        q0, z = _load_vector(start.problem), np.array(start.z, float)
    else:
        q0, z = _start_vector(problem), np.zeros(final.n)
        if final.has_follower:
            z[-1] = problem.curvature * problem.length
        if final.nm:
            q0, z, it, ns = _moment_start(problem, path, q0, z)
            nit, nsteps = nit + it, nsteps + ns
        elif final.nc:
            q0, z, it, ns = _staged_start(problem, path, q0)
            nit, nsteps = nit + it, nsteps + ns
    controls = kernel.PathControls(
        final=final.tolerances,
        tol=float(tol),
        path=path.tolerances,
        initial_step=float(initial_step),
        min_step=float(min_step),
        max_rotation_step=float(max_rotation_step),
        max_position_step=float(max_position_step),
        max_corrector=float(max_corrector),
        max_step_iterations=int(max_step_iterations),
        maxiter=int(maxiter),
    )
    z, status, lam, it, ns, norm, states, F = kernel.follow_path(
        np.array(z, float), np.asarray(q0, float), q1, final.structure, controls
    )
    nit, nsteps = nit + it, nsteps + ns
    converged, message = (
        status == kernel.PATH_CONVERGED,
        {
            kernel.PATH_CONVERGED: "converged",
            kernel.PATH_STALLED: f"continuation stalled at load fraction {lam:.6g} (residual {norm:.3g})",
            kernel.PATH_NO_START: "integration failed at the start state",
            kernel.PATH_FINAL_FAILED: f"final corrector failed (residual {norm:.3g})",
        }[status],
    )
    q_end = q0 + lam * (q1 - q0)
    result = _result(problem, final, z, q_end, n_samples, (states, F) if converged else None)
    result.converged, result.message = converged, message
    result.nit, result.nsteps = nit, nsteps
    result.wall_time = time.perf_counter() - t0
    result.residual = norm
    return result


def dead_equivalent(problem: ElasticaProblem, angles: Sequence[float] | Vector) -> ElasticaProblem:
    """The dead-force problem that ``problem`` is when its pointed forces have the direction angles
    ``angles`` (rad): force + sum_k T_k (cos phi_k, sin phi_k), and no pointed forces."""
    F = np.asarray(problem.force, float).copy()
    for pf, phi in zip(problem.pointed, angles, strict=True):
        F += pf.magnitude * np.array([math.cos(phi), math.sin(phi)])
    return replace(problem, force=(float(F[0]), float(F[1])), pointed=())


def line_angles(pointed: tuple[PointedForce, ...], x: float, y: float) -> Vector:
    """Direction angles phi_k = atan2(P_k - r) + a_k (rad) of the pointed forces with the tip at (x, y).

    Raises ValueError when the tip reaches a point P_k (the direction is undefined there): the
    distance is compared with the scale |P_k| + |r| of the two points."""
    out: list[float] = []
    for pf in pointed:
        dx, dy = pf.toward[0] - x, pf.toward[1] - y
        if math.hypot(dx, dy) <= 1e-12 * (math.hypot(*pf.toward) + math.hypot(x, y)):
            raise ValueError("the tip reached the point a force pulls toward (direction undefined)")
        out.append(math.atan2(dy, dx) + pf.angle)
    return np.array(out, float)


def _wrap(a: ArrayLike) -> Vector:
    """Angles wrapped to [-pi, pi)."""
    wrapped: Vector = (np.asarray(a, np.float64) + math.pi) % (2.0 * math.pi) - math.pi
    return wrapped


def _problem_of(result: ElasticaResult) -> ElasticaProblem:
    """The problem a result answers (every solve records it)."""
    if result.problem is None:
        raise ValueError("the result records no problem (it was not made by a solve)")
    return result.problem


def pointing_error(result: ElasticaResult) -> Vector:
    """g_k = wrap(atan2(P_k - r_L) + a_k - phi_k) (rad) of a solved pointed problem: 0 at equilibrium."""
    return _wrap(line_angles(_problem_of(result).pointed, result.x, result.y) - np.asarray(result.pointed_angles))


def _pointed_newton(
    target: ElasticaProblem,
    current: ElasticaResult | None,
    phi: Vector,
    options: _PathOptions,
    angle_tol: float,
    maxiter: int = 20,
    h: float = 1e-6,
) -> tuple[bool, ElasticaResult, Vector, float]:
    """Newton on g(phi) = wrap(atan2(P - r_L(phi)) + a - phi) = 0 at fixed magnitudes, from ``phi``.

    Each evaluation is the dead problem at phi continued from the last state; dg/dphi by forward
    differences of step ``h`` rad; a step that does not lower max|g| is halved (at most 6 times).
    Returns (converged, last dead result, phi, max|g|)."""

    def evaluate(angles: Vector, start: ElasticaResult | None) -> tuple[ElasticaResult, Vector | None]:
        res = solve_path(dead_equivalent(target, angles), start=start, n_samples=2, **options)
        if not res.converged:
            return res, None
        return res, _wrap(line_angles(target.pointed, res.x, res.y) - angles)

    res, g = evaluate(phi, current)
    if g is None:
        return False, res, phi, math.inf
    n = phi.size
    for _ in range(maxiter):
        norm = float(np.max(np.abs(g)))
        if norm <= angle_tol:
            return True, res, phi, norm
        J = np.empty((n, n))
        for k in range(n):
            shifted = phi.copy()
            shifted[k] += h
            _, gk = evaluate(shifted, res)
            if gk is None:
                return False, res, phi, norm
            J[:, k] = (gk - g) / h
        dphi = -np.linalg.solve(J, g)
        for _halving in range(7):
            trial_res, trial_g = evaluate(phi + dphi, res)
            if trial_g is not None and float(np.max(np.abs(trial_g))) < norm:
                break
            dphi = 0.5 * dphi
        else:
            return False, res, phi, norm
        phi, res, g = phi + dphi, trial_res, trial_g
    norm = float(np.max(np.abs(g)))
    return norm <= angle_tol, res, phi, norm


def _same_pointed(a: ElasticaProblem, b: ElasticaProblem) -> bool:
    """Same pointed forces apart from their magnitudes (same points and angle offsets)."""
    return len(a.pointed) == len(b.pointed) and all(
        tuple(p.toward) == tuple(q.toward) and p.angle == q.angle for p, q in zip(a.pointed, b.pointed)
    )


def _solve_pointed(
    problem: ElasticaProblem, start: ElasticaResult | None, n_samples: int, options: _PathOptions, angle_tol: float
) -> ElasticaResult:
    """Pointed forces: continuation of their magnitudes T(t) = T0 + t (T1 - T0), t: 0 -> 1, with
    Newton on the direction angles at each step (module docstring); the other loads at their targets
    from the first step, continued by the dead solves from the start state."""
    t0 = time.perf_counter()
    T1 = np.array([pf.magnitude for pf in problem.pointed], float)
    current: ElasticaResult | None
    if start is not None and start.problem is not None and start.problem.pointed:
        if _same_pointed(start.problem, problem):
            T0, phi = (
                np.array([pf.magnitude for pf in start.problem.pointed], float),
                np.array(start.pointed_angles, float),
            )
        else:
            T0 = np.zeros_like(T1)
            phi = line_angles(problem.pointed, start.x, start.y)
        current = replace(start, problem=dead_equivalent(start.problem, start.pointed_angles))
        tip = (start.x, start.y)
    else:
        current, T0 = start, np.zeros_like(T1)
        tip = (start.x, start.y) if start is not None else unloaded_tip(problem.length, problem.curvature)[:2]
        phi = line_angles(problem.pointed, *tip)
    t, dt, min_step = 0.0, 1.0, options["min_step"]
    nit = nsteps = 0
    last, norm = current, math.inf
    while t < 1.0:
        step = min(dt, 1.0 - t)
        t_next = 1.0 if step >= 1.0 - t else t + step
        T = T0 + t_next * (T1 - T0)
        target = replace(problem, pointed=tuple(replace(pf, magnitude=float(v)) for pf, v in zip(problem.pointed, T)))
        ok, res, phi_new, norm = _pointed_newton(target, current, phi.copy(), options, angle_tol)
        nit, nsteps, last = nit + res.nit, nsteps + res.nsteps, res
        moved = math.hypot(res.x - tip[0], res.y - tip[1]) / problem.length
        if (
            ok
            and step > min_step
            and (
                moved > options["max_position_step"]
                or float(np.max(np.abs(phi_new - phi))) > options["max_rotation_step"]
            )
        ):
            ok = False  # too long a step: Newton may have left the connected branch
        if ok:
            tip = (res.x, res.y)
            t, current, phi, dt = t_next, res, phi_new, 2.0 * step
        else:
            dt = 0.5 * step
            if dt < min_step:
                break
    converged = t >= 1.0
    base = current if converged else last
    equivalent = dead_equivalent(problem, phi)
    shooter = _Shooter(equivalent, options["rtol"], options["atol"])
    if base is not None and base.z.size == shooter.n:
        result = _result(equivalent, shooter, base.z, _load_vector(equivalent), n_samples)
        residual = base.residual
    else:  # nothing solved: the unloaded beam's shape
        result = _result(equivalent, shooter, np.zeros(shooter.n), _start_vector(equivalent), n_samples)
        residual = math.nan
    result.problem = replace(problem, moment=_problem_of(result).moment)
    result.pointed_angles = tuple(float(v) for v in phi)
    result.converged = converged
    result.message = (
        "converged"
        if converged
        else (
            f"force toward a fixed point: continuation of its magnitude stalled at fraction {t:.6g} "
            f"(direction error {norm:.3g} rad)"
        )
    )
    result.nit, result.nsteps, result.residual = nit, nsteps, residual
    result.wall_time = time.perf_counter() - t0
    return result


def _staged_start(problem: ElasticaProblem, shooter: _Shooter, q0: Vector) -> tuple[Vector, Vector, int, int]:
    """Start of a prescribed-position path that avoids the singular straight state.

    An inextensible straight beam has no axial compliance, so prescribing the tip position along
    the tip tangent from the unloaded state is singular, and moving it in proportion with the
    transverse values drives the path through large axial loads. So: first solve the problem
    without the (mostly) axial constraints, whose force multipliers stay 0; then return that
    state as the start from which only the axial prescribed values move to their targets.
    """
    x0, y0, th0 = unloaded_tip(1.0, problem.curvature * problem.length)
    tangent = np.array([math.cos(th0), math.sin(th0)])
    axial = [abs(float(d @ tangent)) >= 0.5 for d in shooter.dirs]
    z = np.zeros(shooter.n)
    if shooter.has_follower:
        z[-1] = th0
    if not any(axial):
        return q0, z, 0, 0
    keep = tuple(c for c, a in zip(problem.constraints, axial) if not a)
    first = solve_path(replace(problem, constraints=keep), rtol=shooter.rtol, atol=shooter.atol, tol=1e-9, n_samples=2)
    if not first.converged:  # fall back to the plain path from the unloaded beam
        return q0, z, first.nit, first.nsteps
    q = _load_vector(problem)
    x, y = first.x / problem.length, first.y / problem.length
    z[0] = first.z[0]
    kept = iter(first.z[1 : 1 + len(keep)])
    for k, (d, a) in enumerate(zip(shooter.dirs, axial)):
        if a:
            q[5 + k] = d[0] * x + d[1] * y
        else:
            z[1 + k] = next(kept)
    if shooter.has_follower:
        z[-1] = first.z[-1]
    return q, z, first.nit, first.nsteps


def _moment_start(
    problem: ElasticaProblem, shooter: _Shooter, q0: Vector, z0: Vector
) -> tuple[Vector, Vector, int, int]:
    """Start of a path with prescribed section moments: the loaded state without them.

    The moment conditions are dropped (their forces stay 0) and that problem is solved from the
    unloaded beam; its state then satisfies every other end condition of ``problem``, and the
    section moments it carries become the start values continued to the targets.
    """
    first = solve_path(
        replace(problem, moment_constraints=()), rtol=shooter.rtol, atol=shooter.atol, tol=1e-9, n_samples=2
    )
    if not first.converged:  # fall back to the plain path from the unloaded beam
        return q0, z0, first.nit, first.nsteps
    z = np.zeros(shooter.n)
    z[: 1 + shooter.nc] = first.z[: 1 + shooter.nc]
    z[1 + shooter.nc + shooter.nm :] = first.z[1 + shooter.nc :]
    q = _load_vector(problem)
    q[5 + shooter.nc : 5 + shooter.nc + shooter.nm] = _section_moments(shooter, z, q)
    return q, z, first.nit, first.nsteps


def _section_moments(shooter: _Shooter, z: Vector, q: Vector) -> Vector:
    """Normalised m(s_j) at the moment-constraint sites for the unknowns z (q's m_j ignored)."""
    states, _, ok = shooter.integrate(z, q)
    if not ok:
        raise RuntimeError("integration failed")
    moments: Vector = states[shooter.site_at, 3]
    return moments


def loaded_start(
    problem: ElasticaProblem, force: tuple[float, float], moment: float, **options: Unpack[SolveOptions]
) -> ElasticaResult:
    """The beam under the tip loads ``force`` (Fx, Fy) and ``moment`` (CCW), as a start for ``problem``.

    A forward (load-specified) solve from the unloaded beam, returned with the structure of
    ``problem`` (same constraints and section moments, with the values this state has), so
    ``solve_path(problem, start=loaded_start(problem, F0, M0))`` continues the prescribed values
    from this state to the targets. Use it with an approximate solution (e.g. PRBM loads) as the
    initial guess of an inverse problem. ``options`` go to the forward ``solve_path``.
    """
    if problem.follower != (0.0, 0.0):
        raise ValueError("loaded_start does not handle follower forces")
    if problem.pointed:
        raise ValueError("loaded_start does not handle forces toward fixed points")
    L, EI = problem.length, problem.EI
    forward = solve_path(
        ElasticaProblem(
            length=L,
            EI=EI,
            curvature=problem.curvature,
            force=_pair(force),
            moment=moment,
            distributed=problem.distributed,
        ),
        **options,
    )
    rtol = options.get("rtol", 1e-12)
    shooter = _Shooter(problem, rtol, options.get("atol", 0.1 * rtol))
    scale_f = L**2 / EI
    F0 = np.asarray(force, float) * scale_f
    dirs = shooter.unknown_force_directions()
    z = np.zeros(shooter.n)
    z[0] = forward.z[0]
    dead = np.asarray(problem.force, float) * scale_f
    if dirs:  # unknown forces take what they can of F0 - dead
        U = np.column_stack(dirs)
        mu = np.linalg.lstsq(U, F0 - dead, rcond=None)[0]
        z[1 : 1 + len(dirs)] = mu
        dead = F0 - U @ mu
    else:
        dead = F0
    x, y = forward.x / L, forward.y / L
    q = _load_vector(problem)
    q[0:2] = dead
    q[2] = moment * L / EI
    for k, d in enumerate(shooter.dirs):
        q[5 + k] = d[0] * x + d[1] * y
    if shooter.angle_given:
        q[ANGLE] = forward.theta
    m = _section_moments(shooter, z, q)
    q[5 + shooter.nc : 5 + shooter.nc + shooter.nm] = m
    start = replace(
        problem,
        force=tuple(dead / scale_f),
        moment=moment,
        constraints=tuple(replace(c, value=float(q[5 + k] * L)) for k, c in enumerate(problem.constraints)),
        moment_constraints=tuple(replace(c, value=float(mj * EI / L)) for c, mj in zip(problem.moment_constraints, m)),
        tip_angle=forward.theta if shooter.angle_given else None,
    )
    result = _result(start, shooter, z, q, options.get("n_samples", 101))
    result.converged, result.message = forward.converged, forward.message
    result.nit, result.nsteps, result.wall_time = forward.nit, forward.nsteps, forward.wall_time
    return result


def section_moment(result: ElasticaResult, at: float) -> float:
    """Bending moment m(at) (CCW, moment units) at arc length ``at`` of a solved beam.

    Re-integrates the beam from its root moment under its total tip force, with the
    integration split at ``at``, and reads the moment state there (m' = Fx sin(theta) -
    Fy cos(theta), the derivative of m = M + Fy (x_L - x) - Fx (y_L - y)).
    """
    p = _problem_of(result)
    plain = ElasticaProblem(
        length=p.length,
        EI=p.EI,
        curvature=p.curvature,
        force=result.force,
        moment=result.moment,
        moment_constraints=(MomentConstraint(at),),
        distributed=p.distributed,
    )
    shooter = _Shooter(plain, 1e-12, 1e-13)
    z = np.array([result.z[0], 0.0])
    return float(_section_moments(shooter, z, _load_vector(plain))[0] * p.EI / p.length)


def _result(
    problem: ElasticaProblem,
    shooter: _Shooter,
    z: Vector,
    q: Vector,
    n_samples: int,
    evaluated: tuple[Matrix, Vector] | None = None,
) -> ElasticaResult:
    """The result at the unknowns z: tip values from the integration of the last residual
    (``evaluated`` = (boundary states, tip force) at z, else integrated here), the shape sampled by
    integrating from sample to sample (compiled)."""
    states, F = evaluated if evaluated is not None else shooter.integrate(z, q)[:2]
    s = np.linspace(0.0, 1.0, n_samples)
    if n_samples == 2:  # the ends: the boundary states themselves
        samples = states[[0, -1], : kernel.BEAM_STATE_SIZE]
    else:
        samples, _ = plain_samples(states[0], s, shooter.structure.beam, shooter.loads(F, q), shooter.tolerances)
    Ys = samples.T
    Y = states[-1]
    L, EI = problem.length, problem.EI
    fs, ms = EI / L**2, EI / L
    m_tip = Y[3]
    # support reaction on the beam: -(F + w L) and the moment balancing the loads about the root
    reaction = (float(-(F[0] + q[-2]) * fs), float(-(F[1] + q[-1]) * fs), float(-z[0] * ms))
    return ElasticaResult(
        converged=True,
        message="",
        x=float(Y[0] * L),
        y=float(Y[1] * L),
        theta=float(Y[2]),
        force=(float(F[0] * fs), float(F[1] * fs)),
        moment=float(m_tip * ms),
        reaction=reaction,
        strain_energy=float(Y[4] * ms),
        s=s * L,
        shape=np.vstack([Ys[0] * L, Ys[1] * L, Ys[2]]),
        problem=replace(problem, moment=m_tip * ms) if shooter.angle_given else problem,
        z=np.array(z, float),
    )


@checked(
    positive=("length", "EI"),
    finite=("curvature", "force", "moment", "follower", "tip_x", "tip_y", "tip_angle", "inflection_at"),
)
def solve_elastica(
    length: float = 1.0,
    EI: float = 1.0,
    *,
    curvature: float = 0.0,
    force: tuple[float, float] = (0.0, 0.0),
    moment: float = 0.0,
    follower: tuple[float, float] = (0.0, 0.0),
    tip_x: float | None = None,
    tip_y: float | None = None,
    tip_angle: float | None = None,
    constraints: tuple[TipConstraint, ...] = (),
    inflection_at: float | None = None,
    moment_constraints: tuple[MomentConstraint, ...] = (),
    start_loads: tuple[tuple[float, float], float] | None = None,
    distributed: tuple[float, float] = (0.0, 0.0),
    **options: Unpack[SolveOptions],
) -> ElasticaResult:
    """Solve one clamped-beam elastica from the unloaded state (continuation in the load).

    Load-specified: give ``force`` (Fx, Fy), ``moment`` and/or ``follower`` (tangential, normal),
    and/or ``distributed`` (wx, wy): a uniform dead load per unit length (e.g. self-weight).
    Displacement-specified: give ``tip_x`` (the dissertation's a), ``tip_y`` (b) and/or ``tip_angle``
    (theta_0, rad); the conjugate loads are then unknowns, returned in ``result.force`` and
    ``result.moment``. The remaining components of ``force`` are applied as given, e.g. the
    Table 3.5 inverse problem "b, theta_0 and n given" is not expressible this way; use
    ``TipConstraint`` with a direction (see ``inverse_fixed_ratio``).
    Inflection point: ``inflection_at`` = l1 (arc length from the clamp) adds m(l1) = 0 with the
    axial force Fx unknown (``MomentConstraint(l1)``); with ``tip_y`` and ``tip_angle`` this is
    the dissertation's Case 2c (Table 3.6): b, theta_0, l1 given, (Fx, Fy, M) = (-nP, P, -M_seed) out.
    ``start_loads`` = ((Fx, Fy), M): an approximate solution (e.g. the PRBM loads) to start the
    continuation from (``loaded_start``); default: the problem without the section moments.
    ``options`` go to ``solve_path`` (rtol, atol, tol, initial_step, n_samples, ...).
    """
    cons = list(constraints)
    if tip_x is not None:
        cons.append(TipConstraint((1.0, 0.0), tip_x))
    if tip_y is not None:
        cons.append(TipConstraint((0.0, 1.0), tip_y))
    mcons = list(moment_constraints)
    if inflection_at is not None:
        mcons.append(MomentConstraint(inflection_at))
    problem = ElasticaProblem(
        length=length,
        EI=EI,
        curvature=curvature,
        force=_pair(force),
        moment=moment,
        follower=_pair(follower),
        constraints=tuple(cons),
        tip_angle=tip_angle,
        moment_constraints=tuple(mcons),
        distributed=_pair(distributed),
    )
    start = None
    if start_loads is not None:
        start_options = SolveOptions()
        if "rtol" in options:
            start_options["rtol"] = options["rtol"]
        if "atol" in options:
            start_options["atol"] = options["atol"]
        start = loaded_start(problem, start_loads[0], start_loads[1], **start_options)
        if not start.converged:
            start = None
    return solve_path(problem, start=start, **options)
