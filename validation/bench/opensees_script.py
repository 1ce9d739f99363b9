"""OpenSeesPy driven by a plain script: the peer as an engineer using OpenSeesPy directly runs it.

The benchmark (`validation.bench.headline`) times OpenSeesPy twice: through the harness's adapter
(``validation.methods.opensees``, method ``opensees``), whose time includes the harness's fixed costs
(the case read into a model, the requests, the results), and through this plain script
(``opensees-script``), whose time is the OpenSees calls alone, the way an engineer's script makes them:
nodes and ``elasticBeamColumn`` elements with the Corotational transformation, the supports fixed, the
loads applied as one ``LoadControl`` step per level (halved on failure, the failed tries' iterations
counted, as the adapter does), Newton with NormDispIncr 1e-10, BandGeneral, and the displacement of the
point read at the levels asked (a limit load: ``DisplacementControl`` of the loaded point and a parabola
through the peak of the load factor, as the adapter does).

The script's inputs come from the case, read once before any timing (`script_job`): the problem's numbers
(points, members with their EA and EI, supports, reference loads and load factors) as an engineer writes
them into a script; the script (`run_script`) cuts each beam into its elements itself. It expresses
straight fixed-free segments and mechanisms of straight beams, rigid links (stiff elements from a hub,
``rigid_ratio`` times the stiffest beam) and revolute joints without springs (released element ends, the
joints read as the adapter reads them, `validation.methods.opensees._released`), fixed and pinned
supports, and proportional dead forces and couples at points. Anything else (curved beams, other
boundaries and supports, follower, distributed or prescribed loads, sprung joints) it does not express:
the job says so ("unavailable: ...") and gives no numbers.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from fem.critical import refine_extremum
from validation.case.method_options import OpenSeesOptions, options_of
from validation.methods.base import MethodRun, NotApplicable, Request, RunStatus
from validation.methods.opensees import _ops, _released, load_to
from validation.run.runner import requests_for

SCRIPT = "opensees-script"  # the bench's method label of this peer
PEER = "opensees"  # the adapter whose options (steps per level, halvings, ...) the script takes
NEWTON_TOLERANCE = 1e-10  # NormDispIncr: the norm of the last displacement increment
NEWTON_ITERATIONS = 50
POSITIONS = ("x", "y", "dx", "dy")


class ScriptUnavailable(Exception):
    """The plain script cannot express this case; the message says why."""


@dataclass(frozen=True)
class Member:
    """A straight member between points ``i`` and ``j`` (indices into ``ScriptModel.points``): a beam cut
    into the run's elements, or a rigid link's one stiff element (``divided`` False); ``release`` frees the
    element end at i (1), at j (2) or both (3)."""

    i: int
    j: int
    EA: float
    EI: float
    divided: bool = True
    release: int = 0


@dataclass(frozen=True)
class LimitControl:
    """A limit load by displacement control: the loaded point, its degree of freedom (1 x, 2 y), the
    displacement step, at most ``max_steps`` steps; the load factor times ``scale`` is the load."""

    point: int
    dof: int
    step: float
    max_steps: int
    scale: float


@dataclass(frozen=True)
class ScriptModel:
    """What the engineer writes into the script: the points (node tags 1, 2, ... in this order), the
    members, the supports (point, rotation held), the reference nodal loads (point, Fx, Fy, M) and the load
    factor of each level; the levels and points whose displacement is read (``readings``: (level,
    point)), or the limit-load control; the load stepping (steps per level, halvings on failure)."""

    points: tuple[tuple[float, float], ...]
    members: tuple[Member, ...]
    supports: tuple[tuple[int, bool], ...]
    loads: tuple[tuple[int, float, float, float], ...]
    factors: tuple[float, ...]
    readings: tuple[tuple[int, int], ...] = ()
    limit: LimitControl | None = None
    steps_per_level: int = 1
    max_halvings: int = 12


@dataclass
class ScriptAnswer:
    """What the script gives: the displacement (ux, uy) of each read (level, point), or the limit load
    factor; the Newton iterations (failed tries included), whether it converged and why not, and the CPU
    time of the load stepping alone (without building the model)."""

    displacements: dict[tuple[int, int], tuple[float, float]] = field(default_factory=dict)
    limit_factor: float | None = None
    iterations: int = 0
    converged: bool = True
    message: str = ""
    stepping_s: float = 0.0


# ---------------------------------------------------------------------------------------------------------
# The plain script: OpenSees calls only (timed by the bench).


def run_script(ops, model: ScriptModel, elements: int) -> ScriptAnswer:
    """The plain script on ``elements`` elements per beam (``ops``: the ``openseespy.opensees`` module):
    build the model, step the loads (or drive the limit load), read the displacements."""
    _build(ops, model, elements)
    if model.limit is not None:
        return _limit_load(ops, model.limit)
    return _step_levels(ops, model)


def _build(ops, model: ScriptModel, elements: int) -> None:
    """Nodes, Corotational ``elasticBeamColumn`` elements (E = 1, so A = EA and Iz = EI), supports, loads,
    and the solver: BandGeneral, RCM numbering, NormDispIncr, Newton."""
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for tag, (x, y) in enumerate(model.points, start=1):
        ops.node(tag, x, y)
    ops.geomTransf("Corotational", 1)
    node, element = len(model.points), 0
    for m in model.members:
        (xi, yi), (xj, yj) = model.points[m.i], model.points[m.j]
        n = elements if m.divided else 1
        chain = [m.i + 1]
        for k in range(1, n):
            node += 1
            ops.node(node, xi + (xj - xi) * k / n, yi + (yj - yi) * k / n)
            chain.append(node)
        chain.append(m.j + 1)
        for k in range(n):
            element += 1
            release = (m.release & 1 if k == 0 else 0) + (m.release & 2 if k == n - 1 else 0)
            extra = ("-release", release) if release else ()
            ops.element("elasticBeamColumn", element, chain[k], chain[k + 1], m.EA, 1.0, m.EI, 1, *extra)
    for point, held in model.supports:
        ops.fix(point + 1, 1, 1, 1 if held else 0)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for point, fx, fy, moment in model.loads:
        ops.load(point + 1, fx, fy, moment)
    ops.system("BandGeneral")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test("NormDispIncr", NEWTON_TOLERANCE, NEWTON_ITERATIONS)
    ops.algorithm("Newton")


def _step_levels(ops, model: ScriptModel) -> ScriptAnswer:
    """Each level in ``steps_per_level`` LoadControl steps, a failed step halved and retried (up to
    ``max_halvings`` halvings a level: the adapter's loop of OpenSees calls, `validation.methods.opensees.
    load_to`), the displacements read where asked."""
    answer = ScriptAnswer()
    read: dict[int, list[int]] = {}
    for level, point in model.readings:
        read.setdefault(level, []).append(point)
    ops.analysis("Static")
    current = 0.0
    for level, factor in enumerate(model.factors):
        if factor != current:
            start = time.process_time()
            ok, its, current = load_to(ops, current, factor, model.steps_per_level, model.max_halvings)
            answer.stepping_s += time.process_time() - start
            answer.iterations += its
            if not ok:
                answer.converged = False
                answer.message = (
                    f"OpenSees Newton failed between levels {level - 1} and {level} "
                    f"(load factor {current:.6g} reached, {model.max_halvings} halvings)"
                )
                break
        for point in read.get(level, ()):
            answer.displacements[(level, point)] = (ops.nodeDisp(point + 1, 1), ops.nodeDisp(point + 1, 2))
    return answer


def _limit_load(ops, limit: LimitControl) -> ScriptAnswer:
    """Displacement control of the loaded point until the load factor first falls; the peak of the parabola
    through the last three load factors."""
    answer = ScriptAnswer(converged=False, message="no limit point within max_steps")
    ops.integrator("DisplacementControl", limit.point + 1, limit.dof, limit.step)
    ops.analysis("Static")
    history, start = [0.0], time.process_time()
    for _ in range(limit.max_steps):
        if ops.analyze(1) != 0:
            answer.message = f"OpenSees displacement control failed after {len(history)} steps"
            break
        answer.iterations += ops.testIter()
        history.append(ops.getLoadFactor(1))
        if len(history) > 2 and history[-1] < history[-2]:
            # the adapter's parabola through the three load factors around the peak (our FEM's too)
            peak, _ = refine_extremum(np.arange(-1.0, 2.0), np.asarray(history[-3:]), np.full(3, np.nan))
            answer.limit_factor = float(peak)
            answer.converged, answer.message = True, ""
            break
    answer.stepping_s = time.process_time() - start
    return answer


# ---------------------------------------------------------------------------------------------------------
# The case read into the script's inputs (before any timing), and the answer back as the harness's values.


@dataclass(frozen=True)
class ScriptJob:
    """One configuration of the plain script: its model, the elements per beam, and the requests whose
    values the answer gives, each with the index of its point in the model; or, without a model, why the
    script cannot run it (``reason``)."""

    model: ScriptModel | None
    elements: int
    outputs: tuple[tuple[Request, int], ...] = ()
    reason: str = ""

    def run(self) -> MethodRun:
        """One run, as the harness's values."""
        return self.timed()[0]

    def timed(self) -> tuple[MethodRun, float]:
        """One run and the CPU time of the script alone (`run_script`: not the reading of the case, not the
        conversion of its answer to the harness's values)."""
        if self.model is None:
            return MethodRun(values={}, converged=False, message=self.reason, status=RunStatus.NOT_APPLICABLE), 0.0
        ops = _ops()
        wall = time.perf_counter()
        cpu = time.process_time()
        answer = run_script(ops, self.model, self.elements)
        cpu = time.process_time() - cpu
        wall = time.perf_counter() - wall
        return self.method_run(answer, wall), cpu

    def method_run(self, answer: ScriptAnswer, wall: float = 0.0) -> MethodRun:
        """The answer as the values of the requests: positions in the case's units, the limit load."""
        values: dict[Request, float] = {}
        for r, point in self.outputs:
            if r.quantity == "limit_load":
                if answer.limit_factor is not None and self.model is not None and self.model.limit is not None:
                    values[r] = answer.limit_factor * self.model.limit.scale
            elif (r.level, point) in answer.displacements and self.model is not None:
                (x0, y0), (ux, uy) = self.model.points[point], answer.displacements[(r.level, point)]
                values[r] = {"x": x0 + ux, "y": y0 + uy, "dx": ux, "dy": uy}[r.quantity]
        return MethodRun(
            values=values,
            converged=answer.converged,
            message=answer.message,
            wall_time=wall,
            extras={"iterations": answer.iterations, "analysis_cpu_s": answer.stepping_s},
        )


def script_job(case, elements: int) -> ScriptJob:
    """The plain script's configuration for the case (restricted to what the bench reads) at ``elements``
    elements per beam, with the case's OpenSees options (``[methods.opensees]``) for its load stepping; a
    job that says why not when the script cannot express the case or OpenSeesPy cannot run."""
    requests = tuple(requests_for(case, PEER))
    try:
        _ops()
        model, names = script_model(case, requests, options_of(PEER, case.methods.get(PEER)))
    except (ScriptUnavailable, NotApplicable) as exc:
        return ScriptJob(None, elements, reason=f"unavailable: {exc}")
    return ScriptJob(model, elements, tuple((r, names.get(r.point, -1)) for r in requests))


def script_model(case, requests: tuple[Request, ...], options) -> tuple[ScriptModel, dict[str, int]]:
    """The case as the script's inputs, and its named points -> their index; ScriptUnavailable when the
    script does not express it."""
    assert isinstance(options, OpenSeesOptions)
    bad = next((r.quantity for r in requests if r.quantity not in (*POSITIONS, "limit_load")), None)
    if bad is not None:
        raise ScriptUnavailable(f"the quantity '{bad}' (the script reads positions and limit loads)")
    if case.segment is not None:
        points, names, members, supports = _segment(case.segment)
    else:
        points, names, members, supports = _mechanism(case, options.rigid_ratio)
    loads, factors, scale = _loads(case, names)
    model = ScriptModel(
        tuple(points),
        tuple(members),
        tuple(supports),
        loads,
        factors,
        steps_per_level=options.steps_per_level,
        max_halvings=options.max_halvings,
    )
    if any(r.quantity == "limit_load" for r in requests):
        if any(r.quantity != "limit_load" for r in requests):
            raise ScriptUnavailable("a limit load and positions in one run (the script gives one or the other)")
        model = _with_limit(model, options, scale)
    else:
        model = _with_readings(model, requests, names)
    return model, names


def _segment(seg):
    """A straight fixed-free segment along +x: its root and tip, one beam, the root fixed."""
    if seg.initial_curvature() != 0.0:
        raise ScriptUnavailable("a curved segment (the script writes straight beams)")
    if seg.boundary != "fixed-free":
        raise ScriptUnavailable(f"a {seg.boundary} segment (the script writes a fixed root and a free tip)")
    points = [(0.0, 0.0), (seg.length, 0.0)]
    return points, {"root": 0, "tip": 1}, [Member(0, 1, seg.axial_stiffness(), seg.bending_stiffness())], [(0, True)]


def _mechanism(case, rigid_ratio: float):
    """A mechanism's points, beams, links (stiff elements from a hub) and fixed or pinned supports, with its
    joints as released element ends."""
    mech = case.mechanism
    if any(j.spring for j in mech.joints):
        raise ScriptUnavailable("a sprung joint (the script writes joints as released element ends, without springs)")
    points = [(n.x, n.y) for n in mech.nodes]
    names = {n.name: k for k, n in enumerate(mech.nodes)}
    released = _released(case)
    members = []
    for beam in mech.beams:
        if beam.curvature:
            raise ScriptUnavailable(f"the curved beam '{beam.name}' (the script writes straight beams)")
        EA, EI = beam.section.stiffness(beam.E or mech.E)
        members.append(Member(names[beam.start], names[beam.end], EA, EI, release=_ends(beam, released)))
    if mech.links and not mech.beams:
        raise ScriptUnavailable("rigid links without a beam: no stiffness to scale the links' by")
    stiff = (
        rigid_ratio * max((m.EA for m in members), default=0.0),
        rigid_ratio * max((m.EI for m in members), default=0.0),
    )
    for link in mech.links:
        members += _link(link, released, names, points, stiff)
    supports = []
    for sup in mech.supports:
        if sup.kind not in ("fixed", "pinned"):
            raise ScriptUnavailable(f"a '{sup.kind}' support (the script writes fixed and pinned supports)")
        supports.append((names[sup.node], sup.kind == "fixed"))
    for load in case.loads:
        if load.kind == "moment" and (load.body, load.point) in released:
            raise ScriptUnavailable(f"a couple on the released end of '{load.body}' at '{load.point}'")
    return points, names, members, supports


def _ends(beam, released: set[tuple[str, str]]) -> int:
    """The release code of a beam's ends (1 at its start, 2 at its end)."""
    return (1 if (beam.name, beam.start) in released else 0) + (2 if (beam.name, beam.end) in released else 0)


def _link(link, released, names: dict[str, int], points: list, stiff: tuple[float, float]) -> list[Member]:
    """A rigid link's stiff elements: from its hub (a node where it is not released) to each other node;
    hinged at all its nodes, one element between two, or from a new point at the centroid of three or more."""
    EA, EI = stiff
    free = {node: (link.name, node) in released for node in link.nodes}
    hub = next((node for node in link.nodes if not free[node]), None)
    if hub is not None:
        return [Member(names[hub], names[n], EA, EI, False, 2 * free[n]) for n in link.nodes if n != hub]
    if len(link.nodes) == 2:
        return [Member(names[link.nodes[0]], names[link.nodes[1]], EA, EI, False, 3)]
    points.append(tuple(np.mean([points[names[n]] for n in link.nodes], axis=0)))
    return [Member(len(points) - 1, names[n], EA, EI, False, 2) for n in link.nodes]


def _loads(case, names: dict[str, int]) -> tuple[tuple[tuple[int, float, float, float], ...], tuple[float, ...], float]:
    """Proportional dead forces and couples at points: the reference nodal loads (point, Fx, Fy, M) at load
    factor 1 (the loads at one point summed), each level's load factor, and the scale (the largest load's
    largest magnitude, which load factor 1 is)."""
    if not case.loads:
        raise ScriptUnavailable("no loads")
    for load in case.loads:
        if load.kind not in ("force", "moment"):
            raise ScriptUnavailable(f"a '{load.kind}' load (the script writes dead forces and couples at points)")
        if load.follower or load.toward is not None:
            raise ScriptUnavailable(
                "a force turning with the structure or toward a point (the script writes dead loads)"
            )
        if load.point not in names:
            raise ScriptUnavailable(f"a load at '{load.point}', which is not a point of the model")
    paths = [np.asarray(load.levels(), float) for load in case.loads]
    main = max(paths, key=lambda p: float(np.abs(p).max()))
    scale = float(np.abs(main).max())
    if scale == 0.0:
        raise ScriptUnavailable("every load is zero at every level")
    factors = main / scale
    nodal: dict[int, np.ndarray] = {}
    for load, path in zip(case.loads, paths):
        ratio = _proportion(path, factors)
        vector = nodal.setdefault(names[load.point], np.zeros(3))
        if load.kind == "force":
            vector[:2] += ratio * np.asarray(load.require_direction(), float)
        else:
            vector[2] += ratio
    loads = tuple((point, float(v[0]), float(v[1]), float(v[2])) for point, v in nodal.items())
    return loads, tuple(float(f) for f in factors), scale


def _proportion(path: np.ndarray, factors: np.ndarray) -> float:
    """The load's magnitude at load factor 1; ScriptUnavailable when its path is not proportional to the
    load factors."""
    loaded = factors != 0
    if np.any(~loaded & (path != 0)):
        raise ScriptUnavailable("the load paths are not proportional")
    ratios = path[loaded] / factors[loaded]
    if not np.allclose(ratios, ratios[0]):
        raise ScriptUnavailable("the load paths are not proportional")
    return float(ratios[0])


def _with_readings(model: ScriptModel, requests: tuple[Request, ...], names: dict[str, int]) -> ScriptModel:
    """The model reading the displacement of every requested point at its levels."""
    missing = next((r.point for r in requests if r.point not in names), None)
    if missing is not None:
        raise ScriptUnavailable(f"'{missing}' is not a point of the model")
    readings = tuple(dict.fromkeys((r.level, names[r.point]) for r in requests))
    return replace(model, readings=readings)


def _with_limit(model: ScriptModel, options: OpenSeesOptions, scale: float) -> ScriptModel:
    """The model driving its most loaded point (along its load's larger component) to the limit load: steps
    of ``control_step`` (or 0.002 times the model's largest extent) in the load's sense."""
    point, fx, fy, _ = max(model.loads, key=lambda load: math.hypot(load[1], load[2]))
    dof = 1 if abs(fx) > abs(fy) else 2
    extent = max(np.ptp(np.array(model.points), axis=0))
    step = math.copysign(options.control_step or 0.002 * extent, (fx, fy)[dof - 1])
    limit = LimitControl(point, dof, step, options.max_steps, scale)
    return replace(model, limit=limit)
