"""OpenSeesPy as a peer method: corotational ``elasticBeamColumn`` on the same mesh and load steps.

Only for benchmarking and cross-checks (the ``peer`` extra). It models straight or curved beams
(curved ones as chains of straight elements on the arc), fixed and pinned supports, rigid
corners (beams sharing a node), rigid links, revolute joints without springs, and proportional
dead loads at nodes. Follower loads, sprung joints, prescribed motions and non-proportional paths
are outside it and raise ``NotApplicable``. ``limit_load`` is found with displacement control of
the loaded point.

Rigid links and joints (``_mechanism``), as an OpenSees user builds them for large rotations
(``rigidLink`` is a linear constraint, right only for small rotations): a link is stiff
``elasticBeamColumn`` elements from one of its nodes (its hub) to each other node, their EA and EI
``rigid_ratio`` (as the FEM's own stiff bars) times the stiffest beam's; a revolute joint
releases the end moments of the elements of the members it names at its node (the element's
``-release`` option): all of them when something else holds the node's rotation (a fixed or guided
support, or a member at the node the joint does not name), else all but one, which keeps the node's
rotation (the body a couple at the node acts on, if the joint names it; else the first named). A
link's hub is a node where it is not released (else, with three nodes or more, an extra node at
their centroid), so its elements stay joined rigidly. Every node keeps an element end that holds
its rotation, or a fixed support holds it (a joint releases all its members only where something
else holds the node). A couple on a released member end, and a rotation asked at a node with a
released end (which side's?), are refused.

Load stepping is what a competent user does: ``steps_per_level`` load steps per level (one unless the case
says otherwise; the defaults are ``method_options.OpenSeesOptions``'s), halved on failure (OpenSees reverts the failed try to the last converged state) up to
``max_halvings`` times; the failed tries' iterations are counted and their time is in the wall time.
OpenSees is kept quiet: its log goes to the null device (no warnings on the console) and its
"Process 0 Terminating" at interpreter exit is dropped.
"""

from __future__ import annotations

import atexit
import math
import os
import sys
import time

import numpy as np

from fem.critical import refine_extremum
from validation.case.method_options import OpenSeesOptions
from validation.methods.base import MethodRun, NotApplicable, Request, reject_loads_along_beams
from validation.case.quantities import boundary_held_tip

SUPPORTED = {"x", "y", "dx", "dy", "rotation", "limit_load"}


def _ops():
    try:
        import openseespy.opensees as ops
    except Exception as exc:  # not installed, or a missing system BLAS
        raise NotApplicable(f"OpenSeesPy is not available ({exc})") from None
    global _QUIET
    if not _QUIET:
        ops.logFile(os.devnull, "-noEcho")  # warnings and failed-step messages off the console
        atexit.register(_drop_exit_banner)
        _QUIET = True
    return ops


_QUIET = False


def _drop_exit_banner() -> None:
    """OpenSees prints "Process 0 Terminating" to stderr from a C++ destructor after Python's
    exit handlers: point file descriptor 2 at the null device once everything else is written."""
    sys.stderr.flush()
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 2)
    os.close(null)


def load_to(ops, current: float, target: float, steps: int, max_halvings: int) -> tuple[bool, int, float]:
    """Load control from load factor ``current`` to ``target`` in ``steps`` equal steps, each failed
    step halved and retried (at most ``max_halvings`` halvings in all). Returns (converged, Newton
    iterations including the failed tries', load factor reached)."""
    step = (target - current) / steps
    iterations, halvings = 0, 0
    while abs(target - current) > 1e-12 * max(abs(target), 1.0):
        inc = target - current if abs(target - current) <= abs(step) * (1 + 1e-9) else step
        ops.integrator("LoadControl", inc)
        ok = ops.analyze(1)
        iterations += ops.testIter()
        if ok == 0:
            current += inc
            continue
        halvings += 1
        if halvings > max_halvings:
            return False, iterations, current
        step = inc / 2
    return True, iterations, target


