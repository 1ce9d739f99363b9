"""Adapter: a case -> ``fem.Model`` -> the requested outputs, with the FEM's own error estimate.

Segments are built along +x from a fixed root (``root``) to the ``tip`` (an arc if initially curved).
The boundary type adds the tip constraints that no load or prescribed motion replaces:
fixed-guided holds the tip rotation unless a moment or rotation acts there; fixed-fixed holds
every tip DOF that is not loaded or prescribed; pinned-pinned pins both ends. Mechanisms map
node for node: beams become members, rigid links exact master-slave constraints, joints release
rotations (with their torsional springs), supports as given.

Options (``[methods.fem]``): ``elements`` per member (default 16), ``error_estimate`` (default true: solve
on n and 2n elements and report |u_2n - u_n|/3, the Richardson estimate of the O(h^2) error of u_2n),
``richardson`` (report the extrapolated value instead of u_2n), ``tol`` (refine until the estimate is
below it), ``inextensible_ratio`` (EA L^2/EI used when a section gives no area; default 1e6),
and for ``limit_load``: ``arc_length``, ``max_steps``; for ``mechanical_advantage``: ``ma`` (see
`fem_outputs`, which also gives ``max_stress`` and ``inflection_points`` from the finest mesh);
``zero_level``: positions (x, y, dx, dy) measured from the state of that level instead of the unloaded
one (an experiment zeroed its scale under a load already present, e.g. self-weight): x = X0 + x(level)
- x(zero_level).
"""
from __future__ import annotations

import math
import time

import numpy as np

from validation.methods import fem_outputs
from validation.methods.base import MethodRun, NotApplicable, Request

ROTATION_DOF = "rz"


def _section(fem, spec, E, length: float, options: dict):
    """A ``fem.Section`` from a schema section (E may be None for layers)."""
    if spec.kind == "layers" and spec.bonded:         # one section: (EA, EI) of the transformed stack
        return fem.Section.from_EI(*spec.stiffness(None))
    if spec.kind == "layers":
        return fem.Section.layers([(l.E, l.width, l.thickness) for l in spec.layers])
    if spec.kind == "rectangle":
        return fem.Section.rectangle(E, spec.width, spec.thickness)
    EI = E * spec.I
    EA = E * spec.A if spec.A is not None else float(options.get("inextensible_ratio", 1e6)) * EI / length**2
    return fem.Section.from_EI(EA, EI, c=spec.c, E=E)


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
    _add_loads(model, case, {"tip"})
    for dof in _boundary_held_tip(case):
        model.prescribe("tip", dof, np.zeros(case.n_levels()))
    _add_distributed(model, case, {None: (0, seg.section)})
    return model


def _add_distributed(model, case, beams: dict) -> None:
    """Distributed and self-weight loads; ``beams`` maps a beam name (None for a segment's only
    beam) to (member index, schema section). Self-weight is the weight per unit length of each beam's
    section along the gravity direction; rigid links carry none."""
    for load in case.loads:
        if load.kind not in ("distributed", "self_weight"):
            continue
        d = np.asarray(load.direction, float)
        values = np.asarray(load.levels(), float)
        if load.kind == "self_weight":
            d = d / np.hypot(*d)
        for name, (member, section) in beams.items():
            if load.member not in (None, name):
                continue
            scale = section.weight_per_length() if load.kind == "self_weight" else 1.0
            model.add_distributed(scale * values * d[0], scale * values * d[1], member=member,
                                  follower=load.follower)


TIP_HELD = {"fixed-guided": ("rz",), "fixed-fixed": ("ux", "uy", "rz"), "pinned-pinned": ("ux", "uy")}


def _load_dofs(load) -> set[str]:
    """The DOFs of its point that a load acts on or prescribes."""
    if load.kind in ("distributed", "self_weight"):
        return set()                       # along the beam, not at the point
    if load.toward is not None or load.follower:
        return {"ux", "uy"}                # the direction turns: both components
    if load.kind in ("moment", "rotation"):
        return {"rz"}
    d = load.direction
    if load.kind == "displacement":
        return {"ux" if abs(d[0]) > abs(d[1]) else "uy"}
    return {name for name, component in zip(("ux", "uy"), d) if component}


