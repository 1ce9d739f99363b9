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
"""
from __future__ import annotations

import math

import numpy as np

from elastica import mechanism as em
from validation.case.method_options import ElasticaOptions
from validation.methods.base import MethodRun, NotApplicable


def _bodies(mech):
    """node -> body name (GROUND for a fixed support), the movable rigid bodies (welded links), and
    the union-find root of each link."""
    released = {(j.node, m) for j in mech.joints for m in j.members}
    parent = {link.name: link.name for link in mech.links}

    def find(a):
        while parent[a] != a:
            a = parent[a]
        return a

    at: dict[str, list[str]] = {}
    for link in mech.links:
        for nd in link.nodes:
            at.setdefault(nd, []).append(link.name)
    for nd, names in at.items():
        kept = [n for n in names if (nd, n) not in released]
        for other in kept[1:]:
            parent[find(other)] = find(kept[0])
    fixed = {s.node for s in mech.supports if s.kind == "fixed"}
    grounded = {find(n) for nd in fixed for n in at.get(nd, []) if (nd, n) not in released}
    owner: dict[str, str] = {nd: em.GROUND for nd in fixed}
    groups: dict[str, list[str]] = {}
    for link in mech.links:
        root = find(link.name)
        body = em.GROUND if root in grounded else root
        for nd in link.nodes:
            if nd not in owner and (nd, link.name) not in released:
                owner[nd] = body
            if body != em.GROUND:
                groups.setdefault(body, [])
                if nd not in groups[body]:
                    groups[body].append(nd)
    return owner, [em.RigidBody(name, tuple(nodes)) for name, nodes in groups.items()], find


def model(case) -> tuple[em.Mechanism, dict[str, str]]:
    mech = case.mechanism
    for s in mech.supports:
        if s.kind in ("slider", "guided"):
            raise NotApplicable(f"a {s.kind} support at '{s.node}': not in the elastica mechanism model")
    if any(j.spring for j in mech.joints):
        raise NotApplicable("joint torsion springs: not in the elastica mechanism model")
    owner, bodies, find = _bodies(mech)
    body_names = {b.name for b in bodies}
    link_body = {l.name: (find(l.name) if find(l.name) in body_names else em.GROUND) for l in mech.links}
    nodes = {n.name: (n.x, n.y) for n in mech.nodes}
    beam_nodes = [nd for b in mech.beams for nd in (b.start, b.end)]
    beams = []
    for beam in mech.beams:
        EA, EI = beam.section.stiffness(beam.E or mech.E)
        if beam.section.kind == "inertia" and beam.section.A is None:
            EA = None
        ends = []
        for nd in (beam.start, beam.end):
            joint = next((j for j in mech.joints if j.node == nd and beam.name in j.members), None)
            pinned_support = any(s.node == nd and s.kind == "pinned" and s.member in (None, beam.name)
                                 for s in mech.supports)
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
            pins.append(em.BodyPin(link_body[other], link_body[links[0]], j.node))
    for s in mech.supports:
        if s.kind == "pinned":
            target = link_body.get(s.member) if s.member in link_body else owner.get(s.node)
            if target not in (None, em.GROUND):
                pins.append(em.BodyPin(target, em.GROUND, s.node))
    return em.Mechanism(nodes, beams, bodies, pins), {**owner, **{f"link:{k}": v for k, v in link_body.items()}}


def loads(case, owner: dict[str, str]) -> list:
    out = []
    for i, load in enumerate(case.loads):
        v = tuple(float(x) for x in load.levels())
        body = owner.get(f"link:{load.body}") if load.body else owner.get(load.point)
        if load.kind == "force" and load.toward is not None:
            raise NotApplicable(f"loads.{i}: a force toward a fixed point on a mechanism: the elastica "
                                "mechanism model (elastica.mechanism) has point forces of fixed direction "
                                "or turning with a body only; the line to the point is not one of its "
                                "conditions")
        if load.kind == "force":
            d = load.direction
            out.append(em.PointForce(load.point, tuple(x * d[0] for x in v), tuple(x * d[1] for x in v), load.follower))
        elif load.kind == "moment":
            if body in (None, em.GROUND):
                out.append(em.NodeCouple(load.point, v))
            else:
                out.append(em.BodyCouple(body, v))
        elif load.kind == "rotation":
            if body in (None, em.GROUND):
                raise NotApplicable(f"loads.{i}: a prescribed rotation of '{load.point}', on no rigid link")
            out.append(em.BodyRotation(body, tuple(math.radians(x) for x in v)))
        elif load.kind != "displacement":
            raise NotApplicable(f"loads.{i}: a {load.kind.replace('_', '-')} load along the beams of a mechanism: "
                                "the elastica mechanism model (elastica.mechanism) takes point forces, couples "
                                "and prescribed motions only")
        else:
            d = np.asarray(load.direction, float) / math.hypot(*load.direction)
            if abs(d[0]) > 1e-12 and abs(d[1]) > 1e-12:
                raise NotApplicable(f"loads.{i}: a prescribed displacement must be along x or along y")
            axis = "x" if abs(d[0]) > 0.5 else "y"
            out.append(em.NodeDisplacement(load.point, axis, tuple(x * (d[0] if axis == "x" else d[1]) for x in v)))
    return out


def _body_lines(mechanism, positions: dict) -> list[np.ndarray]:
    """The rigid bodies of one level as lines, each from its first node to each of its other nodes (a star,
    as the FEM draws its rigid links): the beams alone would leave the mechanism's coupler undrawn."""
    return [np.array([positions[body.nodes[0]], positions[node]], float)
            for body in mechanism.bodies for node in body.nodes[1:]]


def run_mechanism(case, requests, options: ElasticaOptions) -> MethodRun:
    mechanism, owner = model(case)
    tolerance = {} if options.rtol is None else {"rtol": options.rtol}    # else the solver's own
    try:
        sol = em.solve_mechanism(mechanism, loads(case, owner), case.n_levels(), **tolerance)
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
            point = p if q != "input_torque" else next((ld.point for ld in case.loads
                                                        if ld.kind in ("rotation", "moment")), None)
            if point is None:
                raise NotApplicable("input_torque needs a prescribed rotation or a moment (the input)")
            values[req] = _received(case, sol, drivers, point, lv, min(k, 2))
        elif q == "strain_energy":
            values[req] = sol.strain_energy[lv]
        else:
            raise NotApplicable(f"the elastica mechanism model gives no '{q}'")
    shapes = [[np.asarray(s) for s in level.values()] + _body_lines(mechanism, positions)
              for level, positions in zip(sol.beam_shapes, sol.positions)]
    return MethodRun(values=values, converged=sol.converged, message=f"elastica mechanism: {sol.message}",
                     level_converged=dict(enumerate(sol.level_converged)), extras={"shapes": shapes})


def _received(case, sol, drivers, point: str, level: int, k: int) -> float:
    total = 0.0
    for ld in case.loads:
        if ld.point != point:
            continue
        v = ld.levels()[level]
        if ld.kind == "force" and k < 2 and not ld.follower:
            total += v * ld.direction[k]
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
