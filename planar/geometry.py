"""The geometry of a planar compliant mechanism: nodes, beams, rigid links, joints and supports, and the
bodies they make.

Plain data in the unloaded pose. Which rigid links move as one body follows from the joints alone: two
links sharing a node are welded there unless a joint at that node names one of them, and a link welded to
a node with a fixed support is part of the ground (``welded_bodies``).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

__all__ = [
    "GROUND",
    "SupportKind",
    "SUPPORT_KINDS",
    "Node",
    "Beam",
    "RigidLink",
    "Joint",
    "Support",
    "Geometry",
    "WeldedBodies",
    "welded_bodies",
]

GROUND = "ground"


class SupportKind(StrEnum):
    """How the ground holds a node: every freedom (fixed), the position (pinned), the position across a
    line (slider), or the position across a line and the rotation (guided)."""

    FIXED = "fixed"
    PINNED = "pinned"
    SLIDER = "slider"
    GUIDED = "guided"


SUPPORT_KINDS = tuple(kind.value for kind in SupportKind)


@dataclass(frozen=True)
class Node:
    name: str
    x: float
    y: float


@dataclass(frozen=True)
class Beam:
    """A flexible member from node ``start`` to node ``end``: bending stiffness EI, axial stiffness EA
    (None: inextensible), initial curvature (1/length, CCW from the start)."""

    name: str
    start: str
    end: str
    EI: float
    curvature: float = 0.0
    EA: float | None = None


@dataclass(frozen=True)
class RigidLink:
    """A rigid member through the named nodes."""

    name: str
    nodes: tuple[str, ...]


@dataclass(frozen=True)
class Joint:
    """A revolute hinge at a node releasing the named members, with an optional torsion spring
    (moment/rad) across it."""

    node: str
    members: tuple[str, ...]
    spring: float = 0.0


@dataclass(frozen=True)
class Support:
    """How the ground holds a node: 'fixed', 'pinned', 'slider' (a pin on a line along ``direction``) or
    'guided' (a slider that also holds the rotation); ``member``: the one member it holds, if not all."""

    node: str
    kind: SupportKind
    direction: tuple[float, float] | None = None
    member: str | None = None

    def __post_init__(self) -> None:
        if self.kind not in SUPPORT_KINDS:
            raise ValueError(f"support at '{self.node}': kind '{self.kind}' is not one of {SUPPORT_KINDS}")
        object.__setattr__(self, "kind", SupportKind(self.kind))


@dataclass(frozen=True)
class Geometry:
    nodes: tuple[Node, ...]
    beams: tuple[Beam, ...] = ()
    links: tuple[RigidLink, ...] = ()
    joints: tuple[Joint, ...] = ()
    supports: tuple[Support, ...] = ()

    def released(self, node: str, member: str) -> bool:
        """Whether a joint at ``node`` releases ``member`` (a hinge, not a weld)."""
        return any(j.node == node and member in j.members for j in self.joints)


@dataclass(frozen=True)
class WeldedBodies:
    """The bodies the rigid links make.

    ``body_of_link``: each link's body, named after one of its links (the first one welded), or GROUND;
    ``links_at``: node -> the links through it, in the geometry's order; ``nodes_of``: each movable body's
    nodes, in order of first appearance (a node where a joint releases the link is still a point of its
    body: the pin's place); ``owner``: node -> the body that carries it welded (a fixed support's node:
    GROUND; a node where every link is released has none)."""

    body_of_link: dict[str, str]
    links_at: dict[str, list[str]]
    nodes_of: dict[str, list[str]]
    owner: dict[str, str]

    def links_of(self, body: str) -> list[str]:
        return [name for name, b in self.body_of_link.items() if b == body]


def welded_bodies(geometry: Geometry) -> WeldedBodies:
    """The bodies of ``geometry``'s rigid links: links welded where they share a node that no joint
    releases them at, and welded to the ground at a fixed support (union-find over the link names)."""
    parent: dict[str, str] = {GROUND: GROUND}

    def find(a: str) -> str:
        parent.setdefault(a, a)
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    def union(a: str, b: str) -> None:
        ra, rb = find(a), find(b)
        if ra != rb:
            if rb == GROUND:
                ra, rb = rb, ra
            parent[rb] = ra

    links_at: dict[str, list[str]] = {}
    for link in geometry.links:
        find(link.name)
        for nd in link.nodes:
            links_at.setdefault(nd, []).append(link.name)
    fixed = {s.node for s in geometry.supports if s.kind == SupportKind.FIXED}
    for nd, names in links_at.items():
        kept = [name for name in names if not geometry.released(nd, name)]
        for other in kept[1:]:
            union(kept[0], other)
        if nd in fixed:
            for name in kept:
                union(GROUND, name)
    body_of_link = {link.name: find(link.name) for link in geometry.links}
    owner: dict[str, str] = {nd: GROUND for nd in sorted(fixed)}
    nodes_of: dict[str, list[str]] = {}
    for link in geometry.links:
        body = body_of_link[link.name]
        for nd in link.nodes:
            if not geometry.released(nd, link.name):
                owner.setdefault(nd, body)
            if body != GROUND and nd not in nodes_of.setdefault(body, []):
                nodes_of[body].append(nd)
    return WeldedBodies(body_of_link, links_at, nodes_of, owner)