def _boundary_held_tip(case) -> list[str]:
    """Tip DOFs the segment's boundary type holds because no load acts on or prescribes them."""
    acted = set().union(*(_load_dofs(load) for load in case.loads if load.point == "tip"))
    return [dof for dof in TIP_HELD.get(case.segment.boundary, ()) if dof not in acted]


def _held_dofs(case) -> dict[str, set]:
    """DOFs whose reaction is the load needed to hold them: prescribed by a load, or held by the
    segment's boundary type."""
    held: dict[str, set] = {}
    for load in case.loads:
        if load.kind in ("displacement", "rotation"):
            held.setdefault(load.point, set()).update(_load_dofs(load))
    if case.segment is not None:
        held.setdefault("tip", set()).update(_boundary_held_tip(case))
    return held


def _add_loads(model, case, allowed_points, members: dict | None = None) -> None:
    """Add the case's point loads (distributed ones: `_add_distributed`).

    A moment with ``body`` naming a beam acts on that beam's end (one side of a hinge); on a rigid
    link, or without ``body``, it acts on the node's rotation. A follower force with ``body`` turns
    with that member's end rotation (a beam, or a link modelled as stiff bars), else with the node's.
    A force ``toward`` a fixed point pulls along the current line to it, turned by ``angle``."""
    for i, load in enumerate(case.loads):
        if load.kind in ("distributed", "self_weight"):
            continue
        if load.point not in allowed_points:
            raise NotApplicable(f"loads.{i} acts on '{load.point}', which the FEM model holds fixed")
        values = np.asarray(load.levels(), float)
        if load.kind == "force" and load.toward is not None:
            model.add_pointed_force(load.point, values, load.toward, angle=math.radians(load.angle))
        elif load.kind == "force":
            d = np.asarray(load.direction, float)
            member = (members or {}).get((load.body, load.point)) if load.body else None
            model.add_force(load.point, values * d[0], values * d[1], follower=load.follower,
                            member=member)
        elif load.kind == "moment":
            member = (members or {}).get(load.body) if load.body else None
            model.add_moment(load.point, values, member=member)
        elif load.kind == "rotation":
            model.prescribe(load.point, "rz", np.radians(values))
        else:  # displacement along an axis
            d = np.asarray(load.direction, float)
            d = d / np.hypot(*d)
            if abs(d[0]) > 1e-12 and abs(d[1]) > 1e-12:
                raise NotApplicable("a prescribed displacement must be along x or along y")
            dof = "ux" if abs(d[0]) > 0.5 else "uy"
            model.prescribe(load.point, dof, values * (d[0] if dof == "ux" else d[1]))


def _stiff_bar_links(mech) -> set[str]:
    """Rigid links joined by a revolute joint to another rigid link: modelled as stiff bars.

    Master-slave elimination cannot close a loop of rigid bodies (a node would be the slave of two
    links), so the smaller of two pinned rigid links becomes a flexible member whose EA and EI are
    ``rigid_ratio`` times the largest of the mechanism's beams (default 1e6): its strain is then
    about 1e-6 of the beams', below the discretisation error, while the tangent's condition number
    grows by the same factor, far inside double precision for the direct solvers used.
    """
    links = {link.name: link for link in mech.links}
    bars = set()
    for joint in mech.joints:
        pinned = [m for m in joint.members if m in links]
        if len(pinned) >= 2:
            pinned.sort(key=lambda name: (len(links[name].nodes), name))
            bars.update(pinned[:-1])
    return bars


