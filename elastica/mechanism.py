"""Exact elastica of a planar compliant mechanism: beams coupled through rigid bodies, by shooting.

Every beam is an (optionally axially extensible) elastica integrated from its start, where the
pose is that of the body holding it, under the force F carried through it (the force the body at
its end applies to it; constant along the beam unless a distributed load acts, below). With N = F . t the axial
force (tension positive, t the tangent) and e = N/EA the axial strain (0 if inextensible):

    x' = (1 + e) cos(theta),  y' = (1 + e) sin(theta),  theta' = kappa0 + m/EI,
    m' = (1 + e) (Fx sin(theta) - Fy cos(theta)),   U' = m^2/(2 EI) + N^2/(2 EA),

m the bending moment (the moment the outboard part applies to the inboard part, CCW). The beam
applies F and m(0) to the body at its start, -F and -m(L) to the body at its end.

A force toward a fixed point (``PointedForce``: a rope over a pulley) pulls along the current line from
its point to that point, and a follower force turns with its body or beam end: both are evaluated at the
current unknowns, so their direction is part of every residual and of its Jacobian.

A uniform dead load w per unit reference length along a beam (``DistributedLoad``; self-weight) makes the
force through it vary, F(s) = F + w (L - s) with F the force at its end: the beam then applies F + w L to
the body at its start, -F to the body at its end.

Unknowns: per beam (Fx, Fy) and m(0) (clamped start) or theta(0) (pinned start); per free rigid body
its pose (x, y, phi) (reference node displacement, rotation from the unloaded pose); per pin between
bodies its force; per prescribed rotation its couple, per prescribed displacement its force.
Equations: per beam its end condition (clamped: position and angle of the end body's node; pinned:
position and m(L) = 0; free: F and m(L) equal to the loads applied there); per body its force and
moment balance; per pin the coincidence of its node on both bodies; the prescribed motions.

The Jacobian of these equations (``_System.jacobian``) follows from the chain rule: a beam's end state
e = (x, y, theta, m)(L) depends on the unknowns only through its start inputs p = (x0, y0, theta0, m0, Fx, Fy),
so de/du = (de/dp)(dp/du), where de/dp is the beam's own 4 x 6 block (the identity for the start position,
which only translates the beam; the columns of theta0, m0 and F from the beam's variational equations,
integrated beside it: ``elastica.integrator.beam_rhs`` on its longer state) and dp/du is algebra (the start's
place on its body). Everything else (body balances, pins, prescribed motions, the loads that move with the
unknowns) is algebraic in u and the ends, differentiated by hand. One Jacobian thus costs one integration
of each beam, not a residual per unknown.

They are solved by Newton (that Jacobian kept and updated by Broyden's formula, evaluated afresh where a
step converges slowly) level after level from the unloaded mechanism, halving the load step where a step
does not converge and doubling it (up to a level) after one that does; a level is given up after
``max_cuts`` halvings in a row. Each beam is integrated by the compiled DOP853 of ``elastica.integrator``
(scipy's DOP853 step for step).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
import struct
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from planar import (
    GROUND,
    Couple,
    DistributedLoad,
    Force,
    Pin,
    PointedForce,
    PrescribedDisplacement,
    PrescribedRotation,
    pull_direction,
)

from .integrator import beam_samples, beam_sensitivities, integrate_beam

__all__ = [
    "ElasticBeam",
    "RigidBody",
    "Pin",
    "Force",
    "PointedForce",
    "DistributedLoad",
    "Couple",
    "EndCouple",
    "PrescribedRotation",
    "PrescribedDisplacement",
    "Mechanism",
    "MechanismSolution",
    "solve_mechanism",
    "GROUND",
]

_KEY = struct.Struct("8d")  # a beam's inputs (start state, force, load along it) as bytes: the key of its end states
_ENDS_KEPT = 4  # end states kept per beam
# the largest turn of a beam end or a body in one load step (rad): a step that turns more is taken for a
# jump to another equilibrium (Newton from far away can land on a looped or inverted one) and halved
MAX_TURN_PER_STEP = 0.5
# the relative tolerance of the beams' variational equations (``_System.end_derivative``): the Jacobian only
# sets Newton's steps (the residual alone decides convergence), so 1e-8 of each entry is plenty
JACOBIAN_RTOL = 1e-8


@dataclass(frozen=True)
class ElasticBeam:
    """A beam from node ``start`` to node ``end``; each end 'clamped' or 'pinned' to a body (or GROUND),
    or 'free' (body None). EA None: inextensible. ``curvature``: initial curvature (CCW from start)."""

    name: str
    start: str
    end: str
    EI: float
    start_body: str | None
    end_body: str | None
    start_kind: str = "clamped"
    end_kind: str = "clamped"
    EA: float | None = None
    curvature: float = 0.0


@dataclass(frozen=True)
class RigidBody:
    name: str
    nodes: tuple[str, ...]


@dataclass(frozen=True)
class EndCouple:
    """Couple (CCW) per level on a beam's free or pinned end at ``point`` (on the beam's side of the pin)."""

    point: str
    m: tuple[float, ...]


_Load = Force | PointedForce | DistributedLoad | Couple | EndCouple | PrescribedRotation | PrescribedDisplacement
_Place = tuple[int, float, float, float, float]  # a point of a body: pose index, origin, arm (`_System._place_of`)
_Vector = Callable[[NDArray[np.float64]], NDArray[np.float64]]  # the scaled residual of the unknowns
_Matrix = Callable[[NDArray[np.float64]], NDArray[np.float64]]  # its Jacobian (``_System.jacobian``, scaled)
# a derivative with respect to the unknowns as its nonzero terms (index of the unknown, value); an index
# may repeat (the terms add)
_Terms = list[tuple[int, float]]


@dataclass
class Mechanism:
    nodes: dict[str, tuple[float, float]]
    beams: list[ElasticBeam]
    bodies: list[RigidBody] = field(default_factory=list)
    pins: list[Pin] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.body_of: dict[str, str] = {}
        for rigid in self.bodies:
            if rigid.name == GROUND:
                raise ValueError("the ground is not a movable body")
            for nd in rigid.nodes:
                if nd not in self.nodes:
                    raise ValueError(f"body '{rigid.name}' names unknown node '{nd}'")
                self.body_of.setdefault(nd, rigid.name)
        names = {b.name for b in self.bodies} | {GROUND}
        for beam in self.beams:
            for nd, body, kind in (
                (beam.start, beam.start_body, beam.start_kind),
                (beam.end, beam.end_body, beam.end_kind),
            ):
                if nd not in self.nodes:
                    raise ValueError(f"beam '{beam.name}' names unknown node '{nd}'")
                if kind not in ("clamped", "pinned", "free"):
                    raise ValueError(f"beam '{beam.name}': end kind '{kind}'")
                if (kind == "free") != (body is None) or (body is not None and body not in names):
                    raise ValueError(f"beam '{beam.name}' at '{nd}': {kind} end on body {body!r}")
            if beam.start_kind == "free":
                raise ValueError(f"beam '{beam.name}': give its held end as the start")
        self.index = {b.name: i for i, b in enumerate(self.bodies)}
        self.origin = {b.name: np.asarray(self.nodes[b.nodes[0]], float) for b in self.bodies}


@dataclass
class MechanismSolution:
    """Per level: node positions, body rotations, beam end loads, prescribed-motion loads, energy."""

    converged: bool
    message: str
    positions: list[dict[str, NDArray[np.float64]]]
    rotations: list[dict[str, float]]
    driver_loads: list[list[float]]  # per level: the load each prescribed motion needs, in order
    strain_energy: list[float]
    beam_shapes: list[dict[str, NDArray[np.float64]]]
    wall_time: float
    level_converged: list[bool]
    # per level, per beam: (Fx, Fy, M) the beam applies at its start to what holds it (the force at its
    # end plus the load along it, and the start moment m(0); 0 at a pinned start)
    start_loads: list[dict[str, tuple[float, float, float]]] = field(default_factory=list)


class _LevelLoads(NamedTuple):
    """One level's loads as the residual reads them (`_LoadPath`), in plain floats."""

    forces: dict[str, tuple[float, float]]  # node -> (Fx, Fy), the forces at a node summed
    couples: dict[tuple[str, str], float]  # ("body", body) or ("node", node) -> couple
    rotations: list[float]  # per prescribed rotation
    displacements: list[float]  # per prescribed displacement


