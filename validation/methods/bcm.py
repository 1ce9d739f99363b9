"""Adapter: a case -> the beam constraint model of [chen2021] (``bcm``).

Segments: a straight segment (fixed-free, fixed-pinned, fixed-guided, fixed-fixed) with dead tip
forces, tip moments, and tip displacements along x or y / rotations; one quantity of each pair
(u_x|f_x, u_y|f_y, theta|m_z) is known at every level and ``bcm.solve_mixed`` gives the rest
(Castigliano on eq (11) for displacement-specified problems, eqs (3)-(4) otherwise).

Mechanisms: one rigid link welded to straight beams that are clamped to the ground at their
other end, optionally pinned to the ground at one of its nodes, loaded by dead forces at its
nodes, a moment, or a prescribed rotation (``bcm.RigidBodyOnBeams``; the ``moment`` output at
the driven point is then the torque needed). Anything else raises ``NotApplicable``.

BCM is trusted for |u_y| <= 0.1 and |theta| <= 0.1 rad [chen2021, §3]; levels outside
this range are reported in ``level_messages`` and ``extras['outside_range']`` (values kept).
k_a = A L^2 / I of each beam's section (1e12, i.e. inextensible, if the area is not given).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from bcm.beam import solve_mixed, strain_energy
from bcm.mechanisms import BCMBeam, Displacement, RigidBodyOnBeams
from validation.methods.base import MethodRun, NotApplicable, Request, reject_loads_along_beams
from validation.case.quantities import boundary_held_tip
from validation.case.method_options import BcmOptions
from validation.case.schema import Case, LinkSpec, LoadSpec, MechanismSpec, SegmentSpec

RANGE = 0.1


@dataclass
class _Answers:
    """What a BCM solve gives: the values asked for, a message per level, the levels outside its range."""

    values: dict[Request, float] = field(default_factory=dict)
    messages: dict[int, str] = field(default_factory=dict)
    outside: list[int] = field(default_factory=list)


def _ka(EI: float, EA: float, L: float) -> float:
    return EA * L * L / EI if math.isfinite(EA) else 1e12


def _direction(load: LoadSpec) -> tuple[float, float]:
    """A load's unit direction; a force toward a fixed point has none, and the BCM takes no such force."""
    if load.direction is None:
        raise NotApplicable("the BCM takes no force toward a fixed point")
    return load.direction


def _segment(case: Case, seg: SegmentSpec, requests: list[Request], options: BcmOptions) -> _Answers:
    if seg.initial_curvature() != 0.0:
        raise NotApplicable("BCM models initially straight beams only")
    if seg.boundary == "pinned-pinned":
        raise NotApplicable("boundary 'pinned-pinned' is not a BCM cantilever")
    L = seg.length
    if options.EI is not None:
        EI = options.EI
    elif options.I is not None:
        if seg.E is None:
            raise NotApplicable("[methods.bcm] I needs the segment's modulus E; give EI instead")
        EI = seg.E * options.I
    else:
        EI = seg.bending_stiffness()
    ka = _ka(EI, seg.axial_stiffness(), L)
    f_scale, m_scale = L * L / EI, L / EI
    answers = _Answers()
    values, msgs, outside = answers.values, answers.messages, answers.outside
    for level in sorted({r.level for r in requests}):
        given = {"fx": 0.0, "fy": 0.0, "mz": 0.0}
        disp: dict[str, float] = {}
        for load in case.loads:
            if load.point != "tip":
                raise NotApplicable(f"load at '{load.point}': BCM takes tip loads only")
            v = load.levels()[level]
            if load.kind == "force":
                if load.follower:
                    raise NotApplicable("BCM has no follower force")
                direction = _direction(load)
                given["fx"] += v * direction[0] * f_scale
                given["fy"] += v * direction[1] * f_scale
            elif load.kind == "moment":
                given["mz"] += v * m_scale
            elif load.kind == "displacement":
                direction = _direction(load)
                moved = np.asarray(direction, float) * v
                if direction[0] != 0.0 and direction[1] != 0.0:
                    raise NotApplicable("BCM adapter takes displacements along x or y only")
                key = "ux" if direction[0] != 0.0 else "uy"
                disp[key] = disp.get(key, 0.0) + float(moved[0] if key == "ux" else moved[1]) / L
            elif load.kind == "rotation":
                disp["theta"] = math.radians(v)
        for dof in boundary_held_tip(case):  # the contract's rule (validation/case/quantities.py)
            disp.setdefault({"rz": "theta"}.get(dof, dof), 0.0)
        kw: dict[str, float] = {}
        for motion, force in (("ux", "fx"), ("uy", "fy"), ("theta", "mz")):
            kw.update({motion: disp[motion]} if motion in disp else {force: given[force]})
        ux, uy, th, fx, fy, mz = solve_mixed(ka, **kw)
        if abs(uy) > RANGE or abs(th) > RANGE:
            outside.append(level)
            msgs[level] = f"outside the BCM range (u_y = {uy:.3g}, theta = {th:.3g} rad)"
        table = {
            "x": L * (1 + ux),
            "y": L * uy,
            "dx": L * ux,
            "dy": L * uy,
            "rotation": math.degrees(th),
            "force_x": fx / f_scale,
            "force_y": fy / f_scale,
            "moment": mz / m_scale,
        }
        for req in requests:
            if req.level != level:
                continue
            if req.quantity == "strain_energy":
                values[req] = strain_energy(ux, uy, th, ka) * EI / L
            elif req.point == "root" and req.quantity in ("x", "y", "dx", "dy", "rotation"):
                values[req] = 0.0
            elif req.point == "tip" and req.quantity in table:
                values[req] = table[req.quantity]
            else:
                raise NotApplicable(f"'{req.quantity}' at '{req.point}' is not a BCM output")
    return answers