def _geometry(case, elements: int, options: OpenSeesOptions | None = None):
    """Coordinates, nodes (name -> index), elements (i, j, EA, EI, release code) and supports (node ->
    kind)."""
    coords: list[tuple[float, float]] = []
    names: dict[str, int] = {}

    def add(x, y):
        coords.append((x, y))
        return len(coords) - 1

    if case.segment is not None:
        seg = case.segment
        if seg.initial_curvature() != 0.0:
            raise NotApplicable("curved segments are not built for the OpenSees peer")
        held = boundary_held_tip(case)
        if held or seg.boundary == "pinned-pinned":  # the peer builds a clamped root and a free tip only
            raise NotApplicable(
                f"a {seg.boundary} segment (tip {', '.join(held) or 'root pin'} held) is not "
                "built for the OpenSees peer"
            )
        xs = np.linspace(0.0, seg.length, elements + 1)
        idx = [add(x, 0.0) for x in xs]
        names.update(root=idx[0], tip=idx[-1])
        EA, EI = seg.axial_stiffness(), seg.bending_stiffness()
        elems = [(idx[i], idx[i + 1], EA, EI, 0) for i in range(elements)]
        supports = {idx[0]: "fixed"}
        return coords, names, elems, supports
    return _mechanism(case, elements, (options or OpenSeesOptions()).rigid_ratio, coords, names, add)


def _arc_chain(a, b, curvature: float, elements: int) -> list[np.ndarray]:
    """The interior points of a beam from a to b cut into ``elements`` straight elements (on the arc of
    signed ``curvature``, or on the chord)."""
    ts = [k / elements for k in range(1, elements)]
    if not curvature:
        return [a + t * (b - a) for t in ts]
    chord = b - a
    c = float(np.linalg.norm(chord))
    R = 1.0 / curvature
    half = math.asin(min(1.0, c / (2 * abs(R))))
    normal = np.array([-chord[1], chord[0]]) / c
    centre = (a + b) / 2 + normal * math.copysign(abs(R) * math.cos(half), R)
    ang0 = math.atan2(*(a - centre)[::-1])
    sweep = math.copysign(2 * half, R)
    return [centre + abs(R) * np.array([math.cos(ang0 + sweep * t), math.sin(ang0 + sweep * t)]) for t in ts]


def _released(case) -> set[tuple[str, str]]:
    """The (member, node) pairs where a revolute joint releases that member's end at the node (module
    docstring: all named members when something else holds the node's rotation, else all but the
    keeper)."""
    mech = case.mechanism
    at_node: dict[str, list[str]] = {}
    for beam in mech.beams:
        for node in (beam.start, beam.end):
            at_node.setdefault(node, []).append(beam.name)
    for link in mech.links:
        for node in link.nodes:
            at_node.setdefault(node, []).append(link.name)
    holds_rotation = {sup.node for sup in mech.supports if sup.kind in ("fixed", "guided")}
    couples = {(load.point, load.body) for load in case.loads if load.kind == "moment" and load.body}
    released: set[tuple[str, str]] = set()
    for joint in mech.joints:
        if joint.spring:
            raise NotApplicable(f"the sprung joint at '{joint.node}' is not built for the OpenSees peer")
        named = list(dict.fromkeys(joint.members))
        stray = [m for m in named if m not in at_node.get(joint.node, [])]
        if stray:
            raise NotApplicable(f"the joint at '{joint.node}' names '{stray[0]}', which does not reach that node")
        others = [m for m in at_node.get(joint.node, []) if m not in named]
        if joint.node in holds_rotation or others:
            free = named
        elif len(named) >= 2:
            keeper = next((m for m in named if (joint.node, m) in couples), named[0])
            free = [m for m in named if m != keeper]
        else:
            free = []
        released.update((member, joint.node) for member in free)
    return released


