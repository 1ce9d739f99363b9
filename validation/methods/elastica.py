"""Adapter: a single-segment case -> the exact inextensible elastica (``elastica.shooting``).

Supported: one ``[segment]`` (straight or initially curved, any section: EI from
``segment.bending_stiffness()``), boundaries fixed-free, fixed-pinned, fixed-guided, fixed-fixed;
tip loads of kind force (dead, follower, or toward a fixed point), moment, displacement and
rotation, and a uniform dead distributed load along the segment (kind distributed, or self_weight
from the section's weight density). A force ``toward = [x, y]`` (a rope over a pulley) is
``elastica.PointedForce``: F = T R(angle) (P - r_tip)/|P - r_tip| at the deformed tip, the case's
frame being the elastica's (clamp at the origin, unloaded tangent along +x); its direction is one
more condition of the shooting (``elastica.shooting``), solved on fixed-free, fixed-pinned and
fixed-guided segments. Not applicable: a follower distributed load, a force toward a fixed point on
a fixed-fixed segment (which tip components it frees would depend on its turning direction). The
load path is followed level by level with continuation (each level warm-starts from the previous one).

Boundary handling: a tip freedom that carries a load is load-controlled, whatever the boundary
(the load-specified "fixed-guided" beams of [bapat2015, Tables 3.2-3.6] give P, nP and M). Otherwise
fixed-guided holds the tip angle at its unloaded value (unless a rotation load prescribes it) and
the tip moment is solved for; fixed-fixed also holds the tip position components (x, y) that no
displacement or force load acts along. With prescribed displacements/rotations, the
``force_x``/``force_y``/``moment`` outputs are the tip loads needed. ``rotation`` is the change of
the tip angle from the unloaded state (degrees); ``reaction_*`` are the support loads at the root.

Options (``[methods.elastica]``, ``method_options.ElasticaOptions``): ``I`` (replaces the section's second moment of area, so
EI = E * I), ``EI`` (replaces EI), ``rtol``, ``tol`` (none: the shooting solver's own), ``samples`` (shape points kept in extras).

Inflection problem (``problem = "inflection"``, the dissertation's Case 2c, Table 3.6): the options give
per level (a list, or one value for every level) the tip transverse position ``b`` (the tip's y,
length units), the absolute tip angle ``theta0`` (degrees) and the inflection location ``l1``
(arc length from the clamp where the bending moment vanishes). The end loads are unknowns:
``force_x``, ``force_y``, ``moment`` are the loads needed, ``x`` the tip's x (the dissertation's a). The
case's loads at each level (e.g. the PRBM loads) are not applied: they are the initial guess,
the state the continuation starts from (zero loads: start from the problem without the
inflection condition). Only a fixed-guided segment with force/moment loads.
Inverse tip problem (option table ``inverse``, ``validation.methods.inverse_problem``: tip y ``b``, slope
``theta0_deg`` and one of ``a``, ``n``, ``axial_load``, ``l1`` per level): the tip loads
(``force_x``, ``force_y``, ``moment``) are those that hold the prescribed tip, each level solved on
its own from the unloaded beam (``l1``: from the case's loads, as for ``problem = 'inflection'``);
the other outputs come from the forward solve under the case's loads.
Not applicable: loads away from the tip. The shooting's elastica is inextensible and shear-free
whatever the section's area.

Segments solved as a mechanism (``elastica_network.run_segment``, ``elastica.mechanism``): a pinned-pinned
segment (a root pin, which the shooting of a clamped beam cannot state), and a straight fixed-fixed segment
whose tip's axial motion is held or prescribed (an inextensible beam with x(L) = L cannot bend: its chord
shortens once it bends, so a transverse load or a moment is carried only with the axial stretch). The beam
is then extensible with the section's EA (inextensible, and refused where it would have to stretch, if an
'inertia' section gives no A); the tip freedoms held are those of ``quantities.boundary_held_tip`` (the
FEM's rule: pinned-pinned holds the tip's x and y unless a load acts along them); tip forces (dead or
follower, or toward a fixed point), moments and prescribed motions only: no distributed load. A fixed-fixed
segment pulled toward a fixed point is solved this way too.
The outputs are the shooting's (tip x, y, dx, dy, rotation, force_x, force_y, moment; root reactions),
plus the rotation of a pinned root.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
from numpy.typing import NDArray

from elastica.shooting import (
    ElasticaProblem,
    MomentConstraint,
    PointedForce,
    TipConstraint,
    loaded_start,
    solve_path,
    unloaded_tip,
)
from validation.methods import elastica_network
from validation.methods.inverse_problem import LOAD_OUTPUTS, InverseSpec, Tie, inverse_spec, merge_runs
from validation.methods.base import MethodRun, NotApplicable, Request
from validation.case.method_options import ElasticaOptions
from validation.case.schema import Case

SUPPORTED = {"fixed-free", "fixed-pinned", "fixed-guided", "fixed-fixed"}  # by the shooting (``level_problems``)


def _stiffness(case: Case, options: ElasticaOptions) -> float:
    seg = case.require_segment()
    if options.EI is not None:
        return options.EI
    if options.I is not None:
        if seg.E is None:
            raise NotApplicable("option I needs the segment's E (a layered section has none)")
        return seg.E * options.I
    return seg.bending_stiffness()


def _tolerances(options: ElasticaOptions) -> dict:
    """The shooting solver's ``rtol`` and ``tol`` the case gives (the solver's own where it gives none)."""
    return {name: value for name in ("rtol", "tol") if (value := getattr(options, name)) is not None}


STRAIGHT_FIXED_FIXED = (
    "a straight fixed-fixed segment whose tip's axial motion is held or prescribed: the "
    "inextensible shooting cannot bend it (once it bends its chord shortens); the adapter "
    "solves it as an extensible mechanism instead"
)


def _held_tip_directions(case: Case) -> list[np.ndarray]:
    """The tip-position directions (unit x, y) a fixed-fixed boundary holds at the unloaded tip: those no
    prescribed displacement and no tip force acts along (at most two prescribed components in all)."""
    if case.require_segment().boundary != "fixed-fixed":
        return []
    prescribed = [
        np.asarray(ld.direction, float) / np.hypot(*ld.require_direction())
        for ld in case.loads
        if ld.kind == "displacement"
    ]
    forces = [
        np.asarray(ld.direction, float) if ld.toward is None else np.ones(2)  # a pointed force: both
        for ld in case.loads
        if ld.kind == "force"
    ]
    held: list[np.ndarray] = []
    for u in (np.array([1.0, 0.0]), np.array([0.0, 1.0])):
        free = any(abs(u @ p) >= 0.999 for p in prescribed) or any(abs(u @ f) > 1e-12 for f in forces)
        if not free and len(prescribed) + len(held) < 2:
            held.append(u)
    return held


def _axially_held(case: Case) -> bool:
    """A straight fixed-fixed segment whose tip x is held by the boundary or prescribed: the inextensible
    elastica's tip would have to stay at x = L, which it can only do straight."""
    seg = case.require_segment()
    axial = [
        np.asarray(ld.direction, float) / np.hypot(*ld.require_direction())
        for ld in case.loads
        if ld.kind == "displacement"
    ] + _held_tip_directions(case)
    return seg.boundary == "fixed-fixed" and seg.initial_curvature() == 0.0 and any(abs(u[0]) > 0.999 for u in axial)


