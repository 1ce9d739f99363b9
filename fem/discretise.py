"""Discretisation of a `Model`: element nodes, DOF numbering, constraint map.

Element nodes are the model nodes followed by the interior nodes of every
member.  The full DOF vector is

    u = [ux_0, uy_0, ..., ux_{n-1}, uy_{n-1},  rz_0 ... rz_{n-1},  released rz ...,  ground]

(one node rotation per element node, one extra rotation per member end
released by a revolute joint, and a last always-zero "ground" entry used by
springs to ground).  Rotations are accumulated totals, never wrapped.

Constraints are eliminated exactly (master-slave).  Every full DOF i is
written in terms of the reduced unknowns q as

    u_i = sum_w C[i, w] q[I[i, w]] + u_p,i(load)      (independent DOFs: fixed,
                                                    sliders u = d t, prescribed)
    x_s = x_m + R(theta_m)(X_s - X_m),  theta_s = theta_m      (rigid-link slaves)

so dU/dq has at most two entries per row (``I``, ``C``; the rigid-link
columns depend on theta_m and are refreshed by `System`).  Index ``n_red`` in
``I`` is a dummy column that is dropped.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .local_matrices import member_local_stiffness, prismatic_local_stiffness
from .model import Joint, Member, Model
from .numbering import rcm_order
from .section import Section
from .types import BoolArray, FloatArray, IntArray

__all__ = ["Discretisation", "discretise"]


@dataclass
class Discretisation:
    X: FloatArray  # (n_enodes, 2) reference coordinates of element nodes
    n_model_nodes: int
    conn: IntArray  # (n_el, 2) element node indices
    edofs: IntArray  # (n_el, 6) full DOFs [ux1, uy1, rz1, ux2, uy2, rz2]
    L0: FloatArray  # (n_el,) reference chord lengths
    beta0: FloatArray  # (n_el,) reference chord angles
    ka: FloatArray  # (n_el,) axial stiffness
    kb: FloatArray  # (n_el, 2, 2) bending stiffness
    el_member: IntArray  # (n_el,) owning member
    el_section: list[Section]  # Section at element midpoint (for stresses)
    member_elements: list[IntArray]  # element indices of each member, in order start -> end
    n_full: int  # number of full DOFs (without the ground entry)
    ground: int  # index of the ground entry (= n_full)
    rot_dof: IntArray  # (n_enodes,) node rotation DOF
    rotation_dofs: BoolArray  # all rotation DOFs (bool mask over full DOFs)
    springs: IntArray  # (n_sp, 2) full DOF pairs (second may be ground)
    spring_k: FloatArray  # (n_sp,)
    n_red: int
    I: IntArray  # (n_full+1, 2) reduced indices (dummy = n_red)
    C: FloatArray  # (n_full+1, 2) coefficients
    independent: BoolArray  # bool (n_full+1,): DOF given by the linear map
    prescribed_dofs: IntArray  # (n_p,) full DOFs with prescribed values
    prescribed_values: FloatArray  # (n_p, n_levels)
    constrained: BoolArray  # bool (n_full,): supported or prescribed (reactions)
    slaves: IntArray  # (n_s,) slave element nodes
    masters: IntArray  # (n_s,) their (root) masters
    node_rotation_used: BoolArray  # bool (n_model_nodes,)
    node_first_end_rot: IntArray  # (n_model_nodes,) rotation DOF of first member end
    red_is_rotation: BoolArray  # bool (n_red,)

    @cached_property
    def section_groups(self) -> list[tuple[Section, IntArray]]:
        """(section, element indices) of the elements that share a section (for stresses)."""
        by_id: dict[int, tuple[Section, list[int]]] = {}
        for e, sec in enumerate(self.el_section):
            by_id.setdefault(id(sec), (sec, []))[1].append(e)
        return [(sec, np.array(idx)) for sec, idx in by_id.values()]

    def member_end_dof(self, member: int, node: int) -> int:
        """Full rotation DOF of ``member``'s end at model node ``node`` (released or not)."""
        els = self.member_elements[member]
        for e, side in ((els[0], 0), (els[-1], 1)):
            if self.conn[e, side] == node:
                return int(self.edofs[e, 2 + 3 * side])
        raise ValueError(f"member {member} does not end at node {node}")