@dataclass
class LinkOnBeams:
    """The BCM mechanism: the rigid link, node positions, and the link on its beams."""

    link: LinkSpec
    nodes: dict[str, np.ndarray]
    body: RigidBodyOnBeams

    def point(self, name: str) -> str:
        """A node name, 'input' meaning the link's first node."""
        return name if name != "input" else self.link.nodes[0]


@dataclass
class LevelLoads:
    """One level's loads on the link: dead forces (at, F), the couple, the prescribed rotation (rad),
    the prescribed displacement of a node, the applied force at each node, and the node the couple or
    prescribed motion drives."""

    forces: list = field(default_factory=list)
    moment: float = 0.0
    rotation: float | None = None
    displacement: Displacement | None = None
    applied: dict[str, np.ndarray] = field(default_factory=dict)
    drive_point: str | None = None


def _link_on_beams(mech: MechanismSpec) -> LinkOnBeams:
    if len(mech.links) != 1:
        raise NotApplicable("BCM adapter: exactly one rigid link carried by clamped beams")
    if mech.joints:
        raise NotApplicable("BCM adapter: released joints (pins between members) are not modelled")
    link = mech.links[0]
    nodes = {n.name: np.array([n.x, n.y]) for n in mech.nodes}
    fixed = {s.node for s in mech.supports if s.kind == "fixed"}
    pinned = [s for s in mech.supports if s.kind == "pinned"]
    if any(s.kind not in ("fixed", "pinned") for s in mech.supports) or len(pinned) > 1:
        raise NotApplicable("BCM adapter: supports must be clamps plus at most one pin")
    if pinned and pinned[0].node not in link.nodes:
        raise NotApplicable("BCM adapter: the pin must hold the rigid link")
    beams = []
    for b in mech.beams:
        if b.curvature != 0.0:
            raise NotApplicable("BCM models initially straight beams only")
        if b.start in fixed and b.end in link.nodes:
            ground, tip = b.start, b.end
        elif b.end in fixed and b.start in link.nodes:
            ground, tip = b.end, b.start
        else:
            raise NotApplicable(f"beam '{b.name}' does not run from a clamp to the link")
        EA, EI = b.section.stiffness(b.E if b.E is not None else mech.E)
        L = float(np.linalg.norm(nodes[tip] - nodes[ground]))
        beams.append(BCMBeam(tuple(nodes[ground]), tuple(nodes[tip]), EI, _ka(EI, EA, L)))
    ref = nodes[pinned[0].node] if pinned else nodes[link.nodes[0]]
    return LinkOnBeams(link, nodes, RigidBodyOnBeams(beams, tuple(ref), pinned=bool(pinned)))


def _level_loads(case: Case, mech: LinkOnBeams, level: int) -> LevelLoads:
    loads = LevelLoads()
    for load in case.loads:
        point = mech.point(load.point)
        if point not in mech.link.nodes:
            raise NotApplicable(f"load at '{load.point}' is not on the rigid link")
        v = load.levels()[level]
        if load.kind == "force" and not load.follower:
            F = v * np.asarray(_direction(load), float)
            loads.forces.append((tuple(mech.nodes[point]), F))
            loads.applied[point] = loads.applied.get(point, np.zeros(2)) + F
        elif load.kind == "moment":
            loads.moment += v
            loads.drive_point = point
        elif load.kind == "rotation":
            loads.rotation = math.radians(v)
            loads.drive_point = point
        elif load.kind == "displacement":
            d = _direction(load)
            if abs(d[0]) > 1e-12 and abs(d[1]) > 1e-12:
                raise NotApplicable("BCM adapter: a prescribed displacement along x or along y")
            axis = 0 if abs(d[0]) > 0.5 else 1
            loads.displacement = Displacement(tuple(mech.nodes[point]), axis, v * d[axis])
            loads.drive_point = point
        else:
            raise NotApplicable(f"BCM adapter: load kind '{load.kind}' on a mechanism")
    if loads.rotation is not None and loads.displacement is not None:
        raise NotApplicable("BCM adapter: one prescribed motion of the link at a time")
    return loads


