"""Adapter: a case -> ``fem.Model`` -> the requested outputs, with the FEM's own error estimate.

Segments are built along +x from a fixed root (``root``) to the ``tip`` (an arc if initially curved).
The boundary type adds the tip constraints that no load or prescribed motion replaces:
fixed-guided holds the tip rotation unless a moment or rotation acts there; fixed-fixed holds
every tip DOF that is not loaded or prescribed; pinned-pinned pins both ends. Mechanisms map
node for node: beams become members, rigid links exact master-slave constraints, joints release
rotations (with their torsional springs), supports as given.

Options (``[methods.fem]``): ``elements`` per member (default 16), ``error_estimate`` (solve on n and
2n elements and report |u_2n - u_n|/3, the Richardson estimate of the O(h^2) error of u_2n),
``richardson`` (report the extrapolated value instead of u_2n), ``tol`` (refine until the estimate is
below it), ``inextensible_ratio`` (EA L^2/EI used when a section gives no area; default 1e6),
and for ``limit_load``: ``arc_length``, ``max_steps``.
"""
from __future__ import annotations

import math
import time

import numpy as np

from validation.methods.base import MethodRun, NotApplicable, Request

ROTATION_DOF = "rz"


def _section(fem, spec, E, length: float, options: dict):
    """A ``fem.Section`` from a schema section (E may be None for layers)."""
    if spec.kind == "layers":
        return fem.Section.layers([(l.E, l.width, l.thickness) for l in spec.layers])
    if spec.kind == "rectangle":
        return fem.Section.rectangle(E, spec.width, spec.thickness)
    EI = E * spec.I
    EA = E * spec.A if spec.A is not None else float(options.get("inextensible_ratio", 1e6)) * EI / length**2
    return fem.Section.from_EI(EA, EI, c=spec.c, E=E) if _accepts_E(fem) else fem.Section.from_EI(EA, EI, c=spec.c)


def _accepts_E(fem) -> bool:
    import inspect

    return "E" in inspect.signature(fem.Section.from_EI).parameters


def _segment_model(fem, case, elements: int, options: dict):
    seg = case.segment
    model = fem.Model()
    kappa = seg.initial_curvature()
    L = seg.length
    if kappa == 0.0:
        tip = (L, 0.0)
    else:
        if abs(kappa * L) >= 2 * math.pi:
            raise NotApplicable("an initially curved segment closing on itself")
        tip = (math.sin(kappa * L) / kappa, (1.0 - math.cos(kappa * L)) / kappa)
    model.add_node("root", 0.0, 0.0)
    model.add_node("tip", *tip)
    section = _section(fem, seg.section, seg.E, L, options)
    model.add_member("root", "tip", section, n_elements=elements, curvature=kappa, name="segment")
    model.add_support("root", "pinned" if seg.boundary == "pinned-pinned" else "fixed")
    acted = _add_loads(model, case, {"tip"})
    tip_kind = {"fixed-guided": ["rz"], "fixed-fixed": ["ux", "uy", "rz"], "pinned-pinned": ["ux", "uy"]}
    n = case.n_levels()
    for dof in tip_kind.get(seg.boundary, []):
        if dof not in acted:
            model.prescribe("tip", dof, np.zeros(n))
    return model


def _add_loads(model, case, allowed_points) -> set:
    """Add the case's loads; returns the tip DOFs they act on (for the boundary defaults)."""
    acted = set()
    for i, load in enumerate(case.loads):
        if load.point not in allowed_points:
            raise NotApplicable(f"loads.{i} acts on '{load.point}', which the FEM model holds fixed")
        values = np.asarray(load.levels(), float)
        if load.kind == "force":
            d = np.asarray(load.direction, float)
            model.add_force(load.point, values * d[0], values * d[1], follower=load.follower)
            acted |= {"ux", "uy"} if d[0] and d[1] else ({"ux"} if d[0] else {"uy"})
        elif load.kind == "moment":
            model.add_moment(load.point, values)
            acted.add("rz")
        elif load.kind == "rotation":
            model.prescribe(load.point, "rz", np.radians(values))
            acted.add("rz")
        else:  # displacement along an axis
            d = np.asarray(load.direction, float)
            d = d / np.hypot(*d)
            if abs(d[0]) > 1e-12 and abs(d[1]) > 1e-12:
                raise NotApplicable("a prescribed displacement must be along x or along y")
            dof = "ux" if abs(d[0]) > 0.5 else "uy"
            model.prescribe(load.point, dof, values * (d[0] if dof == "ux" else d[1]))
            acted.add(dof)
    return acted


