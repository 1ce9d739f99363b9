"""A model that can move without deforming: refused, by name, before any Newton step.

A structure held by its supports has a non-singular reduced stiffness at the unloaded state,
K_0 = T^T B^T D B T (`assembly.System`): T maps the reduced DOFs q to the full ones (supports,
sliders, rigid links, linearised at q = 0), B gives each element's three deformations (stretch and
the two end rotations from the chord) and each joint spring's relative rotation, and D > 0 holds
their stiffnesses (EA / l, the 2 x 2 bending block of EI / l, k). So K_0 v = 0 exactly when B T v = 0:
the model can move without deforming exactly when it has a motion in which every element and every
sprung joint moves as a rigid body. That is a question of kinematics alone, with no stiffness in it:

* the rotation DOFs that an element or a sprung joint (k > 0) ties together turn as one body
  (a rotation class; those tied to a support or to the ground do not turn);
* the translations follow along a spanning forest of the model nodes (members and rigid links as
  edges): t(node) = t(root) + sum_c omega_c perp(A_c(node)), A_c the sum of the reference chords of
  class c on the path from the root, perp(a) = (-a_y, a_x);
* what is left to hold are the unknowns z = (omega_c L_ref for every turning class, t(root) for every
  component), and what holds them: an edge outside the forest closes a loop (two equations), a
  support or a prescribed DOF fixes a translation (one or two).

The model moves freely when that constraint matrix G (dimensionless: lengths over L_ref) has a null
space: a singular value at most ``RCOND`` times the largest one, as `numpy.linalg.matrix_rank` decides
a rank. The margin is wide on both sides: rounding leaves G's entries ~1e-15 relative off, so a
mechanism's singular value is ~1e-14 sigma_max or less; a held model's smallest one is its relative
distance from a singular configuration (a four-bar near a dead-centre position, three hinges nearly
in line), O(1) for any model not built within 1e-10 of one. Neither slenderness nor a soft spring
enters G, so a very slender member or a very soft spring (k > 0) is held, whatever the CPU; what a
spring too soft to carry its load does is the Newton solve's to report. A member moves as one rigid
body exactly when its elements do (they share their interior rotations; nothing else acts at an
interior node), so the graphs and G are of the model's size, not the mesh's: the check's cost does not grow
with the number of elements.

The error names the first DOF in model-node order (ux, uy, rz, then any released member end there)
that the free motions move: its share of the null space, |N^T g_d| for the DOF's row g_d, does not
depend on which basis N of the null space the SVD returned.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .discretise import Discretisation
from .model import Model
from .types import BoolArray, FloatArray, IntArray

if TYPE_CHECKING:
    from .assembly import System

__all__ = ["FreeMotion", "FreeMotions", "RCOND", "check_held", "free_motions"]

RCOND = 1e-10  # a singular value of G at most RCOND * sigma_max counts as zero (a free motion)
NAMED_SHARE = 1e-6  # a DOF is named when its share of the null space exceeds this times the largest


class FreeMotion(ValueError):
    """The model can move as a rigid body (or a mechanism) at the unloaded state."""


@dataclass(frozen=True)
class FreeMotions:
    """The kinematic test's answer: ``count`` independent free motions (0: held), the singular values
    of the constraint matrix G over its largest (``relative_sigma``, ascending; shows how far the model
    is from the boundary), and the DOF the error names (None when held)."""

    count: int
    relative_sigma: FloatArray
    named: str | None

    @property
    def held(self) -> bool:
        return self.count == 0


@dataclass
class _Kinematics:
    """The rigid-body kinematics of a discretisation: rotation class of every reduced DOF (-1: not a
    turning rotation), the forest (component and A of every model node), and the constraint rows."""

    turning: IntArray  # (n_red + 1,) column of z of each reduced rotation DOF, -1: does not turn
    n_turning: int
    component: IntArray  # (n_model_nodes,) component of each model node
    A: FloatArray  # (n_model_nodes, n_turning, 2) chord sums from the root, over L_ref
    rows: FloatArray  # (n_rows, n_z) the constraint matrix G


def _perp(a: FloatArray) -> FloatArray:
    return np.stack([-a[..., 1], a[..., 0]], axis=-1)


def _member_ends(disc: Discretisation) -> tuple[IntArray, IntArray, IntArray, IntArray]:
    """(start node, end node, start rotation DOF, end rotation DOF) of every member (full DOFs): a
    member moves as one rigid body exactly when its elements do, since they share their interior node
    rotations and no support, link or joint acts at an interior node."""
    first = np.array([els[0] for els in disc.member_elements], dtype=int)
    last = np.array([els[-1] for els in disc.member_elements], dtype=int)
    return disc.conn[first, 0], disc.conn[last, 1], disc.edofs[first, 2], disc.edofs[last, 5]


def _rotation_classes(disc: Discretisation) -> tuple[IntArray, int]:
    """Column of z of every reduced DOF that is a rotation at a model node or a member end (-1 for any
    other, and for one tied to the ground), and their number. Members join their two end rotations,
    sprung joints (k > 0) theirs; the dummy reduced index n_red stands for 'held' (a supported or
    prescribed rotation, the ground)."""
    n_red = disc.n_red
    red = disc.I[:, 0]
    _, _, r1, r2 = _member_ends(disc)
    parts = [np.column_stack([red[r1], red[r2]])]
    if len(disc.springs):
        parts.append(red[disc.springs[disc.spring_k > 0.0]])
    pairs = np.concatenate(parts)
    present = np.zeros(n_red + 1, dtype=bool)
    present[pairs.ravel()] = True
    present[red[disc.rot_dof[: disc.n_model_nodes]]] = True
    label = _components(n_red + 1, pairs.tolist())
    rotation = np.append(disc.red_is_rotation, False) & present
    classes = np.unique(label[rotation & (label != label[n_red])])
    column = np.full(label.max() + 1, -1)
    column[classes] = np.arange(len(classes))
    turning = np.where(rotation, column[label], -1)
    turning[label == label[n_red]] = -1
    return turning, len(classes)


def _components(n: int, pairs: list[list[int]]) -> IntArray:
    """Connected-component label of each of n vertices joined by ``pairs`` (union-find with path
    halving; the label is the root's index)."""
    parent = np.arange(n)

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = int(parent[i])
        return i

    for i, j in pairs:
        ri, rj = find(i), find(j)
        if ri != rj:
            parent[max(ri, rj)] = min(ri, rj)
    for i in {i for pair in pairs for i in pair}:
        parent[i] = find(i)
    return parent


def _edges(disc: Discretisation, turning: IntArray) -> tuple[IntArray, IntArray, IntArray, FloatArray]:
    """(a, b, column of z of the edge's rotation or -1, chord b - a) of every member and rigid link."""
    red = disc.I[:, 0]
    a, b, r1, _ = _member_ends(disc)
    cls = turning[red[r1]]
    if len(disc.slaves):
        a, b = np.append(a, disc.masters), np.append(b, disc.slaves)
        cls = np.append(cls, turning[red[disc.rot_dof[disc.masters]]])
    return a, b, cls, disc.X[b] - disc.X[a]


def _forest(n_en: int, a: IntArray, b: IntArray) -> tuple[IntArray, int, list[int], list[tuple[int, int]], BoolArray]:
    """A spanning forest of the graph of the model nodes (n_en of them) joined by members and links:
    component of every node, the nodes in breadth-first order with their tree edge (index, +1 when
    traversed a -> b, -1 when b -> a; -1 for a root), and which edges are outside the forest."""
    adjacency: list[list[int]] = [[] for _ in range(n_en)]
    for e, (i, j) in enumerate(zip(a.tolist(), b.tolist())):
        adjacency[i].append(e)
        adjacency[j].append(e)
    component = np.full(n_en, -1)
    order: list[int] = []
    via: list[tuple[int, int]] = []
    in_tree = np.zeros(len(a), dtype=bool)
    a_list, b_list = a.tolist(), b.tolist()
    n_comp = 0
    for root in range(n_en):
        if component[root] >= 0:
            continue
        component[root] = n_comp
        order.append(root)
        via.append((-1, 0))
        queue = deque([root])
        while queue:
            node = queue.popleft()
            for e in adjacency[node]:
                other, sign = (b_list[e], 1) if a_list[e] == node else (a_list[e], -1)
                if component[other] < 0:
                    component[other] = n_comp
                    in_tree[e] = True
                    order.append(other)
                    via.append((e, sign))
                    queue.append(other)
        n_comp += 1
    return component, n_comp, order, via, ~in_tree


def _translation_held(disc: Discretisation, n_en: int) -> list[tuple[int, FloatArray]]:
    """(node, unit normal) for every direction a support or prescribed motion holds a node's
    translation in: both axes where neither translation maps to an unknown, the slider's normal where
    both map to one unknown t (u = d t). Rigid-link slaves are held through their masters."""
    red, coef, n_red = disc.I[:, 0], disc.C[:, 0], disc.n_red
    slave = np.zeros(n_en, dtype=bool)
    slave[disc.slaves] = True
    held: list[tuple[int, FloatArray]] = []
    for node in np.nonzero(~slave)[0].tolist():
        ix, iy = int(red[2 * node]), int(red[2 * node + 1])
        free = {i for i in (ix, iy) if i != n_red}
        if len(free) == 2:
            continue
        if not free:
            held += [(node, np.array([1.0, 0.0])), (node, np.array([0.0, 1.0]))]
            continue
        d = np.array([coef[2 * node] if ix != n_red else 0.0, coef[2 * node + 1] if iy != n_red else 0.0])
        held.append((node, _perp(d / np.hypot(*d))))
    return held


def _kinematics(disc: Discretisation, L_ref: float) -> _Kinematics:
    n_en = disc.n_model_nodes
    turning, n_turn = _rotation_classes(disc)
    a, b, cls, chord = _edges(disc, turning)
    chord = chord / L_ref
    component, n_comp, order, via, loose = _forest(n_en, a, b)
    A = np.zeros((n_en, n_turn, 2))
    for node, (e, sign) in zip(order, via):
        if e < 0:
            continue
        parent = a[e] if sign > 0 else b[e]
        A[node] = A[parent]
        if cls[e] >= 0:
            A[node, cls[e]] += sign * chord[e]
    n_z = n_turn + 2 * n_comp
    rows: list[FloatArray] = []
    for e in np.nonzero(loose)[0].tolist():  # t(b) - t(a) = omega_c perp(chord): the loop closes
        gap = A[b[e]] - A[a[e]]
        if cls[e] >= 0:
            gap[cls[e]] -= chord[e]
        for axis in (0, 1):
            row = np.zeros(n_z)
            row[:n_turn] = _perp(gap)[:, axis]
            rows.append(row)
    for node, normal in _translation_held(disc, n_en):  # normal . t(node) = 0
        row = np.zeros(n_z)
        row[:n_turn] = _perp(A[node]) @ normal
        root = n_turn + 2 * component[node]
        row[root : root + 2] = normal
        rows.append(row)
    G = np.array(rows).reshape(len(rows), n_z)
    return _Kinematics(turning, n_turn, component, A, G)


def _null_space(G: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(orthonormal basis of the null space of G as columns, singular values over the largest)."""
    n_z = G.shape[1]
    if G.shape[0] == 0:
        return np.eye(n_z), np.zeros(n_z)
    _, sigma, vt = np.linalg.svd(G)
    top = sigma.max() if sigma.size else 0.0
    relative = sigma / top if top > 0.0 else np.zeros_like(sigma)
    rank = int(np.sum(relative > RCOND))
    relative = np.concatenate([relative, np.zeros(n_z - len(sigma))])
    return vt[rank:].T, np.sort(relative)


def _dof_rows(disc: Discretisation, kin: _Kinematics, system: System) -> list[tuple[str, FloatArray]]:
    """(label, g_d) of the DOFs the error may name, in naming order: each model node's ux, uy, rz and
    released member ends; g_d gives the DOF's motion (rotations times L_ref) from z. An interior node
    moves only with its member, whose motion moves one of its end nodes or turns its end rotations."""
    n_z = kin.rows.shape[1]
    red = disc.I[:, 0]
    names = system.model.node_names
    n_en, n_mn = len(disc.X), disc.n_model_nodes
    ends: dict[int, list[tuple[int, int]]] = {}
    released = disc.edofs[:, [2, 5]] >= 3 * n_en
    for e, side in zip(*np.nonzero(released)):
        ends.setdefault(int(disc.conn[e, side]), []).append((int(disc.edofs[e, 3 * side + 2]), int(e)))
    out: list[tuple[str, FloatArray]] = []
    for node in range(n_mn):
        where = names[node]
        root = kin.n_turning + 2 * int(kin.component[node])
        for axis, dof in ((0, "ux"), (1, "uy")):
            g = np.zeros(n_z)
            g[: kin.n_turning] = _perp(kin.A[node])[:, axis]
            g[root + axis] = 1.0
            out.append((f"{where} {dof}", g))
        rotations = [(int(disc.rot_dof[node]), "rz")]
        rotations += [
            (dof, f"rz of member {system.model.members[int(disc.el_member[e])].name!r} (its end at a joint)")
            for dof, e in ends.get(node, [])
        ]
        for full, dof in rotations:
            column = kin.turning[red[full]]
            g = np.zeros(n_z)
            if column >= 0:
                g[column] = 1.0
            out.append((f"{where} {dof}", g))
    return out


_KNOWN: dict[tuple[Any, ...], FreeMotions] = {}  # kinematic signature -> answer, for models solved again
_KNOWN_MAX = 256


def _signature(model: Model) -> tuple[Any, ...]:
    """Everything the answer depends on: node names and coordinates, member ends, joints (which members,
    whether sprung), supports, rigid links and prescribed DOFs; not stiffnesses, loads or meshes."""
    return (
        tuple(model.node_names),
        tuple(model.coords),
        tuple((m.start, m.end, m.name) for m in model.members),
        tuple((j.node, j.members, j.k > 0.0, j.k_ground > 0.0) for j in model.joints),
        tuple((sp.node, sp.kind, sp.direction) for sp in model.supports),
        tuple((rl.master, rl.slave) for rl in model.rigid_links),
        tuple((p.node, p.dof) for p in model.prescribed),
        tuple(sorted({ld.node for ld in model.loads if ld.kind == "moment" or ld.follower})),
    )


def free_motions(system: System) -> FreeMotions:
    """The free motions of the system's model at the unloaded state (module docstring): how many,
    how far the model is from the boundary, and the DOF an error names. A model whose kinematics were
    answered before (a sweep, a benchmark, an error estimate solving one geometry again) gets the same
    answer without the work (``_signature``)."""
    key = _signature(system.model)
    known = _KNOWN.get(key)
    if known is None:
        known = _free_motions(system)
        if len(_KNOWN) >= _KNOWN_MAX:
            _KNOWN.pop(next(iter(_KNOWN)))
        _KNOWN[key] = known
    return known


def _free_motions(system: System) -> FreeMotions:
    disc = system.disc
    kin = _kinematics(disc, system.L_ref)
    N, relative = _null_space(kin.rows)
    if N.shape[1] == 0:
        return FreeMotions(0, relative, None)
    candidates = _dof_rows(disc, kin, system)
    share = np.array([np.linalg.norm(g @ N) for _, g in candidates])
    first = int(np.argmax(share > NAMED_SHARE * share.max()))
    return FreeMotions(N.shape[1], relative, candidates[first][0])


def check_held(system: System) -> None:
    """Raise `FreeMotion` naming a DOF the free motions move when the model can move without
    deforming (`free_motions`)."""
    if system.n == 0:
        return
    motions = free_motions(system)
    if not motions.held:
        raise FreeMotion(_message(motions))


def _message(motions: FreeMotions) -> str:
    count = f"{motions.count} independent motions" if motions.count > 1 else "one motion"
    return (
        f"the model can move without deforming (a rigid-body motion or a mechanism, {count}): "
        f"no stiffness holds {motions.named} at the unloaded state; "
        "add a support, a joint spring or a member there"
    )
