"""A planar frame/mechanism model as plain data.

The model is what the user describes; nothing is discretised here.

* Nodes carry a name and reference coordinates (x, y) in consistent length units.
* A member is a flexible beam between two nodes, subdivided into
  ``n_elements`` straight corotational elements.  An initially curved member
  is a circular arc of signed curvature ``curvature`` (1/length; positive when
  the member turns counter-clockwise from start to end, i.e. the centre of
  curvature lies to the left of the chord start -> end); it must subtend less
  than 180 degrees (split longer arcs); its elements are chords of the arc.
  ``section`` is a `Section`, or a callable xi -> Section
  (xi in [0, 1] along the member) for a tapered member.
* A rigid link makes node ``slave`` move with node ``master`` as one rigid
  body: x_s = x_m + R(theta_m)(X_s - X_m), theta_s = theta_m (exact, nonlinear
  master-slave elimination, no penalty).
* By default all members meeting at a node are rigidly connected (one
  rotation, the node rotation).  A revolute joint lets the listed members
  (default: all members at the node) turn relative to each other, with a
  torsional spring of stiffness ``k`` (moment/rad) on each hinge:
  - if something else carries the node rotation (an unlisted member, a rigid
    link, a fixed or guided support), every listed member is released and
    sprung to the node rotation;
  - otherwise the first listed member keeps the node rotation and the others
    are released and sprung to it;
  - a single listed member with nothing else at the node (a ground pivot):
    ``k`` acts between the member and the ground.
  ``k_ground`` ties the node rotation to the ground.  Moments and prescribed
  rotations at the node act on the node rotation.
* Supports: ``fixed`` (u = v = theta = 0), ``pinned`` (u = v = 0),
  ``slider`` (roller: only translation along ``direction``), ``guided``
  (theta = 0, translation along ``direction`` only).
* Loads have one value per load level (arrays of length n_levels; a scalar
  is broadcast): forces of fixed direction, follower forces (rotate with the
  node rotation, or with one member's end rotation at the node), moments,
  forces toward a fixed point (a rope over a pulley; optionally at a fixed
  angle to the line to that point), uniform distributed loads per unit
  reference length on a member or on all members (dead, or follower turning
  with each element's chord; `distributed`), and prescribed
  displacements/rotations of a DOF ("ux", "uy" or "rz").

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any, Callable, SupportsInt, TypeAlias, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .section import Section
from argcheck import checked
from planar.geometry import SUPPORT_KINDS

__all__ = [
    "Model",
    "Member",
    "Support",
    "Joint",
    "RigidLink",
    "PointLoad",
    "PointedForce",
    "DistributedLoad",
    "Prescribed",
]

DOF_NAMES = {"ux": 0, "uy": 1, "rz": 2}

#: a node given by its name or its index
NodeRef: TypeAlias = str | int | np.integer[Any]


@dataclass
class Member:
    start: int
    end: int
    section: Union[Section, Callable[[float], Section]]
    n_elements: int = 8
    curvature: float = 0.0
    name: str = ""
    refined: bool = True  # False: n_elements on every mesh of a refinement study (`discretise`)


@dataclass
class Support:
    node: int
    kind: str
    direction: tuple[float, float] = (1.0, 0.0)


@dataclass
class Joint:
    node: int
    members: tuple[int, ...] | None = None
    k: float = 0.0
    k_ground: float = 0.0


@dataclass
class RigidLink:
    master: int
    slave: int


@dataclass
class PointLoad:
    node: int
    kind: str  # "force" or "moment"
    values: NDArray[np.float64]  # shape (n_levels, 2) for forces, (n_levels,) for moments
    follower: bool = False
    member: int | None = None  # a moment on this member's end (its released rotation at a joint);
    # a follower force turning with this member's end rotation


@dataclass
class PointedForce:
    """A force of magnitude ``values`` (per level) from a node toward a fixed point ``toward``,
    turned by ``angle`` (rad, counter-clockwise) from that line: a rope over a pulley (angle 0), or a
    force that stays at a fixed angle to the line joining a fixed pivot (angle pi/2)."""

    node: int
    values: NDArray[np.float64]  # (n_levels,)
    toward: tuple[float, float]
    angle: float = 0.0


@dataclass
class DistributedLoad:
    """Uniform load per unit reference length, (qx, qy) per level, on one member or all (None).

    A follower load is given in the reference orientation and turns with each element's chord."""

    values: NDArray[np.float64]  # (n_levels, 2)
    member: int | None = None
    follower: bool = False


@dataclass
class Prescribed:
    node: int
    dof: int
    values: NDArray[np.float64]