def _arc_points(P0: FloatArray, P1: FloatArray, kappa: float, n: int) -> tuple[FloatArray, float | None]:
    """n+1 points along the arc P0 -> P1 of signed curvature kappa; arc length (None when straight: the
    sum of the chords). An arc whose sagitta is below rounding of the chord (|kappa| c / 8 < eps: a
    curvature that underflows the arc's formulas) is straight."""
    d = P1 - P0
    if abs(kappa) * float(np.hypot(*d)) < 8.0 * np.finfo(float).eps:
        # t = np.linspace(0, 1, n + 1), computed as linspace does (t_k = k (1/n), t_n = 1)
        t = np.arange(n + 1) * (1.0 / n)
        t[-1] = 1.0
        return P0 + t[:, None] * d, None
    c = np.hypot(*d)
    chord_angle = np.arctan2(d[1], d[0])
    phi = np.arcsin(kappa * c / 2.0)  # half the turning angle
    S = 2.0 * phi / kappa
    a0 = chord_angle - phi
    s = np.linspace(0.0, S, n + 1)
    pts = P0 + np.column_stack([np.sin(a0 + kappa * s) - np.sin(a0), np.cos(a0) - np.cos(a0 + kappa * s)]) / kappa
    pts[-1] = P1
    return pts, float(S)


def _dof_order(
    n_en: int, conn: IntArray, slaves: IntArray, masters: IntArray, extra_owner: list[int]
) -> IntArray | list[int]:
    """Full DOFs node by node in reverse Cuthill-McKee order (small bandwidth; `numbering`): per node
    [ux, uy, rz] and the released member-end rotations it owns."""
    order = rcm_order(n_en, conn, slaves, masters)
    if not len(extra_owner):
        dofs = np.empty((len(order), 3), dtype=order.dtype)
        dofs[:, 0], dofs[:, 1], dofs[:, 2] = 2 * order, 2 * order + 1, 2 * n_en + order
        return dofs.ravel()
    extras: dict[int, list[int]] = {}
    for k, owner in enumerate(extra_owner):
        extras.setdefault(owner, []).append(3 * n_en + k)
    listed: list[int] = []
    for n in order.tolist():
        listed += [2 * n, 2 * n + 1, 2 * n_en + n] + extras.get(n, [])
    return listed


@dataclass
class _Mesh:
    """Element nodes, connectivity and element properties of every member (per member, joined by
    `_mesh` into ``X`` and ``conn``)."""

    X: FloatArray
    conn: IntArray
    el_member: list[int]
    L0: list[FloatArray]
    beta0: list[FloatArray]
    ka: list[FloatArray]
    kb: list[FloatArray]
    el_section: list[Section]
    member_elements: list[IntArray]


def _member_stiffness(m: Member, lengths: FloatArray) -> tuple[Callable[[float], Section], FloatArray, FloatArray]:
    """Section function of a member and its elements' k_a, k_b (`local_matrices`)."""
    if isinstance(m.section, Section):
        sec = m.section
        a, b = prismatic_local_stiffness(lengths, sec.EA, sec.EI)
        return (lambda xi, sec=sec: sec), a, b
    fn = m.section
    s_nodes = np.concatenate([[0.0], np.cumsum(lengths)])

    def prop(attr: str) -> Callable[[FloatArray], FloatArray]:
        def of(xi: FloatArray) -> FloatArray:
            values: FloatArray = np.vectorize(lambda t: getattr(fn(float(t)), attr))(xi)
            return values

        return of

    a, b = member_local_stiffness(s_nodes, prop("EA"), prop("EI"), intorder=8)
    return fn, a, b


def _mesh(model: Model, refine: int) -> _Mesh:
    """Mesh every member with refine x n_elements elements (a member with ``refined`` False: n_elements)
    (interior nodes after the model nodes)."""
    X = [np.asarray(model.coords, dtype=float).reshape(-1, 2)]
    n_en = model.n_nodes
    conns: list[IntArray] = []
    mesh = _Mesh(np.zeros((0, 2)), np.zeros((0, 2), dtype=int), [], [], [], [], [], [], [])
    first = 0
    for im, m in enumerate(model.members):
        n = m.n_elements * int(refine) if m.refined else m.n_elements
        pts, _ = _arc_points(X[0][m.start], X[0][m.end], m.curvature, n)
        ids = np.arange(n_en - 1, n_en + n)  # [start, interior nodes n_en .. n_en + n - 2, end]
        ids[0], ids[-1] = m.start, m.end
        X.append(pts[1:-1])
        n_en += n - 1
        seg = pts[1:] - pts[:-1]
        lengths = np.hypot(seg[:, 0], seg[:, 1])
        fn, a, b = _member_stiffness(m, lengths)
        mesh.member_elements.append(np.arange(first, first + n))
        first += n
        conn = np.empty((n, 2), dtype=int)
        conn[:, 0], conn[:, 1] = ids[:-1], ids[1:]
        conns.append(conn)
        mesh.el_member += [im] * n
        mesh.L0.append(lengths)
        mesh.beta0.append(np.arctan2(seg[:, 1], seg[:, 0]))
        mesh.ka.append(a)
        mesh.kb.append(b)
        if isinstance(m.section, Section):  # prismatic: one section object for every element
            mesh.el_section += [m.section] * n
        else:
            s_nodes = np.concatenate([[0.0], np.cumsum(lengths)])
            mid = (s_nodes[:-1] + s_nodes[1:]) / 2 / s_nodes[-1]
            mesh.el_section += [fn(float(t)) for t in mid]
    mesh.X = np.concatenate(X) if len(X) > 1 else X[0]
    mesh.conn = _joined(conns, (0, 2), int)
    return mesh