def _mechanism_model(fem, case, elements: int, options: dict):
    mech = case.mechanism
    model = fem.Model()
    for node in mech.nodes:
        model.add_node(node.name, node.x, node.y)
    member_index = {}
    for beam in mech.beams:
        E = beam.E or mech.E
        a = next(n for n in mech.nodes if n.name == beam.start)
        b = next(n for n in mech.nodes if n.name == beam.end)
        length = math.hypot(b.x - a.x, b.y - a.y)
        member_index[beam.name] = model.add_member(beam.start, beam.end, _section(fem, beam.section, E, length,
                                                                                  options),
                                                   n_elements=elements, curvature=beam.curvature, name=beam.name)
    links = {link.name: link for link in mech.links}
    for link in mech.links:
        for node in link.nodes[1:]:
            model.add_rigid_link(link.nodes[0], node)
    for joint in mech.joints:
        beams = [member_index[m] for m in joint.members if m in member_index]
        if any(m in links for m in joint.members) and not beams:
            raise NotApplicable(f"the joint at '{joint.node}' joins rigid links only; "
                                "the FEM releases joints of flexible members")
        model.add_joint(joint.node, beams, k=joint.spring)
    for sup in mech.supports:
        model.add_support(sup.node, sup.kind, direction=sup.direction or (1.0, 0.0))
    _add_loads(model, case, {n.name for n in mech.nodes})
    return model


def build_model(case, elements: int, options: dict):
    import fem

    if case.segment is not None:
        return _segment_model(fem, case, elements, options)
    return _mechanism_model(fem, case, elements, options)


def _prescribed_dofs(case) -> dict[str, set]:
    out: dict[str, set] = {}
    for load in case.loads:
        if load.kind == "rotation":
            out.setdefault(load.point, set()).add("rz")
        elif load.kind == "displacement":
            out.setdefault(load.point, set()).add("ux" if abs(load.direction[0]) > abs(load.direction[1]) else "uy")
    return out


def _applied(case, point: str, level: int) -> np.ndarray:
    total = np.zeros(3)
    for load in case.loads:
        if load.point != point:
            continue
        v = load.levels()[level]
        if load.kind == "force" and not load.follower:
            total[:2] += v * np.asarray(load.direction, float)
        elif load.kind == "moment":
            total[2] += v
    return total


def _extract(case, result, requests: list[Request], origin: dict) -> dict[Request, float]:
    """Values of the requested outputs from a FemResult (angles in degrees)."""
    held = _prescribed_dofs(case)
    values = {}
    for req in requests:
        q, p, lv = req
        if q in ("x", "y", "dx", "dy"):
            x, y = result.position(p, lv)
            x0, y0 = origin[p]
            values[req] = {"x": x, "y": y, "dx": x - x0, "dy": y - y0}[q]
        elif q == "rotation":
            values[req] = math.degrees(result.rotation(p, lv))
        elif q in ("reaction_x", "reaction_y", "reaction_moment"):
            values[req] = float(result.reaction(p, lv)[("reaction_x", "reaction_y", "reaction_moment").index(q)])
        elif q in ("force_x", "force_y", "moment"):
            k = ("force_x", "force_y", "moment").index(q)
            dof = ("ux", "uy", "rz")[k]
            if dof in held.get(p, set()) or (case.segment is not None and p == "tip"
                                             and _tip_held(case, dof)):
                values[req] = float(result.reaction(p, lv)[k])  # the load needed to hold the motion
            else:
                values[req] = float(_applied(case, p, lv)[k])
        elif q == "strain_energy":
            values[req] = float(result.strain_energy[lv])
        elif q == "input_torque":
            values[req] = float(result.reaction(_input_node(case), lv)[2])
        elif q == "input_angle":
            values[req] = math.degrees(result.rotation(_input_node(case), lv))
    return values


def _tip_held(case, dof: str) -> bool:
    seg = case.segment
    acted = set()
    for load in case.loads:
        if load.point == "tip":
            if load.kind in ("moment", "rotation"):
                acted.add("rz")
            elif load.kind == "displacement":
                acted.add("ux" if abs(load.direction[0]) > abs(load.direction[1]) else "uy")
    default = {"fixed-guided": {"rz"}, "fixed-fixed": {"ux", "uy", "rz"}, "pinned-pinned": {"ux", "uy"}}
    return dof in (default.get(seg.boundary, set()) - acted) or dof in _prescribed_dofs(case).get("tip", set())


def _input_node(case) -> str:
    for load in case.loads:
        if load.kind in ("rotation", "moment"):
            return load.point
    raise NotApplicable("input_torque/input_angle need a prescribed rotation or a moment (the input)")