def _mechanism_value(mech: LinkOnBeams, req: Request, q, needed: float, loads: LevelLoads) -> float:
    """One requested value at a solved level (q: the link's (x, y, phi); needed: the driving moment)."""
    if req.quantity == "strain_energy":
        return mech.body.strain_energy(q)
    point = mech.point(req.point)
    on_link = point in mech.link.nodes
    if not on_link and point not in mech.nodes:
        raise NotApplicable(f"unknown point '{req.point}'")
    X = mech.nodes[point]
    p = mech.body.position(X, q) if on_link else X
    applied = loads.applied.get(point, np.zeros(2)).copy()
    driven = point == loads.drive_point
    if driven and loads.displacement is not None:  # the force the prescribed displacement needs
        applied[loads.displacement.axis] += needed
    table = {
        "x": p[0],
        "y": p[1],
        "dx": p[0] - X[0],
        "dy": p[1] - X[1],
        "rotation": math.degrees(q[2]) if on_link else 0.0,
        "force_x": applied[0],
        "force_y": applied[1],
        "moment": needed if driven and loads.displacement is None else 0.0,
    }
    if req.quantity not in table:
        raise NotApplicable(f"'{req.quantity}' is not a BCM mechanism output")
    return float(table[req.quantity])


def _mechanism(case: Case, spec: MechanismSpec, requests: list[Request], options: BcmOptions) -> _Answers:
    mech = _link_on_beams(spec)
    answers = _Answers()
    values, msgs, outside = answers.values, answers.messages, answers.outside
    q = None
    for level in range(max(r.level for r in requests) + 1):
        loads = _level_loads(case, mech, level)
        try:
            q, needed = mech.body.solve(
                forces=loads.forces,
                moment=loads.moment,
                rotation=loads.rotation,
                guess=q,
                displacement=loads.displacement,
            )
        except RuntimeError as exc:  # no equilibrium from here on: the levels so far stand
            msgs[level] = f"level {level}: {exc}"
            break
        states = mech.body.beam_states(q)
        if any(abs(s[1]) > RANGE or abs(s[2]) > RANGE for s in states):
            outside.append(level)
            msgs[level] = "outside the BCM range: " + ", ".join(f"u_y = {s[1]:.3g}, theta = {s[2]:.3g}" for s in states)
        for req in requests:
            if req.level == level:
                values[req] = _mechanism_value(mech, req, q, needed, loads)
    return answers


def run(case: Case, requests: list[Request], options: BcmOptions) -> MethodRun:
    t0 = time.perf_counter()
    if not requests:
        return MethodRun(values={})
    reject_loads_along_beams(case, "the BCM")
    try:
        if case.segment is not None:
            answers = _segment(case, case.segment, requests, options)
        elif case.mechanism is not None:
            answers = _mechanism(case, case.mechanism, requests, options)
        else:
            raise NotApplicable("the case has neither a segment nor a mechanism")
        values, msgs, outside = answers.values, answers.messages, answers.outside
    except RuntimeError as exc:  # the library's solver found no equilibrium: say so, never a bare crash
        return MethodRun(
            values={},
            converged=False,
            wall_time=time.perf_counter() - t0,
            message=f"{exc} (the load path leaves what the BCM equations solve)",
        )
    levels = sorted({r.level for r in requests})
    solved = {lv: all(r in values for r in requests if r.level == lv) for lv in levels}
    message = "converged" if not outside else f"BCM range exceeded at levels {outside}"
    if not all(solved.values()):
        first = min(lv for lv, ok in solved.items() if not ok)
        message = f"no BCM equilibrium from level {first} on: {msgs.get(first, '')}"
    return MethodRun(
        values=values,
        converged=all(solved.values()),
        message=message,
        wall_time=time.perf_counter() - t0,
        level_converged=solved,
        level_messages={lv: msgs.get(lv, "") for lv in levels},
        extras={"outside_range": outside, "model": "beam constraint model [chen2021]"},
    )