def _joined(parts: list[np.ndarray], empty_shape: tuple[int, ...] = (0,), dtype: type = float) -> np.ndarray:
    """The arrays of every member end to end (the one array itself when there is one member; an empty
    array of ``empty_shape`` when there is none)."""
    if len(parts) == 1:
        return parts[0]
    return np.concatenate(parts) if parts else np.zeros(empty_shape, dtype)


@dataclass
class _Joints:
    """Member-end rotation DOFs (released ends get their own), joint springs, and the owner node of
    every released-end DOF."""

    end_rot: IntArray
    springs: list[tuple[int, int]]
    spring_k: list[float]
    extra_owner: list[int]
    n_full: int


def _joints(model: Model, mesh: _Mesh, rot_dof: IntArray) -> _Joints:
    """Release member ends at revolute joints: a released end turns on its own DOF, tied to the node
    rotation by the joint spring k; an unanchored single member's spring acts to ground."""
    conn = mesh.conn
    end_rot = rot_dof[conn].astype(int)
    out = _Joints(end_rot, [], [], [], 3 * len(mesh.X))
    link_nodes = {n for rl in model.rigid_links for n in (rl.master, rl.slave)}
    rot_held = {sp.node for sp in model.supports if sp.kind in ("fixed", "guided")}
    for j in model.joints:
        at_node = [im for im, m in enumerate(model.members) if j.node in (m.start, m.end)]
        listed: tuple[int, ...] = tuple(at_node) if j.members is None else tuple(j.members)
        # the node rotation is carried by something else than the listed members?
        anchored = j.node in link_nodes or j.node in rot_held or any(im not in listed for im in at_node)
        k_ground = j.k
        if anchored:
            released, k_ground = listed, j.k_ground  # every listed member turns freely (+ spring k)
        elif len(listed) >= 2:
            released, k_ground = listed[1:], j.k_ground  # the first listed member keeps the node rotation
        else:
            released, k_ground = (), j.k_ground + j.k  # a single member: its spring k acts to ground
        for im in released:
            _release(model, mesh, out, im, j, rot_dof)
        if k_ground > 0.0:
            out.springs.append((int(rot_dof[j.node]), -1))
            out.spring_k.append(k_ground)
    return out


def _release(model: Model, mesh: _Mesh, out: _Joints, im: int, j: Joint, rot_dof: IntArray) -> None:
    """Give member ``im``'s end at joint ``j`` its own rotation DOF (the next one)."""
    m = model.members[im]
    if j.node not in (m.start, m.end):
        raise ValueError(f"member {im} does not end at joint node {model.node_names[j.node]}")
    els = mesh.member_elements[im]
    for e, side in ((els[0], 0), (els[-1], 1)):
        if mesh.conn[e, side] == j.node:
            out.end_rot[e, side] = out.n_full
    out.extra_owner.append(j.node)
    if j.k > 0.0:
        out.springs.append((out.n_full, int(rot_dof[j.node])))
        out.spring_k.append(j.k)
    out.n_full += 1


def _rigid_link_roots(model: Model) -> tuple[IntArray, IntArray]:
    """Slave nodes of rigid links and their root masters (chains resolved)."""
    parent: dict[int, int] = {}
    for rl in model.rigid_links:
        if rl.slave in parent:
            raise ValueError(f"node {model.node_names[rl.slave]} is slave of two rigid links")
        parent[rl.slave] = rl.master

    def root(n: int) -> int:
        seen = set()
        while n in parent:
            if n in seen:
                raise ValueError("rigid links form a loop")
            seen.add(n)
            n = parent[n]
        return n

    if not parent:
        return np.zeros(0, dtype=int), np.zeros(0, dtype=int)
    slaves = sorted(parent)
    return np.array(slaves, dtype=int), np.array([root(s) for s in slaves], dtype=int)