def _mechanism_model(fem, case, elements: int, options: dict):
    mech = case.mechanism
    model = fem.Model()
    coords = {node.name: (node.x, node.y) for node in mech.nodes}
    for node in mech.nodes:
        model.add_node(node.name, node.x, node.y)
    member_index, stiffest = {}, (0.0, 0.0)
    for beam in mech.beams:
        E = beam.E or mech.E
        (ax, ay), (bx, by) = coords[beam.start], coords[beam.end]
        section = _section(fem, beam.section, E, math.hypot(bx - ax, by - ay), options)
        stiffest = (max(stiffest[0], section.EA), max(stiffest[1], section.EI))
        member_index[beam.name] = model.add_member(beam.start, beam.end, section, n_elements=elements,
                                                   curvature=beam.curvature, name=beam.name)
    bars = _stiff_bar_links(mech)
    ratio = float(options.get("rigid_ratio", 1e6))
    for link in mech.links:
        if link.name in bars:
            if not mech.beams:
                raise NotApplicable("pinned rigid links need at least one flexible beam to scale their stiffness")
            bar = fem.Section.from_EI(ratio * stiffest[0], ratio * stiffest[1])
            first = [model.add_member(link.nodes[0], node, bar, n_elements=1, name=f"{link.name}:{node}")
                     for node in link.nodes[1:]]
            member_index[link.name] = first[0]
            continue
        anchored = {sup.node for sup in mech.supports} | {ld.point for ld in case.loads
                                                           if ld.kind in ("displacement", "rotation")}
        master = next((n for n in link.nodes if n in anchored), link.nodes[0])  # supports and prescribed
        for node in link.nodes:                                                # motions sit on the master
            if node != master:
                model.add_rigid_link(master, node)
    ends = {}                                            # (body, node) -> the member ending there
    for name, index in member_index.items():
        if name in bars:
            link = next(l for l in mech.links if l.name == name)
            for k, node in enumerate(link.nodes[1:]):
                ends[(name, node)] = index + k
            ends[(name, link.nodes[0])] = index
        else:
            beam = next(b for b in mech.beams if b.name == name)
            ends[(name, beam.start)] = ends[(name, beam.end)] = index
    for joint in mech.joints:
        released = [member_index[m] for m in joint.members if m in member_index]
        if not released:
            raise NotApplicable(f"the joint at '{joint.node}' releases no flexible member or bar")
        model.add_joint(joint.node, released, k=joint.spring)
    for sup in mech.supports:
        model.add_support(sup.node, sup.kind, direction=sup.direction or (1.0, 0.0))
    _add_loads(model, case, set(coords), {b.name: member_index[b.name] for b in mech.beams} | ends)
    _add_distributed(model, case, {b.name: (member_index[b.name], b.section) for b in mech.beams})
    return model


def build_model(case, elements: int, options: dict):
    import fem

    if case.segment is not None:
        return _segment_model(fem, case, elements, options)
    return _mechanism_model(fem, case, elements, options)


def _applied(case, point: str, level: int) -> np.ndarray:
    total = np.zeros(3)
    for load in case.loads:
        if load.point != point:
            continue
        v = load.levels()[level]
        if load.kind == "force" and load.toward is not None:
            raise NotApplicable(f"the force at '{point}' pulls toward a fixed point: its components "
                                "depend on the solution")
        if load.kind == "force" and not load.follower:
            total[:2] += v * np.asarray(load.direction, float)
        elif load.kind == "moment":
            total[2] += v
    return total


class _Fields:
    """The nodal arrays ``_extract`` reads: a FemResult's, or its error estimates or extrapolations."""

    def __init__(self, names, positions, rotations, reactions, strain_energy):
        self.names, self.positions, self.rotations = list(names), positions, rotations
        self.reactions, self.strain_energy = reactions, strain_energy

    @classmethod
    def of(cls, result):
        return cls(result.node_names, result.positions, result.rotations, result.reactions, result.strain_energy)

    def position(self, node, level):
        return self.positions[level, self.names.index(node)]

    def rotation(self, node, level):
        return float(self.rotations[level, self.names.index(node)])

    def reaction(self, node, level):
        return self.reactions[level, self.names.index(node)]


