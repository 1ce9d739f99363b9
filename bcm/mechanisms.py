"""The two example mechanisms of [chen2021, §4], and a rigid body carried by BCM beams.

- Circular-guided mechanism (section 4.1, Table 2): beam OA clamped at O, rigid crank AB welded
  at A and pinned at B on the beam line (B inferred at L_OA - L_AB from eq (18), see
  notes/seed-003-004.md section 2.1). Castigliano's first theorem: T_i = dv/dbeta (eq (20)).
- Slant parallelogram (section 4.2, Table 3): two equal beams at angle beta from the vertical
  carry a coupler of weight F_w pushed sideways by F_h; equal load sharing (eq (22)), guided
  beam tips, Crotti-Engesser with eq (16) or (17) (eqs (23)-(29)) and Castigliano with eq (30),
  whose printed derivatives eq (32) are corrected here (notes/seed-003-004.md section 2.2):

      f_x1 = k_a (700 u_x1 + 420 u_y1^2) / (700 + k_a u_y1^2)
      f_y1 = k_a u_y1 (840 u_x1 + 504 u_y1^2) / (700 + k_a u_y1^2)
             - 7 k_a^2 u_y1 (10 u_x1 + 6 u_y1^2)^2 / (700 + k_a u_y1^2)^2 + 12 u_y1

  (printed: denominators 700 + u_y1^2, no factor u_y1 in the first term of f_y1, k_a not squared).

``RigidBodyOnBeams`` generalises both: one rigid body joined rigidly to straight BCM beams that
are clamped to the ground, loaded by forces and moments, optionally pinned to the ground at a
point and driven by a prescribed rotation; equilibrium by Castigliano (dV/dq = generalised load).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import fsolve

from bcm.beam import C0, C1, C2, C3, K0, K1, K2, axial_stiffness_parameter, loads_from_deflections, strain_energy
from argcheck import checked

__all__ = [
    "circular_guided_torque",
    "circular_guided_torque_eq20",
    "slant_parallelogram",
    "eq32_corrected",
    "eq32_printed",
    "BCMBeam",
    "RigidBodyOnBeams",
    "Displacement",
]

Vector = NDArray[np.float64]
Matrix = NDArray[np.float64]
Point = Sequence[float] | Vector  # a position (x, y) or a force (Fx, Fy)
Forces = Sequence[tuple[Point, Point]]  # dead forces: (where, (Fx, Fy))


class Displacement(NamedTuple):
    """A prescribed displacement ``value`` of the body point ``point`` along axis 0 (x) or 1 (y)."""

    point: Point
    axis: int
    value: float


Law = Callable[[float, float, float], tuple[float, float]]  # (u_x1, u_y1, k_a) -> (f_x1, f_y1)


# ------------------------------------------------------------------ circular-guided mechanism


def _crank_deflections(beta: float, R: float) -> tuple[float, float, float]:
    """Eq (18): tip deflections of OA (normalised by L_OA) for crank angle beta."""
    return R * (math.cos(beta) - 1.0), R * math.sin(beta), beta


@checked(positive=("R", "ka"), finite=("beta",))
def circular_guided_torque(beta: float, R: float, ka: float) -> float:
    """Normalised input torque T_i = dv/dbeta (Castigliano on eq (11) with eqs (18), (19)).

    T_i = f_x du_x/dbeta + f_y du_y/dbeta + m_z, with du_x = -R sin(beta), du_y = R cos(beta);
    the dimensional torque is T = (EI/L_OA) T_i. R = L_AB/L_OA, ka = 12 L_OA^2/T^2.
    """
    ux, uy, theta = _crank_deflections(beta, R)
    fx, fy, mz = loads_from_deflections(ux, uy, theta, ka)
    return -fx * R * math.sin(beta) + fy * R * math.cos(beta) + mz


def circular_guided_torque_eq20(beta: float, R: float, ka: float) -> float:
    """Eq (20) with eq (21), as printed in [chen2021] (checked equal to ``circular_guided_torque``)."""
    sb, cb = math.sin(beta), math.cos(beta)
    k0, k1, k2 = K0, K1, K2
    Q1: float = -2 * R + k1[1, 1] * beta**2 + 2 * R * cb + 2 * k1[0, 1] * R * beta * sb + k1[0, 0] * R**2 * sb**2
    Q2: float = -1 + k2[1, 1] * ka * beta**2 + 2 * k2[0, 1] * ka * R * beta * sb + k2[0, 0] * ka * R**2 * sb**2

    def term(k: Matrix, shift: float = 0.0) -> float:
        value: float = k[1, 1] * beta + (k[0, 1] + shift) * R * sb + R * cb * (k[0, 1] * beta + k[0, 0] * R * sb)
        return value

    return term(k0) - ka * Q1 * term(k1, -1.0) / (2 * Q2) + ka**2 * Q1**2 * term(k2) / (4 * Q2**2)


# ------------------------------------------------------------------ slant parallelogram


def eq32_corrected(ux: float, uy: float, ka: float) -> tuple[float, float]:
    """(f_x1, f_y1) = grad of eq (30) at theta_z = 0 (corrected eq (32))."""
    d = 700.0 + ka * uy * uy
    fx = ka * (700.0 * ux + 420.0 * uy * uy) / d
    fy = (
        ka * uy * (840.0 * ux + 504.0 * uy * uy) / d
        - 7.0 * ka**2 * uy * (10.0 * ux + 6.0 * uy * uy) ** 2 / d**2
        + 12.0 * uy
    )
    return fx, fy


def eq32_printed(ux: float, uy: float, ka: float) -> tuple[float, float]:
    """Eq (32) exactly as printed in [chen2021] (inconsistent with eq (30); kept to show the misprint)."""
    d = 700.0 + uy * uy
    fx = ka * (700.0 * ux + 420.0 * uy * uy) / d
    fy = ka * (840.0 * ux + 504.0 * uy * uy) / d - 7.0 * ka * uy * (10.0 * ux + 6.0 * uy * uy) ** 2 / d**2 + 12.0 * uy
    return fx, fy


@dataclass(frozen=True)
class SlantResult:
    """The slant parallelogram's coupler displacement, with the result protocol the libraries share
    (converged, status, message, iterations, wall_time)."""

    dX: float  # coupler displacement along the weight (paper X, downward), length units
    dY: float  # coupler displacement along F_h (paper Y)
    fx1: float
    fy1: float
    mz1: float
    ux1: float
    uy1: float
    converged: bool = True
    message: str = "closed form"
    iterations: int = 0  # function evaluations of the root find (Castigliano forms); 0 closed form
    wall_time: float = 0.0

    @property
    def status(self) -> str:
        return "ok" if self.converged else "not converged"


def slant_parallelogram(
    F_h: float,
    *,
    F_w: float = 0.25,
    beta: float = 0.1,
    L: float = 25.0,
    E: float = 73e3,
    W: float = 5.1,
    T: float = 0.25,
    method: str = "CE3",
) -> SlantResult:
    """Coupler displacement of the slant parallelogram [chen2021, §4.2], one beam by symmetry.

    Units of Table 3 as mm, N, MPa. method: 'CE2' (eq (16): eqs (23)-(27)), 'CE3' (eq (17)),
    'castigliano' (eq (30) with the corrected eq (32)), 'castigliano-printed' (eq (32) as printed).
    Loads per beam: eq (22); guided tip theta_z1 = 0; coupler displacement: eqs (28), (29).
    """
    start = time.perf_counter()
    EI = E * W * T**3 / 12.0
    ka = axial_stiffness_parameter(L, T)
    converged, message, iterations = True, f"closed form ({method})", 0
    Fx1 = F_w * math.cos(beta) / 2.0 - F_h * math.sin(beta) / 2.0
    Fy1 = F_w * math.sin(beta) / 2.0 + F_h * math.cos(beta) / 2.0
    fx, fy = Fx1 * L**2 / EI, Fy1 * L**2 / EI
    if method in ("CE2", "CE3"):
        C, dC = C0 - fx * C1 + fx**2 * C2, -C1 + 2 * fx * C2
        if method == "CE3":
            C, dC = C - fx**3 * C3, dC - 3 * fx**2 * C3
        mz = -C[0, 1] / C[1, 1] * fy  # eq (24)/(25): theta_z1 = dv*/dm_z1 = 0
        p = np.array([fy, mz])
        ux = fx / ka + 0.5 * p @ dC @ p  # eq (26)
        uy = (C @ p)[0]  # eq (27)
    elif method in ("castigliano", "castigliano-printed"):
        law = eq32_corrected if method == "castigliano" else eq32_printed
        guess = slant_parallelogram(F_h, F_w=F_w, beta=beta, L=L, E=E, W=W, T=T, method="CE3")
        ux, uy, converged, message, iterations = _castigliano_root(law, fx, fy, ka, guess, method)
        mz = (K0 + fx * K1 + fx**2 * K2)[1, 0] * uy  # eq (3), second row, theta_z1 = 0
    else:
        raise ValueError(f"unknown method '{method}'")
    dY = L * (-ux * math.sin(beta) + uy * math.cos(beta))  # eq (28)
    dX = L * (ux * math.cos(beta) + uy * math.sin(beta))  # eq (29)
    return SlantResult(
        dX,
        dY,
        fx,
        fy,
        mz,
        ux,
        uy,
        converged=bool(converged),
        message=message,
        iterations=iterations,
        wall_time=time.perf_counter() - start,
    )


def _castigliano_root(
    law: Law, fx: float, fy: float, ka: float, guess: SlantResult, method: str
) -> tuple[float, float, bool, str, int]:
    """(u_x1, u_y1) with law(u_x1, u_y1) = (f_x1, f_y1), by MINPACK's hybrid method from the CE3 answer;
    converged when fsolve says so or when the residual is at rounding (1e-12 of the loads): fsolve's
    progress test stalls on an answer already exact to rounding (residuals ~1e-15 at F_h = 0.5 N), and
    that is an answer, not a failure. Returns (u_x1, u_y1, converged, message, function evaluations)."""
    u, info, ier, msg = fsolve(
        lambda v: np.array(law(v[0], v[1], ka)) - [fx, fy], [guess.ux1, guess.uy1], xtol=1e-14, full_output=True
    )
    residual = float(np.max(np.abs(np.array(law(u[0], u[1], ka)) - [fx, fy])))
    at_rounding = residual <= 1e-12 * max(abs(fx), abs(fy))
    converged = ier == 1 or at_rounding
    msg = " ".join(msg.split())
    if ier == 1:
        message = f"{method}: {msg}"
    else:
        state = "converged to rounding" if at_rounding else "not converged"
        message = f"{method}: {state}, residual {residual:.2g} (fsolve: {msg})"
    return float(u[0]), float(u[1]), bool(converged), message, int(info["nfev"])


# ------------------------------------------------------------------ general: one rigid body on beams


@dataclass(frozen=True)
class BCMBeam:
    """A straight beam clamped at ``start`` and welded to the body at ``end`` (undeformed positions)."""

    start: tuple[float, float]
    end: tuple[float, float]
    EI: float
    ka: float

    @property
    def length(self) -> float:
        return math.dist(self.start, self.end)


class RigidBodyOnBeams:
    """One rigid body joined rigidly to clamped BCM beams; q = (u, v, phi) of ``reference``.

    A pin at the reference point (``pinned=True``) removes u and v. The total potential is
    Pi = sum_i (EI_i/L_i) v_i(u_x, u_y, theta) - sum_k F_k . u(p_k) - sum M phi, and equilibrium is
    grad Pi = 0 over the free coordinates (Castigliano's first theorem per beam).
    """

    def __init__(self, beams: list[BCMBeam], reference: tuple[float, float], pinned: bool = False):
        self.beams, self.ref, self.pinned = beams, np.asarray(reference, float), pinned

    def position(self, point: Point, q: Vector) -> Vector:
        """Where a body point is: its undeformed position plus its displacement."""
        where: Vector = np.asarray(point, float) + self.displacement(point, q)
        return where

    def displacement(self, point: Point, q: Vector) -> Vector:
        """Displacement of a body point, u = (u, v) + (R(phi) - I) r, formed without the point's
        coordinates (cos phi - 1 = -2 sin^2(phi/2)), so a small motion keeps its relative accuracy."""
        r = np.asarray(point, float) - self.ref
        s, c1 = math.sin(q[2]), -2.0 * math.sin(q[2] / 2.0) ** 2
        u: Vector = q[:2] + np.array([c1 * r[0] - s * r[1], s * r[0] + c1 * r[1]])
        return u

    def _local(self, beam: BCMBeam, q: Vector) -> tuple[float, float, float, Vector, Vector, float]:
        """The beam's normalised tip deflections (u_x, u_y, theta) at q, its axis e1 and normal e2, its
        length."""
        X0, X1 = np.asarray(beam.start, float), np.asarray(beam.end, float)
        L = beam.length
        e1 = (X1 - X0) / L
        e2 = np.array([-e1[1], e1[0]])
        u = self.displacement(X1, q)  # d = X1 - X0 + u, with (X1 - X0) . e1 = L
        return (u @ e1) / L, (u @ e2) / L, q[2], e1, e2, L

    def strain_energy(self, q: Vector) -> float:
        """The beams' strain energy at q (energy units)."""
        total = 0.0
        for b in self.beams:
            ux, uy, th, *_ = self._local(b, q)
            total += b.EI / b.length * strain_energy(ux, uy, th, b.ka)
        return total

    def beam_states(self, q: Vector) -> list[tuple[float, float, float, float, float, float]]:
        """Per beam: normalised (u_x, u_y, theta, f_x, f_y, m_z)."""
        out = []
        for b in self.beams:
            ux, uy, th, *_ = self._local(b, q)
            out.append((ux, uy, th, *loads_from_deflections(ux, uy, th, b.ka)))
        return out

    def internal_force(self, q: Vector) -> Vector:
        """dV/dq: the generalised load the beams exert back (what the external loads must supply)."""
        g = np.zeros(3)
        c, s = math.cos(q[2]), math.sin(q[2])
        for b in self.beams:
            ux, uy, th, e1, e2, L = self._local(b, q)
            fx, fy, mz = loads_from_deflections(ux, uy, th, b.ka)
            F = (b.EI / L**2) * (fx * e1 + fy * e2)  # force on the beam tip, global
            r = np.asarray(b.end, float) - self.ref
            dp_dphi = np.array([-s * r[0] - c * r[1], c * r[0] - s * r[1]])
            g += np.array([F[0], F[1], F @ dp_dphi + (b.EI / L) * mz])
        return g

    def external_force(self, q: Vector, forces: Forces, moment: float) -> Vector:
        """Generalised load of dead forces [(point, (Fx, Fy))] and a body moment."""
        g = np.array([0.0, 0.0, moment])
        c, s = math.cos(q[2]), math.sin(q[2])
        for point, F in forces:
            r = np.asarray(point, float) - self.ref
            dp_dphi = np.array([-s * r[0] - c * r[1], c * r[0] - s * r[1]])
            g += np.array([F[0], F[1], np.dot(F, dp_dphi)])
        return g

    def solve(
        self,
        forces: Forces = (),
        moment: float = 0.0,
        rotation: float | None = None,
        guess: ArrayLike | None = None,
        displacement: Displacement | None = None,
    ) -> tuple[Vector, float]:
        """Equilibrium configuration q; with ``rotation`` prescribed, phi is fixed and the moment
        that must be applied is returned as the second value; with ``displacement`` prescribed (a body
        point's displacement along x or y), the force along that axis the point needs is returned; else
        the applied ``moment``.

        A prescribed displacement is the constraint C(q) = e . u(p, q) - value = 0, e the axis: Newton on
        grad Pi = lambda dC/dq and C = 0 over the free coordinates and lambda, the force the point needs
        along e (Lagrange). Newton from ``guess`` (rest if none); where that finds no root, the loads
        and the prescribed motion are ramped from rest, where q = 0 is the equilibrium, in 4 steps, then
        16, then 64, each step started from the last.
        """
        if rotation is not None and displacement is not None:
            raise ValueError("one prescribed motion at a time: a rotation or a displacement")
        start = np.zeros(3) if guess is None else np.array(guess, float)
        try:
            q, pull = self._equilibrium(forces, moment, rotation, start, displacement)
        except RuntimeError as first:
            q, pull = self._ramped(forces, moment, rotation, displacement, first)
        needed = moment
        if rotation is not None:
            needed = (self.internal_force(q) - self.external_force(q, forces, 0.0))[2]
        if displacement is not None:
            needed = pull
        return q, needed

    def _ramped(
        self,
        forces: Forces,
        moment: float,
        rotation: float | None,
        displacement: Displacement | None,
        first: RuntimeError,
    ) -> tuple[Vector, float]:
        """Load continuation from rest; re-raises the direct attempt's error with the ramp's."""
        for steps in (4, 16, 64):
            q, pull = np.zeros(3), 0.0
            try:
                for lam in np.arange(1, steps + 1) / steps:
                    scaled: Forces = [(p, lam * np.asarray(F, float)) for p, F in forces]
                    moved = (
                        None
                        if displacement is None
                        else Displacement(displacement.point, displacement.axis, lam * displacement.value)
                    )
                    q, pull = self._equilibrium(
                        scaled, lam * moment, None if rotation is None else lam * rotation, q, moved
                    )
                return q, pull
            except RuntimeError as exc:
                last = exc
        raise RuntimeError(f"{first}; ramped from rest in 64 steps: {last}")

    def _equilibrium(
        self,
        forces: Forces,
        moment: float,
        rotation: float | None,
        q0: Vector,
        displacement: Displacement | None = None,
    ) -> tuple[Vector, float]:
        """Newton on grad Pi = 0 over the free coordinates (with a prescribed displacement, on
        grad Pi = lambda dC/dq and C = 0, lambda scaled to the beams' force unit), from q0; returns q and
        lambda (0 without a prescribed displacement)."""
        free = [0, 1, 2] if not self.pinned else [2]
        if rotation is not None:
            free = [i for i in free if i != 2]
        q = np.array(q0, float)
        if rotation is not None:
            q[2] = rotation
        scale = max(b.EI / b.length**2 for b in self.beams)  # force unit of the beams
        length = min(b.length for b in self.beams)
        reach = 0.1 * np.array([length] * 2 + [1.0])[free]
        if displacement is None:
            if not free:
                return q, 0.0

            def res(z: Vector) -> Vector:
                qq = q.copy()
                qq[free] = z
                return (self.internal_force(qq) - self.external_force(qq, forces, moment))[free]

            q[free] = _newton(lambda z: res(z) / scale, q[free], reach)
            return q, 0.0
        if not free:
            raise RuntimeError("a prescribed displacement of a body whose every coordinate is held")
        axis = np.eye(2)[displacement.axis]

        def constrained(z: Vector) -> Vector:
            qq = q.copy()
            qq[free] = z[:-1]
            pull = z[-1] * scale
            grad = self._constraint_gradient(displacement.point, axis, qq)[free]
            g = (self.internal_force(qq) - self.external_force(qq, forces, moment))[free] - pull * grad
            c = axis @ self.displacement(displacement.point, qq) - displacement.value
            return np.concatenate([g / scale, [c / length]])

        z = _newton(constrained, np.concatenate([q[free], [0.0]]), np.concatenate([reach, [10.0]]))
        q[free] = z[:-1]
        return q, float(z[-1] * scale)

    def _constraint_gradient(self, point: Point, axis: Vector, q: Vector) -> Vector:
        """d(e . u(p, q))/dq for a body point p and an axis e."""
        r = np.asarray(point, float) - self.ref
        c, s = math.cos(q[2]), math.sin(q[2])
        dp_dphi = np.array([-s * r[0] - c * r[1], c * r[0] - s * r[1]])
        gradient: Vector = np.array([axis[0], axis[1], axis @ dp_dphi])
        return gradient


def _central_jacobian(fun: Callable[[Vector], Vector], z: Vector, f0: Vector) -> Matrix:
    """dfun/dz by central differences, step 1e-6 of max(|z_j|, 1e-3) (truncation error ~1e-12)."""
    J = np.empty((f0.size, z.size))
    for j in range(z.size):
        h = 1e-6 * max(abs(z[j]), 1e-3)
        e = np.zeros(z.size)
        e[j] = h
        J[:, j] = (fun(z + e) - fun(z - e)) / (2.0 * h)
    return J


def _newton(
    fun: Callable[[Vector], Vector], z0: Vector, reach: Vector, maxiter: int = 60, tol: float = 1e-13
) -> Vector:
    """Root of a normalised residual by Newton's method with a central-difference Jacobian; a step
    is shortened to at most ``reach`` per coordinate (0.1 L and 0.1 rad: the BCM's own range, so a
    far start walks towards the root instead of jumping to a spurious one) and halved where the
    residual is not finite.

    MINPACK's hybrid method (fsolve) stalls on stiff axial beams (k_a = 1e6: the Jacobian's
    condition number is 1e3..1e5) even with this Jacobian supplied, and so does damping on the
    residual norm (the norm rises on the way); full Newton steps converge in under 15 iterations.
    Raises RuntimeError, with the residual reached, when it does not converge.
    """
    z: Vector = np.array(z0, float)
    r = fun(z)
    for _ in range(maxiter):
        if not np.any(r):
            return z
        step = np.linalg.solve(_central_jacobian(fun, z, r), -r)
        step = step / max(1.0, np.max(np.abs(step) / reach))
        trial = fun(z + step)
        while not np.all(np.isfinite(trial)) and np.max(np.abs(step) / reach) > tol:
            step = step / 2.0  # outside the energy's domain (1 - k_a S2 <= 0): shorten
            trial = fun(z + step)
        z, r = z + step, trial
        if np.max(np.abs(step) / reach) <= tol:
            return z
    raise RuntimeError(
        f"BCM equilibrium not found: residual {np.max(np.abs(r)):.3g} (in EI/L^2) "
        f"after {maxiter} Newton iterations at q = {z}"
    )