def _by_mechanism(case: Case) -> bool:
    """The segments the shooting of one clamped beam cannot state, solved as a mechanism
    (``elastica_network.run_segment``): a pinned root, and a straight fixed-fixed segment whose tip's
    axial motion is held or prescribed (a transverse load or a moment then needs the axial stretch), and a
    fixed-fixed segment pulled toward a fixed point (the shooting frees the held tip components a force acts
    along, and this force turns; the mechanism holds them as constraints)."""
    seg = case.require_segment()
    pointed = seg.boundary == "fixed-fixed" and any(ld.toward is not None for ld in case.loads)
    return seg.boundary == "pinned-pinned" or _axially_held(case) or pointed


def level_problems(case: Case, options: ElasticaOptions) -> list[ElasticaProblem]:
    """One ``ElasticaProblem`` per load level of a segment case (raises NotApplicable)."""
    if case.mechanism is not None:
        raise NotApplicable("the exact elastica solves a single segment, not a mechanism")
    seg = case.require_segment()
    if seg.boundary not in SUPPORTED:
        raise NotApplicable(
            f"boundary '{seg.boundary}' is not a clamped-root problem of the shooting; the "
            "adapter solves it as a mechanism instead"
        )
    L, k0 = seg.length, seg.initial_curvature()
    EI = _stiffness(case, options)
    x0, y0, th0 = unloaded_tip(L, k0)
    c0, s0 = math.cos(th0), math.sin(th0)
    for load in case.loads:
        if load.point != "tip":
            raise NotApplicable(f"load at '{load.point}': the elastica adapter takes tip loads only")
        if load.body is not None:
            raise NotApplicable("loads on a named body belong to mechanisms")
        if load.kind == "distributed" and load.follower:
            raise NotApplicable("a follower distributed load is not in the elastica's shooting equations")
        if load.toward is not None and seg.boundary == "fixed-fixed":
            raise NotApplicable(
                "a force toward a fixed point on a fixed-fixed segment: the adapter frees "
                "the held tip components a force acts along, and this force turns"
            )
    held = _held_tip_directions(case)
    if _axially_held(case):
        raise NotApplicable(STRAIGHT_FIXED_FIXED)
    problems = []
    for i in range(case.n_levels()):
        force = np.zeros(2)
        follower = np.zeros(2)
        moment = 0.0
        constraints: list[TipConstraint] = []
        prescribed_dirs: list[np.ndarray] = []
        tip_angle = None
        distributed = np.zeros(2)
        pointed: list[PointedForce] = []
        for load in case.loads:
            v = load.levels()[i]
            d = np.asarray(load.direction if load.direction is not None else (0.0, 0.0), float)
            if load.kind == "force" and load.toward is not None:
                pointed.append(
                    PointedForce(float(v), (float(load.toward[0]), float(load.toward[1])), math.radians(load.angle))
                )
            elif load.kind == "distributed":
                distributed += v * d
            elif load.kind == "self_weight":
                weight = seg.section.weight_per_length()
                if weight is None:
                    raise NotApplicable("self_weight needs the section's weight density")
                distributed += v * weight * d / np.hypot(*d)
            elif load.kind == "force" and not load.follower:
                force += v * d
            elif load.kind == "force":
                # components in the deformed tip frame: rotate the undeformed-frame vector by -theta_tip0
                f = v * d
                follower += np.array([c0 * f[0] + s0 * f[1], -s0 * f[0] + c0 * f[1]])
            elif load.kind == "moment":
                moment += v
            elif load.kind == "displacement":
                u = d / np.hypot(*d)
                if k0 == 0.0 and abs(u[0]) > 0.999 and v != 0.0:
                    raise NotApplicable(
                        "a prescribed axial displacement of a straight segment: the "
                        "inextensible elastica has no unbuckled solution"
                    )
                constraints.append(TipConstraint(tuple(u), float(u @ [x0, y0] + v * np.hypot(*d))))
                prescribed_dirs.append(u)
            elif load.kind == "rotation":
                tip_angle = th0 + math.radians(v)
        # a load on a tip freedom makes it load-controlled; the boundary holds only the others
        has_moment = any(ld.kind == "moment" for ld in case.loads)
        if seg.boundary in ("fixed-guided", "fixed-fixed") and tip_angle is None and not has_moment:
            tip_angle = th0
        for u in held:
            constraints.append(TipConstraint(tuple(u), float(u @ [x0, y0])))
            prescribed_dirs.append(u)
        if len(prescribed_dirs) > 2:
            raise NotApplicable("more than two prescribed tip-position components")
        problems.append(
            ElasticaProblem(
                length=L,
                EI=EI,
                curvature=k0,
                force=_pair(force),
                moment=moment,
                follower=_pair(follower),
                constraints=tuple(constraints),
                tip_angle=tip_angle,
                distributed=_pair(distributed),
                pointed=tuple(pointed),
            )
        )
    return problems


