"""Is a mechanism held? The rigid-body (mobility) check of a case, before any solve.

Every member (beam or rigid link) is taken as a rigid body with a small motion (u, v, w) about its
first node; a motion of the whole model that deforms no beam and stretches no spring costs no
energy, and a model with such a motion cannot be solved for equilibrium (the FEM sees a singular
tangent matrix). The linearised conditions, one row each of a matrix C acting on the stacked body
and node velocities, are

- a member's node moves with it: u_node = u_m + w_m * k x (x_node - x_m)   (2 rows per member node);
- the node's rotation is the member's, unless a spring-free joint at the node releases the member
  (1 row): a beam bends only if its ends turn against each other, and a torsional spring resists;
- a support holds its node: 'fixed' u = v = theta = 0, 'pinned' u = v = 0, 'slider' the component
  normal to its direction, 'guided' that component and theta;
- a prescribed displacement or rotation (the drive of the load path) holds its node's component.

The rigid-body motions are the null space of C. A null vector is reported as the body that moves
most in it and how it moves (a translation along a direction, or a rotation about a point, named
when it is a node), which says the constraint that is missing.

A single segment is one such body, its small motion z = (u, v, L w) about the root (length units:
the rotation times the segment's length L, so every column of C is O(1) and the rank is the same for
any unit of length). The root holds u = v = 0 ('fixed' also w = 0, every boundary but
'pinned-pinned'); the tip (X, Y) holds each freedom its boundary holds and no load frees
(`quantities.boundary_held_tip`: a load frees the tip freedoms it acts on, a follower force or a force
toward a point both components) and each freedom a prescribed motion there holds:

    ux: u - w Y = 0,    uy: v + w X = 0,    rz: w = 0.

A pinned-pinned segment whose tip is held along the chord only (a force across it, a follower force,
a force toward a point) swings about its root pin: a mechanism, rejected before any method runs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from validation.case.quantities import boundary_held_tip, load_dofs
from validation.case.schema import Case, MechanismSpec


@dataclass(frozen=True)
class RigidBodyMode:
    """One way the model moves without deforming: the member that moves most, and how."""

    body: str
    motion: str  # "translates along (0.707, 0.707)" or "rotates about node 'O2'"
    missing: str  # the constraint that would stop it


class _Unknowns:
    """Column index of each unknown: a member's (u, v, w), a node's (u, v, theta)."""

    def __init__(self, mech: MechanismSpec):
        members = [b.name for b in mech.beams] + [l.name for l in mech.links]
        nodes = [n.name for n in mech.nodes]
        self.member = {name: 3 * i for i, name in enumerate(members)}
        self.node = {name: 3 * (len(members) + i) for i, name in enumerate(nodes)}
        self.size = 3 * (len(members) + len(nodes))


def _member_nodes(mech: MechanismSpec) -> dict[str, list[str]]:
    out = {b.name: [b.start, b.end] for b in mech.beams}
    out.update({l.name: list(l.nodes) for l in mech.links})
    return out


def constraint_matrix(case: Case) -> tuple[np.ndarray, _Unknowns, set[str]]:
    """(C, unknowns, node names on some member) of a mechanism case, as described above."""
    mech = case.require_mechanism()
    xy = {n.name: np.array([n.x, n.y]) for n in mech.nodes}
    idx = _Unknowns(mech)
    members = _member_nodes(mech)
    released = {(j.node, m) for j in mech.joints if j.spring == 0.0 for m in j.members}
    rows: list[np.ndarray] = []

    def row(entries: dict[int, float]) -> None:
        r = np.zeros(idx.size)
        for col, value in entries.items():
            r[col] += value
        rows.append(r)

    attached: dict[str, list[str]] = {}
    for member, names in members.items():
        m, origin = idx.member[member], xy[names[0]]
        for name in names:
            attached.setdefault(name, []).append(member)
            n, (rx, ry) = idx.node[name], xy[name] - origin
            row({n: 1.0, m: -1.0, m + 2: ry})  # u_node = u_m - w_m * ry
            row({n + 1: 1.0, m + 1: -1.0, m + 2: -rx})  # v_node = v_m + w_m * rx
            if (name, member) not in released:
                row({n + 2: 1.0, m + 2: -1.0})
    turning = {name for name, ms in attached.items() if any((name, m) not in released for m in ms)}
    for name in xy:
        if name not in turning:  # no member turns with this node: its rotation is no unknown
            row({idx.node[name] + 2: 1.0})
    for sup in mech.supports:
        n = idx.node[sup.node]
        d = np.asarray(sup.direction or (1.0, 0.0), float)
        normal = np.array([-d[1], d[0]]) / np.linalg.norm(d)
        if sup.kind in ("fixed", "pinned"):
            row({n: 1.0})
            row({n + 1: 1.0})
        else:
            row({n: normal[0], n + 1: normal[1]})
        if sup.kind in ("fixed", "guided"):
            row({n + 2: 1.0})
    for load in case.loads:
        if load.point not in idx.node:
            continue
        n = idx.node[load.point]
        if load.kind == "rotation":
            row({n + 2: 1.0})
        elif load.kind == "displacement":
            d = np.asarray(load.direction, float)
            row({n: d[0], n + 1: d[1]})
    C = np.vstack(rows) if rows else np.zeros((0, idx.size))
    return C, idx, set(attached)


def _describe(vector: np.ndarray, idx: _Unknowns, mech: MechanismSpec) -> RigidBodyMode:
    members = _member_nodes(mech)
    xy = {n.name: np.array([n.x, n.y]) for n in mech.nodes}
    scale = max(1e-12, max(np.ptp([p[0] for p in xy.values()]), np.ptp([p[1] for p in xy.values()])))

    def speed(member: str) -> float:
        u, v, w = vector[idx.member[member] : idx.member[member] + 3]
        return math.hypot(u, v) + abs(w) * scale

    body = max(members, key=speed)
    u, v, w = vector[idx.member[body] : idx.member[body] + 3]
    origin = xy[members[body][0]]
    if abs(w) * scale < 1e-9 * max(math.hypot(u, v), 1e-300):
        direction = np.array([u, v]) / math.hypot(u, v)
        direction = np.where(np.abs(direction) < 1e-9, 0.0, direction) + 0.0  # no -0 or 1e-15 in the message
        return RigidBodyMode(
            body,
            f"translates along ({direction[0]:.3g}, {direction[1]:.3g})",
            "a support or member holding that direction",
        )
    centre = origin + np.array([-v, u]) / w
    near = min(xy, key=lambda name: np.linalg.norm(xy[name] - centre))
    if np.linalg.norm(xy[near] - centre) <= 1e-6 * scale:
        return RigidBodyMode(
            body,
            f"rotates about node '{near}'",
            f"a rotational restraint at '{near}' (a fixed support, a joint spring or a prescribed rotation)",
        )
    return RigidBodyMode(
        body, f"rotates about ({centre[0]:.4g}, {centre[1]:.4g})", "a support or member resisting that rotation"
    )


def null_space(C: np.ndarray, rcond: float = 1e-10) -> np.ndarray:
    """Orthonormal basis of the null space of C (columns), from its singular value decomposition."""
    if C.shape[0] == 0:
        return np.eye(C.shape[1])
    _, sigma, vt = np.linalg.svd(C)
    rank = int(np.sum(sigma > rcond * sigma.max())) if sigma.size else 0
    return vt[rank:].T


def rigid_body_modes(case: Case) -> list[RigidBodyMode]:
    """Every independent rigid-body motion of a mechanism case (empty when it is held)."""
    C, idx, _ = constraint_matrix(case)
    basis = null_space(C)
    return [_describe(basis[:, k], idx, case.require_mechanism()) for k in range(basis.shape[1])]


def segment_tip(length: float, curvature: float) -> np.ndarray:
    """The unloaded tip (X, Y) of a segment from the root at the origin along +x (an arc if curved)."""
    if curvature == 0.0:
        return np.array([length, 0.0])
    return np.array([math.sin(curvature * length), 1.0 - math.cos(curvature * length)]) / curvature


def segment_constraint_matrix(case: Case) -> np.ndarray:
    """C of a segment case acting on z = (u, v, L w), its rigid motion about the root (see above)."""
    seg = case.require_segment()
    X, Y = segment_tip(seg.length, seg.initial_curvature()) / seg.length
    rows = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    if seg.boundary != "pinned-pinned":
        rows.append([0.0, 0.0, 1.0])
    prescribed = {
        dof
        for load in case.loads
        if load.point == "tip" and load.kind in ("displacement", "rotation")
        for dof in load_dofs(load)
    }
    tip_rows = {"ux": [1.0, 0.0, -Y], "uy": [0.0, 1.0, X], "rz": [0.0, 0.0, 1.0]}
    rows += [tip_rows[dof] for dof in ("ux", "uy", "rz") if dof in set(boundary_held_tip(case)) | prescribed]
    return np.array(rows)


def segment_check(case: Case) -> list[tuple[str, str]]:
    """(field, problem) for a segment that can move as a rigid body under its boundary and loads: a
    pinned-pinned segment whose tip is held along the chord only swings about its root pin (the only
    rigid motion the root pin leaves)."""
    if null_space(segment_constraint_matrix(case)).shape[1] == 0:
        return []
    turning = [
        f"loads.{i} ({'a follower force' if load.follower else 'a force toward a point'})"
        for i, load in enumerate(case.loads)
        if load.point == "tip" and load.kind == "force" and (load.follower or load.toward is not None)
    ]
    why = (
        f"{' and '.join(turning)} turns with the tip and frees both of its components"
        if turning
        else "no load or prescribed motion holds the tip across the chord"
    )
    return [
        (
            "segment",
            f"a {case.require_segment().boundary} segment swings about its root pin, its tip free across "
            f"the chord: hold the tip or load it along the chord; {why}, so the case has a rigid-body motion "
            "(only a force of fixed direction along the chord leaves the tip held across it)",
        )
    ]


def check(case: Case) -> list[tuple[str, str]]:
    """(field, problem) for each node on no member and for a mechanism or segment that can move as a
    rigid body."""
    if case.segment is not None:
        return segment_check(case)
    if case.mechanism is None:
        return []
    mech = case.mechanism
    _, _, on_members = constraint_matrix(case)
    problems = [
        (f"mechanism.nodes.{i}", f"node '{n.name}' belongs to no beam or link")
        for i, n in enumerate(mech.nodes)
        if n.name not in on_members
    ]
    if problems:
        return problems
    modes = rigid_body_modes(case)
    if modes:
        mode = modes[0]
        more = f" ({len(modes)} independent rigid-body motions)" if len(modes) > 1 else ""
        problems.append(
            (
                "mechanism",
                f"case '{case.case.id}': body '{mode.body}' {mode.motion} without "
                f"deforming anything{more}; missing constraint: {mode.missing}",
            )
        )
    return problems