def _extract(case, fields: _Fields, requests: list[Request], origin: dict | None) -> dict[Request, float]:
    """Values of the requested outputs (angles in degrees). With ``origin=None`` the fields are error
    estimates: displacements then carry the position error and applied loads have none."""
    held = _held_dofs(case)
    values = {}
    for req in requests:
        q, p, lv = req
        if q in ("x", "y", "dx", "dy"):
            x, y = fields.position(p, lv)
            x0, y0 = origin[p] if origin is not None else (0.0, 0.0)
            values[req] = float({"x": x, "y": y, "dx": x - x0, "dy": y - y0}[q])
        elif q == "rotation":
            values[req] = math.degrees(fields.rotation(p, lv))
        elif q in ("reaction_x", "reaction_y", "reaction_moment"):
            values[req] = float(fields.reaction(p, lv)[("reaction_x", "reaction_y", "reaction_moment").index(q)])
        elif q in ("force_x", "force_y", "moment"):
            k = ("force_x", "force_y", "moment").index(q)
            dof = ("ux", "uy", "rz")[k]
            if dof in held.get(p, set()):
                values[req] = float(fields.reaction(p, lv)[k])  # the load needed to hold the motion
            else:
                values[req] = float(_applied(case, p, lv)[k]) if origin is not None else 0.0
        elif q == "strain_energy":
            values[req] = float(fields.strain_energy[lv])
        elif q == "input_torque":
            values[req] = float(fields.reaction(_input_node(case), lv)[2])
        elif q == "input_angle":
            values[req] = math.degrees(fields.rotation(_input_node(case), lv))
    return values


def _input_node(case) -> str:
    for load in case.loads:
        if load.kind in ("rotation", "moment"):
            return load.point
    raise NotApplicable("input_torque/input_angle need a prescribed rotation or a moment (the input)")


def _limit_load(fem, case, model, options: dict):
    """Load at the first limit point: by arc length (default) or by displacement control of the
    loaded point along the load (``limit_control = "displacement"``, step ``control_step``)."""
    if not model.loads:
        raise NotApplicable("limit_load scales the point loads; this case has none (distributed loads only)")
    reference = max(abs(np.asarray(ld.values)[-1]).max() for ld in model.loads)
    if options.get("limit_control", "arclength") == "displacement":
        load = max((ld for ld in case.loads if ld.kind == "force"), key=lambda ld: max(map(abs, ld.levels())))
        d = np.asarray(load.direction, float)
        dof = "ux" if abs(d[0]) > abs(d[1]) else "uy"
        sign = math.copysign(1.0, d[0] if dof == "ux" else d[1])
        step = float(options.get("control_step", 0.005 * model.characteristic_length()))
        n = int(options.get("max_steps", 400))
        res = fem.solve(model, control="displacement", control_dof=(load.point, dof),
                        targets=sign * step * np.arange(1, n + 1))
        lam = np.asarray(res.load_factor)
        peaks = [i for i in range(1, len(lam) - 1) if lam[i] >= lam[i - 1] and lam[i] > lam[i + 1]]
        if not peaks:
            return math.nan, res, f"no limit point within {len(lam)} displacement steps ({res.message})"
        i = peaks[0]
        y0, y1, y2 = lam[i - 1:i + 2]
        curvature = y0 - 2 * y1 + y2
        peak = y1 - (y0 - y2) ** 2 / (8 * curvature) if curvature else y1  # parabola through the peak
        return abs(peak) * reference, res, ""
    res = fem.solve(model, control="arclength", max_limit_points=1,
                    arc_length=options.get("arc_length"), max_steps=int(options.get("max_steps", 2000)))
    limits = [c for c in res.critical_points if c.get("kind") == "limit"]
    if not limits:
        return math.nan, res, f"no limit point found ({res.message})"
    return abs(limits[0]["load_factor"]) * reference, res, ""


def _solve_levels(fem, case, model, requests, options: dict):
    """Load-controlled solve of the requested outputs, with the Richardson estimate if asked."""
    origin = {name: model.coords[i] for i, name in enumerate(model.node_names)}
    kwargs = dict(n_levels=case.n_levels(), rtol=float(options.get("rtol", 1e-10)))
    if not (options.get("error_estimate", True) or options.get("tol")):
        result = fem.solve(model, **kwargs)
        done = [r for r in requests if r.level < result.n_levels]
        return (_extract(case, _Fields.of(result), done, origin), {}, result, result.converged,
                result.message, result.iterations)
    tol = options.get("tol")
    est = fem.solve_with_error_estimate(model, tol=float(tol) if tol else None,
                                        levels=int(options.get("levels", 2)), **kwargs)
    result = est.result
    iterations = sum(r.iterations for r in est.results)
    if not est.error:  # a mesh failed: report what the finest mesh reached
        done = [r for r in requests if r.level < result.n_levels]
        return _extract(case, _Fields.of(result), done, origin), {}, result, False, est.message, iterations
    richardson = bool(options.get("richardson"))
    source = est.extrapolated if richardson else {"positions": result.positions, "rotations": result.rotations,
                                                  "reactions": result.reactions,
                                                  "strain_energy": result.strain_energy}
    errors = est.extrapolated_error if (richardson and est.extrapolated_error) else est.error
    fields = [_Fields(result.node_names, f["positions"], f["rotations"], f["reactions"], f["strain_energy"])
              for f in (source, errors)]
    values = _extract(case, fields[0], requests, origin)
    errs = {r: abs(v) for r, v in _extract(case, fields[1], requests, None).items()}
    return values, errs, result, est.converged, est.message, iterations


