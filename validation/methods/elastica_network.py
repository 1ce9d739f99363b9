"""The mechanism part of the elastica adapter: a case's ``[mechanism]`` -> ``elastica.mechanism``.

Every beam becomes an exact elastica (axially extensible with the section's EA, as the FEM; an
'inertia' section without A is inextensible), coupled through the rigid links and supports by
shooting on the beam end loads (see ``elastica/mechanism.py``). How each beam end is held: on a
rigid link (welded where links share a node without a joint) or a fixed support -> clamped to that
body (or the ground); a joint naming the beam, or a pinned support on a node with no link -> pinned;
nothing -> free. Joints between links and pinned supports on links are pins. Not modelled (the
run says so): slider and guided supports, joint springs, beams welded to beams, distributed loads.

Outputs: x, y, dx, dy of any node; rotation of the body a node is on (or of a free beam end);
force_x, force_y, moment received at a node (applied, plus what a prescribed motion there needs);
input_torque (the prescribed rotation's couple or the applied moment); strain_energy.

Segments (``segment_model``, ``run_segment``): a single segment whose boundary the shooting of one clamped
beam cannot state (a pinned root; a straight fixed-fixed tip whose axial motion is held) is built as a
one-beam mechanism with its tip on a one-node body, and answers the segment adapter's outputs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

import planar
from elastica import mechanism as em
from elastica.shooting import unloaded_tip
from validation.case.method_options import ElasticaOptions
from validation.case.quantities import boundary_held_tip
from validation.methods.base import MethodRun, NotApplicable
from validation.methods.geometry import geometry


def model(case) -> tuple[em.Mechanism, dict[str, str]]:
    mech = case.mechanism
    for s in mech.supports:
        if s.kind in ("slider", "guided"):
            raise NotApplicable(f"a {s.kind} support at '{s.node}': not in the elastica mechanism model")
    if any(j.spring for j in mech.joints):
        raise NotApplicable("joint torsion springs: not in the elastica mechanism model")
    geo = geometry(mech)
    welded = planar.welded_bodies(geo)
    owner = welded.owner
    bodies = [em.RigidBody(name, tuple(nodes)) for name, nodes in welded.nodes_of.items()]
    link_body = welded.body_of_link
    nodes = {n.name: (n.x, n.y) for n in geo.nodes}
    beam_nodes = [nd for b in geo.beams for nd in (b.start, b.end)]
    beams = []
    for beam in geo.beams:
        EA, EI = beam.EA, beam.EI
        ends: list[tuple[str | None, str]] = []
        for nd in (beam.start, beam.end):
            joint = next((j for j in mech.joints if j.node == nd and beam.name in j.members), None)
            pinned_support = any(
                s.node == nd and s.kind == "pinned" and s.member in (None, beam.name) for s in mech.supports
            )
            body = owner.get(nd)
            if joint:
                body = next((link_body[m] for m in joint.members if m in link_body), body)
                if body is None:
                    raise NotApplicable(f"beam '{beam.name}' pinned at '{nd}' to no rigid link")
                ends.append((body, "pinned"))
            elif body is not None:
                ends.append((body, "clamped"))
            elif pinned_support:
                ends.append((em.GROUND, "pinned"))
            elif beam_nodes.count(nd) > 1:
                raise NotApplicable(f"beams welded to each other at '{nd}': not in the elastica mechanism model")
            else:
                ends.append((None, "free"))
        (b0, k0), (b1, k1) = ends
        start, end, kappa = beam.start, beam.end, beam.curvature
        if k0 == "free":
            (b0, k0), (b1, k1), start, end, kappa = (b1, k1), (b0, k0), end, start, -kappa
        if k0 == "free":
            raise NotApplicable(f"beam '{beam.name}' is held at neither end")
        beams.append(em.ElasticBeam(beam.name, start, end, EI, b0, b1, k0, k1, EA, kappa))
    pins = []
    for j in mech.joints:
        links = [m for m in j.members if m in link_body]
        for other in links[1:]:
            pins.append(em.Pin(link_body[other], link_body[links[0]], nodes[j.node], j.node))
    for s in mech.supports:
        if s.kind == "pinned":
            target = link_body.get(s.member) if s.member in link_body else owner.get(s.node)
            if target not in (None, em.GROUND):
                pins.append(em.Pin(target, em.GROUND, nodes[s.node], s.node))
    return em.Mechanism(nodes, beams, bodies, pins), {**owner, **{f"link:{k}": v for k, v in link_body.items()}}


def _follower_body_refused(load, owner: dict[str, str], mechanism: em.Mechanism) -> str | None:
    """Why a follower force naming ``body`` is not the one the elastica mechanism model turns (with the
    rigid body carrying its point, or with the free beam end it is at), or None when it is."""
    carried = mechanism.body_of.get(load.point)
    if f"link:{load.body}" in owner:
        named = owner[f"link:{load.body}"]
        return None if named == carried else f"it turns with link '{load.body}', not the body carrying '{load.point}'"
    beam = next((b for b in mechanism.beams if b.name == load.body), None)
    if beam is None:
        return None
    kind, body = (beam.start_kind, beam.start_body) if beam.start == load.point else (beam.end_kind, beam.end_body)
    if kind == "free" or (kind == "clamped" and body == carried):
        return None
    return f"it turns with beam '{load.body}', {kind} at '{load.point}' (its end turns apart from the body there)"


def _along_beam(i: int, load, values: tuple[float, ...], beam: str, section) -> planar.DistributedLoad:
    """A distributed or self-weight load as a uniform dead load per unit length on one beam (self-weight:
    its section's weight per length along gravity)."""
    if load.follower:
        raise NotApplicable(
            f"loads.{i}: a follower distributed load (a pressure turning with the beam): the "
            "elastica mechanism model's loads along a beam are dead"
        )
    d = np.asarray(load.direction, float)
    d = d / math.hypot(*d)
    scale = section.weight_per_length() if load.kind == "self_weight" else 1.0
    if scale is None:
        raise NotApplicable(f"loads.{i}: self-weight, but beam '{beam}''s section gives no weight density")
    return planar.DistributedLoad(
        beam, tuple(scale * x * d[0] for x in values), tuple(scale * x * d[1] for x in values)
    )


def _along_beams(case, i: int, load, values: tuple[float, ...]) -> list[planar.DistributedLoad]:
    """A distributed or self-weight load on each beam it covers (``member``, else every beam; rigid links
    carry none, as in the FEM)."""
    return [
        _along_beam(i, load, values, beam.name, beam.section)
        for beam in case.mechanism.beams
        if load.member in (None, beam.name)
    ]


def loads(case, owner: dict[str, str], mechanism: em.Mechanism) -> list[planar.Load | em.EndCouple]:
    out: list[planar.Load | em.EndCouple] = []
    for i, load in enumerate(case.loads):
        v = tuple(float(x) for x in load.levels())
        body = owner.get(f"link:{load.body}") if load.body else owner.get(load.point)
        if load.kind == "force" and load.follower and load.body is not None:
            why = _follower_body_refused(load, owner, mechanism)
            if why is not None:
                raise NotApplicable(
                    f"loads.{i}: a follower force {why}: the elastica mechanism model turns a "
                    "follower with the rigid body carrying its point, or its free beam end"
                )
        if load.kind == "force" and load.toward is not None:
            out.append(
                em.PointedForce(load.point, v, (float(load.toward[0]), float(load.toward[1])), math.radians(load.angle))
            )
        elif load.kind == "force":
            d = load.direction
            out.append(em.Force(load.point, tuple(x * d[0] for x in v), tuple(x * d[1] for x in v), load.follower))
        elif load.kind == "moment":
            if body in (None, em.GROUND):
                out.append(em.EndCouple(load.point, v))
            else:
                out.append(em.Couple(body, v))
        elif load.kind == "rotation":
            if body in (None, em.GROUND):
                raise NotApplicable(f"loads.{i}: a prescribed rotation of '{load.point}', on no rigid link")
            out.append(em.PrescribedRotation(body, tuple(math.radians(x) for x in v)))
        elif load.kind in ("distributed", "self_weight"):
            out.extend(_along_beams(case, i, load, v))
        elif load.kind != "displacement":
            raise NotApplicable(f"loads.{i}: a {load.kind} load: not in the elastica mechanism model")
        else:
            d = np.asarray(load.direction, float) / math.hypot(*load.direction)
            if abs(d[0]) > 1e-12 and abs(d[1]) > 1e-12:
                raise NotApplicable(f"loads.{i}: a prescribed displacement must be along x or along y")
            axis = "x" if abs(d[0]) > 0.5 else "y"
            out.append(
                em.PrescribedDisplacement(load.point, axis, tuple(x * (d[0] if axis == "x" else d[1]) for x in v))
            )
    return out


def _body_lines(mechanism, positions: dict) -> list[np.ndarray]:
    """The rigid bodies of one level as lines, each from its first node to each of its other nodes (a star,
    as the FEM draws its rigid links): the beams alone would leave the mechanism's coupler undrawn."""
    return [
        np.array([positions[body.nodes[0]], positions[node]], float)
        for body in mechanism.bodies
        for node in body.nodes[1:]
    ]


def run_mechanism(case, requests, options: ElasticaOptions) -> MethodRun:
    mechanism, owner = model(case)
    tolerance: dict[str, Any] = {} if options.rtol is None else {"rtol": options.rtol}  # else the solver's own
    try:
        sol = em.solve_mechanism(mechanism, loads(case, owner, mechanism), case.n_levels(), **tolerance)
    except ValueError as exc:
        raise NotApplicable(str(exc)) from None
    drivers = [ld for ld in case.loads if ld.kind in ("rotation", "displacement")]
    values = {}
    for req in requests:
        q, p, lv = req
        if lv >= len(sol.positions):
            continue
        if q in ("x", "y", "dx", "dy"):
            xy = sol.positions[lv][p]
            x0, y0 = mechanism.nodes[p]
            values[req] = float({"x": xy[0], "y": xy[1], "dx": xy[0] - x0, "dy": xy[1] - y0}[q])
        elif q == "rotation":
            body = owner.get(p)
            if body in (None, em.GROUND):
                raise NotApplicable(f"the rotation of '{p}', on no rigid link")
            values[req] = math.degrees(sol.rotations[lv][body])
        elif q in ("force_x", "force_y", "moment", "input_torque"):
            k = ("force_x", "force_y", "moment", "input_torque").index(q)
            point = (
                p
                if q != "input_torque"
                else next((ld.point for ld in case.loads if ld.kind in ("rotation", "moment")), None)
            )
            if point is None:
                raise NotApplicable("input_torque needs a prescribed rotation or a moment (the input)")
            values[req] = _received(case, sol, drivers, mechanism.body_of, point, lv, min(k, 2))
        elif q == "strain_energy":
            values[req] = sol.strain_energy[lv]
        else:
            raise NotApplicable(f"the elastica mechanism model gives no '{q}'")
    shapes = [
        [np.asarray(s) for s in level.values()] + _body_lines(mechanism, positions)
        for level, positions in zip(sol.beam_shapes, sol.positions)
    ]
    return MethodRun(
        values=values,
        converged=sol.converged,
        message=f"elastica mechanism: {sol.message}",
        level_converged=dict(enumerate(sol.level_converged)),
        extras={"shapes": shapes},
    )


def _received(case, sol, drivers, body_of: dict[str, str], point: str, level: int, k: int) -> float:
    """Component k (force_x, force_y, moment) of the load the mechanism receives at ``point`` at a solved
    level: the applied loads there in their solved directions (a follower turned with its body, a force
    toward a fixed point along the solved line to it), plus what a prescribed motion there needs."""
    total = 0.0
    for ld in case.loads:
        if ld.point != point:
            continue
        v = ld.levels()[level]
        if ld.kind == "force" and k < 2:
            total += v * _solved_direction(ld, sol, body_of, level)[k]
        elif ld.kind == "moment" and k == 2:
            total += v
    rot = [ld for ld in drivers if ld.kind == "rotation"]
    disp = [ld for ld in drivers if ld.kind == "displacement"]
    for j, ld in enumerate(rot):
        if ld.point == point and k == 2:
            total += sol.driver_loads[level][j]
    for j, ld in enumerate(disp):
        axis = 0 if abs(ld.direction[0]) > abs(ld.direction[1]) else 1
        if ld.point == point and k == axis:
            total += sol.driver_loads[level][len(rot) + j]
    return float(total)


def _solved_direction(load, sol, body_of: dict[str, str], level: int) -> tuple[float, float]:
    """The unit direction of a force load at a solved level (a follower: turned with the body carrying its
    point, ``body_of``, as the solver turns it)."""
    if load.toward is not None:
        p = sol.positions[level][load.point]
        return planar.pull_direction(load.toward, math.radians(load.angle), (float(p[0]), float(p[1])))
    d = load.direction
    if not load.follower:
        return d[0], d[1]
    body = body_of.get(load.point)
    if body is None or body not in sol.rotations[level]:
        raise NotApplicable(
            f"the load received at '{load.point}': its follower force turns with a free beam "
            "end, whose angle the elastica mechanism model does not report"
        )
    phi = sol.rotations[level][body]
    return math.cos(phi) * d[0] - math.sin(phi) * d[1], math.sin(phi) * d[0] + math.cos(phi) * d[1]


# A single segment as a mechanism: the boundaries the shooting of one clamped beam (``elastica.shooting``)
# cannot state, or can only state inextensibly.

ROOT_BODY, TIP_BODY = "root end", "tip end"  # the one-node bodies carrying a pinned root and the tip
SEGMENT_STEP_CUTS = 30  # load-step halvings per level at most (elastica.mechanism)


@dataclass(frozen=True)
class SegmentMechanism:
    """One segment as ``elastica.mechanism`` data: the mechanism, its loads (the case's, then the
    boundary's held tip freedoms as prescribed zero motions) and what each prescribed motion is."""

    mechanism: em.Mechanism
    loads: list
    pinned_root: bool
    driver_axes: tuple[str, ...]  # per prescribed motion, in the solver's order: 'rz', 'ux' or 'uy'


def segment_model(case, EI: float) -> SegmentMechanism:
    """The segment of ``case`` as a mechanism (raises NotApplicable).

    Nodes ``root`` at the origin and ``tip`` at the unloaded tip; one beam between them (EI as given,
    EA = E A of the section, inextensible if an 'inertia' section gives no A; the initial curvature).
    The root is clamped to the ground, or for a pinned-pinned segment clamped to a one-node body
    (``ROOT_BODY``) pinned to the ground there, so that the root's rotation is an unknown and an output.
    The tip is clamped to a one-node body (``TIP_BODY``) that carries the tip loads (a force at the
    node, turning with the body if a follower; a moment and a prescribed rotation on the body; a
    prescribed displacement of the node) and whose freedoms the boundary holds
    (``quantities.boundary_held_tip``: the same rule as the FEM's) are prescribed zero motions. The
    body's moment balance makes the beam's end moment the applied moment: a free tip angle.
    """
    seg = case.segment
    L, kappa = seg.length, seg.initial_curvature()
    if abs(kappa * L) >= math.pi:
        raise NotApplicable(
            "an arc of |kappa L| >= pi: the elastica mechanism model finds a beam's arc from "
            "its chord, which names the minor arc only"
        )
    EA, _ = seg.section.stiffness(seg.E)
    if seg.section.kind == "inertia" and seg.section.A is None:
        EA = None
    pinned_root = seg.boundary == "pinned-pinned"
    held = boundary_held_tip(case)
    moved = set(held) | {
        "ux" if abs(ld.direction[0]) > abs(ld.direction[1]) else "uy" for ld in case.loads if ld.kind == "displacement"
    }
    if kappa == 0.0 and EA is None and "ux" in moved:
        raise NotApplicable(
            f"a straight {seg.boundary} segment whose tip's axial motion is held or prescribed, "
            "inextensible (no section area A): once it bends its chord shortens, so it cannot "
            "bend at all"
        )
    x0, y0, _ = unloaded_tip(L, kappa)
    nodes = {"root": (0.0, 0.0), "tip": (x0, y0)}
    bodies = [em.RigidBody(TIP_BODY, ("tip",))]
    pins = []
    start = em.GROUND
    if pinned_root:
        bodies.append(em.RigidBody(ROOT_BODY, ("root",)))
        pins.append(em.Pin(ROOT_BODY, em.GROUND, nodes["root"], "root"))
        start = ROOT_BODY
    beam = em.ElasticBeam("segment", "root", "tip", EI, start, TIP_BODY, "clamped", "clamped", EA, kappa)
    n = case.n_levels()
    applied: list[planar.Load] = []
    rotations: list[tuple[planar.PrescribedRotation, str]] = []
    displacements: list[tuple[planar.PrescribedDisplacement, str]] = []
    for i, load in enumerate(case.loads):
        v = tuple(float(x) for x in load.levels())
        if load.point != "tip" or load.body is not None:
            raise NotApplicable(f"loads.{i}: the elastica adapter takes tip loads only")
        if load.kind in ("distributed", "self_weight"):
            applied.append(_along_beam(i, load, v, "segment", seg.section))
        elif load.kind == "force" and load.toward is not None:
            applied.append(
                em.PointedForce("tip", v, (float(load.toward[0]), float(load.toward[1])), math.radians(load.angle))
            )
        elif load.kind == "force":
            d = load.direction
            applied.append(em.Force("tip", tuple(x * d[0] for x in v), tuple(x * d[1] for x in v), load.follower))
        elif load.kind == "moment":
            applied.append(em.Couple(TIP_BODY, v))
        elif load.kind == "rotation":
            rotations.append((em.PrescribedRotation(TIP_BODY, tuple(math.radians(x) for x in v)), "rz"))
        else:
            d = np.asarray(load.direction, float) / math.hypot(*load.direction)
            if abs(d[0]) > 1e-12 and abs(d[1]) > 1e-12:
                raise NotApplicable(f"loads.{i}: a prescribed displacement must be along x or along y")
            axis = "x" if abs(d[0]) > 0.5 else "y"
            displacements.append(
                (em.PrescribedDisplacement("tip", axis, tuple(x * d[0 if axis == "x" else 1] for x in v)), "u" + axis)
            )
    for dof in held:
        if dof == "rz":
            rotations.append((em.PrescribedRotation(TIP_BODY, (0.0,) * n), "rz"))
        else:
            displacements.append((em.PrescribedDisplacement("tip", dof[1], (0.0,) * n), dof))
    drivers = rotations + displacements  # the solver's order of prescribed-motion loads
    return SegmentMechanism(
        em.Mechanism(nodes, [beam], bodies, pins),
        applied + [d for d, _ in drivers],
        pinned_root,
        tuple(axis for _, axis in drivers),
    )


def run_segment(case, requests, options: ElasticaOptions, EI: float) -> MethodRun:
    """A segment case solved as the mechanism ``segment_model``: the segment adapter's outputs.

    At the tip: x, y, dx, dy; ``rotation``, the tip body's (the change of the tip angle, degrees);
    ``force_x``, ``force_y``, ``moment``, the tip loads acting on the beam (applied, a follower turned
    with the tip, plus the loads the held and prescribed freedoms need). At the root: its position, its
    rotation (a pinned root turns), and ``reaction_*``, the support's loads on the beam: minus what the
    beam applies at its root (the tip force plus the load along the beam, and the root moment m(0))."""
    built = segment_model(case, EI)
    tolerance = {} if options.rtol is None else {"rtol": options.rtol}  # else the solver's own
    try:  # a held tip stiffens by membrane action (N ~ EA (w/L)^2): the path may need many step halvings
        sol = em.solve_mechanism(built.mechanism, built.loads, case.n_levels(), max_cuts=SEGMENT_STEP_CUTS, **tolerance)
    except ValueError as exc:
        raise NotApplicable(str(exc)) from None
    x0, y0 = built.mechanism.nodes["tip"]
    values, shapes = {}, {}
    for level in range(len(sol.positions)):
        tip, phi = sol.positions[level]["tip"], sol.rotations[level][TIP_BODY]
        force, moment = np.zeros(2), 0.0
        for ld in built.loads:
            if isinstance(ld, em.Force):
                f = np.array([ld.fx[level], ld.fy[level]])
                c, s = math.cos(phi), math.sin(phi)
                force += np.array([c * f[0] - s * f[1], s * f[0] + c * f[1]]) if ld.follower else f
            elif isinstance(ld, em.PointedForce):
                force += ld.values[level] * np.array(planar.pull_direction(ld.toward, ld.angle, (tip[0], tip[1])))
            elif isinstance(ld, em.Couple):
                moment += ld.m[level]
        for axis, load in zip(built.driver_axes, sol.driver_loads[level]):
            if axis == "rz":
                moment += load
            else:
                force[0 if axis == "ux" else 1] += load
        root_turn = sol.rotations[level][ROOT_BODY] if built.pinned_root else 0.0
        Rx, Ry, M0 = sol.start_loads[level]["segment"]  # what the beam applies at its root
        table = {
            "tip": {
                "x": tip[0],
                "y": tip[1],
                "dx": tip[0] - x0,
                "dy": tip[1] - y0,
                "rotation": math.degrees(phi),
                "force_x": force[0],
                "force_y": force[1],
                "moment": moment,
            },
            "root": {
                "x": 0.0,
                "y": 0.0,
                "dx": 0.0,
                "dy": 0.0,
                "rotation": math.degrees(root_turn),
                "reaction_x": -Rx,
                "reaction_y": -Ry,
                "reaction_moment": -M0,
            },
        }
        for req in requests:
            if req.level != level:
                continue
            if req.quantity == "strain_energy":
                values[req] = float(sol.strain_energy[level])
            elif req.quantity in table.get(req.point, {}):
                values[req] = float(table[req.point][req.quantity])
            else:
                raise NotApplicable(f"'{req.quantity}' at '{req.point}' is not an elastica output")
        shapes[level] = [np.asarray(line) for line in sol.beam_shapes[level].values()]
    for req in requests:
        values.setdefault(req, math.nan)  # the levels past the first that did not converge
    extensible = "inextensible" if built.mechanism.beams[0].EA is None else "extensible (EA of the section)"
    return MethodRun(
        values=values,
        converged=sol.converged,
        message=f"elastica mechanism: {sol.message}",
        level_converged=dict(enumerate(sol.level_converged)),
        extras={
            "shapes": shapes,
            "model": f"{extensible} elastica of a {case.segment.boundary} "
            "segment as a mechanism (elastica.mechanism), DOP853 shooting",
        },
    )
