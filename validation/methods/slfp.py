"""A PRB mechanism's sprung joints realised as small-length flexural pivots (SLFPs), for the FEM.

Chapter 7 of [bapat2015] designs mechanisms whose compliance sits in SLFPs: a short flexible segment
of length l between two (much longer) rigid segments. Its PRBM ([bapat2015, §2.3.6], Howell 2001)
is a pin at the middle of the flexure with a torsional spring

    k = E I / l                                                    [bapat2015, eq 186]

The dissertation prints k (and E = 450,000 psi for its ANSYS runs) but not l, w or t. Given k and
E, a flexure of length l has I = k l / E; its thickness t and width w only split I = w t^3/12 and
set the axial stiffness E w t (second order for a bending pivot). So one size is truly free, the
flexure length l, and the PRBM's error against the compliant mechanism grows with l / (link
length) (the SLFP model is exact as l -> 0). ``with_flexures`` builds the compliant mechanism for
a chosen l; a sweep over l shows the band of PRBM-vs-FEM error.

Construction, for every joint with a spring k > 0 at pivot node N:
* the flexure is a straight beam of length l centred on N, along u, the unit vector from N towards
  the nearest other node of the joint's last-listed member (the flexure is that member's end);
* between two members: the end N- = N - (l/2) u joins the other members (which take N- in place of
  N), the end N+ = N + (l/2) u joins the last member (which takes N+);
* a single member at a support (a spring to ground): N+ joins the member and N- is the ground side:
  clamped for a pinned support, a guided support (translation along the slider, no rotation) for a
  slider or guided one, i.e. the sliding block;
* the joint itself disappears (the flexure is the hinge) and so does the pivot node N (no material
  there); loads at N move to N+ (the member's side; to N-, the block, at a slider), outputs at N are
  not available.
* a slider whose travel a ``displacement`` load prescribes while a force or moment drives the
  mechanism (a work piece holding the slider at a location, chapter 7's Type 1 MA): the block N- gets
  no support but three prescribed freedoms, the travel along the slider and zero motion across it and
  zero rotation (the FEM prescribes no translation on a sliding node, and the block held there is the
  same thing); its reaction along the slider is the work piece's force.  A travel that is the only
  load stays on the guided block: it is the target of an outer solve (``input_moment_at``).
Section: I = k l / E, thickness t = ``thickness_ratio`` l (default 0.1: slender, t << l << L), width
w = 12 I / t^3.
"""

from __future__ import annotations

import math

from validation.case.schema import BeamSpec, Case, LoadSpec, MechanismSpec, NodeSpec, SectionSpec, SupportSpec


def _unit(dx: float, dy: float) -> tuple[float, float]:
    r = math.hypot(dx, dy)
    return dx / r, dy / r


def _held_block(node: str, direction, travel: list, n_levels: int) -> list:
    """Zero displacement across the slider and zero rotation at a block whose travel is prescribed."""
    if not travel:
        return []
    d = direction or (1.0, 0.0)
    if min(abs(d[0]), abs(d[1])) > 1e-12:
        raise ValueError(f"a held slider at '{node}' must run along x or y (the FEM prescribes axis motions)")
    across = (0.0, 1.0) if abs(d[0]) > abs(d[1]) else (1.0, 0.0)
    zero = [0.0] * n_levels
    return [
        LoadSpec(
            kind="displacement",
            point=node,
            direction=across,
            values=zero,
            label="slider block: no motion across the slider",
        ),
        LoadSpec(kind="rotation", point=node, values=zero, label="slider block: does not turn"),
    ]


def with_flexures(case: Case, length: float, E: float, thickness_ratio: float = 0.1) -> Case:
    """The case with every sprung joint of its mechanism replaced by an SLFP of length ``length``."""
    mech = case.require_mechanism()
    if length <= 0 or E <= 0 or thickness_ratio <= 0:
        raise ValueError("slfp length, E and thickness_ratio must be positive")
    xy = {n.name: (n.x, n.y) for n in mech.nodes}
    members = {b.name: [b.start, b.end] for b in mech.beams} | {lk.name: list(lk.nodes) for lk in mech.links}
    nodes = list(mech.nodes)
    beams = list(mech.beams)
    supports = list(mech.supports)
    joints = []
    extra_loads: list = []
    renamed: dict[str, str] = {}
    for joint in mech.joints:
        if joint.spring <= 0:
            joints.append(joint)
            continue
        N = joint.node
        last = joint.members[-1]
        others = [m for m in members[last] if m != N and m in xy]
        if not others:
            raise ValueError(f"joint at '{N}': member '{last}' has no other node to orient the flexure")
        far = min(others, key=lambda m: math.hypot(xy[m][0] - xy[N][0], xy[m][1] - xy[N][1]))
        ux, uy = _unit(xy[far][0] - xy[N][0], xy[far][1] - xy[N][1])
        if math.hypot(xy[far][0] - xy[N][0], xy[far][1] - xy[N][1]) <= length / 2:
            raise ValueError(f"flexure at '{N}' (length {length:g}) longer than twice the distance to '{far}'")
        minus, plus = f"{N}-", f"{N}+"
        for name, sign in ((minus, -0.5), (plus, 0.5)):
            xy[name] = (xy[N][0] + sign * length * ux, xy[N][1] + sign * length * uy)
            nodes.append(NodeSpec(name=name, x=xy[name][0], y=xy[name][1]))
        I = joint.spring * length / E
        t = thickness_ratio * length
        section = SectionSpec(kind="rectangle", width=12.0 * I / t**3, thickness=t)
        beams.append(BeamSpec(name=f"flexure:{N}", start=minus, end=plus, E=E, section=section))
        members[last] = [plus if m == N else m for m in members[last]]
        for name in joint.members[:-1]:
            members[name] = [minus if m == N else m for m in members[name]]
        renamed[N] = plus
        if len(joint.members) == 1:
            held = [s for s in supports if s.node == N]
            if not held:
                raise ValueError(f"joint at '{N}' springs a single member but '{N}' has no support")
            ground = held[0]
            if ground.kind in ("slider", "guided"):  # a sliding block: it translates, never turns
                renamed[N] = minus  # loads on the pivot act on the block
                driven = any(ld.kind in ("force", "moment") for ld in case.loads)
                held_travel = [ld for ld in case.loads if ld.point == N and ld.kind == "displacement" and driven]
                base = [] if held_travel else [SupportSpec(node=minus, kind="guided", direction=ground.direction)]
                extra_loads += _held_block(minus, ground.direction, held_travel, case.n_levels())
            else:
                base = [SupportSpec(node=minus, kind="fixed")]
            supports = [s for s in supports if s.node != N] + base
    links = [lk.model_copy(update={"nodes": members[lk.name]}) for lk in mech.links]
    beams = [
        b.model_copy(update={"start": members[b.name][0], "end": members[b.name][1]})
        if b.name in members and not b.name.startswith("flexure:")
        else b
        for b in beams
    ]
    supports = [s.model_copy(update={"node": renamed.get(s.node, s.node)}) for s in supports]
    loads = [ld.model_copy(update={"point": renamed.get(ld.point, ld.point)}) for ld in case.loads] + extra_loads
    nodes = [n for n in nodes if n.name not in renamed]
    new_mech = MechanismSpec(nodes=nodes, beams=beams, links=links, joints=joints, supports=supports, E=mech.E)
    return case.model_copy(update={"mechanism": new_mech, "loads": loads})