def _critical_note(result) -> str:
    found = [c for c in result.critical_points if c.get("kind") == "bifurcation"]
    if not found or result.control == "arclength":
        return ""
    c = found[0]
    return (f"; warning: det K changed sign at load factor {c['load_factor']:.4g} ({c.get('kind_detail', '')}):"
            " states beyond it may lie on an unstable branch")


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
    import fem

    start = time.perf_counter()
    elements = int(options.get("elements", 16))
    model = build_model(case, elements, options)
    values, errors, iterations, converged, messages, result = {}, {}, 0, True, [], None
    zero = options.get("zero_level")
    if zero is not None:
        if not 0 <= int(zero) < case.n_levels():
            raise NotApplicable(f"zero_level = {zero}: the case has {case.n_levels()} load levels")
        shifted = [r for r in requests if r.quantity in ZEROED]
        requests = list(dict.fromkeys(requests + [Request(r.quantity, r.point, int(zero)) for r in shifted]))
    dof = [r for r in requests if r.quantity == "dof"]
    if dof:
        count, note = _soft_mode_count(case, model, options)
        values.update({r: float(count) for r in dof})
        messages.append(note)
        requests = [r for r in requests if r.quantity != "dof"]
    ordinary = [r for r in requests if r.quantity != "limit_load" and r.quantity not in BEAM_OUTPUTS]
    beam_outputs = [r for r in requests if r.quantity in BEAM_OUTPUTS]
    limit = [r for r in requests if r.quantity == "limit_load"]
    if ordinary or beam_outputs:
        vals, errs, result, ok, msg, its = _solve_levels(fem, case, model, ordinary, options)
        values.update(vals)
        errors.update(errs)
        iterations += its
        converged &= ok
        messages.append(msg + _critical_note(result))
        values.update(_beam_outputs(fem, case, model, result, beam_outputs, elements, options))
    if limit:
        value, res, why = _limit_load(fem, case, model, options)
        iterations += res.iterations
        if why:
            converged = False
            messages.append(why)
        else:
            if options.get("error_estimate", True):  # Richardson on the limit load itself (O(h^2))
                fine, res_fine, why_fine = _limit_load(fem, case, build_model(case, 2 * elements, options), options)
                iterations += res_fine.iterations
                if not why_fine:
                    errors.update({r: abs(fine - value) / 3.0 for r in limit})
                    value = fine + (fine - value) / 3.0 if options.get("richardson") else fine
            values.update({r: value for r in limit})
            messages.append(f"limit load by {options.get('limit_control', 'arclength')}: {res.message}")
        result = result or res
    if zero is not None:
        at_zero = {r: values.get(Request(r.quantity, r.point, int(zero))) for r in shifted}
        origin = {name: model.coords[i] for i, name in enumerate(model.node_names)}
        for r in shifted:
            if r in values and at_zero[r] is not None:
                unloaded = {"x": origin[r.point][0], "y": origin[r.point][1]}.get(r.quantity, 0.0)
                values[r] = values[r] - at_zero[r] + unloaded
    extras = {"iterations": iterations, "elements": elements,
              "rejected_iterations": getattr(result, "rejected_iterations", 0)}
    if result is not None and result.n_levels:
        extras["shapes"] = _shapes(result)
        path = _continuation_path(case, result)
        if path:
            extras["path"] = path
    return MethodRun(values=values, converged=converged, message="; ".join(m for m in messages if m),
                     error_estimate=errors, wall_time=time.perf_counter() - start, extras=extras)