def _used_dofs(
    model: Model,
    n_en: int,
    n_full: int,
    edofs: IntArray,
    springs: IntArray,
    rot_dof: IntArray,
    slaves: IntArray,
    masters: IntArray,
) -> BoolArray:
    """Full DOFs that carry stiffness or load: translations, element and spring ends, loaded node
    rotations, rigid-link rotations (the ground entry excluded)."""
    used = np.zeros(n_full + 1, dtype=bool)
    used[edofs.ravel()] = True
    if len(springs):
        used[springs.ravel()] = True
    used[: 2 * n_en] = True
    for ld in model.loads:
        if ld.member is None and (ld.kind == "moment" or ld.follower):
            used[rot_dof[ld.node]] = True
    for s, m in zip(slaves.tolist(), masters.tolist()):
        used[rot_dof[m]] = True
        used[rot_dof[s]] = True
    used[n_full] = False
    return used


@dataclass
class _Held:
    """What the supports and prescribed motions hold."""

    fixed: BoolArray
    constrained: BoolArray
    slider_dirs: dict[int, tuple[float, float]]
    p_dofs: list[int]
    p_vals: list[FloatArray]


def _supports(model: Model, n_full: int, used: BoolArray, rot_dof: IntArray, slaves: IntArray) -> _Held:
    """Fixed, slider and prescribed DOFs."""
    fixed = np.zeros(n_full + 1, dtype=bool)
    fixed[n_full] = True
    fixed[~used] = True
    held = _Held(fixed, np.zeros(n_full, dtype=bool), {}, [], [])
    slave_set = set(slaves.tolist())
    for sp in model.supports:
        if sp.node in slave_set:
            raise ValueError(f"support on rigid-link slave node {model.node_names[sp.node]}: put it on the master")
        n = sp.node
        if sp.kind in ("fixed", "pinned"):
            fixed[2 * n : 2 * n + 2] = True
        else:
            held.slider_dirs[n] = sp.direction
        held.constrained[2 * n : 2 * n + 2] = True
        if sp.kind in ("fixed", "guided"):
            fixed[rot_dof[n]] = True
            held.constrained[rot_dof[n]] = True
    n_lev = model.n_levels if model.prescribed else 1
    for p in model.prescribed:
        if p.node in slave_set:
            raise ValueError("prescribed DOF on a rigid-link slave node")
        dof = 2 * p.node + p.dof if p.dof < 2 else int(rot_dof[p.node])
        if p.node in held.slider_dirs and p.dof < 2:
            raise ValueError("prescribed translation on a slider/guided node is not supported")
        fixed[dof] = True
        held.constrained[dof] = True
        used[dof] = True
        held.p_dofs.append(dof)
        held.p_vals.append(np.broadcast_to(p.values, (n_lev,)) if len(p.values) == 1 else p.values)
    return held


