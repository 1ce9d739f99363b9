"""Planar rigid-link networks with torsion springs: equilibrium, stability and lock detection.

The model (plain data, no knowledge of case files): rigid bodies, each with the coordinates
q_b = (x_b, y_b, phi_b), the position of its reference point and its rotation from the unloaded
pose (phi_b = 0 there); the ground is a body with no coordinates. Every point is given by its
global position in the unloaded pose, so a point r of body b sits at

    p(q) = X_b + R(phi_b) (r0 - X_b0),        R(phi) = [[cos, -sin], [sin, cos]].

Joints are holonomic constraints Phi(q) = 0:
  pin      p_a(q) - p_b(q) = 0                                   (2 rows; b may be the ground)
  slider   n . (p_a(q) - p_0) = 0, n the normal of a ground line (1 row; ``guided`` adds phi_a = 0)
Prescribed motions of the load path are constraints too (displacement of a point along x or y,
rotation of a body); their multipliers are the loads needed to hold them.

Torsion springs act on relative rotations: U = 1/2 sum k_s (phi_a - phi_b - rest_s)^2.
External loads: dead forces at points (work F . p(q)), follower forces that turn with their body,
forces toward a fixed point (``PointedForce``, a rope over a pulley: along P - p(q), turned by an angle),
couples on bodies (work M phi_b).

Equilibrium is the stationary point of the total potential Pi = U - W under Phi = 0 (Lagrange):

    G(q, lam) = grad U - Q(q) + J^T lam = 0,   Phi(q) = 0,          J = dPhi/dq,

solved by Newton on the KKT system [[K, J^T], [J, 0]] with K = hess U - dQ/dq + sum lam_i hess Phi_i,
level after level (load stepping with step halving), or by pseudo-arclength continuation in the
load factor (``trace``), which passes limit points. Constraint rows that are linearly dependent
(redundant joints) are dropped by a rank-revealing QR of J at the unloaded pose.

Stability of a state: the Hessian K restricted to the tangent space of the constraints,
Z^T K Z with Z a basis of null(J) (including prescribed motions), positive definite = stable.
Mobility (degrees of freedom) = number of coordinates - rank J of the joints alone; a network
whose mobility is smaller than the number of prescribed motions is locked (``mobility``,
``LockedNetwork``). A prescribed motion must also be one the joints let the network make: its row
of the Jacobian at the unloaded pose must raise the rank of the joints' rows (and of the prescribed
motions before it). A row in their span is a motion no joint-compatible velocity makes (the coupler
of a parallelogram cannot turn: its joints keep its angle), refused before any Newton step
(``UnreachableMotion``). The rank is taken in the coordinates z = (x, y, L phi), L the network's
``length_scale``, each row scaled to unit length, as the singular values above ``RCOND`` times the
largest (``numpy.linalg.matrix_rank``'s rule): rounding leaves a dependent row ~1e-15 off the span,
while an independent one is O(1) off for any network not built within 1e-10 of a singular pose, and
the decision does not depend on the unit of length.

Sign conventions: angles CCW positive, rotations are changes from the unloaded pose; the load
received at a point is the total external load applied there (applied forces and couples, plus
what a prescribed motion there needs).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, NamedTuple, overload

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import qr
from scipy.linalg.lapack import dgesv

from planar import GROUND, Couple, Force, Pin, PointedForce, PrescribedDisplacement, PrescribedRotation

__all__ = [
    "Pin",
    "Slider",
    "TorsionSpring",
    "LinearSpring",
    "Force",
    "Couple",
    "PrescribedDisplacement",
    "PrescribedRotation",
    "Network",
    "NetworkState",
    "NetworkResult",
    "GroundLoad",
    "LockedNetwork",
    "UnreachableMotion",
    "GROUND",
    "RCOND",
    "solve",
    "trace",
]

RCOND = 1e-10  # a singular value at most RCOND times the largest counts as zero (rank of the Jacobian)


class LockedNetwork(ValueError):
    """The network cannot move as its prescribed motions ask (zero or too little mobility)."""


class UnreachableMotion(LockedNetwork):
    """A prescribed motion the network cannot make from its unloaded pose: the joints (with the prescribed
    motions before it, unless ``by_joints``) hold that rotation of ``load.body`` or that displacement of
    ``load.point``. ``moves``: the body (of a rotation) or the point (of a displacement) still moves in
    the motions the joints allow (a parallelogram's coupler translates), else it is held altogether."""

    def __init__(self, message: str, load: "PrescribedDisplacement | PrescribedRotation", by_joints: bool, moves: bool):
        super().__init__(message)
        self.load = load
        self.by_joints = by_joints
        self.moves = moves


@dataclass(frozen=True)
class Slider:
    """Point ``at`` of body ``a`` slides on the ground line through ``at`` along ``direction``;
    ``guided``: the body's rotation is held as well (a guided support)."""

    a: str
    at: tuple[float, float]
    direction: tuple[float, float]
    guided: bool = False
    name: str = ""


@dataclass(frozen=True)
class TorsionSpring:
    """Torsion spring of stiffness k (moment/rad) on phi_a - phi_b, free at phi_a - phi_b = rest (rad)."""

    a: str
    b: str
    k: float
    rest: float = 0.0
    name: str = ""


@dataclass(frozen=True)
class LinearSpring:
    """Spring of stiffness k (force/length) on the displacement of a named point along a fixed
    ground direction (e.g. a slider's spring): U = 1/2 k (e . (p - p0))^2."""

    point: str
    direction: tuple[float, float]
    k: float
    name: str = ""


Load = Force | PointedForce | Couple | PrescribedDisplacement | PrescribedRotation
Prescription = PrescribedDisplacement | PrescribedRotation
#: indices of rows of a Jacobian (int32 from LAPACK's pivots, or the platform's int)
Rows = NDArray[np.signedinteger[Any]]


class _Unreachable(NamedTuple):
    """The first prescribed motion the network cannot make (``UnreachableMotion``'s fields)."""

    message: str
    motion: int  # its index among the prescribed motions
    by_joints: bool
    moves: bool


class _LinearSpringTerm(NamedTuple):
    """One linear spring at a configuration (``Network._linear_spring_terms``)."""

    body: int
    k: float
    stretch: float
    de: NDArray[np.float64]
    d2: float


@dataclass
class Network:
    """Bodies, named points (name -> (body, (x, y)) in the unloaded pose), joints and springs.

    ``origins``: each body's reference point (default: its first point); the ground needs none.
    """

    bodies: list[str]
    points: dict[str, tuple[str, tuple[float, float]]]
    pins: list[Pin] = field(default_factory=list)
    sliders: list[Slider] = field(default_factory=list)
    springs: list[TorsionSpring] = field(default_factory=list)
    origins: dict[str, tuple[float, float]] = field(default_factory=dict)
    linear_springs: list[LinearSpring] = field(default_factory=list)

    def __post_init__(self) -> None:
        if GROUND in self.bodies:
            raise ValueError(f"'{GROUND}' is the fixed frame, not a movable body")
        if len(set(self.bodies)) != len(self.bodies):
            raise ValueError("body names must be unique")
        self.index = {b: i for i, b in enumerate(self.bodies)}
        self.index[GROUND] = len(self.bodies)
        for name, (body, _) in self.points.items():
            if body not in self.index:
                raise ValueError(f"point '{name}' is on unknown body '{body}'")
        items: list[Pin | Slider | TorsionSpring] = [*self.pins, *self.sliders, *self.springs]
        for item in items:
            for body in (item.a, getattr(item, "b", GROUND)):
                if body not in self.index:
                    raise ValueError(f"{type(item).__name__} {item.name or item}: unknown body '{body}'")
        for body in self.bodies:
            if body not in self.origins:
                first = next((xy for b, xy in self.points.values() if b == body), None)
                if first is None:
                    first = next((p.at for p in self.pins if body in (p.a, p.b)), (0.0, 0.0))
                self.origins[body] = first
        nb = len(self.bodies)
        self.n = 3 * nb
        self.X0 = np.zeros((nb + 1, 2))
        for body, xy in self.origins.items():
            if body in self.index and body != GROUND:
                self.X0[self.index[body]] = xy
        # pins, vectorised: body indices and arms (r0 - X_b0) on each side
        self._pin_a = np.array([self.index[p.a] for p in self.pins], int)
        self._pin_b = np.array([self.index[p.b] for p in self.pins], int)
        at = np.array([p.at for p in self.pins], float).reshape(-1, 2)
        self._pin_ra = at - self.X0[self._pin_a]
        self._pin_rb = at - self.X0[self._pin_b]
        self._pin_at = at
        k = np.arange(len(self.pins))
        width = 3 * len(self.bodies) + 3
        rx, ry = 2 * k * width, (2 * k + 1) * width
        ca, cb = 3 * self._pin_a, 3 * self._pin_b
        # flat indices of J: (x_a in row x, y_a in row y, -x_b, -y_b) = (+1, +1, -1, -1), then phi_a, phi_b
        self._pin_flat = np.concatenate(
            [rx + ca, ry + ca + 1, rx + cb, ry + cb + 1, rx + ca + 2, ry + ca + 2, rx + cb + 2, ry + cb + 2]
        )
        self._pin_ones = np.concatenate([np.ones(2 * len(k)), -np.ones(2 * len(k))])
        self._joint_rows = 2 * len(self.pins) + sum(1 + s.guided for s in self.sliders)
        self._X0_list = self.X0.tolist()
        self._pin_list = [
            (int(a), int(b), float(ra[0]), float(ra[1]), float(rb[0]), float(rb[1]))
            for a, b, ra, rb in zip(self._pin_a, self._pin_b, self._pin_ra, self._pin_rb)
        ]
        # springs: a constant matrix D (rows: springs, columns: phi of the bodies)
        self._spring_k = np.array([s.k for s in self.springs], float)
        self._spring_rest = np.array([s.rest for s in self.springs], float)
        D = np.zeros((len(self.springs), nb + 1))
        for i, s in enumerate(self.springs):
            D[i, self.index[s.a]] += 1.0
            D[i, self.index[s.b]] -= 1.0
        self._spring_D = D[:, :nb]
        self._spring_H = np.zeros((self.n, self.n))
        self._spring_H[2::3, 2::3] = self._spring_D.T @ (self._spring_k[:, None] * self._spring_D)
        # (mobility, rank, independent joint rows), computed once by solve
        self._analysis: tuple[int, int, Rows] | None = None
        # prescribed motions -> the unreachable one, if any
        self._reachable: dict[tuple[tuple[str, str] | str, ...], _Unreachable | None] = {}
        self._length: float | None = None
        for ls in self.linear_springs:
            if ls.point not in self.points:
                raise ValueError(f"linear spring {ls.name or ''} at unknown point '{ls.point}'")

    # --- geometry -------------------------------------------------------------------------------
    def point_arm(self, point: str) -> tuple[int, NDArray[np.float64]]:
        body, xy = self.points[point]
        i = self.index[body]
        return i, np.asarray(xy, float) - self.X0[i]

    def state_arrays(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(X, phi) of every body and the ground (last row) for coordinates q."""
        nb = len(self.bodies)
        X = np.empty((nb + 1, 2))
        phi = np.zeros(nb + 1)
        X[:nb] = self.X0[:nb] + q.reshape(nb, 3)[:, :2]
        X[nb] = 0.0
        phi[:nb] = q[2::3]
        return X, phi

    def position(self, q: NDArray[np.float64], point: str) -> NDArray[np.float64]:
        i, r = self.point_arm(point)
        X, phi = self.state_arrays(q)
        c, s = math.cos(phi[i]), math.sin(phi[i])
        p: NDArray[np.float64] = X[i] + np.array([c * r[0] - s * r[1], s * r[0] + c * r[1]])
        return p

    # --- constraints ----------------------------------------------------------------------------
    @overload
    def joint_constraints(
        self, q: NDArray[np.float64], lam: None = None, diagonal: bool = False
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], None]: ...

    @overload
    def joint_constraints(
        self, q: NDArray[np.float64], lam: NDArray[np.float64], diagonal: bool = False
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...

    def joint_constraints(
        self, q: NDArray[np.float64], lam: NDArray[np.float64] | None = None, diagonal: bool = False
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64] | None]:
        """(Phi, J, H_lam) of the pins and sliders: residual, Jacobian, and sum lam_i hess Phi_i (it is
        diagonal, on the rotations: ``diagonal=True`` returns that diagonal only).

        Pin k, rows 2k (x) and 2k+1 (y): Phi = X_a + R_a r_a - X_b - R_b r_b;
        dPhi/d(x_a, y_a, phi_a) = [I, (-R_a r_a)_y, (R_a r_a)_x], the b side with the opposite sign;
        d2 Phi/dphi_a2 = -R_a r_a (so H[phi_a, phi_a] = -lam . R_a r_a), +R_b r_b for b.
        A PRB network has a handful of pins, so this is a loop over them in plain floats (numpy's
        per-call overhead would dominate); the ground's three columns are written and then dropped."""
        nb = len(self.bodies)
        width = 3 * nb + 3
        m_pin = 2 * len(self.pins)
        Phi = np.empty(self._joint_rows)
        J = np.zeros((self._joint_rows, width))
        Hd = [0.0] * width if lam is not None else None
        lv: list[float] = lam.tolist() if lam is not None else []
        qv: list[float] = q.tolist() + [0.0, 0.0, 0.0]
        X0 = self._X0_list
        for k, (ia, ib, rax, ray, rbx, rby) in enumerate(self._pin_list):
            ca, sa = math.cos(qv[3 * ia + 2]), math.sin(qv[3 * ia + 2])
            cb, sb = math.cos(qv[3 * ib + 2]), math.sin(qv[3 * ib + 2])
            Rax, Ray = ca * rax - sa * ray, sa * rax + ca * ray
            Rbx, Rby = cb * rbx - sb * rby, sb * rbx + cb * rby
            Phi[2 * k] = X0[ia][0] + qv[3 * ia] + Rax - X0[ib][0] - qv[3 * ib] - Rbx
            Phi[2 * k + 1] = X0[ia][1] + qv[3 * ia + 1] + Ray - X0[ib][1] - qv[3 * ib + 1] - Rby
            rx, ry = J[2 * k], J[2 * k + 1]
            rx[3 * ia] = 1.0
            ry[3 * ia + 1] = 1.0
            rx[3 * ia + 2] = -Ray
            ry[3 * ia + 2] = Rax
            rx[3 * ib] = -1.0
            ry[3 * ib + 1] = -1.0
            rx[3 * ib + 2] = Rby
            ry[3 * ib + 2] = -Rbx
            if Hd is not None:
                lx, ly = lv[2 * k], lv[2 * k + 1]
                Hd[3 * ia + 2] -= lx * Rax + ly * Ray
                Hd[3 * ib + 2] += lx * Rbx + ly * Rby
        H = np.array(Hd) if Hd is not None else None
        phi = q[2::3]
        X = self.X0[:nb] + q.reshape(nb, 3)[:, :2] if self.sliders else None
        row = m_pin
        for s in self.sliders:
            assert X is not None  # computed whenever there are sliders
            i = self.index[s.a]
            d = np.asarray(s.direction, float)
            nrm = np.array([-d[1], d[0]]) / math.hypot(*d)
            r = np.asarray(s.at, float) - self.X0[i]
            c, sn = math.cos(phi[i]), math.sin(phi[i])
            Rr = np.array([c * r[0] - sn * r[1], sn * r[0] + c * r[1]])
            Phi[row] = nrm @ (X[i] + Rr - np.asarray(s.at, float))
            J[row, 3 * i : 3 * i + 2] = nrm
            J[row, 3 * i + 2] = nrm @ np.array([-Rr[1], Rr[0]])
            if H is not None and lam is not None:  # H is made exactly when lam is given
                H[3 * i + 2] += -lam[row] * (nrm @ Rr)
            row += 1
            if s.guided:
                Phi[row] = phi[i]
                J[row, 3 * i + 2] = 1.0
                row += 1
        n = 3 * nb
        H = None if H is None else (H[:n] if diagonal else np.diag(H[:n]))
        return Phi, J[:, :n], H

    def joint_rank(self, q: NDArray[np.float64] | None = None, rtol: float = 1e-9) -> tuple[int, Rows]:
        """Rank of the joints' Jacobian and the indices of a maximal independent set of its rows."""
        q = np.zeros(self.n) if q is None else q
        _, J, _ = self.joint_constraints(q)
        if J.shape[0] == 0:
            return 0, np.zeros(0, int)
        _, R, piv = qr(J.T, pivoting=True, mode="economic")
        d = np.abs(np.diag(R))
        rank = int(np.sum(d > rtol * max(d[0], 1.0))) if d.size else 0
        return rank, np.sort(piv[:rank])

    def first_order_mobility(self) -> int:
        """Coordinates - rank of the joints' Jacobian at the unloaded pose (instantaneous freedoms)."""
        return self.n - self.joint_rank()[0]

    def mobility(self) -> int:
        """Degrees of freedom of the network at the unloaded pose.

        First order: coordinates - rank J. At a singular pose (e.g. links in line) a first-order motion
        v may not extend to a finite one; each null direction v of J is kept only if the second-order
        compatibility J w = -(v^T hess Phi_i v)_i has a solution (second-order test of rigidity),
        so a network that locks at a dead-centre pose reports zero mobility."""
        rank, rows = self.joint_rank()
        m = self.n - rank
        if m == 0:
            return 0
        q = np.zeros(self.n)
        _, J, _ = self.joint_constraints(q)  # every row: a row dependent at this pose may curve away
        if not J.shape[0]:
            return self.n
        null = np.linalg.svd(J)[2][rank:]
        length = self.length_scale()
        kept = 0
        unit = np.eye(J.shape[0])
        hessians = [self.joint_constraints(q, unit[r])[2] for r in range(J.shape[0])]
        for v in null:
            curvature = np.array([v @ H @ v for H in hessians])
            size = float(np.linalg.norm(curvature))
            if size <= 1e-12 * length:
                kept += 1
                continue
            w, *_ = np.linalg.lstsq(J, -curvature, rcond=None)
            if np.linalg.norm(J @ w + curvature) <= 1e-8 * size:
                kept += 1
        return kept

    def length_scale(self) -> float:
        """Twice the largest distance of a point or pin from their centroid in the unloaded pose."""
        if self._length is None:
            pts = [xy for _, xy in self.points.values()] + [p.at for p in self.pins]
            P = np.asarray(pts, float).reshape(-1, 2)
            size = float(np.max(np.linalg.norm(P - P.mean(axis=0), axis=1))) * 2 if len(P) > 1 else 0.0
            self._length = size or 1.0
        return self._length

    # --- energy ---------------------------------------------------------------------------------
    def spring_deflections(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        d: NDArray[np.float64] = self._spring_D @ q[2::3] - self._spring_rest
        return d

    def _linear_spring_terms(self, q: NDArray[np.float64]) -> list[_LinearSpringTerm]:
        """For each linear spring: (body index, stretch s = e . (p - p0), e . dp/dq on the body's three
        coordinates, e . d2p/dphi2)."""
        nb = len(self.bodies)
        out: list[_LinearSpringTerm] = []
        for ls in self.linear_springs:
            i, r = self.point_arm(ls.point)
            e = np.asarray(ls.direction, float) / math.hypot(*ls.direction)
            if i == nb:
                continue
            phi = q[3 * i + 2]
            c, sn = math.cos(phi), math.sin(phi)
            Rr = np.array([c * r[0] - sn * r[1], sn * r[0] + c * r[1]])
            stretch = float(e @ (q[3 * i : 3 * i + 2] + Rr - r))
            out.append(
                _LinearSpringTerm(
                    i, ls.k, stretch, np.array([e[0], e[1], e @ np.array([-Rr[1], Rr[0]])]), -float(e @ Rr)
                )
            )
        return out

    def strain_energy(self, q: NDArray[np.float64]) -> float:
        d = self.spring_deflections(q)
        U = 0.5 * float(self._spring_k @ (d * d))
        for _, k, stretch, _, _ in self._linear_spring_terms(q):
            U += 0.5 * k * stretch**2
        return U

    def spring_gradient(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        g = np.zeros(self.n)
        g[2::3] = self._spring_D.T @ (self._spring_k * self.spring_deflections(q))
        for i, k, stretch, de, _ in self._linear_spring_terms(q):
            g[3 * i : 3 * i + 3] += k * stretch * de
        return g

    def spring_hessian(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        if not self.linear_springs:
            return self._spring_H
        H = self._spring_H.copy()
        for i, k, stretch, de, d2 in self._linear_spring_terms(q):
            H[3 * i : 3 * i + 3, 3 * i : 3 * i + 3] += k * np.outer(de, de)
            H[3 * i + 2, 3 * i + 2] += k * stretch * d2
        return H

    def driving_torque(self, q: NDArray[np.float64], body: str) -> float:
        """The torque on ``body`` that holds the springs at the configuration q (joints closed), by
        virtual work: T = grad U . v with v the joint-compatible velocity of unit rotation rate of
        ``body`` (J v = 0, v_phi(body) = 1); a least-squares v where the joints are redundant."""
        _, J, _ = self.joint_constraints(q)
        i = self.index[body]
        drive = np.zeros((1, self.n))
        drive[0, 3 * i + 2] = 1.0
        A = np.vstack([J, drive])
        rhs = np.zeros(A.shape[0])
        rhs[-1] = 1.0
        v, *_ = np.linalg.lstsq(A, rhs, rcond=None)
        return float(self.spring_gradient(q) @ v)


@dataclass
class NetworkState:
    """One equilibrium: coordinates, multipliers, and how it was found."""

    q: NDArray[np.float64]
    lam: NDArray[np.float64]
    converged: bool
    iterations: int
    stable: bool | None
    min_reduced_eigenvalue: float


@dataclass(frozen=True)
class GroundLoad:
    """A load the ground exerts on the network through one joint or spring: the force (fx, fy) at the
    point ``at`` (None for a spring's couple) and the couple ``moment`` (CCW)."""

    name: str
    at: tuple[float, float] | None
    fx: float
    fy: float
    moment: float


@dataclass
class NetworkResult:
    """Outcome of a solve over load levels (scipy-style: success flag and message, never silent)."""

    network: Network
    states: list[NetworkState]
    converged: bool
    message: str
    wall_time: float
    iterations: int
    mobility: int
    load_factor: NDArray[np.float64] | None = None

    @property
    def n_levels(self) -> int:
        return len(self.states)

    def position(self, point: str, level: int) -> NDArray[np.float64]:
        return self.network.position(self.states[level].q, point)

    def displacement(self, point: str, level: int) -> NDArray[np.float64]:
        u: NDArray[np.float64] = self.position(point, level) - np.asarray(self.network.points[point][1], float)
        return u

    def rotation(self, body: str, level: int) -> float:
        """Rotation of a body from the unloaded pose (rad, CCW)."""
        if body == GROUND:
            return 0.0
        return float(self.states[level].q[3 * self.network.index[body] + 2])

    def strain_energy(self, level: int) -> float:
        return self.network.strain_energy(self.states[level].q)

    def ground_loads(self, level: int) -> list["GroundLoad"]:
        """The loads the ground exerts on the network at a level, one per joint or spring to the ground.

        From the multipliers: the generalised constraint force on the bodies is -J^T lam, so a pin
        (a, ground) pushes body a with -lam_k (+lam_k when the ground is its first body); a slider
        with -n lam along its normal n at its current contact point (a guided slider adds the couple
        -lam); a spring to the ground turns its body with -k (phi_a - phi_b - rest) (the sign
        follows which side the ground is). Raises ValueError where joint rows were dropped as
        redundant: the PRB model is then statically indeterminate and the split is not unique."""
        net = self.network
        assert net._analysis is not None  # set by the solve that made this result (`_check_mobility`)
        rows = net._analysis[2]
        if len(rows) != net._joint_rows:
            raise ValueError(
                "redundant joints in the PRB model: the loads through its ground joints are statically indeterminate"
            )
        state = self.states[level]
        lam = state.lam
        out: list[GroundLoad] = []
        for k, pin in enumerate(net.pins):
            if GROUND in (pin.a, pin.b) and pin.a != pin.b:
                sign = -1.0 if pin.b == GROUND else 1.0
                out.append(GroundLoad(pin.name, pin.at, sign * float(lam[2 * k]), sign * float(lam[2 * k + 1]), 0.0))
        row = 2 * len(net.pins)
        for sl in net.sliders:
            d = np.asarray(sl.direction, float)
            normal = np.array([-d[1], d[0]]) / math.hypot(*d)
            contact = self._slider_point(sl, state.q)
            moment = -float(lam[row + 1]) if sl.guided else 0.0
            fx, fy = -normal * float(lam[row])
            out.append(GroundLoad(sl.name, contact, fx, fy, moment))
            row += 1 + sl.guided
        torques = net.spring_deflections(state.q) * net._spring_k
        for spring, torque in zip(net.springs, torques.tolist()):
            if GROUND in (spring.a, spring.b) and spring.a != spring.b:
                out.append(GroundLoad(spring.name, None, 0.0, 0.0, -torque if spring.b == GROUND else torque))
        return out

    def pin_force(self, level: int, name: str) -> tuple[float, float]:
        """The force a pin applies to its first body (``a``) at a level: -lam of its two rows (the
        generalised constraint force is -J^T lam). Raises ValueError where joint rows were dropped as
        redundant (the split between the joints is then not unique) or no pin has that name."""
        net = self.network
        assert net._analysis is not None  # set by the solve that made this result (`_check_mobility`)
        if len(net._analysis[2]) != net._joint_rows:
            raise ValueError(
                "redundant joints in the PRB model: the loads through its pins are statically indeterminate"
            )
        k = next((i for i, pin in enumerate(net.pins) if pin.name == name), None)
        if k is None:
            raise ValueError(f"no pin named '{name}'")
        lam = self.states[level].lam
        return -float(lam[2 * k]), -float(lam[2 * k + 1])

    def _slider_point(self, slider: "Slider", q: NDArray[np.float64]) -> tuple[float, float]:
        net = self.network
        i = net.index[slider.a]
        r = np.asarray(slider.at, float) - net.X0[i]
        X, phi = net.state_arrays(q)
        c, s = math.cos(phi[i]), math.sin(phi[i])
        return (float(X[i][0] + c * r[0] - s * r[1]), float(X[i][1] + s * r[0] + c * r[1]))

    def spring_torques(self, level: int) -> dict[str, float]:
        """Torque k (phi_a - phi_b - rest) carried by each spring (name or index)."""
        d = self.network.spring_deflections(self.states[level].q)
        return {
            s.name or str(i): float(k * x)
            for i, (s, k, x) in enumerate(zip(self.network.springs, self.network._spring_k, d))
        }


# --- the problem: loads of one level as generalised forces and prescribed-motion constraints ---------
class _Problem:
    """Loads along the path, evaluated at a load parameter t (level index, fractional between levels)."""

    def __init__(self, network: Network, loads: list[Load], n_levels: int):
        self.net = network
        self.n_levels = n_levels
        self.forces = [ld for ld in loads if isinstance(ld, Force)]
        self.pointed = [ld for ld in loads if isinstance(ld, PointedForce)]
        self.couples = [ld for ld in loads if isinstance(ld, Couple)]
        self.disps = [ld for ld in loads if isinstance(ld, PrescribedDisplacement)]
        self.rots = [ld for ld in loads if isinstance(ld, PrescribedRotation)]
        for ld in loads:
            if not isinstance(ld, (Force, PointedForce, Couple, PrescribedDisplacement, PrescribedRotation)):
                raise ValueError(
                    f"{type(ld).__name__}: the PRB network takes forces, forces toward a point, "
                    "couples and prescribed motions only"
                )
            values = [getattr(ld, f) for f in ("fx", "fy", "m", "values") if hasattr(ld, f)]
            for v in values:
                if len(v) != n_levels:
                    raise ValueError(f"{ld}: {len(v)} values for {n_levels} load levels")
            body = getattr(ld, "body", None)
            if body is not None and body not in network.index:
                raise ValueError(f"{type(ld).__name__} on unknown body '{body}'")
            point = getattr(ld, "point", None)
            if point is not None and point not in network.points:
                raise ValueError(f"{type(ld).__name__} at unknown point '{point}'")
            if isinstance(ld, PrescribedDisplacement) and ld.axis not in ("x", "y"):
                raise ValueError(f"prescribed displacement axis '{ld.axis}': use 'x' or 'y'")
            if isinstance(ld, PrescribedRotation) and ld.body == GROUND:
                raise ValueError("a prescribed rotation of the ground")
        self.force_arms = [network.point_arm(f.point) for f in self.forces]
        self.pointed_arms = [network.point_arm(f.point) for f in self.pointed]
        self.disp_arms = [network.point_arm(d.point) for d in self.disps]
        self.n_prescribed = len(self.disps) + len(self.rots)
        self.length = network.length_scale()
        # the converged state's Hessian and Jacobian, for its stability
        self.last_kkt: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None

    @staticmethod
    def _at(values: tuple[float, ...], t: float) -> float:
        """values at the load parameter t: level i at t = i, linear in between, from 0 below level 0."""
        if t <= 0.0:
            return values[0] * max(t + 1.0, 0.0) if t < 0.0 else values[0]
        i = min(int(t), len(values) - 1)
        if i >= len(values) - 1:
            return values[-1]
        f = t - i
        return values[i] * (1.0 - f) + values[i + 1] * f

    def generalised_forces(
        self, q: NDArray[np.float64], t: float, scale: float = 1.0
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(Q, dQ/dq) of the applied forces and couples at load parameter t (times ``scale``)."""
        net = self.net
        n = net.n
        Q = np.zeros(n)
        dQ = np.zeros((n, n))
        nb = len(net.bodies)
        for f, (i, r) in zip(self.forces, self.force_arms):
            if i == nb:
                continue
            Fx, Fy = scale * self._at(f.fx, t), scale * self._at(f.fy, t)
            phi = q[3 * i + 2]
            c, s = math.cos(phi), math.sin(phi)
            Rr = (c * r[0] - s * r[1], s * r[0] + c * r[1])
            if f.follower:
                Fx, Fy = c * Fx - s * Fy, s * Fx + c * Fy
                Q[3 * i] += Fx
                Q[3 * i + 1] += Fy
                Q[3 * i + 2] += r[0] * (scale * self._at(f.fy, t)) - r[1] * (scale * self._at(f.fx, t))
                dQ[3 * i, 3 * i + 2] += -Fy
                dQ[3 * i + 1, 3 * i + 2] += Fx
            else:
                Q[3 * i] += Fx
                Q[3 * i + 1] += Fy
                Q[3 * i + 2] += Rr[0] * Fy - Rr[1] * Fx
                dQ[3 * i + 2, 3 * i + 2] += -(Rr[0] * Fx + Rr[1] * Fy)
        for pf, (i, r) in zip(self.pointed, self.pointed_arms):
            if i < nb:
                self._pointed_force(Q, dQ, q, i, r, pf, scale * self._at(pf.values, t))
        for cp in self.couples:
            i = net.index[cp.body]
            if i < nb:
                Q[3 * i + 2] += scale * self._at(cp.m, t)
        return Q, dQ

    @staticmethod
    def _pointed_force(
        Q: NDArray[np.float64],
        dQ: NDArray[np.float64],
        q: NDArray[np.float64],
        i: int,
        r: NDArray[np.float64],
        pf: PointedForce,
        T: float,
    ) -> None:
        """Add a force of size T toward ``pf.toward`` (turned by ``pf.angle``) at the point of body i with
        arm r, and its derivative, to (Q, dQ).

        p = X_i + R(phi_i) r, d = P - p, F = T R(a) d / |d|; with A = T R(a) (I - d d^T / |d|^2) / |d|,
        dF/dq = -A dp/dq, where dp/dX_i = I and dp/dphi_i = (-(R r)_y, (R r)_x). Q gets F on X_i and
        (R r) x F on phi_i; d((R r) x F)/dq = d(R r)/dq x F + (R r) x dF/dq."""
        c, s = math.cos(q[3 * i + 2]), math.sin(q[3 * i + 2])
        Rr = np.array([c * r[0] - s * r[1], s * r[0] + c * r[1]])
        d = np.array(pf.toward, float) - (q[3 * i : 3 * i + 2] + Rr)
        length = math.hypot(d[0], d[1])
        if length == 0.0:
            raise ValueError(f"the force at '{pf.point}' pulls toward {pf.toward}, where the point now is")
        ca, sa = math.cos(pf.angle), math.sin(pf.angle)
        turn = np.array([[ca, -sa], [sa, ca]])
        F = T * turn @ d / length
        unit = d / length
        A = T * turn @ (np.eye(2) - np.outer(unit, unit)) / length
        dp = np.array([[1.0, 0.0, -Rr[1]], [0.0, 1.0, Rr[0]]])  # dp/d(x_i, y_i, phi_i)
        dF = -A @ dp
        cols = slice(3 * i, 3 * i + 3)
        Q[3 * i : 3 * i + 2] += F
        Q[3 * i + 2] += Rr[0] * F[1] - Rr[1] * F[0]
        dQ[3 * i : 3 * i + 2, cols] += dF
        dQ[3 * i + 2, cols] += Rr[0] * dF[1] - Rr[1] * dF[0]
        dQ[3 * i + 2, 3 * i + 2] += -(Rr[0] * F[0] + Rr[1] * F[1])

    def prescribed(
        self, q: NDArray[np.float64], t: float, scale: float = 1.0
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(Phi, J) of the prescribed motions at load parameter t."""
        net = self.net
        m = self.n_prescribed
        Phi = np.empty(m)
        J = np.zeros((m, net.n))
        nb = len(net.bodies)
        for k, (d, (i, r)) in enumerate(zip(self.disps, self.disp_arms)):
            axis = 0 if d.axis == "x" else 1
            target = scale * self._at(d.values, t)
            if i == nb:
                raise LockedNetwork(f"prescribed displacement of '{d.point}', which is on the ground")
            phi = q[3 * i + 2]
            c, s = math.cos(phi), math.sin(phi)
            Rr = (c * r[0] - s * r[1], s * r[0] + c * r[1])
            Phi[k] = q[3 * i + axis] + Rr[axis] - r[axis] - target
            J[k, 3 * i + axis] = 1.0
            J[k, 3 * i + 2] = -Rr[1] if axis == 0 else Rr[0]
        for k, rot in enumerate(self.rots, start=len(self.disps)):
            i = net.index[rot.body]
            Phi[k] = q[3 * i + 2] - scale * self._at(rot.values, t)
            J[k, 3 * i + 2] = 1.0
        return Phi, J

    def prescribed_hessian(self, q: NDArray[np.float64], lam: NDArray[np.float64]) -> NDArray[np.float64]:
        """sum lam_k hess Phi_k of the prescribed displacements (rotations are linear)."""
        net = self.net
        H = np.zeros((net.n, net.n))
        for k, (d, (i, r)) in enumerate(zip(self.disps, self.disp_arms)):
            axis = 0 if d.axis == "x" else 1
            phi = q[3 * i + 2]
            c, s = math.cos(phi), math.sin(phi)
            Rr = (c * r[0] - s * r[1], s * r[0] + c * r[1])
            H[3 * i + 2, 3 * i + 2] += -lam[k] * Rr[axis]
        return H


def _residual(
    problem: _Problem, rows: Rows, q: NDArray[np.float64], lam: NDArray[np.float64], t: float, scale: float = 1.0
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], float]:
    """KKT residual and matrix at (q, lam) for load parameter t, and the force scale of the residual
    (the largest of the spring, applied and constraint generalised forces)."""
    net = problem.net
    nj = len(rows)
    every_row = nj == net._joint_rows  # no redundant joint rows dropped (the usual case)
    if every_row:
        full = lam[:nj]
    else:
        full = np.zeros(net._joint_rows)
        full[rows] = lam[:nj]
    Phi_j, J_j, H_j = net.joint_constraints(q, full, diagonal=True)
    if not every_row:
        Phi_j, J_j = Phi_j[rows], J_j[rows]
    Q, dQ = problem.generalised_forces(q, t, scale)
    grad = net.spring_gradient(q)
    K = net.spring_hessian(q) - dQ
    K.flat[:: net.n + 1] += H_j
    if problem.n_prescribed:
        Phi_p, J_p = problem.prescribed(q, t, scale)
        Phi = np.concatenate([Phi_j, Phi_p])
        J = np.vstack([J_j, J_p])
        K += problem.prescribed_hessian(q, lam[nj:])
    else:
        Phi, J = Phi_j, J_j
    reaction = J.T @ lam
    g = grad - Q + reaction
    force = float(np.abs(np.concatenate((grad, Q, reaction))).max()) if net.n else 0.0
    return g, Phi, K, J, force


def _newton(
    problem: _Problem,
    rows: Rows,
    q: NDArray[np.float64],
    lam: NDArray[np.float64],
    t: float,
    *,
    rtol: float,
    maxiter: int,
    scale: float = 1.0,
) -> tuple[NDArray[np.float64], NDArray[np.float64], bool, int]:
    """Newton on the KKT system at fixed load parameter t, until the residual is below rtol times its
    force scale and the loop closes to rtol times the network's size (a step-size test alone can stop
    on a singular system). Returns (q, lam, converged, linear solves)."""
    n = problem.net.n
    closure = rtol * problem.length
    for it in range(maxiter + 1):
        g, Phi, K, J, force = _residual(problem, rows, q, lam, t, scale)
        g_size = float(np.abs(g).max()) if n else 0.0
        phi_size = float(np.abs(Phi).max()) if Phi.size else 0.0
        if not (math.isfinite(g_size) and math.isfinite(phi_size)):
            return q, lam, False, it
        if g_size <= rtol * force and phi_size <= closure:
            problem.last_kkt = (K, J)
            return q, lam, True, it
        if it == maxiter:
            break
        m = len(Phi)
        A = np.zeros((n + m, n + m))
        A[:n, :n] = K
        A[:n, n:] = J.T
        A[n:, :n] = J
        _, _, step, info = dgesv(A, -np.concatenate([g, Phi]))  # LAPACK LU, without numpy's wrapper cost
        if info != 0:
            return q, lam, False, it
        q = q + step[:n]
        lam = lam + step[n:]
    return q, lam, False, maxiter


def _stability(
    problem: _Problem,
    rows: Rows,
    q: NDArray[np.float64],
    lam: NDArray[np.float64],
    t: float,
    scale: float = 1.0,
    kkt: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
) -> tuple[bool | None, float]:
    """Positive definiteness of the Hessian on the constraints' tangent space (Z^T K Z); ``kkt``:
    (K, J) at this state when already known."""
    K, J = kkt if kkt is not None else _residual(problem, rows, q, lam, t, scale)[2:4]
    n = problem.net.n
    if J.shape[0]:
        _, s, vt = np.linalg.svd(J)
        rank = int(np.sum(s > 1e-10 * max(s[0], 1.0)))
        Z = vt[rank:].T
    else:
        Z = np.eye(n)
    if Z.shape[1] == 0:
        return True, math.inf
    Kr = Z.T @ (0.5 * (K + K.T)) @ Z
    ev = float(np.linalg.eigvalsh(Kr)[0])
    scale_k = max(float(np.max(np.abs(Kr))), 1e-300)
    return ev > -1e-10 * scale_k, ev


def _check_mobility(network: Network, problem: _Problem) -> tuple[int, Rows]:
    if network._analysis is None:
        rank, rows = network.joint_rank()
        network._analysis = (network.mobility(), rank, rows)
    mobility, rank, rows = network._analysis
    if problem.n_prescribed > mobility:
        raise LockedNetwork(
            f"the network has {mobility} degree(s) of freedom ({network.n} coordinates, "
            f"rank of the joint Jacobian {rank}) but {problem.n_prescribed} motion(s) are "
            "prescribed: it locks"
        )
    _check_reachable(network, problem)
    return mobility, rows


def _rank(rows: NDArray[np.float64]) -> int:
    """Rank by singular values above RCOND times the largest (rows already scaled)."""
    if rows.shape[0] == 0:
        return 0
    sigma = np.linalg.svd(rows, compute_uv=False)
    return int(np.sum(sigma > RCOND * sigma[0])) if sigma[0] > 0.0 else 0


def _scaled(J: NDArray[np.float64], length: float) -> NDArray[np.float64]:
    """Jacobian rows in the coordinates z = (x, y, L phi) (rotation columns over L), each of unit length
    (a row of zeros stays zero: it constrains nothing)."""
    A = np.array(J, float)
    A[:, 2::3] /= length
    norms = np.linalg.norm(A, axis=1)
    return A / np.where(norms > 0.0, norms, 1.0)[:, None]


def _check_reachable(network: Network, problem: _Problem) -> None:
    """Raise ``UnreachableMotion`` for the first prescribed motion whose Jacobian row at the unloaded pose
    lies in the span of the joints' rows and the prescribed ones before it (see the module's docstring).
    Decided once per network and set of prescribed motions."""
    prescribed: list[Prescription] = [*problem.disps, *problem.rots]
    if not prescribed:
        return
    key: tuple[tuple[str, str] | str, ...] = tuple((d.point, d.axis) for d in problem.disps) + tuple(
        r.body for r in problem.rots
    )
    if key not in network._reachable:
        network._reachable[key] = _unreachable(network, problem, prescribed)
    known = network._reachable[key]
    if known is not None:
        message, k, by_joints, moves = known
        raise UnreachableMotion(message, prescribed[k], by_joints, moves)


def _unreachable(network: Network, problem: _Problem, prescribed: list[Prescription]) -> _Unreachable | None:
    """(message, index, by_joints, moves) of the first unreachable prescribed motion, or None."""
    length = network.length_scale()
    q = np.zeros(network.n)
    joints = _scaled(network.joint_constraints(q)[1], length)
    rows = _scaled(problem.prescribed(q, 0.0)[1], length)
    base, rank = joints, _rank(joints)
    for k, load in enumerate(prescribed):
        with_it = np.vstack([base, rows[k : k + 1]])
        if _rank(with_it) > rank:
            base, rank = with_it, rank + 1
            continue
        by_joints = _rank(np.vstack([joints, rows[k : k + 1]])) == _rank(joints)
        free = np.linalg.svd(base)[2][rank:].T if base.shape[0] else np.eye(network.n)  # allowed motions
        held_by = "its joints" if by_joints else "its joints and the prescribed motions before it"
        # the basis is orthonormal in z: a body or point that moves has an O(1) entry, one held ~1e-15
        if isinstance(load, PrescribedRotation):
            i = network.index[load.body]
            moves = bool(free.size) and float(np.abs(free[3 * i : 3 * i + 2]).max()) > math.sqrt(RCOND)
            what = (
                f"every motion {held_by} allow translates body '{load.body}' without turning it"
                if moves
                else f"{held_by} hold body '{load.body}' still"
            )
            message = f"the prescribed rotation of body '{load.body}' is no motion of the network: {what}"
        else:
            i, r = network.point_arm(load.point)
            other = 1 if load.axis == "x" else 0
            arm = np.array([-r[1], r[0]])[other] / length
            speed = free[3 * i + other] + arm * free[3 * i + 2] if free.size else np.zeros(0)
            moves = bool(speed.size) and float(np.abs(speed).max()) > math.sqrt(RCOND)
            message = (
                f"the prescribed {load.axis}-displacement of point '{load.point}' is no motion of the "
                f"network: {held_by} hold that point along {load.axis}"
            )
        return _Unreachable(
            f"{message} at the unloaded pose (rank of the constraint Jacobian {rank} with the prescription as without)",
            k,
            by_joints,
            moves,
        )
    return None


def solve(
    network: Network,
    loads: Sequence[Load],
    n_levels: int,
    *,
    rtol: float = 1e-11,
    maxiter: int = 30,
    max_cuts: int = 12,
    stability: bool = True,
) -> NetworkResult:
    """Equilibrium at every load level by Newton with load stepping (each level from the last one;
    a failed step is halved up to ``max_cuts`` times). Raises LockedNetwork if the prescribed motions
    exceed the mobility."""
    t0 = time.perf_counter()
    problem = _Problem(network, list(loads), n_levels)
    mobility, rows = _check_mobility(network, problem)
    q = np.zeros(network.n)
    lam = np.zeros(len(rows) + problem.n_prescribed)
    states: list[NetworkState] = []
    total_it = 0
    messages: list[str] = []
    t_prev = -1.0
    history: list[tuple[float, NDArray[np.float64], NDArray[np.float64]]] = [(t_prev, q, lam)]
    for level in range(n_levels):
        t_target = float(level)
        t = t_prev
        step = t_target - t_prev
        ok = True
        cuts = 0
        its = 0
        while t < t_target - 1e-15:
            dt = min(step, t_target - t)
            if len(history) >= 2 and cuts == 0:  # secant predictor along the last two states
                (t0_, q0_, l0_), (t1_, q1_, l1_) = history[-2], history[-1]
                f = dt / (t1_ - t0_)
                guess = (q + f * (q1_ - q0_), lam + f * (l1_ - l0_))
            else:
                guess = (q, lam)
            q_new, lam_new, conv, it = _newton(
                problem, rows, guess[0].copy(), guess[1].copy(), t + dt, rtol=rtol, maxiter=maxiter
            )
            its += it
            if not conv and guess[0] is not q:
                q_new, lam_new, conv, it = _newton(
                    problem, rows, q.copy(), lam.copy(), t + dt, rtol=rtol, maxiter=maxiter
                )
                its += it
            if conv:
                q, lam, t = q_new, lam_new, t + dt
                history.append((t, q, lam))
            else:
                cuts += 1
                step = dt / 2
                if cuts > max_cuts:
                    ok = False
                    break
        total_it += its
        if not ok:
            messages.append(
                f"level {level}: Newton did not converge after {max_cuts} step halvings "
                f"(load parameter {t:.6g} of {t_target:g})"
            )
            for lv in range(level, n_levels):
                states.append(NetworkState(np.full(network.n, np.nan), lam * np.nan, False, 0, None, math.nan))
            break
        stable, ev = (
            _stability(problem, rows, q, lam, t_target, kkt=problem.last_kkt) if stability else (None, math.nan)
        )
        states.append(NetworkState(q.copy(), lam.copy(), True, its, stable, ev))
        t_prev = t_target
    converged = all(s.converged for s in states)
    message = "; ".join(messages) if messages else f"converged at {n_levels} level(s), {total_it} Newton iterations"
    unstable = [i for i, s in enumerate(states) if s.stable is False]
    if unstable:
        message += f"; unstable equilibrium at level(s) {unstable}"
    return NetworkResult(network, states, converged, message, time.perf_counter() - t0, total_it, mobility)


def trace(
    network: Network,
    loads: Sequence[Load],
    *,
    steps: int = 200,
    ds: float = 0.05,
    t_max: float = 1.0,
    rtol: float = 1e-11,
    maxiter: int = 25,
) -> NetworkResult:
    """Pseudo-arclength continuation in the load factor lambda (loads = lambda x the last level of
    ``loads``), from the unloaded pose until lambda reaches ``t_max`` or ``steps`` are taken; passes
    limit points. Unknowns z = (q, lam, lambda); the extra equation is t_prev . (z - z_pred) = 0
    with t_prev the unit tangent of the last step (Keller)."""
    t0 = time.perf_counter()
    n_levels = max(len(getattr(ld, f)) for ld in loads for f in ("fx", "fy", "m", "values") if hasattr(ld, f))
    problem = _Problem(network, list(loads), n_levels)
    mobility, rows = _check_mobility(network, problem)
    n = network.n
    m = len(rows) + problem.n_prescribed
    t_last = float(n_levels - 1)

    def F(z: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        q, lam, lf = z[:n], z[n : n + m], z[-1]
        g, Phi, K, J, _ = _residual(problem, rows, q, lam, t_last, lf)
        # d/d lambda of (g, Phi): loads are linear in the scale
        g1, Phi1, _, _, _ = _residual(problem, rows, q, lam, t_last, 1.0)
        g0, Phi0, _, _, _ = _residual(problem, rows, q, lam, t_last, 0.0)
        A = np.zeros((n + m, n + m + 1))
        A[:n, :n] = K
        A[:n, n : n + m] = J.T
        A[n:, :n] = J
        A[:, -1] = np.concatenate([g1 - g0, Phi1 - Phi0])
        return np.concatenate([g, Phi]), A

    # arc length measured in the coordinates and the load factor (the multipliers are forces and
    # would dominate the metric): weights 1 on q and lambda, 0 on the multipliers
    weight = np.ones(n + m + 1)
    weight[n : n + m] = 0.0

    def unit_tangent(A: NDArray[np.float64], previous: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
        t = _null_vector(A)
        t = t / max(float(np.linalg.norm(weight * t)), 1e-300)
        if previous is not None and (weight * t) @ (weight * previous) < 0:
            t = -t
        return t

    z = np.zeros(n + m + 1)
    _, A = F(z)
    tangent = unit_tangent(A)
    if tangent[-1] < 0:
        tangent = -tangent
    states: list[NetworkState] = []
    lfs: list[float] = []
    total = 0
    converged, message = True, ""
    for _ in range(steps):
        pred = z + ds * tangent
        zz = pred.copy()
        ok = False
        for it in range(1, maxiter + 1):
            r, A = F(zz)
            full = np.vstack([A, weight * tangent])
            rhs = -np.concatenate([r, [(weight * tangent) @ (zz - pred)]])
            dz = np.linalg.solve(full, rhs)
            zz = zz + dz
            total += 1
            if np.max(np.abs(dz[:n])) <= rtol * max(np.max(np.abs(zz[:n])), 1e-3) and abs(dz[-1]) <= rtol * max(
                abs(zz[-1]), 1e-3
            ):
                ok = True
                break
        if not ok:
            converged, message = False, f"arc-length step did not converge at load factor {z[-1]:.6g}"
            break
        _, A = F(zz)
        z, tangent = zz, unit_tangent(A, tangent)
        q, lam = z[:n], z[n : n + m]
        stable, ev = _stability(problem, rows, q, lam, t_last, z[-1])
        states.append(NetworkState(q.copy(), lam.copy(), True, it, stable, ev))
        lfs.append(z[-1])
        if z[-1] >= t_max:
            break
    message = message or f"{len(states)} arc-length steps to load factor {lfs[-1] if lfs else 0.0:.6g}"
    return NetworkResult(
        network, states, converged, message, time.perf_counter() - t0, total, mobility, load_factor=np.array(lfs)
    )


def _null_vector(A: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit vector spanning the null space of a full-row-rank (k, k+1) matrix."""
    _, _, vt = np.linalg.svd(A)
    v: NDArray[np.float64] = vt[-1]
    return v