def _pair(vector: NDArray[np.float64]) -> tuple[float, float]:
    """A 2-vector as the (x, y) pair ``ElasticaProblem`` takes."""
    return float(vector[0]), float(vector[1])


def _per_level(options: ElasticaOptions, name: str, n: int) -> list[float]:
    v = getattr(options, name)
    if v is None:
        raise NotApplicable(f"problem = 'inflection' needs the option '{name}'")
    values = list(v) if isinstance(v, list) else [v] * n
    if len(values) != n:
        raise NotApplicable(f"option '{name}' has {len(values)} values for {n} load levels")
    return values


def inflection_problems(case: Case, options: ElasticaOptions) -> list[tuple[ElasticaProblem, tuple, float]]:
    """Per level: the Case 2c problem (b, theta0, l1 given) and its start loads ((Fx, Fy), M)."""
    if case.mechanism is not None:
        raise NotApplicable("the exact elastica solves a single segment, not a mechanism")
    seg = case.require_segment()
    if seg.boundary != "fixed-guided":
        raise NotApplicable("problem = 'inflection' is a fixed-guided segment problem")
    if any(
        ld.kind not in ("force", "moment") or ld.follower or ld.toward is not None or ld.point != "tip"
        for ld in case.loads
    ):
        raise NotApplicable("problem = 'inflection' takes dead tip forces/moments (the start loads) only")
    n = case.n_levels()
    b, theta0, l1 = (_per_level(options, k, n) for k in ("b", "theta0", "l1"))
    L, EI, k0 = seg.length, _stiffness(case, options), seg.initial_curvature()
    out = []
    for i in range(n):
        force, moment = np.zeros(2), 0.0
        for load in case.loads:
            v = load.levels()[i]
            if load.kind == "force":
                force += v * np.asarray(load.direction, float)
            else:
                moment += v
        problem = ElasticaProblem(
            length=L,
            EI=EI,
            curvature=k0,
            constraints=(TipConstraint((0.0, 1.0), b[i]),),
            tip_angle=math.radians(theta0[i]),
            moment_constraints=(MomentConstraint(l1[i]),),
        )
        out.append((problem, (float(force[0]), float(force[1])), moment))
    return out


