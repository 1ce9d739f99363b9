"""The mechanism part of the PRBM adapter: a case's ``[mechanism]`` -> ``prbm.build`` -> ``prbm.solve``.

The geometry the FEM reads (nodes, beams with their section and E, rigid links, joints, supports)
becomes ``prbm.Geometry``; the builder applies its rules to each beam (see ``prbm.builder``)
and the general rigid-link network solver finds the equilibrium at every load level. No
``[methods.prbm]`` input is needed; ``rules = {...}`` may override the builder's rules:

  gamma, K_theta, slfp_ratio        defaults of every beam
  beams = { name = { model, gamma, K_theta, stiffness, clamp } }   per beam
A straight beam with a free end loaded by one dead force of one sense has a defined load ratio n
(``load_ratios``): the builder then takes gamma(n), K_Theta(n) of the Pauly-Midha fits
[bapat2015, eqs 41, 43] and says so in the beam's record. A beam spring turned past the fits' 65 deg flags the
level (``Applicability.DEFLECTION``).

Loads, as the FEM takes them: forces at nodes (dead, or ``follower``: turning with the node's body),
moments (on ``body`` if given: a link, or a beam's end at that node; else the node's body),
prescribed displacements along x or y and prescribed rotations (of ``body``, else of the node's body).

Outputs (quantity contract): x, y, dx, dy of any node (global frame; from the unloaded pose);
rotation of the body the node moves with (change from the unloaded angle, CCW, deg); force_x,
force_y, moment at a node = the total external load it receives (applied, plus what a prescribed
motion there needs); input_angle and input_torque of the input (the prescribed rotation or the
applied moment); strain_energy (sum of 1/2 K (Delta Theta)^2); reaction_x, reaction_y, reaction_moment at a
support = the load the support exerts on the mechanism (the ground joints and springs the builder made
for it, from the multipliers; moment about the support node); mechanical_advantage as the FEM defines
it (``ma = {output, direction, input, step, d_i, definition}``, ``validation/methods/fem_outputs.py``).
The model built for a geometry and rules is kept for the process (``built_model``), so a second run of
the same mechanism only solves. The model chosen for every beam is
in the message and in ``extras['prb_model']``; each state's stability in ``extras['stable']``.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

import planar
import prbm
from prbm.fits import THETA_RANGE
from prbm.network import UnreachableMotion
from validation.case.method_options import PrbmOptions, RulesOptions
from validation.methods import fem_outputs
from validation.methods.base import Applicability, MethodRun, NotApplicable, Request
from validation.methods.geometry import geometry
from prbm import builder as pb


#: a beam's ``segment_type`` -> the builder's model; 'fixed-guided-inflection' (chapter 3/5, a pivot that
#: moves with the load) is no fixed network, so such a beam gets the builder's rule (stated in its record)
SEGMENT_TYPES = {
    "fixed-pinned": "fixed-pinned",
    "fixed-free": "fixed-free",
    "fixed-guided": "fixed-guided",
    "fixed-fixed": "fixed-guided",
    "slfp": "slfp",
    "pinned-pinned": "rigid",
}


def load_ratios(mech, loads) -> dict[str, float]:
    """The load ratio n of each straight beam whose end load the case defines: a free end (no support,
    link, joint or other beam there) loaded by one dead force of one sense at every level; n = -F_x'/|F_y'|
    in the beam frame (x' from the other end to the free end), as the segment PRBMs take it."""
    held = {s.node for s in mech.supports} | {nd for l in mech.links for nd in l.nodes} | {j.node for j in mech.joints}
    ends = [nd for b in mech.beams for nd in (b.start, b.end)]
    out = {}
    for beam in mech.beams:
        for free, root in ((beam.end, beam.start), (beam.start, beam.end)):
            at = [ld for ld in loads if ld.point == free]
            if beam.curvature != 0.0 or free in held or ends.count(free) > 1 or len(at) != 1:
                continue
            load = at[0]
            values = [v for v in load.levels() if v != 0.0]
            if (
                load.kind != "force"
                or load.follower
                or load.body is not None
                or load.toward is not None
                or not values
                or min(values) * max(values) < 0
            ):
                continue
            xy = {nd.name: np.array([nd.x, nd.y]) for nd in mech.nodes}
            t = xy[free] - xy[root]
            t = t / math.hypot(*t)
            d = np.sign(values[0]) * np.asarray(load.direction, float)
            along, across = float(d @ t), float(d[1] * t[0] - d[0] * t[1])
            if across != 0.0:
                out[beam.name] = -along / abs(across)
    return out


def rules(given: RulesOptions | None, mech, loads=()) -> pb.Rules:
    """The builder's rules from ``[methods.prbm] rules = {gamma, K_theta, slfp_ratio, beams}`` (a rule not
    given: the builder's own), and each beam's load ratio where the loads define it (``load_ratios``)."""
    given = given or RulesOptions()
    per_beam = {}
    names = {b.name for b in mech.beams}
    for name, over in (given.beams or {}).items():
        if name not in names:
            raise NotApplicable(f"[methods.prbm] beams.{name}: no beam of that name")
        per_beam[name] = pb.BeamRule(**over.model_dump(exclude_none=True))
    for beam in mech.beams:  # the case's own segment_type picks the model unless the rules do
        model = SEGMENT_TYPES.get(beam.segment_type or "")
        if model and beam.name not in per_beam:
            per_beam[beam.name] = pb.BeamRule(model=model)
    for name, n in load_ratios(mech, loads).items():
        per_beam[name] = replace(per_beam.get(name, pb.BeamRule()), load_ratio=n)
    builder = {
        name: value for name in ("gamma", "K_theta", "slfp_ratio") if (value := getattr(given, name)) is not None
    }  # else the builder's own
    return pb.Rules(**builder, beams=per_beam)


def _body_for(model: pb.PRBModel, load) -> str:
    if load.body is not None:
        body = model.member_body.get((load.body, load.point))
        if body is None:
            raise NotApplicable(f"a load on '{load.body}' at '{load.point}': that member does not reach that node")
        return body
    return model.node_body[load.point]


def network_loads(case, model: pb.PRBModel) -> list[prbm.network.Load]:
    loads: list[prbm.network.Load] = []
    for i, load in enumerate(case.loads):
        v = np.asarray(load.levels(), float)
        if load.kind == "force" and load.toward is not None:
            loads.append(
                planar.PointedForce(
                    load.point,
                    tuple(float(x) for x in v),
                    (float(load.toward[0]), float(load.toward[1])),
                    math.radians(load.angle),
                )
            )
        elif load.kind == "force":
            if load.follower and load.body is not None and _body_for(model, load) != model.node_body[load.point]:
                raise NotApplicable(
                    f"loads.{i}: a follower force turning with '{load.body}', whose PRB body at "
                    f"'{load.point}' is not the one carrying the point: the PRB network turns a "
                    "follower with the body carrying its point"
                )
            d = np.asarray(load.direction, float)
            loads.append(prbm.Force(load.point, tuple(v * d[0]), tuple(v * d[1]), follower=load.follower))
        elif load.kind == "moment":
            loads.append(prbm.Couple(_body_for(model, load), tuple(v)))
        elif load.kind == "rotation":
            loads.append(prbm.PrescribedRotation(_body_for(model, load), tuple(np.radians(v))))
        else:
            d = np.asarray(load.direction, float) / math.hypot(*load.direction)
            if abs(d[0]) > 1e-12 and abs(d[1]) > 1e-12:
                raise NotApplicable(f"loads.{i}: a prescribed displacement must be along x or along y")
            axis = "x" if abs(d[0]) > 0.5 else "y"
            loads.append(prbm.PrescribedDisplacement(load.point, axis, tuple(v * (d[0] if axis == "x" else d[1]))))
    return loads


def _received(case, model, result, point: str, level: int) -> np.ndarray:
    """(Fx, Fy, M) received at a node: the applied loads there plus the multipliers of the prescribed
    motions there (the load a driver must apply: minus the multiplier)."""
    total = np.zeros(3)
    n_joint = len(result.states[level].lam) - sum(ld.kind in ("displacement", "rotation") for ld in case.loads)
    k = n_joint
    disp = [ld for ld in case.loads if ld.kind == "displacement"]
    rots = [ld for ld in case.loads if ld.kind == "rotation"]
    lam = result.states[level].lam
    for ld in case.loads:
        if ld.point != point or ld.kind not in ("force", "moment"):
            continue
        v = ld.levels()[level]
        if ld.kind == "force" and ld.toward is not None:
            p = result.position(point, level)
            total[:2] += v * np.array(planar.pull_direction(ld.toward, math.radians(ld.angle), (p[0], p[1])))
        elif ld.kind == "force":
            d = np.asarray(ld.direction, float)
            F = v * d
            if ld.follower:
                phi = result.rotation(model.node_body[point], level)
                c, s = math.cos(phi), math.sin(phi)
                F = np.array([c * F[0] - s * F[1], s * F[0] + c * F[1]])
            total[:2] += F
        else:
            total[2] += v
    for ld in disp:
        if ld.point == point:
            d = np.asarray(ld.direction, float)
            total[0 if abs(d[0]) > 0.5 * math.hypot(*d) else 1] += -lam[k]
        k += 1
    for ld in rots:
        if ld.point == point:
            total[2] += -lam[k]
        k += 1
    return total


_MODELS: dict[str, pb.PRBModel] = {}  # the PRB models built, by geometry and rules (a model is plain data)
_MODELS_KEPT = 64
_LAST: dict[str, tuple] = {}  # the last mechanism object asked for, its rules option and its model


def built_model(mech, given: RulesOptions | None, loads=()) -> pb.PRBModel:
    """The PRB model of the mechanism by the builder's rules; the same geometry and rules give the same
    model, so it is built (and its mobility analysed) once per process."""
    same = _LAST.get("key")
    if same is not None and same[0] is mech and same[1] is loads and same[2] == given:
        return same[3]  # the same mechanism and loads as the last call (a repeated run): no rebuild, no key
    geo, rl = geometry(mech), rules(given, mech, loads)
    key = repr((geo, rl))
    model = _MODELS.get(key)
    if model is None:
        try:
            model = pb.build(geo, rl)
        except prbm.LockedNetwork as exc:
            raise NotApplicable(f"PRB model locked: {exc}") from None
        except ValueError as exc:
            raise NotApplicable(f"PRB model not built: {exc}") from None
        if len(_MODELS) >= _MODELS_KEPT:
            _MODELS.pop(next(iter(_MODELS)))
        _MODELS[key] = model
    _LAST["key"] = (mech, loads, given, model)
    return model


def _body_name(body: str) -> str:
    """A PRB body in the case's words: a rigid link by its name, a beam's PRB link as that beam's."""
    return f"PRB link of beam '{body.removeprefix('prb:')}'" if body.startswith("prb:") else body


def unreachable(exc: UnreachableMotion) -> str:
    """Why the PRB model cannot make a prescribed motion, and what to prescribe instead."""
    load = exc.load
    by = "its joints" if exc.by_joints else "its joints and the motions prescribed before"
    if isinstance(load, prbm.PrescribedRotation):
        name = _body_name(load.body)
        if exc.moves:
            like = ", as a parallelogram's coupler does" if exc.by_joints else ""
            return (
                f"the PRB model's {name} cannot rotate: {by} keep its angle; it only translates{like}: "
                "prescribe a translation"
            )
        return f"the PRB model's {name} cannot rotate: {by} hold it still; prescribe another motion"
    return (
        f"the PRB model's point '{load.point}' cannot move along {load.axis}: {by} hold it there; prescribe "
        f"{'its other component' if exc.moves else 'another motion'}"
    )


def solve_case(case, model: pb.PRBModel) -> prbm.NetworkResult:
    try:
        return prbm.solve(model.network, network_loads(case, model), case.n_levels())
    except UnreachableMotion as exc:
        raise NotApplicable(unreachable(exc)) from None
    except prbm.LockedNetwork as exc:
        raise NotApplicable(f"PRB model locked under the prescribed motions: {exc} ({model.describe()})") from None
    except ValueError as exc:  # a load the PRB model cannot take (e.g. a prescribed rotation of the ground)
        raise NotApplicable(f"PRB model: {exc}") from None


def _support_of(mech, node: str) -> str | None:
    """The support a ground joint at ``node`` belongs to: the node's own, else the one fixed support on
    a rigid link through the node (None when there is none or several)."""
    supported = {s.node for s in mech.supports}
    if node in supported:
        return node
    found = {nd for link in mech.links if node in link.nodes for nd in link.nodes if nd in supported}
    return found.pop() if len(found) == 1 else None


def reaction(case, model: pb.PRBModel, result, node: str, level: int) -> np.ndarray:
    """(R_x, R_y, M) the support at ``node`` exerts on the mechanism (moment about the node, CCW): the sum
    of the loads through the ground joints and springs of that support (``NetworkResult.ground_loads``)."""
    mech = case.mechanism
    if not any(s.node == node for s in mech.supports):
        raise NotApplicable(f"no support at '{node}': reactions are given at supports")
    if model.lock:
        raise NotApplicable(
            "reactions of a locked PRB model: the lock workaround carries the clamp's force "
            "through the pin it moved the pivot to"
        )
    try:
        loads = result.ground_loads(level)
    except ValueError as exc:
        raise NotApplicable(str(exc)) from None
    X = np.array(next((nd.x, nd.y) for nd in mech.nodes if nd.name == node))
    total = np.zeros(3)
    for load in loads:
        recorded = model.ground_nodes.get(load.name)
        owner = _support_of(mech, recorded) if recorded is not None else None
        if owner is None:
            raise NotApplicable(f"the ground joint '{load.name}' belongs to no single support")
        if owner != node:
            continue
        total += (load.fx, load.fy, load.moment)
        if load.at is not None:
            r = np.asarray(load.at, float) - X
            total[2] += r[0] * load.fy - r[1] * load.fx
    return total


def mechanical_advantage(case, options: PrbmOptions, model: pb.PRBModel, result) -> np.ndarray:
    """MA per level as the FEM defines it (``validation/methods/fem_outputs.py``, ``ma = {output,
    direction, input, step, d_i, definition}``): the force the mechanism exerts on the held output
    along ``direction`` over the input load, tangent (a second solve with the input raised) or secant."""
    n = case.n_levels()
    ma = options.ma
    base = fem_outputs.output_force(case, ma, lambda node, lv: reaction(case, model, result, node, lv))
    input_load = case.loads[fem_outputs.input_load_index(case, ma)]
    if ma is not None and ma.definition == "secant":
        return fem_outputs.secant_mechanical_advantage(ma, base, input_load)
    raised_case, delta, _ = fem_outputs.incremented_case(case, ma)
    raised = solve_case(raised_case, model)
    if not raised.converged:
        raise NotApplicable(
            f"mechanical advantage: the solve with the input raised did not converge ({raised.message})"
        )
    up = fem_outputs.output_force(raised_case, ma, lambda node, lv: reaction(raised_case, model, raised, node, lv))
    return fem_outputs.mechanical_advantage(ma, base[:n], up[:n], delta, input_load)


def _value(case, model: pb.PRBModel, result, req, inputs: list, options: PrbmOptions, memo: dict) -> float:
    """One requested value at a converged level (quantity contract)."""
    net = model.network
    q, p, lv = req
    if q in ("x", "y", "dx", "dy"):
        if p not in net.points:
            raise NotApplicable(f"point '{p}' is not in the PRB model")
        xy = result.position(p, lv)
        d = xy - np.asarray(net.points[p][1])
        return float({"x": xy[0], "y": xy[1], "dx": d[0], "dy": d[1]}[q])
    if q == "rotation":
        body = model.node_body[p]
        if body.startswith("prb:"):  # a free beam end riding on its PRB link
            raise NotApplicable(
                f"the rotation of '{p}': the PRB link's angle Theta is not the beam's end "
                "slope (theta_0 = c_theta Theta needs a c_theta the builder's model does not carry)"
            )
        return math.degrees(result.rotation(body, lv))
    if q in ("force_x", "force_y", "moment"):
        return float(_received(case, model, result, p, lv)[("force_x", "force_y", "moment").index(q)])
    if q in ("reaction_x", "reaction_y", "reaction_moment"):
        return float(reaction(case, model, result, p, lv)[("reaction_x", "reaction_y", "reaction_moment").index(q)])
    if q == "strain_energy":
        return result.strain_energy(lv)
    if q in ("input_angle", "input_torque"):
        if not inputs:
            raise NotApplicable("input_angle/input_torque need a prescribed rotation or a moment (the input)")
        if q == "input_torque":
            return float(_received(case, model, result, inputs[0].point, lv)[2])
        return math.degrees(result.rotation(_body_for(model, inputs[0]), lv))
    if q == "mechanical_advantage":
        if "ma" not in memo:
            memo["ma"] = mechanical_advantage(case, options, model, result)
        return float(memo["ma"][lv])
    raise NotApplicable(f"the PRB network gives no '{q}'")


def _flag_deflection(model: pb.PRBModel, result, info: MethodRun, only: int | None = None) -> None:
    """Flag the levels (``only`` that one) where a beam's PRB spring (a fixed-pinned, fixed-free or
    fixed-guided pivot) has turned past the printed Theta range of the fits (``prbm.fits.THETA_RANGE``,
    65 deg)."""
    beam_springs = [
        i for i, sp in enumerate(model.network.springs) if sp.name.endswith(("pivot", "pivot 1", "pivot 2"))
    ]
    if not beam_springs:
        return
    for level, state in enumerate(result.states):
        if only is not None and level != only:
            continue
        if state.converged and np.abs(model.network.spring_deflections(state.q)[beam_springs]).max() > THETA_RANGE:
            info.flag(level, Applicability.DEFLECTION)


def run_mechanism(case, requests, options: PrbmOptions, info: MethodRun) -> dict:
    """Values of the requested outputs of a mechanism case from the PRB model built by rule."""
    if options.rules is not None and options.rules.fixed_guided_fits:
        return _run_fitted(case, requests, options, info)
    model = built_model(case.mechanism, options.rules, case.loads)
    result = solve_case(case, model)
    inputs = [ld for ld in case.loads if ld.kind in ("rotation", "moment")]
    values: dict[Request, float] = {}
    memo: dict[Any, Any] = {}
    for req in requests:
        if result.states[req.level].converged:
            values[req] = _value(case, model, result, req, inputs, options, memo)
    _flag_deflection(model, result, info)
    info.converged = result.converged
    info.level_converged = {i: s.converged for i, s in enumerate(result.states)}
    info.message = f"PRB model built by rule ({result.mobility} DOF): {model.describe()}; {result.message}"
    info.extras.update(
        {
            "prb_model": [
                {
                    "beam": b.beam,
                    "model": str(b.model),
                    "ends": [str(end) for end in b.ends],
                    "pivots": [list(p) for p in b.pivots],
                    "springs": list(b.springs),
                    "gamma": b.gamma,
                    "K_theta": b.K_theta,
                    "reason": b.reason,
                }
                for b in model.beams
            ],
            "lock": model.lock,
            "stable": {i: s.stable for i, s in enumerate(result.states)},
            "spring_torques": {i: result.spring_torques(i) for i, s in enumerate(result.states) if s.converged},
            "iterations": result.iterations,
            "shapes": _shapes(model, result),
        }
    )
    return values


FIT_ITERATIONS = 30
"""Solves at most per level to reach the fixed-guided beams' end-load ratios (``fixed_guided_fits``)."""
FIT_TOLERANCE = 1e-9
"""A beam's ratio n settled: it changed by at most this (times max(1, |n|)) between two solves."""


def guided_ratios(case, model: pb.PRBModel, result, level: int) -> dict[str, float]:
    """Each straight fixed-guided beam's end-load ratio at a solved level: the force its guided end's body
    applies to its PRB link at pivot 2, in the beam's frame (x' along the beam from its root, turned with
    the root's body; y' across it): (-nP, P), n = -F_x'/|F_y'| as ``load_ratios`` reads a free end. A beam
    with no transverse force at its end has none."""
    starts = {beam.name: beam.start for beam in case.mechanism.beams}
    out: dict[str, float] = {}
    for record in model.beams:
        if record.model != pb.BeamChoice.FIXED_GUIDED:
            continue
        (x1, y1), (x2, y2) = record.pivots
        axis = np.array([x2 - x1, y2 - y1]) / math.hypot(x2 - x1, y2 - y1)
        root = model.member_body[(record.beam, starts[record.beam])]
        turn = 0.0 if root == prbm.GROUND else result.rotation(root, level)
        c, s = math.cos(turn), math.sin(turn)
        along = np.array([c * axis[0] - s * axis[1], s * axis[0] + c * axis[1]])
        force = np.array(result.pin_force(level, f"{record.beam} pivot 2"))
        axial, transverse = float(force @ along), float(force @ np.array([-along[1], along[0]]))
        if abs(transverse) > 1e-12 * max(float(np.hypot(*force)), 1e-300):
            out[record.beam] = -axial / abs(transverse)
    return out


def _model_at_ratios(case, given: RulesOptions, ratios: dict[str, float]) -> pb.PRBModel:
    """The PRB model with each fixed-guided beam's gamma(n), K_Theta(n) at ``ratios``."""
    rl = rules(given, case.mechanism, case.loads)
    per_beam = dict(rl.beams)
    for name, n in ratios.items():
        per_beam[name] = replace(per_beam.get(name, pb.BeamRule()), load_ratio=n)
    try:
        return pb.build(geometry(case.mechanism), replace(rl, beams=per_beam))
    except (prbm.LockedNetwork, ValueError) as exc:
        raise NotApplicable(f"PRB model not built at the fixed-guided beams' ratios {ratios}: {exc}") from None


def _first_levels(loads: list[prbm.network.Load], n: int) -> list[prbm.network.Load]:
    """The loads of the first n levels."""
    fields = ("fx", "fy", "m", "values")
    return [replace(ld, **{f: getattr(ld, f)[:n] for f in fields if hasattr(ld, f)}) for ld in loads]


def _fitted_level(case, given: RulesOptions, level: int, model: pb.PRBModel, result) -> tuple:
    """One level's PRB model with its fixed-guided beams at their own end-load ratios: from the ratios of
    ``result`` (the model at the default constants), the model rebuilt at them and solved to this level,
    until no ratio moves by more than FIT_TOLERANCE. Returns (model, result, ratios, settled)."""
    ratios = guided_ratios(case, model, result, level)
    for _ in range(FIT_ITERATIONS):
        model = _model_at_ratios(case, given, ratios)
        try:
            result = prbm.solve(model.network, _first_levels(network_loads(case, model), level + 1), level + 1)
        except ValueError as exc:
            raise NotApplicable(f"PRB model at the fixed-guided beams' ratios: {exc}") from None
        if not result.states[level].converged:
            return model, result, ratios, False
        new = guided_ratios(case, model, result, level)
        settled = new.keys() == ratios.keys() and all(
            abs(new[b] - ratios[b]) <= FIT_TOLERANCE * max(1.0, abs(new[b])) for b in new
        )
        ratios = new
        if settled:
            return model, result, ratios, True
    return model, result, ratios, False


def _run_fitted(case, requests, options: PrbmOptions, info: MethodRun) -> dict:
    """``run_mechanism`` with the option ``rules.fixed_guided_fits``: each level from its own PRB model."""
    assert options.rules is not None  # the option that routes here is one of the rules'
    base = built_model(case.mechanism, options.rules, case.loads)
    start = solve_case(case, base)
    inputs = [ld for ld in case.loads if ld.kind in ("rotation", "moment")]
    values: dict[Request, float] = {}
    shapes: list[list[np.ndarray]] = []
    notes: list[str] = []
    model = base
    for level in range(case.n_levels()):
        if not start.states[level].converged:
            info.level_converged[level] = False
            shapes.append([])
            continue
        model, result, ratios, settled = _fitted_level(case, options.rules, level, base, start)
        ok = bool(result.states[level].converged) and settled
        info.level_converged[level] = ok
        memo: dict[Any, Any] = {}
        for req in requests:
            if req.level == level and ok:
                values[req] = _value(case, model, result, req, inputs, options, memo)
        _flag_deflection(model, result, info, only=level)
        shapes.append(_shapes(model, result)[level])
        told = (
            ", ".join(f"{b} n = {n:.6g}" for b, n in ratios.items())
            or "no fixed-guided beam with a transverse end force"
        )
        notes.append(f"level {level}: {told}" + ("" if settled else " (the ratios did not settle)"))
    info.converged = all(info.level_converged.values())
    info.message = (
        f"PRB model built by rule ({start.mobility} DOF), fixed-guided beams at their own end-load ratios "
        f"(Pauly-Midha fits, iterated per level): {'; '.join(notes)}; last level's model: {model.describe()}"
    )
    info.extras.update(
        {
            "prb_model": [
                {"beam": b.beam, "model": str(b.model), "gamma": b.gamma, "K_theta": b.K_theta, "reason": b.reason}
                for b in model.beams
            ],
            "lock": model.lock,
            "shapes": shapes,
        }
    )
    return values


def _outline(points: np.ndarray) -> np.ndarray:
    """A body's pins and points in an order whose polyline does not cross itself: along the line when
    they are collinear, else around their centroid and closed (a rigid body's outline)."""
    centred = points - points.mean(axis=0)
    if len(points) < 3:
        return points
    _, sizes, axes = np.linalg.svd(centred)
    if sizes[1] <= 1e-9 * sizes[0]:
        return points[np.argsort(centred @ axes[0])]
    order = np.argsort(np.arctan2(centred[:, 1], centred[:, 0]))
    return points[np.append(order, order[0])]


def _shapes(model: pb.PRBModel, result) -> list:
    """Per level, each PRB body as a polyline through its pins and points, around its outline (unloaded
    order, ``_outline``)."""
    net = model.network
    per_body: dict[str, list[str]] = {}
    for name, (body, _) in net.points.items():
        per_body.setdefault(body, []).append(name)
    arms = {}  # body -> its index and the polyline's points relative to its reference point (unloaded)
    for body in net.bodies:
        pts = [p.at for p in net.pins if body in (p.a, p.b)] + [net.points[nm][1] for nm in per_body.get(body, [])]
        if len(pts) >= 2:
            i = net.index[body]
            arms[body] = (i, _outline(np.asarray(pts, float)) - net.X0[i])
    shapes: list[list[np.ndarray]] = []
    for state in result.states:
        if not state.converged:
            shapes.append([])
            continue
        X, phi = net.state_arrays(state.q)
        lines = []
        for i, r in arms.values():
            c, s = math.cos(phi[i]), math.sin(phi[i])
            lines.append(X[i] + np.column_stack([c * r[:, 0] - s * r[:, 1], s * r[:, 0] + c * r[:, 1]]))
        shapes.append(lines)
    return shapes