def _mechanism(case, elements: int, ratio: float, coords, names, add):
    """A mechanism's nodes, elements (i, j, EA, EI, release code: 1 the end at i, 2 at j, 3 both) and
    supports, with its links and joints (module docstring)."""
    mech = case.mechanism
    for node in mech.nodes:
        names[node.name] = add(node.x, node.y)
    released = _released(case)
    elems, stiffest = [], (0.0, 0.0)

    def element(i: int, j: int, EA: float, EI: float, member: str, start: str | None, end: str | None):
        code = (1 if (member, start) in released else 0) + (2 if (member, end) in released else 0)
        elems.append((i, j, EA, EI, code))

    for beam in mech.beams:
        EA, EI = beam.section.stiffness(beam.E or mech.E)
        stiffest = (max(stiffest[0], EA), max(stiffest[1], EI))
        a, b = np.array(coords[names[beam.start]]), np.array(coords[names[beam.end]])
        chain = [names[beam.start]] + [add(*p) for p in _arc_chain(a, b, beam.curvature, elements)] + [names[beam.end]]
        for k in range(len(chain) - 1):
            element(
                chain[k],
                chain[k + 1],
                EA,
                EI,
                beam.name,
                beam.start if k == 0 else None,
                beam.end if k == len(chain) - 2 else None,
            )
    if mech.links and not mech.beams:
        raise NotApplicable("rigid links without a beam: no stiffness to scale the links' by")
    for link in mech.links:
        EA, EI = ratio * stiffest[0], ratio * stiffest[1]
        hub = next((n for n in link.nodes if (link.name, n) not in released), None)
        if hub is not None:
            for node in link.nodes:
                if node != hub:
                    element(names[hub], names[node], EA, EI, link.name, hub, node)
        elif len(link.nodes) == 2:
            element(names[link.nodes[0]], names[link.nodes[1]], EA, EI, link.name, *link.nodes)
        else:
            centre = add(*np.mean([coords[names[n]] for n in link.nodes], axis=0))
            for node in link.nodes:
                element(centre, names[node], EA, EI, link.name, None, node)
    supports = {}
    for sup in mech.supports:
        if sup.kind not in ("fixed", "pinned"):
            raise NotApplicable(f"'{sup.kind}' supports are not built for the OpenSees peer")
        supports[names[sup.node]] = sup.kind
    for load in case.loads:
        if load.kind == "moment" and (load.body, load.point) in released:
            raise NotApplicable(
                f"a couple on the released end of '{load.body}' at '{load.point}' is not built for the OpenSees peer"
            )
    return coords, names, elems, supports


def _reference_loads(case, names):
    """Proportional loads: a reference nodal load vector and the load factor of each level."""
    if not case.loads:
        raise NotApplicable("no loads")
    paths = []
    for load in case.loads:
        if load.kind not in ("force", "moment") or load.follower:
            raise NotApplicable(f"'{load.kind}{' follower' if load.follower else ''}' loads are outside the peer")
        paths.append(np.asarray(load.levels(), float))
    ref = max(paths, key=lambda p: np.abs(p).max())
    scale = np.abs(ref).max()
    factors = ref / scale
    nodal = {}
    for load, path in zip(case.loads, paths):
        ratio = np.divide(path, factors, out=np.full_like(path, np.nan), where=factors != 0)
        ok = np.isfinite(ratio)
        if not np.allclose(ratio[ok], ratio[ok][0]) or np.any((factors == 0) & (path != 0)):
            raise NotApplicable("load paths are not proportional")
        r = ratio[ok][0]
        vec = nodal.setdefault(names[load.point], np.zeros(3))
        if load.kind == "force":
            vec[:2] += r * np.asarray(load.direction, float)
        else:
            vec[2] += r
    return nodal, factors


def _build(ops, coords, elems, supports, nodal):
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for i, (x, y) in enumerate(coords):
        ops.node(i + 1, x, y)
    for node, kind in supports.items():
        ops.fix(node + 1, 1, 1, 1 if kind == "fixed" else 0)
    ops.geomTransf("Corotational", 1)
    for k, (i, j, EA, EI, release) in enumerate(elems):
        # elasticBeamColumn takes A, E, Iz: pass E = 1 so that A = EA and Iz = EI
        ops.element(
            "elasticBeamColumn", k + 1, i + 1, j + 1, EA, 1.0, EI, 1, *(("-release", release) if release else ())
        )
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for node, vec in nodal.items():
        ops.load(node + 1, *vec)
    ops.system("BandGeneral")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test("NormDispIncr", 1e-10, 50)
    ops.algorithm("Newton")