def _value(res, req: Request, case: Case) -> float:
    seg = case.require_segment()
    x0, y0, th0 = unloaded_tip(seg.length, seg.initial_curvature())
    q, point = req.quantity, req.point
    if q == "strain_energy":
        return res.strain_energy
    if point == "root":
        table = {
            "x": 0.0,
            "y": 0.0,
            "dx": 0.0,
            "dy": 0.0,
            "rotation": 0.0,
            "reaction_x": res.reaction[0],
            "reaction_y": res.reaction[1],
            "reaction_moment": res.reaction[2],
        }
    else:
        table = {
            "x": res.x,
            "y": res.y,
            "dx": res.x - x0,
            "dy": res.y - y0,
            "rotation": math.degrees(res.theta - th0),
            "force_x": res.force[0],
            "force_y": res.force[1],
            "moment": res.moment,
        }
    if q not in table:
        raise NotApplicable(f"'{q}' at '{point}' is not an elastica output")
    return float(table[q])


def inverse_problems(case: Case, spec: InverseSpec, options: ElasticaOptions) -> list[ElasticaProblem]:
    """One ``ElasticaProblem`` per level for the inverse tip problem ``spec``."""
    seg = case.require_segment()
    EI = (
        spec.EI
        if spec.EI is not None
        else (seg.E * spec.I if spec.I is not None and seg.E is not None else _stiffness(case, options))
    )
    out = []
    for lv in spec.levels:
        y = TipConstraint((0.0, 1.0), lv.b)
        common: dict[str, Any] = dict(length=seg.length, EI=EI, curvature=seg.initial_curvature(), tip_angle=lv.theta0)
        if lv.tie is Tie.POSITION_X:
            problem = ElasticaProblem(constraints=(TipConstraint((1.0, 0.0), lv.value), y), **common)
        elif lv.tie is Tie.LOAD_RATIO:
            problem = ElasticaProblem(constraints=(TipConstraint((0.0, 1.0), lv.b, (-lv.value, 1.0)),), **common)
        elif lv.tie is Tie.AXIAL_LOAD:
            problem = ElasticaProblem(force=(lv.value, 0.0), constraints=(y,), **common)
        else:
            problem = ElasticaProblem(constraints=(y,), moment_constraints=(MomentConstraint(lv.value),), **common)
        out.append(problem)
    return out


def _start_loads(case: Case, level: int) -> tuple[tuple[float, float], float]:
    force, moment = np.zeros(2), 0.0
    for load in case.loads:
        if load.kind == "force" and load.toward is not None:
            raise NotApplicable("the inverse tip problem starts from dead tip loads, not a force toward a fixed point")
        if load.kind == "force" and not load.follower:
            force += load.levels()[level] * np.asarray(load.direction, float)
        elif load.kind == "moment":
            moment += load.levels()[level]
    return (float(force[0]), float(force[1])), moment