def _constraint_map(
    n_en: int,
    n_full: int,
    order_: IntArray | list[int],
    independent: BoolArray,
    held: _Held,
    rotation_dofs: BoolArray,
    slaves: IntArray,
    masters: IntArray,
    rot_dof: IntArray,
) -> tuple[IntArray, FloatArray, int, BoolArray]:
    """I, C of u_i = sum_w C[i, w] q[I[i, w]] in the DOF ``order`` (free DOFs, sliders u = d t, then
    the rigid-link slave rows copied from their masters); the number of unknowns and which are
    rotations."""
    I = np.empty((n_full + 1, 2), dtype=int)  # every entry not set below: the dummy column n_red
    C = np.zeros((n_full + 1, 2))
    order = np.asarray(order_, dtype=int)
    free = order[independent[order] & ~held.fixed[order]]
    if held.slider_dirs:
        node = np.where(free < 2 * n_en, free // 2, -1)
        slider = np.isin(node, np.array(list(held.slider_dirs), dtype=int))
        keep = ~(slider & (free % 2 == 1))  # a slider's one unknown t sits on its x DOF
        free, slider = free[keep], slider[keep]
    n_red = len(free)
    I[:] = n_red
    I[free, 0] = np.arange(n_red)
    C[free, 0] = 1.0
    if held.slider_dirs:
        for i in free[slider]:  # slider: u = d t on both translations
            I[i + 1, 0] = I[i, 0]
            C[i, 0], C[i + 1, 0] = held.slider_dirs[i // 2]
    red_is_rot = rotation_dofs[free]
    for s, m in zip(slaves.tolist(), masters.tolist()):  # slave rows: copy the master map (+ theta column)
        I[2 * s] = [I[2 * m, 0], I[rot_dof[m], 0]]
        I[2 * s + 1] = [I[2 * m + 1, 0], I[rot_dof[m], 0]]
        C[2 * s] = [C[2 * m, 0], 0.0]
        C[2 * s + 1] = [C[2 * m + 1, 0], 0.0]
        I[rot_dof[s]] = I[rot_dof[m]]
        C[rot_dof[s]] = C[rot_dof[m]]
    return I, C, n_red, red_is_rot


def _first_member_ends(n_mn: int, conn: IntArray, edofs: IntArray, member_elements: list[IntArray]) -> IntArray:
    """Rotation DOF of the first member end at every model node (-1: none): of the element ends
    in the order (element, start before end), the first one at the node. Only member ends lie at model
    nodes (the interior nodes are numbered after them), a member's at its first element's start and its
    last element's end, and the elements are numbered member by member: so the members' (start, end)
    in order, in plain Python (a few members)."""
    first_end = [-1] * n_mn
    for els in member_elements:
        for e, side in ((int(els[0]), 0), (int(els[-1]), 1)):
            node = int(conn[e, side])
            if first_end[node] < 0:
                first_end[node] = int(edofs[e, 3 * side + 2])
    return np.array(first_end, dtype=int)


def _marked(n: int, indices: IntArray) -> BoolArray:
    """Boolean mask of length n, True at the given indices (those in range)."""
    mask = np.zeros(n, dtype=bool)
    mask[indices[(indices >= 0) & (indices < n)]] = True
    return mask


def discretise(model: Model, refine: int = 1) -> Discretisation:
    """Mesh every member with refine x n_elements elements (a member with ``refined`` False keeps
    n_elements); number and constrain the DOFs."""
    n_mn = model.n_nodes
    mesh = _mesh(model, refine)
    X, conn = mesh.X, mesh.conn
    n_en = len(X)
    rot_dof = 2 * n_en + np.arange(n_en)  # node rotations, then released member ends
    joints = _joints(model, mesh, rot_dof)
    n_full = ground = joints.n_full
    springs = np.array(joints.springs, dtype=int).reshape(-1, 2)
    if len(springs):
        springs[springs < 0] = ground
    edofs = np.empty((len(conn), 6), dtype=int)  # per element [ux1, uy1, rz1, ux2, uy2, rz2]
    edofs[:, 0::3] = 2 * conn
    edofs[:, 1::3] = edofs[:, 0::3] + 1
    edofs[:, 2::3] = joints.end_rot
    rotation_dofs = np.zeros(n_full + 1, dtype=bool)
    rotation_dofs[2 * n_en : n_full] = True
    slaves, masters = _rigid_link_roots(model)
    used = _used_dofs(model, n_en, n_full, edofs, springs, rot_dof, slaves, masters)
    independent = np.ones(n_full + 1, dtype=bool)
    independent[ground] = False
    for s in slaves.tolist():
        independent[[2 * s, 2 * s + 1, rot_dof[s]]] = False
    held = _supports(model, n_full, used, rot_dof, slaves)
    order = _dof_order(n_en, conn, slaves, masters, joints.extra_owner)
    I, C, n_red, red_is_rot = _constraint_map(
        n_en, n_full, order, independent, held, rotation_dofs, slaves, masters, rot_dof
    )
    n_lev = model.n_levels
    return Discretisation(
        X=X,
        n_model_nodes=n_mn,
        conn=conn,
        edofs=edofs,
        L0=_joined(mesh.L0),
        beta0=_joined(mesh.beta0),
        ka=_joined(mesh.ka),
        kb=_joined(mesh.kb, (0, 2, 2)),
        el_member=np.array(mesh.el_member, dtype=int),
        el_section=mesh.el_section,
        member_elements=mesh.member_elements,
        n_full=n_full,
        ground=ground,
        rot_dof=rot_dof,
        rotation_dofs=rotation_dofs,
        springs=springs,
        spring_k=np.array(joints.spring_k, dtype=float),
        n_red=n_red,
        I=I,
        C=C,
        independent=independent,
        prescribed_dofs=np.array(held.p_dofs, dtype=int),
        prescribed_values=np.array(held.p_vals, dtype=float).reshape(len(held.p_dofs), n_lev),
        constrained=held.constrained,
        slaves=slaves,
        masters=masters,
        node_rotation_used=(used[rot_dof[:n_mn]] | _marked(n_mn, slaves)) if len(slaves) else used[rot_dof[:n_mn]],
        node_first_end_rot=_first_member_ends(n_mn, conn, edofs, mesh.member_elements),
        red_is_rotation=red_is_rot,
    )