def run(case, requests: list[Request], options: OpenSeesOptions) -> MethodRun:
    reject_loads_along_beams(case, "the OpenSees peer")
    ops = _ops()
    if any(r.quantity not in SUPPORTED for r in requests):
        bad = next(r.quantity for r in requests if r.quantity not in SUPPORTED)
        raise NotApplicable(f"the OpenSees peer does not give '{bad}'")
    elements, substeps, max_halvings = options.elements, options.steps_per_level, options.max_halvings
    start = time.perf_counter()
    coords, names, elems, supports = _geometry(case, elements, options)
    hinged = {node for i, j, *_, code in elems for node, end in ((i, 1), (j, 2)) if code & end}
    asked = next((r.point for r in requests if r.quantity == "rotation" and names.get(r.point) in hinged), None)
    if asked is not None:
        raise NotApplicable(f"a rotation at '{asked}', where a joint releases a member end (whose rotation?)")
    nodal, factors = _reference_loads(case, names)
    _build(ops, coords, elems, supports, nodal)
    values, iterations, converged, message = {}, 0, True, ""
    wanted: dict[int, list[Request]] = {}
    for r in requests:
        wanted.setdefault(r.level, []).append(r)
    if any(r.quantity == "limit_load" for r in requests):
        node, vec = max(nodal.items(), key=lambda kv: np.hypot(*kv[1][:2]))
        dof = 1 if abs(vec[0]) > abs(vec[1]) else 2
        step = -(options.control_step or 0.002 * max(np.ptp(np.array(coords), axis=0)))
        step = math.copysign(abs(step), vec[dof - 1])
        ops.integrator("DisplacementControl", node + 1, dof, step)
        ops.analysis("Static")
        history, cpu = [0.0], time.process_time()
        for _ in range(options.max_steps):
            if ops.analyze(1) != 0:
                converged, message = False, f"OpenSees displacement control failed after {len(history)} steps"
                break
            iterations += ops.testIter()
            history.append(ops.getLoadFactor(1))
            if len(history) > 2 and history[-1] < history[-2]:
                i = len(history) - 2  # the same parabola through the three points around the peak as our FEM
                peak, _ = refine_extremum(np.arange(-1.0, 2.0), np.asarray(history[i - 1 : i + 2]), np.full(3, np.nan))
                scale = np.abs(np.concatenate([np.atleast_1d(np.asarray(l.levels())) for l in case.loads])).max()
                for r in requests:
                    if r.quantity == "limit_load":
                        values[r] = peak * scale
                break
        else:
            converged, message = False, "no limit point within max_steps"
        return MethodRun(
            values=values,
            converged=converged,
            message=message,
            wall_time=time.perf_counter() - start,
            extras={"iterations": iterations, "analysis_cpu_s": time.process_time() - cpu},
        )
    ops.analysis("Static")
    current, analysis = 0.0, 0.0  # analysis: CPU seconds of the load stepping alone
    for level, factor in enumerate(factors):
        if factor != current:
            cpu = time.process_time()
            ok, its, current = load_to(ops, current, factor, substeps, max_halvings)
            analysis += time.process_time() - cpu
            iterations += its
            if not ok:
                converged = False
                message = (
                    f"OpenSees Newton failed between levels {level - 1} and {level} "
                    f"(load factor {current:.6g} reached, {max_halvings} halvings)"
                )
                break
        for r in wanted.get(level, []):
            tag = names[r.point] + 1
            x0, y0 = coords[tag - 1]
            ux, uy, rz = (ops.nodeDisp(tag, k) for k in (1, 2, 3))
            values[r] = {"x": x0 + ux, "y": y0 + uy, "dx": ux, "dy": uy, "rotation": math.degrees(rz)}[r.quantity]
    return MethodRun(
        values=values,
        converged=converged,
        message=message,
        wall_time=time.perf_counter() - start,
        extras={"iterations": iterations, "analysis_cpu_s": analysis},
    )