def _limit_load(fem, model, options: dict):
    res = fem.solve(model, control="arclength", max_limit_points=1,
                    arc_length=options.get("arc_length"), max_steps=int(options.get("max_steps", 2000)))
    limits = [c for c in res.critical_points if c.get("kind") == "limit"]
    if not limits:
        return math.nan, res, f"no limit point found ({res.message})"
    reference = max(abs(np.asarray(ld.values)[-1]).max() for ld in model.loads)
    return abs(limits[0]["load_factor"]) * reference, res, ""


def _solve_once(case, requests, options, elements: int):
    import fem

    model = build_model(case, elements, options)
    origin = {name: model.coords[i] for i, name in enumerate(model.node_names)}
    values, message, iterations = {}, "", 0
    limit_requests = [r for r in requests if r.quantity == "limit_load"]
    other = [r for r in requests if r.quantity != "limit_load"]
    result = None
    converged = True
    if other:
        result = fem.solve(model, n_levels=case.n_levels(), rtol=float(options.get("rtol", 1e-10)))
        iterations += result.iterations
        converged = result.converged
        message = result.message
        if result.converged:
            values.update(_extract(case, result, other, origin))
        else:
            done = result.n_levels  # levels reached before the failure are still reported
            values.update(_extract(case, result, [r for r in other if r.level < done], origin))
    if limit_requests:
        limit, res, why = _limit_load(fem, model, options)
        iterations += res.iterations
        if why:
            converged, message = False, why
        else:
            values.update({r: limit for r in limit_requests})
            message = message or res.message
            result = result or res
    return values, converged, message, iterations, result


def _shapes(result) -> list:
    """Per level, the deformed mesh as polylines (chains of consecutive elements)."""
    conn = np.asarray(result.connectivity)
    shapes = []
    for level in range(result.n_levels):
        pts = result.mesh_positions[level]
        lines, current = [], [conn[0, 0], conn[0, 1]] if len(conn) else []
        for a, b in conn[1:]:
            if a == current[-1]:
                current.append(b)
            else:
                lines.append(pts[current].copy())
                current = [a, b]
        if current:
            lines.append(pts[current].copy())
        shapes.append(lines)
    return shapes


def run(case, requests: list[Request], options: dict) -> MethodRun:
    start = time.perf_counter()
    elements = int(options.get("elements", 16))
    estimate = bool(options.get("error_estimate", False) or options.get("tol"))
    tol = options.get("tol")
    values, converged, message, iterations, result = _solve_once(case, requests, options, elements)
    errors = {}
    while estimate and converged:
        fine, ok, msg, its, fine_result = _solve_once(case, requests, options, 2 * elements)
        iterations += its
        if not ok:
            converged, message = False, f"refined mesh ({2 * elements} elements): {msg}"
            break
        errors = {r: abs(fine[r] - values[r]) / 3.0 for r in fine if r in values}
        if options.get("richardson"):
            fine = {r: fine[r] + (fine[r] - values[r]) / 3.0 for r in fine if r in values}
        values, result, elements = fine, fine_result, 2 * elements
        if tol is None or max(errors.values(), default=0.0) <= float(tol) or elements >= 1024:
            if tol is not None and max(errors.values(), default=0.0) > float(tol):
                converged, message = False, f"error estimate still above tol={tol} at {elements} elements"
            break
    extras = {"iterations": iterations, "elements": elements}
    if result is not None and getattr(result, "mesh_positions", None) is not None and result.n_levels:
        extras["shapes"] = _shapes(result)
        path = _continuation_path(case, result)
        if path:
            extras["path"] = path
    return MethodRun(values=values, converged=converged, message=message, error_estimate=errors,
                     wall_time=time.perf_counter() - start, extras=extras)


def _continuation_path(case, result):
    if result.control != "arclength":
        return None
    loads = [ld for ld in case.loads if ld.kind == "force"]
    if not loads:
        return None
    point = loads[0].point
    d = np.asarray(loads[0].direction, float)
    d = d / np.hypot(*d)
    disp = [(result.position(point, k) - np.asarray(result.mesh_positions_ref[result._node(point)])) @ d
            for k in range(result.n_levels)]
    reference = max(abs(np.asarray(ld.levels())).max() for ld in loads)
    limits = [(disp[c["step"]], c["load_factor"] * reference) for c in result.critical_points
              if c.get("kind") == "limit" and 0 <= c.get("step", -1) < len(disp)]
    return {"displacement": disp, "load": list(np.asarray(result.load_factor) * reference),
            "limit_points": limits, "displacement_label": f"displacement of {point} along the load",
            "load_label": "load"}