class _System:
    """Unknown layout, residual and integration of one mechanism under the loads of one level."""

    def __init__(
        self,
        mech: Mechanism,
        forces: list[Force],
        couples: list[Couple | EndCouple],
        rotations: list[PrescribedRotation],
        displacements: list[PrescribedDisplacement],
        rtol: float,
    ):
        self.m = mech
        self.forces, self.couples, self.rotations, self.displacements = forces, couples, rotations, displacements
        # beam -> its uniform load (wx, wy) per unit length at the load parameter being solved (`_LoadPath`)
        self.along: dict[str, tuple[float, float]] = {}
        self.rtol = rtol
        # beam -> {its inputs: its end state}, the last few: the loads, the residual, the Jacobian and the
        # turn check ask for the same end at one point, and a step that moves only other beams' unknowns
        # (a pose no beam starts on) leaves a beam's inputs as they were
        self._ends: dict[str, dict[bytes, NDArray[np.float64]]] = {}
        nb, nbeam, npin = len(mech.bodies), len(mech.beams), len(mech.pins)
        self.i_body = 3 * nbeam
        self.i_pin = self.i_body + 3 * nb
        self.i_rot = self.i_pin + 2 * npin
        self.i_disp = self.i_rot + len(rotations)
        self.size = self.i_disp + len(displacements)
        self.tangent0: dict[str, tuple[float, float, float]] = {}  # beam -> (start angle, end angle, arc length)
        for beam in mech.beams:
            A, B = (np.asarray(mech.nodes[n], float) for n in (beam.start, beam.end))
            chord = B - A
            L = float(np.linalg.norm(chord))
            if beam.curvature:
                half = L * abs(beam.curvature) / 2
                if half >= 1.0:
                    raise ValueError(f"beam '{beam.name}': chord longer than the arc's diameter")
                arc = 2 * math.asin(half) / abs(beam.curvature)
                angle0 = math.atan2(chord[1], chord[0]) - beam.curvature * arc / 2
            else:
                arc, angle0 = L, math.atan2(chord[1], chord[0])
            self.tangent0[beam.name] = (angle0, angle0 + beam.curvature * arc, arc)
        self.beam_index = {beam.name: i for i, beam in enumerate(mech.beams)}
        self.pose_at = {b.name: self.i_body + 3 * i for i, b in enumerate(mech.bodies)}
        # where a node sits on each body (and the ground), as plain floats for the residual (`_place_of`)
        self._place: dict[tuple[str, str], _Place] = {
            (body, nd): self._place_of(body, (float(xy[0]), float(xy[1])))
            for body in (GROUND, *(b.name for b in mech.bodies))
            for nd, xy in mech.nodes.items()
        }
        # each pin's place on its two bodies, from its position in the unloaded pose
        self._pin_place = [(self._place_of(pin.a, pin.at), self._place_of(pin.b, pin.at)) for pin in mech.pins]
        self._origin = {
            b.name: (self.pose_at[b.name], float(mech.origin[b.name][0]), float(mech.origin[b.name][1]))
            for b in mech.bodies
        }
        self._atol = {beam.name: self.rtol * 1e-3 * max(self.tangent0[beam.name][2], 1.0) for beam in mech.beams}

    # poses
    def pose(self, u: NDArray[np.float64], body: str) -> tuple[NDArray[np.float64], float]:
        if body == GROUND:
            return np.zeros(2), 0.0
        i = self.pose_at[body]
        return u[i : i + 2], u[i + 2]

    def _phi(self, ul: list[float], body: str) -> float:
        """The rotation of ``body`` (0 for the ground) from the unknowns as a list of floats."""
        return 0.0 if body == GROUND else ul[self.pose_at[body] + 2]

    def node_position(self, u: NDArray[np.float64], body: str, node: str) -> NDArray[np.float64]:
        """Current position of a node carried by ``body`` (an array; `_xy`)."""
        return np.array(self._xy(u.tolist(), body, node))

    def _place_of(self, body: str, xy: tuple[float, float]) -> _Place:
        """(pose index, origin, arm) of the point of ``body`` at ``xy`` in the unloaded pose (`_xy`)."""
        if body == GROUND:
            return (-1, float(xy[0]), float(xy[1]), 0.0, 0.0)
        o = self.m.origin[body]
        return (self.pose_at[body], float(o[0]), float(o[1]), float(xy[0] - o[0]), float(xy[1] - o[1]))

    def _xy(self, ul: list[float], body: str, node: str) -> tuple[float, float]:
        """Current (x, y) of a node carried by ``body``, origin + d + R(phi) (p0 - origin), from the
        unknowns as a list of floats."""
        return self._at(ul, self._place[(body, node)])

    @staticmethod
    def _at(ul: list[float], place: _Place) -> tuple[float, float]:
        """Current (x, y) of the point at ``place`` (`_place_of`) under the unknowns (a list of floats)."""
        i, o0, o1, r0, r1 = place
        if i < 0:
            return o0, o1
        c, s = math.cos(ul[i + 2]), math.sin(ul[i + 2])
        return o0 + ul[i] + (c * r0 - s * r1), o1 + ul[i + 1] + (s * r0 + c * r1)

    def _start(self, beam: ElasticBeam, ul: list[float]) -> tuple[float, float, float, float, float, float]:
        """(x, y, theta, m) at a beam's start under the unknowns (a list of floats), and its (Fx, Fy)."""
        k = 3 * self.beam_index[beam.name]
        Fx, Fy, a = ul[k], ul[k + 1], ul[k + 2]
        angle0 = self.tangent0[beam.name][0]
        assert beam.start_body is not None  # a beam's start is held (`Mechanism` checks it)
        x, y = self._xy(ul, beam.start_body, beam.start)
        phi = self._phi(ul, beam.start_body)
        if beam.start_kind == "clamped":
            return x, y, angle0 + phi, a, Fx, Fy
        return x, y, angle0 + a, 0.0, Fx, Fy

    def integrate(
        self, beam: ElasticBeam, u: NDArray[np.float64], ul: list[float] | None = None
    ) -> NDArray[np.float64]:
        """End state (x, y, theta, m, U) of a beam from its start under the unknowns u (the compiled
        DOP853 of ``elastica.integrator``); ``ul``: u as a list of floats, when the caller has it."""
        x, y, theta0, m0, Fx, Fy = self._start(beam, u.tolist() if ul is None else ul)
        wx, wy = self.along.get(beam.name, (0.0, 0.0))
        key = _KEY.pack(x, y, theta0, m0, Fx, Fy, wx, wy)
        ends = self._ends.setdefault(beam.name, {})
        known = ends.get(key)
        if known is not None:  # the same inputs again (the loads, the residual, the Jacobian and the turn
            return known  # check at one point; a state that moved only other beams' unknowns)
        end = self._integrate_from(beam, x, y, theta0, m0, Fx, Fy)
        end.flags.writeable = False
        if len(ends) >= _ENDS_KEPT:
            del ends[next(iter(ends))]  # the oldest
        ends[key] = end
        return end

    def _integrate_from(
        self, beam: ElasticBeam, x: float, y: float, theta0: float, m0: float, Fx: float, Fy: float
    ) -> NDArray[np.float64]:
        """End state (x, y, theta, m, U) of a beam from the start state (x, y, theta0, m0) under the force
        (Fx, Fy) at its end and its load along it (``along``), not kept."""
        wx, wy = self.along.get(beam.name, (0.0, 0.0))
        end: NDArray[np.float64]
        end, ok = integrate_beam(
            [x, y, theta0, m0, 0.0],
            self.tangent0[beam.name][2],
            Fx,
            Fy,
            beam.curvature,
            beam.EI,
            beam.EA or 0.0,
            self.rtol,
            self._atol[beam.name],
            wx,
            wy,
        )
        if not ok:
            raise RuntimeError(f"beam '{beam.name}': integration failed (step below the rounding of s)")
        return end

    def end_derivative(
        self, beam: ElasticBeam, u: NDArray[np.float64], ul: list[float]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """A beam's end state under the unknowns u (``ul``: u as a list of floats) and its derivative
        D = d(x, y, theta, m)(L) / d(theta0, m0, Fx, Fy) (4, 4) with respect to its own start inputs (the
        start position enters by translation alone: d(x, y)(L)/d(x0, y0) = I, d(theta, m)(L)/d(x0, y0) = 0),
        by the beam's variational equations (``elastica.integrator.beam_rhs`` on its longer state) integrated
        beside it at the tolerance ``JACOBIAN_RTOL``. The end state is the residual's own (``integrate``),
        so the Jacobian's integration never changes the equations solved."""
        x, y, theta0, m0, Fx, Fy = self._start(beam, ul)
        end = self.integrate(beam, u, ul)
        wx, wy = self.along.get(beam.name, (0.0, 0.0))
        arc = self.tangent0[beam.name][2]
        D: NDArray[np.float64]
        _, D, ok = beam_sensitivities(
            [x, y, theta0, m0, 0.0],
            arc,
            Fx,
            Fy,
            beam.curvature,
            beam.EI,
            beam.EA or 0.0,
            JACOBIAN_RTOL,
            JACOBIAN_RTOL * 1e-3 * max(arc, 1.0),
            wx,
            wy,
        )
        if not ok:
            raise RuntimeError(f"beam '{beam.name}': integration failed (step below the rounding of s)")
        return end, D

    def shape(self, beam: ElasticBeam, u: NDArray[np.float64], n: int) -> NDArray[np.float64]:
        """(n, 2) positions along a beam at n equally spaced arc lengths (start to end)."""
        x, y, theta0, m0, Fx, Fy = self._start(beam, u.tolist())
        s = np.linspace(0.0, self.tangent0[beam.name][2], n)
        states: NDArray[np.float64]
        states, ok = beam_samples(
            np.array([x, y, theta0, m0, 0.0]),
            s,
            Fx,
            Fy,
            beam.curvature,
            beam.EI,
            beam.EA or 0.0,
            self.rtol,
            self._atol[beam.name],
            *self.along.get(beam.name, (0.0, 0.0)),
        )
        if not ok:
            raise RuntimeError(f"beam '{beam.name}': integration failed (step below the rounding of s)")
        return states[:, :2]

    def residual(self, u: NDArray[np.float64], level_loads: _LevelLoads) -> NDArray[np.float64]:
        """The equations at the unknowns u under one level's loads (module docstring), in plain floats."""
        forces, couples, rot_values, disp_values = level_loads
        m = self.m
        ul = u.tolist()
        r = [0.0] * self.size
        wrench = {b.name: [0.0, 0.0, 0.0] for b in m.bodies}  # (Fx, Fy, M about the body's current origin)
        origin = self._origin

        def add(body: str | None, F0: float, F1: float, M: float, at0: float, at1: float) -> None:
            if body == GROUND or body is None:
                return
            i, o0, o1 = origin[body]
            w = wrench[body]
            lever_x, lever_y = at0 - (o0 + ul[i]), at1 - (o1 + ul[i + 1])
            w[0] += F0
            w[1] += F1
            w[2] += M + lever_x * F1 - lever_y * F0

        applied: dict[str, list[float]] = {}
        for node, F in forces.items():
            a = applied.get(node, [0.0, 0.0, 0.0])
            applied[node] = [a[0] + float(F[0]), a[1] + float(F[1]), a[2] + 0.0]
        for i, beam in enumerate(m.beams):
            end = self.integrate(beam, u, ul).tolist()
            F0, F1 = ul[3 * i], ul[3 * i + 1]
            start_m = ul[3 * i + 2] if beam.start_kind == "clamped" else 0.0
            assert beam.start_body is not None  # a beam's start is held (`Mechanism` checks it)
            wx, wy = self.along.get(beam.name, (0.0, 0.0))
            arc = self.tangent0[beam.name][2]  # the force at the start: the end's plus the load along the beam
            add(beam.start_body, F0 + wx * arc, F1 + wy * arc, start_m, *self._xy(ul, beam.start_body, beam.start))
            if beam.end_kind == "clamped":
                assert beam.end_body is not None  # a clamped end is held (`Mechanism` checks it)
                tx, ty = self._xy(ul, beam.end_body, beam.end)
                phi = self._phi(ul, beam.end_body)
                r[3 * i], r[3 * i + 1] = end[0] - tx, end[1] - ty
                r[3 * i + 2] = end[2] - (self.tangent0[beam.name][1] + phi)
                add(beam.end_body, -F0, -F1, -end[3], end[0], end[1])
            elif beam.end_kind == "pinned":
                assert beam.end_body is not None  # a pinned end is held (`Mechanism` checks it)
                tx, ty = self._xy(ul, beam.end_body, beam.end)
                r[3 * i], r[3 * i + 1] = end[0] - tx, end[1] - ty
                r[3 * i + 2] = end[3] - couples.get(("node", beam.end), 0.0)  # a couple on the beam's side
                add(beam.end_body, -F0, -F1, 0.0, end[0], end[1])
            else:
                load = applied.pop(beam.end, (0.0, 0.0, 0.0))
                M_end = couples.get(("node", beam.end), 0.0)
                r[3 * i], r[3 * i + 1] = F0 - load[0], F1 - load[1]
                r[3 * i + 2] = end[3] - M_end
        for node, load in applied.items():
            body = m.body_of.get(node)
            if body is None:
                raise ValueError(f"a force at node '{node}', which is on no rigid body and at no free beam end")
            add(body, load[0], load[1], 0.0, *self._xy(ul, body, node))
        for (kind, name), value in couples.items():
            if kind == "body":
                add(name, 0.0, 0.0, value, 0.0, 0.0)
        for j, pin in enumerate(m.pins):
            k = self.i_pin + 2 * j
            R0, R1 = ul[k], ul[k + 1]
            place_a, place_b = self._pin_place[j]
            pa = self._at(ul, place_a)
            pb = self._at(ul, place_b)
            r[k], r[k + 1] = pa[0] - pb[0], pa[1] - pb[1]
            add(pin.a, R0, R1, 0.0, *pa)
            add(pin.b, -R0, -R1, 0.0, *pb)
        self._motion_rows(ul, r, add, rot_values, disp_values)
        for rigid in m.bodies:
            i = self.i_body + 3 * m.index[rigid.name]
            r[i : i + 3] = wrench[rigid.name]
        return np.array(r)

    def _motion_rows(
        self,
        ul: list[float],
        r: list[float],
        add: Callable[..., None],
        rot_values: list[float],
        disp_values: list[float],
    ) -> None:
        """The prescribed motions' rows of ``residual`` (r) and the loads they need, on their bodies (add)."""
        for j, (rot, value) in enumerate(zip(self.rotations, rot_values)):
            M = ul[self.i_rot + j]
            phi = self._phi(ul, rot.body)
            r[self.i_rot + j] = phi - value
            add(rot.body, 0.0, 0.0, M, 0.0, 0.0)
        for j, (disp, value) in enumerate(zip(self.displacements, disp_values)):
            P = ul[self.i_disp + j]
            body = self.m.body_of[disp.point]
            axis = 0 if disp.axis == "x" else 1
            p = self._xy(ul, body, disp.point)
            r[self.i_disp + j] = p[axis] - self.m.nodes[disp.point][axis] - value
            add(body, P if axis == 0 else 0.0, P if axis == 1 else 0.0, 0.0, *p)

    def jacobian(
        self, u: NDArray[np.float64], level_loads: _LevelLoads, force_rates: dict[str, list[float]]
    ) -> NDArray[np.float64]:
        """dr/du, the derivative of ``residual`` at the unknowns u under one level's loads, row for row.

        Each beam's end state e = (x, y, theta, m)(L) depends on u only through its start inputs
        p = (x0, y0, theta0, m0, Fx, Fy): de/du = (de/dp)(dp/du), de/dp from ``end_derivative`` and dp/du
        from the start's place: x0, y0 on the start body, d(o + d + R(phi) a)/d(d, phi) = (I, R'(phi) a),
        theta0 = angle0 + phi (clamped) or the unknown start angle (pinned), m0 and F unknowns themselves.
        The rest is algebra: a body's balance sums forces F and moments M + (p - o - d) x F of the loads
        on it, whose derivative is dF, dM + (dp - dd) x F + (p - o - d) x dF; the end conditions, pin
        coincidences and prescribed motions are differences of positions and angles. A load that
        depends on u (``_LoadPath.force_rates``: a follower force, a force toward a fixed point) adds
        dF/d(p, phi) of its point times that point's own derivative (a body's node, or a free beam end
        through de/du)."""
        rows = _JacobianRows(self, u, level_loads, force_rates)
        popped = rows.beams()
        rows.applied_forces(popped)
        rows.pins()
        rows.prescribed_motions()
        return np.array(rows.J)

    @staticmethod
    def _place_rate(ul: list[float], place: _Place) -> tuple[_Terms, _Terms]:
        """The derivatives of the (x, y) of the point at ``place`` (`_at`) with respect to the unknowns:
        d(o + d + R(phi) a) = (dd_x - (sin(phi) a_x + cos(phi) a_y) dphi, dd_y + (cos(phi) a_x - sin(phi) a_y) dphi);
        none on the ground."""
        i, _, _, r0, r1 = place
        if i < 0:
            return [], []
        c, s = math.cos(ul[i + 2]), math.sin(ul[i + 2])
        return [(i, 1.0), (i + 2, -(s * r0 + c * r1))], [(i + 1, 1.0), (i + 2, c * r0 - s * r1)]


class _JacobianRows:
    """dr/du of one mechanism at the unknowns u, assembled row for row as ``_System.residual`` builds r
    (``_System.jacobian`` gives the chain rule); a derivative is a list of (column, value) terms."""

    def __init__(
        self, system: _System, u: NDArray[np.float64], level_loads: _LevelLoads, force_rates: dict[str, list[float]]
    ):
        self.s, self.m, self.u, self.ul = system, system.m, u, u.tolist()
        self.forces, self.force_rates = level_loads.forces, force_rates
        self.J = [[0.0] * system.size for _ in range(system.size)]
        # the beams' ends (x, y, theta, m, U)(L), their derivatives, and the derivatives of their starts
        self.ends: list[list[float]] = []
        self.end_rates: list[list[_Terms]] = []
        self.start_rates: list[tuple[_Terms, _Terms]] = []
        self.free_end: dict[str, int] = {}
        for i, beam in enumerate(self.m.beams):
            self._beam_end(i, beam)

    def put(self, row: int, terms: _Terms, factor: float = 1.0) -> None:
        Jr = self.J[row]
        for col, value in terms:
            Jr[col] += factor * value

    def add(
        self,
        body: str | None,
        F0: float,
        F1: float,
        at0: float,
        at1: float,
        dF0: _Terms,
        dF1: _Terms,
        dM: _Terms,
        dat0: _Terms,
        dat1: _Terms,
    ) -> None:
        """The derivative of ``residual``'s add(body, F0, F1, M, at0, at1): (dF0, dF1, dM, d at)."""
        if body == GROUND or body is None:
            return
        i, o0, o1 = self.s._origin[body]  # the body's pose, and its balance's rows, start at index i
        lever_x, lever_y = at0 - (o0 + self.ul[i]), at1 - (o1 + self.ul[i + 1])
        self.put(i, dF0)
        self.put(i + 1, dF1)
        self.put(i + 2, dM)
        self.put(i + 2, dF1, lever_x)
        self.put(i + 2, dF0, -lever_y)
        self.put(i + 2, dat0, F1)
        self.put(i + 2, dat1, -F0)
        self.J[i + 2][i] -= F1
        self.J[i + 2][i + 1] += F0

    def turn(self, body: str | None) -> _Terms:
        return [] if body == GROUND or body is None else [(self.s.pose_at[body] + 2, 1.0)]

    def place_rate(self, body: str, node: str) -> tuple[_Terms, _Terms]:
        return self.s._place_rate(self.ul, self.s._place[(body, node)])

    def _beam_end(self, i: int, beam: ElasticBeam) -> None:
        """A beam's end and de/du = (de/dp)(dp/du) through its start inputs p."""
        k = 3 * i
        assert beam.start_body is not None  # a beam's start is held (`Mechanism` checks it)
        end_state, D = self.s.end_derivative(beam, self.u, self.ul)
        dx0, dy0 = self.place_rate(beam.start_body, beam.start)
        inputs = (
            [self.turn(beam.start_body), [(k + 2, 1.0)]] if beam.start_kind == "clamped" else [[(k + 2, 1.0)], []]
        ) + [[(k, 1.0)], [(k + 1, 1.0)]]  # theta0, m0, Fx, Fy
        rates: list[_Terms] = [list(dx0), list(dy0), [], []]
        for row in range(4):
            for col, terms in enumerate(inputs):
                d = float(D[row, col])
                rates[row].extend((c, d * v) for c, v in terms)
        self.ends.append(end_state.tolist())
        self.end_rates.append(rates)
        self.start_rates.append((dx0, dy0))
        if beam.end_kind == "free":
            self.free_end.setdefault(beam.end, i)

    def load_rate(self, node: str) -> tuple[_Terms, _Terms]:
        """d(Fx, Fy)/du of the force at a node: dF/d(p, phi) (``force_rates``) times the derivative of
        the node's position p and turn phi (on its body, or the free beam end it is)."""
        a = self.force_rates.get(node)
        if a is None:
            return [], []
        body = self.m.body_of.get(node)
        if body is not None:
            dpx, dpy = self.place_rate(body, node)
            dphi = self.turn(body)
        else:
            dpx, dpy, dphi = self.end_rates[self.free_end[node]][:3]
        dFx = [(c, a[0] * v) for c, v in dpx] + [(c, a[1] * v) for c, v in dpy] + [(c, a[2] * v) for c, v in dphi]
        dFy = [(c, a[3] * v) for c, v in dpx] + [(c, a[4] * v) for c, v in dpy] + [(c, a[5] * v) for c, v in dphi]
        return dFx, dFy

    def beams(self) -> set[str]:
        """The beams' rows (end conditions) and their loads on the bodies; returns the free ends' nodes,
        whose applied force the beam's own rows take."""
        popped: set[str] = set()
        ul = self.ul
        for i, beam in enumerate(self.m.beams):
            k = 3 * i
            end, (de_x, de_y, de_theta, de_m) = self.ends[i], self.end_rates[i]
            F0, F1 = ul[k], ul[k + 1]
            wx, wy = self.s.along.get(beam.name, (0.0, 0.0))
            arc = self.s.tangent0[beam.name][2]
            assert beam.start_body is not None  # a beam's start is held (`Mechanism` checks it)
            self.add(
                beam.start_body,
                F0 + wx * arc,
                F1 + wy * arc,
                *self.s._xy(ul, beam.start_body, beam.start),
                [(k, 1.0)],
                [(k + 1, 1.0)],
                [(k + 2, 1.0)] if beam.start_kind == "clamped" else [],
                *self.start_rates[i],
            )
            if beam.end_kind in ("clamped", "pinned"):
                assert beam.end_body is not None  # a held end is on a body (`Mechanism` checks it)
                tx, ty = self.place_rate(beam.end_body, beam.end)
                self.put(k, de_x)
                self.put(k, tx, -1.0)
                self.put(k + 1, de_y)
                self.put(k + 1, ty, -1.0)
                if beam.end_kind == "clamped":
                    self.put(k + 2, de_theta)
                    self.put(k + 2, self.turn(beam.end_body), -1.0)
                    self.add(
                        beam.end_body,
                        -F0,
                        -F1,
                        end[0],
                        end[1],
                        [(k, -1.0)],
                        [(k + 1, -1.0)],
                        [(c, -v) for c, v in de_m],
                        de_x,
                        de_y,
                    )
                else:
                    self.put(k + 2, de_m)
                    self.add(beam.end_body, -F0, -F1, end[0], end[1], [(k, -1.0)], [(k + 1, -1.0)], [], de_x, de_y)
            else:
                popped.add(beam.end)
                dFx, dFy = self.load_rate(beam.end)
                self.J[k][k] += 1.0
                self.put(k, dFx, -1.0)
                self.J[k + 1][k + 1] += 1.0
                self.put(k + 1, dFy, -1.0)
                self.put(k + 2, de_m)
        return popped

    def applied_forces(self, popped: set[str]) -> None:
        """The forces at nodes on bodies (a free beam end's is in its beam's rows)."""
        for node, F in self.forces.items():
            if node in popped:
                continue
            body = self.m.body_of.get(node)
            if body is None:
                raise ValueError(f"a force at node '{node}', which is on no rigid body and at no free beam end")
            self.add(
                body,
                float(F[0]),
                float(F[1]),
                *self.s._xy(self.ul, body, node),
                *self.load_rate(node),
                [],
                *self.place_rate(body, node),
            )

    def pins(self) -> None:
        """Each pin's coincidence rows and its force on both bodies."""
        ul = self.ul
        for j, pin in enumerate(self.m.pins):
            k = self.s.i_pin + 2 * j
            place_a, place_b = self.s._pin_place[j]
            da_x, da_y = self.s._place_rate(ul, place_a)
            db_x, db_y = self.s._place_rate(ul, place_b)
            self.put(k, da_x)
            self.put(k, db_x, -1.0)
            self.put(k + 1, da_y)
            self.put(k + 1, db_y, -1.0)
            self.add(pin.a, ul[k], ul[k + 1], *self.s._at(ul, place_a), [(k, 1.0)], [(k + 1, 1.0)], [], da_x, da_y)
            self.add(pin.b, -ul[k], -ul[k + 1], *self.s._at(ul, place_b), [(k, -1.0)], [(k + 1, -1.0)], [], db_x, db_y)

    def prescribed_motions(self) -> None:
        """The prescribed rotations' and displacements' rows and the loads they need on their bodies."""
        ul = self.ul
        for j, rot in enumerate(self.s.rotations):
            self.put(self.s.i_rot + j, self.turn(rot.body))
            self.add(rot.body, 0.0, 0.0, 0.0, 0.0, [], [], [(self.s.i_rot + j, 1.0)], [], [])
        for j, disp in enumerate(self.s.displacements):
            k = self.s.i_disp + j
            body = self.m.body_of[disp.point]
            dp_x, dp_y = self.place_rate(body, disp.point)
            self.put(k, dp_x if disp.axis == "x" else dp_y)
            along_x = disp.axis == "x"
            self.add(
                body,
                ul[k] if along_x else 0.0,
                0.0 if along_x else ul[k],
                *self.s._xy(ul, body, disp.point),
                [(k, 1.0)] if along_x else [],
                [] if along_x else [(k, 1.0)],
                [],
                dp_x,
                dp_y,
            )


@dataclass
class _LoadPath:
    """The loads along the path, at a load parameter t (level index, linear between levels, from zero
    below level 0); follower forces turn with their body (or the free beam end they act at)."""

    mech: Mechanism
    system: "_System"
    forces: list[Force]
    couples: list[Couple | EndCouple]
    rotations: list[PrescribedRotation]
    displacements: list[PrescribedDisplacement]
    n_levels: int
    pointed: list[PointedForce]
    distributed: list[DistributedLoad]

    def value(self, values: tuple[float, ...], t: float) -> float:
        if t < 0:
            return values[0] * (t + 1.0)
        i = min(int(t), self.n_levels - 1)
        f = t - i
        return values[i] if i >= self.n_levels - 1 else values[i] * (1 - f) + values[i + 1] * f

    def __call__(self, t: float, u: NDArray[np.float64]) -> _LevelLoads:
        along: dict[str, tuple[float, float]] = {}
        for dl in self.distributed:
            a = along.get(dl.beam, (0.0, 0.0))
            along[dl.beam] = (a[0] + float(self.value(dl.wx, t)), a[1] + float(self.value(dl.wy, t)))
        self.system.along = along  # the beams' integrations below and in the residual read it
        F: dict[str, tuple[float, float]] = {}  # node -> (Fx, Fy) in plain floats, the forces at a node summed in order
        for f in self.forces:
            fx, fy = float(self.value(f.fx, t)), float(self.value(f.fy, t))
            if f.follower:
                body = self.mech.body_of.get(f.point)
                phi = self.system.pose(u, body)[1] if body else _free_end_angle(self.system, u, f.point)
                c, s = math.cos(phi), math.sin(phi)
                fx, fy = c * fx - s * fy, s * fx + c * fy
            a = F.get(f.point, (0.0, 0.0))
            F[f.point] = (a[0] + fx, a[1] + fy)
        for pf in self.pointed:
            p = _point_position(self.system, u, pf.point)
            ex, ey = pull_direction(pf.toward, pf.angle, (float(p[0]), float(p[1])))
            size = float(self.value(pf.values, t))
            fx, fy = size * ex, size * ey
            a = F.get(pf.point, (0.0, 0.0))
            F[pf.point] = (a[0] + fx, a[1] + fy)
        C: dict[tuple[str, str], float] = {}
        for cp in self.couples:
            key = ("body", cp.body) if isinstance(cp, Couple) else ("node", cp.point)
            C[key] = C.get(key, 0.0) + self.value(cp.m, t)
        return _LevelLoads(
            F,
            C,
            [self.value(r.values, t) for r in self.rotations],
            [self.value(d.values, t) for d in self.displacements],
        )

    def force_rates(self, t: float, u: NDArray[np.float64]) -> dict[str, list[float]]:
        """The derivatives of the forces at the nodes (``__call__``) that depend on the unknowns, with
        respect to their point's current position p and turn phi: node -> [dFx/dpx, dFx/dpy, dFx/dphi,
        dFy/dpx, dFy/dpy, dFy/dphi]. A follower force F = R(phi) f turns with its point: dF/dphi = R'(phi) f
        = (-Fy, Fx). A force of size P toward a fixed point q, turned by alpha: with d = q - p,
        F = P R(alpha) d/|d|, so dF/dp = -(P/|d|) R(alpha) (I - d d^T/|d|^2)."""
        rates: dict[str, list[float]] = {}
        for f in self.forces:
            if f.follower:
                fx, fy = float(self.value(f.fx, t)), float(self.value(f.fy, t))
                body = self.mech.body_of.get(f.point)
                phi = self.system.pose(u, body)[1] if body else _free_end_angle(self.system, u, f.point)
                c, s = math.cos(phi), math.sin(phi)
                a = rates.setdefault(f.point, [0.0] * 6)
                a[2] -= s * fx + c * fy
                a[5] += c * fx - s * fy
        for pf in self.pointed:
            p = _point_position(self.system, u, pf.point)
            dx, dy = pf.toward[0] - float(p[0]), pf.toward[1] - float(p[1])
            length = math.hypot(dx, dy)
            if length == 0.0:
                raise ValueError(f"the force at '{pf.point}' pulls toward {pf.toward}, where the point now is")
            ex, ey = dx / length, dy / length
            c, s = math.cos(pf.angle), math.sin(pf.angle)
            size = float(self.value(pf.values, t)) / length
            # -(P/|d|) R(alpha) (I - e e^T), e = d/|d|
            p00, p01, p11 = 1.0 - ex * ex, -ex * ey, 1.0 - ey * ey
            a = rates.setdefault(pf.point, [0.0] * 6)
            a[0] -= size * (c * p00 - s * p01)
            a[1] -= size * (c * p01 - s * p11)
            a[3] -= size * (s * p00 + c * p01)
            a[4] -= size * (s * p01 + c * p11)
        return rates


@dataclass
class _LevelState:
    """One solved level: node positions, body rotations, driver multipliers, strain energy, beam shapes."""

    positions: dict[str, NDArray[np.float64]]
    rotations: dict[str, float]
    drivers: list[float]
    energy: float
    shape: dict[str, NDArray[np.float64]]
    start_loads: dict[str, tuple[float, float, float]]


def _level_state(mech: Mechanism, system: "_System", u: NDArray[np.float64]) -> _LevelState:
    pos: dict[str, NDArray[np.float64]] = {}
    shape: dict[str, NDArray[np.float64]] = {}
    U = 0.0
    start_loads: dict[str, tuple[float, float, float]] = {}
    for i, beam in enumerate(mech.beams):
        wx, wy = system.along.get(beam.name, (0.0, 0.0))
        arc = system.tangent0[beam.name][2]
        m0 = float(u[3 * i + 2]) if beam.start_kind == "clamped" else 0.0
        start_loads[beam.name] = (float(u[3 * i]) + wx * arc, float(u[3 * i + 1]) + wy * arc, m0)
        end = system.integrate(beam, u)
        U += end[4]
        shape[beam.name] = system.shape(beam, u, 33)
        pos[beam.end] = end[:2].copy()
        assert beam.start_body is not None  # a beam's start is held (`Mechanism` checks it)
        pos[beam.start] = system.node_position(u, beam.start_body, beam.start)
    for node in mech.nodes:
        body = mech.body_of.get(node)
        if body is not None:
            pos[node] = system.node_position(u, body, node)
        elif node not in pos:
            pos[node] = np.asarray(mech.nodes[node], float)
    return _LevelState(
        pos,
        {b.name: float(system.pose(u, b.name)[1]) for b in mech.bodies},
        [float(x) for x in u[system.i_rot : system.size]],
        U,
        shape,
        start_loads,
    )


class _Problem(NamedTuple):
    """A mechanism under its loads as Newton sees it: the system, the loads along the path, the residual's
    row scaling (``_scale``) and the unknowns' typical sizes (``_unknown_scale``)."""

    system: _System
    path: _LoadPath
    scale: NDArray[np.float64]
    typical: NDArray[np.float64]

    def residual(self, t: float, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """The scaled residual at the load parameter t."""
        scaled: NDArray[np.float64] = self.system.residual(u, self.path(t, u)) / self.scale
        return scaled

    def jacobian(self, t: float, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """The derivative of ``residual`` with respect to u (``_System.jacobian``)."""
        loads = self.path(t, u)
        rates = self.path.force_rates(t, u)
        scaled: NDArray[np.float64] = self.system.jacobian(u, loads, rates) / self.scale[:, None]
        return scaled


def _problem(mech: Mechanism, loads: Sequence[_Load], n_levels: int, rtol: float) -> _Problem:
    """The unknowns, the residual and its scaling for a mechanism under its loads (``solve_mechanism``)."""
    forces = [ld for ld in loads if isinstance(ld, Force)]
    pointed = [ld for ld in loads if isinstance(ld, PointedForce)]
    distributed = [ld for ld in loads if isinstance(ld, DistributedLoad)]
    names = {beam.name for beam in mech.beams}
    for dl in distributed:
        if dl.beam not in names:
            raise ValueError(f"a distributed load on '{dl.beam}', which is no beam of the mechanism")
    couples = [ld for ld in loads if isinstance(ld, (Couple, EndCouple))]
    rotations = [ld for ld in loads if isinstance(ld, PrescribedRotation)]
    displacements = [ld for ld in loads if isinstance(ld, PrescribedDisplacement)]
    system = _System(mech, forces, couples, rotations, displacements, rtol)
    level_loads = _LoadPath(mech, system, forces, couples, rotations, displacements, n_levels, pointed, distributed)
    arcs = {beam.name: system.tangent0[beam.name][2] for beam in mech.beams}
    scale_F = max(
        [abs(v) for f in forces for v in (*f.fx, *f.fy)]
        + [abs(v) for f in pointed for v in f.values]
        + [abs(v) * arcs[d.beam] for d in distributed for v in (*d.wx, *d.wy)]
        + [0.0]
    )
    scale_F = max([scale_F] + [abs(v) for c in couples for v in c.m])
    # the force unit of the residual and the unknowns: the applied loads' size, else (motions prescribed)
    # the force EI/L^2 that bends a beam by its length; never a fixed number, so a load 1e-11 EI/L^2 is
    # solved, not taken for the unloaded state
    bending = _bending_force(mech, system)
    scale_F = scale_F if scale_F > 0.0 else bending
    scale = _scale(system, scale_F)
    # the sizes of the unknowns, the force unknowns' at least a bending force's worth (the scale a
    # finite-difference check of the Jacobian steps by)
    return _Problem(system, level_loads, scale, _unknown_scale(system, max(scale_F, bending)))


def solve_mechanism(
    mech: Mechanism, loads: Sequence[_Load], n_levels: int, *, rtol: float = 1e-11, max_cuts: int = 8
) -> MechanismSolution:
    """Equilibrium at every load level (loads: Force, PointedForce, DistributedLoad, Couple, EndCouple,
    PrescribedRotation, PrescribedDisplacement, each with one value per level); a level is given up after
    ``max_cuts`` halvings of its load step in a row."""
    t0 = time.perf_counter()
    problem = _problem(mech, loads, n_levels, rtol)
    system = problem.system
    u = np.zeros(system.size)  # the unloaded mechanism: no loads, every pose and beam angle as built
    states: list[_LevelState] = []
    ok_levels: list[bool] = []
    t = -1.0
    messages: list[str] = []
    jac: NDArray[np.float64] | None = None
    history = [(t, u)]
    for level in range(n_levels):
        step, cuts = 1.0, 0  # cuts: consecutive halvings since the last accepted step
        converged = True
        while t < level - 1e-12:
            target = min(t + step, float(level))
            scaled = lambda x: problem.residual(target, x)  # noqa: E731
            tangent = lambda x: problem.jacobian(target, x)  # noqa: E731
            guess = u
            if len(history) >= 2 and cuts == 0:  # secant predictor along the last two states
                (t0_, u0_), (t1_, u1_) = history[-2], history[-1]
                guess = u + (target - t) / (t1_ - t0_) * (u1_ - u0_)
            x, ok, jac, why = _chord_newton(scaled, guess, jac, tangent)
            if not ok and guess is not u:
                x, ok, jac, why = _chord_newton(scaled, u, jac, tangent)
            if ok:
                turn = _largest_turn(system, u, x)
                if turn > MAX_TURN_PER_STEP:  # a jump to another equilibrium, not the path's next state
                    ok, why = False, f"a step turned a beam end or a body by {turn:.3g} rad"
            if ok:
                u, t = x, target
                history.append((t, u))
                step = min(2.0 * step, 1.0)
                cuts = 0
            else:
                cuts += 1
                step /= 2
                if cuts > max_cuts:
                    converged = False
                    messages.append(
                        f"level {level}: no convergence after {max_cuts} step halvings in a row, at "
                        f"load parameter {t:.6g} ({why})"
                    )
                    break
        ok_levels.append(converged)
        if not converged:
            break
        states.append(_level_state(mech, system, u))
    done = all(ok_levels) and len(ok_levels) == n_levels
    return MechanismSolution(
        done,
        "; ".join(messages) or f"converged at {n_levels} level(s)",
        [s.positions for s in states],
        [s.rotations for s in states],
        [s.drivers for s in states],
        [s.energy for s in states],
        [s.shape for s in states],
        time.perf_counter() - t0,
        ok_levels,
        [s.start_loads for s in states],
    )


def _chord_newton(
    f: _Vector,
    x: NDArray[np.float64],
    jac: NDArray[np.float64] | None,
    jacobian: _Matrix,
    tol: float = 1e-10,
    maxiter: int = 30,
    min_steps: int = 1,
    refresh: float = 0.1,
) -> tuple[NDArray[np.float64], bool, NDArray[np.float64] | None, str]:
    """Newton on f(x) = 0 with the Jacobian ``jacobian`` kept between iterations and load steps and updated by
    Broyden's rank-one formula; evaluated afresh at the new point after a step that lowered the residual
    by less than the factor ``refresh`` (from an accurate Jacobian Newton's steps lower it by far more
    near the root), and at the old point when a step does not halve the residual. Returns (x, converged,
    Jacobian, why not).  At least ``min_steps`` steps are taken: a motion or load so small that the starting
    state's residual is already within the tolerance (a prescribed displacement of 1e-10 L) is still
    solved, not answered by the starting state; such a step is kept where it lowers the residual."""
    r = f(x)
    fresh = stale = False
    for step in range(maxiter):
        size = float(np.max(np.abs(r)))
        if not math.isfinite(size):
            return x, False, None, "the residual is not finite"
        if size <= tol and step >= min_steps:
            return x, True, jac, ""
        if size <= tol:
            return _one_more_step(f, x, r, jac, jacobian, size), True, jac, ""
        if jac is None or stale:
            jac, fresh, stale = jacobian(x), True, False
        try:
            dx = np.linalg.solve(jac, -r)
        except np.linalg.LinAlgError:
            return x, False, None, "singular Jacobian"
        x_try = x + dx
        r_try = f(x_try)
        new = float(np.max(np.abs(r_try)))
        if fresh:  # a fresh Jacobian: backtrack along its step until the residual falls
            for _ in range(6):
                if math.isfinite(new) and new < size:
                    break
                dx = dx / 2
                x_try = x + dx
                r_try = f(x_try)
                new = float(np.max(np.abs(r_try)))
        if new <= 0.5 * size or (fresh and math.isfinite(new) and new < size):
            stale = new > refresh * size
            if not stale:
                jac = jac + np.outer(r_try - r - jac @ dx, dx) / float(dx @ dx)  # Broyden's update
            x, r, fresh = x_try, r_try, False
        elif not fresh:
            jac, fresh = jacobian(x), True
        else:
            return x, False, jac, f"the residual stalled at {size:.3g}"
    return x, False, jac, f"{maxiter} iterations"


def _one_more_step(
    f: _Vector,
    x: NDArray[np.float64],
    r: NDArray[np.float64],
    jac: NDArray[np.float64] | None,
    jacobian: _Matrix,
    size: float,
) -> NDArray[np.float64]:
    """x after one Newton step from a state already within the tolerance, kept where it lowers the residual."""
    jac = jacobian(x) if jac is None else jac
    try:
        x_try = x + np.linalg.solve(jac, -r)
    except np.linalg.LinAlgError:
        return x
    new = float(np.max(np.abs(f(x_try))))
    return x_try if math.isfinite(new) and new < size else x


def _bending_force(mech: Mechanism, system: _System) -> float:
    """EI/L^2 of the stiffest beam over the longest: the force that bends a beam by about its length."""
    L = max(v[2] for v in system.tangent0.values())
    return max(beam.EI for beam in mech.beams) / (L * L)


def _unknown_scale(system: _System, scale_F: float) -> NDArray[np.float64]:
    """Typical size of each unknown: forces by the load scale, moments by load x length, poses by
    the length (translations) and 1 (angles)."""
    L = max(v[2] for v in system.tangent0.values())
    F = scale_F
    s = np.empty(system.size)
    for i, beam in enumerate(system.m.beams):
        s[3 * i : 3 * i + 2] = F
        s[3 * i + 2] = F * L if beam.start_kind == "clamped" else 1.0
    s[system.i_body : system.i_pin] = np.tile([L, L, 1.0], (system.i_pin - system.i_body) // 3)
    s[system.i_pin : system.i_rot] = F
    s[system.i_rot : system.i_disp] = F * L
    s[system.i_disp :] = F
    return s


def _scale(system: _System, scale_F: float) -> NDArray[np.float64]:
    """Residual scaling: positions by the largest beam length, angles by 1, loads by the load scale."""
    L = max(v[2] for v in system.tangent0.values())
    s = np.ones(system.size)
    for i, beam in enumerate(system.m.beams):
        s[3 * i : 3 * i + 2] = L if beam.end_kind != "free" else scale_F
    s[system.i_body : system.i_pin] = scale_F
    s[system.i_pin : system.i_rot] = L
    return s


def _largest_turn(system: _System, u: NDArray[np.float64], x: NDArray[np.float64]) -> float:
    """The largest change of a body's rotation or of a beam's end angles from the state u to x (rad)."""
    turn = 0.0
    for body in system.m.bodies:
        turn = max(turn, abs(system.pose(x, body.name)[1] - system.pose(u, body.name)[1]))
    ul, xl = u.tolist(), x.tolist()
    for beam in system.m.beams:
        turn = max(
            turn,
            abs(system._start(beam, xl)[2] - system._start(beam, ul)[2]),
            abs(float(system.integrate(beam, x, xl)[2]) - float(system.integrate(beam, u, ul)[2])),
        )
    return turn


def _point_position(system: _System, u: NDArray[np.float64], point: str) -> NDArray[np.float64]:
    """The current position of a named point: on its body, or at the free beam end it is."""
    body = system.m.body_of.get(point)
    if body is not None:
        return system.node_position(u, body, point)
    for beam in system.m.beams:
        if beam.end == point and beam.end_kind == "free":
            return system.integrate(beam, u)[:2]
    raise ValueError(f"a force at node '{point}', which is on no rigid body and at no free beam end")


def _free_end_angle(system: _System, u: NDArray[np.float64], node: str) -> float:
    for beam in system.m.beams:
        if beam.end == node and beam.end_kind == "free":
            end = system.integrate(beam, u)
            angle: float = end[2] - system.tangent0[beam.name][1]
            return angle
    return 0.0