def _levels(values: ArrayLike) -> NDArray[np.float64]:
    return np.atleast_1d(np.asarray(values, dtype=float))


@dataclass
class Model:
    """Plain-data description of a planar compliant mechanism or frame."""

    node_names: list[str] = field(default_factory=list)
    coords: list[tuple[float, float]] = field(default_factory=list)
    members: list[Member] = field(default_factory=list)
    supports: list[Support] = field(default_factory=list)
    joints: list[Joint] = field(default_factory=list)
    rigid_links: list[RigidLink] = field(default_factory=list)
    loads: list[PointLoad] = field(default_factory=list)
    prescribed: list[Prescribed] = field(default_factory=list)
    pointed: list[PointedForce] = field(default_factory=list)
    distributed: list[DistributedLoad] = field(default_factory=list)

    # -- building -------------------------------------------------------
    def node(self, name: NodeRef) -> int:
        """Index of a node given by name (or index)."""
        if isinstance(name, (int, np.integer)):
            return int(name)
        try:
            return self.node_names.index(str(name))
        except ValueError:
            raise KeyError(f"no node named {name!r}") from None

    @checked(positive=(), finite=("x", "y"))
    def add_node(self, name: str, x: float, y: float) -> int:
        if str(name) in self.node_names:
            raise ValueError(f"node {name!r} already exists")
        self.node_names.append(str(name))
        self.coords.append((float(x), float(y)))
        return len(self.node_names) - 1

    @checked(positive=("n_elements",), finite=("curvature",))
    def add_member(
        self,
        start: NodeRef,
        end: NodeRef,
        section: Union[Section, Callable[[float], Section]],
        n_elements: int = 8,
        curvature: float = 0.0,
        name: str = "",
        refined: bool = True,
    ) -> int:
        """Flexible member start -> end; returns its index. ``refined=False``: the member keeps its
        ``n_elements`` when the mesh is refined (`discretise`'s ``refine``, the error estimate's finer
        meshes), e.g. a very stiff straight bar standing for a rigid body, whose one element has no
        discretisation error worth estimating and whose refinement only adds stiff, ill-conditioned
        unknowns."""
        i, j = self.node(start), self.node(end)
        if i == j:
            raise ValueError("a member needs two different nodes")
        if n_elements < 1:
            raise ValueError("n_elements must be >= 1")
        (xi, yi), (xj, yj) = self.coords[i], self.coords[j]
        chord = math.hypot(xj - xi, yj - yi)  # checked only, not stored
        if not chord > 0.0:
            raise ValueError(f"add_member: nodes {start!r} and {end!r} coincide (zero length)")
        if abs(curvature) * chord / 2 > 1.0:
            raise ValueError("curvature too large for the chord length")
        self.members.append(
            Member(i, j, section, int(n_elements), float(curvature), name or f"m{len(self.members)}", bool(refined))
        )
        return len(self.members) - 1

    def add_support(
        self, node: NodeRef, kind: str, direction: Sequence[float] | NDArray[np.float64] = (1.0, 0.0)
    ) -> None:
        """kind: 'fixed', 'pinned', 'slider' (free along direction), 'guided'."""
        if kind not in SUPPORT_KINDS:
            raise ValueError(f"support kind must be one of {SUPPORT_KINDS}")
        if type(direction) is tuple and direction == (1.0, 0.0):
            unit = (1.0, 0.0)  # the default (a fixed or pinned support's unused direction): exact
        else:
            d = np.asarray(direction, dtype=float)
            d = d / math.sqrt(d.dot(d))  # = d / np.linalg.norm(d), the same dot and square root
            unit = (float(d[0]), float(d[1]))
        self.supports.append(Support(self.node(node), kind, unit))

    def add_joint(
        self,
        node: NodeRef,
        members: Iterable[SupportsInt] | None = None,
        k: float | None = 0.0,
        k_ground: float | None = 0.0,
    ) -> None:
        """Revolute joint at node between `members` (indices; default all at the
        node), torsional springs k (between members) and k_ground (moment/rad)."""
        mem = None if members is None else tuple(int(m) for m in members)
        self.joints.append(Joint(self.node(node), mem, float(k or 0.0), float(k_ground or 0.0)))

    def add_rigid_link(self, master: NodeRef, slave: NodeRef) -> None:
        self.rigid_links.append(RigidLink(self.node(master), self.node(slave)))

    @checked(positive=(), finite=("values_x", "values_y"))
    def add_force(
        self, node: NodeRef, values_x: ArrayLike, values_y: ArrayLike, follower: bool = False, member: int | None = None
    ) -> None:
        """Point force per load level (consistent force units).

        A follower force is given in the node's reference orientation and turns
        with the node rotation: F = R(theta) (values_x, values_y); with ``member``
        it turns with that member's end rotation at the node (one side of a hinge).
        """
        fx, fy = _levels(values_x), _levels(values_y)
        if fx.shape != fy.shape:
            fx, fy = np.broadcast_arrays(fx, fy)
        i = self.node(node)
        if member is not None:
            if not follower:
                raise ValueError("only a follower force turns with a member end")
            m = self.members[int(member)]
            if i not in (m.start, m.end):
                raise ValueError(f"member {member} does not end at node {self.node_names[i]!r}")
            member = int(member)
        if fx.ndim == 1:  # = np.column_stack([fx, fy]), without its Python-level overhead
            values = np.empty((len(fx), 2))
            values[:, 0], values[:, 1] = fx, fy
        else:
            values = np.column_stack([fx, fy])
        self.loads.append(PointLoad(i, "force", values, bool(follower), member=member))

    def add_pointed_force(self, node: NodeRef, values: ArrayLike, toward: Iterable[float], angle: float = 0.0) -> None:
        """Force of magnitude ``values`` (per level) toward the fixed point ``toward`` (x, y),
        turned by ``angle`` rad from the line node -> toward (a rope over a pulley: angle 0)."""
        tx, ty = (float(v) for v in toward)
        self.pointed.append(PointedForce(self.node(node), _levels(values), (tx, ty), float(angle)))

    def add_distributed(
        self, values_x: ArrayLike, values_y: ArrayLike, member: int | None = None, follower: bool = False
    ) -> None:
        """Uniform load per unit reference length (qx, qy) per level on ``member`` (default: every
        member); a follower load turns with each element's chord from its reference orientation."""
        qx, qy = np.broadcast_arrays(_levels(values_x), _levels(values_y))
        if member is not None and not 0 <= int(member) < len(self.members):
            raise ValueError(f"no member {member}")
        self.distributed.append(
            DistributedLoad(np.column_stack([qx, qy]), None if member is None else int(member), bool(follower))
        )

    @checked(positive=(), finite=("values",))
    def add_moment(self, node: NodeRef, values: ArrayLike, member: int | None = None) -> None:
        """Point moment (input torque) per load level, counter-clockwise positive.

        With ``member`` the moment acts on that member's end at the node, which is its own rotation
        where a joint releases it (a torque on one side of a hinge), else the node rotation."""
        i = self.node(node)
        if member is not None:
            m = self.members[int(member)]
            if i not in (m.start, m.end):
                raise ValueError(f"member {member} does not end at node {self.node_names[i]!r}")
            member = int(member)
        self.loads.append(PointLoad(i, "moment", _levels(values), member=member))

    def prescribe(self, node: NodeRef, dof: str, values: ArrayLike) -> None:
        """Prescribed displacement ('ux', 'uy') or rotation ('rz') per load level."""
        if dof not in DOF_NAMES:
            raise ValueError("dof must be 'ux', 'uy' or 'rz'")
        self.prescribed.append(Prescribed(self.node(node), DOF_NAMES[dof], _levels(values)))

    # -- queries ----------------------------------------------------------
    @property
    def n_nodes(self) -> int:
        return len(self.node_names)

    @property
    def n_levels(self) -> int:
        """Number of load levels implied by the load histories (1 if none)."""
        lengths = {
            len(x.values) for group in (self.loads, self.prescribed, self.pointed, self.distributed) for x in group
        }
        lengths.discard(0)
        lengths.discard(1)
        if len(lengths) > 1:
            raise ValueError(f"load histories have different lengths: {sorted(lengths)}")
        return lengths.pop() if lengths else 1

    def characteristic_length(self) -> float:
        """Mean member chord length (the length scale used for tolerances)."""
        if not self.members:
            return 1.0
        if len(self.members) == 1:  # the same float64 difference and hypot, the sum of one chord
            m = self.members[0]
            (xi, yi), (xj, yj) = self.coords[m.start], self.coords[m.end]
            return float(np.hypot(xj - xi, yj - yi))
        coords = self.coords  # (x, y) floats: the float64 differences the arrays had, without them
        dx = np.array([coords[m.end][0] - coords[m.start][0] for m in self.members])
        dy = np.array([coords[m.end][1] - coords[m.start][1] for m in self.members])
        chords = np.hypot(dx, dy)
        return float(chords.sum() / len(chords))  # = np.mean(chords)