BEAM_OUTPUTS = ("max_stress", "inflection_points", "mechanical_advantage")
ZEROED = ("x", "y", "dx", "dy")


def _soft_mode_count(case, model, options: dict) -> tuple[int, str]:
    """dof: soft modes of the unloaded tangent condensed to the actuation points (``fem.soft_modes``),
    ``[methods.fem] dof = {points = [...], ratio = 1e-2}``; the stretching reference is the largest
    EA/l of the case's beams."""
    from fem.soft_modes import soft_modes

    spec = options.get("dof") or {}
    points = spec.get("points")
    if not points or case.mechanism is None:
        raise NotApplicable("dof by the FEM needs a mechanism and [methods.fem] dof = {points = [...]}")
    ratio = float(spec.get("ratio", 1e-2))
    reference = max(m.section.EA / math.dist(model.coords[m.start], model.coords[m.end])
                    for m in model.members if ":" not in m.name)
    found = soft_modes(model, [(p, d) for p in points for d in ("ux", "uy", "rz")], ratio=ratio,
                       reference_stiffness=reference)
    return found.count, (f"dof: {found.count} soft mode(s) of the tangent condensed to {', '.join(points)}, "
                         f"k/k_ref = {', '.join(f'{r:.2e}' for r in found.ratios)}, threshold {ratio:g}")


def _beam_outputs(fem, case, model, result, requests, elements: int, options: dict) -> dict:
    """max_stress and inflection_points of the finest mesh; mechanical_advantage by an increment
    of the input load (`fem_outputs`)."""
    values = {}
    beams = [i for i, m in enumerate(model.members) if ":" not in m.name]    # stiff bars are 'link:node'
    ma = None
    for req in requests:
        if req.level >= result.n_levels:
            continue
        if req.quantity == "max_stress":
            values[req] = fem_outputs.max_stress(result, req.level)
        elif req.quantity == "inflection_points":
            values[req] = float(fem_outputs.inflection_points(result, model, beams, req.level))
        else:
            if ma is None and fem_outputs.definition(options) == "secant":
                load = case.loads[fem_outputs.input_load_index(case, options)]
                ma = fem_outputs.secant_mechanical_advantage(
                    options, fem_outputs.output_force(case, options, result.reaction), load)
            elif ma is None:
                raised_case, delta, load = fem_outputs.incremented_case(case, options)
                solves = [fem.solve(m, n_levels=case.n_levels(), rtol=float(options.get("rtol", 1e-10)))
                          for m in (model, build_model(raised_case, elements, options))]
                if not all(r.converged for r in solves):
                    raise NotApplicable("mechanical_advantage: a solve of the increment did not converge: "
                                        + "; ".join(r.message for r in solves))
                forces = [fem_outputs.output_force(case, options, r.reaction) for r in solves]
                ma = fem_outputs.mechanical_advantage(case, options, forces[0], forces[1], delta, load)
            if np.isfinite(ma[req.level]):                      # secant: undefined without input load
                values[req] = float(ma[req.level])
    return values


def _continuation_path(case, result):
    if result.control == "load":
        return None
    loads = [ld for ld in case.loads if ld.kind == "force" and ld.direction is not None]
    if not loads:
        return None
    point = loads[0].point
    d = np.asarray(loads[0].direction, float)
    d = d / np.hypot(*d)
    disp = [float((result.position(point, k) - result.mesh_positions_ref[result._node(point)]) @ d)
            for k in range(result.n_levels)]
    reference = max(abs(np.asarray(ld.levels())).max() for ld in loads)
    load = list(np.asarray(result.load_factor) * reference)
    limits = [(disp[c["step"]], c["load_factor"] * reference) for c in result.critical_points
              if c.get("kind") == "limit" and 0 <= c.get("step", -1) < len(disp)]
    if result.control == "displacement" and not limits:
        limits = [(disp[i], load[i]) for i in range(1, len(load) - 1) if load[i - 1] <= load[i] > load[i + 1]][:1]
    return {"displacement": disp, "load": load, "limit_points": limits,
            "displacement_label": f"displacement of {point} along the load [{case.unit('length')}]",
            "load_label": f"load [{case.unit('force')}]"}
