"""The PRBM adapter's chapter-5 part: fixed-guided segments with one inflection point on one rigid coupler.

A ``[mechanism]`` whose beams are all fixed-guided segments with one inflection point
(``segment_type = 'fixed-guided-inflection'``, or ``[methods.prbm] segment_model = 'inflection'``),
each clamped at one end by a 'fixed' support and rigidly attached at the other to one rigid link (the
coupler), driven by a prescribed translation of a coupler node along one direction and a prescribed
rotation of the coupler: the verification of [bapat2015, §5.5] (Examples 2 and 3, Tables 5.5-5.6:
"specifying the transverse deflection and rotation of the rigid coupler"), the other translation free.
The model is ``prbm.inflection_coupler`` (every segment the chapter-3/5 three-pivot PRBM, eqs
(131)-(152); the free translation from the coupler's equilibrium along it).

Outputs at any coupler node (quantity contract): x, y, dx, dy (global, from the unloaded pose),
rotation (of the coupler, deg); strain_energy (the PRBM springs, eq 165); force_x, force_y, moment at
the driven node (the load the prescribed motions need there; moment CCW). A level with no motion is
the unloaded pose. Where the PRBM has no state within its fits at a loaded level, that level has no
value and says why (each segment's reachable window of the free translation; the run is then not
converged, per level); where it has none at any loaded level, NotApplicable with those reasons.
"""

from __future__ import annotations

import cmath
import math

from prbm.inflection_coupler import CouplerDrive, GuidedSegment, solve_coupler
from prbm.result import PRBMResult
from validation.case.method_options import PrbmOptions
from validation.methods.base import MethodRun, NotApplicable, Request

INFLECTION_TYPES = ("fixed-guided-inflection", "inflection")


def applies(case, options: PrbmOptions) -> bool:
    """Is the mechanism a set of inflection fixed-guided segments on one coupler, driven by a prescribed
    translation and rotation of the coupler? (The shape this module models; anything else is not its.)"""
    mech = case.mechanism
    if mech is None or not mech.beams or len(mech.links) != 1 or mech.joints:
        return False
    inflection = options.segment_model == "inflection"
    if not all(b.segment_type in INFLECTION_TYPES or (b.segment_type is None and inflection) for b in mech.beams):
        return False
    kinds = {ld.kind for ld in case.loads}
    return kinds == {"displacement", "rotation"} and len(case.loads) == 2 and len(mech.supports) == len(mech.beams)


def _segments(case) -> tuple[list[GuidedSegment], set[str]]:
    """Each beam as a GuidedSegment (root at its fixed support), and the coupler's nodes."""
    mech = case.mechanism
    nodes = {nd.name: complex(nd.x, nd.y) for nd in mech.nodes}
    fixed = {s.node for s in mech.supports if s.kind == "fixed"}
    coupler = set(mech.links[0].nodes)
    segments = []
    for beam in mech.beams:
        root, end = (beam.start, beam.end) if beam.start in fixed else (beam.end, beam.start)
        if root not in fixed or end not in coupler:
            raise NotApplicable(
                f"beam '{beam.name}' is not clamped at one end and held by the coupler "
                f"'{mech.links[0].name}' at the other"
            )
        EI = beam.section.stiffness(beam.E or mech.E)[1]
        segments.append(GuidedSegment(beam.name, nodes[root], nodes[end], EI))
    return segments, coupler


def _drive_loads(case, coupler: set[str]):
    """(point, direction, translations, rotations in rad) of the prescribed coupler motion."""
    shift = next(ld for ld in case.loads if ld.kind == "displacement")
    turn = next(ld for ld in case.loads if ld.kind == "rotation")
    if shift.point not in coupler or (turn.body not in (None, case.mechanism.links[0].name)):
        raise NotApplicable("the prescribed translation and rotation must act on the coupler")
    return shift.point, complex(*shift.direction), shift.levels(), [math.radians(v) for v in turn.levels()]


def run_coupler(case, requests: list[Request], info: MethodRun) -> dict:
    """Solve every needed level and pick the requested outputs."""
    segments, coupler = _segments(case)
    point, along, shifts, turns = _drive_loads(case, coupler)
    nodes = {nd.name: complex(nd.x, nd.y) for nd in case.mechanism.nodes}
    P0 = nodes[point]
    results: dict[int, PRBMResult | None] = {}  # None: an unloaded level, the free pose
    messages: list[str] = []
    failed: list[str] = []
    for lv in sorted({r.level for r in requests}):
        if shifts[lv] == 0.0 and turns[lv] == 0.0:
            results[lv] = None
            continue
        res = solve_coupler(segments, CouplerDrive(P0, along, shifts[lv], turns[lv]))
        results[lv] = res
        (messages if res.converged else failed).append(f"level {lv}: {res.message}")
    solved = {lv for lv, res in results.items() if res is not None and res.converged}
    if failed and not solved:
        raise NotApplicable("; ".join(failed))
    values = {}
    for req in requests:
        if results[req.level] is None or req.level in solved:
            values[req] = _value(req, results[req.level], nodes, P0, point, along, shifts[req.level], turns[req.level])
    info.converged = not failed
    info.level_converged = {lv: res is None or lv in solved for lv, res in results.items()}
    info.level_messages = {lv: "unloaded" if res is None else res.message for lv, res in results.items()}
    info.message = "; ".join(failed + messages) or "unloaded"
    info.extras.update(
        {
            "model": "fixed-guided segments with one inflection point on a rigid coupler, seed 000 "
            "eqs (131)-(152), section 5.5",
            "windows": {
                lv: {w.segment: None if w.empty else [w.low, w.high] for w in r.extras["windows"]}
                for lv, r in results.items()
                if r is not None
            },
        }
    )
    return values


def _value(
    req: Request, res, nodes: dict, P0: complex, point: str, along: complex, shift: float, gamma: float
) -> float:
    """One output of one level (res None: the unloaded pose)."""
    if req.point not in nodes and req.quantity not in ("strain_energy",):
        raise NotApplicable(f"point '{req.point}' is not a node of the mechanism")
    t = 0.0 if res is None else float(res.outputs["t"])
    drive = CouplerDrive(P0, along, shift, gamma)
    P = drive.position(t) if res is not None else P0
    if req.quantity == "strain_energy":
        return 0.0 if res is None else float(res.outputs["strain_energy"])
    if req.quantity in ("x", "y", "dx", "dy", "rotation"):
        z = P + (nodes[req.point] - P0) * cmath.exp(1j * gamma)
        return {
            "x": z.real,
            "y": z.imag,
            "dx": (z - nodes[req.point]).real,
            "dy": (z - nodes[req.point]).imag,
            "rotation": math.degrees(gamma),
        }[req.quantity]
    if req.quantity in ("force_x", "force_y", "moment") and req.point == point:
        if res is None:
            return 0.0
        u = along / abs(along)
        force = complex(float(res.outputs["force_along"]), 0.0) * u
        return {"force_x": force.real, "force_y": force.imag, "moment": float(res.outputs["moment"])}[req.quantity]
    raise NotApplicable(f"the chapter-5 coupler PRBM gives no '{req.quantity}' at '{req.point}'")