def _run_inverse(case: Case, spec: InverseSpec, requests: list[Request], options: ElasticaOptions) -> MethodRun:
    """The tip loads of the inverse problem, each level from its own start."""
    t0 = time.perf_counter()
    kwargs = _tolerances(options)
    problems = inverse_problems(case, spec, options)
    values, ok, msg = {}, {}, {}
    for level in sorted({r.level for r in requests}):
        problem, start = problems[level], None
        if problem.moment_constraints:
            force, moment = _start_loads(case, level)
            if force != (0.0, 0.0) or moment != 0.0:
                start = loaded_start(
                    problem, force, moment, n_samples=2, **{k: v for k, v in kwargs.items() if k == "rtol"}
                )
                start = start if start.converged else None
        res = solve_path(problem, start=start, n_samples=2, **kwargs)  # loads only: no shape
        ok[level], msg[level] = res.converged, res.message
        loads = {"force_x": res.force[0], "force_y": res.force[1], "moment": res.moment}
        for req in requests:
            if req.level == level:
                values[req] = float(loads[req.quantity]) if res.converged else math.nan
    bad = "; ".join(f"inverse level {lv}: {m}" for lv, m in msg.items() if not ok[lv])
    return MethodRun(
        values=values,
        converged=all(ok.values()),
        message=bad or "converged",
        wall_time=time.perf_counter() - t0,
        level_converged=ok,
        level_messages=msg,
    )


def run(case: Case, requests: list[Request], options: ElasticaOptions) -> MethodRun:
    spec = inverse_spec(case, options.inverse, "elastica")
    if spec is None:
        return _run_forward(case, requests, options)
    loads = [r for r in requests if r.quantity in LOAD_OUTPUTS and r.point == "tip"]
    others = [r for r in requests if r not in loads]
    forward = _run_forward(case, others, options) if others else None
    return merge_runs(forward, _run_inverse(case, spec, loads, options))


def _run_forward(case: Case, requests: list[Request], options: ElasticaOptions) -> MethodRun:
    t0 = time.perf_counter()
    if case.mechanism is not None:  # beams coupled through rigid links: validation/methods/elastica_network.py
        run = elastica_network.run_mechanism(case, requests, options)
        run.wall_time = time.perf_counter() - t0
        return run
    inflection = options.problem == "inflection"
    if not inflection and _by_mechanism(case):
        run = elastica_network.run_segment(case, requests, options, _stiffness(case, options))
        run.wall_time = time.perf_counter() - t0
        return run
    started = inflection_problems(case, options) if inflection else []
    problems = [] if inflection else level_problems(case, options)
    kwargs = _tolerances(options)
    samples = options.samples
    wanted = sorted({r.level for r in requests})
    last = max(wanted) if wanted else -1
    values, level_ok, level_msg, shapes = {}, {}, {}, {}
    previous = None
    for level in range(last + 1):
        if inflection:  # each level from its own start loads; skip levels not asked for
            if level not in wanted:
                continue
            problem, force, moment = started[level]
            start = None
            if force != (0.0, 0.0) or moment != 0.0:
                start = loaded_start(
                    problem, force, moment, n_samples=2, **{k: v for k, v in kwargs.items() if k == "rtol"}
                )
                start = start if start.converged else None
            res = solve_path(problem, start=start, n_samples=samples, **kwargs)
        else:
            res = solve_path(problems[level], start=previous, n_samples=samples, **kwargs)
        level_ok[level], level_msg[level] = res.converged, res.message
        if level in wanted:
            shapes[level] = res.shape
            for req in requests:
                if req.level == level:
                    values[req] = _value(res, req, case) if res.converged else math.nan
        previous = res if res.converged else None
    converged = all(level_ok.get(lv, False) for lv in wanted)
    message = "; ".join(f"level {lv}: {m}" for lv, m in level_msg.items() if not level_ok[lv])
    return MethodRun(
        values=values,
        converged=converged,
        message=message or "converged",
        wall_time=time.perf_counter() - t0,
        level_converged={lv: level_ok[lv] for lv in wanted},
        level_messages={lv: level_msg[lv] for lv in wanted},
        extras={
            "shapes": shapes,
            "model": "inextensible elastica, DOP853 shooting"
            + (", inverse problem with a given inflection point" if inflection else ""),
        },
    )
