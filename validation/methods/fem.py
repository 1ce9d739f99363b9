"""Adapter: a case -> ``fem.Model`` -> the requested outputs, with the FEM's own error estimate.

Segments are built along +x from a fixed root (``root``) to the ``tip`` (an arc if initially curved).
The boundary type adds the tip constraints that no load or prescribed motion replaces:
fixed-guided holds the tip rotation unless a moment or rotation acts there; fixed-fixed holds
every tip DOF that is not loaded or prescribed; pinned-pinned pins both ends. Mechanisms map
node for node: beams become members, rigid links exact master-slave constraints, joints release
rotations (with their torsional springs), supports as given.

Options (``[methods.fem]``, ``method_options.FemOptions``, which holds their defaults): ``elements`` per
member, ``error_estimate`` (solve on n and 2n elements and report |u_2n - u_n|/3, the Richardson estimate of the O(h^2) error of u_2n,
after checking on a third mesh that the outputs asked for are in the asymptotic range, the meshes
doubled up to ``max_refine`` x elements until they are; a value still outside keeps its estimate, marked
in ``MethodRun.unreliable_estimate``: `fem.error_estimate`; the two-mesh estimates of ``limit_load``, of
the inverse problem's tip loads and of an ``input_moment_at`` torque are not judged), ``richardson``
(report the extrapolated value instead of u_2n), ``tol`` (refine until the estimate is below it),
``inextensible_ratio`` (EA L^2/EI used when a section gives no area),
and for ``limit_load``: ``arc_length``, ``max_steps``; for ``mechanical_advantage``: ``ma`` (see
`fem_outputs`, which also gives ``max_stress`` and ``inflection_points`` from the finest mesh);
``zero_level``: positions (x, y, dx, dy) measured from the state of that level instead of the unloaded
one (an experiment zeroed its scale under a load already present, e.g. self-weight): x = X0 + x(level)
- x(zero_level). ``slfp = {length, E, thickness_ratio}``: build every
sprung joint of a mechanism as a small-length flexural pivot of that length (``validation.methods.slfp``).
``input_moment_at = "<node>"``: the case's one prescribed displacement (e.g. a slider position) is not
imposed but reached by a moment at that node, found by an outer solve; the moment is ``input_torque``.

Inverse tip problem (option table ``inverse``, see ``validation.methods.inverse_problem``): per level a
clamped segment whose tip has y = ``b`` and absolute slope ``theta0_deg`` prescribed (displacement
control), and x prescribed (``a``), loaded by a fixed axial load (``axial_load``), or carrying the
tied load F_x = -n F_y (``n``) or the F_x that puts a zero bending moment at arc length ``l1``
(a mesh node is placed there), both found by the outer secant solve of ``fem.solve_tip_inverse``.
Each level is its own problem, solved from the unloaded segment; the tip loads (``force_x``,
``force_y``, ``moment``) are those of the inverse problem, on n and 2n elements per member with
the Richardson estimate |F_2n - F_n|/3 (unless ``error_estimate = false``; n and extrapolation from
``inverse.elements``/``inverse.richardson``, else the method's; with extrapolation the estimate stays
|F_2n - F_n|/3, the error of F_2n, a conservative bound for the extrapolated value); with
``inverse.tip_x = true`` the tip's ``x`` is that of the inverse solution too (same estimate); every
other output comes from the forward solve under the case's loads.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

import fem
from fem.critical import refine_extremum
from fem.soft_modes import soft_modes
from validation.methods.inverse_problem import (
    LOAD_OUTPUTS,
    POSITION_OUTPUT,
    InverseLevel,
    InverseSpec,
    Tie,
    inverse_spec,
    merge_runs,
)
from validation.methods import fem_outputs
from validation.methods.base import DeferredList, MethodRun, NotApplicable, Request
from validation.case.method_options import FemInverseOptions, FemOptions
from validation.case.quantities import boundary_held_tip as _boundary_held_tip
from validation.case.quantities import load_dofs as _load_dofs
from validation.methods.slfp import with_flexures

ROTATION_DOF = "rz"
LIMIT_STEPS = {"displacement": 400, "arclength": 2000}  # limit load: continuation steps without max_steps


def _section(fem, spec, E, length: float, options: FemOptions):
    """A ``fem.Section`` from a schema section (E may be None for layers)."""
    if spec.kind == "layers" and spec.bonded:  # one section: (EA, EI) of the transformed stack
        return fem.Section.from_EI(*spec.stiffness(None))
    if spec.kind == "layers":
        return fem.Section.layers([(l.E, l.width, l.thickness) for l in spec.layers])
    if spec.kind == "rectangle":
        return fem.Section.rectangle(E, spec.width, spec.thickness)
    EI = E * spec.I
    EA = E * spec.A if spec.A is not None else options.inextensible_ratio * EI / length**2
    return fem.Section.from_EI(EA, EI, c=spec.c, E=E)


def _segment_model(fem, case, elements: int, options: FemOptions):
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
            model.add_distributed(scale * values * d[0], scale * values * d[1], member=member, follower=load.follower)


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
            model.add_force(load.point, values * d[0], values * d[1], follower=load.follower, member=member)
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


def _stiff_bar_links(mech, anchored: set[str]) -> set[str]:
    """Rigid links modelled as stiff bars: the smaller of two rigid links joined by a revolute joint, and a
    link with two or more ``anchored`` nodes (held by a support or driven by a prescribed motion).

    Master-slave elimination cannot close a loop of rigid bodies (a node would be the slave of two
    links), nor prescribe a motion of a slave node (its motion is a function of the master's), so such a
    link becomes flexible members whose EA and EI are ``rigid_ratio`` times the largest of the mechanism's
    beams (default 1e6): its strain is then about 1e-6 of the beams', below the discretisation error,
    while the tangent's condition number grows by the same factor, far inside double precision for the
    direct solvers used.
    """
    links = {link.name: link for link in mech.links}
    bars = {link.name for link in mech.links if sum(nd in anchored for nd in link.nodes) >= 2}
    for joint in mech.joints:
        pinned = [m for m in joint.members if m in links]
        if len(pinned) >= 2:
            pinned.sort(key=lambda name: (len(links[name].nodes), name))
            bars.update(pinned[:-1])
    return bars


def _mechanism_model(fem, case, elements: int, options: FemOptions):
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
        member_index[beam.name] = model.add_member(
            beam.start, beam.end, section, n_elements=elements, curvature=beam.curvature, name=beam.name
        )
    anchored = {sup.node for sup in mech.supports} | {
        ld.point for ld in case.loads if ld.kind in ("displacement", "rotation")
    }
    bars = _stiff_bar_links(mech, anchored)
    ratio = options.rigid_ratio
    for link in mech.links:
        if link.name in bars:
            if not mech.beams:
                raise NotApplicable(
                    f"rigid link '{link.name}' is modelled as a stiff bar (pinned to another link, or "
                    "held at two points), which needs a flexible beam to scale its stiffness"
                )
            bar = fem.Section.from_EI(ratio * stiffest[0], ratio * stiffest[1])
            # one element, on every mesh of the error estimate too: a straight bar 1e6 times stiffer than
            # the beams stands for a rigid body, with no discretisation error of its own to estimate
            first = [
                model.add_member(link.nodes[0], node, bar, n_elements=1, name=f"{link.name}:{node}", refined=False)
                for node in link.nodes[1:]
            ]
            member_index[link.name] = first[0]
            continue
        master = next((n for n in link.nodes if n in anchored), link.nodes[0])  # supports and prescribed
        for node in link.nodes:
            if node != master:
                model.add_rigid_link(master, node)
    ends = {}  # (body, node) -> the member ending there
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


def build_model(case, elements: int, options: FemOptions):
    if case.segment is not None:
        return _segment_model(fem, case, elements, options)
    return _mechanism_model(fem, case, elements, options)


def _applied(case, point: str, level: int, rotation: float = 0.0) -> np.ndarray:
    """Applied (Fx, Fy, M) at a point; a follower force turned with the point's ``rotation`` (rad)."""
    total = np.zeros(3)
    c, s = math.cos(rotation), math.sin(rotation)
    for load in case.loads:
        if load.point != point:
            continue
        v = load.levels()[level]
        if load.kind == "force" and load.toward is not None:
            raise NotApplicable(
                f"the force at '{point}' pulls toward a fixed point: its components depend on the solution"
            )
        if load.kind == "force":
            fx, fy = v * np.asarray(load.direction, float)
            total[:2] += (c * fx - s * fy, s * fx + c * fy) if load.follower else (fx, fy)
        elif load.kind == "moment":
            total[2] += v
    return total


class _Fields:
    """The nodal arrays ``_extract`` reads, by name from ``fields``: a FemResult's (`of`), or its error
    estimates or extrapolations (`fem.ErrorEstimate`'s mappings). Reactions and energy are read only for
    a request that asks for them (the result and the estimates compute them then)."""

    def __init__(self, names, fields):
        self.names, self.fields = list(names), fields
        self.positions, self.rotations = fields["positions"], fields["rotations"]

    @classmethod
    def of(cls, result):
        return cls(result.node_names, _ResultFields(result))

    @property
    def reactions(self) -> np.ndarray:
        return self.fields["reactions"]

    @property
    def strain_energy(self) -> np.ndarray:
        return self.fields["strain_energy"]

    def position(self, node, level):
        return self.positions[level, self.names.index(node)]

    def rotation(self, node, level):
        return float(self.rotations[level, self.names.index(node)])

    def reaction(self, node, level):
        return self.reactions[level, self.names.index(node)]


class _ResultFields:
    """A FemResult's fields by name (positions, rotations, reactions, strain_energy), as the error
    estimate's mappings give theirs."""

    def __init__(self, result):
        self._result = result

    def __getitem__(self, name):
        return getattr(self._result, name)


def _extract(case, fields: _Fields, requests: list[Request], origin: dict | None) -> dict[Request, float]:
    """Values of the requested outputs (angles in degrees). With ``origin=None`` the fields are error
    estimates: displacements then carry the position error and applied loads have none."""
    held = _held_dofs(case)
    values = {}
    for req in requests:
        q, p, lv = req
        if q in ("x", "y", "dx", "dy"):
            axis = 0 if q in ("x", "dx") else 1
            value = float(fields.position(p, lv)[axis])
            if q in ("dx", "dy") and origin is not None:
                value -= origin[p][axis]  # the same float64 difference
            values[req] = value
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
                values[req] = float(_applied(case, p, lv, fields.rotation(p, lv))[k]) if origin is not None else 0.0
        elif q == "strain_energy":
            values[req] = float(fields.strain_energy[lv])
        elif q == "input_torque":  # the torque holding a prescribed input rotation, else the applied one
            node = _input_node(case)
            if "rz" in held.get(node, set()):
                values[req] = float(fields.reaction(node, lv)[2])
            else:
                values[req] = float(_applied(case, node, lv)[2]) if origin is not None else 0.0
        elif q == "input_angle":
            values[req] = math.degrees(fields.rotation(_input_node(case), lv))
    return values


def _input_node(case) -> str:
    for load in case.loads:
        if load.kind in ("rotation", "moment"):
            return load.point
    raise NotApplicable("input_torque/input_angle need a prescribed rotation or a moment (the input)")


def _limit_load(fem, case, model, options: FemOptions):
    """Load at the first limit point: by arc length (default) or by displacement control of the
    loaded point along the load (``limit_control = "displacement"``, step ``control_step``)."""
    if not model.loads:
        raise NotApplicable("limit_load scales the point loads; this case has none (distributed loads only)")
    reference = max(abs(np.asarray(ld.values)[-1]).max() for ld in model.loads)
    if options.limit_control == "displacement":
        load = max((ld for ld in case.loads if ld.kind == "force"), key=lambda ld: max(map(abs, ld.levels())))
        d = np.asarray(load.direction, float)
        dof = "ux" if abs(d[0]) > abs(d[1]) else "uy"
        sign = math.copysign(1.0, d[0] if dof == "ux" else d[1])
        step = options.control_step or 0.005 * model.characteristic_length()
        n = options.max_steps or LIMIT_STEPS["displacement"]
        res = fem.solve(
            model, control="displacement", control_dof=(load.point, dof), targets=sign * step * np.arange(1, n + 1)
        )
        lam = np.asarray(res.load_factor)
        peaks = [i for i in range(1, len(lam) - 1) if lam[i] >= lam[i - 1] and lam[i] > lam[i + 1]]
        if not peaks:
            return math.nan, res, f"no limit point within {len(lam)} displacement steps ({res.message})"
        i = peaks[0]
        peak, _ = refine_extremum(np.arange(-1.0, 2.0), lam[i - 1 : i + 2], np.full(3, np.nan))  # parabola
        return abs(peak) * reference, res, ""
    res = fem.solve(
        model,
        control="arclength",
        max_limit_points=1,
        arc_length=options.arc_length,
        max_steps=options.max_steps or LIMIT_STEPS["arclength"],
    )
    limits = [c for c in res.critical_points if c.kind == "limit"]
    if not limits:
        return math.nan, res, f"no limit point found ({res.message})"
    return abs(limits[0].load_factor) * reference, res, ""


@dataclass
class _Levels:
    """What the load-controlled solve gave: the values, their estimates, the values whose estimate is
    unreliable (with why), the finest result and the refine of its mesh over ``elements`` (1 without an
    estimate), and how the solve went."""

    values: dict[Request, float]
    errors: dict[Request, float]
    unreliable: dict[Request, str]
    result: Any  # fem.SolveResult (the fem module is imported where the method runs)
    refine: int
    converged: bool
    message: str
    iterations: int
    analysis: float


def _solve_levels(fem, case, model, requests, options: FemOptions) -> _Levels:
    """Load-controlled solve of the requested outputs, with the Richardson estimate if asked."""
    origin = {name: model.coords[i] for i, name in enumerate(model.node_names)}
    kwargs = dict(n_levels=case.n_levels(), rtol=options.rtol)
    if not (options.error_estimate or options.tol):
        result = fem.solve(model, **kwargs)
        done = [r for r in requests if r.level < result.n_levels]
        return _Levels(
            _extract(case, _Fields.of(result), done, origin),
            {},
            {},
            result,
            1,
            result.converged,
            result.message,
            result.iterations,
            result.analysis_time,
        )
    est = fem.solve_with_error_estimate(
        model,
        tol=options.tol,
        levels=options.levels,
        max_refine=options.max_refine,
        check=fem.AsymptoticCheck(fields=_estimated_fields(case, requests)),
        **kwargs,
    )
    result = est.result
    iterations = sum(r.iterations for r in est.results)
    analysis = sum(r.analysis_time for r in est.results)
    if not est.error:  # a mesh failed: report what the finest mesh reached
        done = [r for r in requests if r.level < result.n_levels]
        return _Levels(
            _extract(case, _Fields.of(result), done, origin),
            {},
            {},
            result,
            est.refine,
            False,
            est.message,
            iterations,
            analysis,
        )
    richardson = options.richardson
    source = est.extrapolated if richardson else _ResultFields(result)
    errors = est.extrapolated_error if (richardson and est.extrapolated_error) else est.error
    fields = [_Fields(result.node_names, f) for f in (source, errors, _Flags(est.unreliable))]
    values = _extract(case, fields[0], requests, origin)
    errs = {r: abs(v) for r, v in _extract(case, fields[1], requests, None).items()}
    flagged = [r for r, flag in _extract(case, fields[2], requests, None).items() if flag]
    unreliable = {
        r: (
            f"the FEM's error estimate is unreliable: its meshes (up to refine={est.refine} x "
            f"{_mesh_words(model)}) are not in the asymptotic range for this value (observed order "
            f"outside 2 +- {est.check.band:g})"
        )
        for r in flagged
    }
    return _Levels(values, errs, unreliable, result, est.refine, est.converged, est.message, iterations, analysis)


def _mesh_words(model) -> str:
    """'16 elements per member' (the model's counts; several when its members differ)."""
    counts = sorted({m.n_elements for m in model.members if m.refined})
    return f"{'/'.join(map(str, counts)) or 'the'} elements per member"


class _Flags(dict):
    """The error estimate's ``unreliable`` masks as the numbers ``_extract`` reads (1.0: unreliable)."""

    def __init__(self, masks):
        super().__init__()
        self._masks = masks

    def __missing__(self, name):
        self[name] = np.asarray(self._masks[name], float)
        return self[name]


def _estimated_fields(case, requests) -> tuple:
    """The FEM result fields whose error estimates the requests read (`_extract`): judged for the
    asymptotic range and refined for."""
    held = _held_dofs(case)
    fields = set()
    for q, p, _ in requests:
        if q in ("x", "y", "dx", "dy"):
            fields.add("positions")
        elif q in ("rotation", "input_angle"):
            fields.add("rotations")
        elif q in ("reaction_x", "reaction_y", "reaction_moment"):
            fields.add("reactions")
        elif q in ("force_x", "force_y", "moment"):
            if ("ux", "uy", "rz")[("force_x", "force_y", "moment").index(q)] in held.get(p, set()):
                fields.add("reactions")
        elif q == "input_torque":
            if "rz" in held.get(_input_node(case), set()):
                fields.add("reactions")
        elif q == "strain_energy":
            fields.add("strain_energy")
    return tuple(f for f in ("positions", "rotations", "reactions", "strain_energy") if f in fields)


def _critical_note(result) -> str:
    found = [c for c in result.critical_points if c.kind == "bifurcation"]
    if not found or result.control == "arclength":
        return ""
    c = found[0]
    return (
        f"; warning: det K changed sign at load factor {c.load_factor:.4g} ({c.detail}):"
        " states beyond it may lie on an unstable branch"
    )


def _shapes(result) -> list:
    """Per level, the deformed mesh as polylines (chains of consecutive elements), then each rigid link
    as a line from its master node to its slave (a rigid body drawn as a star from its master)."""
    conn = np.asarray(result.connectivity)
    chains, current = [], [conn[0, 0], conn[0, 1]] if len(conn) else []
    for a, b in conn[1:].tolist():
        if a == current[-1]:
            current.append(b)
        else:
            chains.append(np.array(current))
            current = [a, b]
    if current:
        chains.append(np.array(current))
    chains += list(result.rigid_links())
    return [[pts[chain] for chain in chains] for pts in result.mesh_positions[: result.n_levels]]


def _as_is(value):
    return value


class _DeferredFields:
    """A result's `fem.result.FieldSeries`, built when an attribute is first read; pickles as the
    FieldSeries itself."""

    def __init__(self, result):
        self._result, self._series = result, None

    def _built(self):
        if self._series is None:
            self._series, self._result = self._result.field_series(), None
        return self._series

    def __getattr__(self, name):
        if name.startswith("__") or name in ("_result", "_series"):
            raise AttributeError(name)
        return getattr(self._built(), name)

    def __reduce__(self):
        return _as_is, (self._built(),)


def _arc_point(kappa: float, s: float) -> tuple[float, float]:
    """Unloaded position at arc length s of a segment along +x from the origin (an arc if kappa != 0)."""
    if kappa == 0.0:
        return s, 0.0
    return math.sin(kappa * s) / kappa, (1.0 - math.cos(kappa * s)) / kappa


def _inverse_model(fem, case, spec: InverseSpec, level: InverseLevel, elements: int, options: FemOptions):
    """The clamped segment with the prescribed tip of one level (a node 'inflection' at l1)."""
    seg = case.segment
    L, kappa = seg.length, seg.initial_curvature()
    if abs(kappa * L) >= 2 * math.pi:
        raise NotApplicable("an initially curved segment closing on itself")
    section = _section(fem, seg.section, seg.E, L, options)
    if spec.EI is not None or spec.I is not None:
        if spec.EI is None and seg.E is None:
            raise NotApplicable("methods.fem.inverse.I needs the segment's E (a layered section has none)")
        EI = spec.EI if spec.EI is not None else seg.E * spec.I
        section = fem.Section.from_EI(section.EA, EI, E=seg.E)
    model = fem.Model()
    model.add_node("root", 0.0, 0.0)
    tip = _arc_point(kappa, L)
    model.add_node("tip", *tip)
    if level.tie is Tie.INFLECTION:
        model.add_node("inflection", *_arc_point(kappa, level.value))
        n1 = min(max(1, round(elements * level.value / L)), elements - 1) if elements > 1 else 1
        model.add_member("root", "inflection", section, n_elements=n1, curvature=kappa, name="segment:root")
        model.add_member(
            "inflection", "tip", section, n_elements=max(1, elements - n1), curvature=kappa, name="segment:tip"
        )
    else:
        model.add_member("root", "tip", section, n_elements=elements, curvature=kappa, name="segment")
    model.add_support("root", "fixed")
    model.prescribe("tip", "uy", [level.b - tip[1]])
    model.prescribe("tip", "rz", [level.theta0 - kappa * L])
    if level.tie is Tie.POSITION_X:
        model.prescribe("tip", "ux", [level.value - tip[0]])
    elif level.tie is Tie.AXIAL_LOAD:
        model.add_force("tip", [level.value], [0.0])
    return model


def _tie(fem, level: InverseLevel):
    if level.tie is Tie.LOAD_RATIO:
        return fem.LoadRatio("ux", "uy", -level.value)  # F_x = -n F_y
    if level.tie is Tie.INFLECTION:
        return fem.ZeroMoment("ux", "inflection")
    return None


def _run_inverse(
    fem, case, spec: InverseSpec, requests: list[Request], options: FemOptions, own: FemInverseOptions
) -> MethodRun:
    """Tip loads of the inverse problem, level by level, on n and 2n elements (Richardson); ``own``: the
    problem's option table, with its own mesh and extrapolation (else the method's)."""
    t0 = time.perf_counter()
    elements = own.elements if own.elements is not None else options.elements
    richardson = own.richardson if own.richardson is not None else options.richardson
    estimate = options.error_estimate
    solve_options = dict(rtol=options.rtol)
    values, errors, ok, msg, iterations = {}, {}, {}, {}, 0
    for lv in sorted({r.level for r in requests}):
        level = spec.levels[lv]
        guess = _applied(case, "tip", lv)[0]
        results, tip_xs = [], []
        for n in (elements, 2 * elements) if estimate else (elements,):
            model = _inverse_model(fem, case, spec, level, n, options)
            res = fem.solve_tip_inverse(model, "tip", _tie(fem, level), guess=guess, **solve_options)
            if not res.converged and level.tie is Tie.POSITION_X:
                # displacement control of x met a singular state (a buckling load of the clamped-
                # clamped beam on the straight path to the target): reach the same x by the
                # axial load that puts the tip there
                free = _inverse_model(
                    fem, case, spec, InverseLevel(level.b, level.theta0, Tie.AXIAL_LOAD, 0.0), n, options
                )
                res = fem.solve_tip_inverse(free, "tip", fem.Position("ux", level.value), guess=guess, **solve_options)
                res.message = f"x reached by its axial load (displacement control of x failed): {res.message}"
            iterations += res.result.iterations
            results.append(res)
            tip_xs.append(float(res.result.positions[0, model.node("tip"), 0]) if res.converged else math.nan)
            if not res.converged:
                break
            guess = res.tied[0]
        final = results[-1]
        ok[lv], msg[lv] = final.converged, final.message
        state = np.append(final.tip_loads[0], tip_xs[-1])  # F_x, F_y, M, x of the inverse solution
        coarse = np.append(results[0].tip_loads[0], tip_xs[0])
        error = abs(state - coarse) / 3.0 if len(results) == 2 and final.converged else None
        if richardson and error is not None:
            state = state + (state - coarse) / 3.0
        for req in requests:
            if req.level == lv:
                k = (*LOAD_OUTPUTS, POSITION_OUTPUT).index(req.quantity)
                values[req] = float(state[k]) if final.converged else math.nan
                if error is not None:
                    errors[req] = float(error[k])
    bad = "; ".join(f"inverse level {lv}: {m}" for lv, m in msg.items() if not ok[lv])
    return MethodRun(
        values=values,
        converged=all(ok.values()),
        message=bad or "converged",
        error_estimate=errors,
        wall_time=time.perf_counter() - t0,
        level_converged=ok,
        level_messages=msg,
        extras={"iterations": iterations},
    )


def _run_moment_driven(fem, case, requests: list[Request], options: FemOptions) -> MethodRun:
    """The case's one prescribed displacement reached by a moment at the input node (option
    ``input_moment_at``), found by the outer secant of ``fem.solve_tip_inverse`` (a Position tie); the
    moment is the ``input_torque`` output, on n and 2n elements with the Richardson estimate."""
    t0 = time.perf_counter()
    node = options.input_moment_at
    case = _realised(case, options)
    moved = [ld for ld in case.loads if ld.kind == "displacement"]
    if len(moved) != 1 or any(ld.kind == "rotation" for ld in case.loads):
        raise NotApplicable(
            "methods.fem.input_moment_at: needs exactly one prescribed displacement (the target) "
            "and no prescribed rotation"
        )
    target = moved[0]
    d = np.asarray(target.direction, float) / math.hypot(*target.direction)
    if min(abs(d[0]), abs(d[1])) > 1e-12:
        raise NotApplicable("methods.fem.input_moment_at: the prescribed displacement must be along x or y")
    axis = 0 if abs(d[0]) > 0.5 else 1
    driven = case.model_copy(update={"loads": [ld for ld in case.loads if ld is not target]})
    elements = options.elements
    estimate = options.error_estimate
    n = case.n_levels()
    results: list[Any] = []  # fem.TipInverseResult per mesh
    model: Any = None
    for count in (elements, 2 * elements) if estimate else (elements,):
        model = build_model(driven, count, options)
        if node not in model.node_names:
            raise NotApplicable(f"methods.fem.input_moment_at: no node '{node}' in the FEM model")
        origin = model.coords[model.node(target.point)][axis]
        goal = origin + np.asarray(target.levels(), float) * d[axis]
        res = fem.solve_tip_inverse(
            model,
            node,
            fem.Position("rz", goal, node=target.point, direction=("ux", "uy")[axis]),
            guess=results[-1].tied if results else None,
            n_levels=n,
            rtol=options.rtol,
        )
        results.append(res)
        if not res.converged:
            break
    final = results[-1]
    torque = final.tied
    error = np.abs(torque - results[0].tied) / 3.0 if len(results) == 2 and final.converged else None
    origin_xy = {name: model.coords[i] for i, name in enumerate(model.node_names)}
    others = [r for r in requests if r.quantity != "input_torque"]
    values = _extract(driven, _Fields.of(final.result), others, origin_xy) if final.converged else {}
    errors = {}
    for req in requests:
        if req.quantity == "input_torque":
            values[req] = float(torque[req.level]) if final.converged else math.nan
            if error is not None:
                errors[req] = float(error[req.level])
    return MethodRun(
        values=values,
        converged=final.converged,
        error_estimate=errors,
        message=f"input moment at '{node}' found by an outer solve: {final.message}",
        wall_time=time.perf_counter() - t0,
        extras={"iterations": sum(r.result.iterations for r in results), "elements": elements},
    )


def run(case, requests: list[Request], options: FemOptions) -> MethodRun:
    if options.input_moment_at is not None:
        return _run_moment_driven(fem, case, requests, options)
    spec = inverse_spec(case, options.inverse, "fem")
    if spec is None or options.inverse is None:
        return _run_forward(fem, case, requests, options)
    inverse_outputs = LOAD_OUTPUTS + ((POSITION_OUTPUT,) if spec.tip_x else ())
    loads = [r for r in requests if r.quantity in inverse_outputs and r.point == "tip"]
    others = [r for r in requests if r not in loads]
    forward = _run_forward(fem, case, others, options) if others else None
    return merge_runs(forward, _run_inverse(fem, case, spec, loads, options, options.inverse))


def _realised(case, options: FemOptions):
    """The case's mechanism with its sprung joints built as flexures (option ``slfp``), else the case."""
    spec = options.slfp
    if spec is None:
        return case
    if case.mechanism is None:
        raise NotApplicable("methods.fem.slfp: realises the sprung joints of a mechanism; this case is a segment")
    try:
        return with_flexures(case, spec.length, spec.E, spec.thickness_ratio)
    except ValueError as exc:
        raise NotApplicable(f"methods.fem.slfp: {exc}") from None


def _run_forward(fem, case, requests: list[Request], options: FemOptions) -> MethodRun:
    start = time.perf_counter()
    case = _realised(case, options)
    elements = options.elements
    model = build_model(case, elements, options)
    values: dict[Request, float] = {}
    errors: dict[Request, float] = {}
    iterations, converged, messages = 0, True, []
    result: Any = None  # the first solve's fem.SolveResult
    unreliable: dict[Request, str] = {}
    refine = 1
    analysis = 0.0  # CPU seconds of the load stepping of every solve (without set-up and results)
    zero = options.zero_level
    if zero is not None:
        if not 0 <= zero < case.n_levels():
            raise NotApplicable(f"zero_level = {zero}: the case has {case.n_levels()} load levels")
        shifted = [r for r in requests if r.quantity in ZEROED]
        requests = list(dict.fromkeys(requests + [Request(r.quantity, r.point, zero) for r in shifted]))
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
        solved = _solve_levels(fem, case, model, ordinary, options)
        result, analysis, refine = solved.result, solved.analysis, solved.refine
        values.update(solved.values)
        errors.update(solved.errors)
        unreliable.update(solved.unreliable)
        iterations += solved.iterations
        converged &= solved.converged
        messages.append(solved.message + _critical_note(result))
        values.update(_beam_outputs(fem, case, model, result, beam_outputs, elements, options))
    if limit:
        value, res, why = _limit_load(fem, case, model, options)
        iterations += res.iterations
        analysis += res.analysis_time
        if why:
            converged = False
            messages.append(why)
        else:
            if options.error_estimate:  # Richardson on the limit load itself (O(h^2))
                fine, res_fine, why_fine = _limit_load(fem, case, build_model(case, 2 * elements, options), options)
                iterations += res_fine.iterations
                analysis += res_fine.analysis_time
                if not why_fine:
                    errors.update({r: abs(fine - value) / 3.0 for r in limit})
                    value = fine + (fine - value) / 3.0 if options.richardson else fine
            values.update({r: value for r in limit})
            messages.append(f"limit load by {options.limit_control}: {res.message}")
        result = result or res
    if zero is not None:
        at_zero = {r: values.get(Request(r.quantity, r.point, zero)) for r in shifted}
        origin = {name: model.coords[i] for i, name in enumerate(model.node_names)}
        for r in shifted:
            base = at_zero[r]
            if r in values and base is not None:
                unloaded = {"x": origin[r.point][0], "y": origin[r.point][1]}.get(r.quantity, 0.0)
                values[r] = values[r] - base + unloaded
    extras = {
        "iterations": iterations,
        "elements": elements,
        "refine": refine,
        "rejected_iterations": getattr(result, "rejected_iterations", 0),
        "analysis_cpu_s": analysis,
    }
    if result is not None and result.n_levels:
        extras["shapes"] = DeferredList(lambda: _shapes(result))  # built when the report reads them
        extras["fields"] = _DeferredFields(result)  # point data for the ParaView series, likewise
        path = _continuation_path(case, result)
        if path:
            extras["path"] = path
    return MethodRun(
        values=values,
        converged=converged,
        message="; ".join(m for m in messages if m),
        error_estimate=errors,
        unreliable_estimate=unreliable,
        wall_time=time.perf_counter() - start,
        extras=extras,
    )


BEAM_OUTPUTS = ("max_stress", "inflection_points", "mechanical_advantage")
ZEROED = ("x", "y", "dx", "dy")


def _soft_mode_count(case, model, options: FemOptions) -> tuple[int, str]:
    """dof: soft modes of the unloaded tangent condensed to the actuation points (``fem.soft_modes``),
    ``[methods.fem] dof = {points = [...], ratio = 1e-2}``; the stretching reference is the largest
    EA/l of the case's beams."""
    spec = options.dof
    if spec is None or case.mechanism is None:
        raise NotApplicable("dof by the FEM needs a mechanism and [methods.fem] dof = {points = [...]}")
    points, ratio = spec.points, spec.ratio
    reference = max(
        m.section.EA / math.dist(model.coords[m.start], model.coords[m.end]) for m in model.members if ":" not in m.name
    )
    found = soft_modes(
        model, [(p, d) for p in points for d in ("ux", "uy", "rz")], ratio=ratio, reference_stiffness=reference
    )
    return found.count, (
        f"dof: {found.count} soft mode(s) of the tangent condensed to {', '.join(points)}, "
        f"k/k_ref = {', '.join(f'{r:.2e}' for r in found.ratios)}, threshold {ratio:g}"
    )


def _beam_outputs(fem, case, model, result, requests, elements: int, options: FemOptions) -> dict:
    """max_stress and inflection_points of the finest mesh; mechanical_advantage by an increment
    of the input load (`fem_outputs`)."""
    values = {}
    beams = [i for i, m in enumerate(model.members) if ":" not in m.name]  # stiff bars are 'link:node'
    ma = None
    for req in requests:
        if req.level >= result.n_levels:
            continue
        if req.quantity == "max_stress":
            values[req] = fem_outputs.max_stress(result, req.level)
        elif req.quantity == "inflection_points":
            values[req] = float(fem_outputs.inflection_points(result, model, beams, req.level))
        else:
            if ma is None and options.ma is not None and options.ma.definition == "secant":
                load = case.loads[fem_outputs.input_load_index(case, options.ma)]
                ma = fem_outputs.secant_mechanical_advantage(
                    options.ma, fem_outputs.output_force(case, options.ma, result.reaction), load
                )
            elif ma is None:
                raised_case, delta, load = fem_outputs.incremented_case(case, options.ma)
                solves = [
                    fem.solve(m, n_levels=case.n_levels(), rtol=options.rtol)
                    for m in (model, build_model(raised_case, elements, options))
                ]
                if not all(r.converged for r in solves):
                    raise NotApplicable(
                        "mechanical_advantage: a solve of the increment did not converge: "
                        + "; ".join(r.message for r in solves)
                    )
                forces = [fem_outputs.output_force(case, options.ma, r.reaction) for r in solves]
                ma = fem_outputs.mechanical_advantage(options.ma, forces[0], forces[1], delta, load)
            if np.isfinite(ma[req.level]):  # secant: undefined without input load
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
    disp = [
        float((result.position(point, k) - result.mesh_positions_ref[result.node_index(point)]) @ d)
        for k in range(result.n_levels)
    ]
    reference = max(abs(np.asarray(ld.levels())).max() for ld in loads)
    load = list(np.asarray(result.load_factor) * reference)
    limits = [
        (disp[c.step], c.load_factor * reference)
        for c in result.critical_points
        if c.kind == "limit" and 0 <= c.step < len(disp)
    ]
    if result.control == "displacement" and not limits:
        limits = [(disp[i], load[i]) for i in range(1, len(load) - 1) if load[i - 1] <= load[i] > load[i + 1]][:1]
    return {
        "displacement": disp,
        "load": load,
        "limit_points": limits,
        "displacement_label": f"displacement of {point} along the load [{case.unit('length')}]",
        "load_label": f"load [{case.unit('force')}]",
    }
